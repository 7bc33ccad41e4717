//! What a run returns: how it ended and its results as typed values.

use crate::error::Error;
use crate::post::curve::{Curve, CurveRow};
use crate::post::frame::Frame;
use std::path::PathBuf;

/// How a run ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Status {
    /// The load program ran to its end.
    Completed,
    /// A stop ended the run early (an observer, `max_increments`, a deck's
    /// `INC`, separation): the run can be restarted.
    Stopped,
    /// An increment fell below the smallest size.
    Failed,
    /// The user interrupted the run.
    Interrupted,
}

/// Why a run ended: the [`Status`] with its reason. The status line of
/// `summary.json` and the command line ([`EndReason::line`]) is written
/// from it, never parsed back.
#[derive(Debug, Clone, PartialEq)]
pub enum EndReason {
    /// The load program ran to its end.
    EndOfProgram,
    /// Path following brought the load factor back to zero after its
    /// maximum, with `failed` of the model's `points` interface points
    /// failed: the structure came apart when they all have; otherwise the
    /// crack's run ended there (no further increment dissipates at a
    /// positive load: the curved beam's delamination runs out through the
    /// loaded end), and the status line says so rather than that it
    /// carries no load.
    Unloaded {
        /// Interface points failed at the last increment.
        failed: usize,
        /// Interface points of the model.
        points: usize,
    },
    /// Every interface point failed (`stop_when_separated`).
    Separated,
    /// An observer stopped the run, with its reason.
    Requested(String),
    /// The run reached the number of increments asked for this call.
    IncrementLimit,
    /// A deck's `*STEP` reached its `INC` before its end (the step's line).
    DeckIncrementLimit {
        /// `INC` of the step.
        increments: usize,
        /// Line of the `*STEP` keyword.
        line: usize,
    },
    /// `[analysis.arc_length] max_increments` reached before the end load
    /// factor.
    ArcLengthLimit(usize),
    /// An increment fell below the smallest size (the driver's message).
    Failed(String),
    /// The user interrupted the run (Ctrl-C).
    Interrupted,
}

impl EndReason {
    /// The run's status.
    pub fn status(&self) -> Status {
        match self {
            EndReason::EndOfProgram | EndReason::Unloaded { .. } => Status::Completed,
            EndReason::Failed(_) => Status::Failed,
            EndReason::Interrupted => Status::Interrupted,
            _ => Status::Stopped,
        }
    }

    /// True when a restart has nothing left to do: the program's end, or
    /// every interface point failed.
    pub fn is_final(&self) -> bool {
        matches!(self, EndReason::EndOfProgram | EndReason::Separated)
    }

    /// The status line (`completed`, `stopped: ...`, `failed: ...`,
    /// `interrupted (Ctrl-C)`).
    pub fn line(&self) -> String {
        match self {
            EndReason::EndOfProgram => "completed".into(),
            EndReason::Unloaded { failed, points } if failed >= points => "completed: the load factor fell back to zero after its maximum (every interface point has failed: the structure carries no load any more)".into(),
            EndReason::Unloaded { failed, points } => format!(
                "completed: the load factor fell back to zero after its maximum, with {failed} of {points} interface points failed: the delamination has run to its end (no further increment dissipates at a positive load); the structure has not come apart, and the branch on which it would carry load again is not traced"
            ),
            EndReason::Separated => "stopped: every interface point has failed".into(),
            EndReason::Requested(why) => format!("stopped: {why}"),
            EndReason::IncrementLimit => "stopped after the requested number of increments".into(),
            EndReason::DeckIncrementLimit { increments, line } => format!(
                "stopped: the *STEP at line {line} reached its maximum number of increments INC={increments} before its end; raise INC"
            ),
            EndReason::ArcLengthLimit(n) => format!(
                "stopped: [analysis.arc_length] max_increments = {n} reached before the end load factor"
            ),
            EndReason::Failed(e) => format!("failed: {e}"),
            EndReason::Interrupted => "interrupted (Ctrl-C)".into(),
        }
    }
}

