//! Reader for Abaqus / CalculiX input decks (`.inp`): mesh, sets, elastic
//! materials, sections, boundary conditions, concentrated loads and one
//! static step.
//!
//! # Syntax accepted
//!
//! Keyword lines start with `*` and are case-insensitive; parameters are
//! `KEY=value` (or a bare `KEY`), comma separated; a keyword line ending with
//! a comma continues on the next line. `**` starts a comment line. Data lines
//! are comma separated; an element data line continues on the next line when
//! it ends with a comma (or holds the Abaqus maximum of 16 entries) and the
//! element still lacks nodes. Numbers may use a Fortran `D` exponent.
//!
//! Keywords: `*HEADING`, `*NODE [, NSET=]`, `*ELEMENT, TYPE= [, ELSET=]`,
//! `*NSET, NSET= [, GENERATE]`, `*ELSET, ELSET= [, GENERATE]`,
//! `*MATERIAL, NAME=`, `*ELASTIC [, TYPE=ISOTROPIC | ENGINEERING CONSTANTS |
//! ORTHO | TRACTION]`, `*DENSITY` (kept, noted as unused), `*DAMAGE INITIATION`,
//! `*DAMAGE EVOLUTION`, `*DAMAGE STABILIZATION` (cohesive damage, below),
//! `*SOLID SECTION, ELSET=, MATERIAL=`, `*COHESIVE SECTION, ELSET=,
//! MATERIAL=, RESPONSE=TRACTION SEPARATION [, THICKNESS=SPECIFIED]` (data
//! line: the constitutive thickness, default 1), `*BOUNDARY [,
//! OP=MOD|NEW] [, AMPLITUDE=]`, `*CLOAD [, OP=MOD|NEW] [, AMPLITUDE=]`
//! (also on `*DLOAD` and `*DSLOAD`; only inside a step), `*AMPLITUDE,
//! NAME= [, TIME=STEP TIME|TOTAL TIME] [, DEFINITION=TABULAR] [,
//! VALUE=RELATIVE] [, SHIFTX=, SHIFTY=]` ([`InpAmplitude`]), `*STEP [, NLGEOM, INC, NAME]` (any
//! number of steps), `*STATIC [, DIRECT] [, SOLVER=]` (data line `dt0, T, dtmin,
//! dtmax`; SOLVER is mapped to a back end by the CLI; TIME RESET, TOTAL TIME
//! AT START, ALLSDTOL, CONTINUE, FACTOR noted and skipped; RIKS,
//! STABILIZE, FULLY PLASTIC, LONG TERM refused), `*END STEP`; thermal
//! loads: `*EXPANSION [, TYPE=ISO|ORTHO|ANISO] [, ZERO=]` in a material
//! ([`InpExpansion`]), `*INITIAL CONDITIONS, TYPE=TEMPERATURE` and
//! `*TEMPERATURE [, OP=]` in a step ([`InpTemperature`]); `*MEMBRANE` on
//! an element set without elements (noted); the output requests `*NODE PRINT` (kept in [`InpDeck::node_prints`]: the CLI writes its `U` and `RF` as CSV) and `*EL PRINT` ([`InpDeck::el_prints`]: `S` and `E` as CSV), `*NODE FILE`,
//! `*EL FILE`, `*NODE OUTPUT`, `*ELEMENT OUTPUT`, `*OUTPUT` are
//! skipped with a note (Junta's outputs are chosen in the scene);
//! `*INCLUDE, INPUT=file` ([`read_inp`] puts the file's text in its place,
//! see [`expand_includes`]; errors then name the included file and its
//! line). Anything else is an error that lists these keywords.
//!
//! # Cohesive damage
//!
//! Inside a `*MATERIAL` whose `*ELASTIC, TYPE=TRACTION` gives `K_nn, K_ss,
//! K_tt`, and only for a material used by a `*COHESIVE SECTION`:
//!
//! - `*DAMAGE INITIATION, CRITERION=QUADS | MAXS`, data line `t_n^0, t_s^0,
//!   t_t^0` (nominal strengths) -> [`InpDamageInitiation`];
//! - `*DAMAGE EVOLUTION, TYPE=ENERGY [, SOFTENING=LINEAR | EXPONENTIAL] [,
//!   MIXED MODE BEHAVIOR=MODE INDEPENDENT | BK | POWER LAW, POWER=p]`, data
//!   line `G_c` (mode independent) or `G_Ic, G_IIc, G_IIIc` (as in Abaqus,
//!   the BK exponent eta and the power-law exponent alpha are the `POWER`
//!   parameter, not a data field) -> [`InpDamageEvolution`]; it must follow
//!   the `*DAMAGE INITIATION`; `DEGRADATION=MAXIMUM` (the default) is
//!   accepted;
//! - `*DAMAGE STABILIZATION`, data line: the viscosity coefficient ->
//!   [`InpDamageStabilization`].
//!
//! Errors, each naming file:line: a damage keyword outside a material; a
//! `*DAMAGE INITIATION` without `*DAMAGE EVOLUTION` (Abaqus would evaluate
//! the criterion but never soften); an unsupported option (`TYPE=
//! DISPLACEMENT`, `SOFTENING=TABULAR`, `MIXED MODE BEHAVIOR=TABULAR`, other
//! criteria, temperature-dependent data); damage on a material that is not
//! TRACTION, that a `*SOLID SECTION` uses, or that no `*COHESIVE SECTION`
//! uses. What the values become (the `bilinear` / `exponential` laws) is
//! decided by the CLI's deck builder.
//!
//! # Junta directives
//!
//! Comment lines `** junta: ...` (comments for Abaqus, so the deck still
//! runs there) carry what a deck has no keyword for:
//!
//! - `** junta: curve reaction_set=NSET reaction_component=x|y|z
//!   point_set=NSET point_component=x|y|z [relative_to=NSET]`: the
//!   load-displacement curve of an incremental run (as `[output.curve]` of a
//!   scene) -> [`InpDeck::curve`];
//! - `** junta: output every=N`: a frame every N increments ->
//!   [`InpDeck::every`].
//!
//! Unknown directives or keys are errors naming the line.
//!
//! # Names
//!
//! Set and material names are matched case-insensitively, as Abaqus does,
//! but are stored as first written (`*NSET, NSET=Bottom` gives the node set
//! `Bottom` in [`Mesh::node_sets`]; `BOTTOM` finds it in the deck).
//!
//! # Element types and node orders
//!
//! | TYPE   | shape  | `element_type` | conversion |
//! |--------|--------|----------------|------------|
//! | C3D8   | Hex8   | `h8`           | none (Abaqus = VTK = ours) |
//! | C3D8I  | Hex8   | `h8i`          | none (incompatible modes) |
//! | C3D20  | Hex20  | `h20`          | none |
//! | C3D20R | Hex20  | `h20r`         | none |
//! | C3D27  | Hex27  | `h27`          | face / body centres, see [`C3D27_TO_OURS`] |
//! | C3D6   | Wedge6 | `wedge6r`      | none (Abaqus = ours; VTK differs, mapped by the writer); CalculiX's 2-point rule |
//! | C3D15  | Wedge15| `wedge15`      | none |
//! | COH3D8 | Inter8 | `inter8`       | none: bottom face 1-4 then top face 5-8 |
//! | COH3D6 | Inter6 | `inter6`       | none: bottom triangle 1-3 then top triangle 4-6 (normal from 1-2-3 towards 4-6 by the right-hand rule) |
//!
//! Faces for `*DLOAD` `P1..P6` and `*SURFACE` `S1..S6`: hexahedra have six
//! ([`junta_core::topology::HEX_FACES`]), wedges five
//! ([`junta_core::topology::WEDGE_FACES`]: 1 = 1-2-3, 2 = 4-5-6, 3 = 1-2-5-4,
//! 4 = 2-3-6-5, 5 = 3-1-4-6, as in the Abaqus and CalculiX manuals); a
//! pressure on a face the element does not have (`P6` on a wedge) is an
//! error naming the line.
//!
//! Each (TYPE, ELSET) pair of `*ELEMENT` makes one [`ElementBlock`] named
//! after the ELSET (or the lower-case TYPE); when sections give the elements
//! of one block different materials the block is split into
//! `<name>_<material>` blocks. Element labels map to [`ElementRef`]s in
//! [`InpDeck::element_labels`].

use junta_core::mesh::{ElementBlock, ElementRef, Mesh};
use junta_core::topology::CellShape;
use rayon::prelude::*;
use rustc_hash::FxHashMap;
use std::collections::{BTreeMap, HashMap};
use std::path::Path;
use thiserror::Error;

/// `ours[i] = abaqus[C3D27_TO_OURS[i]]` (0-based).
///
/// Abaqus numbers the C3D27 nodes 21-26 at the centres of faces 1-6 and
/// node 27 at the centroid, the faces being (Abaqus Analysis User's Guide,
/// "Three-dimensional solid element library", face numbering of brick
/// elements): 1 = 1-2-3-4 (z-), 2 = 5-8-7-6 (z+), 3 = 1-5-6-2 (y-),
/// 4 = 2-6-7-3 (x+), 5 = 3-7-8-4 (y+), 6 = 4-8-5-1 (x-). The same face
/// order is the S1..S6 order of [`junta_core::topology::HEX_FACES`]. Ours puts
/// the face centres in VTK order x-, x+, y-, y+, z-, z+.
pub const C3D27_TO_OURS: [usize; 27] = [
    0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16, 17, 18, 19, //
    25, 23, 22, 24, 20, 21, 26,
];

/// Keywords the reader understands (for messages).
pub const SUPPORTED_KEYWORDS: &str =
    "*HEADING, *NODE, *ELEMENT, *NSET, *ELSET, *MATERIAL, *ELASTIC, *DENSITY, \
*DAMAGE INITIATION, *DAMAGE EVOLUTION, *DAMAGE STABILIZATION, \
*EXPANSION, *SOLID SECTION, *COHESIVE SECTION, *MEMBRANE (on an empty element set), *BOUNDARY, *CLOAD, *AMPLITUDE, *DLOAD, *DSLOAD, *SURFACE, *EQUATION, \
*INITIAL CONDITIONS (TYPE=TEMPERATURE), *TEMPERATURE, *STEP, *STATIC, *CONTROLS, *END STEP, \
*NODE PRINT, *NODE FILE, *EL PRINT, *EL FILE, *NODE OUTPUT, *ELEMENT OUTPUT, *OUTPUT, *INCLUDE";

/// Element types the reader understands (for messages).
pub const SUPPORTED_ELEMENT_TYPES: &str =
    "C3D8, C3D8I, C3D20, C3D20R, C3D27, C3D6, C3D15, COH3D8, COH3D6";

const OUTPUT_KEYWORDS: [&str; 7] = [
    "NODE PRINT",
    "NODE FILE",
    "EL PRINT",
    "EL FILE",
    "NODE OUTPUT",
    "ELEMENT OUTPUT",
    "OUTPUT",
];

/// Errors of the deck reader. Each names the file, the 1-based line, the
/// keyword, and what would be valid.
#[derive(Debug, Error)]
pub enum InpError {
    /// The file could not be read.
    #[error("cannot read `{file}`: {source}")]
    Io {
        /// The file that could not be read (the deck or an included file).
        file: String,
        /// The operating system's error.
        #[source]
        source: std::io::Error,
    },
    /// A keyword the reader does not support.
    #[error("{file}:{line}: unsupported keyword `*{keyword}`; supported keywords: {valid}")]
    UnknownKeyword {
        /// The deck, or the included file the line comes from.
        file: String,
        /// Line in that file (1-based).
        line: usize,
        /// The keyword, upper case, without its `*`.
        keyword: String,
        /// The supported keywords ([`SUPPORTED_KEYWORDS`]).
        valid: String,
    },
    /// A parameter the keyword does not accept, or a bad parameter value.
    #[error("{file}:{line}: *{keyword}: unsupported parameter `{parameter}`; valid: {valid}")]
    Parameter {
        /// The deck, or the included file the line comes from.
        file: String,
        /// Line in that file (1-based).
        line: usize,
        /// The keyword, upper case, without its `*` (for a directive,
        /// `** junta: NAME`).
        keyword: String,
        /// The parameter (upper case), with its value when the value is
        /// at fault (`KEY=value`).
        parameter: String,
        /// The parameters (or values) the keyword accepts.
        valid: String,
    },
    /// A required parameter is missing.
    #[error("{file}:{line}: *{keyword} needs the parameter {parameter}")]
    MissingParameter {
        /// The deck, or the included file the line comes from.
        file: String,
        /// Line in that file (1-based).
        line: usize,
        /// The keyword, upper case, without its `*` (for a directive,
        /// `** junta: NAME`).
        keyword: String,
        /// The missing parameter (e.g. `TYPE=`).
        parameter: String,
    },
    /// An element TYPE the reader does not support.
    #[error("{file}:{line}: *ELEMENT: unsupported element TYPE={element_type}; supported types: {valid}")]
    ElementType {
        /// The deck, or the included file the line comes from.
        file: String,
        /// Line in that file (1-based).
        line: usize,
        /// The `TYPE=` value, upper case.
        element_type: String,
        /// The supported types ([`SUPPORTED_ELEMENT_TYPES`]).
        valid: String,
    },
    /// A field that should be a number is not.
    #[error("{file}:{line}: *{keyword}: {what} `{text}` is not a valid {expected}")]
    BadNumber {
        /// The deck, or the included file the line comes from.
        file: String,
        /// Line in that file (1-based).
        line: usize,
        /// The keyword, upper case, without its `*` (for a directive,
        /// `** junta: NAME`).
        keyword: String,
        /// What the field holds (e.g. `"node label"`, `"density"`).
        what: String,
        /// The field as written.
        text: String,
        /// What it should be: `"number"` (finite) or `"positive integer
        /// label"`.
        expected: &'static str,
    },
    /// A node or element label that was never defined.
    #[error("{file}:{line}: *{keyword}: {kind} label {label} is not defined")]
    UndefinedLabel {
        /// The deck, or the included file the line comes from.
        file: String,
        /// Line in that file (1-based).
        line: usize,
        /// The keyword, upper case, without its `*` (for a directive,
        /// `** junta: NAME`).
        keyword: String,
        /// `"node"` or `"element"`.
        kind: &'static str,
        /// The label as written in the deck.
        label: usize,
    },
    /// A set or material name that was never defined.
    #[error("{file}:{line}: *{keyword}: {kind} `{name}` is not defined; defined: {valid}")]
    UnknownName {
        /// The deck, or the included file the line comes from.
        file: String,
        /// Line in that file (1-based).
        line: usize,
        /// The keyword, upper case, without its `*` (for a directive,
        /// `** junta: NAME`).
        keyword: String,
        /// What was named: `"node set"`, `"element set"`, `"material"` or
        /// `"orientation"`.
        kind: &'static str,
        /// The name as written.
        name: String,
        /// The names of that kind the deck defines (`(none)` if none).
        valid: String,
    },
    /// Any other mistake in the deck.
    #[error("{file}:{line}: *{keyword}: {message}")]
    Invalid {
        /// The deck, or the included file the line comes from.
        file: String,
        /// Line in that file (1-based).
        line: usize,
        /// The keyword, upper case, without its `*` (for a directive,
        /// `** junta: NAME`).
        keyword: String,
        /// What is wrong, and what would be valid.
        message: String,
    },
}

/// Elastic constants of a material.
#[derive(Debug, Clone, PartialEq)]
pub enum InpMaterialKind {
    /// `*ELASTIC` (TYPE=ISOTROPIC): Young's modulus and Poisson's ratio.
    Isotropic {
        /// Young's modulus `E` (stress units).
        e: f64,
        /// Poisson's ratio `nu`.
        nu: f64,
    },
    /// `*ELASTIC, TYPE=ENGINEERING CONSTANTS`:
    /// `[E1, E2, E3, nu12, nu13, nu23, G12, G13, G23]`.
    EngineeringConstants([f64; 9]),
    /// `*ELASTIC, TYPE=TRACTION` (cohesive): `[K_nn, K_ss, K_tt]`.
    Traction([f64; 3]),
    /// `*ELASTIC, TYPE=ANISO`: the 21 constants `D1111, D1122, D2222, ...,
    /// D2323` in the Abaqus order.
    Anisotropic(Box<[f64; 21]>),
}

/// A `*MATERIAL` with its `*ELASTIC` data and, for cohesive elements, its
/// damage options.
#[derive(Debug, Clone, PartialEq)]
pub struct InpMaterial {
    /// Name as written.
    pub name: String,
    /// Elastic constants.
    pub kind: InpMaterialKind,
    /// `*DENSITY`, if given (not used by static analyses).
    pub density: Option<f64>,
    /// Line of `*MATERIAL`.
    pub line: usize,
    /// Line of the `*ELASTIC` data line.
    pub elastic_line: usize,
    /// `*DAMAGE INITIATION`, if given.
    pub damage_initiation: Option<InpDamageInitiation>,
    /// `*DAMAGE EVOLUTION`, if given.
    pub damage_evolution: Option<InpDamageEvolution>,
    /// `*DAMAGE STABILIZATION`, if given.
    pub damage_stabilization: Option<InpDamageStabilization>,
    /// `*EXPANSION`, if given.
    pub expansion: Option<InpExpansion>,
}

/// `*EXPANSION [, TYPE=ISO | ORTHO | ANISO] [, ZERO=]`: thermal expansion
/// coefficients, constant in temperature (one data line; a temperature
/// given on it is ignored with a note). With constant coefficients
/// `ZERO=` (the reference temperature of the secant coefficients) does not
/// change the thermal strain `alpha (T - T_initial)` and is noted.
#[derive(Debug, Clone, PartialEq)]
pub enum InpExpansion {
    /// `TYPE=ISO` (default): `alpha`.
    Isotropic(f64),
    /// `TYPE=ORTHO`: `alpha_11, alpha_22, alpha_33` in the material axes.
    Orthotropic([f64; 3]),
    /// `TYPE=ANISO`: `alpha_11, alpha_22, alpha_33, alpha_12, alpha_13,
    /// alpha_23` (tensor components, material axes).
    Anisotropic([f64; 6]),
}

/// A temperature data line of `*INITIAL CONDITIONS, TYPE=TEMPERATURE` or
/// `*TEMPERATURE`: `node or node set, temperature`.
#[derive(Debug, Clone, PartialEq)]
pub struct InpTemperature {
    /// Node set name or node label, as written.
    pub target: String,
    /// 0-based node ids.
    pub nodes: Vec<usize>,
    /// The temperature.
    pub value: f64,
    /// `*TEMPERATURE`: index of its step in [`InpDeck::steps`] (`None` for
    /// an initial condition).
    pub step: Option<usize>,
    /// The `*TEMPERATURE` keyword had `OP=NEW`: the temperatures of earlier
    /// steps are dropped (back to the initial ones) from this step on.
    pub op_new: bool,
    /// Line of the data line.
    pub line: usize,
}

impl InpMaterial {
    /// The material has damage options (a softening cohesive material).
    pub fn has_damage(&self) -> bool {
        self.damage_initiation.is_some()
            || self.damage_evolution.is_some()
            || self.damage_stabilization.is_some()
    }
}

/// Damage-initiation criterion of a cohesive material.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum InpOnset {
    /// `CRITERION=QUADS`: quadratic nominal-stress criterion.
    Quads,
    /// `CRITERION=MAXS`: maximum nominal-stress criterion.
    Maxs,
}

/// `*DAMAGE INITIATION, CRITERION=QUADS | MAXS`.
#[derive(Debug, Clone, PartialEq)]
pub struct InpDamageInitiation {
    /// The criterion.
    pub criterion: InpOnset,
    /// Nominal strengths `[t_n^0, t_s^0, t_t^0]`.
    pub strengths: [f64; 3],
    /// Line of the keyword.
    pub line: usize,
    /// Line of the data line.
    pub data_line: usize,
}

/// `SOFTENING=` of `*DAMAGE EVOLUTION`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum InpSoftening {
    /// `LINEAR` (the default).
    Linear,
    /// `EXPONENTIAL`.
    Exponential,
}

/// `MIXED MODE BEHAVIOR=` of `*DAMAGE EVOLUTION, TYPE=ENERGY`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum InpMixedMode {
    /// `MODE INDEPENDENT` (the default): one fracture energy.
    ModeIndependent,
    /// `BK` with `POWER=eta`.
    Bk {
        /// The BK exponent eta (`POWER=`).
        power: f64,
    },
    /// `POWER LAW` with `POWER=alpha`.
    PowerLaw {
        /// The power-law exponent alpha (`POWER=`).
        power: f64,
    },
}

