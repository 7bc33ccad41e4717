//! TOML scenes: the file format users write, its validation, and the
//! translation to a [`junta_core::Model`].
//!
//! Every error names the file, the TOML key path (e.g. `boundary[1].set`),
//! the line where we know it, and what would be valid. See the README for
//! an annotated example.

use crate::error::{bail, err, Context, Result};
use junta_core::mesh::generate::{box_mesh, BoxSpec};
use junta_core::mesh::Mesh;
use junta_core::registry::{self, ElementBuild, ElementEntry, Entry, LawEntry, MaterialEntry};
use junta_core::{Element, InterfaceLaw, Kinematics, Material, Model};
use serde::Deserialize;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use toml::Spanned;

/// A whole scene file.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    /// Title, description, units (informative).
    #[serde(default)]
    pub model: ModelInfo,
    /// Named materials: `[materials.NAME] type = "isotropic", E = .., nu = ..`.
    #[serde(default)]
    pub materials: BTreeMap<String, toml::Table>,
    /// Named interface laws: `[laws.NAME] type = "linear_penalty", d = ..`.
    #[serde(default)]
    pub laws: BTreeMap<String, toml::Table>,
    /// The mesh: built-in box generator or a file (or `[laminate]`).
    pub mesh: Option<MeshSpec>,
    /// A laminate built from its lay-up (instead of `[mesh]`):
    /// [`crate::input::layup`].
    pub laminate: Option<crate::input::layup::LaminateSpec>,
    /// Interface elements inserted between two element sets.
    #[serde(default)]
    pub interface: Vec<InterfaceSpec>,
    /// Traction-free cuts between two element sets (nodes duplicated, no element).
    #[serde(default)]
    pub crack: Vec<CrackSpec>,
    /// Node sets selected by a box of coordinates.
    #[serde(default)]
    pub node_set: Vec<NodeSetSpec>,
    /// Element type and material of imported blocks, by block name.
    #[serde(default)]
    pub blocks: Vec<BlockSpec>,
    /// Dirichlet conditions.
    #[serde(default)]
    pub boundary: Vec<BoundarySpec>,
    /// Loads.
    #[serde(default)]
    pub load: Vec<LoadSpec>,
    /// Linear solver: `type = "cholesky" | "cg"` plus its parameters.
    #[serde(default)]
    pub solver: Option<toml::Table>,
    /// Output options.
    #[serde(default)]
    pub output: OutputSpec,
    /// An outside reference value the run is compared with (reported in
    /// `summary.json`, used by `junta sweep`).
    pub reference: Option<ReferenceSpec>,
    /// Analysis type: linear (default) or incremental-iterative.
    #[serde(default)]
    pub analysis: AnalysisSpec,
    /// A temperature change of the solids from their stress-free
    /// temperature (thermal strains; cure residual stresses).
    pub temperature: Option<TemperatureSpec>,
    /// High-cycle fatigue: a fatigue step after the load program.
    pub fatigue: Option<FatigueSpec>,
    /// Ply failure criteria evaluated as outputs on the stress in the
    /// material axes: `type` (a registered ply criterion), optional `name`
    /// and `blocks`, and its strengths ([`crate::post::ply_failure`]).
    #[serde(default)]
    pub ply_failure: Vec<toml::Table>,
    /// Node-to-node equations between two node sets (periodic cells,
    /// generalized plane strain slices): [`crate::input::tie`].
    #[serde(default)]
    pub tie: Vec<crate::input::tie::TieSpec>,
}

/// `[fatigue]`: a fatigue step after the load program of a `static` run.
/// The load factor is held at the program's last value, the envelope
/// maximum of a constant-amplitude cycle of ratio `load_ratio`, while the
/// cycle count goes from 0 to `cycles` (Turon et al. 2007's cycle jump;
/// [`junta_core::FatigueProgram`]); fatigue laws (`fatigue_bilinear`,
/// `fatigue_cf20`) grow their damage with the increment's cycles. With
/// `blocks` instead of `cycles`: a sequence of constant-amplitude blocks,
/// each its own envelope maximum, cycles and load ratio (block loading).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FatigueSpec {
    /// Cycles at the end of the fatigue step (one block at the program's
    /// last load factor); not with `blocks`.
    pub cycles: Option<f64>,
    /// Blocks of constant amplitude, in order; not with `cycles`.
    #[serde(default)]
    pub blocks: Vec<FatigueBlock>,
    /// `R = min / max` of the load cycle, in `[0, 1)`. Default 0.
    #[serde(default)]
    pub load_ratio: f64,
    /// Largest damage growth of any point in one increment (sizes the cycle
    /// jumps from the laws' `damage_rate`). Default 0.05.
    #[serde(default = "default_max_damage_increment")]
    pub max_damage_increment: f64,
    /// Where the fatigue laws take the energy release rate and the
    /// process-zone length from: `"crack_front"` (default: measured on the
    /// interface at the start of each increment, the J integral of the
    /// cohesive tractions, `junta_core::crack_drive`) or `"local"` (each
    /// point's own estimate, the law's `l_cz`).
    #[serde(default = "default_energy_release_rate")]
    pub energy_release_rate: String,
    /// Direction of crack growth for `"crack_front"` (default: `[output]
    /// crack`'s direction, else the axis along which the interfaces are
    /// longest).
    #[serde(default, deserialize_with = "some_origin")]
    pub direction: Option<[f64; 3]>,
}

/// One block of `[fatigue] blocks`: the envelope maximum `load` (a load
/// factor), the `cycles` run at it, and its load ratio (default
/// `[fatigue] load_ratio`).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FatigueBlock {
    /// Load factor at the cycle's maximum.
    pub load: f64,
    /// Cycles in this block.
    pub cycles: f64,
    /// `R = min / max` of the block's cycle.
    pub load_ratio: Option<f64>,
}

fn default_energy_release_rate() -> String {
    "crack_front".into()
}

fn default_max_damage_increment() -> f64 {
    0.05
}

/// `[temperature]`: the stress-free temperature, the temperature of every
/// node (uniform `value`, then per node or element set, later entries
/// winning) and, in a `static` run, when it is applied (`ramp`).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TemperatureSpec {
    /// Temperature at which the solids carry no thermal strain (e.g. the
    /// cure temperature of a laminate).
    pub stress_free: f64,
    /// Temperature of every node not in `sets` (default: `stress_free`).
    pub value: Option<f64>,
    /// Temperatures of node sets or element sets (the nodes of their
    /// elements), in order: a later entry overrides an earlier one.
    #[serde(default)]
    pub sets: Vec<TemperatureSet>,
    /// In a `static` run: `"before"` (default) a thermal step ahead of the
    /// load program (the temperature goes from `stress_free` to its values
    /// with the loads and prescribed displacements at zero, then stays
    /// while the program runs), or `"with_first"` (ramped with the first
    /// step of the program, in proportion to its loads). A linear run
    /// applies it with the loads.
    #[serde(default)]
    pub ramp: Ramp,
}

/// `[[temperature.sets]]`: one set's temperature.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TemperatureSet {
    /// A node set, or an element set (the nodes of its elements).
    pub set: Spanned<String>,
    /// Its nodes' temperature.
    pub value: f64,
}

/// `[temperature] ramp`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Ramp {
    /// A thermal step before the load program.
    #[default]
    Before,
    /// With the first step of the load program.
    WithFirst,
}

/// `[analysis] type`: what a run does.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum AnalysisKind {
    /// One linear solve (`"linear"`, the default).
    #[default]
    Linear,
    /// Incremental-iterative over the load program (`"static"`).
    Static,
}

/// Read from its name; another name is an error naming the key and the
/// valid names (the TOML reader adds the file and line).
impl<'de> Deserialize<'de> for AnalysisKind {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        let name = String::deserialize(d)?;
        match name.as_str() {
            "linear" => Ok(AnalysisKind::Linear),
            "static" => Ok(AnalysisKind::Static),
            other => Err(serde::de::Error::custom(format!(
                "key `analysis.type`: `{other}` is not valid; use \"linear\" or \"static\""
            ))),
        }
    }
}

impl AnalysisKind {
    /// The name in a scene and in `summary.json` (`"linear"`, `"static"`).
    pub fn name(self) -> &'static str {
        match self {
            AnalysisKind::Linear => "linear",
            AnalysisKind::Static => "static",
        }
    }

    /// True for the incremental-iterative kind.
    pub fn is_incremental(self) -> bool {
        self == AnalysisKind::Static
    }
}