/// What a run's `summary.json` holds, typed where a program reads it: the
/// input, the model's size, the kind and end of the run, its warnings, and
/// the sections of an incremental run's end (energies, crack, iterations,
/// driver counts, timings). The sections that are tables keyed by the
/// model's own names (reactions, interfaces, advice per interface, solver
/// report, fatigue, limit points, ...) are kept by name in
/// [`Summary::sections`], as the JSON they are written as
/// (`docs/outputs.md` describes each). `summary.json` is written from this
/// struct, and reads back into it ([`Summary::read`]): the round trip
/// gives the same value.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Summary {
    /// The input file.
    pub input: String,
    /// The model's title.
    pub title: String,
    /// The model's units, when the input states them.
    pub units: Option<String>,
    /// What ran.
    pub analysis: SummaryAnalysis,
    /// The status line of an incremental run ([`EndReason::line`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub status: Option<String>,
    /// Nodes of the model.
    pub nodes: usize,
    /// Degrees of freedom (three per node).
    pub dofs: usize,
    /// Free equations solved for.
    pub equations: usize,
    /// Elements per element type.
    pub elements: std::collections::BTreeMap<String, usize>,
    /// Converged increments (incremental runs).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub increments: Option<usize>,
    /// Warnings for the user (each also printed once by the command line).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<String>,
    /// Largest nodal displacement magnitude at the end state.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub displacement_max: Option<f64>,
    /// Energies at the last converged increment (incremental runs).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub energy: Option<EnergySummary>,
    /// The crack at the last converged increment (incremental runs whose
    /// interfaces have a crack to measure).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub crack: Option<CrackSummary>,
    /// Newton iterations of the converged increments (incremental runs).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub newton_iterations: Option<IterationSummary>,
    /// The driver's own counts, failed attempts included (incremental runs
    /// whose driver returned).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub driver: Option<DriverSummary>,
    /// Cut-backs of the driver (incremental runs whose driver returned).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cutbacks: Option<usize>,
    /// Symbolic analyses (orderings) of the linear solver (incremental runs
    /// whose driver returned).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub symbolic_analyses: Option<usize>,
    /// Wall-clock seconds per phase (absent after a failed increment).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub timings: Option<Timings>,
    /// Every other section, by its key in `summary.json`.
    #[serde(flatten)]
    pub sections: std::collections::BTreeMap<String, serde_json::Value>,
}

/// `summary.json` `energy`: energies at the last converged increment.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct EnergySummary {
    /// Work of the applied loads and prescribed displacements.
    pub external_work: f64,
    /// Fracture energy dissipated in all interfaces.
    pub dissipated_energy: f64,
    /// Energy dissipated by viscous regularisation.
    pub viscous_energy: f64,
    /// Energy dissipated by friction.
    pub frictional_dissipation: f64,
}

/// `summary.json` `crack`: the crack at the last converged increment
/// (`docs/outputs.md`, "the crack": failed points and the process zone).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct CrackSummary {
    /// Point the crack length is measured from.
    pub origin: [f64; 3],
    /// Direction the crack runs in.
    pub direction: [f64; 3],
    /// Width across which the damaged area is divided.
    pub width: f64,
    /// Damaged (failed) area divided by the width.
    pub crack_length: f64,
    /// Position of the furthest failed point along the direction.
    pub crack_front: Option<f64>,
    /// Length of the process zone (damage started, not yet failed).
    pub process_zone_length: Option<f64>,
    /// Integration points in the process zone.
    pub process_zone_points: Option<usize>,
    /// The fewest process-zone points in an increment in which the crack
    /// grew.
    pub process_zone_points_min_while_growing: Option<usize>,
    /// Fewest points the process zone should span (the warning's bound).
    pub min_process_zone_points: usize,
}

/// `summary.json` `newton_iterations`: iterations of the converged
/// increments.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct IterationSummary {
    /// Sum over increments.
    pub total: usize,
    /// Most in one increment.
    pub max_per_increment: usize,
    /// Mean per increment.
    pub mean_per_increment: f64,
    /// Per increment, in order.
    pub per_increment: Vec<usize>,
}

/// `summary.json` `driver`: counts of this call of the driver (a restarted
/// run counts from its restart), failed attempts included.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct DriverSummary {
    /// Newton iterations, failed attempts included.
    pub newton_iterations_with_failed_attempts: usize,
    /// Linear solves.
    pub linear_solves: usize,
    /// Attempts that switched to the laws' secant tangent.
    pub secant_attempts: usize,
}

/// `summary.json` `timings`: wall-clock seconds per phase.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Timings {
    /// Reading and preparing the input.
    pub read: f64,
    /// Building a scene's model (part of `read`): mesh, lay-up,
    /// interfaces, elements.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub build: Option<f64>,
    /// Peak resident memory of the process after the build, bytes.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub build_peak_bytes: Option<u64>,
    /// Choosing the linear solver.
    pub choose_solver: f64,
    /// Building the matrix pattern (linear runs).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pattern: Option<f64>,
    /// Assembly.
    pub assemble: f64,
    /// Symbolic analysis.
    pub analyze: f64,
    /// Numeric factorisation.
    pub factor: f64,
    /// Triangular solves.
    pub solve: f64,
    /// Writing the result files (linear runs).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub output: Option<f64>,
    /// The nonlinear driver, start to end (incremental runs).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub driver_total: Option<f64>,
    /// The whole run.
    pub total: f64,
}

/// `summary.json` `analysis`: what ran.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum SummaryAnalysis {
    /// One linear solve (`"linear_static"`), or a deck's linear steps.
    #[serde(rename = "linear_static")]
    LinearStatic,
    /// An incremental-iterative run (`"static"`).
    #[serde(rename = "static")]
    Static,
}