/// `*DAMAGE EVOLUTION, TYPE=ENERGY`.
#[derive(Debug, Clone, PartialEq)]
pub struct InpDamageEvolution {
    /// Softening shape.
    pub softening: InpSoftening,
    /// Mixed-mode rule.
    pub mixed_mode: InpMixedMode,
    /// Fracture energies `[G_Ic, G_IIc, G_IIIc]` (all three equal for
    /// `MODE INDEPENDENT`).
    pub toughness: [f64; 3],
    /// Line of the keyword.
    pub line: usize,
    /// Line of the data line.
    pub data_line: usize,
}

/// `*DAMAGE STABILIZATION`: viscous regularisation.
#[derive(Debug, Clone, PartialEq)]
pub struct InpDamageStabilization {
    /// Viscosity coefficient (step-time units).
    pub viscosity: f64,
    /// Line of the keyword.
    pub line: usize,
}

/// The deck-side curve definition, from the comment directive
/// `** junta: curve reaction_set=.. reaction_component=.. point_set=..
/// point_component=.. [relative_to=..]` (a comment for Abaqus). Set names
/// are resolved to the names stored in [`Mesh::node_sets`].
#[derive(Debug, Clone, PartialEq)]
pub struct InpCurve {
    /// Node set whose total internal force is recorded (the reaction on
    /// supports, the applied load on a loaded free set).
    pub reaction_set: String,
    /// Its component: `x`, `y` or `z` (lower case).
    pub reaction_component: String,
    /// Node set whose mean displacement is recorded.
    pub point_set: String,
    /// Its component: `x`, `y` or `z` (lower case).
    pub point_component: String,
    /// Node set whose mean displacement (same component) is subtracted,
    /// for a relative displacement (e.g. the opening of a DCB's arms).
    pub relative_to: Option<String>,
    /// Line of the directive.
    pub line: usize,
}

/// A `*SOLID SECTION`.
#[derive(Debug, Clone, PartialEq)]
pub struct InpSolidSection {
    /// Element set as written.
    pub elset: String,
    /// Material name as written in `*MATERIAL`.
    pub material: String,
    /// `ORIENTATION=` name as written.
    pub orientation: Option<String>,
    /// Line of the keyword.
    pub line: usize,
}

/// A `*COHESIVE SECTION`.
#[derive(Debug, Clone, PartialEq)]
pub struct InpCohesiveSection {
    /// Element set as written.
    pub elset: String,
    /// Material name as written in `*MATERIAL`.
    pub material: String,
    /// RESPONSE parameter, upper case (`TRACTION SEPARATION`).
    pub response: String,
    /// Initial constitutive thickness from the data line, if given.
    pub thickness: Option<f64>,
    /// Line of the keyword.
    pub line: usize,
}

/// A `*BOUNDARY` data line: prescribed value on dofs `first_dof..=last_dof`
/// (1-based, 1..=3) of the target's nodes.
#[derive(Debug, Clone, PartialEq)]
pub struct InpBoundary {
    /// Node set name or node label, as written.
    pub target: String,
    /// 0-based node ids of the target.
    pub nodes: Vec<usize>,
    /// First dof, 1-based.
    pub first_dof: usize,
    /// Last dof, 1-based (inclusive).
    pub last_dof: usize,
    /// Prescribed value (0 when not given).
    pub value: f64,
    /// Given inside `*STEP` (history data) rather than as model data.
    pub in_step: bool,
    /// Index of that step in [`InpDeck::steps`].
    pub step: Option<usize>,
    /// The keyword had `OP=NEW`: every boundary condition given before it
    /// is removed (from its step on).
    pub op_new: bool,
    /// Line of the `*BOUNDARY` keyword.
    pub keyword_line: usize,
    /// Line of the data line.
    pub line: usize,
    /// `AMPLITUDE=`: index in [`InpDeck::amplitudes`].
    pub amplitude: Option<usize>,
}

/// A `*CLOAD` data line: force `value` on dof `dof` of every target node.
#[derive(Debug, Clone, PartialEq)]
pub struct InpCload {
    /// Node set name or node label, as written.
    pub target: String,
    /// 0-based node ids.
    pub nodes: Vec<usize>,
    /// Dof, 1-based (1..=3).
    pub dof: usize,
    /// Force per node.
    pub value: f64,
    /// Given inside `*STEP`.
    pub in_step: bool,
    /// Index of that step in [`InpDeck::steps`].
    pub step: Option<usize>,
    /// The keyword had `OP=NEW`: every concentrated load given before it is
    /// removed (from its step on).
    pub op_new: bool,
    /// Line of the `*CLOAD` keyword.
    pub keyword_line: usize,
    /// Line of the data line.
    pub line: usize,
    /// `AMPLITUDE=`: index in [`InpDeck::amplitudes`].
    pub amplitude: Option<usize>,
}

/// The `*STATIC` procedure of a step (data line values, all optional).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct InpStatic {
    /// First value, `dt0`: the initial time increment (step-time units).
    pub initial_increment: Option<f64>,
    /// Second value, `T`: the step's time period.
    pub period: Option<f64>,
    /// Third value, `dtmin`: the smallest time increment allowed.
    pub min_increment: Option<f64>,
    /// Fourth value, `dtmax`: the largest time increment allowed.
    pub max_increment: Option<f64>,
    /// DIRECT parameter (fixed increments).
    pub direct: bool,
    /// `SOLVER=` (upper case, as written): the CLI maps it to a back end.
    pub solver: Option<String>,
    /// `RIKS` (Abaqus arc length): the CLI runs it with path following.
    pub riks: Option<InpRiks>,
    /// Line of the `*STATIC` keyword.
    pub line: usize,
}

/// `*STATIC, RIKS` data beyond the four increment values: the maximum load
/// proportionality factor (the 5th value), which ends the run.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct InpRiks {
    /// The maximum load proportionality factor; `None` when the field is
    /// empty.
    pub max_load_factor: Option<f64>,
}

/// Parameters of `*STATIC` that do not change a linear-static or
/// incremental result of Junta (noted and skipped): CalculiX `TIME RESET`,
/// `TOTAL TIME AT START` (time labels only), Abaqus `ALLSDTOL`, `CONTINUE`,
/// `FACTOR` (automatic stabilisation controls without `STABILIZE`).
const STATIC_NOTED: [&str; 5] = [
    "TIME RESET",
    "TOTAL TIME AT START",
    "ALLSDTOL",
    "CONTINUE",
    "FACTOR",
];

/// Parameters of `*STATIC` that change the answer and that Junta does not
/// have: an error naming the line.
const STATIC_REFUSED: [(&str, &str); 3] = [
    ("STABILIZE", "automatic viscous stabilisation"),
    ("FULLY PLASTIC", "fully plastic limit analysis"),
    ("LONG TERM", "long-term viscoelastic response"),
];

/// A `*STEP ... *END STEP`.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct InpStep {
    /// `NAME=`, as written.
    pub name: Option<String>,
    /// NLGEOM (YES when given without value).
    pub nlgeom: bool,
    /// INC (maximum number of increments).
    pub max_increments: Option<usize>,
    /// The `*STATIC` procedure, if any.
    pub static_procedure: Option<InpStatic>,
    /// Line of `*STEP`.
    pub line: usize,
}

/// Everything read from a deck.
///
/// - `mesh`: nodes (labels in [`Mesh::node_labels`]), blocks (one per
///   TYPE / ELSET / material), node sets (`*NSET`, `*NODE, NSET=`), element
///   sets (`*ELSET`, `*ELEMENT, ELSET=`); no face sets.
/// - `element_labels`: element label -> [`ElementRef`].
/// - `materials`, `solid_sections`, `cohesive_sections`: as written; block
///   materials already carry the section materials.
/// - `boundaries`, `cloads`: targets resolved to node ids.
/// - `steps`: in order; boundaries and loads say which step they belong to
///   (`None`: model data) and whether their keyword had `OP=NEW`.
/// - `notes`: what was accepted but ignored, with line numbers.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct InpDeck {
    /// Nodes, blocks, node and element sets (no face sets).
    pub mesh: Mesh,
    /// Element label -> block and index in the block.
    pub element_labels: BTreeMap<usize, ElementRef>,
    /// The `*HEADING` data lines, joined by newlines.
    pub heading: String,
    /// `*MATERIAL`s, in input order.
    pub materials: Vec<InpMaterial>,
    /// `*SOLID SECTION`s, in input order.
    pub solid_sections: Vec<InpSolidSection>,
    /// `*COHESIVE SECTION`s, in input order.
    pub cohesive_sections: Vec<InpCohesiveSection>,
    /// `*BOUNDARY` data lines, in input order.
    pub boundaries: Vec<InpBoundary>,
    /// `*CLOAD` data lines, in input order.
    pub cloads: Vec<InpCload>,
    /// `*STEP`s, in input order.
    pub steps: Vec<InpStep>,
    /// What was accepted but ignored or changed, with line numbers.
    pub notes: Vec<String>,
    /// `** junta: curve ...` directive, if any.
    pub curve: Option<InpCurve>,
    /// `** junta: output every=N` directive, if any.
    pub every: Option<usize>,
    /// `*NODE PRINT` requests, in order.
    pub node_prints: Vec<InpNodePrint>,
    /// `*EL PRINT` requests, in order.
    pub el_prints: Vec<InpElPrint>,
    /// `*EQUATION`s, node sets expanded (one equation per member).
    pub equations: Vec<InpEquation>,
    /// `*DLOAD` and `*DSLOAD` distributed loads, in input order.
    pub dloads: Vec<InpDload>,
    /// Node surfaces (`*SURFACE, TYPE=NODE`): name (upper case) -> nodes.
    pub node_surfaces: BTreeMap<String, Vec<usize>>,
    /// `*ORIENTATION`s (rectangular and cylindrical systems).
    pub orientations: Vec<InpOrientation>,
    /// Orientation of each mesh block (index-aligned with `mesh.blocks`):
    /// its index in `orientations`, from `*SOLID SECTION, ORIENTATION=`.
    pub block_orientations: Vec<Option<usize>>,
    /// `*AMPLITUDE`s, in input order.
    pub amplitudes: Vec<InpAmplitude>,
    /// `*INITIAL CONDITIONS, TYPE=TEMPERATURE` and `*TEMPERATURE` data
    /// lines, in deck order.
    pub temperatures: Vec<InpTemperature>,
}

/// A tabular `*AMPLITUDE`: the factor `a(t)` by which the loads and
/// prescribed displacements that name it (`AMPLITUDE=` on `*CLOAD`,
/// `*BOUNDARY`, `*DLOAD`, `*DSLOAD`) are multiplied at time `t`.
///
/// `a(t)` is linear between the points `(t_i, a_i)` (times non-decreasing;
/// two equal times make a jump, the later value holding from that time on)
/// and constant outside them (the first value before `t_1`, the last after
/// `t_n`), as in Abaqus and CalculiX. `t` is the step time, or the total
/// time with `TIME=TOTAL TIME`. `SHIFTX` / `SHIFTY` (CalculiX) are added to
/// the times / values when the deck is read.
#[derive(Debug, Clone, PartialEq)]
pub struct InpAmplitude {
    /// `NAME=` as written.
    pub name: String,
    /// `(t_i, a_i)`, at least one.
    pub points: Vec<(f64, f64)>,
    /// `TIME=TOTAL TIME` (otherwise step time).
    pub total_time: bool,
    /// Line of the keyword.
    pub line: usize,
}

impl InpAmplitude {
    /// `a(t)` (see the type's docs).
    pub fn value(&self, t: f64) -> f64 {
        let p = &self.points;
        // first point later than t: t lies in [p[k - 1], p[k])
        let k = p.partition_point(|q| q.0 <= t);
        if k == 0 {
            return p[0].1;
        }
        if k == p.len() {
            return p[k - 1].1;
        }
        let ((t0, a0), (t1, a1)) = (p[k - 1], p[k]);
        a0 + (a1 - a0) * (t - t0) / (t1 - t0)
    }
}

/// An `*ORIENTATION`. Rectangular: material axis 1 along `a - c`, `b - c`
/// in the 1-2 plane (`c` the origin, default 0). Cylindrical: `a`, `b` two
/// points of the cylinder axis; at a point the material axes are r (1,
/// radial), theta (2), z (3, along `b - a`), as in CalculiX.
#[derive(Debug, Clone, PartialEq)]
pub struct InpOrientation {
    /// Name as written.
    pub name: String,
    /// Rectangular: material axis 1 direction (`a - c`). Cylindrical: point a of the axis.
    pub a: [f64; 3],
    /// Rectangular: a direction in the material 1-2 plane (`b - c`).
    /// Cylindrical: point b of the axis (`b != a`).
    pub b: [f64; 3],
    /// `SYSTEM=CYLINDRICAL`.
    pub cylindrical: bool,
    /// Line of the keyword.
    pub line: usize,
}

/// What a distributed load does.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum InpDloadKind {
    /// Pressure on one face of each element (positive into the solid).
    Pressure(f64),
    /// `GRAV`: acceleration vector (magnitude times the normalised
    /// direction); the force is density times it.
    Gravity([f64; 3]),
    /// `CENTRIF`: `omega^2`, a point of the axis, the axis direction.
    Centrifugal {
        /// Square of the angular velocity, `omega^2` (1 / time^2).
        omega2: f64,
        /// A point of the rotation axis.
        point: [f64; 3],
        /// Direction of the rotation axis, as written (not normalised).
        axis: [f64; 3],
    },
    /// `BX`, `BY`, `BZ`: body force per unit volume (no density).
    BodyForce([f64; 3]),
}

/// A `*DLOAD` or `*DSLOAD` data line, targets resolved.
#[derive(Debug, Clone, PartialEq)]
pub struct InpDload {
    /// Load label as written, upper case (`P3`, `GRAV`, `CENTRIF`, `BZ`;
    /// `P` for a `*DSLOAD` surface pressure).
    pub label: String,
    /// The load and its values.
    pub kind: InpDloadKind,
    /// `(element, face)`: the face (0-based, S1..S6 order of hexahedra,
    /// S1..S5 of wedges) for pressures,
    /// 0 for body loads.
    pub elements: Vec<(ElementRef, usize)>,
    /// Index of the enclosing step (`None`: model data).
    pub step: Option<usize>,
    /// `OP=NEW`: distributed loads given before are removed.
    pub op_new: bool,
    /// Line of the keyword.
    pub keyword_line: usize,
    /// Line of the data line.
    pub line: usize,
    /// `AMPLITUDE=`: index in [`InpDeck::amplitudes`].
    pub amplitude: Option<usize>,
}

/// One linear equation `sum a_k u_k = 0` of an `*EQUATION` (the first term
/// is the dependent one).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct InpEquation {
    /// `(node id (0-based), dof (1..=3), coefficient)`.
    pub terms: Vec<(usize, usize, f64)>,
    /// Line of the equation's first data line.
    pub line: usize,
}

/// A `*NODE PRINT, NSET= [, TOTALS=YES|ONLY|NO]` request: its data lines
/// name the variables (`U`, `RF`, ...), upper case. The set name is as
/// written (matched case-insensitively); `step` is the index of the
/// enclosing `*STEP` (`None`: outside any step).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct InpNodePrint {
    /// `NSET=`, as written.
    pub nset: String,
    /// The variables of the data lines (`U`, `RF`, ...), upper case.
    pub variables: Vec<String>,
    /// `TOTALS=`: `NO` (default), `YES` (rows and their sum) or `ONLY`.
    pub totals: String,
    /// Index of the enclosing step in [`InpDeck::steps`] (`None`: outside
    /// any step).
    pub step: Option<usize>,
    /// Line of the keyword.
    pub line: usize,
}

/// An `*EL PRINT, ELSET=` request: element variables (`S`, `E`, ...) of
/// the set's elements at their integration points.
#[derive(Debug, Clone, PartialEq)]
pub struct InpElPrint {
    /// `ELSET=`, as written (matched case-insensitively).
    pub elset: String,
    /// Upper case, as written (default `S`).
    pub variables: Vec<String>,
    /// `GLOBAL=YES`: global axes also for elements with an orientation
    /// (default `NO`: as CalculiX, their material axes at each point).
    pub global: bool,
    /// Index of the enclosing step in [`InpDeck::steps`] (`None`: outside
    /// any step).
    pub step: Option<usize>,
    /// Line of the keyword.
    pub line: usize,
}

impl InpDeck {
    /// Material by name (case-insensitive).
    pub fn material(&self, name: &str) -> Option<&InpMaterial> {
        self.materials
            .iter()
            .find(|m| m.name.eq_ignore_ascii_case(name))
    }
}

/// Read a deck from a file, with its `*INCLUDE, INPUT=` files in place
/// ([`expand_includes`]); an error names the file and line it comes from,
/// included files too.
pub fn read_inp(path: impl AsRef<Path>) -> Result<InpDeck, InpError> {
    let expanded = expand_includes(path.as_ref())?;
    let main = expanded.files[0].clone();
    parse_inp(&expanded.text, &main).map_err(|e| expanded.relocate(e))
}

/// Deepest chain of `*INCLUDE`s followed.
pub const MAX_INCLUDE_DEPTH: usize = 16;
/// Largest expanded deck in bytes (1 GiB): a deck that includes the same
/// file many times over at several levels grows exponentially.
pub const MAX_EXPANDED_BYTES: usize = 1 << 30;

/// A deck with its `*INCLUDE` lines replaced by the included files' text,
/// and for every line of that text the file and line it came from.
#[derive(Debug, Clone)]
pub struct ExpandedDeck {
    /// The text, includes in place.
    pub text: String,
    /// The files read: the deck first, then each included file once.
    pub files: Vec<String>,
    /// `(file index, 1-based line)` of each line of `text`.
    origin: Vec<(u32, u32)>,
}

impl ExpandedDeck {
    /// `err` (located in `text`, named after `files[0]`) with the file and
    /// line of the deck or included file the line came from.
    pub fn relocate(&self, mut err: InpError) -> InpError {
        use InpError::*;
        let loc = match &mut err {
            Io { .. } => None,
            UnknownKeyword { file, line, .. }
            | Parameter { file, line, .. }
            | MissingParameter { file, line, .. }
            | ElementType { file, line, .. }
            | BadNumber { file, line, .. }
            | UndefinedLabel { file, line, .. }
            | UnknownName { file, line, .. }
            | Invalid { file, line, .. } => Some((file, line)),
        };
        if let Some((file, line)) = loc {
            if let Some(&(f, l)) = line.checked_sub(1).and_then(|i| self.origin.get(i)) {
                *file = self.files[f as usize].clone();
                *line = l as usize;
            }
        }
        err
    }
}

/// The `INPUT=` file of an `*INCLUDE` keyword line (`None` if `line` is
/// not one; `Some(Err(..))` without an `INPUT`).
fn include_target(line: &str) -> Option<Result<String, ()>> {
    let rest = line.trim().strip_prefix('*')?;
    let mut parts = rest.split(',');
    if norm_key(parts.next()?) != "INCLUDE" {
        return None;
    }
    for p in parts {
        if let Some((k, v)) = p.split_once('=') {
            if norm_key(k) == "INPUT" {
                let v = v.trim().trim_matches('"').trim_matches('\'').trim();
                return Some(if v.is_empty() {
                    Err(())
                } else {
                    Ok(v.to_string())
                });
            }
        }
    }
    Some(Err(()))
}

/// Read `path` and, recursively, every file an `*INCLUDE, INPUT=name`
/// line names (CalculiX and Abaqus), in place of that line. A relative
/// name is looked for next to the file that includes it, then in the
/// working directory. Errors, naming the including file and line: a
/// missing `INPUT`, a file that cannot be read, an include cycle, more
/// than [`MAX_INCLUDE_DEPTH`] levels, or an expanded deck over
/// [`MAX_EXPANDED_BYTES`].
pub fn expand_includes(path: &Path) -> Result<ExpandedDeck, InpError> {
    let mut out = ExpandedDeck {
        text: String::new(),
        files: Vec::new(),
        origin: Vec::new(),
    };
    let text = std::fs::read_to_string(path).map_err(|source| InpError::Io {
        file: path.display().to_string(),
        source,
    })?;
    let mut stack = Vec::new();
    expand_into(path, text, &mut out, &mut stack)?;
    Ok(out)
}

