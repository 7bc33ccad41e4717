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
//! `*SOLID SECTION, ELSET=, MATERIAL=` (or `COMPOSITE` with a data line per
//! ply, [`InpComposite`]), `*COHESIVE SECTION, ELSET=,
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
//! | CPE3, CPE4, CPE4I, CPE6, CPE8, CPE8R | PlaneTri3 / PlaneQuad4 / PlaneTri6 / PlaneQuad8 | `cpe3` ... `cpe8r` (`cpe4i`: incompatible modes) | none; thickness: the `*SOLID SECTION` data line (default 1) |
//! | CPS3 ... CPS8R | the same | `cps3` ... `cps8r` | as CPE |
//! | CAX3 ... CAX8R, CAX4I | the same | `cax3` ... `cax8r` (`cax4i`: incompatible modes) | none; the full ring (a thickness on the data line has no effect, as in CalculiX) |
//! | COH2D4, COHAX4 | LineInter4 | `line_inter4` | 2-1-3-4: Abaqus's is counter-clockwise (the top on the left of 1-2), ours has the top on the right of the bottom line; out-of-plane thickness: the `*COHESIVE SECTION` data line's second field (default 1); axisymmetric in a model of CAX elements |
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

mod deck;
mod keywords;
mod lex;
mod materials;
mod mesh;
mod parse;
mod resolve;
mod steps;

pub use deck::*;
pub use keywords::{markdown_rows, supported_keywords, Keyword, KEYWORDS};
pub use lex::{expand_includes, ExpandedDeck, MAX_EXPANDED_BYTES, MAX_INCLUDE_DEPTH};
use lex::{lex, norm_key, Item};

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

/// Element types the reader understands (for messages).
pub const SUPPORTED_ELEMENT_TYPES: &str =
    "C3D8, C3D8I, C3D20, C3D20R, C3D27, C3D6, C3D15, COH3D8, COH3D6, CPE3, CPE4, CPE4I, CPE6, CPE8, CPE8R, CPS3, CPS4, CPS4I, CPS6, CPS8, CPS8R, CAX3, CAX4, CAX4I, CAX6, CAX8, CAX8R, COH2D4, COHAX4";

/// Read a deck from a file, with its `*INCLUDE, INPUT=` files in place
/// ([`expand_includes`]); an error names the file and line it comes from,
/// included files too.
pub fn read_inp(path: impl AsRef<Path>) -> Result<InpDeck, InpError> {
    let expanded = expand_includes(path.as_ref())?;
    let main = expanded.files[0].clone();
    parse_inp(&expanded.text, &main).map_err(|e| expanded.relocate(e))
}

// ---------------------------------------------------------------- the parser

struct Elem {
    pre_block: usize,
    conn: Vec<usize>,
    label: usize,
    material: Option<(String, usize)>,
    /// `*SOLID SECTION, ORIENTATION=` name (upper case).
    orientation: Option<String>,
    /// Out-of-plane thickness of a plane element (`*SOLID SECTION` data
    /// line) or a 2D cohesive element (`*COHESIVE SECTION`, second field).
    thickness: Option<f64>,
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

pub(super) fn element_kind(t: &str) -> Option<(CellShape, &'static str)> {
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
        "COH2D4" | "COHAX4" => Some((CellShape::LineInter4, "line_inter4")),
        _ => plane_kind(t),
    }
}

/// The plane elements CPE*, CPS*, CAX* (3, 4, 6, 8 nodes, 8R reduced):
/// the registry keys of [`junta_elements::plane`] are their lower-case
/// names.
fn plane_kind(t: &str) -> Option<(CellShape, &'static str)> {
    const KEYS: [(&str, CellShape, &str); 18] = [
        ("CPE3", CellShape::PlaneTri3, "cpe3"),
        ("CPE4", CellShape::PlaneQuad4, "cpe4"),
        ("CPE4I", CellShape::PlaneQuad4, "cpe4i"),
        ("CPS4I", CellShape::PlaneQuad4, "cps4i"),
        ("CPE6", CellShape::PlaneTri6, "cpe6"),
        ("CPE8", CellShape::PlaneQuad8, "cpe8"),
        ("CPE8R", CellShape::PlaneQuad8, "cpe8r"),
        ("CPS3", CellShape::PlaneTri3, "cps3"),
        ("CPS4", CellShape::PlaneQuad4, "cps4"),
        ("CPS6", CellShape::PlaneTri6, "cps6"),
        ("CPS8", CellShape::PlaneQuad8, "cps8"),
        ("CPS8R", CellShape::PlaneQuad8, "cps8r"),
        ("CAX3", CellShape::PlaneTri3, "cax3"),
        ("CAX4", CellShape::PlaneQuad4, "cax4"),
        ("CAX4I", CellShape::PlaneQuad4, "cax4i"),
        ("CAX6", CellShape::PlaneTri6, "cax6"),
        ("CAX8", CellShape::PlaneQuad8, "cax8"),
        ("CAX8R", CellShape::PlaneQuad8, "cax8r"),
    ];
    match KEYS.iter().find(|k| k.0 == t) {
        Some(&(_, shape, key)) => Some((shape, key)),
        None => None,
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
