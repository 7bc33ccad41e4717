//! What a run returns: how it ended and its results as typed values.

use crate::error::Error;
use crate::post::curve::{Curve, CurveRow};
use crate::post::frame::Frame;
use std::path::PathBuf;

/// How a run ended.
#[derive(Debug, Clone, PartialEq)]
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
    /// maximum: the structure carries no load any more.
    Unloaded,
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
            EndReason::EndOfProgram | EndReason::Unloaded => Status::Completed,
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
            EndReason::Unloaded => "completed: the load factor fell back to zero after its maximum (the structure carries no load any more)".into(),
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

/// What a run's `summary.json` holds, typed where every run has it: the
/// input, the model's size, the kind and end of the run, its warnings.
/// The sections that differ by kind of run (reactions, solver, timings,
/// energies, crack, fatigue, advice, ...) are kept by name in
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
    /// Every other section, by its key in `summary.json`.
    #[serde(flatten)]
    pub sections: std::collections::BTreeMap<String, serde_json::Value>,
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

/// `summary["reactions"]`: a section by its key; `Null` when there is none
/// (the typed fields are read as fields).
impl std::ops::Index<&str> for Summary {
    type Output = serde_json::Value;
    fn index(&self, key: &str) -> &serde_json::Value {
        static NULL: serde_json::Value = serde_json::Value::Null;
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
    /// The curve of an incremental run, as columns (empty for linear runs).
    pub curve: Curve,
    /// The rows of the curve.
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
            EndReason::Unloaded,
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