fn expand_into(
    path: &Path,
    text: String,
    out: &mut ExpandedDeck,
    stack: &mut Vec<std::path::PathBuf>,
) -> Result<(), InpError> {
    let name = path.display().to_string();
    let fi = match out.files.iter().position(|f| *f == name) {
        Some(i) => i,
        None => {
            out.files.push(name.clone());
            out.files.len() - 1
        }
    };
    stack.push(std::fs::canonicalize(path).unwrap_or_else(|_| path.to_path_buf()));
    let dir = path.parent().unwrap_or(Path::new("")).to_path_buf();
    let invalid = |line: usize, message: String| InpError::Invalid {
        file: name.clone(),
        line,
        keyword: "INCLUDE".into(),
        message,
    };
    for (i, raw) in text.lines().enumerate() {
        let line = i + 1;
        match include_target(raw) {
            None => {
                if out.text.len() + raw.len() + 1 > MAX_EXPANDED_BYTES {
                    return Err(invalid(
                        line,
                        format!(
                            "the deck with its included files exceeds {} MiB",
                            MAX_EXPANDED_BYTES >> 20
                        ),
                    ));
                }
                out.text.push_str(raw);
                out.text.push('\n');
                out.origin.push((fi as u32, line as u32));
            }
            Some(Err(())) => {
                return Err(invalid(line, "needs INPUT=<file name>".into()));
            }
            Some(Ok(target)) => {
                let beside = dir.join(&target);
                let found = if beside.exists() {
                    beside
                } else {
                    std::path::PathBuf::from(&target)
                };
                let canon = std::fs::canonicalize(&found).unwrap_or_else(|_| found.clone());
                if stack.contains(&canon) {
                    return Err(invalid(
                        line,
                        format!(
                            "INPUT={target} includes itself (through {} level(s))",
                            stack.len()
                        ),
                    ));
                }
                if stack.len() >= MAX_INCLUDE_DEPTH {
                    return Err(invalid(
                        line,
                        format!(
                            "INPUT={target}: more than {MAX_INCLUDE_DEPTH} nested *INCLUDE levels"
                        ),
                    ));
                }
                let inner = std::fs::read_to_string(&found).map_err(|e| {
                    invalid(
                        line,
                        format!(
                            "cannot read INPUT={target} (looked for {}): {e}",
                            dir.join(&target).display()
                        ),
                    )
                })?;
                expand_into(&found, inner, out, stack)?;
            }
        }
    }
    stack.pop();
    Ok(())
}

// ---------------------------------------------------------------- lexing

#[derive(Debug)]
enum Item<'a> {
    Keyword {
        line: usize,
        name: String,
        params: Vec<(String, Option<String>)>,
    },
    Data {
        line: usize,
        raw: &'a str,
        fields: Vec<&'a str>,
        continues: bool,
    },
}

/// One line of a deck, lexed alone.
enum Line<'a> {
    /// Blank or a `**` comment.
    Skip,
    /// A keyword line: its text after the `*`.
    Keyword(&'a str),
    /// A data line.
    Data(Item<'a>),
}

/// The deck's items: each line is lexed alone (in parallel: a large deck's
/// data lines are most of the reading time), then keyword lines ending with
/// a comma take the data lines that follow them as their continuation.
fn lex(text: &str) -> Vec<Item<'_>> {
    let lines: Vec<&str> = text.lines().collect();
    let lexed: Vec<Line<'_>> = lines
        .par_iter()
        .enumerate()
        .map(|(i, raw)| lex_line(i + 1, raw))
        .collect();
    let mut items = Vec::with_capacity(lexed.len());
    let mut lexed = lexed.into_iter().enumerate().peekable();
    while let Some((i, line)) = lexed.next() {
        match line {
            Line::Skip => {}
            Line::Data(item) => items.push(item),
            Line::Keyword(rest) => {
                let mut full = rest.to_string();
                // keyword-line continuation
                while full.trim_end().ends_with(',') {
                    match lexed.peek() {
                        Some((_, Line::Data(Item::Data { raw, .. }))) => {
                            full.push_str(raw);
                            lexed.next();
                        }
                        _ => break,
                    }
                }
                items.push(keyword_item(i + 1, &full));
            }
        }
    }
    items
}

/// Line `line` (1-based) of a deck, alone.
fn lex_line(line: usize, raw: &str) -> Line<'_> {
    let l = raw.trim();
    if l.is_empty() || l.starts_with("**") {
        return Line::Skip;
    }
    if let Some(rest) = l.strip_prefix('*') {
        return Line::Keyword(rest);
    }
    let continues = l.ends_with(',');
    let mut fields: Vec<&str> = l.split(',').map(str::trim).collect();
    if continues {
        fields.pop();
    }
    Line::Data(Item::Data {
        line,
        raw: l,
        fields,
        continues,
    })
}

/// A keyword line's name (upper case, single spaces) and parameters.
fn keyword_item(line: usize, full: &str) -> Item<'static> {
    let mut parts = full.split(',');
    let name = parts
        .next()
        .unwrap_or("")
        .split_whitespace()
        .collect::<Vec<_>>()
        .join(" ")
        .to_uppercase();
    let params = parts
        .filter(|p| !p.trim().is_empty())
        .map(|p| match p.split_once('=') {
            Some((k, v)) => (norm_key(k), Some(v.trim().to_string())),
            None => (norm_key(p), None),
        })
        .collect();
    Item::Keyword { line, name, params }
}

fn norm_key(k: &str) -> String {
    k.split_whitespace()
        .collect::<Vec<_>>()
        .join(" ")
        .to_uppercase()
}

// ---------------------------------------------------------------- parsing

struct Elem {
    pre_block: usize,
    conn: Vec<usize>,
    label: usize,
    material: Option<(String, usize)>,
    /// `*SOLID SECTION, ORIENTATION=` name (upper case).
    orientation: Option<String>,
}

struct PreBlock {
    name: String,
    shape: CellShape,
    element_type: &'static str,
}

/// A named set: name as first written, members (node ids or flat element ids).
struct NamedSet {
    name: String,
    members: Vec<usize>,
}

struct PendingMaterial {
    name: String,
    line: usize,
    elastic: Option<(InpMaterialKind, usize)>,
    density: Option<f64>,
    expansion: Option<(InpExpansion, usize)>,
    initiation: Option<InpDamageInitiation>,
    evolution: Option<InpDamageEvolution>,
    stabilization: Option<InpDamageStabilization>,
}

/// A term of an `*EQUATION` as written: node label or set, dof, coefficient.
type WrittenTerm = (String, usize, f64);

enum DloadTarget {
    Elements { target: String, face: usize },
    Surface(String),
}

struct PendingTarget {
    target: String,
    line: usize,
    keyword: &'static str,
}

struct Parser<'a> {
    file: &'a str,
    nodes: Vec<[f64; 3]>,
    labels: Vec<usize>,
    node_id: FxHashMap<usize, usize>,
    elems: Vec<Elem>,
    elem_id: FxHashMap<usize, usize>,
    pre_blocks: Vec<PreBlock>,
    pre_block_key: HashMap<(String, String), usize>,
    nsets: Vec<NamedSet>,
    nset_index: HashMap<String, usize>,
    elsets: Vec<NamedSet>,
    elset_index: HashMap<String, usize>,
    deck: InpDeck,
    material_index: HashMap<String, usize>,
    /// material being defined
    current_material: Option<PendingMaterial>,
    step_open: Option<usize>,
    boundary_targets: Vec<PendingTarget>,
    cload_targets: Vec<PendingTarget>,
    /// `*MEMBRANE` lines and their ELSET (checked to be empty at the end).
    membranes: Vec<(usize, String)>,
    /// `*EQUATION`s as written: `(line, [(node or set, dof, a)])`.
    equation_terms: Vec<(usize, Vec<WrittenTerm>)>,
    /// Element surfaces: name (upper case) -> `(line, [(element or
    /// elset, face 0-based)])`.
    surfaces: HashMap<String, (usize, Vec<(String, usize)>)>,
    /// Distributed loads with their targets as written: `(element or
    /// elset, face)` for `*DLOAD`, the surface name for `*DSLOAD`.
    dload_targets: Vec<DloadTarget>,
    /// `** junta: curve` directive: line and `key=value` pairs.
    curve_directive: Option<(usize, Vec<(String, String)>)>,
    /// `AMPLITUDE=` names as written: `(what, index in its list, name,
    /// keyword line)`, resolved when the deck is read.
    amplitude_refs: Vec<(AmplitudeUse, usize, String, usize)>,
}

/// Which list an `AMPLITUDE=` reference belongs to.
#[derive(Debug, Clone, Copy)]
enum AmplitudeUse {
    Boundary,
    Cload,
    Dload,
}

type Params = [(String, Option<String>)];

fn element_kind(t: &str) -> Option<(CellShape, &'static str)> {
    match t {
        "C3D8" => Some((CellShape::Hex8, "h8")),
        "C3D8I" => Some((CellShape::Hex8, "h8i")),
        "C3D20" => Some((CellShape::Hex20, "h20")),
        "C3D20R" => Some((CellShape::Hex20, "h20r")),
        "C3D27" => Some((CellShape::Hex27, "h27")),
        "C3D6" => Some((CellShape::Wedge6, "wedge6r")),
        "C3D15" => Some((CellShape::Wedge15, "wedge15")),
        "COH3D8" => Some((CellShape::Inter8, "inter8")),
        "COH3D6" => Some((CellShape::Inter6, "inter6")),
        _ => None,
    }
}

impl<'a> Parser<'a> {
    fn invalid(&self, line: usize, keyword: &str, message: impl Into<String>) -> InpError {
        InpError::Invalid {
            file: self.file.into(),
            line,
            keyword: keyword.into(),
            message: message.into(),
        }
    }

    fn check_params(
        &self,
        line: usize,
        keyword: &str,
        params: &Params,
        valid: &[&str],
    ) -> Result<(), InpError> {
        for (k, _) in params {
            if !valid.contains(&k.as_str()) {
                return Err(InpError::Parameter {
                    file: self.file.into(),
                    line,
                    keyword: keyword.into(),
                    parameter: k.clone(),
                    valid: if valid.is_empty() {
                        "(none)".into()
                    } else {
                        valid.join(", ")
                    },
                });
            }
        }
        Ok(())
    }

    /// A parameter with two values `(key, default, other)`: `false` when
    /// absent or `default`, `true` for `other` (case-insensitive), an error
    /// listing `valid` otherwise.
    fn two_way(
        &self,
        line: usize,
        keyword: &str,
        params: &Params,
        (key, default, other): (&str, &str, &str),
        valid: &str,
    ) -> Result<bool, InpError> {
        match Self::param(params, key) {
            None => Ok(false),
            Some((_, Some(v))) if v.eq_ignore_ascii_case(default) => Ok(false),
            Some((_, Some(v))) if v.eq_ignore_ascii_case(other) => Ok(true),
            Some((_, v)) => Err(InpError::Parameter {
                file: self.file.into(),
                line,
                keyword: keyword.into(),
                parameter: format!("{key}={}", v.as_deref().unwrap_or("")),
                valid: valid.into(),
            }),
        }
    }