/// `[analysis]`: `type = "linear"` (default, one solve) or `"static"`
/// (incremental-iterative Newton-Raphson over a proportional load program:
/// forces and prescribed displacements scale with the load factor).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AnalysisSpec {
    /// `linear` or `static`.
    #[serde(rename = "type", default)]
    pub kind: AnalysisKind,
    /// Load factor at the end of each step (default `[1.0]`).
    #[serde(default = "one_step")]
    pub steps: Vec<f64>,
    /// Stop as soon as every interface point has failed (the body split).
    #[serde(default)]
    pub stop_when_separated: bool,
    /// Newton-Raphson settings (`[analysis.newton]`, see `junta_solvers::newton::NewtonSettings`).
    #[serde(default)]
    pub newton: junta_solvers::newton::NewtonSettings,
    /// What constrains the increments of a `static` run: `"auto"`
    /// (default: the load factor, i.e. load or displacement control,
    /// whatever the scene prescribes, with path following taking over at
    /// limit points and handing back after them; see
    /// `junta_solvers::path_switch`), `"load"` or its synonym
    /// `"displacement"` (the load factor only: the run stops at the first
    /// limit point), or `"arc_length"` (path following throughout:
    /// cylindrical arc length, then the dissipated energy once the laws
    /// dissipate; see `junta_solvers::arc_length`).
    #[serde(default)]
    pub control: Control,
    /// Path-following settings (`[analysis.arc_length]`, see
    /// `junta_solvers::arc_length::ArcLengthSettings`).
    #[serde(default)]
    pub arc_length: junta_solvers::arc_length::ArcLengthSettings,
    /// Large deformation: total-Lagrangian solids and interfaces framed on
    /// their current mid-surface (default `false`: small strains). A
    /// `linear` analysis with it runs as `static` (incremental).
    #[serde(default)]
    pub nlgeom: bool,
}

/// `[analysis] control`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Control {
    /// The load factor is prescribed; path following takes over at limit
    /// points and hands back after them.
    #[default]
    Auto,
    /// The load factor is prescribed throughout (`"load"` or
    /// `"displacement"`): the run stops at a limit point.
    #[serde(alias = "displacement")]
    Load,
    /// Path following (arc length / dissipation).
    ArcLength,
}

fn one_step() -> Vec<f64> {
    vec![1.0]
}

impl Default for AnalysisSpec {
    fn default() -> Self {
        AnalysisSpec {
            kind: AnalysisKind::Linear,
            steps: one_step(),
            stop_when_separated: false,
            newton: Default::default(),
            control: Control::Auto,
            arc_length: Default::default(),
            nlgeom: false,
        }
    }
}

/// `[output.curve]`: the load-displacement curve of an incremental run.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CurveSpec {
    /// Node set whose total internal force is recorded: the reaction on
    /// supports, the applied load on a loaded free set.
    pub reaction_set: String,
    /// Its component: x, y or z.
    pub reaction_component: String,
    /// Node set whose mean displacement is recorded.
    pub point_set: String,
    /// Its component: x, y or z.
    pub point_component: String,
    /// Optional node set whose mean displacement (same component) is
    /// subtracted: the recorded displacement is then a relative one, e.g.
    /// the total opening of a DCB's arms.
    #[serde(default)]
    pub relative_to: Option<String>,
    /// Record `-reaction` and `-displacement` (a load pushing along the
    /// negative axis, e.g. a bending test loaded downwards, then reads
    /// positive).
    #[serde(default)]
    pub negate: bool,
    /// A reference curve drawn with Junta's in `curve.svg`.
    #[serde(default)]
    pub reference: Option<ReferenceCurve>,
    /// Record the load factor as the load and `f_ext . u` (the
    /// displacement work-conjugate to the applied forces) as the
    /// displacement, instead of the sets' values: for a force-driven scene
    /// whose forces make up a unit load, e.g. a mixed-mode bending lever
    /// replaced by the forces it applies, this is the load P and its
    /// load-point displacement. The sets still name the axes.
    #[serde(default)]
    pub conjugate: bool,
}

/// A reference load-displacement curve (closed form, peer code, test).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ReferenceCurve {
    /// CSV file with two columns (displacement, reaction), relative to the scene.
    pub file: String,
    /// Legend, e.g. "corrected beam theory".
    pub label: String,
}

/// A reference reaction: the total reaction component on a node set that
/// an outside source (closed form, paper, peer code) gives.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ReferenceSpec {
    /// Node set carrying a boundary condition.
    pub set: String,
    /// `x`, `y` or `z`.
    pub component: String,
    /// The reference value.
    pub value: f64,
    /// Where the value comes from.
    pub source: Option<String>,
}

impl ReferenceSpec {
    /// Component index 0..3, or an error naming the key.
    pub fn component_index(&self, file: &Path) -> Result<usize> {
        component(&self.component).ok_or_else(|| {
            err!(
                "{}: key `reference.component`: `{}` is not valid; use x, y or z",
                file.display(),
                self.component
            )
        })
    }
}

/// Informative header of a scene.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ModelInfo {
    /// Title, shown in summaries and charts.
    pub title: Option<String>,
    /// The units the scene's numbers are in (informative, e.g. "N, mm, MPa").
    pub units: Option<String>,
    /// The out-of-plane thickness of a plane strain or plane stress model
    /// (its plane elements and line interfaces; default 1): forces,
    /// reactions and energies are those of this thickness. An axisymmetric
    /// model (cax elements) takes none: it is the full ring.
    pub thickness: Option<f64>,
}

/// Where the mesh comes from: `type = "box"` (built-in structured box),
/// `"boxes"` (several boxes merged at coincident nodes), `"gmsh"` or `"inp"`
/// (a file, path relative to the scene).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MeshSpec {
    /// `box`, `boxes`, `gmsh` or `inp`.
    #[serde(rename = "type")]
    pub kind: Spanned<String>,
    /// Box: edge lengths (`[x, y]` for a plane box).
    #[serde(default, deserialize_with = "some_size")]
    pub size: Option<[f64; 3]>,
    /// Box: elements along x, y, z (`[x, y]` for a plane box).
    #[serde(default, deserialize_with = "some_divisions")]
    pub divisions: Option<[usize; 3]>,
    /// Box: element type key (h8, h8i, h20, h27, h20r, h27r).
    pub element: Option<Spanned<String>>,
    /// Box: material name (a key of `[materials]`).
    pub material: Option<Spanned<String>>,
    /// Box: lower corner.
    #[serde(default, deserialize_with = "some_origin")]
    pub origin: Option<[f64; 3]>,
    /// Box: last/first element size per axis.
    #[serde(default, deserialize_with = "some_grading")]
    pub grading: Option<[f64; 3]>,
    /// Gmsh / inp: the file.
    pub file: Option<PathBuf>,
    /// Boxes: the parts, `[[mesh.boxes]]`.
    #[serde(default)]
    pub boxes: Vec<BoxPart>,
}

/// One part of a `type = "boxes"` mesh. Its sets are named `NAME.x0` ...
/// `NAME.z1` and its elements form the element set `NAME`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BoxPart {
    /// Name of the part: its element set and the prefix of its node sets.
    pub name: String,
    /// Edge lengths along x, y, z (`[x, y]` for a plane box).
    #[serde(deserialize_with = "size_xyz")]
    pub size: [f64; 3],
    /// Elements along x, y, z (`[x, y]` for a plane box).
    #[serde(deserialize_with = "divisions_xyz")]
    pub divisions: [usize; 3],
    /// Element type key (h8, h8i, h20, h27, h20r, h27r, wedge6, wedge15;
    /// plane: cpe4, cps8, cax8, ...).
    pub element: Spanned<String>,
    /// Material name (a key of `[materials]`).
    pub material: Spanned<String>,
    /// Lower corner (default the origin).
    #[serde(default, deserialize_with = "origin_xyz")]
    pub origin: [f64; 3],
    /// Ratio of the last to the first element size per axis (default 1).
    #[serde(default = "unit_grading", deserialize_with = "grading_xyz")]
    pub grading: [f64; 3],
    /// Further element set the box's elements join (several boxes with the
    /// same `group` form one body, e.g. a beam arm meshed finer near a
    /// crack tip; an interface can then go between two groups).
    pub group: Option<String>,
}

fn unit_grading() -> [f64; 3] {
    [1.0; 3]
}

