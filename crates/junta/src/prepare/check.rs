//! `check`: what a model is, and what to change, before any solve. The
//! report is data ([`CheckReport`]); its `Display` is what `junta check`
//! prints.

use crate::error::Result;
use crate::prepare::Prepared;
use serde::Serialize;
use std::collections::BTreeMap;
use std::fmt;
use std::path::Path;

/// One element block of the model.
#[derive(Debug, Clone, Serialize)]
pub struct BlockReport {
    /// Block name.
    pub name: String,
    /// Number of elements.
    pub elements: usize,
    /// Element type key (`h20`, `inter18`, ...).
    pub element: String,
    /// Integration points per element.
    pub points_per_element: usize,
    /// Material (solids) or law (interfaces) name.
    pub material: String,
}

/// One load case of a linear deck with several steps.
#[derive(Debug, Clone, Serialize)]
pub struct StepReport {
    /// Step name.
    pub name: String,
    /// Line of its `*STEP`.
    pub line: usize,
    /// Constrained dofs.
    pub constrained: usize,
    /// Loaded dofs.
    pub loaded: usize,
}

/// What `junta check` reports: the model summary, the penalty and mesh
/// advice, the laws' warnings and the notes.
#[derive(Debug, Clone, Serialize)]
pub struct CheckReport {
    /// The input file.
    pub input: String,
    /// Title (may be empty).
    pub title: String,
    /// Units (informative).
    pub units: Option<String>,
    /// Number of nodes.
    pub nodes: usize,
    /// Number of dofs.
    pub dofs: usize,
    /// Number of free dofs (equations).
    pub equations: usize,
    /// Elements per type.
    pub elements: BTreeMap<String, usize>,
    /// The incremental analysis, described (None for a linear run).
    pub analysis: Option<String>,
    /// Load cases of a linear deck with several steps.
    pub steps: Vec<StepReport>,
    /// Element blocks.
    pub blocks: Vec<BlockReport>,
    /// Node sets with their sizes.
    pub node_sets: Vec<(String, usize)>,
    /// Element sets with their sizes.
    pub element_sets: Vec<(String, usize)>,
    /// Face sets with their sizes.
    pub face_sets: Vec<(String, usize)>,
    /// Sum of the applied nodal forces per component.
    pub total_force: [f64; 3],
    /// The linear solver chosen.
    pub solver: String,
    /// Penalty advice per interface block (as in `summary.json`).
    pub penalty_advice: serde_json::Value,
    /// Penalty advice, one line per block.
    pub penalty_lines: Vec<String>,
    /// Cohesive-zone (mesh) advice, one line per block.
    pub mesh_advice: Vec<String>,
    /// Warnings about the laws' parameters and the mesh (thin blocks of
    /// fully integrated H8 that lock in bending: [`crate::prepare::bending`]).
    pub warnings: Vec<String>,
    /// Notes from reading the input.
    pub notes: Vec<String>,
    /// The kinematics of the run (`small`, or `finite` under `nlgeom`).
    pub kinematics: junta_core::Kinematics,
    /// What the run reports about rotations and when it warns
    /// ([`crate::post::rotation::check_note`]; a rotation is known only after
    /// the solve). `None` without solid elements.
    pub rotation: Option<String>,
}

fn sizes<V>(m: &BTreeMap<String, Vec<V>>) -> Vec<(String, usize)> {
    m.iter().map(|(k, v)| (k.clone(), v.len())).collect()
}

impl CheckReport {
    /// The report of the prepared model of `input`.
    pub fn of(input: &Path, p: &Prepared) -> Result<CheckReport> {
        let m = &p.model;
        let mut total_force = [0.0; 3];
        for (i, f) in m.f_ext.iter().enumerate() {
            total_force[i % 3] += f;
        }
        let (penalty_advice, penalty_lines, _) =
            crate::output::summary::penalty_advice(m, &|b| p.thickness.get(b).copied())?;
        let (_, mesh_advice, mut warnings) = crate::output::summary::cohesive_zone_advice(m)?;
        warnings.extend(crate::prepare::bending::bending_warnings(m));
        let analysis = p.analysis.kind.is_incremental().then(|| {
            let n = &p.analysis.newton;
            format!(
                "incremental static, load program {:?}, increments (fractions of a step) initial {}, min {}, max {}",
                p.analysis.steps, n.initial_increment, n.min_increment, n.max_increment
            )
        });
        Ok(CheckReport {
            input: input.display().to_string(),
            title: p.title.clone(),
            units: p.units.clone(),
            nodes: m.mesh.nodes.len(),
            dofs: m.dofs.num_dofs(),
            equations: m.dofs.num_free,
            elements: crate::output::summary::element_counts(m),
            analysis,
            steps: p
                .deck_steps
                .iter()
                .map(|st| StepReport {
                    name: st.name.clone(),
                    line: st.line,
                    constrained: st.constraints.len(),
                    loaded: st.f_ext.iter().filter(|f| **f != 0.0).count(),
                })
                .collect(),
            blocks: m
                .mesh
                .blocks
                .iter()
                .zip(&m.elements)
                .map(|(b, el)| BlockReport {
                    name: b.name.clone(),
                    elements: b.len(),
                    element: el.key().to_string(),
                    points_per_element: el.num_points(),
                    material: b.material.clone(),
                })
                .collect(),
            node_sets: sizes(&m.mesh.node_sets),
            element_sets: sizes(&m.mesh.element_sets),
            face_sets: sizes(&m.mesh.face_sets),
            total_force,
            solver: p.solver.key().to_string(),
            penalty_advice,
            penalty_lines,
            mesh_advice,
            warnings,
            notes: p.notes.clone(),
            kinematics: crate::post::rotation::model_kinematics(m),
            rotation: crate::post::rotation::check_note(m, crate::post::rotation::is_deck(input)),
        })
    }
}

