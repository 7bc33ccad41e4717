//! Observers: what a run reports to after each converged increment.
//!
//! An incremental run calls [`Observer::on_start`] once, then
//! [`Observer::on_increment`] after every converged increment, in the order
//! the observers were given, then [`Observer::on_end`] once, whatever ended
//! the run (the end of the load program, a stop, a failed increment). Any
//! observer can end the run by returning [`Flow::Stop`] or
//! [`Flow::Interrupt`]: the driver stops cleanly after that increment, so
//! the files the writers left are a valid restart point.
//!
//! The command line's progress bar, the Python callback and
//! [`FrameCollector`] (which keeps typed fields in memory) are observers.
//! They read the run's [`RunLog`] (the rows of the curve so far, the
//! frames written, the first failure) but cannot change it: only the run
//! and its standard writers of `curve.csv`, the VTU frames,
//! `checkpoint.json` and `summary.json` (`crate::output::writers`, a
//! crate-private [`Writer`] trait) write to it, in a fixed order (frames
//! before the checkpoint that lists them), and always before the caller's
//! observers. So an observer sees the same log whatever its place in the
//! list.

use crate::error::Result;
use crate::post::curve::CurveRow;
use crate::post::fields::InterfaceResults;
use crate::post::frame::Frame;
use crate::run::checkpoint::FirstFailure;
use junta_core::element::StepInfo;
use junta_core::state::StateStore;
use junta_core::Model;
use junta_solvers::newton::{Checkpoint, IncrementReport, IncrementView};

/// What an observer tells the run after an increment.
#[derive(Debug, Clone, PartialEq)]
pub enum Flow {
    /// Go on.
    Continue,
    /// End the run after this increment; the reason is the run's status
    /// (`stopped: REASON`).
    Stop(String),
    /// The user interrupted the run (Ctrl-C): it ends after this increment
    /// with the status `interrupted (Ctrl-C)`.
    Interrupt,
}

/// Why an observer ended the run.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum Stop {
    Requested(String),
    Interrupted,
}

impl Flow {
    pub(crate) fn stop(self) -> Option<Stop> {
        match self {
            Flow::Continue => None,
            Flow::Stop(why) => Some(Stop::Requested(why)),
            Flow::Interrupt => Some(Stop::Interrupted),
        }
    }
}

/// What an observer learns of the run before its first increment: a
/// read-only view, not the prepared model.
#[derive(Debug, Clone, Copy)]
pub struct RunInfo<'a> {
    /// The input file (scene or deck).
    pub input: &'a std::path::Path,
    /// The model's title (empty when it has none).
    pub title: &'a str,
    /// The model.
    pub model: &'a Model,
    /// Load factor at the end of each step of the program.
    pub steps: &'a [f64],
    /// Registry key of the linear solver.
    pub solver: &'a str,
    /// Increment the run starts from (0, or a restart's checkpoint).
    pub start_increment: usize,
}

/// A phase of a run, for progress displays ([`Observer::on_phase`]); its
/// `Display` is the line a progress bar shows.
#[derive(Debug, Clone, PartialEq)]
pub enum Phase {
    /// One linear solve.
    Solving {
        /// Equations.
        equations: usize,
        /// Elements.
        elements: usize,
        /// Registry key of the linear solver.
        solver: String,
    },
    /// A deck's linear steps `first..=last` (1-based) of `total`, on one
    /// factorisation.
    SolvingSteps {
        /// First step (1-based).
        first: usize,
        /// Last step (1-based).
        last: usize,
        /// Steps of the deck.
        total: usize,
        /// Equations.
        equations: usize,
    },
    /// Writing the result files.
    WritingResults,
}

impl std::fmt::Display for Phase {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Phase::Solving {
                equations,
                elements,
                solver,
            } => write!(
                f,
                "solving {equations} equations ({elements} elements) with {solver}"
            ),
            Phase::SolvingSteps {
                first,
                last,
                total,
                equations,
            } => write!(
                f,
                "solving steps {first}..{last} of {total} ({equations} equations, one factorisation)"
            ),
            Phase::WritingResults => f.write_str("writing results"),
        }
    }
}

/// What the run keeps across increments, shared by its observers.
#[derive(Debug, Clone, Default)]
pub struct RunLog {
    /// One row per converged increment (with a restarted run's past rows).
    pub rows: Vec<CurveRow>,
    /// Frames written so far `(load factor, file relative to the output
    /// directory)`.
    pub frames: Vec<(f64, String)>,
    /// When the first interface point failed.
    pub first_failure: Option<FirstFailure>,
    /// Changes of control at limit points (`control = "auto"`).
    pub path_switches: Vec<junta_solvers::path_switch::PathSwitch>,
    /// Every interface point failed and none is still being released.
    pub separated: bool,
    /// Increment the run started from (0, or a restart's checkpoint).
    pub start_increment: usize,
    /// The last converged increment.
    pub last_increment: usize,
    /// External forces of the last converged increment (the reactions on
    /// the prescribed dofs plus the applied loads, per dof): the left end
    /// of the next increment's trapezoid for `external_work`, kept in
    /// `checkpoint.json` for a restart.
    pub external_force: Vec<f64>,
    /// The `[[ply_failure]]` criteria's last increment and first failure.
    pub ply_failure: crate::post::ply_failure_history::PlyFailureHistory,
}

