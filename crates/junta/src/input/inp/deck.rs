//! What a deck reads into: the [`InpDeck`] and its parts, and the reader's
//! errors ([`InpError`]).

use super::*;

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
        /// The supported keywords ([`supported_keywords`]).
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
    /// Material name as written in `*MATERIAL` (empty for a composite
    /// section, whose plies name theirs).
    pub material: String,
    /// `ORIENTATION=` name as written.
    pub orientation: Option<String>,
    /// The data line's first value: the out-of-plane thickness of plane
    /// strain and plane stress elements (ignored by 3D and axisymmetric
    /// ones).
    pub thickness: Option<f64>,
    /// `COMPOSITE`: the plies.
    pub composite: Option<InpComposite>,
    /// Line of the keyword.
    pub line: usize,
}

impl InpSolidSection {
    /// The material name its elements' block carries: the material's, or
    /// `composite_<ELSET>` for a composite section.
    pub fn block_material(&self) -> String {
        match self.composite {
            Some(_) => format!("composite_{}", self.elset),
            None => self.material.clone(),
        }
    }
}

/// `*SOLID SECTION, COMPOSITE [, ORIENTATION=] [, STACK DIRECTION=1|2|3]
/// [, LAYUP=]`: the plies, bottom (negative stack direction) to top, one
/// data line each.
#[derive(Debug, Clone, PartialEq)]
pub struct InpComposite {
    /// `STACK DIRECTION=` (1, 2 or 3: the element's natural direction
    /// the plies stack along; default 3).
    pub stack_direction: usize,
    /// `LAYUP=`, as written (a name, unused).
    pub layup: Option<String>,
    /// The section's `ORIENTATION=`: its index in [`InpDeck::orientations`]
    /// (resolved when the deck is read).
    pub orientation: Option<usize>,
    /// The plies, bottom to top.
    pub plies: Vec<InpPly>,
}

/// A ply of a composite solid section: `thickness, number of integration
/// points, material, orientation, ply name`.
#[derive(Debug, Clone, PartialEq)]
pub struct InpPly {
    /// Relative thickness (> 0; normalised over the plies).
    pub thickness: f64,
    /// Integration points through the ply (default 3; 1 to 5).
    pub points: usize,
    /// Material name, as spelt in its `*MATERIAL` (resolved when the deck
    /// is read).
    pub material: String,
    /// The ply's axes.
    pub axes: InpPlyAxes,
    /// Ply name, if given.
    pub name: Option<String>,
    /// Line of the data line.
    pub line: usize,
}

/// The axes of a ply of a composite section.
#[derive(Debug, Clone, PartialEq)]
pub enum InpPlyAxes {
    /// No orientation field: the section's `ORIENTATION=`, else the global
    /// axes.
    Section,
    /// An `*ORIENTATION`.
    Named {
        /// As spelt in the `*ORIENTATION` (once the deck is read).
        name: String,
        /// Its index in [`InpDeck::orientations`] (resolved when the deck
        /// is read).
        index: usize,
    },
    /// An angle in degrees about axis 3 of the section's orientation (the
    /// global z without one), positive from its axis 1 towards its axis 2.
    Angle(f64),
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
    /// Out-of-plane thickness of 2D cohesive elements (COH2D4): the data
    /// line's second value, if given.
    pub out_of_plane: Option<f64>,
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
    /// its index in `orientations`, from `*SOLID SECTION, ORIENTATION=`
    /// (`None` for a composite section's block, whose plies carry theirs).
    pub block_orientations: Vec<Option<usize>>,
    /// Composite section of each mesh block (index-aligned with
    /// `mesh.blocks`): its index in `solid_sections`.
    pub block_composites: Vec<Option<usize>>,
    /// Out-of-plane thickness of each mesh block's elements (index-aligned
    /// with `mesh.blocks`) from its section: plane elements and 2D
    /// cohesive elements (blocks are split by thickness).
    pub block_thickness: Vec<Option<f64>>,
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