/// How many set names per kind `junta check` shows without `--verbose`.
pub const SETS_SHOWN: usize = 4;

/// The report with every set listed (`junta check --verbose`); the plain
/// `Display` of [`CheckReport`] summarises the sets (count per kind and
/// the first [`SETS_SHOWN`] names).
pub struct Verbose<'a>(pub &'a CheckReport);

impl fmt::Display for Verbose<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        self.0.write(f, true)
    }
}

impl CheckReport {
    /// The report listing every node, element and face set.
    pub fn verbose(&self) -> Verbose<'_> {
        Verbose(self)
    }

    /// One line per kind of set: all of them (`all`), else the count and
    /// the first [`SETS_SHOWN`] names.
    fn write_sets(&self, f: &mut fmt::Formatter<'_>, all: bool) -> fmt::Result {
        for (kind, v) in [
            ("node", &self.node_sets),
            ("element", &self.element_sets),
            ("face", &self.face_sets),
        ] {
            if v.is_empty() {
                continue;
            }
            let shown = if all {
                v.len()
            } else {
                v.len().min(SETS_SHOWN)
            };
            let s: Vec<String> = v[..shown]
                .iter()
                .map(|(k, n)| format!("{k} ({n})"))
                .collect();
            if shown == v.len() {
                writeln!(f, "  {kind} sets: {}", s.join(", "))?;
            } else {
                writeln!(
                    f,
                    "  {kind} sets: {} ({}, ... and {} more; --verbose lists them all)",
                    v.len(),
                    s.join(", "),
                    v.len() - shown
                )?;
            }
        }
        Ok(())
    }
}

impl fmt::Display for CheckReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        self.write(f, false)
    }
}

impl CheckReport {
    fn write(&self, f: &mut fmt::Formatter<'_>, all_sets: bool) -> fmt::Result {
        writeln!(f, "{}: valid", self.input)?;
        if !self.title.is_empty() {
            writeln!(f, "  title: {}", self.title)?;
        }
        if let Some(u) = &self.units {
            writeln!(f, "  units: {u}")?;
        }
        writeln!(
            f,
            "  nodes: {}, dofs: {}, equations: {} ({} constrained)",
            self.nodes,
            self.dofs,
            self.equations,
            self.dofs - self.equations
        )?;
        for (k, n) in &self.elements {
            writeln!(f, "  elements {k}: {n}")?;
        }
        if let Some(a) = &self.analysis {
            writeln!(f, "  analysis: {a}")?;
        }
        for (k, st) in self.steps.iter().enumerate() {
            writeln!(
                f,
                "  step {} `{}` (line {}): {} constrained dofs, {} loaded dofs",
                k + 1,
                st.name,
                st.line,
                st.constrained,
                st.loaded
            )?;
        }
        for b in &self.blocks {
            writeln!(
                f,
                "  block `{}`: {} x {} ({} integration points each), material `{}`",
                b.name, b.elements, b.element, b.points_per_element, b.material
            )?;
        }
        self.write_sets(f, all_sets)?;
        writeln!(f, "  total applied force: {:?}", self.total_force)?;
        writeln!(f, "  solver: {}", self.solver)?;
        for l in &self.penalty_lines {
            writeln!(f, "  penalty advisor: {l}")?;
        }
        for l in &self.mesh_advice {
            writeln!(f, "  mesh advice: {l}")?;
        }
        for w in &self.warnings {
            writeln!(f, "  warning: {w}")?;
        }
        for n in &self.notes {
            writeln!(f, "  note: {n}")?;
        }
        if let Some(r) = &self.rotation {
            writeln!(f, "  rotation: {r}")?;
        }
        Ok(())
    }
}
