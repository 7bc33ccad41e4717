//! The plugin registry, on `inventory`.
//!
//! Every element, material, interface law, failure criterion, ply failure
//! criterion and linear solver registers one entry with `inventory::submit!`: a snake_case key,
//! a one-line description, its parameter documentation and a constructor
//! from a TOML table (unknown keys rejected with `deny_unknown_fields`).
//! Adding a plugin is one new file plus one `submit!`; nothing central to edit.
//!
//! ```ignore
//! inventory::submit! {
//!     junta_core::registry::LawEntry {
//!         key: "linear_penalty",
//!         description: "linear penalty D = diag(d1, d2, d3)",
//!         params: &[ParamDoc { name: "d", doc: "penalty stiffness, N/m^3" }],
//!         build: |table| Ok(Arc::new(LinearPenalty::from_table(table)?)),
//!     }
//! }
//! ```
//!
//! A binary must reference each plugin crate (`use junta_elements as _;`)
//! so that the linker keeps its registrations.

use crate::error::CoreError;
pub use crate::ply_criterion::PlyCriterionEntry;
use crate::topology::CellShape;
use crate::{Element, FailureCriterion, InterfaceLaw, LinearSolver, Material};
use serde::de::DeserializeOwned;
use std::sync::Arc;

/// Documentation of one parameter of a plugin.
#[derive(Debug, Clone, Copy)]
pub struct ParamDoc {
    /// Key in the TOML table.
    pub name: &'static str,
    /// What it means, its unit and default.
    pub doc: &'static str,
}

/// What an element constructor receives.
#[derive(Debug)]
pub struct ElementBuild<'a> {
    /// Solid material (solid elements).
    pub material: Option<Arc<dyn Material>>,
    /// Traction law (interface elements).
    pub law: Option<Arc<dyn InterfaceLaw>>,
    /// Element options (e.g. integration rule).
    pub options: &'a toml::Table,
    /// Small or finite (large-deformation) kinematics, the model's.
    pub kinematics: crate::Kinematics,
}

/// Registry entry of an element type.
pub struct ElementEntry {
    /// Registry key, by which scenes name it (e.g. `h20`).
    pub key: &'static str,
    /// One-line description, for listings (`junta list`).
    pub description: &'static str,
    /// Documentation of each key of its parameter table.
    pub params: &'static [ParamDoc],
    /// Cell shape the element expects.
    pub shape: CellShape,
    /// Builds the element from its material or law and its options.
    pub build: fn(&ElementBuild<'_>) -> Result<Arc<dyn Element>, CoreError>,
}

/// Registry entry of a solid material.
pub struct MaterialEntry {
    /// Registry key, by which scenes name it (e.g. `isotropic`).
    pub key: &'static str,
    /// One-line description, for listings (`junta list`).
    pub description: &'static str,
    /// Documentation of each key of its parameter table.
    pub params: &'static [ParamDoc],
    /// Builds the material from its parameter table.
    pub build: fn(&toml::Table) -> Result<Arc<dyn Material>, CoreError>,
}

/// Registry entry of an interface law.
pub struct LawEntry {
    /// Registry key, by which scenes name it (e.g. `linear_penalty`).
    pub key: &'static str,
    /// One-line description, for listings (`junta list`).
    pub description: &'static str,
    /// Documentation of each key of its parameter table.
    pub params: &'static [ParamDoc],
    /// Builds the law from its parameter table (without `type`).
    pub build: fn(&toml::Table) -> Result<Arc<dyn InterfaceLaw>, CoreError>,
}

/// Builds a law registered at run time from its parameter table.
pub type RuntimeLawBuild =
    Arc<dyn Fn(&toml::Table) -> Result<Arc<dyn InterfaceLaw>, CoreError> + Send + Sync>;

/// A law registered at run time (a law written in Python): its key,
/// description, and builder.
#[derive(Clone)]
pub struct RuntimeLaw {
    /// Key scenes name in `[laws.NAME] type = "KEY"`.
    pub key: String,
    /// One-line description.
    pub description: String,
    /// Builder from the scene's parameter table (without `type`).
    pub build: RuntimeLawBuild,
}

static RUNTIME_LAWS: std::sync::RwLock<Vec<RuntimeLaw>> = std::sync::RwLock::new(Vec::new());

/// Register (or replace) a law at run time. A key of a compiled-in law is
/// refused: compiled laws cannot be shadowed.
pub fn register_runtime_law(law: RuntimeLaw) -> Result<(), CoreError> {
    if inventory::iter::<LawEntry>
        .into_iter()
        .any(|e| e.key == law.key)
    {
        return Err(CoreError::Invalid(format!(
            "law `{}` is a built-in law; register the new law under another name",
            law.key
        )));
    }
    let mut laws = RUNTIME_LAWS.write().unwrap_or_else(|p| p.into_inner());
    laws.retain(|l| l.key != law.key);
    laws.push(law);
    Ok(())
}

/// Remove a law registered at run time; true when it was there.
pub fn unregister_runtime_law(key: &str) -> bool {
    let mut laws = RUNTIME_LAWS.write().unwrap_or_else(|p| p.into_inner());
    let n = laws.len();
    laws.retain(|l| l.key != key);
    laws.len() != n
}

/// The laws registered at run time, by key.
pub fn runtime_laws() -> Vec<RuntimeLaw> {
    let mut v = RUNTIME_LAWS
        .read()
        .unwrap_or_else(|p| p.into_inner())
        .clone();
    v.sort_by(|a, b| a.key.cmp(&b.key));
    v
}

/// Build the law `key` (compiled in, or registered at run time) from its
/// parameters; an unknown key lists every valid one.
pub fn build_law(key: &str, params: &toml::Table) -> Result<Arc<dyn InterfaceLaw>, CoreError> {
    if let Some(l) = runtime_laws().into_iter().find(|l| l.key == key) {
        return (l.build)(params);
    }
    match find::<LawEntry>(key) {
        Ok(e) => (e.build)(params),
        Err(CoreError::UnknownKey { kind, key, valid }) => {
            let mut all: Vec<String> = valid.split(", ").map(str::to_string).collect();
            all.extend(runtime_laws().into_iter().map(|l| l.key));
            all.sort();
            Err(CoreError::UnknownKey {
                kind,
                key,
                valid: all.join(", "),
            })
        }
        Err(e) => Err(e),
    }
}

/// Registry entry of a failure criterion.
pub struct CriterionEntry {
    /// Registry key, by which scenes name it (e.g. `quadratic`).
    pub key: &'static str,
    /// One-line description, for listings (`junta list`).
    pub description: &'static str,
    /// Documentation of each key of its parameter table.
    pub params: &'static [ParamDoc],
    /// Builds the criterion from its parameter table.
    pub build: fn(&toml::Table) -> Result<Arc<dyn FailureCriterion>, CoreError>,
}

/// Registry entry of a linear solver back end.
pub struct SolverEntry {
    /// Registry key, by which scenes name it (e.g. `cholesky`).
    pub key: &'static str,
    /// One-line description, for listings (`junta list`).
    pub description: &'static str,
    /// Documentation of each key of its parameter table.
    pub params: &'static [ParamDoc],
    /// Builds the back end from its settings table.
    pub build: fn(&toml::Table) -> Result<Box<dyn LinearSolver>, CoreError>,
}

inventory::collect!(ElementEntry);
inventory::collect!(MaterialEntry);
inventory::collect!(LawEntry);
inventory::collect!(CriterionEntry);
inventory::collect!(SolverEntry);
inventory::collect!(PlyCriterionEntry);

/// Common view of the six entry types.
pub trait Entry: 'static {
    /// Kind name used in messages ("element", "material", ...).
    const KIND: &'static str;
    /// The entry's registry key.
    fn key(&self) -> &'static str;
    /// The entry's one-line description.
    fn description(&self) -> &'static str;
    /// Documentation of the entry's parameters.
    fn params(&self) -> &'static [ParamDoc];
}