/// Two or three values per axis: `[x, y]` (a plane box, a vector of a
/// plane model) gets `pad` along z.
fn xyz<'de, D: serde::Deserializer<'de>, T: Deserialize<'de> + Copy>(
    d: D,
    pad: T,
) -> std::result::Result<[T; 3], D::Error> {
    let v: Vec<T> = Vec::deserialize(d)?;
    match v[..] {
        [x, y] => Ok([x, y, pad]),
        [x, y, z] => Ok([x, y, z]),
        _ => Err(serde::de::Error::invalid_length(
            v.len(),
            &"two values [x, y] (a plane model) or three [x, y, z]",
        )),
    }
}
fn size_xyz<'de, D: serde::Deserializer<'de>>(d: D) -> std::result::Result<[f64; 3], D::Error> {
    xyz(d, 1.0)
}
fn divisions_xyz<'de, D: serde::Deserializer<'de>>(
    d: D,
) -> std::result::Result<[usize; 3], D::Error> {
    xyz(d, 1)
}
pub(crate) fn origin_xyz<'de, D: serde::Deserializer<'de>>(
    d: D,
) -> std::result::Result<[f64; 3], D::Error> {
    xyz(d, 0.0)
}
fn grading_xyz<'de, D: serde::Deserializer<'de>>(d: D) -> std::result::Result<[f64; 3], D::Error> {
    xyz(d, 1.0)
}
fn some_size<'de, D: serde::Deserializer<'de>>(
    d: D,
) -> std::result::Result<Option<[f64; 3]>, D::Error> {
    size_xyz(d).map(Some)
}
fn some_divisions<'de, D: serde::Deserializer<'de>>(
    d: D,
) -> std::result::Result<Option<[usize; 3]>, D::Error> {
    divisions_xyz(d).map(Some)
}
fn some_origin<'de, D: serde::Deserializer<'de>>(
    d: D,
) -> std::result::Result<Option<[f64; 3]>, D::Error> {
    origin_xyz(d).map(Some)
}
fn some_grading<'de, D: serde::Deserializer<'de>>(
    d: D,
) -> std::result::Result<Option<[f64; 3]>, D::Error> {
    grading_xyz(d).map(Some)
}

/// Zero-thickness interface elements along the faces shared by two element
/// sets (`between`): the first set is the bottom side, the normal points
/// from it to the second; or along the faces of a face set inside the mesh
/// (`along`: a Gmsh physical curve or surface, a box side), the listed
/// elements the bottom side, cutting through a body or ending inside it
/// (`junta_core::mesh::along`). The element (INTER8/16/18, LINE_INTER4/6)
/// follows the solids' order.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InterfaceSpec {
    /// Name of the interface block (and of its element set; node sets
    /// `NAME.bottom`, `NAME.top`).
    pub name: String,
    /// `[bottom_set, top_set]`.
    pub between: Option<Spanned<[String; 2]>>,
    /// A face set inside the mesh (instead of `between`).
    pub along: Option<Spanned<String>>,
    /// Law name (a key of `[laws]`).
    pub law: Spanned<String>,
    /// `"gauss"` (default) or `"lobatto"`.
    pub integration: Option<String>,
    /// Physical thickness of the adhesive layer, if any (for Turon's
    /// stiffness rule K = 50 E / t in the penalty advisor).
    pub thickness: Option<f64>,
    /// Keep only the interface elements whose centre lies in this box
    /// `[[xmin, ymin, zmin], [xmax, ymax, zmax]]`; the rest of the shared
    /// surface is cut (traction free), e.g. a notch ahead of a ligament.
    pub within: Option<Spanned<[[f64; 3]; 2]>>,
    /// A precracked part of the surface with its own law (e.g. `contact`):
    /// the interface elements whose centre lies in `within` form the block
    /// `NAME.precrack` with law `law`.
    pub precrack: Option<PrecrackSpec>,
}

/// The precracked part of an interface.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PrecrackSpec {
    /// `[[xmin, ymin, zmin], [xmax, ymax, zmax]]`.
    pub within: Spanned<[[f64; 3]; 2]>,
    /// Law name (a key of `[laws]`), e.g. a `contact` law.
    pub law: Spanned<String>,
}

/// A node set of all nodes inside an axis-aligned box (bounds inclusive,
/// with a tolerance of 1e-9 of the mesh size).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NodeSetSpec {
    /// Name of the new set.
    pub name: String,
    /// `[[xmin, ymin, zmin], [xmax, ymax, zmax]]`.
    pub within: Spanned<[[f64; 3]; 2]>,
}

/// A traction-free cut (e.g. a notch) between two element sets.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CrackSpec {
    /// Name; node sets `NAME.bottom` and `NAME.top` are created.
    pub name: String,
    /// `[bottom_set, top_set]`.
    pub between: Spanned<[String; 2]>,
}

/// Element type and material of an imported block.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BlockSpec {
    /// Name of the imported block (Gmsh physical volume or deck element set).
    pub name: Spanned<String>,
    /// Element type key (default: from the file's element type).
    pub element: Option<Spanned<String>>,
    /// Material name (a key of `[materials]`).
    pub material: Spanned<String>,
}

/// Either `"all"` or a list of components.
#[derive(Debug, Deserialize)]
#[serde(untagged)]
pub enum Fixed {
    /// `"all"` (every component).
    Word(String),
    /// Components by name, e.g. `["x", "z"]`.
    List(Vec<String>),
}

/// Optional x, y, z components.
#[derive(Debug, Default, Deserialize, Clone, Copy)]
#[serde(deny_unknown_fields)]
pub struct Components {
    /// x component, if given.
    pub x: Option<f64>,
    /// y component, if given.
    pub y: Option<f64>,
    /// z component, if given.
    pub z: Option<f64>,
}

/// A Dirichlet condition on a node set.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BoundarySpec {
    /// Node set name.
    pub set: Spanned<String>,
    /// Components fixed at zero: `"all"` or `["x", "z"]`.
    pub fixed: Option<Fixed>,
    /// Prescribed displacements: `{ z = -0.01 }`.
    pub displacement: Option<Components>,
}

/// A load on a node set (nodal force) or a face set (pressure / traction).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LoadSpec {
    /// Node set that receives `force` at every node.
    pub set: Option<Spanned<String>>,
    /// Face set that receives `pressure` or `traction`.
    pub face_set: Option<Spanned<String>>,
    /// Force applied at *each* node of `set` (like `*CLOAD`).
    #[serde(default, deserialize_with = "some_origin")]
    pub force: Option<[f64; 3]>,
    /// Total force on the nodes of `set`, shared as `split` says.
    #[serde(default, deserialize_with = "some_origin")]
    pub total_force: Option<[f64; 3]>,
    /// How `total_force` is shared by the nodes of `set`:
    /// `"consistent"` (the default) gives each node the integral of its
    /// shape function over the element faces the set spans (all their
    /// nodes in the set), divided by their area; if the set holds no
    /// complete face, over the element edges it spans (a quadratic edge:
    /// 1/6, 2/3, 1/6); isolated points share equally (with a note).
    /// `"equal"` gives every node of the set the same share.
    pub split: Option<Spanned<String>>,
    /// Pressure on `face_set`, positive pushing into the solid.
    pub pressure: Option<f64>,
    /// Traction vector (force per area) on `face_set`.
    #[serde(default, deserialize_with = "some_origin")]
    pub traction: Option<[f64; 3]>,
}

/// Output options.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OutputSpec {
    /// Output directory (relative to the working directory); `-o` overrides.
    pub directory: Option<PathBuf>,
    /// Write `results.vtu` (default true).
    #[serde(default = "yes")]
    pub vtu: bool,
    /// Node sets whose mean displacement is reported in `summary.json`
    /// (`probes.NAME = [ux, uy, uz]`).
    #[serde(default)]
    pub probes: Vec<String>,
    /// Also write the (linear) solution scaled to these fractions of the
    /// load, as `results_<f>.vtu` with a `results.pvd` index.
    #[serde(default)]
    pub fractions: Vec<f64>,
    /// Incremental runs: the load-displacement curve to record.
    pub curve: Option<CurveSpec>,
    /// Incremental runs: write a VTU frame every this many increments (default 1).
    #[serde(default = "every_one")]
    pub every: usize,
    /// Incremental runs: how the crack length, the crack front and the
    /// process zone are measured (`crate::post::crack`); without it the
    /// direction is the axis along which the interfaces are longest.
    #[serde(default)]
    pub crack: Option<CrackFrontSpec>,
}

/// `[output] crack = { direction = [1, 0, 0], origin = [..], width = ..,
/// interface = ".." }`: the direction a crack grows in, for the crack
/// length, the front position and the process zone of `curve.csv`
/// (`crate::post::crack`).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CrackFrontSpec {
    /// Direction of growth (normalised; need not be a unit vector).
    #[serde(deserialize_with = "origin_xyz")]
    pub direction: [f64; 3],
    /// Point the front position is measured from (its coordinate along
    /// the direction is the zero); default: where the interface starts
    /// along the direction (its smallest node coordinate).
    #[serde(default, deserialize_with = "some_origin")]
    pub origin: Option<[f64; 3]>,
    /// Width of the crack front: the crack length is the damaged area over
    /// it; default: the interface's area over its extent along the
    /// direction (a rectangular bond's width).
    #[serde(default)]
    pub width: Option<f64>,
    /// The interface (block name) whose crack is measured; default: all.
    #[serde(default)]
    pub interface: Option<String>,
}

