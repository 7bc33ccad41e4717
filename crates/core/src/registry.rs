//! The plugin registry, on `inventory`.
//!
//! Every element, material, interface law, failure criterion and linear
//! solver registers one entry with `inventory::submit!`: a snake_case key,
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
}

/// Registry entry of an element type.
pub struct ElementEntry {
    pub key: &'static str,
    pub description: &'static str,
    pub params: &'static [ParamDoc],
    /// Cell shape the element expects.
    pub shape: CellShape,
    pub build: fn(&ElementBuild<'_>) -> Result<Arc<dyn Element>, CoreError>,
}

/// Registry entry of a solid material.
pub struct MaterialEntry {
    pub key: &'static str,
    pub description: &'static str,
    pub params: &'static [ParamDoc],
    pub build: fn(&toml::Table) -> Result<Arc<dyn Material>, CoreError>,
}

/// Registry entry of an interface law.
pub struct LawEntry {
    pub key: &'static str,
    pub description: &'static str,
    pub params: &'static [ParamDoc],
    pub build: fn(&toml::Table) -> Result<Arc<dyn InterfaceLaw>, CoreError>,
}

/// Registry entry of a failure criterion.
pub struct CriterionEntry {
    pub key: &'static str,
    pub description: &'static str,
    pub params: &'static [ParamDoc],
    pub build: fn(&toml::Table) -> Result<Arc<dyn FailureCriterion>, CoreError>,
}

/// Registry entry of a linear solver back end.
pub struct SolverEntry {
    pub key: &'static str,
    pub description: &'static str,
    pub params: &'static [ParamDoc],
    pub build: fn(&toml::Table) -> Result<Box<dyn LinearSolver>, CoreError>,
}

inventory::collect!(ElementEntry);
inventory::collect!(MaterialEntry);
inventory::collect!(LawEntry);
inventory::collect!(CriterionEntry);
inventory::collect!(SolverEntry);

/// Common view of the five entry types.
pub trait Entry: 'static {
    /// Kind name used in messages ("element", "material", ...).
    const KIND: &'static str;
    fn key(&self) -> &'static str;
    fn description(&self) -> &'static str;
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
