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
    pub summary: serde_json::Value,
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
        serde_json::to_string_pretty(&self.summary).unwrap_or_default()
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