fn every_one() -> usize {
    1
}

impl Default for OutputSpec {
    fn default() -> Self {
        OutputSpec {
            directory: None,
            vtu: true,
            probes: Vec::new(),
            fractions: Vec::new(),
            curve: None,
            every: 1,
            crack: None,
        }
    }
}

fn yes() -> bool {
    true
}

/// A parsed scene with its source, for messages.
pub struct SceneFile {
    /// The scene's path (messages name it; relative files are read next to it).
    pub path: PathBuf,
    /// The scene's text (messages give line numbers from it).
    pub text: String,
    /// The parsed scene.
    pub scene: Scene,
}

impl SceneFile {
    /// Read and parse a scene file; TOML and schema errors name the line.
    pub fn read(path: &Path) -> Result<Self> {
        let text = std::fs::read_to_string(path)
            .with_context(|| format!("cannot read scene file {}", path.display()))?;
        Self::parse(path, text)
    }

    /// Parse scene text (the path is used in messages and for relative files).
    pub fn parse(path: &Path, text: String) -> Result<Self> {
        let scene: Scene = toml::from_str(&text)
            .map_err(|e| err!("{}: {}", path.display(), e.to_string().trim_end()))?;
        let sf = SceneFile {
            path: path.to_path_buf(),
            text,
            scene,
        };
        Ok(sf)
    }

    /// `file:line` of a span, for messages.
    pub fn at(&self, span: std::ops::Range<usize>) -> String {
        let line = self.text[..span.start.min(self.text.len())]
            .matches('\n')
            .count()
            + 1;
        format!("{}:{}", self.path.display(), line)
    }

    pub(crate) fn relative(&self, file: &Path) -> PathBuf {
        if file.is_absolute() {
            file.to_path_buf()
        } else {
            self.path.parent().unwrap_or(Path::new(".")).join(file)
        }
    }
}

/// Parse a component name.
pub fn component(name: &str) -> Option<usize> {
    match name {
        "x" => Some(0),
        "y" => Some(1),
        "z" => Some(2),
        _ => None,
    }
}

fn list_keys<T>(m: &BTreeMap<String, T>) -> String {
    if m.is_empty() {
        "(none)".to_string()
    } else {
        m.keys().cloned().collect::<Vec<_>>().join(", ")
    }
}

/// Build the registry object of every entry of a `[section.NAME]` table
/// (`type` picks the registered plugin, the other keys are its parameters).
pub fn build_plugins<E: Entry, T>(
    sf: &SceneFile,
    section: &str,
    tables: &BTreeMap<String, toml::Table>,
    build: impl Fn(&E, &toml::Table) -> Result<T, junta_core::CoreError>,
) -> Result<BTreeMap<String, T>>
where
    junta_core::inventory::iter<E>: IntoIterator<Item = &'static E>,
{
    let mut out = BTreeMap::new();
    for (name, table) in tables {
        let mut t = table.clone();
        let key = match t.remove("type") {
            Some(toml::Value::String(s)) => s,
            _ => {
                let valid: Vec<_> = registry::entries::<E>().iter().map(|e| e.key()).collect();
                bail!(
                    "{}: key `{section}.{name}.type` is missing or not a string; valid types: {}",
                    sf.path.display(),
                    valid.join(", ")
                )
            }
        };
        let entry = registry::find::<E>(&key)
            .map_err(|e| err!("{}: key `{section}.{name}.type`: {e}", sf.path.display()))?;
        let m = build(entry, &t)
            .map_err(|e| err!("{}: key `{section}.{name}`: {e}", sf.path.display()))?;
        out.insert(name.clone(), m);
    }
    Ok(out)
}

/// The `[laws.NAME]` of a scene: compiled-in laws and laws registered at
/// run time (a law written in Python) alike.
fn build_laws(sf: &SceneFile) -> Result<BTreeMap<String, Arc<dyn InterfaceLaw>>> {
    let file = sf.path.display();
    let mut out = BTreeMap::new();
    for (name, table) in &sf.scene.laws {
        let mut t = table.clone();
        let Some(toml::Value::String(key)) = t.remove("type") else {
            let mut valid: Vec<String> = registry::entries::<LawEntry>()
                .iter()
                .map(|e| e.key().to_string())
                .collect();
            valid.extend(registry::runtime_laws().into_iter().map(|l| l.key));
            bail!(
                "{file}: key `laws.{name}.type` is missing or not a string; valid types: {}",
                valid.join(", ")
            )
        };
        let law = registry::build_law(&key, &t).map_err(|e| match e {
            junta_core::CoreError::UnknownKey { .. } => err!("{file}: key `laws.{name}.type`: {e}"),
            e => err!("{file}: key `laws.{name}`: {e}"),
        })?;
        out.insert(name.clone(), law);
    }
    Ok(out)
}

/// Geometry of one generated box (scene keys `size`, `divisions`, `origin`,
/// `grading`).
pub(crate) struct BoxGeometry {
    pub(crate) size: [f64; 3],
    pub(crate) divisions: [usize; 3],
    pub(crate) origin: [f64; 3],
    pub(crate) grading: [f64; 3],
}

/// Build one box of the generator, checking the element key.
pub(crate) fn generate_box(
    sf: &SceneFile,
    key: &str,
    geometry: BoxGeometry,
    element: &Spanned<String>,
    material: &str,
) -> Result<Mesh> {
    let BoxGeometry {
        size,
        divisions,
        origin,
        grading,
    } = geometry;
    let entry = registry::find::<ElementEntry>(element.get_ref())
        .map_err(|e| err!("{}: key `{key}.element`: {e}", sf.at(element.span())))?;
    if !entry.shape.is_solid() {
        bail!(
            "{}: key `{key}.element`: `{}` is not a solid element; the box generator makes h8, h8i, h20, h27, h20r, h27r, wedge6, wedge6r, wedge15, and the plane cpe*, cps*, cax* elements",
            sf.at(element.span()),
            entry.key
        );
    }
    for (name, v) in [("size", size), ("origin", origin), ("grading", grading)] {
        if let Some(x) = v.iter().find(|x| !x.is_finite()) {
            bail!(
                "{}: key `{key}.{name}`: {x} is not a finite number",
                sf.at(element.span())
            );
        }
    }
    if let Some(g) = grading
        .iter()
        .find(|g| **g <= 0.0 || **g > 1e6 || **g < 1e-6)
    {
        bail!(
            "{}: key `{key}.grading`: {g} is out of range; the ratio of last to first element size must lie in [1e-6, 1e6]",
            sf.at(element.span())
        );
    }
    let order = if entry.shape.num_nodes() > 8 { 2 } else { 1 };
    crate::prepare::limits::check_memory(
        &format!(
            "{}: key `{key}.divisions` = {divisions:?}: the box and its model",
            sf.at(element.span())
        ),
        crate::prepare::limits::box_bytes(divisions, order, entry.shape.num_nodes()),
    )?;
    let spec = BoxSpec {
        origin,
        size,
        divisions,
        shape: entry.shape,
        grading,
    };
    box_mesh(&spec, "solid", element.get_ref(), material)
        .map_err(|e| err!("{}: key `{key}`: {e}", sf.at(element.span())))
}

fn mesh_diagonal(mesh: &Mesh) -> f64 {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in &mesh.nodes {
        for c in 0..3 {
            lo[c] = lo[c].min(p[c]);
            hi[c] = hi[c].max(p[c]);
        }
    }
    (0..3).map(|c| (hi[c] - lo[c]).powi(2)).sum::<f64>().sqrt()
}

/// Load the mesh of a scene, then insert its cracks, box node sets and interfaces.
///
/// Stages: `load_mesh`, `insert_cracks`, `add_box_node_sets`,
/// `insert_interfaces`.
pub fn build_mesh(sf: &SceneFile) -> Result<Mesh> {
    let mut mesh = load_mesh(sf)?;
    insert_cracks(sf, &mut mesh)?;
    add_box_node_sets(sf, &mut mesh)?;
    insert_interfaces(sf, &mut mesh)?;
    Ok(mesh)
}