impl Summary {
    /// The summary a run built as JSON; an error names the key that does
    /// not fit.
    pub(crate) fn from_json(v: serde_json::Value) -> crate::Result<Summary> {
        serde_json::from_value(v).map_err(|e| crate::error::err!("summary.json: {e}"))
    }

    /// The summary as JSON (what `summary.json` holds).
    pub fn to_json(&self) -> serde_json::Value {
        serde_json::to_value(self).unwrap_or_default()
    }

    /// Read a run's `summary.json`.
    pub fn read(path: &std::path::Path) -> crate::Result<Summary> {
        let text = std::fs::read_to_string(path)
            .map_err(|e| crate::error::err!("cannot read {}: {e}", path.display()))?;
        serde_json::from_str(&text).map_err(|e| crate::error::err!("{}: {e}", path.display()))
    }

    /// A section by its key (`"reactions"`, `"solver"`, ...), or `None`.
    pub fn section(&self, key: &str) -> Option<&serde_json::Value> {
        self.sections.get(key)
    }
}

/// The keys of `summary.json` that are typed fields of [`Summary`].
const TYPED_KEYS: [&str; 19] = [
    "input",
    "title",
    "units",
    "analysis",
    "status",
    "nodes",
    "dofs",
    "equations",
    "elements",
    "increments",
    "warnings",
    "displacement_max",
    "energy",
    "crack",
    "newton_iterations",
    "driver",
    "cutbacks",
    "symbolic_analyses",
    "timings",
];

/// `summary["reactions"]`: an untyped section by its key; `Null` when there
/// is none.
///
/// # Panics
/// On a typed key (`summary["crack"]`): read the field (`summary.crack`),
/// which the compiler checks.
impl std::ops::Index<&str> for Summary {
    type Output = serde_json::Value;
    fn index(&self, key: &str) -> &serde_json::Value {
        static NULL: serde_json::Value = serde_json::Value::Null;
        assert!(
            !TYPED_KEYS.contains(&key),
            "summary[\"{key}\"] is a typed field of junta::Summary: read `summary.{key}`"
        );
        self.sections.get(key).unwrap_or(&NULL)
    }
}

/// What a run returns.
#[derive(Debug)]
pub struct RunResults {
    /// How the run ended.
    pub status: Status,
    /// Why ([`EndReason::status`] is `status`).
    pub reason: EndReason,
    /// The status line (`completed`, `stopped: ...`, `failed: ...`).
    pub status_line: String,
    /// The summary (what `summary.json` holds).
    pub summary: Summary,
    /// The rows of the curve of an incremental run, one per converged
    /// increment (empty for linear runs); [`RunResults::curve`] gives them
    /// as columns.
    pub rows: Vec<CurveRow>,
    /// The output directory, when the run wrote files.
    pub output: Option<PathBuf>,
    /// Notes for the user (solver choice, print tables, edited inputs).
    pub notes: Vec<String>,
    /// Warnings for the user (penalty advice, residual after the solve).
    pub warnings: Vec<String>,
    /// The error the command line exits with after a failed or
    /// interrupted run (the files are written).
    pub failure: Option<Error>,
    /// The typed fields of the end state (linear runs; incremental runs
    /// keep frames with a [`crate::FrameCollector`]).
    pub frame: Option<Frame>,
}

impl RunResults {
    /// The curve as columns (`curve.csv`'s, by name).
    pub fn curve(&self) -> Curve {
        Curve::from_rows(&self.rows)
    }

    /// The summary as text (pretty JSON).
    pub fn summary_json(&self) -> String {
        serde_json::to_string_pretty(&self.summary.to_json()).unwrap_or_default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The status line starts with the status's word, and only the ends a
    /// restart cannot continue are final.
    #[test]
    fn each_reason_has_its_status_and_line() {
        let all = [
            EndReason::EndOfProgram,
            EndReason::Unloaded {
                failed: 3,
                points: 3,
            },
            EndReason::Unloaded {
                failed: 1,
                points: 3,
            },
            EndReason::Separated,
            EndReason::Requested("enough".into()),
            EndReason::IncrementLimit,
            EndReason::DeckIncrementLimit {
                increments: 5,
                line: 12,
            },
            EndReason::ArcLengthLimit(40),
            EndReason::Failed("increment too small".into()),
            EndReason::Interrupted,
        ];
        for r in &all {
            let word = match r.status() {
                Status::Completed => "completed",
                Status::Stopped => "stopped",
                Status::Failed => "failed",
                Status::Interrupted => "interrupted",
            };
            assert!(r.line().starts_with(word), "{r:?}: {}", r.line());
        }
        let finals: Vec<_> = all.iter().filter(|r| r.is_final()).collect();
        assert_eq!(finals, [&EndReason::EndOfProgram, &EndReason::Separated]);
        assert!(EndReason::DeckIncrementLimit {
            increments: 5,
            line: 12
        }
        .line()
        .contains("line 12"));
    }
}