/// A converged increment, as the observers see it.
pub struct Increment<'a> {
    /// The model.
    pub model: &'a Model,
    /// The driver's report (load factor, iterations, cut-backs, timings).
    pub report: &'a IncrementReport,
    /// The increment's curve row (also the last row of the log).
    pub row: &'a CurveRow,
    /// Full displacement vector, node-major (`3 * node + component`).
    pub u: &'a [f64],
    /// Full residual `f_int - lambda f_ext` (reactions on constrained dofs).
    pub residual: &'a [f64],
    /// Integration-point state.
    pub state: &'a StateStore,
    /// Interface results per interface block (traction, jump, law outputs).
    pub interfaces: &'a [InterfaceResults],
    /// The increment as the elements saw it.
    pub step: StepInfo,
    /// The `[[ply_failure]]` criteria at this increment (empty without
    /// them).
    pub ply_failure: &'a [crate::post::ply_failure::PlyFailureResult],
    pub(crate) view: &'a IncrementView<'a>,
}

impl Increment<'_> {
    /// A restart point after this increment.
    pub fn checkpoint(&self) -> Checkpoint {
        self.view.checkpoint()
    }

    /// The typed fields of this increment (allocates: call it for the
    /// increments you keep).
    pub fn frame(&self) -> Result<Frame> {
        Frame::at(self.model, self.u, self.state, self.interfaces, self.step)
    }
}

/// The end of a run, as the observers see it.
pub struct RunEnd<'a> {
    /// The model.
    pub model: &'a Model,
    /// Displacement the run ends on (the last converged increment), if any
    /// increment converged.
    pub u: Option<&'a [f64]>,
    /// State the run ends on.
    pub state: Option<&'a StateStore>,
    /// Residual the run ends on (None after a failed increment).
    pub residual: Option<&'a [f64]>,
    /// Interface results at the end state.
    pub interfaces: &'a [InterfaceResults],
    /// The last converged increment.
    pub step: StepInfo,
    /// Whether this call (not only a restarted run's past) converged an
    /// increment.
    pub converged_here: bool,
    /// The status line (`completed`, `stopped: ...`, `failed: ...`).
    pub status: &'a str,
    /// Why the run ended (the status line is written from it).
    pub reason: &'a crate::run::results::EndReason,
    /// The summary (what `summary.json` holds).
    pub summary: &'a crate::run::results::Summary,
}

/// Something a run reports to. Every method but `on_increment` has a
/// default that does nothing. `Send`: the run calls it from a thread of
/// rayon's pool (`Simulation::run`).
pub trait Observer: Send {
    /// Before the first increment (after a restart: the log holds the past
    /// rows and frames).
    fn on_start(&mut self, _run: &RunInfo<'_>, _log: &RunLog) -> Result<()> {
        Ok(())
    }
    /// After each converged increment (the log holds its row and frame).
    /// An error ends the run (the increments before stay on disk).
    fn on_increment(&mut self, inc: &Increment<'_>, log: &RunLog) -> Result<Flow>;
    /// Once, at the end, whatever ended the run.
    fn on_end(&mut self, _end: &RunEnd<'_>, _log: &RunLog) -> Result<()> {
        Ok(())
    }
    /// A phase of a run begins: for progress displays.
    fn on_phase(&mut self, _phase: &Phase) {}
}

/// The run's own reporters, which keep the [`RunLog`] (the standard file
/// writers): the same calls as [`Observer`], with the log writable. The
/// run calls them in their fixed order, then the observers.
pub(crate) trait Writer {
    fn on_start(&mut self, _run: &RunInfo<'_>, _log: &RunLog) -> Result<()> {
        Ok(())
    }
    fn on_increment(&mut self, inc: &Increment<'_>, log: &mut RunLog) -> Result<Flow>;
    fn on_end(&mut self, _end: &RunEnd<'_>, _log: &mut RunLog) -> Result<()> {
        Ok(())
    }
}

/// A caller's observer in the run's list of reporters, with the log
/// read-only.
pub(crate) struct ReadOnly<'o>(pub &'o mut dyn Observer);

impl Writer for ReadOnly<'_> {
    fn on_start(&mut self, run: &RunInfo<'_>, log: &RunLog) -> Result<()> {
        self.0.on_start(run, log)
    }
    fn on_increment(&mut self, inc: &Increment<'_>, log: &mut RunLog) -> Result<Flow> {
        self.0.on_increment(inc, log)
    }
    fn on_end(&mut self, end: &RunEnd<'_>, log: &mut RunLog) -> Result<()> {
        self.0.on_end(end, log)
    }
}

/// A closure as an observer: `|inc| Flow::Continue`.
pub struct FnObserver<F>(pub F);

impl<F: FnMut(&Increment<'_>) -> Flow + Send> Observer for FnObserver<F> {
    fn on_increment(&mut self, inc: &Increment<'_>, _log: &RunLog) -> Result<Flow> {
        Ok((self.0)(inc))
    }
}

/// Keeps the typed fields of every `every`-th increment, and of the last
/// one, in memory.
#[derive(Debug, Default)]
pub struct FrameCollector {
    /// Keep one increment in `every` (0 or 1: all).
    pub every: usize,
    /// The frames kept, in increment order.
    pub frames: Vec<Frame>,
}

impl FrameCollector {
    /// Keep every `every`-th increment.
    pub fn every(every: usize) -> Self {
        FrameCollector {
            every,
            frames: Vec::new(),
        }
    }
}

impl Observer for FrameCollector {
    fn on_increment(&mut self, inc: &Increment<'_>, _log: &RunLog) -> Result<Flow> {
        if inc.step.increment.is_multiple_of(self.every.max(1)) {
            self.frames.push(inc.frame()?);
        }
        Ok(Flow::Continue)
    }
    fn on_end(&mut self, end: &RunEnd<'_>, _log: &RunLog) -> Result<()> {
        let kept = self.frames.last().map(|f| f.increment);
        if let (Some(u), Some(state)) = (end.u, end.state) {
            if end.converged_here && kept != Some(end.step.increment) {
                self.frames
                    .push(Frame::at(end.model, u, state, end.interfaces, end.step)?);
            }
        }
        Ok(())
    }
}