/// The `[mesh]` of a scene: generated (`box`, `boxes`) or read (`gmsh`,
/// `inp`); keys that the type does not use are an error.
fn load_mesh(sf: &SceneFile) -> Result<Mesh> {
    let m = match (&sf.scene.mesh, &sf.scene.laminate) {
        (Some(m), None) => m,
        (None, Some(l)) => return crate::input::layup::build_mesh(sf, l),
        (Some(_), Some(_)) => bail!(
            "{}: both `[mesh]` and `[laminate]` are given; a scene's solids come from one of them",
            sf.path.display()
        ),
        (None, None) => bail!(
            "{}: missing `[mesh]` (a box, boxes, a Gmsh or .inp file) or `[laminate]` (a lay-up)",
            sf.path.display()
        ),
    };
    let kind = m.kind.get_ref().as_str();
    let at = sf.at(m.kind.span());
    let given: Vec<&str> = [
        ("size", m.size.is_some()),
        ("divisions", m.divisions.is_some()),
        ("element", m.element.is_some()),
        ("material", m.material.is_some()),
        ("origin", m.origin.is_some()),
        ("grading", m.grading.is_some()),
        ("file", m.file.is_some()),
        ("boxes", !m.boxes.is_empty()),
    ]
    .iter()
    .filter(|(_, g)| *g)
    .map(|(k, _)| *k)
    .collect();
    let allowed: &[&str] = match kind {
        "box" => &["size", "divisions", "element", "material", "origin", "grading"],
        "boxes" => &["boxes"],
        "gmsh" | "inp" => &["file"],
        other => bail!("{at}: key `mesh.type`: `{other}` is not valid; use \"box\", \"boxes\", \"gmsh\" or \"inp\""),
    };
    if let Some(k) = given.iter().find(|k| !allowed.contains(k)) {
        bail!(
            "{at}: key `mesh.{k}` is not used with type = \"{kind}\"; valid keys: type, {}",
            allowed.join(", ")
        );
    }
    let missing = |k: &str| err!("{at}: key `mesh.{k}` is required with type = \"{kind}\"");
    Ok(match kind {
        "box" => generate_box(
            sf,
            "mesh",
            BoxGeometry {
                size: m.size.ok_or_else(|| missing("size"))?,
                divisions: m.divisions.ok_or_else(|| missing("divisions"))?,
                origin: m.origin.unwrap_or([0.0; 3]),
                grading: m.grading.unwrap_or([1.0; 3]),
            },
            m.element.as_ref().ok_or_else(|| missing("element"))?,
            m.material
                .as_ref()
                .ok_or_else(|| missing("material"))?
                .get_ref(),
        )?,
        "boxes" => {
            if m.boxes.is_empty() {
                return Err(missing("boxes"));
            }
            merged_boxes(sf, m, &at)?
        }
        "gmsh" => {
            let p = sf.relative(m.file.as_ref().ok_or_else(|| missing("file"))?);
            crate::input::gmsh::read_msh(&p).map_err(|e| err!("{at}: key `mesh.file`: {e}"))?
        }
        _ => {
            let p = sf.relative(m.file.as_ref().ok_or_else(|| missing("file"))?);
            crate::input::inp::read_inp(&p)
                .map_err(|e| err!("{at}: key `mesh.file`: {e}"))?
                .mesh
        }
    })
}

/// `type = "boxes"`: the boxes generated one by one and merged at their
/// coincident nodes (boxes sharing volume are an error: they would be
/// bonded on many faces), each box an element set, a `group` the union of
/// its boxes' sets.
fn merged_boxes(sf: &SceneFile, m: &MeshSpec, at: &str) -> Result<Mesh> {
    for (j, b) in m.boxes.iter().enumerate() {
        for (i, a) in m.boxes.iter().enumerate().take(j) {
            let overlap = (0..3).all(|c| {
                let lo = a.origin[c].max(b.origin[c]);
                let hi = (a.origin[c] + a.size[c]).min(b.origin[c] + b.size[c]);
                let scale = a.size[c].abs().min(b.size[c].abs());
                hi - lo > 1e-9 * scale
            });
            if overlap {
                bail!(
                    "{}: key `mesh.boxes[{j}]`: box `{}` overlaps box `{}` (mesh.boxes[{i}]); boxes may touch but not share volume",
                    sf.at(b.element.span()),
                    b.name,
                    a.name
                );
            }
        }
    }
    let mut parts = Vec::new();
    for (i, b) in m.boxes.iter().enumerate() {
        let key = format!("mesh.boxes[{i}]");
        let part = generate_box(
            sf,
            &key,
            BoxGeometry {
                size: b.size,
                divisions: b.divisions,
                origin: b.origin,
                grading: b.grading,
            },
            &b.element,
            b.material.get_ref(),
        )?;
        parts.push((b.name.clone(), part));
    }
    let mut mesh = junta_core::mesh::merge::merge(parts, 1e-9)
        .map_err(|e| err!("{at}: key `mesh.boxes`: {e}"))?;
    for (i, b) in m.boxes.iter().enumerate() {
        if let Some(g) = &b.group {
            if m.boxes.iter().any(|o| &o.name == g) {
                bail!("{at}: key `mesh.boxes[{i}].group`: `{g}` is also the name of a box; give the group its own name");
            }
            let members = mesh.element_sets.get(&b.name).cloned().unwrap_or_default();
            let set = mesh.element_sets.entry(g.clone()).or_default();
            set.extend(members);
            set.sort_unstable();
            set.dedup();
        }
    }
    Ok(mesh)
}

/// `[[crack]]`: each a traction-free cut between two element sets (the
/// interface's nodes duplicated, its elements dropped).
fn insert_cracks(sf: &SceneFile, mesh: &mut Mesh) -> Result<()> {
    for (i, c) in sf.scene.crack.iter().enumerate() {
        let [a, b] = c.between.get_ref();
        let ins = junta_core::mesh::interface::insert_interface(mesh, a, b, &c.name, "")
            .map_err(|e| err!("{}: key `crack[{i}].between`: {e}", sf.at(c.between.span())))?;
        // keep the duplicated nodes, drop the elements: a traction-free cut
        mesh.element_sets.remove(&c.name);
        for &b in ins.blocks.iter().rev() {
            remove_block(mesh, b);
        }
    }
    Ok(())
}

/// `[[node_set]]`: the nodes within each box `[lo, hi]` (to 1e-9 of the
/// larger of the mesh diagonal and the box's largest side); an empty set
/// or an existing name is an error.
fn add_box_node_sets(sf: &SceneFile, mesh: &mut Mesh) -> Result<()> {
    for (i, ns) in sf.scene.node_set.iter().enumerate() {
        let [lo, hi] = *ns.within.get_ref();
        let size = (0..3)
            .map(|c| hi[c] - lo[c])
            .fold(0.0f64, f64::max)
            .max(1e-300);
        let diag = mesh_diagonal(mesh).max(size);
        let tol = 1e-9 * diag;
        let nodes: Vec<usize> = (0..mesh.nodes.len())
            .filter(|&n| {
                (0..3).all(|c| mesh.nodes[n][c] >= lo[c] - tol && mesh.nodes[n][c] <= hi[c] + tol)
            })
            .collect();
        if nodes.is_empty() {
            bail!(
                "{}: key `node_set[{i}].within`: no node lies in {lo:?} .. {hi:?}",
                sf.at(ns.within.span())
            );
        }
        if mesh.node_sets.insert(ns.name.clone(), nodes).is_some() {
            bail!(
                "{}: key `node_set[{i}].name`: a node set `{}` already exists",
                sf.at(ns.within.span()),
                ns.name
            );
        }
    }
    Ok(())
}

/// `[[interface]]`: interface elements between two element sets, with
/// their law; a `precrack` region gets its own law, `within` keeps only
/// the elements inside a box.
fn insert_interfaces(sf: &SceneFile, mesh: &mut Mesh) -> Result<()> {
    for (i, f) in sf.scene.interface.iter().enumerate() {
        let ins = match (&f.between, &f.along) {
            (Some(between), None) => {
                let [a, b] = between.get_ref();
                junta_core::mesh::interface::insert_interface(mesh, a, b, &f.name, f.law.get_ref())
                    .map_err(|e| {
                        err!("{}: key `interface[{i}].between`: {e}", sf.at(between.span()))
                    })?
            }
            (None, Some(along)) => junta_core::mesh::along::insert_interface_along(
                mesh,
                along.get_ref(),
                &f.name,
                f.law.get_ref(),
            )
            .map_err(|e| err!("{}: key `interface[{i}].along`: {e}", sf.at(along.span())))?,
            _ => bail!(
                "{}: `[[interface]]` `{}` (interface[{i}]): give `between = [bottom_set, top_set]` (two element sets) or `along = \"FACE_SET\"` (faces inside the mesh), one of them",
                sf.at(f.law.span()),
                f.name
            ),
        };
        if let Some(pc) = &f.precrack {
            split_precrack(
                mesh,
                &ins.blocks,
                &f.name,
                *pc.within.get_ref(),
                pc.law.get_ref(),
            )
            .map_err(|e| {
                err!(
                    "{}: key `interface[{i}].precrack.within`: {e}",
                    sf.at(pc.within.span())
                )
            })?;
        }
        if let Some(w) = &f.within {
            keep_within(mesh, &ins.blocks, &f.name, *w.get_ref())
                .map_err(|e| err!("{}: key `interface[{i}].within`: {e}", sf.at(w.span())))?;
        }
    }
    Ok(())
}

