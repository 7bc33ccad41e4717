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

/// What a run returns.
#[derive(Debug)]
pub struct RunResults {
    /// How the run ended.
    pub status: Status,
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