    fn param<'p>(params: &'p Params, key: &str) -> Option<&'p (String, Option<String>)> {
        params.iter().find(|(k, _)| k == key)
    }

    fn required(
        &self,
        line: usize,
        keyword: &str,
        params: &Params,
        key: &str,
    ) -> Result<String, InpError> {
        match Self::param(params, key) {
            Some((_, Some(v))) if !v.is_empty() => Ok(v.clone()),
            _ => Err(InpError::MissingParameter {
                file: self.file.into(),
                line,
                keyword: keyword.into(),
                parameter: format!("{key}="),
            }),
        }
    }

    fn float(&self, line: usize, keyword: &str, what: &str, text: &str) -> Result<f64, InpError> {
        let t = text.replace(['d', 'D'], "e");
        t.parse::<f64>()
            .ok()
            .filter(|x| x.is_finite())
            .ok_or_else(|| InpError::BadNumber {
                file: self.file.into(),
                line,
                keyword: keyword.into(),
                what: what.into(),
                text: text.into(),
                expected: "number",
            })
    }

    fn label(&self, line: usize, keyword: &str, what: &str, text: &str) -> Result<usize, InpError> {
        text.parse::<usize>()
            .ok()
            .filter(|&x| x > 0)
            .ok_or_else(|| InpError::BadNumber {
                file: self.file.into(),
                line,
                keyword: keyword.into(),
                what: what.into(),
                text: text.into(),
                expected: "positive integer label",
            })
    }

    fn dof(&self, line: usize, keyword: &str, text: &str) -> Result<usize, InpError> {
        let d = self.label(line, keyword, "degree of freedom", text)?;
        if !(1..=3).contains(&d) {
            return Err(self.invalid(
                line,
                keyword,
                format!("degree of freedom {d} is not supported; valid: 1, 2, 3 (displacements of solids)"),
            ));
        }
        Ok(d)
    }

    fn unknown_set(&self, line: usize, keyword: &str, kind: &'static str, name: &str) -> InpError {
        let sets = if kind == "node set" {
            &self.nsets
        } else {
            &self.elsets
        };
        let valid = if sets.is_empty() {
            "(none)".to_string()
        } else {
            sets.iter()
                .map(|s| s.name.as_str())
                .collect::<Vec<_>>()
                .join(", ")
        };
        InpError::UnknownName {
            file: self.file.into(),
            line,
            keyword: keyword.into(),
            kind,
            name: name.into(),
            valid,
        }
    }

    fn node_of(&self, line: usize, keyword: &str, label: usize) -> Result<usize, InpError> {
        self.node_id
            .get(&label)
            .copied()
            .ok_or_else(|| InpError::UndefinedLabel {
                file: self.file.into(),
                line,
                keyword: keyword.into(),
                kind: "node",
                label,
            })
    }

    fn set_mut(sets: &mut Vec<NamedSet>, index: &mut HashMap<String, usize>, name: &str) -> usize {
        let key = name.to_uppercase();
        *index.entry(key).or_insert_with(|| {
            sets.push(NamedSet {
                name: name.to_string(),
                members: Vec::new(),
            });
            sets.len() - 1
        })
    }

    /// Resolve a node target (label or node set) to node ids.
    fn node_target(
        &self,
        line: usize,
        keyword: &str,
        target: &str,
    ) -> Result<Vec<usize>, InpError> {
        if target.chars().all(|c| c.is_ascii_digit()) {
            let l = self.label(line, keyword, "node label", target)?;
            Ok(vec![self.node_of(line, keyword, l)?])
        } else {
            match self.nset_index.get(&target.to_uppercase()) {
                Some(&i) => Ok(self.nsets[i].members.clone()),
                None => Err(self.unknown_set(line, keyword, "node set", target)),
            }
        }
    }

    /// `*EXPANSION [, TYPE=ISO | ORTHO | ANISO] [, ZERO=]` ([`InpExpansion`]).
    fn expansion(
        &mut self,
        line: usize,
        params: &Params,
        data: &[(usize, &[&str], bool)],
    ) -> Result<(), InpError> {
        let kw = "EXPANSION";
        self.check_params(line, kw, params, &["TYPE", "ZERO"])?;
        let Some(m) = &self.current_material else {
            return Err(self.invalid(line, kw, "*EXPANSION must follow *MATERIAL"));
        };
        if m.expansion.is_some() {
            return Err(self.invalid(
                line,
                kw,
                format!("material `{}` has two *EXPANSION", m.name),
            ));
        }
        let ty = Self::param(params, "TYPE")
            .and_then(|(_, v)| v.as_deref())
            .map(norm_key)
            .unwrap_or_else(|| "ISO".into());
        let names: &[&str] = match ty.as_str() {
            "ISO" | "ISOTROPIC" => &["alpha"],
            "ORTHO" | "ORTHOTROPIC" => &["alpha_11", "alpha_22", "alpha_33"],
            "ANISO" | "ANISOTROPIC" => &[
                "alpha_11", "alpha_22", "alpha_33", "alpha_12", "alpha_13", "alpha_23",
            ],
            _ => {
                return Err(InpError::Parameter {
                    file: self.file.into(),
                    line,
                    keyword: kw.into(),
                    parameter: format!("TYPE={ty}"),
                    valid: "TYPE=ISO, TYPE=ORTHO, TYPE=ANISO".into(),
                })
            }
        };
        let Some(&(dl, f, _)) = data.first() else {
            return Err(self.invalid(
                line,
                kw,
                format!("TYPE={ty} expects a data line with {}", names.join(", ")),
            ));
        };
        if let Some(&(d2, _, _)) = data.get(1) {
            return Err(self.invalid(
                d2,
                kw,
                "temperature-dependent expansion is not supported (one set of coefficients only)",
            ));
        }
        let values: Vec<&str> = f.iter().copied().filter(|s| !s.is_empty()).collect();
        if values.len() < names.len() || values.len() > names.len() + 1 {
            return Err(self.invalid(
                dl,
                kw,
                format!(
                    "TYPE={ty} expects {} value(s) ({}) and optionally the temperature, found {}",
                    names.len(),
                    names.join(", "),
                    values.len()
                ),
            ));
        }
        let mut v = Vec::with_capacity(names.len());
        for (name, t) in names.iter().zip(&values) {
            v.push(self.float(dl, kw, name, t)?);
        }
        if let Some(t) = values.get(names.len()) {
            let t = self.float(dl, kw, "temperature", t)?;
            self.deck.notes.push(format!(
                "line {dl}: *EXPANSION at temperature {t}: one set of coefficients, used at every temperature"
            ));
        }
        if let Some((_, z)) = Self::param(params, "ZERO") {
            let z = z.as_deref().unwrap_or("");
            self.float(line, kw, "ZERO", z)?;
            self.deck.notes.push(format!(
                "line {line}: *EXPANSION, ZERO={z}: with coefficients constant in temperature the thermal strain is alpha (T - T_initial) whatever the reference temperature"
            ));
        }
        let e = match v.len() {
            1 => InpExpansion::Isotropic(v[0]),
            3 => InpExpansion::Orthotropic([v[0], v[1], v[2]]),
            _ => InpExpansion::Anisotropic([v[0], v[1], v[2], v[3], v[4], v[5]]),
        };
        if let Some(m) = self.current_material.as_mut() {
            m.expansion = Some((e, dl));
        }
        Ok(())
    }

    /// `node or node set, temperature` data lines of `kw` into
    /// [`InpDeck::temperatures`].
    fn temperature_lines(
        &mut self,
        kw: &str,
        data: &[(usize, &[&str], bool)],
        step: Option<usize>,
        op_new: bool,
    ) -> Result<(), InpError> {
        for &(dl, f, _) in data {
            let values: Vec<&str> = f.iter().copied().filter(|s| !s.is_empty()).collect();
            if values.len() != 2 {
                return Err(self.invalid(dl, kw, "expected `node or node set, temperature`"));
            }
            let value = self.float(dl, kw, "temperature", values[1])?;
            self.deck.temperatures.push(InpTemperature {
                target: values[0].into(),
                nodes: Vec::new(),
                value,
                step,
                op_new,
                line: dl,
            });
        }
        Ok(())
    }

    /// `*INITIAL CONDITIONS, TYPE=TEMPERATURE`: the initial (stress-free)
    /// temperature of nodes; other types are refused.
    fn initial_conditions(
        &mut self,
        line: usize,
        params: &Params,
        data: &[(usize, &[&str], bool)],
    ) -> Result<(), InpError> {
        let kw = "INITIAL CONDITIONS";
        self.check_params(line, kw, params, &["TYPE"])?;
        self.model_data_only(line, kw)?;
        let ty = Self::param(params, "TYPE")
            .and_then(|(_, v)| v.as_deref())
            .map(norm_key)
            .unwrap_or_default();
        if ty != "TEMPERATURE" {
            return Err(InpError::Parameter {
                file: self.file.into(),
                line,
                keyword: kw.into(),
                parameter: format!("TYPE={ty}"),
                valid: "TYPE=TEMPERATURE".into(),
            });
        }
        self.temperature_lines(kw, data, None, false)
    }

    /// `*TEMPERATURE [, OP=MOD | NEW]` inside a step: the temperature of
    /// nodes at the end of the step.
    fn temperature(
        &mut self,
        line: usize,
        params: &Params,
        data: &[(usize, &[&str], bool)],
    ) -> Result<(), InpError> {
        let kw = "TEMPERATURE";
        self.check_params(line, kw, params, &["OP"])?;
        if self.step_open.is_none() {
            return Err(self.invalid(
                line,
                kw,
                "*TEMPERATURE belongs inside a *STEP (the initial temperature is *INITIAL CONDITIONS, TYPE=TEMPERATURE)",
            ));
        }
        let op_new = self.op_new(line, kw, params)?;
        let step = Some(self.deck.steps.len() - 1);
        self.temperature_lines(kw, data, step, op_new)
    }

    /// `*MEMBRANE, ELSET=, MATERIAL=`: accepted on an element set without
    /// elements (CalculiX's test decks carry such lines), refused otherwise
    /// (checked when the sets are complete).
    fn membrane(
        &mut self,
        line: usize,
        params: &Params,
        data: &[(usize, &[&str], bool)],
    ) -> Result<(), InpError> {
        let kw = "MEMBRANE";
        self.check_params(line, kw, params, &["ELSET", "MATERIAL", "ORIENTATION"])?;
        self.model_data_only(line, kw)?;
        let elset = self.required(line, kw, params, "ELSET")?;
        if data.len() > 1 {
            return Err(self.invalid(data[1].0, kw, "expected one data line (the thickness)"));
        }
        self.membranes.push((line, elset));
        Ok(())
    }

    fn model_data_only(&self, line: usize, keyword: &str) -> Result<(), InpError> {
        if let Some(s) = self.step_open {
            return Err(self.invalid(
                line,
                keyword,
                format!(
                    "model data is not allowed inside the *STEP of line {s}; move it before *STEP"
                ),
            ));
        }
        Ok(())
    }

    fn finish_material(&mut self) -> Result<(), InpError> {
        if let Some(m) = self.current_material.take() {
            let (name, line) = (m.name, m.line);
            let (kind, elastic_line) = m.elastic.ok_or_else(|| {
                self.invalid(
                    line,
                    "MATERIAL",
                    format!("material `{name}` has no *ELASTIC"),
                )
            })?;
            let damage =
                m.initiation.is_some() || m.evolution.is_some() || m.stabilization.is_some();
            if damage && !matches!(kind, InpMaterialKind::Traction(_)) {
                return Err(self.invalid(
                    line,
                    "MATERIAL",
                    format!("material `{name}` has damage options but its *ELASTIC is not TYPE=TRACTION: damage is read for cohesive materials (*ELASTIC, TYPE=TRACTION with *COHESIVE SECTION) only"),
                ));
            }
            if let (Some(i), None) = (&m.initiation, &m.evolution) {
                return Err(self.invalid(
                    i.line,
                    "DAMAGE INITIATION",
                    format!("material `{name}` has *DAMAGE INITIATION but no *DAMAGE EVOLUTION: Abaqus would then only report the initiation criterion and never soften (the stiffness stays K); add *DAMAGE EVOLUTION, TYPE=ENERGY with the fracture energies, or drop the damage keywords for a linear penalty"),
                ));
            }
            if let (Some(st), None) = (&m.stabilization, &m.initiation) {
                return Err(self.invalid(
                    st.line,
                    "DAMAGE STABILIZATION",
                    format!("material `{name}` has *DAMAGE STABILIZATION but no *DAMAGE INITIATION / *DAMAGE EVOLUTION: there is no damage to stabilise"),
                ));
            }
            self.material_index
                .insert(name.to_uppercase(), self.deck.materials.len());
            self.deck.materials.push(InpMaterial {
                name,
                kind,
                density: m.density,
                line,
                elastic_line,
                damage_initiation: m.initiation,
                damage_evolution: m.evolution,
                damage_stabilization: m.stabilization,
                expansion: m.expansion.map(|e| e.0),
            });
        }
        Ok(())
    }

    /// Read the `** junta: ...` comment directives (comments for Abaqus):
    /// `curve key=value ...` and `output every=N`.
    fn directives(&mut self, text: &str) -> Result<(), InpError> {
        for (i, raw) in text.lines().enumerate() {
            let line = i + 1;
            let Some(rest) = raw.trim().strip_prefix("**") else {
                continue;
            };
            let rest = rest.trim();
            let Some(body) = rest
                .get(..6)
                .filter(|h| h.eq_ignore_ascii_case("junta:"))
                .and_then(|_| rest.get(6..))
            else {
                continue;
            };
            let mut words = body.split_whitespace();
            let what = words.next().unwrap_or("").to_ascii_lowercase();
            let kw = format!("** junta: {what}");
            let mut pairs = Vec::new();
            for w in words {
                let Some((k, v)) = w.split_once('=') else {
                    return Err(self.invalid(line, &kw, format!("`{w}` is not `key=value`")));
                };
                pairs.push((k.to_ascii_lowercase(), v.to_string()));
            }
            let valid: &[&str] = match what.as_str() {
                "curve" => &[
                    "reaction_set",
                    "reaction_component",
                    "point_set",
                    "point_component",
                    "relative_to",
                ],
                "output" => &["every"],
                _ => {
                    return Err(self.invalid(
                        line,
                        "** junta:",
                        format!("unknown directive `{what}`; valid: `** junta: curve reaction_set=.. reaction_component=.. point_set=.. point_component=.. [relative_to=..]`, `** junta: output every=N`"),
                    ))
                }
            };
            if let Some((k, _)) = pairs.iter().find(|(k, _)| !valid.contains(&k.as_str())) {
                return Err(self.invalid(
                    line,
                    &kw,
                    format!("unknown key `{k}`; valid: {}", valid.join(", ")),
                ));
            }
            if what == "curve" {
                if let Some((l, _)) = &self.curve_directive {
                    return Err(self.invalid(
                        line,
                        &kw,
                        format!("a second curve directive (the first is at line {l})"),
                    ));
                }
                self.curve_directive = Some((line, pairs));
            } else {
                for (_, v) in pairs {
                    let n = self.label(line, &kw, "every", &v)?;
                    self.deck.every = Some(n);
                }
            }
        }
        Ok(())
    }

    /// Walk the keywords in order, each with its data lines, to its reader
    /// ([`Parser::keyword`]). A material is complete at the first keyword
    /// that is not one of its options; a step must be closed at the end.
    fn run(&mut self, items: &[Item<'_>]) -> Result<(), InpError> {
        let mut i = 0;
        // data lines before any keyword
        if let Some(Item::Data { line, .. }) = items.first() {
            return Err(self.invalid(*line, "(none)", "data line before any keyword"));
        }
        while i < items.len() {
            let Item::Keyword { line, name, params } = &items[i] else {
                unreachable!("data lines are consumed by their keyword")
            };
            i += 1;
            let start = i;
            while i < items.len() && matches!(items[i], Item::Data { .. }) {
                i += 1;
            }
            let data: Vec<(usize, &[&str], bool)> = items[start..i]
                .iter()
                .map(|it| match it {
                    Item::Data {
                        line,
                        fields,
                        continues,
                        ..
                    } => (*line, fields.as_slice(), *continues),
                    Item::Keyword { .. } => unreachable!(),
                })
                .collect();
            if !matches!(
                name.as_str(),
                "ELASTIC"
                    | "DENSITY"
                    | "EXPANSION"
                    | "DAMAGE INITIATION"
                    | "DAMAGE EVOLUTION"
                    | "DAMAGE STABILIZATION"
            ) {
                self.finish_material()?;
            }
            self.keyword(*line, name, params, &items[start..i], &data)?;
        }
        self.finish_material()?;
        if let Some(s) = self.step_open {
            return Err(self.invalid(s, "STEP", "missing *END STEP at the end of the deck"));
        }
        Ok(())
    }

    /// One keyword (`kw` at `line`) with its data `items` (as `data`
    /// fields): dispatch to its reader.
    fn keyword(
        &mut self,
        line: usize,
        kw: &str,
        params: &Params,
        items: &[Item<'_>],
        data: &[(usize, &[&str], bool)],
    ) -> Result<(), InpError> {
        match kw {
            "HEADING" => self.heading(line, params, items),
            "NODE" => self.node(line, params, data),
            "ELEMENT" => self.element(line, params, data),
            "NSET" | "ELSET" => self.set(line, kw, params, data),
            "MATERIAL" => self.material(line, params, data),
            "ELASTIC" => self.elastic(line, params, data),
            "DAMAGE INITIATION" => self.damage_initiation(line, params, data),
            "DAMAGE EVOLUTION" => self.damage_evolution(line, params, data),
            "DAMAGE STABILIZATION" => self.damage_stabilization(line, params, data),
            "DENSITY" => self.density(line, params, data),
            "CONTROLS" => self.controls(line, params),
            "EXPANSION" => self.expansion(line, params, data),
            "INITIAL CONDITIONS" => self.initial_conditions(line, params, data),
            "TEMPERATURE" => self.temperature(line, params, data),
            "MEMBRANE" => self.membrane(line, params, data),
            "SOLID SECTION" => self.solid_section(line, params, data),
            "COHESIVE SECTION" => self.cohesive_section(line, params, data),
            "ORIENTATION" => self.orientation(line, params, data),
            "BOUNDARY" => self.boundary(line, params, data),
            "CLOAD" => self.cload(line, params, data),
            "AMPLITUDE" => self.amplitude(line, params, data),
            "EQUATION" => self.equation(line, params, data),
            "SURFACE" => self.surface(line, params, data),
            "DLOAD" => self.dload(line, params, data),
            "DSLOAD" => self.dsload(line, params, data),
            "STEP" => self.step(line, params, data),
            "STATIC" => self.static_procedure(line, params, data),
            "END STEP" => {
                self.check_params(line, kw, params, &[])?;
                if self.step_open.take().is_none() {
                    return Err(self.invalid(line, kw, "*END STEP without *STEP"));
                }
                Ok(())
            }
            "NODE PRINT" => self.node_print(line, params, data),
            "EL PRINT" => self.el_print(line, params, data),
            "INCLUDE" => Err(self.invalid(
                line,
                "INCLUDE",
                "an included file is read in place only when the deck is read from a file (read_inp); this text was given without one",
            )),
            k if OUTPUT_KEYWORDS.contains(&k) => {
                self.deck.notes.push(format!(
                    "line {line}: *{k} ignored (outputs are chosen in the scene); {} data line(s) skipped",
                    data.len()
                ));
                Ok(())
            }
            _ => Err(InpError::UnknownKeyword {
                file: self.file.into(),
                line,
                keyword: kw.into(),
                valid: SUPPORTED_KEYWORDS.into(),
            }),
        }
    }

    /// `*HEADING`: its data lines, as written, are the deck's heading.
    fn heading(
        &mut self,
        line: usize,
        params: &Params,
        items: &[Item<'_>],
    ) -> Result<(), InpError> {
        self.check_params(line, "HEADING", params, &[])?;
        let text: Vec<&str> = items
            .iter()
            .filter_map(|it| match it {
                Item::Data { raw, .. } => Some(*raw),
                Item::Keyword { .. } => None,
            })
            .collect();
        self.deck.heading = text.join("\n");
        Ok(())
    }

    /// `*MATERIAL, NAME=`: opens a material; its options follow.
    fn material(
        &mut self,
        line: usize,
        params: &Params,
        data: &[(usize, &[&str], bool)],
    ) -> Result<(), InpError> {
        let kw = "MATERIAL";
        self.model_data_only(line, kw)?;
        self.check_params(line, kw, params, &["NAME"])?;
        let name = self.required(line, kw, params, "NAME")?;
        if let Some(&m) = self.material_index.get(&name.to_uppercase()) {
            return Err(self.invalid(
                line,
                kw,
                format!(
                    "material `{name}` already defined at line {}",
                    self.deck.materials[m].line
                ),
            ));
        }
        if let Some(&(d, _, _)) = data.first() {
            return Err(self.invalid(d, kw, "*MATERIAL takes no data lines"));
        }
        self.current_material = Some(PendingMaterial {
            name,
            line,
            elastic: None,
            density: None,
            expansion: None,
            initiation: None,
            evolution: None,
            stabilization: None,
        });
        Ok(())
    }

    /// `*DENSITY`: kept on the material, noted as unused.
    fn density(
        &mut self,
        line: usize,
        params: &Params,
        data: &[(usize, &[&str], bool)],
    ) -> Result<(), InpError> {
        let kw = "DENSITY";
        self.check_params(line, kw, params, &[])?;
        if self.current_material.is_none() {
            return Err(self.invalid(line, kw, "*DENSITY must follow *MATERIAL"));
        }
        let (dl, f, _) = *data
            .first()
            .ok_or_else(|| self.invalid(line, kw, "expected a data line with the density"))?;
        let rho = self.float(dl, kw, "density", f.first().copied().unwrap_or(""))?;
        let name = self
            .current_material
            .as_ref()
            .map(|m| m.name.clone())
            .unwrap_or_default();
        if let Some(m) = self.current_material.as_mut() {
            m.density = Some(rho);
        }
        self.deck.notes.push(format!(
            "line {line}: *DENSITY of material `{name}` read but unused (static analysis)"
        ));
        Ok(())
    }

    /// `*CONTROLS [, PARAMETERS=] [, RESET]`: CalculiX's and Abaqus'
    /// solution controls (convergence criteria, time incrementation),
    /// read and noted as unused: Junta's Newton criteria apply.
    fn controls(&mut self, line: usize, params: &Params) -> Result<(), InpError> {
        self.check_params(
            line,
            "CONTROLS",
            params,
            &["PARAMETERS", "RESET", "ANALYSIS", "TYPE"],
        )?;
        self.deck.notes.push(format!(
            "line {line}: *CONTROLS read but unused: Junta's own Newton criteria apply (out-of-balance force 1e-6 of the largest force, see [analysis.newton] in docs/path-following.md)"
        ));
        Ok(())
    }

    /// `*SOLID SECTION, ELSET=, MATERIAL= [, ORIENTATION=]` (resolved in
    /// [`Parser::assign_sections`]).
    fn solid_section(
        &mut self,
        line: usize,
        params: &Params,
        data: &[(usize, &[&str], bool)],
    ) -> Result<(), InpError> {
        let kw = "SOLID SECTION";
        self.model_data_only(line, kw)?;
        self.check_params(line, kw, params, &["ELSET", "MATERIAL", "ORIENTATION"])?;
        let elset = self.required(line, kw, params, "ELSET")?;
        let material = self.required(line, kw, params, "MATERIAL")?;
        let orientation = match Self::param(params, "ORIENTATION") {
            None => None,
            Some(_) => Some(self.required(line, kw, params, "ORIENTATION")?),
        };
        if data.len() > 1 {
            return Err(self.invalid(data[1].0, kw, "expected at most one data line"));
        }
        self.deck.solid_sections.push(InpSolidSection {
            elset,
            material,
            orientation,
            line,
        });
        Ok(())
    }

    /// `*COHESIVE SECTION, ELSET=, MATERIAL=, RESPONSE=TRACTION SEPARATION
    /// [, THICKNESS=SPECIFIED]`, data line: the constitutive thickness.
    fn cohesive_section(
        &mut self,
        line: usize,
        params: &Params,
        data: &[(usize, &[&str], bool)],
    ) -> Result<(), InpError> {
        let kw = "COHESIVE SECTION";
        self.model_data_only(line, kw)?;
        self.check_params(
            line,
            kw,
            params,
            &["ELSET", "MATERIAL", "RESPONSE", "THICKNESS"],
        )?;
        let elset = self.required(line, kw, params, "ELSET")?;
        let material = self.required(line, kw, params, "MATERIAL")?;
        let response = norm_key(&self.required(line, kw, params, "RESPONSE")?);
        if response != "TRACTION SEPARATION" {
            return Err(InpError::Parameter {
                file: self.file.into(),
                line,
                keyword: kw.into(),
                parameter: format!("RESPONSE={response}"),
                valid: "RESPONSE=TRACTION SEPARATION".into(),
            });
        }
        match Self::param(params, "THICKNESS").map(|(_, v)| v.as_deref().map(norm_key)) {
            None => {}
            Some(Some(v)) if v == "SPECIFIED" => {}
            Some(v) => {
                return Err(self.bad_param(
                    line,
                    kw,
                    format!("THICKNESS={}", v.unwrap_or_default()),
                    "THICKNESS=SPECIFIED (the default: the constitutive thickness is the data line's, 1 when not given); GEOMETRY would take the element's geometric thickness, which is zero for Junta's interface elements",
                ))
            }
        }
        if data.len() > 1 {
            return Err(self.invalid(data[1].0, kw, "expected at most one data line"));
        }
        let thickness = match data.first() {
            Some((dl, f, _)) if !f.is_empty() && !f[0].is_empty() => {
                let t = self.float(*dl, kw, "initial thickness", f[0])?;
                if t <= 0.0 {
                    return Err(self.invalid(
                        *dl,
                        kw,
                        format!("constitutive thickness {t} must be positive (leave the field empty for the default 1)"),
                    ));
                }
                Some(t)
            }
            _ => None,
        };
        self.deck.cohesive_sections.push(InpCohesiveSection {
            elset,
            material,
            response,
            thickness,
            line,
        });
        Ok(())
    }

    /// `*STEP [, NAME=] [, NLGEOM[=YES|NO]] [, INC=]`: opens a step (a
    /// description line is skipped).
    fn step(
        &mut self,
        line: usize,
        params: &Params,
        data: &[(usize, &[&str], bool)],
    ) -> Result<(), InpError> {
        let kw = "STEP";
        self.check_params(line, kw, params, &["NAME", "NLGEOM", "INC"])?;
        if let Some(s) = self.step_open {
            return Err(self.invalid(
                line,
                kw,
                format!("*STEP inside the *STEP of line {s}; close it with *END STEP"),
            ));
        }
        let nlgeom = match Self::param(params, "NLGEOM") {
            None => false,
            Some((_, None)) => true,
            Some((_, Some(v))) => match v.to_uppercase().as_str() {
                "YES" => true,
                "NO" => false,
                _ => {
                    return Err(InpError::Parameter {
                        file: self.file.into(),
                        line,
                        keyword: kw.into(),
                        parameter: format!("NLGEOM={v}"),
                        valid: "NLGEOM, NLGEOM=YES, NLGEOM=NO".into(),
                    })
                }
            },
        };
        let max_increments = match Self::param(params, "INC") {
            Some((_, Some(v))) => Some(self.label(line, kw, "INC", v)?),
            Some((_, None)) => {
                return Err(self.invalid(line, kw, "INC needs a value, e.g. INC=100"))
            }
            None => None,
        };
        let name = Self::param(params, "NAME").and_then(|(_, v)| v.clone());
        if let Some((dl, _, _)) = data.first() {
            // Abaqus allows a step description line
            self.deck
                .notes
                .push(format!("line {dl}: *STEP description skipped"));
        }
        self.deck.steps.push(InpStep {
            name,
            nlgeom,
            max_increments,
            static_procedure: None,
            line,
        });
        self.step_open = Some(line);
        Ok(())
    }

    /// `*STATIC [, DIRECT] [, SOLVER=] [, RIKS]` inside a step: parameters
    /// that change nothing are noted, unsupported ones refused; the data
    /// line is read by [`Parser::static_values`].
    fn static_procedure(
        &mut self,
        line: usize,
        params: &Params,
        data: &[(usize, &[&str], bool)],
    ) -> Result<(), InpError> {
        let kw = "STATIC";
        let mut valid = vec!["DIRECT", "SOLVER", "RIKS"];
        valid.extend(STATIC_NOTED);
        valid.extend(STATIC_REFUSED.iter().map(|(k, _)| *k));
        self.check_params(line, kw, params, &valid)?;
        for (k, what) in STATIC_REFUSED {
            if Self::param(params, k).is_some() {
                return Err(self.invalid(
                    line,
                    kw,
                    format!("*STATIC, {k} ({what}) is not supported"),
                ));
            }
        }
        for k in STATIC_NOTED {
            if Self::param(params, k).is_some() {
                self.deck.notes.push(format!(
                    "line {line}: *STATIC, {k} does not change Junta's results; skipped"
                ));
            }
        }
        let solver = match Self::param(params, "SOLVER") {
            None => None,
            Some((_, Some(v))) if !v.is_empty() => Some(v.to_uppercase()),
            Some(_) => {
                return Err(self.invalid(
                    line,
                    kw,
                    "SOLVER needs a value (SPOOLES, PARDISO, PASTIX, ITERATIVE SCALING, ITERATIVE CHOLESKY)",
                ))
            }
        };
        if self.step_open.is_none() {
            return Err(self.invalid(line, kw, "*STATIC must be inside *STEP ... *END STEP"));
        }
        let riks = Self::param(params, "RIKS").is_some();
        let v = self.static_values(line, riks, data)?;
        let step = self.deck.steps.last_mut().unwrap();
        step.static_procedure = Some(InpStatic {
            initial_increment: v[0],
            period: v[1],
            min_increment: v[2],
            max_increment: v[3],
            direct: Self::param(params, "DIRECT").is_some(),
            solver,
            riks: riks.then_some(InpRiks {
                max_load_factor: v[4],
            }),
            line,
        });
        Ok(())
    }

    /// The data line of `*STATIC`: initial increment, period, minimum and
    /// maximum increment; with RIKS also the maximum load factor and the
    /// (noted, unsupported) monitored node, dof and displacement. Empty
    /// fields are `None`.
    fn static_values(
        &mut self,
        line: usize,
        riks: bool,
        data: &[(usize, &[&str], bool)],
    ) -> Result<[Option<f64>; 8], InpError> {
        let kw = "STATIC";
        if data.len() > 1 {
            return Err(self.invalid(data[1].0, kw, "expected at most one data line"));
        }
        let mut v = [None; 8];
        if let Some((dl, f, _)) = data.first() {
            let most = if riks { 8 } else { 4 };
            if f.len() > most {
                return Err(self.invalid(
                    *dl,
                    kw,
                    if riks {
                        "expected at most 8 values: initial arc length, period, minimum, maximum arc length, maximum load factor, node, dof, displacement"
                    } else {
                        "expected at most 4 values: initial increment, period, minimum, maximum increment"
                    },
                ));
            }
            let names = [
                "initial increment",
                "time period",
                "minimum increment",
                "maximum increment",
                "maximum load proportionality factor",
                "monitored node",
                "monitored degree of freedom",
                "finishing displacement",
            ];
            for (k, t) in f.iter().enumerate() {
                if !t.is_empty() {
                    v[k] = Some(self.float(*dl, kw, names[k], t)?);
                }
            }
        }
        if riks && v[5..].iter().any(Option::is_some) {
            self.deck.notes.push(format!(
                "line {line}: *STATIC, RIKS: the stop on a node's displacement (values 6-8) is not supported; the run ends at the maximum load factor or after INC increments"
            ));
        }
        Ok(v)
    }

    /// `*NODE PRINT, NSET= [, TOTALS=]`: variables of the data lines (`U`
    /// when none).
    fn node_print(
        &mut self,
        line: usize,
        params: &Params,
        data: &[(usize, &[&str], bool)],
    ) -> Result<(), InpError> {
        let kw = "NODE PRINT";
        let nset = self.required(line, kw, params, "NSET")?;
        let totals = match Self::param(params, "TOTALS") {
            None => "NO".to_string(),
            Some((_, Some(v))) => v.to_uppercase(),
            Some((_, None)) => "YES".to_string(),
        };
        if !["NO", "YES", "ONLY"].contains(&totals.as_str()) {
            return Err(self.invalid(
                line,
                kw,
                format!("TOTALS={totals}: valid are YES, ONLY, NO"),
            ));
        }
        let variables = data
            .iter()
            .flat_map(|(_, f, _)| f.iter())
            .filter(|t| !t.is_empty())
            .map(|t| t.to_uppercase())
            .collect::<Vec<_>>();
        let variables = if variables.is_empty() {
            vec!["U".to_string()]
        } else {
            variables
        };
        self.deck.node_prints.push(InpNodePrint {
            nset,
            variables,
            totals,
            step: self.step_open.map(|_| self.deck.steps.len() - 1),
            line,
        });
        Ok(())
    }

    /// `*EL PRINT, ELSET= [, GLOBAL=]`: variables of the data lines (`S`
    /// when none).
    fn el_print(
        &mut self,
        line: usize,
        params: &Params,
        data: &[(usize, &[&str], bool)],
    ) -> Result<(), InpError> {
        let kw = "EL PRINT";
        let elset = self.required(line, kw, params, "ELSET")?;
        // CalculiX prints oriented elements in their material
        // axes unless GLOBAL=YES
        let global = match Self::param(params, "GLOBAL")
            .and_then(|(_, v)| v.as_deref())
            .map(norm_key)
            .as_deref()
        {
            None | Some("NO") => false,
            Some("YES") => true,
            Some(v) => {
                return Err(InpError::Parameter {
                    file: self.file.into(),
                    line,
                    keyword: kw.into(),
                    parameter: format!("GLOBAL={v}"),
                    valid: "GLOBAL=YES or GLOBAL=NO".into(),
                })
            }
        };
        let mut variables = data
            .iter()
            .flat_map(|(_, f, _)| f.iter())
            .filter(|t| !t.is_empty())
            .map(|t| t.to_uppercase())
            .collect::<Vec<_>>();
        if variables.is_empty() {
            variables.push("S".to_string());
        }
        self.deck.el_prints.push(InpElPrint {
            elset,
            variables,
            global,
            step: self.step_open.map(|_| self.deck.steps.len() - 1),
            line,
        });
        Ok(())
    }

    fn node(
        &mut self,
        line: usize,
        params: &Params,
        data: &[(usize, &[&str], bool)],
    ) -> Result<(), InpError> {
        let kw = "NODE";
        self.model_data_only(line, kw)?;
        self.check_params(line, kw, params, &["NSET"])?;
        let set = match Self::param(params, "NSET") {
            Some(_) => {
                let name = self.required(line, kw, params, "NSET")?;
                Some(Self::set_mut(&mut self.nsets, &mut self.nset_index, &name))
            }
            None => None,
        };
        for &(dl, f, _) in data {
            let f: Vec<&str> = f.iter().copied().filter(|s| !s.is_empty()).collect();
            if f.len() < 3 || f.len() > 4 {
                return Err(self.invalid(
                    dl,
                    kw,
                    format!("expected `label, x, y[, z]`, found {} values", f.len()),
                ));
            }
            let label = self.label(dl, kw, "node label", f[0])?;
            let mut x = [0.0; 3];
            for (d, t) in f[1..].iter().enumerate() {
                x[d] = self.float(dl, kw, ["x", "y", "z"][d], t)?;
            }
            if self.node_id.contains_key(&label) {
                return Err(self.invalid(dl, kw, format!("node label {label} defined twice")));
            }
            let id = self.nodes.len();
            self.node_id.insert(label, id);
            self.nodes.push(x);
            self.labels.push(label);
            if let Some(s) = set {
                self.nsets[s].members.push(id);
            }
        }
        Ok(())
    }

    fn element(
        &mut self,
        line: usize,
        params: &Params,
        data: &[(usize, &[&str], bool)],
    ) -> Result<(), InpError> {
        let kw = "ELEMENT";
        self.model_data_only(line, kw)?;
        self.check_params(line, kw, params, &["TYPE", "ELSET"])?;
        let type_name = self.required(line, kw, params, "TYPE")?.to_uppercase();
        let (shape, etype) = element_kind(&type_name).ok_or_else(|| InpError::ElementType {
            file: self.file.into(),
            line,
            element_type: type_name.clone(),
            valid: SUPPORTED_ELEMENT_TYPES.into(),
        })?;
        let elset = match Self::param(params, "ELSET") {
            Some(_) => Some(self.required(line, kw, params, "ELSET")?),
            None => None,
        };
        let key = (
            type_name.clone(),
            elset.as_deref().unwrap_or("").to_uppercase(),
        );
        let pb = match self.pre_block_key.get(&key) {
            Some(&b) => b,
            None => {
                let base = elset.clone().unwrap_or_else(|| type_name.to_lowercase());
                let name = if self.pre_blocks.iter().any(|b| b.name == base) {
                    format!("{base}_{}", type_name.to_lowercase())
                } else {
                    base
                };
                self.pre_blocks.push(PreBlock {
                    name,
                    shape,
                    element_type: etype,
                });
                self.pre_block_key.insert(key, self.pre_blocks.len() - 1);
                self.pre_blocks.len() - 1
            }
        };
        let set = elset
            .as_deref()
            .map(|e| Self::set_mut(&mut self.elsets, &mut self.elset_index, e));
        let n = shape.num_nodes();
        let mut k = 0;
        while k < data.len() {
            let (dl, first, mut cont) = data[k];
            let mut fields: Vec<&str> = first.to_vec();
            let mut full16 = first.len() + usize::from(cont) >= 16;
            k += 1;
            while fields.len() < n + 1 && (cont || full16) && k < data.len() {
                let (_, more, c) = data[k];
                fields.extend_from_slice(more);
                cont = c;
                full16 = more.len() + usize::from(c) >= 16;
                k += 1;
            }
            let fields: Vec<&str> = fields.into_iter().filter(|s| !s.is_empty()).collect();
            if fields.is_empty() {
                continue;
            }
            let label = self.label(dl, kw, "element label", fields[0])?;
            if fields.len() != n + 1 {
                return Err(self.invalid(
                    dl,
                    kw,
                    format!(
                        "element {label}: TYPE={type_name} needs {n} nodes, found {} (a long element line continues on the next line when it ends with a comma)",
                        fields.len() - 1
                    ),
                ));
            }
            let mut given = Vec::with_capacity(n);
            for t in &fields[1..] {
                let l = self.label(dl, kw, "node label", t)?;
                given.push(self.node_of(dl, kw, l)?);
            }
            let conn: Vec<usize> = if shape == CellShape::Hex27 {
                C3D27_TO_OURS.iter().map(|&a| given[a]).collect()
            } else {
                given
            };
            if self.elem_id.contains_key(&label) {
                return Err(self.invalid(dl, kw, format!("element label {label} defined twice")));
            }
            let id = self.elems.len();
            self.elem_id.insert(label, id);
            self.elems.push(Elem {
                pre_block: pb,
                conn,
                label,
                material: None,
                orientation: None,
            });
            if let Some(s) = set {
                self.elsets[s].members.push(id);
            }
        }
        Ok(())
    }

    fn set(
        &mut self,
        line: usize,
        kw: &str,
        params: &Params,
        data: &[(usize, &[&str], bool)],
    ) -> Result<(), InpError> {
        self.model_data_only(line, kw)?;
        let is_node = kw == "NSET";
        self.check_params(line, kw, params, &[kw, "GENERATE"])?;
        let name = self.required(line, kw, params, kw)?;
        let generate = Self::param(params, "GENERATE").is_some();
        let mut members = Vec::new();
        for &(dl, f, _) in data {
            let f: Vec<&str> = f.iter().copied().filter(|s| !s.is_empty()).collect();
            if generate {
                if f.len() < 2 || f.len() > 3 {
                    return Err(self.invalid(
                        dl,
                        kw,
                        "GENERATE expects `first, last[, increment]`",
                    ));
                }
                let a = self.label(dl, kw, "first label", f[0])?;
                let b = self.label(dl, kw, "last label", f[1])?;
                let inc = if f.len() == 3 {
                    self.label(dl, kw, "increment", f[2])?
                } else {
                    1
                };
                if b < a {
                    return Err(self.invalid(
                        dl,
                        kw,
                        format!("GENERATE range {a}..{b} is empty (last < first)"),
                    ));
                }
                if inc == 0 {
                    return Err(self.invalid(dl, kw, "GENERATE increment must be >= 1"));
                }
                // labels missing inside a range are skipped, as gaps are common;
                // a range wider than the labels defined walks the labels
                // instead (bounded by the deck, not by the range: 1..1e11 is quick)
                let map = if is_node {
                    &self.node_id
                } else {
                    &self.elem_id
                };
                if (b - a) / inc >= map.len() {
                    let mut hits: Vec<(usize, usize)> = map
                        .iter()
                        .filter(|(&l, _)| l >= a && l <= b && (l - a) % inc == 0)
                        .map(|(&l, &id)| (l, id))
                        .collect();
                    hits.sort_unstable();
                    members.extend(hits.into_iter().map(|h| h.1));
                } else {
                    for l in (a..=b).step_by(inc) {
                        if let Some(&id) = map.get(&l) {
                            members.push(id);
                        }
                    }
                }
            } else {
                for t in f {
                    // a label or a set name, as every other target
                    if is_node {
                        members.extend(self.node_target(dl, kw, t)?);
                    } else {
                        members.extend(self.element_target(dl, kw, t)?);
                    }
                }
            }
        }
        let s = if is_node {
            Self::set_mut(&mut self.nsets, &mut self.nset_index, &name)
        } else {
            Self::set_mut(&mut self.elsets, &mut self.elset_index, &name)
        };
        let target = if is_node {
            &mut self.nsets[s]
        } else {
            &mut self.elsets[s]
        };
        target.members.extend(members);
        Ok(())
    }

    /// `*ELASTIC [, TYPE=]` of the current material: the constants of the
    /// type ([`Parser::elastic_type`], [`Parser::elastic_values`]); an
    /// orthotropic stiffness becomes engineering constants
    /// ([`Parser::ortho_to_engineering`]).
    fn elastic(
        &mut self,
        line: usize,
        params: &Params,
        data: &[(usize, &[&str], bool)],
    ) -> Result<(), InpError> {
        let kw = "ELASTIC";
        self.check_params(line, kw, params, &["TYPE"])?;
        if self.current_material.is_none() {
            return Err(self.invalid(line, kw, "*ELASTIC must follow *MATERIAL"));
        }
        let ty = Self::param(params, "TYPE")
            .and_then(|(_, v)| v.as_deref())
            .map(norm_key)
            .unwrap_or_else(|| "ISOTROPIC".into());
        let (count, names) = self.elastic_type(line, &ty)?;
        // one set of constants at one temperature (`E, nu, T`): constant
        let lines_needed = count.div_ceil(8);
        let nonempty = |f: &[&str]| f.iter().filter(|s| !s.is_empty()).count();
        let total: usize = data.iter().take(lines_needed).map(|d| nonempty(d.1)).sum();
        let last: Vec<&str>;
        let mut data_vec: Vec<(usize, &[&str], bool)> = data.to_vec();
        if data.len() == lines_needed && total == count + 1 {
            let (dl, f, c) = data[lines_needed - 1];
            last = f.iter().copied().filter(|s| !s.is_empty()).collect();
            let t = self.float(dl, kw, "temperature", last[last.len() - 1])?;
            self.deck.notes.push(format!(
                "line {dl}: *ELASTIC at temperature {t}: one set of constants, used at every temperature"
            ));
            data_vec[lines_needed - 1] = (dl, &last[..last.len() - 1], c);
        }
        let data = &data_vec[..];
        let mut v = self.elastic_values(line, &ty, count, names, data)?;
        if ty == "ORTHO" || ty == "ORTHOTROPIC" {
            v = self.ortho_to_engineering(data[0].0, &v)?;
        }
        let kind = match count {
            2 => InpMaterialKind::Isotropic { e: v[0], nu: v[1] },
            3 => InpMaterialKind::Traction([v[0], v[1], v[2]]),
            21 => {
                let mut a = [0.0; 21];
                a.copy_from_slice(&v);
                InpMaterialKind::Anisotropic(Box::new(a))
            }
            _ => {
                let mut a = [0.0; 9];
                a.copy_from_slice(&v);
                InpMaterialKind::EngineeringConstants(a)
            }
        };
        if let Some(m) = &self.current_material {
            if m.elastic.is_some() {
                return Err(self.invalid(
                    line,
                    kw,
                    format!("material `{}` has two *ELASTIC", m.name),
                ));
            }
        }
        let data_line = data[0].0;
        if let Some(m) = self.current_material.as_mut() {
            m.elastic = Some((kind, data_line));
        }
        Ok(())
    }

    /// Number and names of the constants of `*ELASTIC, TYPE=ty`.
    fn elastic_type(
        &self,
        line: usize,
        ty: &str,
    ) -> Result<(usize, &'static [&'static str]), InpError> {
        Ok(match ty {
            "ISOTROPIC" | "ISO" => (2, &["E", "nu"]),
            "ENGINEERING CONSTANTS" => (
                9,
                &[
                    "E1", "E2", "E3", "nu12", "nu13", "nu23", "G12", "G13", "G23",
                ],
            ),
            "TRACTION" => (3, &["K_nn", "K_ss", "K_tt"]),
            "ANISOTROPIC" | "ANISO" => (
                21,
                &[
                    "D1111", "D1122", "D2222", "D1133", "D2233", "D3333", "D1112", "D2212",
                    "D3312", "D1212", "D1113", "D2213", "D3313", "D1213", "D1313", "D1123",
                    "D2223", "D3323", "D1223", "D1323", "D2323",
                ],
            ),
            "ORTHOTROPIC" | "ORTHO" => (
                9,
                &[
                    "D1111", "D1122", "D2222", "D1133", "D2233", "D3333", "D1212", "D1313", "D2323",
                ],
            ),
            _ => {
                return Err(InpError::Parameter {
                    file: self.file.into(),
                    line,
                    keyword: "ELASTIC".into(),
                    parameter: format!("TYPE={ty}"),
                    valid: "TYPE=ISOTROPIC, TYPE=ENGINEERING CONSTANTS, TYPE=ORTHO, TYPE=ANISO, TYPE=TRACTION"
                        .into(),
                })
            }
        })
    }

    /// The `count` constants (`names`) of `*ELASTIC, TYPE=ty`, 8 per data
    /// line (ENGINEERING CONSTANTS and ORTHO on 2 lines, ANISO on 3); more
    /// lines (temperature dependence) are refused.
    fn elastic_values(
        &self,
        line: usize,
        ty: &str,
        count: usize,
        names: &[&str],
        data: &[(usize, &[&str], bool)],
    ) -> Result<Vec<f64>, InpError> {
        let kw = "ELASTIC";
        let lines_needed = count.div_ceil(8);
        if data.len() < lines_needed {
            return Err(self.invalid(
                line,
                kw,
                format!(
                    "TYPE={ty} expects {count} values ({}) on {lines_needed} data line(s)",
                    names.join(", ")
                ),
            ));
        }
        if data.len() > lines_needed {
            return Err(self.invalid(
                data[lines_needed].0,
                kw,
                "temperature-dependent elastic data is not supported (one set of constants only)",
            ));
        }
        let mut v = Vec::with_capacity(count);
        for &(dl, f, _) in &data[..lines_needed] {
            for t in f.iter().filter(|s| !s.is_empty()) {
                if v.len() == count {
                    return Err(self.invalid(
                        dl,
                        kw,
                        format!("too many values; TYPE={ty} expects {count} ({}); temperature is not supported", names.join(", ")),
                    ));
                }
                let name = names[v.len()];
                v.push(self.float(dl, kw, name, t)?);
            }
        }
        if v.len() != count {
            return Err(self.invalid(
                data[0].0,
                kw,
                format!(
                    "TYPE={ty} expects {count} values ({}), found {}",
                    names.join(", "),
                    v.len()
                ),
            ));
        }
        Ok(v)
    }

    /// Orthotropic stiffness `D1111 D1122 D2222 D1133 D2233 D3333 D1212
    /// D1313 D2323` -> engineering constants `E1 E2 E3 nu12 nu13 nu23 G12
    /// G13 G23`: `S` = inverse of the normal block [[D1111 D1122 D1133]
    /// [D1122 D2222 D2233] [D1133 D2233 D3333]]; `E_i = 1 / S_ii`, `nu_ij =
    /// -S_ij / S_ii` (`S_ij = -nu_ij / E_i`), `G_ij = D_ijij` (Abaqus
    /// Analysis User's Guide, "Linear elastic behavior", orthotropic
    /// `D_ijkl`). A stiffness that is not positive definite is refused
    /// (`data_line`).
    fn ortho_to_engineering(&self, data_line: usize, v: &[f64]) -> Result<Vec<f64>, InpError> {
        let d = [[v[0], v[1], v[3]], [v[1], v[2], v[4]], [v[3], v[4], v[5]]];
        let det = d[0][0] * (d[1][1] * d[2][2] - d[1][2] * d[2][1])
            - d[0][1] * (d[1][0] * d[2][2] - d[1][2] * d[2][0])
            + d[0][2] * (d[1][0] * d[2][1] - d[1][1] * d[2][0]);
        let pos = d[0][0] > 0.0 && d[0][0] * d[1][1] - d[0][1] * d[0][1] > 0.0 && det > 0.0;
        if !(pos && v[6] > 0.0 && v[7] > 0.0 && v[8] > 0.0) {
            return Err(self.invalid(
                data_line,
                "ELASTIC",
                "TYPE=ORTHO: the stiffness is not positive definite",
            ));
        }
        let cof = |i: usize, j: usize| {
            let (r, c) = ([(i + 1) % 3, (i + 2) % 3], [(j + 1) % 3, (j + 2) % 3]);
            d[r[0]][c[0]] * d[r[1]][c[1]] - d[r[0]][c[1]] * d[r[1]][c[0]]
        };
        // symmetric: S_ij = cof(j, i) / det = cof(i, j) / det
        let sm = |i: usize, j: usize| cof(j, i) / det;
        let e = [1.0 / sm(0, 0), 1.0 / sm(1, 1), 1.0 / sm(2, 2)];
        let (g12, g13, g23) = (v[6], v[7], v[8]);
        Ok(vec![
            e[0],
            e[1],
            e[2],
            -sm(0, 1) / sm(0, 0),
            -sm(0, 2) / sm(0, 0),
            -sm(1, 2) / sm(1, 1),
            g12,
            g13,
            g23,
        ])
    }

    /// The material a damage keyword belongs to, or an error naming the
    /// line.
    fn damage_material(&self, line: usize, kw: &str) -> Result<&PendingMaterial, InpError> {
        self.current_material.as_ref().ok_or_else(|| {
            self.invalid(
                line,
                kw,
                format!("*{kw} must follow the *MATERIAL (and its *ELASTIC, TYPE=TRACTION) of a cohesive material"),
            )
        })
    }

    /// The values of the single data line of a damage keyword: exactly
    /// `names.len()` numbers (temperature / field dependence is not read).
    fn damage_values(
        &self,
        line: usize,
        kw: &str,
        what: &str,
        names: &[&str],
        data: &[(usize, &[&str], bool)],
    ) -> Result<(Vec<f64>, usize), InpError> {
        let expected = || {
            format!(
                "{what} expects one data line with {} value(s): {}",
                names.len(),
                names.join(", ")
            )
        };
        let Some(&(dl, f, _)) = data.first() else {
            return Err(self.invalid(line, kw, expected()));
        };
        if data.len() > 1 {
            return Err(self.invalid(
                data[1].0,
                kw,
                format!(
                    "{}; temperature- or field-dependent damage data is not supported",
                    expected()
                ),
            ));
        }
        let f: Vec<&str> = f.iter().copied().filter(|t| !t.is_empty()).collect();
        if f.len() > names.len() {
            return Err(self.invalid(
                dl,
                kw,
                format!(
                    "{}, found {}; temperature- or field-dependent damage data is not supported",
                    expected(),
                    f.len()
                ),
            ));
        }
        if f.len() < names.len() {
            return Err(self.invalid(dl, kw, format!("{}, found {}", expected(), f.len())));
        }
        let mut v = Vec::with_capacity(f.len());
        for (t, name) in f.iter().zip(names) {
            let x = self.float(dl, kw, name, t)?;
            if x < 0.0 {
                return Err(self.invalid(dl, kw, format!("{name} = {x} must not be negative")));
            }
            v.push(x);
        }
        Ok((v, dl))
    }

    fn bad_param(&self, line: usize, kw: &str, parameter: String, valid: &str) -> InpError {
        InpError::Parameter {
            file: self.file.into(),
            line,
            keyword: kw.into(),
            parameter,
            valid: valid.into(),
        }
    }

    /// `*DAMAGE INITIATION, CRITERION=QUADS | MAXS`.
    fn damage_initiation(
        &mut self,
        line: usize,
        params: &Params,
        data: &[(usize, &[&str], bool)],
    ) -> Result<(), InpError> {
        let kw = "DAMAGE INITIATION";
        let m = self.damage_material(line, kw)?;
        if let Some(i) = &m.initiation {
            return Err(self.invalid(
                line,
                kw,
                format!("material `{}` already has a *DAMAGE INITIATION at line {}; Junta reads one criterion per cohesive material", m.name, i.line),
            ));
        }
        self.check_params(line, kw, params, &["CRITERION"])?;
        let valid = "CRITERION=QUADS, CRITERION=MAXS (cohesive nominal-stress criteria)";
        let criterion = match norm_key(&self.required(line, kw, params, "CRITERION")?).as_str() {
            "QUADS" => InpOnset::Quads,
            "MAXS" => InpOnset::Maxs,
            other => return Err(self.bad_param(line, kw, format!("CRITERION={other}"), valid)),
        };
        let (v, data_line) = self.damage_values(
            line,
            kw,
            "the criterion",
            &[
                "t_n^0 (normal strength)",
                "t_s^0 (first shear strength)",
                "t_t^0 (second shear strength)",
            ],
            data,
        )?;
        if let Some(k) = v.iter().position(|&x| x <= 0.0) {
            return Err(self.invalid(
                data_line,
                kw,
                format!(
                    "strength {} must be positive",
                    ["t_n^0", "t_s^0", "t_t^0"][k]
                ),
            ));
        }
        if let Some(m) = self.current_material.as_mut() {
            m.initiation = Some(InpDamageInitiation {
                criterion,
                strengths: [v[0], v[1], v[2]],
                line,
                data_line,
            });
        }
        Ok(())
    }

    /// `*DAMAGE EVOLUTION, TYPE=ENERGY [, SOFTENING=] [, MIXED MODE
    /// BEHAVIOR=, POWER=]`: softening ([`Parser::evolution_softening`]),
    /// mixed-mode rule ([`Parser::evolution_mixed_mode`]) and the fracture
    /// energies of the data line.
    fn damage_evolution(
        &mut self,
        line: usize,
        params: &Params,
        data: &[(usize, &[&str], bool)],
    ) -> Result<(), InpError> {
        let kw = "DAMAGE EVOLUTION";
        let m = self.damage_material(line, kw)?;
        if m.initiation.is_none() {
            return Err(self.invalid(
                line,
                kw,
                format!("*DAMAGE EVOLUTION of material `{}` must follow its *DAMAGE INITIATION (it is a sub-option of it)", m.name),
            ));
        }
        if let Some(e) = &m.evolution {
            return Err(self.invalid(
                line,
                kw,
                format!(
                    "material `{}` already has a *DAMAGE EVOLUTION at line {}",
                    m.name, e.line
                ),
            ));
        }
        self.check_params(
            line,
            kw,
            params,
            &[
                "TYPE",
                "SOFTENING",
                "MIXED MODE BEHAVIOR",
                "POWER",
                "DEGRADATION",
            ],
        )?;
        let softening = self.evolution_softening(line, params)?;
        let mixed_mode = self.evolution_mixed_mode(line, params)?;
        let (toughness, data_line) = if mixed_mode == InpMixedMode::ModeIndependent {
            let (v, dl) = self.damage_values(
                line,
                kw,
                "MODE INDEPENDENT",
                &["G_c (fracture energy)"],
                data,
            )?;
            ([v[0]; 3], dl)
        } else {
            let (v, dl) = self.damage_values(
                line,
                kw,
                "a mixed-mode rule",
                &[
                    "G_Ic (normal mode fracture energy)",
                    "G_IIc (first shear)",
                    "G_IIIc (second shear)",
                ],
                data,
            )?;
            ([v[0], v[1], v[2]], dl)
        };
        if let Some(k) = toughness.iter().position(|&x| x <= 0.0) {
            return Err(self.invalid(
                data_line,
                kw,
                format!(
                    "fracture energy {} must be positive",
                    ["G_Ic", "G_IIc", "G_IIIc"][k]
                ),
            ));
        }
        if let Some(m) = self.current_material.as_mut() {
            m.evolution = Some(InpDamageEvolution {
                softening,
                mixed_mode,
                toughness,
                line,
                data_line,
            });
        }
        Ok(())
    }

    /// `TYPE=ENERGY` (required), `SOFTENING=LINEAR | EXPONENTIAL` and
    /// `DEGRADATION=MAXIMUM` of `*DAMAGE EVOLUTION`.
    fn evolution_softening(&self, line: usize, params: &Params) -> Result<InpSoftening, InpError> {
        let kw = "DAMAGE EVOLUTION";
        match norm_key(&self.required(line, kw, params, "TYPE")?).as_str() {
            "ENERGY" => {}
            other => {
                return Err(self.bad_param(
                    line,
                    kw,
                    format!("TYPE={other}"),
                    "TYPE=ENERGY (fracture energies; TYPE=DISPLACEMENT is not supported)",
                ))
            }
        }
        let softening =
            match Self::param(params, "SOFTENING").map(|(_, v)| v.as_deref().map(norm_key)) {
                None => InpSoftening::Linear,
                Some(Some(v)) if v == "LINEAR" => InpSoftening::Linear,
                Some(Some(v)) if v == "EXPONENTIAL" => InpSoftening::Exponential,
                Some(v) => return Err(self.bad_param(
                    line,
                    kw,
                    format!("SOFTENING={}", v.unwrap_or_default()),
                    "SOFTENING=LINEAR (default), SOFTENING=EXPONENTIAL (TABULAR is not supported)",
                )),
            };
        match Self::param(params, "DEGRADATION").map(|(_, v)| v.as_deref().map(norm_key)) {
            None => {}
            Some(Some(v)) if v == "MAXIMUM" => {}
            Some(v) => {
                return Err(self.bad_param(
                    line,
                    kw,
                    format!("DEGRADATION={}", v.unwrap_or_default()),
                    "DEGRADATION=MAXIMUM (the default; one damage mechanism per material)",
                ))
            }
        }
        Ok(softening)
    }

    /// `MIXED MODE BEHAVIOR=MODE INDEPENDENT | BK | POWER LAW` of `*DAMAGE
    /// EVOLUTION`, with the exponent `POWER=` that BK and POWER LAW need
    /// (and MODE INDEPENDENT refuses).
    fn evolution_mixed_mode(&self, line: usize, params: &Params) -> Result<InpMixedMode, InpError> {
        let kw = "DAMAGE EVOLUTION";
        let power = match Self::param(params, "POWER") {
            None => None,
            Some((_, Some(v))) => {
                let p = self.float(line, kw, "POWER", v)?;
                if p <= 0.0 {
                    return Err(self.invalid(line, kw, format!("POWER={p} must be positive")));
                }
                Some(p)
            }
            Some((_, None)) => {
                return Err(self.invalid(line, kw, "POWER needs a value, e.g. POWER=2.284"))
            }
        };
        let mixed = Self::param(params, "MIXED MODE BEHAVIOR")
            .map(|(_, v)| v.as_deref().map(norm_key).unwrap_or_default());
        let need_power = |what: &str| {
            self.invalid(
                line,
                kw,
                format!("MIXED MODE BEHAVIOR={what} needs POWER= (the exponent of the rule)"),
            )
        };
        Ok(match mixed.as_deref() {
            None | Some("MODE INDEPENDENT") => {
                if power.is_some() {
                    return Err(self.invalid(
                        line,
                        kw,
                        "POWER= is only used with MIXED MODE BEHAVIOR=BK or POWER LAW",
                    ));
                }
                InpMixedMode::ModeIndependent
            }
            Some("BK") => InpMixedMode::Bk {
                power: power.ok_or_else(|| need_power("BK"))?,
            },
            Some("POWER LAW") => InpMixedMode::PowerLaw {
                power: power.ok_or_else(|| need_power("POWER LAW"))?,
            },
            Some(other) => {
                return Err(self.bad_param(
                    line,
                    kw,
                    format!("MIXED MODE BEHAVIOR={other}"),
                    "MIXED MODE BEHAVIOR=MODE INDEPENDENT (default), BK, POWER LAW (TABULAR is not supported)",
                ))
            }
        })
    }

    /// `*DAMAGE STABILIZATION`: one viscosity coefficient.
    fn damage_stabilization(
        &mut self,
        line: usize,
        params: &Params,
        data: &[(usize, &[&str], bool)],
    ) -> Result<(), InpError> {
        let kw = "DAMAGE STABILIZATION";
        let m = self.damage_material(line, kw)?;
        if let Some(st) = &m.stabilization {
            return Err(self.invalid(
                line,
                kw,
                format!(
                    "material `{}` already has a *DAMAGE STABILIZATION at line {}",
                    m.name, st.line
                ),
            ));
        }
        self.check_params(line, kw, params, &[])?;
        let (v, _) = self.damage_values(
            line,
            kw,
            "*DAMAGE STABILIZATION",
            &["viscosity coefficient"],
            data,
        )?;
        if let Some(m) = self.current_material.as_mut() {
            m.stabilization = Some(InpDamageStabilization {
                viscosity: v[0],
                line,
            });
        }
        Ok(())
    }

    fn boundary(
        &mut self,
        line: usize,
        params: &Params,
        data: &[(usize, &[&str], bool)],
    ) -> Result<(), InpError> {
        let kw = "BOUNDARY";
        self.check_params(line, kw, params, &["OP", "AMPLITUDE"])?;
        let op_new = self.op_new(line, kw, params)?;
        let amplitude = self.amplitude_param(line, kw, params)?;
        for &(dl, f, _) in data {
            let f: Vec<&str> = f.to_vec();
            let target = f.first().copied().unwrap_or("");
            if target.is_empty() || f.len() < 2 || f.len() > 4 {
                return Err(self.invalid(
                    dl,
                    kw,
                    "expected `node or node set, first dof[, last dof[, value]]`",
                ));
            }
            let (first, last) = match f[1].to_uppercase().as_str() {
                "ENCASTRE" | "PINNED" => (1, 3),
                "XSYMM" => (1, 1),
                "YSYMM" => (2, 2),
                "ZSYMM" => (3, 3),
                _ => {
                    let a = self.dof(dl, kw, f[1])?;
                    let b = match f.get(2) {
                        Some(t) if !t.is_empty() => self.dof(dl, kw, t)?,
                        _ => a,
                    };
                    if b < a {
                        return Err(self.invalid(
                            dl,
                            kw,
                            format!("last dof {b} is below first dof {a}"),
                        ));
                    }
                    (a, b)
                }
            };
            let value = match f.get(3) {
                Some(t) if !t.is_empty() => self.float(dl, kw, "value", t)?,
                _ => 0.0,
            };
            self.boundary_targets.push(PendingTarget {
                target: target.into(),
                line: dl,
                keyword: "BOUNDARY",
            });
            self.deck.boundaries.push(InpBoundary {
                target: target.into(),
                nodes: Vec::new(),
                first_dof: first,
                last_dof: last,
                value,
                in_step: self.step_open.is_some(),
                step: self.step_open.map(|_| self.deck.steps.len() - 1),
                op_new,
                keyword_line: line,
                line: dl,
                amplitude: None,
            });
            self.refer_amplitude(
                AmplitudeUse::Boundary,
                self.deck.boundaries.len() - 1,
                &amplitude,
                line,
            );
        }
        Ok(())
    }

    /// The `OP` parameter of `*BOUNDARY` / `*CLOAD`: `MOD` (default) or
    /// `NEW` (only inside a step).
    fn op_new(&self, line: usize, kw: &str, params: &Params) -> Result<bool, InpError> {
        let bad = |op: &str| InpError::Parameter {
            file: self.file.into(),
            line,
            keyword: kw.into(),
            parameter: format!("OP={op}"),
            valid: "OP=MOD, OP=NEW (inside *STEP)".into(),
        };
        match Self::param(params, "OP") {
            None => Ok(false),
            Some((_, None)) => Err(bad("")),
            Some((_, Some(op))) if op.eq_ignore_ascii_case("MOD") => Ok(false),
            Some((_, Some(op))) if op.eq_ignore_ascii_case("NEW") => {
                if self.step_open.is_none() {
                    return Err(self.invalid(
                        line,
                        kw,
                        "OP=NEW removes what earlier steps applied; it is only valid inside *STEP",
                    ));
                }
                Ok(true)
            }
            Some((_, Some(op))) => Err(bad(op)),
        }
    }

    /// `*AMPLITUDE, NAME= [, TIME=STEP TIME | TOTAL TIME] [,
    /// DEFINITION=TABULAR] [, VALUE=RELATIVE] [, SHIFTX=] [, SHIFTY=]`:
    /// data lines of `time, value` pairs (any number per line).
    fn amplitude(
        &mut self,
        line: usize,
        params: &Params,
        data: &[(usize, &[&str], bool)],
    ) -> Result<(), InpError> {
        let kw = "AMPLITUDE";
        self.check_params(
            line,
            kw,
            params,
            &["NAME", "TIME", "DEFINITION", "VALUE", "SHIFTX", "SHIFTY"],
        )?;
        let name = self.required(line, kw, params, "NAME")?;
        if self
            .deck
            .amplitudes
            .iter()
            .any(|a| a.name.eq_ignore_ascii_case(&name))
        {
            return Err(self.invalid(line, kw, format!("amplitude `{name}` is defined twice")));
        }
        let total_time = self.two_way(
            line,
            kw,
            params,
            ("TIME", "STEP TIME", "TOTAL TIME"),
            "TIME=STEP TIME, TIME=TOTAL TIME",
        )?;
        for (key, valid) in [("DEFINITION", "TABULAR"), ("VALUE", "RELATIVE")] {
            if let Some((_, v)) = Self::param(params, key) {
                if !v.as_deref().is_some_and(|v| v.eq_ignore_ascii_case(valid)) {
                    return Err(InpError::Parameter {
                        file: self.file.into(),
                        line,
                        keyword: kw.into(),
                        parameter: format!("{key}={}", v.as_deref().unwrap_or("")),
                        valid: format!("{key}={valid} (the only form Junta reads)"),
                    });
                }
            }
        }
        let shift = |key: &str| -> Result<f64, InpError> {
            match Self::param(params, key) {
                None => Ok(0.0),
                Some((_, Some(v))) => {
                    let x = self.float(line, kw, key, v)?;
                    if x.is_finite() {
                        Ok(x)
                    } else {
                        Err(self.invalid(line, kw, format!("{key}={v} is not finite")))
                    }
                }
                Some((_, None)) => Err(self.invalid(line, kw, format!("{key}= needs a value"))),
            }
        };
        let (dx, dy) = (shift("SHIFTX")?, shift("SHIFTY")?);
        let mut points: Vec<(f64, f64)> = Vec::new();
        for &(dl, f, _) in data {
            let f: Vec<&str> = f.iter().copied().filter(|t| !t.trim().is_empty()).collect();
            if !f.len().is_multiple_of(2) {
                return Err(self.invalid(
                    dl,
                    kw,
                    format!("{} values: expected `time, value` pairs", f.len()),
                ));
            }
            for pair in f.chunks(2) {
                let t = self.float(dl, kw, "time", pair[0])? + dx;
                let a = self.float(dl, kw, "amplitude value", pair[1])? + dy;
                if !(t.is_finite() && a.is_finite()) {
                    return Err(self.invalid(dl, kw, "times and values must be finite"));
                }
                if let Some(&(t0, _)) = points.last() {
                    if t < t0 {
                        return Err(self.invalid(
                            dl,
                            kw,
                            format!("time {t} is earlier than the point before it ({t0}): times must not decrease"),
                        ));
                    }
                }
                points.push((t, a));
            }
        }
        if points.is_empty() {
            return Err(self.invalid(line, kw, "no `time, value` pairs follow"));
        }
        self.deck.amplitudes.push(InpAmplitude {
            name,
            points,
            total_time,
            line,
        });
        Ok(())
    }

    /// Keep the `AMPLITUDE=` name of record `index` of list `what` (if
    /// any) for resolution when the deck is read.
    fn refer_amplitude(
        &mut self,
        what: AmplitudeUse,
        index: usize,
        amplitude: &Option<String>,
        line: usize,
    ) {
        if let Some(name) = amplitude {
            self.amplitude_refs.push((what, index, name.clone(), line));
        }
    }

    /// The `AMPLITUDE=` parameter of a load keyword: the name, only inside
    /// a step (an amplitude scales a load over the step time).
    fn amplitude_param(
        &self,
        line: usize,
        kw: &str,
        params: &Params,
    ) -> Result<Option<String>, InpError> {
        match Self::param(params, "AMPLITUDE") {
            None => Ok(None),
            Some((_, Some(name))) if !name.is_empty() => {
                if self.step_open.is_none() {
                    return Err(self.invalid(
                        line,
                        kw,
                        "AMPLITUDE= scales a load over a step's time; it is only valid inside *STEP",
                    ));
                }
                Ok(Some(name.clone()))
            }
            Some(_) => Err(self.invalid(line, kw, "AMPLITUDE= needs the name of an *AMPLITUDE")),
        }
    }

    fn cload(
        &mut self,
        line: usize,
        params: &Params,
        data: &[(usize, &[&str], bool)],
    ) -> Result<(), InpError> {
        let kw = "CLOAD";
        self.check_params(line, kw, params, &["OP", "AMPLITUDE"])?;
        let op_new = self.op_new(line, kw, params)?;
        let amplitude = self.amplitude_param(line, kw, params)?;
        for &(dl, f, _) in data {
            if f.len() != 3 || f[0].is_empty() {
                return Err(self.invalid(dl, kw, "expected `node or node set, dof, value`"));
            }
            let dof = self.dof(dl, kw, f[1])?;
            let value = self.float(dl, kw, "value", f[2])?;
            self.cload_targets.push(PendingTarget {
                target: f[0].into(),
                line: dl,
                keyword: "CLOAD",
            });
            self.deck.cloads.push(InpCload {
                target: f[0].into(),
                nodes: Vec::new(),
                dof,
                value,
                in_step: self.step_open.is_some(),
                step: self.step_open.map(|_| self.deck.steps.len() - 1),
                op_new,
                keyword_line: line,
                line: dl,
                amplitude: None,
            });
            self.refer_amplitude(
                AmplitudeUse::Cload,
                self.deck.cloads.len() - 1,
                &amplitude,
                line,
            );
        }
        Ok(())
    }

    /// `*EQUATION`: per equation a line with the number of terms N, then N
    /// `node (or node set), dof, coefficient` triples over as many lines as
    /// needed (CalculiX and Abaqus put at most four per line).
    fn equation(
        &mut self,
        line: usize,
        params: &Params,
        data: &[(usize, &[&str], bool)],
    ) -> Result<(), InpError> {
        let kw = "EQUATION";
        self.check_params(line, kw, params, &[])?;
        self.model_data_only(line, kw)?;
        if data.is_empty() {
            return Err(self.invalid(
                line,
                kw,
                "no equation follows (expected the number of terms)",
            ));
        }
        let mut k = 0;
        while k < data.len() {
            let (dl, f, _) = data[k];
            if f.len() != 1 {
                return Err(self.invalid(
                    dl,
                    kw,
                    "expected the number of terms of the next equation alone on its line",
                ));
            }
            let n = self.label(dl, kw, "number of terms", f[0])?;
            if n < 2 {
                return Err(self.invalid(
                    dl,
                    kw,
                    format!("an equation needs at least 2 terms, not {n}"),
                ));
            }
            k += 1;
            let mut fields: Vec<(usize, &str)> = Vec::with_capacity(3 * n);
            while fields.len() < 3 * n {
                let Some(&(tl, tf, _)) = data.get(k) else {
                    return Err(self.invalid(
                        dl,
                        kw,
                        format!(
                            "the equation announces {n} terms but the data ends after {} fields (3 per term: node, dof, coefficient)",
                            fields.len()
                        ),
                    ));
                };
                fields.extend(tf.iter().map(|t| (tl, *t)));
                k += 1;
            }
            if fields.len() != 3 * n {
                return Err(self.invalid(
                    fields[3 * n].0,
                    kw,
                    format!(
                        "the equation has {n} terms, so {} fields, but its lines hold {}",
                        3 * n,
                        fields.len()
                    ),
                ));
            }
            let mut terms = Vec::with_capacity(n);
            for t in fields.chunks(3) {
                let (tl, target) = t[0];
                if target.is_empty() {
                    return Err(self.invalid(
                        tl,
                        kw,
                        "expected `node or node set, dof, coefficient`",
                    ));
                }
                let dof = self.dof(t[1].0, kw, t[1].1)?;
                let a = self.float(t[2].0, kw, "coefficient", t[2].1)?;
                terms.push((target.to_string(), dof, a));
            }
            if terms[0].2 == 0.0 {
                return Err(self.invalid(
                    dl,
                    kw,
                    "the first (dependent) term has coefficient 0; it must be non-zero",
                ));
            }
            self.equation_terms.push((dl, terms));
        }
        Ok(())
    }

    /// `*ORIENTATION, NAME= [, SYSTEM=RECTANGULAR|CYLINDRICAL] [, DEFINITION=COORDINATES]`:
    /// rectangular `a, b [, c]` (points: a on material axis 1, b in the 1-2
    /// plane, c the origin); cylindrical `a, b` (two points of the axis,
    /// exactly 6 values); an optional second line `axis, angle` must have
    /// angle 0.
    fn orientation(
        &mut self,
        line: usize,
        params: &Params,
        data: &[(usize, &[&str], bool)],
    ) -> Result<(), InpError> {
        let kw = "ORIENTATION";
        self.model_data_only(line, kw)?;
        self.check_params(line, kw, params, &["NAME", "SYSTEM", "DEFINITION"])?;
        let name = self.required(line, kw, params, "NAME")?;
        let value = |k: &str| {
            Self::param(params, k)
                .and_then(|(_, v)| v.as_deref())
                .map(norm_key)
        };
        let cylindrical = match value("SYSTEM").as_deref() {
            None | Some("RECTANGULAR") | Some("R") => false,
            Some("CYLINDRICAL") | Some("C") => true,
            Some(sys) => {
                return Err(InpError::Parameter {
                    file: self.file.into(),
                    line,
                    keyword: kw.into(),
                    parameter: format!("SYSTEM={sys}"),
                    valid: "SYSTEM=RECTANGULAR or SYSTEM=CYLINDRICAL".into(),
                })
            }
        };
        if let Some(d) = value("DEFINITION").filter(|d| d != "COORDINATES") {
            return Err(InpError::Parameter {
                file: self.file.into(),
                line,
                keyword: kw.into(),
                parameter: format!("DEFINITION={d}"),
                valid: "DEFINITION=COORDINATES".into(),
            });
        }
        let expected = if cylindrical {
            "`ax, ay, az, bx, by, bz` (two points a, b of the cylinder axis)"
        } else {
            "`ax, ay, az, bx, by, bz [, cx, cy, cz]`"
        };
        let Some(&(dl, f, _)) = data.first() else {
            return Err(self.invalid(line, kw, format!("expected a data line {expected}")));
        };
        let f: Vec<&str> = f.iter().copied().filter(|t| !t.is_empty()).collect();
        if !(f.len() == 6 || (f.len() == 9 && !cylindrical)) {
            return Err(self.invalid(
                dl,
                kw,
                format!(
                    "expected {} values {expected}, found {}",
                    if cylindrical { "6" } else { "6 or 9" },
                    f.len()
                ),
            ));
        }
        let a = self.vector3(dl, kw, "point a", &f[0..3])?;
        let b = self.vector3(dl, kw, "point b", &f[3..6])?;
        let c = if f.len() == 9 {
            self.deck.notes.push(format!(
                "{}:{dl}: *ORIENTATION {name}: origin c (values 7-9) used as in Abaqus, material axis 1 along a - c; CalculiX 2.20 ignores these values",
                self.file
            ));
            self.vector3(dl, kw, "origin c", &f[6..9])?
        } else {
            [0.0; 3]
        };
        if let Some(&(l2, f2, _)) = data.get(1) {
            let angle = match f2.get(1) {
                Some(t) => self.float(l2, kw, "rotation angle", t)?,
                None => 0.0,
            };
            if angle != 0.0 || data.len() > 2 {
                return Err(self.invalid(
                    l2,
                    kw,
                    "an additional rotation about a local axis (second data line with a non-zero angle) is not supported",
                ));
            }
        }
        let norm = |v: [f64; 3]| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        let sub = |p: [f64; 3], q: [f64; 3]| [p[0] - q[0], p[1] - q[1], p[2] - q[2]];
        let (a, b) = if cylindrical {
            // the axis direction b - a, relative to the points' size
            if norm(sub(b, a)) <= 1e-12 * norm(a).max(norm(b)) {
                return Err(self.invalid(
                    dl,
                    kw,
                    format!(
                        "cylindrical system: points a = {a:?} and b = {b:?} must differ (they give the cylinder axis)"
                    ),
                ));
            }
            (a, b)
        } else {
            let (a, b) = (sub(a, c), sub(b, c));
            let cross = [
                a[1] * b[2] - a[2] * b[1],
                a[2] * b[0] - a[0] * b[2],
                a[0] * b[1] - a[1] * b[0],
            ];
            if norm(a) == 0.0 || norm(cross) <= 1e-10 * norm(a) * norm(b) {
                return Err(self.invalid(
                    dl,
                    kw,
                    "point a must differ from the origin and point b must not lie on the line through the origin and a",
                ));
            }
            (a, b)
        };
        if self
            .deck
            .orientations
            .iter()
            .any(|o| o.name.eq_ignore_ascii_case(&name))
        {
            return Err(self.invalid(line, kw, format!("orientation `{name}` is defined twice")));
        }
        self.deck.orientations.push(InpOrientation {
            name,
            a,
            b,
            cylindrical,
            line,
        });
        Ok(())
    }

    /// `*SURFACE, NAME= [, TYPE=ELEMENT|NODE]`: element faces
    /// (`element or elset, S1..S6` or `P1..P6`) or nodes (`node or nset [, weight]`).
    fn surface(
        &mut self,
        line: usize,
        params: &Params,
        data: &[(usize, &[&str], bool)],
    ) -> Result<(), InpError> {
        let kw = "SURFACE";
        self.check_params(line, kw, params, &["NAME", "TYPE"])?;
        let name = self.required(line, kw, params, "NAME")?;
        let node = self.two_way(
            line,
            kw,
            params,
            ("TYPE", "ELEMENT", "NODE"),
            "TYPE=ELEMENT (faces S1..S6, the default), TYPE=NODE",
        )?;
        if data.is_empty() {
            return Err(self.invalid(line, kw, format!("surface `{name}` has no data lines")));
        }
        let key = name.to_uppercase();
        if node {
            let mut nodes = Vec::new();
            for &(dl, f, _) in data {
                if f.is_empty() || f[0].is_empty() || f.len() > 2 {
                    return Err(self.invalid(dl, kw, "expected `node or node set [, weight]`"));
                }
                nodes.extend(self.node_target(dl, kw, f[0])?);
            }
            nodes.sort_unstable();
            nodes.dedup();
            self.deck
                .node_surfaces
                .entry(key)
                .or_default()
                .extend(nodes);
            return Ok(());
        }
        let mut faces = Vec::with_capacity(data.len());
        for &(dl, f, _) in data {
            if f.len() != 2 || f[0].is_empty() {
                return Err(self.invalid(
                    dl,
                    kw,
                    "expected `element or element set, face` with the face S1..S6",
                ));
            }
            // S1..S6 (Abaqus) or P1..P6 (CalculiX's *DLOAD face names)
            let letter = if f[1].trim().to_uppercase().starts_with('P') {
                'P'
            } else {
                'S'
            };
            let face = self.face_label(dl, kw, f[1], letter)?;
            faces.push((f[0].to_string(), face));
        }
        self.surfaces
            .entry(key)
            .or_insert_with(|| (line, Vec::new()))
            .1
            .extend(faces);
        Ok(())
    }

    /// Face `S1`..`S6` (or `P1`..`P6` with `letter = 'P'`), 0-based.
    fn face_label(
        &self,
        line: usize,
        kw: &str,
        text: &str,
        letter: char,
    ) -> Result<usize, InpError> {
        let t = text.trim().to_uppercase();
        match t.strip_prefix(letter).and_then(|n| n.parse::<usize>().ok()) {
            Some(n @ 1..=6) => Ok(n - 1),
            _ => Err(self.invalid(
                line,
                kw,
                format!(
                    "face `{text}`: valid faces are {letter}1..{letter}6 (solid element faces)"
                ),
            )),
        }
    }

    /// Three finite numbers from `f[i..i + 3]`.
    fn vector3(&self, line: usize, kw: &str, what: &str, f: &[&str]) -> Result<[f64; 3], InpError> {
        let mut v = [0.0; 3];
        for (k, x) in v.iter_mut().enumerate() {
            *x = self.float(line, kw, what, f[k])?;
        }
        Ok(v)
    }

    /// `*DLOAD [, OP=]`: `element or elset, label, values`: `P1`..`P6`
    /// pressure, `GRAV, g, nx, ny, nz`, `CENTRIF, omega^2, point, axis`,
    /// `BX|BY|BZ, force per volume`.
    fn dload(
        &mut self,
        line: usize,
        params: &Params,
        data: &[(usize, &[&str], bool)],
    ) -> Result<(), InpError> {
        let kw = "DLOAD";
        self.check_params(line, kw, params, &["OP", "AMPLITUDE"])?;
        let op_new = self.op_new(line, kw, params)?;
        let amplitude = self.amplitude_param(line, kw, params)?;
        for &(dl, f, _) in data {
            if f.len() < 3 || f[0].is_empty() {
                return Err(self.invalid(
                    dl,
                    kw,
                    "expected `element or element set, load label, magnitude [, ...]`",
                ));
            }
            let label = f[1].trim().to_uppercase();
            let want = |n: usize| -> Result<(), InpError> {
                if f.len() != n {
                    return Err(self.invalid(
                        dl,
                        kw,
                        format!(
                            "load {label} takes {} values after the label, not {}",
                            n - 2,
                            f.len() - 2
                        ),
                    ));
                }
                Ok(())
            };
            let (kind, face) = match label.as_str() {
                "GRAV" => {
                    want(6)?;
                    let g = self.float(dl, kw, "GRAV magnitude", f[2])?;
                    let d = self.vector3(dl, kw, "GRAV direction", &f[3..6])?;
                    let l = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
                    if !(l > 0.0 && l.is_finite()) {
                        return Err(self.invalid(dl, kw, "GRAV direction (values 4-6) has no length"));
                    }
                    (InpDloadKind::Gravity([g * d[0] / l, g * d[1] / l, g * d[2] / l]), 0)
                }
                "CENTRIF" => {
                    want(9)?;
                    let omega2 = self.float(dl, kw, "CENTRIF omega^2", f[2])?;
                    let point = self.vector3(dl, kw, "CENTRIF axis point", &f[3..6])?;
                    let axis = self.vector3(dl, kw, "CENTRIF axis direction", &f[6..9])?;
                    if axis.iter().all(|&a| a == 0.0) {
                        return Err(self.invalid(dl, kw, "CENTRIF axis direction (values 7-9) is zero"));
                    }
                    (InpDloadKind::Centrifugal { omega2, point, axis }, 0)
                }
                "BX" | "BY" | "BZ" => {
                    want(3)?;
                    let b = self.float(dl, kw, "body force", f[2])?;
                    let mut v = [0.0; 3];
                    v[(label.as_bytes()[1] - b'X') as usize] = b;
                    (InpDloadKind::BodyForce(v), 0)
                }
                l if l.starts_with('P') && l.len() == 2 => {
                    want(3)?;
                    let face = self.face_label(dl, kw, l, 'P')?;
                    (InpDloadKind::Pressure(self.float(dl, kw, "pressure", f[2])?), face)
                }
                _ => {
                    return Err(self.invalid(
                        dl,
                        kw,
                        format!("load label `{}` is not supported; valid: P1..P6 (pressure on a face), GRAV, CENTRIF, BX, BY, BZ", f[1]),
                    ))
                }
            };
            self.dload_targets.push(DloadTarget::Elements {
                target: f[0].to_string(),
                face,
            });
            self.deck.dloads.push(InpDload {
                label,
                kind,
                elements: Vec::new(),
                step: self.step_open.map(|_| self.deck.steps.len() - 1),
                op_new,
                keyword_line: line,
                line: dl,
                amplitude: None,
            });
            self.refer_amplitude(
                AmplitudeUse::Dload,
                self.deck.dloads.len() - 1,
                &amplitude,
                line,
            );
        }
        Ok(())
    }

    /// `*DSLOAD [, OP=]`: `surface, P, pressure` on an element surface.
    fn dsload(
        &mut self,
        line: usize,
        params: &Params,
        data: &[(usize, &[&str], bool)],
    ) -> Result<(), InpError> {
        let kw = "DSLOAD";
        self.check_params(line, kw, params, &["OP", "AMPLITUDE"])?;
        let op_new = self.op_new(line, kw, params)?;
        let amplitude = self.amplitude_param(line, kw, params)?;
        for &(dl, f, _) in data {
            if f.len() != 3 || f[0].is_empty() {
                return Err(self.invalid(dl, kw, "expected `surface, P, pressure`"));
            }
            if !f[1].trim().eq_ignore_ascii_case("P") {
                return Err(self.invalid(
                    dl,
                    kw,
                    format!(
                        "load label `{}` is not supported; valid: P (uniform pressure)",
                        f[1]
                    ),
                ));
            }
            let p = self.float(dl, kw, "pressure", f[2])?;
            self.dload_targets
                .push(DloadTarget::Surface(f[0].to_string()));
            self.deck.dloads.push(InpDload {
                label: "P".into(),
                kind: InpDloadKind::Pressure(p),
                elements: Vec::new(),
                step: self.step_open.map(|_| self.deck.steps.len() - 1),
                op_new,
                keyword_line: line,
                line: dl,
                amplitude: None,
            });
            self.refer_amplitude(
                AmplitudeUse::Dload,
                self.deck.dloads.len() - 1,
                &amplitude,
                line,
            );
        }
        Ok(())
    }

    /// Flat element ids of an element label or element set.
    fn element_target(&self, line: usize, kw: &str, target: &str) -> Result<Vec<usize>, InpError> {
        if target.chars().all(|c| c.is_ascii_digit()) {
            let l = self.label(line, kw, "element label", target)?;
            let id = self
                .elem_id
                .get(&l)
                .copied()
                .ok_or_else(|| InpError::UndefinedLabel {
                    file: self.file.into(),
                    line,
                    keyword: kw.into(),
                    kind: "element",
                    label: l,
                })?;
            Ok(vec![id])
        } else {
            match self.elset_index.get(&target.to_uppercase()) {
                Some(&s) => Ok(self.elsets[s].members.clone()),
                None => Err(self.unknown_set(line, kw, "element set", target)),
            }
        }
    }

    /// Resolve the targets of the distributed loads to `(flat element id,
    /// face)` lists (the flat ids become element references in `finish`),
    /// checking that a pressure's face exists on the element.
    fn resolve_dloads(&mut self) -> Result<Vec<Vec<(usize, usize)>>, InpError> {
        let targets = std::mem::take(&mut self.dload_targets);
        let mut out = Vec::with_capacity(targets.len());
        for (k, t) in targets.iter().enumerate() {
            let (line, pressure) = (
                self.deck.dloads[k].line,
                matches!(self.deck.dloads[k].kind, InpDloadKind::Pressure(_)),
            );
            let kw = if matches!(t, DloadTarget::Surface(_)) {
                "DSLOAD"
            } else {
                "DLOAD"
            };
            let mut list = Vec::new();
            // where the faces were written: the *SURFACE's keyword line
            let mut surface_at = None;
            match t {
                DloadTarget::Elements { target, face } => {
                    for e in self.element_target(line, kw, target)? {
                        list.push((e, *face));
                    }
                }
                DloadTarget::Surface(name) => {
                    let key = name.to_uppercase();
                    let Some((_, faces)) = self.surfaces.get(&key) else {
                        let what = if self.deck.node_surfaces.contains_key(&key) {
                            format!("`{name}` is a node surface (TYPE=NODE); a pressure needs an element surface (TYPE=ELEMENT, faces S1..S6)")
                        } else {
                            let mut names: Vec<&String> = self.surfaces.keys().collect();
                            names.sort();
                            format!("element surface `{name}` is not defined; defined: {names:?}")
                        };
                        return Err(self.invalid(line, kw, what));
                    };
                    surface_at = Some((name, self.surfaces[&key].0));
                    for (target, face) in faces {
                        for e in self.element_target(line, kw, target)? {
                            list.push((e, *face));
                        }
                    }
                }
            }
            for &(e, face) in &list {
                let el = &self.elems[e];
                let shape = self.pre_blocks[el.pre_block].shape;
                if !shape.is_solid() {
                    return Err(self.invalid(
                        line,
                        kw,
                        format!(
                            "element {} is a {} element; distributed loads act on solids",
                            el.label,
                            shape.name()
                        ),
                    ));
                }
                if pressure && face >= shape.num_faces() {
                    let n = shape.num_faces();
                    let written = match &surface_at {
                        Some((name, at)) => {
                            format!("face S{} of surface `{name}` (line {at})", face + 1)
                        }
                        None => format!("P{}", face + 1),
                    };
                    return Err(self.invalid(
                        line,
                        kw,
                        format!(
                            "{written}: element {} is a {} element, whose faces are P1..P{n} (S1..S{n})",
                            el.label,
                            shape.name()
                        ),
                    ));
                }
            }
            out.push(list);
        }
        Ok(out)
    }

    /// Resolve the terms of the `*EQUATION`s: a node set stands for each of
    /// its members in turn (every set of one equation must have as many).
    fn resolve_equations(&mut self) -> Result<(), InpError> {
        let kw = "EQUATION";
        let written = std::mem::take(&mut self.equation_terms);
        for (line, terms) in &written {
            let mut nodes = Vec::with_capacity(terms.len());
            let mut count = 1;
            for (target, _, _) in terms {
                let ns = self.node_target(*line, kw, target)?;
                if ns.is_empty() {
                    return Err(self.invalid(*line, kw, format!("node set `{target}` is empty")));
                }
                if ns.len() != 1 {
                    if count != 1 && ns.len() != count {
                        return Err(self.invalid(
                            *line,
                            kw,
                            format!(
                                "node set `{target}` has {} nodes but another set of the equation has {count}; sets of one equation must have as many nodes",
                                ns.len()
                            ),
                        ));
                    }
                    count = ns.len();
                }
                nodes.push(ns);
            }
            for i in 0..count {
                let terms = terms
                    .iter()
                    .zip(&nodes)
                    .map(|((_, dof, a), ns)| (if ns.len() == 1 { ns[0] } else { ns[i] }, *dof, *a))
                    .collect();
                self.deck.equations.push(InpEquation { terms, line: *line });
            }
        }
        Ok(())
    }

    /// Resolve targets, assign sections, build the mesh: the `*EQUATION`
    /// terms, the `AMPLITUDE=` names, the distributed loads' elements, the
    /// boundary and load nodes, the sections ([`Parser::assign_sections`]),
    /// the use of damage materials, the curve directive, then the blocks
    /// ([`Parser::build_blocks`]) and the mesh with its sets
    /// ([`Parser::into_deck`]).
    fn finish(mut self) -> Result<InpDeck, InpError> {
        self.resolve_equations()?;
        self.resolve_amplitudes()?;
        let dload_ids = self.resolve_dloads()?;
        for (k, p) in self.boundary_targets.iter().enumerate() {
            self.deck.boundaries[k].nodes = self.node_target(p.line, p.keyword, &p.target)?;
        }
        for (k, p) in self.cload_targets.iter().enumerate() {
            self.deck.cloads[k].nodes = self.node_target(p.line, p.keyword, &p.target)?;
        }
        for k in 0..self.deck.temperatures.len() {
            let t = &self.deck.temperatures[k];
            let kw = if t.step.is_some() {
                "TEMPERATURE"
            } else {
                "INITIAL CONDITIONS"
            };
            self.deck.temperatures[k].nodes = self.node_target(t.line, kw, &t.target)?;
        }
        for &(line, ref elset) in &self.membranes {
            let members = self
                .elset_index
                .get(&elset.to_uppercase())
                .map_or(0, |&i| self.elsets[i].members.len());
            if members > 0 {
                return Err(self.invalid(
                    line,
                    "MEMBRANE",
                    format!("ELSET={elset} has {members} element(s): membrane elements are not supported (Junta's elements are solids and interfaces)"),
                ));
            }
            self.deck.notes.push(format!(
                "line {line}: *MEMBRANE, ELSET={elset} ignored: the set has no elements"
            ));
        }
        self.assign_sections()?;
        for m in self.deck.materials.iter().filter(|m| m.has_damage()) {
            if !self
                .deck
                .cohesive_sections
                .iter()
                .any(|c| c.material.eq_ignore_ascii_case(&m.name))
            {
                return Err(self.invalid(
                    m.line,
                    "MATERIAL",
                    format!("material `{}` has damage options but no *COHESIVE SECTION uses it: damage is read for cohesive elements (COH3D8, COH3D6) only", m.name),
                ));
            }
        }
        self.resolve_curve()?;
        let (refs, blocks, block_orientations) = self.build_blocks();
        self.into_deck(refs, blocks, block_orientations, dload_ids)
    }

    /// Each `AMPLITUDE=` name to the index of its `*AMPLITUDE`.
    fn resolve_amplitudes(&mut self) -> Result<(), InpError> {
        for (what, k, name, line) in std::mem::take(&mut self.amplitude_refs) {
            let Some(a) = self
                .deck
                .amplitudes
                .iter()
                .position(|a| a.name.eq_ignore_ascii_case(&name))
            else {
                let kw = match what {
                    AmplitudeUse::Boundary => "BOUNDARY",
                    AmplitudeUse::Cload => "CLOAD",
                    AmplitudeUse::Dload => "DLOAD",
                };
                let known: Vec<&str> = self
                    .deck
                    .amplitudes
                    .iter()
                    .map(|a| a.name.as_str())
                    .collect();
                return Err(self.invalid(
                    line,
                    kw,
                    format!(
                        "AMPLITUDE={name}: no *AMPLITUDE of that name (defined: {})",
                        if known.is_empty() {
                            "none".to_string()
                        } else {
                            known.join(", ")
                        }
                    ),
                ));
            };
            match what {
                AmplitudeUse::Boundary => self.deck.boundaries[k].amplitude = Some(a),
                AmplitudeUse::Cload => self.deck.cloads[k].amplitude = Some(a),
                AmplitudeUse::Dload => self.deck.dloads[k].amplitude = Some(a),
            }
        }
        Ok(())
    }

    /// Sections -> element materials: every element of a section's set
    /// gets the section's material (as the material is spelt) and
    /// orientation ([`Parser::assign_section`]). Solid sections first, then
    /// cohesive ones, each in input order.
    fn assign_sections(&mut self) -> Result<(), InpError> {
        #[allow(clippy::type_complexity)]
        let mut sections: Vec<(String, String, usize, bool, Option<String>)> = self
            .deck
            .solid_sections
            .iter()
            .map(|s| {
                (
                    s.elset.clone(),
                    s.material.clone(),
                    s.line,
                    false,
                    s.orientation.clone(),
                )
            })
            .collect();
        sections.extend(
            self.deck
                .cohesive_sections
                .iter()
                .map(|s| (s.elset.clone(), s.material.clone(), s.line, true, None)),
        );
        for (elset, material, line, cohesive, orientation) in sections {
            let orientation = match orientation {
                None => None,
                Some(o) => Some(self.section_orientation(line, o)?),
            };
            let kw = if cohesive {
                "COHESIVE SECTION"
            } else {
                "SOLID SECTION"
            };
            let set = match self.elset_index.get(&elset.to_uppercase()) {
                Some(&s) => s,
                None => return Err(self.unknown_set(line, kw, "element set", &elset)),
            };
            let m = self.section_material(line, kw, material)?;
            let mname = self.deck.materials[m].name.clone();
            if !cohesive && self.deck.materials[m].has_damage() {
                return Err(self.invalid(
                    line,
                    kw,
                    format!("material `{mname}` has damage options (a cohesive material): use it in a *COHESIVE SECTION for COH3D8 elements, not in a *SOLID SECTION"),
                ));
            }
            self.assign_section(set, &mname, line, kw, &orientation)?;
        }
        Ok(())
    }

    /// The `*ORIENTATION` a solid section names (as the orientation is
    /// spelt).
    fn section_orientation(&self, line: usize, o: String) -> Result<String, InpError> {
        let orientations = &self.deck.orientations;
        match orientations
            .iter()
            .find(|x| x.name.eq_ignore_ascii_case(&o))
        {
            Some(x) => Ok(x.name.clone()),
            None => {
                let valid: Vec<&str> = orientations.iter().map(|x| x.name.as_str()).collect();
                Err(InpError::UnknownName {
                    file: self.file.into(),
                    line,
                    keyword: "SOLID SECTION".into(),
                    kind: "orientation",
                    name: o,
                    valid: if valid.is_empty() {
                        "(none)".into()
                    } else {
                        valid.join(", ")
                    },
                })
            }
        }
    }

    /// Index of the material a section names.
    fn section_material(&self, line: usize, kw: &str, material: String) -> Result<usize, InpError> {
        match self.material_index.get(&material.to_uppercase()) {
            Some(&m) => Ok(m),
            None => {
                let valid = if self.deck.materials.is_empty() {
                    "(none)".to_string()
                } else {
                    self.deck
                        .materials
                        .iter()
                        .map(|m| m.name.as_str())
                        .collect::<Vec<_>>()
                        .join(", ")
                };
                Err(InpError::UnknownName {
                    file: self.file.into(),
                    line,
                    keyword: kw.into(),
                    kind: "material",
                    name: material,
                    valid,
                })
            }
        }
    }

    /// Give the elements of element set `set` the material `mname` and the
    /// orientation of the section of `line`: cohesive sections hold
    /// interface elements only, solid sections solids only, and an element
    /// keeps one material.
    fn assign_section(
        &mut self,
        set: usize,
        mname: &str,
        line: usize,
        kw: &str,
        orientation: &Option<String>,
    ) -> Result<(), InpError> {
        let cohesive = kw == "COHESIVE SECTION";
        for &e in &self.elsets[set].members.clone() {
            let el = &self.elems[e];
            let shape = self.pre_blocks[el.pre_block].shape;
            if shape.is_interface() != cohesive {
                return Err(self.invalid(
                    line,
                    kw,
                    format!(
                        "element {} is a {} element; use {} for it",
                        el.label,
                        shape.name(),
                        if shape.is_interface() {
                            "*COHESIVE SECTION"
                        } else {
                            "*SOLID SECTION"
                        }
                    ),
                ));
            }
            match &el.material {
                Some((other, oline)) if *other != mname => {
                    return Err(self.invalid(
                        line,
                        kw,
                        format!(
                            "element {} already has material `{other}` from the section of line {oline}",
                            el.label
                        ),
                    ))
                }
                _ => {
                    self.elems[e].material = Some((mname.to_string(), line));
                    self.elems[e].orientation = orientation.clone();
                }
            }
        }
        Ok(())
    }

    /// The `** junta: curve` directive -> [`InpDeck::curve`]: its keys,
    /// node sets (as spelt) and components checked.
    fn resolve_curve(&mut self) -> Result<(), InpError> {
        let Some((line, raw)) = self.curve_directive.take() else {
            return Ok(());
        };
        let kw = "** junta: curve";
        let get = |key: &str, required: bool| -> Result<Option<String>, InpError> {
            match raw.iter().find(|(k, _)| k == key) {
                Some((_, v)) => Ok(Some(v.clone())),
                None if required => Err(InpError::Invalid {
                    file: self.file.into(),
                    line,
                    keyword: kw.into(),
                    message: format!("missing `{key}=`; the directive is `** junta: curve reaction_set=NSET reaction_component=x|y|z point_set=NSET point_component=x|y|z [relative_to=NSET]`"),
                }),
                None => Ok(None),
            }
        };
        let set_name = |name: String| -> Result<String, InpError> {
            match self.nset_index.get(&name.to_uppercase()) {
                Some(&i) => Ok(self.nsets[i].name.clone()),
                None => Err(self.unknown_set(line, kw, "node set", &name)),
            }
        };
        let component = |c: String| -> Result<String, InpError> {
            let l = c.to_ascii_lowercase();
            if matches!(l.as_str(), "x" | "y" | "z") {
                Ok(l)
            } else {
                Err(InpError::Invalid {
                    file: self.file.into(),
                    line,
                    keyword: kw.into(),
                    message: format!("component `{c}`: use x, y or z"),
                })
            }
        };
        let rs = get("reaction_set", true)?.unwrap_or_default();
        let rc = get("reaction_component", true)?.unwrap_or_default();
        let ps = get("point_set", true)?.unwrap_or_default();
        let pc = get("point_component", true)?.unwrap_or_default();
        let rel = get("relative_to", false)?;
        let curve = InpCurve {
            reaction_set: set_name(rs)?,
            reaction_component: component(rc)?,
            point_set: set_name(ps)?,
            point_component: component(pc)?,
            relative_to: rel.map(set_name).transpose()?,
            line,
        };
        self.deck.curve = Some(curve);
        Ok(())
    }

    /// The blocks: one per (pre-block, material, orientation), in input
    /// order, named after the pre-block or, when it splits,
    /// `<name>_<material>[_<orientation>]` (`nosection` for elements
    /// without a section, which are noted). Returns the element reference
    /// of each flat element id, the blocks and each block's orientation.
    fn build_blocks(&mut self) -> (Vec<ElementRef>, Vec<ElementBlock>, Vec<Option<usize>>) {
        let mut refs = vec![
            ElementRef {
                block: 0,
                element: 0
            };
            self.elems.len()
        ];
        let mut blocks: Vec<ElementBlock> = Vec::new();
        let mut block_orientations = Vec::new();
        for (pb_i, pb) in self.pre_blocks.iter().enumerate() {
            // one block per (material, orientation)
            let mut mats: Vec<(String, Option<String>)> = Vec::new();
            for e in self.elems.iter().filter(|e| e.pre_block == pb_i) {
                let m = e.material.as_ref().map(|m| m.0.clone()).unwrap_or_default();
                let key = (m, e.orientation.clone());
                if !mats.contains(&key) {
                    mats.push(key);
                }
            }
            let split = mats.len() > 1;
            for (m, o) in &mats {
                let bi = blocks.len();
                let name = if split {
                    let mut n =
                        format!("{}_{}", pb.name, if m.is_empty() { "nosection" } else { m });
                    if let Some(o) = o {
                        n = format!("{n}_{o}");
                    }
                    n
                } else {
                    pb.name.clone()
                };
                block_orientations.push(
                    o.as_ref()
                        .and_then(|o| self.deck.orientations.iter().position(|x| &x.name == o)),
                );
                let mut b = ElementBlock {
                    name,
                    shape: pb.shape,
                    connectivity: Vec::new(),
                    element_type: pb.element_type.into(),
                    material: m.clone(),
                };
                for (id, e) in self.elems.iter().enumerate() {
                    let em = e.material.as_ref().map(|x| x.0.as_str()).unwrap_or("");
                    if e.pre_block == pb_i && em == m && &e.orientation == o {
                        refs[id] = ElementRef {
                            block: bi,
                            element: b.len(),
                        };
                        b.connectivity.extend_from_slice(&e.conn);
                    }
                }
                blocks.push(b);
            }
            let unassigned = self
                .elems
                .iter()
                .filter(|e| e.pre_block == pb_i && e.material.is_none())
                .count();
            if unassigned > 0 {
                self.deck.notes.push(format!(
                    "{unassigned} element(s) of block `{}` have no section (material left empty)",
                    pb.name
                ));
            }
        }
        (refs, blocks, block_orientations)
    }

    /// The mesh of `blocks` with the node and element sets, the element
    /// labels and the distributed loads' elements (`refs`: the reference
    /// of each flat element id), validated; the deck that holds it.
    fn into_deck(
        mut self,
        refs: Vec<ElementRef>,
        blocks: Vec<ElementBlock>,
        block_orientations: Vec<Option<usize>>,
        dload_ids: Vec<Vec<(usize, usize)>>,
    ) -> Result<InpDeck, InpError> {
        let mut mesh = Mesh {
            nodes: self.nodes,
            node_labels: self.labels,
            blocks,
            ..Mesh::default()
        };
        for s in self.nsets {
            let mut v = s.members;
            v.sort_unstable();
            v.dedup();
            mesh.node_sets.insert(s.name, v);
        }
        for s in self.elsets {
            let mut v: Vec<ElementRef> = s.members.iter().map(|&e| refs[e]).collect();
            v.sort_unstable();
            v.dedup();
            mesh.element_sets.insert(s.name, v);
        }
        mesh.element_labels = mesh.blocks.iter().map(|b| vec![0; b.len()]).collect();
        for (id, e) in self.elems.iter().enumerate() {
            self.deck.element_labels.insert(e.label, refs[id]);
            mesh.element_labels[refs[id].block][refs[id].element] = e.label;
        }
        for (d, ids) in self.deck.dloads.iter_mut().zip(dload_ids) {
            d.elements = ids.into_iter().map(|(e, face)| (refs[e], face)).collect();
        }
        mesh.validate().map_err(|e| InpError::Invalid {
            file: self.file.into(),
            line: 0,
            keyword: "(mesh)".into(),
            message: e.to_string(),
        })?;
        self.deck.mesh = mesh;
        self.deck.block_orientations = block_orientations;
        Ok(self.deck)
    }
}

/// Parse the text of a deck; `file_name` is used in messages.
pub fn parse_inp(text: &str, file_name: &str) -> Result<InpDeck, InpError> {
    let items = lex(text);
    let mut p = Parser {
        file: file_name,
        nodes: Vec::new(),
        labels: Vec::new(),
        node_id: FxHashMap::default(),
        elems: Vec::new(),
        elem_id: FxHashMap::default(),
        pre_blocks: Vec::new(),
        pre_block_key: HashMap::new(),
        nsets: Vec::new(),
        nset_index: HashMap::new(),
        elsets: Vec::new(),
        elset_index: HashMap::new(),
        deck: InpDeck::default(),
        material_index: HashMap::new(),
        current_material: None,
        step_open: None,
        boundary_targets: Vec::new(),
        cload_targets: Vec::new(),
        membranes: Vec::new(),
        amplitude_refs: Vec::new(),
        equation_terms: Vec::new(),
        surfaces: HashMap::new(),
        dload_targets: Vec::new(),
        curve_directive: None,
    };
    p.directives(text)?;
    p.run(&items)?;
    p.finish()
}

#[cfg(test)]
mod tests {
    use super::*;
    use junta_core::topology::HEX27_NODES;

    #[test]
    fn c3d27_permutation_is_geometric() {
        // Abaqus C3D27 natural coordinates written from the face definitions:
        // 1-20 as C3D20 (= ours), 21..26 centres of faces 1..6, 27 centroid.
        let mut abq: Vec<[f64; 3]> = HEX27_NODES[..20].to_vec();
        let faces: [[usize; 4]; 6] = [
            [1, 2, 3, 4],
            [5, 8, 7, 6],
            [1, 5, 6, 2],
            [2, 6, 7, 3],
            [3, 7, 8, 4],
            [4, 8, 5, 1],
        ];
        for f in faces {
            let mut c = [0.0; 3];
            for n in f {
                for d in 0..3 {
                    c[d] += 0.25 * HEX27_NODES[n - 1][d];
                }
            }
            abq.push(c);
        }
        abq.push([0.0; 3]);
        for (i, &k) in C3D27_TO_OURS.iter().enumerate() {
            assert_eq!(
                abq[k],
                HEX27_NODES[i],
                "our node {i} <- abaqus node {}",
                k + 1
            );
        }
    }

    #[test]
    fn lexer_joins_keyword_continuations() {
        let items = lex("*element, type=C3D8,\n elset=A\n1,2\n");
        match &items[0] {
            Item::Keyword { name, params, .. } => {
                assert_eq!(name, "ELEMENT");
                assert_eq!(params[1], ("ELSET".into(), Some("A".into())));
            }
            _ => panic!(),
        }
    }

    /// `*AMPLITUDE`: pairs over several lines, SHIFTX/SHIFTY, linear
    /// between points, a jump at a repeated time, constant outside.
    #[test]
    fn amplitude_table_and_values() {
        let text = "*NODE\n1, 0, 0, 0\n*AMPLITUDE, NAME=Ramp, TIME=TOTAL TIME, SHIFTX=1, SHIFTY=0.5\n0, 0, 1, 2,\n1, 4, 3, 0\n";
        let deck = parse_inp(text, "a.inp").unwrap();
        let a = &deck.amplitudes[0];
        assert_eq!(a.name, "Ramp");
        assert!(a.total_time);
        assert_eq!(
            a.points,
            vec![(1.0, 0.5), (2.0, 2.5), (2.0, 4.5), (4.0, 0.5)]
        );
        let v = |t: f64| a.value(t);
        assert_eq!(v(0.0), 0.5); // before the first point
        assert_eq!(v(1.5), 1.5); // linear
        assert_eq!(v(2.0), 4.5); // the jump: the later value from t on
        assert_eq!(v(3.0), 2.5);
        assert_eq!(v(9.0), 0.5); // after the last point
    }
}