/// Centre of each element of a block, in order.
fn element_centres(mesh: &Mesh, block: usize) -> Vec<[f64; 3]> {
    let b = &mesh.blocks[block];
    let npe = b.nodes_per_element();
    b.connectivity
        .chunks(npe)
        .map(|c| {
            let mut centre = [0.0; 3];
            for &n in c {
                for (x, p) in centre.iter_mut().zip(mesh.nodes[n]) {
                    *x += p / npe as f64;
                }
            }
            centre
        })
        .collect()
}

/// Remove block `b` from the mesh; element sets drop its elements and
/// refer to the later blocks by their new indices.
fn remove_block(mesh: &mut Mesh, b: usize) {
    mesh.blocks.remove(b);
    if b < mesh.element_labels.len() {
        mesh.element_labels.remove(b);
    }
    for set in mesh.element_sets.values_mut() {
        set.retain(|r| r.block != b);
        for r in set.iter_mut() {
            if r.block > b {
                r.block -= 1;
            }
        }
    }
}

/// Which elements of the interface blocks `blocks` have their centre in
/// `[lo, hi]` (per block, per element).
fn centres_within(mesh: &Mesh, blocks: &[usize], [lo, hi]: [[f64; 3]; 2]) -> Vec<Vec<bool>> {
    let tol = 1e-9 * mesh_diagonal(mesh);
    blocks
        .iter()
        .map(|&b| {
            element_centres(mesh, b)
                .iter()
                .map(|c| (0..3).all(|k| c[k] >= lo[k] - tol && c[k] <= hi[k] + tol))
                .collect()
        })
        .collect()
}

/// Split the elements of each interface block (`blocks`, the blocks of
/// interface `name`: one per face shape) in two by `inside`: block `b`
/// keeps those with `inside[k][e] == keep_inside`, the others go to a new
/// block named `suffix(b's name)` with material `law` (`None`: dropped).
/// Blocks left empty are removed. Returns the new blocks.
fn partition_blocks(
    mesh: &mut Mesh,
    blocks: &[usize],
    inside: &[Vec<bool>],
    keep_inside: bool,
    moved: Option<(&dyn Fn(&str) -> String, &str)>,
) -> Vec<usize> {
    let mut new_blocks = Vec::new();
    for (&block, inside) in blocks.iter().zip(inside) {
        let b = &mesh.blocks[block];
        let npe = b.nodes_per_element();
        let (mut keep, mut other) = (Vec::new(), Vec::new());
        for (e, c) in b.connectivity.chunks(npe).enumerate() {
            if inside[e] == keep_inside {
                keep.extend_from_slice(c);
            } else {
                other.extend_from_slice(c);
            }
        }
        if let (Some((suffix, law)), false) = (&moved, other.is_empty()) {
            let mut pre = b.clone();
            pre.name = suffix(&b.name);
            pre.material = law.to_string();
            pre.connectivity = other;
            new_blocks.push(mesh.blocks.len());
            mesh.blocks.push(pre);
        }
        mesh.blocks[block].connectivity = keep;
    }
    new_blocks
}

/// The element set `name` of every element of `blocks`.
fn set_of_blocks(mesh: &mut Mesh, name: &str, blocks: &[usize]) {
    let set = blocks
        .iter()
        .flat_map(|&block| {
            (0..mesh.blocks[block].len())
                .map(move |element| junta_core::mesh::ElementRef { block, element })
        })
        .collect();
    mesh.element_sets.insert(name.to_string(), set);
}

/// Remove the blocks of `blocks` that have no element left (highest
/// index first); `blocks` keeps those that stay, at their new indices.
fn drop_empty(mesh: &mut Mesh, blocks: &mut Vec<usize>) {
    let mut sorted = blocks.clone();
    sorted.sort_unstable();
    for &b in sorted.iter().rev() {
        if mesh.blocks[b].is_empty() {
            remove_block(mesh, b);
            blocks.retain(|&x| x != b);
            for x in blocks.iter_mut() {
                if *x > b {
                    *x -= 1;
                }
            }
        }
    }
}

/// Move the elements of the interface blocks `blocks` (interface `name`)
/// whose centre lies in `[lo, hi]` to new blocks `NAME.precrack` (and
/// `NAME.tri.precrack` for the triangles of a mixed surface) with law
/// `law`; element sets `NAME` (bonded) and `NAME.precrack`.
fn split_precrack(
    mesh: &mut Mesh,
    blocks: &[usize],
    name: &str,
    within: [[f64; 3]; 2],
    law: &str,
) -> Result<()> {
    let [lo, hi] = within;
    let inside = centres_within(mesh, blocks, within);
    if !inside.iter().flatten().any(|&x| x) {
        bail!("no interface element lies in {lo:?} .. {hi:?}");
    }
    if inside.iter().flatten().all(|&x| x) {
        bail!("every interface element lies in {lo:?} .. {hi:?}: nothing is left bonded");
    }
    let suffix = |n: &str| format!("{n}.precrack");
    let mut pre = partition_blocks(mesh, blocks, &inside, false, Some((&suffix, law)));
    let mut kept = blocks.to_vec();
    // (the precrack blocks come after every interface block: removing an
    // emptied bonded block shifts them by one)
    let n_before = mesh.blocks.len();
    drop_empty(mesh, &mut kept);
    let shift = n_before - mesh.blocks.len();
    for p in &mut pre {
        *p -= shift;
    }
    set_of_blocks(mesh, name, &kept);
    set_of_blocks(mesh, &format!("{name}.precrack"), &pre);
    Ok(())
}

/// Keep only the elements of the interface blocks `blocks` (interface
/// `name`) whose centre lies in the box `[lo, hi]`; the rest of the
/// surface stays cut (traction free).
fn keep_within(mesh: &mut Mesh, blocks: &[usize], name: &str, within: [[f64; 3]; 2]) -> Result<()> {
    let [lo, hi] = within;
    let inside = centres_within(mesh, blocks, within);
    if !inside.iter().flatten().any(|&x| x) {
        bail!("no interface element lies in {lo:?} .. {hi:?}");
    }
    partition_blocks(mesh, blocks, &inside, true, None);
    let mut kept = blocks.to_vec();
    drop_empty(mesh, &mut kept);
    set_of_blocks(mesh, name, &kept);
    Ok(())
}