macro_rules! impl_entry {
    ($t:ty, $kind:literal) => {
        impl Entry for $t {
            const KIND: &'static str = $kind;
            fn key(&self) -> &'static str {
                self.key
            }
            fn description(&self) -> &'static str {
                self.description
            }
            fn params(&self) -> &'static [ParamDoc] {
                self.params
            }
        }
    };
}
impl_entry!(ElementEntry, "element");
impl_entry!(MaterialEntry, "material");
impl_entry!(LawEntry, "law");
impl_entry!(CriterionEntry, "criterion");
impl_entry!(SolverEntry, "solver");
impl_entry!(PlyCriterionEntry, "ply criterion");

/// All entries of one kind, sorted by key.
pub fn entries<E: Entry>() -> Vec<&'static E>
where
    &'static E: 'static,
    inventory::iter<E>: IntoIterator<Item = &'static E>,
{
    let mut v: Vec<&'static E> = inventory::iter::<E>.into_iter().collect();
    v.sort_by_key(|e| e.key());
    v
}

/// The entry with `key`, or an error listing the valid keys.
pub fn find<E: Entry>(key: &str) -> Result<&'static E, CoreError>
where
    inventory::iter<E>: IntoIterator<Item = &'static E>,
{
    let all = entries::<E>();
    all.iter()
        .copied()
        .find(|e| e.key() == key)
        .ok_or_else(|| CoreError::UnknownKey {
            kind: E::KIND,
            key: key.to_string(),
            valid: all.iter().map(|e| e.key()).collect::<Vec<_>>().join(", "),
        })
}

/// Deserialize a plugin's parameter table (use `#[serde(deny_unknown_fields)]`
/// on `T` so that misspelt keys are rejected with the list of valid ones).
pub fn parse_params<T: DeserializeOwned>(
    kind: &'static str,
    key: &str,
    table: &toml::Table,
) -> Result<T, CoreError> {
    T::deserialize(toml::Value::Table(table.clone())).map_err(|e| CoreError::InvalidParameters {
        kind,
        key: key.to_string(),
        message: e.to_string().trim().to_string(),
    })
}