/// Build the element object of every block (after `[[blocks]]` overrides).
pub fn build_elements(
    sf: &SceneFile,
    mesh: &mut Mesh,
    materials: &BTreeMap<String, Arc<dyn Material>>,
    laws: &BTreeMap<String, Arc<dyn InterfaceLaw>>,
) -> Result<Vec<Arc<dyn Element>>> {
    for (i, b) in sf.scene.blocks.iter().enumerate() {
        let names: Vec<String> = mesh.blocks.iter().map(|b| b.name.clone()).collect();
        let block = mesh
            .blocks
            .iter_mut()
            .find(|mb| mb.name == *b.name.get_ref())
            .ok_or_else(|| {
                err!(
                    "{}: key `blocks[{i}].name`: no block `{}` in the mesh; blocks: {}",
                    sf.at(b.name.span()),
                    b.name.get_ref(),
                    names.join(", ")
                )
            })?;
        if let Some(el) = &b.element {
            block.element_type = el.get_ref().clone();
        }
        block.material = b.material.get_ref().clone();
    }
    let mut out = Vec::new();
    for (bi, block) in mesh.blocks.iter().enumerate() {
        let override_ = sf
            .scene
            .blocks
            .iter()
            .position(|b| *b.name.get_ref() == block.name);
        let boxes = sf.scene.mesh.as_ref().map_or(&[][..], |m| &m.boxes[..]);
        let part = boxes.iter().position(|b| b.name == block.name);
        // an interface's blocks: `NAME`, and `NAME.tri` on a surface of
        // triangles and quadrilaterals
        let iface = sf.scene.interface.iter().position(|f| {
            block.name == f.name || block.name.strip_suffix(".tri") == Some(f.name.as_str())
        });
        let mesh_element = sf.scene.mesh.as_ref().and_then(|m| m.element.as_ref());
        let laminate_element = sf.scene.laminate.as_ref().map(|l| &l.element);
        let where_ = match (override_, part, iface, mesh_element.or(laminate_element)) {
            (Some(i), _, _, _) => format!(
                "{}: key `blocks[{i}]`",
                sf.at(sf.scene.blocks[i].name.span())
            ),
            (_, Some(i), _, _) => {
                format!("{}: key `mesh.boxes[{i}]`", sf.at(boxes[i].element.span()))
            }
            (_, _, Some(i), _) => format!(
                "{}: key `interface[{i}]`",
                sf.at(sf.scene.interface[i].law.span())
            ),
            (_, _, _, Some(el)) if laminate_element.is_some() => {
                format!("{}: key `laminate`", sf.at(el.span()))
            }
            (_, _, _, Some(el)) => format!("{}: key `mesh`", sf.at(el.span())),
            _ => format!(
                "{}: block `{}` (give it a [[blocks]] entry)",
                sf.path.display(),
                block.name
            ),
        };
        let entry = registry::find::<ElementEntry>(&block.element_type)
            .map_err(|e| err!("{where_}: {e}"))?;
        if entry.shape != block.shape {
            bail!(
                "{where_}: element type `{}` needs {} cells but block `{}` has {} cells",
                entry.key,
                entry.shape.name(),
                block.name,
                block.shape.name()
            );
        }
        let mut options = plane_options(sf, mesh, bi)?;
        let (material, law) = if block.shape.is_interface() {
            let law = laws.get(&block.material).cloned().ok_or_else(|| {
                err!(
                    "{where_}: unknown law `{}`; laws defined in [laws]: {}",
                    block.material,
                    list_keys(laws)
                )
            })?;
            let laminate_rule = sf
                .scene
                .laminate
                .as_ref()
                .filter(|_| iface.is_none())
                .and_then(|l| l.integration.clone());
            let rule = iface.and_then(|i| sf.scene.interface[i].integration.clone());
            if let Some(r) = rule.or(laminate_rule) {
                options.insert("integration".into(), toml::Value::String(r));
            }
            (None, Some(law))
        } else {
            let m = materials.get(&block.material).cloned().ok_or_else(|| {
                err!(
                    "{where_}: unknown material `{}`; materials defined in [materials]: {}",
                    block.material,
                    list_keys(materials)
                )
            })?;
            (Some(m), None)
        };
        let el = (entry.build)(&ElementBuild {
            material,
            law,
            options: &options,
            kinematics: if sf.scene.analysis.nlgeom {
                Kinematics::Finite
            } else {
                Kinematics::Small
            },
        })
        .map_err(|e| err!("{where_}: {e}"))?;
        out.push(el);
    }
    Ok(out)
}

/// The options of a plane block `b` (plane elements, line interfaces):
/// `thickness` from `[model] thickness`, or `axisymmetric = true` for a
/// line interface of a model of cax elements (see [`ModelInfo::thickness`]).
fn plane_options(sf: &SceneFile, mesh: &Mesh, b: usize) -> Result<toml::Table> {
    let mut t = toml::Table::new();
    let block = &mesh.blocks[b];
    if block.shape.dimension() != 2 {
        return Ok(t);
    }
    let axisymmetric = mesh
        .blocks
        .iter()
        .any(|o| o.element_type.starts_with("cax"));
    match (axisymmetric, sf.scene.model.thickness) {
        (true, Some(_)) => bail!(
            "{}: key `model.thickness`: an axisymmetric model (cax elements) takes no thickness: it models the full ring",
            sf.path.display()
        ),
        (true, None) if block.shape.is_interface() => {
            t.insert("axisymmetric".into(), true.into());
        }
        (false, Some(w)) => {
            t.insert("thickness".into(), w.into());
        }
        _ => {}
    }
    Ok(t)
}

/// Translate the whole scene into a model.
pub fn build_model(sf: &SceneFile) -> Result<Model> {
    build_model_with_notes(sf, &mut Vec::new())
}

/// Translate the whole scene into a model; notes about the input (e.g. a
/// `total_force` shared equally because its set spans no face or edge) go
/// to `notes`.
pub fn build_model_with_notes(sf: &SceneFile, notes: &mut Vec<String>) -> Result<Model> {
    let mut materials =
        build_plugins::<MaterialEntry, _>(sf, "materials", &sf.scene.materials, |e, t| {
            (e.build)(t)
        })?;
    if let Some(l) = &sf.scene.laminate {
        crate::input::layup::add_ply_materials(sf, l, &mut materials)?;
    }
    let laws = build_laws(sf)?;
    let mut mesh = build_mesh(sf)?;
    let elements = build_elements(sf, &mut mesh, &materials, &laws)?;
    let (constraints, reaction_sets) = boundary_constraints(sf, &mesh)?;
    let f_ext = nodal_loads(sf, &mesh, &elements, notes)?;
    crate::prepare::limits::check_memory(
        &format!(
            "{}: the model ({} nodes, {} elements)",
            sf.path.display(),
            mesh.nodes.len(),
            mesh.num_elements()
        ),
        crate::prepare::limits::model_bytes(&mesh),
    )?;
    let constrained: std::collections::HashSet<usize> =
        constraints.iter().map(|&(d, _)| d).collect();
    let ties = crate::input::tie::equations(sf, &mesh, &constrained, notes)?;
    let mut model = Model::new(mesh, elements, &constraints, f_ext, reaction_sets)
        .map_err(|e| err!("{}: {e}", sf.path.display()))?;
    model
        .add_equations(&ties)
        .map_err(|e| err!("{}: key `tie`: {e}", sf.path.display()))?;
    if let Some(t) = &sf.scene.temperature {
        let delta = temperature_change(sf, t, &model, notes)?;
        model
            .set_temperature(Some(delta))
            .map_err(|e| err!("{}: key `temperature`: {e}", sf.path.display()))?;
    }
    Ok(model)
}

/// `[[boundary]]`: the prescribed dofs `(dof, value)` and the sets whose
/// reactions are reported.
fn boundary_constraints(
    sf: &SceneFile,
    mesh: &junta_core::mesh::Mesh,
) -> Result<(Vec<(usize, f64)>, Vec<String>)> {
    let mut constraints = Vec::new();
    let mut reaction_sets = Vec::new();
    for (i, bc) in sf.scene.boundary.iter().enumerate() {
        let set = bc.set.get_ref();
        let nodes = mesh
            .node_set(set)
            .map_err(|e| err!("{}: key `boundary[{i}].set`: {e}", sf.at(bc.set.span())))?;
        let mut comps: Vec<(usize, f64)> = Vec::new();
        match &bc.fixed {
            Some(Fixed::Word(w)) if w == "all" => comps.extend([(0, 0.0), (1, 0.0), (2, 0.0)]),
            Some(Fixed::Word(w)) => bail!(
                "{}: key `boundary[{i}].fixed`: `{w}` is not valid; use \"all\" or a list such as [\"x\", \"z\"]",
                sf.at(bc.set.span())
            ),
            Some(Fixed::List(l)) => {
                for c in l {
                    let k = component(c).ok_or_else(|| {
                        err!(
                            "{}: key `boundary[{i}].fixed`: component `{c}` is not valid; use x, y or z",
                            sf.at(bc.set.span())
                        )
                    })?;
                    comps.push((k, 0.0));
                }
            }
            None => {}
        }
        if let Some(d) = bc.displacement {
            for (k, v) in [d.x, d.y, d.z].into_iter().enumerate() {
                if let Some(v) = v {
                    comps.push((k, v));
                }
            }
        }
        if comps.is_empty() {
            bail!(
                "{}: key `boundary[{i}]`: give `fixed` and/or `displacement`",
                sf.at(bc.set.span())
            );
        }
        for &n in nodes {
            for &(k, v) in &comps {
                constraints.push((3 * n + k, v));
            }
        }
        if !reaction_sets.contains(set) {
            reaction_sets.push(set.clone());
        }
    }
    Ok((constraints, reaction_sets))
}

/// `[[load]]`: the external nodal forces at load factor 1.
fn nodal_loads(
    sf: &SceneFile,
    mesh: &junta_core::mesh::Mesh,
    elements: &[Arc<dyn Element>],
    notes: &mut Vec<String>,
) -> Result<Vec<f64>> {
    let mut f_ext = vec![0.0; 3 * mesh.nodes.len()];
    for (i, l) in sf.scene.load.iter().enumerate() {
        match (&l.set, &l.face_set) {
            (Some(set), None) => node_set_load(sf, i, l, set, mesh, notes, &mut f_ext)?,
            (None, Some(fs)) => face_set_load(sf, i, l, fs, mesh, elements, &mut f_ext)?,
            _ => bail!(
                "{}: key `load[{i}]`: give exactly one of `set` (nodal force) or `face_set` (pressure, traction)",
                sf.path.display()
            ),
        }
    }
    Ok(f_ext)
}

/// A `[[load]]` on a node set: `force` at each node, or `total_force`
/// shared by the set's nodes ([`total_force_weights`]).
fn node_set_load(
    sf: &SceneFile,
    i: usize,
    l: &LoadSpec,
    set: &Spanned<String>,
    mesh: &junta_core::mesh::Mesh,
    notes: &mut Vec<String>,
    f_ext: &mut [f64],
) -> Result<()> {
    if l.pressure.is_some() || l.traction.is_some() {
        bail!(
            "{}: key `load[{i}]`: `pressure` and `traction` need `face_set`, not `set`",
            sf.at(set.span())
        );
    }
    let nodes = mesh
        .node_set(set.get_ref())
        .map_err(|e| err!("{}: key `load[{i}].set`: {e}", sf.at(set.span())))?;
    if let Some(sp) = &l.split {
        if l.total_force.is_none() {
            bail!(
                "{}: key `load[{i}].split`: `split` goes with `total_force` on a node set (it says how the total is shared), not with `force`",
                sf.at(sp.span())
            );
        }
    }
    match (l.force, l.total_force) {
        (Some(f), None) => {
            for &n in nodes {
                for c in 0..3 {
                    f_ext[3 * n + c] += f[c];
                }
            }
        }
        (None, Some(t)) if !nodes.is_empty() => {
            let weights = total_force_weights(sf, i, l, set, mesh, nodes, notes)?;
            for (&n, w) in nodes.iter().zip(weights) {
                for c in 0..3 {
                    f_ext[3 * n + c] += w * t[c];
                }
            }
        }
        _ => bail!(
            "{}: key `load[{i}]`: a node-set load needs exactly one of `force = [fx, fy, fz]` (per node) or `total_force` (shared by the set's nodes, see `split`)",
            sf.at(set.span())
        ),
    }
    Ok(())
}

/// The shares of a `total_force` over the nodes of its set: from the
/// element faces or edges the set spans (`split = "consistent"`, the
/// default; a note when it spans none or leaves nodes out), or equal.
fn total_force_weights(
    sf: &SceneFile,
    i: usize,
    l: &LoadSpec,
    set: &Spanned<String>,
    mesh: &junta_core::mesh::Mesh,
    nodes: &[usize],
    notes: &mut Vec<String>,
) -> Result<Vec<f64>> {
    let split = l.split.as_ref().map(|s| (s.get_ref().as_str(), s.span()));
    let weights = match split {
        None | Some(("consistent", _)) => {
            let w = junta_elements::face_load::set_weights(mesh, nodes)
                .map_err(|e| {
                    err!("{}: key `load[{i}].total_force`: node set `{}`: {e}", sf.at(set.span()), set.get_ref())
                })?;
            if w.span == junta_elements::face_load::SetSpan::Points {
                notes.push(format!(
                    "{}: key `load[{i}]`: node set `{}` holds no complete element face or edge, so its {} nodes share `total_force` equally (write `split = \"equal\"` to say so)",
                    sf.at(set.span()),
                    set.get_ref(),
                    nodes.len()
                ));
            } else {
                let idle = w.off_span;
                if idle > 0 {
                    notes.push(format!(
                        "{}: key `load[{i}]`: {idle} of the {} nodes of set `{}` lie on none of the element {} it spans and get no share of `total_force`",
                        sf.at(set.span()),
                        nodes.len(),
                        set.get_ref(),
                        match w.span {
                            junta_elements::face_load::SetSpan::Faces(_) => "faces",
                            _ => "edges",
                        }
                    ));
                }
            }
            w.weights
        }
        Some(("equal", _)) => vec![1.0 / nodes.len() as f64; nodes.len()],
        Some((other, span)) => bail!(
            "{}: key `load[{i}].split`: `{other}` is not valid; use \"consistent\" (the default: shares from the element faces or edges the set spans) or \"equal\" (the same share for every node)",
            sf.at(span)
        ),
    };
    Ok(weights)
}

/// A `[[load]]` on a face set: `pressure` or `traction`.
fn face_set_load(
    sf: &SceneFile,
    i: usize,
    l: &LoadSpec,
    fs: &Spanned<String>,
    mesh: &junta_core::mesh::Mesh,
    elements: &[Arc<dyn Element>],
    f_ext: &mut [f64],
) -> Result<()> {
    let faces = mesh
        .face_set(fs.get_ref())
        .map_err(|e| err!("{}: key `load[{i}].face_set`: {e}", sf.at(fs.span())))?
        .to_vec();
    if let Some(sp) = &l.split {
        bail!(
            "{}: key `load[{i}].split`: `split` goes with `total_force` on a node set (`set`), not with `face_set`",
            sf.at(sp.span())
        );
    }
    let load = match (l.pressure, l.traction, l.force.or(l.total_force)) {
        (Some(p), None, None) => junta_elements::face_load::FaceLoad::Pressure(p),
        (None, Some(t), None) => junta_elements::face_load::FaceLoad::Traction(t),
        _ => bail!(
            "{}: key `load[{i}]`: a face-set load needs exactly one of `pressure` or `traction`",
            sf.at(fs.span())
        ),
    };
    let width = |b: usize| elements[b].plane_width();
    junta_elements::face_load::add_face_load_with(mesh, &faces, load, &width, f_ext)
        .map_err(|e| err!("{}: key `load[{i}]`: {e}", sf.at(fs.span())))?;
    Ok(())
}

/// The temperature change of every node from `[temperature]`
/// `stress_free`: `value` everywhere, then each `sets` entry on its nodes.
/// Notes when nothing changes or no material expands.
fn temperature_change(
    sf: &SceneFile,
    t: &TemperatureSpec,
    model: &Model,
    notes: &mut Vec<String>,
) -> Result<Vec<f64>> {
    let file = sf.path.display();
    let finite = |key: &str, v: f64| -> Result<()> {
        if !v.is_finite() {
            bail!("{file}: key `temperature.{key}`: {v} is not a finite temperature");
        }
        Ok(())
    };
    finite("stress_free", t.stress_free)?;
    let value = t.value.unwrap_or(t.stress_free);
    finite("value", value)?;
    let mesh = &model.mesh;
    let mut temp = vec![value; mesh.nodes.len()];
    for (i, s) in t.sets.iter().enumerate() {
        finite(&format!("sets[{i}].value"), s.value)?;
        let name = s.set.get_ref();
        let nodes: Vec<usize> = match (mesh.node_set(name), mesh.element_set(name)) {
            (Ok(n), _) => n.to_vec(),
            (_, Ok(els)) => els
                .iter()
                .flat_map(|er| mesh.blocks[er.block].element(er.element).iter().copied())
                .collect(),
            (Err(e), Err(_)) => bail!(
                "{}: key `temperature.sets[{i}].set`: {e} (an element set works too: its elements' nodes)",
                sf.at(s.set.span())
            ),
        };
        for n in nodes {
            temp[n] = s.value;
        }
    }
    let delta: Vec<f64> = temp.iter().map(|x| x - t.stress_free).collect();
    if delta.iter().all(|d| *d == 0.0) {
        notes.push(format!(
            "{file}: [temperature]: every node is at the stress-free temperature {}: no thermal strain",
            t.stress_free
        ));
    } else if !model.elements.iter().any(|e| e.has_thermal_expansion()) {
        notes.push(format!(
            "{file}: [temperature]: no solid's material has a thermal expansion coefficient (alpha; alpha1, alpha2, alpha3): the temperature change makes no strain"
        ));
    }
    Ok(delta)
}

/// The solver table of the scene (`type` plus parameters), or the default.
pub fn solver_table(sf: &SceneFile) -> (String, toml::Table) {
    match &sf.scene.solver {
        Some(t) => {
            let mut t = t.clone();
            let key = match t.remove("type") {
                Some(toml::Value::String(s)) => s,
                None => "auto".to_string(),
                // not a string (`type = 5`): keep it as text so that the
                // registry lookup names it with the valid keys
                Some(v) => v.to_string(),
            };
            (key, t)
        }
        None => ("auto".to_string(), toml::Table::new()),
    }
}
