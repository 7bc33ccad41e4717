//! Nonlinear static analysis: proportional load program, incremental
//! Newton-Raphson with line search, adaptive increments with cut-back, the
//! paper's small-increment rule, and checkpoint / restart.
//!
//! # Load program
//!
//! Everything the model applies is scaled by one load factor `lambda`: the
//! external forces `model.f_ext` and the prescribed displacements
//! `model.dofs.prescribed`. A program is a list of step ends
//! `[lambda_1, lambda_2, ...]`; step `s` goes from `lambda_{s-1}` (0 for the
//! first step) to `lambda_s`, so `[1.0]` loads, `[1.0, 0.0]` loads and
//! unloads. Force control and displacement control are the same thing here:
//! it depends on what the model prescribes.
//!
//! A model with a temperature field ([`Model::temperature`]) has a second,
//! non-proportional load: the temperature factor `theta` of
//! [`Model::temperature_steps`] goes linearly over each step like `lambda`
//! (from the previous step's end value), so a step with `lambda` held and
//! `theta` moving is a thermal step (a cool-down before the mechanical
//! load: the program `[0, lambda_1, ...]` with `theta = [1]`). Both are
//! functions of the cursor (step, fraction), so checkpoints need nothing
//! more. The force scale of the convergence test includes the thermal
//! force `|theta f_th,f|` (`f_th` the internal force of the temperature
//! field at zero displacement), so that a free body expanding under a
//! temperature change, with no load and no reaction, has a scale.
//!
//! Increment sizes are *fractions of the step* (`t` in `[0, 1]`,
//! `lambda = lambda_start + t (lambda_end - lambda_start)`); the last
//! increment of a step is shortened to end exactly on `lambda_end`.
//!
//! # Equations
//!
//! With `u` the full displacement vector (constrained dofs hold
//! `lambda * prescribed`), the residual is
//!
//! ```text
//! r(u, lambda) = f_int(u) - lambda f_ext        (all dofs)
//! ```
//!
//! Its free part must vanish; on constrained dofs it is the reaction.
//! With linear equations (`*EQUATION`, see [`junta_core::dof`]) the free
//! part is the reduced residual `r_f = T^T r` (each dependent's residual
//! distributed onto the free dofs of its equation), the tangent is the
//! reduced `T^T K T` the assembler builds, and every trial state sets the
//! dependents from their terms; the raw residual on a dependent dof is the
//! force its equation carries.
//! Each increment `lambda_n -> lambda_{n+1}` starts from the converged
//! free displacements of the previous increment with the constrained dofs
//! moved to `lambda_{n+1} * prescribed` (the prescribed jump enters the first
//! residual through `f_int`, exactly as in [`crate::linear_static`]). Full
//! Newton then iterates with the consistent tangent `K = d f_int / d u`
//! assembled by the elements:
//!
//! ```text
//! K_ff(u_i) du = -r_f(u_i),    u_{i+1} = u_i + s du
//! ```
//!
//! where the step length `s` comes from a backtracking line search on the
//! residual norm: `s = 1, 1/2, 1/4, ...` (at most `max_line_search`
//! halvings), the first `s` with `|r_f(u_i + s du)| <= (1 - 1e-4 s) |r_f(u_i)|`
//! is taken; if none passes, the `s` with the smallest residual is taken.
//!
//! # Convergence
//!
//! An increment has converged after iteration `i >= 1` when both hold:
//!
//! ```text
//! force:   |r_f(u_i)| / max(|lambda f_ext,f|, |reactions|, floor) <= tol_force
//! energy:  |s du_i . r_f(u_i)| / |s du_1 . r_f(u_0)|             <= tol_energy
//! ```
//!
//! The energy of an iteration is the work of the remaining out-of-balance
//! force on the last correction; it is measured relative to the first
//! iteration's work of the increment. `floor` = `force_floor` times the
//! largest force scale `max(|lambda f_ext,f|, |reactions|)` met at a
//! converged increment of the run so far: it keeps the criterion meaningful
//! when the current load is zero (e.g. at the end of an unloading step).
//! An increment that changes nothing (zero load-factor increment, or any
//! increment of a model whose load pattern is zero, e.g. after the thermal
//! step of a temperature-only program) may converge with zero iterations;
//! a model without free dofs always does.
//!
//! # Cut-back
//!
//! An attempt fails on: the iteration limit, a non-finite residual or
//! correction, a residual growing past `divergence_ratio` times the first
//! one of the attempt, a linear-solver error (e.g. a tangent that is not
//! positive definite past a limit point), or an element error (e.g. a law
//! failure). The driver then restores the trial state
//! ([`StateStore::restore`]), `u` and `lambda` to the last converged
//! increment, multiplies the increment by `cutback` and retries. Below
//! `min_increment` it stops with [`NonlinearError::IncrementTooSmall`];
//! every converged increment has been reported to the observer by then.
//!
//! Before every assembly the trial state is reset to the committed one, so
//! the trial state is always the result of exactly one evaluation from the
//! last converged state, whatever an element leaves untouched.
//!
//! # Increment size
//!
//! The first increment of each step is `initial_increment` (fraction of the
//! step). After an increment that converged without cut-back in at most
//! `growth_iterations` iterations, the next one is `growth` times larger
//! (capped at `max_increment`); otherwise it keeps its size. *Release rule*
//! (paper, section 4): after every converged increment the driver asks
//! every element [`Element::wants_small_increments`] with its committed
//! state; while any says yes, every increment is `small_increment`
//! (constant). When none does any more, the adaptive rule resumes from the
//! small size.
//!
//! # Observer, checkpoint, restart
//!
//! After each converged increment the driver commits the state
//! ([`StateStore::commit`]), decides the next increment's size, and calls
//! the observer with an [`IncrementView`]: the [`IncrementReport`], the full
//! `u`, the full residual `f_int - lambda f_ext` (reactions on constrained
//! dofs), the state, and [`IncrementView::checkpoint`]. The observer returns
//! [`Control::Stop`] to end the run cleanly. A [`Checkpoint`] holds
//! everything the driver's future depends on (step, fraction of the step,
//! lambda, increment counter, next increment size, small-increment flag,
//! force-scale floor, `u`, committed state), so a run restarted from it
//! computes exactly the increments of an uninterrupted run.
//!
//! The symbolic analysis of the linear solver is done once per run (on the
//! first tangent), then `factorize` once per Newton iteration. Work vectors
//! are allocated once per run.
//!
//! [`Element::wants_small_increments`]: junta_core::Element::wants_small_increments

use crate::linear_static::Timings;
use junta_core::assembly::Assembler;
use junta_core::dof::CONSTRAINED;
use junta_core::element::StepInfo;
use junta_core::state::StateStore;
use junta_core::{CoreError, LinearSolver, Model, SolverError, SymmetricCsc};
use serde::{Deserialize, Serialize};
use std::time::Instant;
use thiserror::Error;

/// Settings of the incremental-iterative driver. Increment sizes are
/// fractions of the current step's load-factor range.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct NewtonSettings {
    /// First increment of each step, as a fraction of the step. Default 0.1.
    pub initial_increment: f64,
    /// Smallest increment (fraction of the step) before giving up with
    /// [`NonlinearError::IncrementTooSmall`]. Default 1e-6.
    pub min_increment: f64,
    /// Largest increment (fraction of the step). Default 0.25.
    pub max_increment: f64,
    /// Newton iterations allowed per increment attempt. Default 25.
    pub max_iterations: usize,
    /// Relative force tolerance:
    /// `|r_f| / max(|lambda f_ext,f|, |reactions|, floor)`. Default 1e-6.
    pub tol_force: f64,
    /// Relative energy tolerance: `|du_i . r_i| / |du_1 . r_0|`.
    /// Default 1e-12.
    pub tol_energy: f64,
    /// Backtracking line search on the residual norm. Default true.
    pub line_search: bool,
    /// When an iteration with the consistent tangent does not reduce the
    /// residual, use the laws' secant tangent for the rest of the attempt
    /// (see [`junta_core::element::StepInfo::secant`]). Default true.
    pub secant_fallback: bool,
    /// Maximum halvings of the step length in the line search. Default 5.
    pub max_line_search: usize,
    /// Growth factor of the increment after a fast increment. Default 1.5.
    pub growth: f64,
    /// An increment converged in at most this many iterations (and without
    /// cut-back) lets the next one grow. Default 4.
    pub growth_iterations: usize,
    /// Factor applied to the increment on a cut-back. Default 0.5.
    pub cutback: f64,
    /// Constant increment (fraction of the step) used while any element
    /// wants small increments (paper, section 4: a point is being released).
    /// `None` (default) means `min(initial_increment, 0.01)`.
    pub small_increment: Option<f64>,
    /// An attempt whose residual norm exceeds this many times its first
    /// residual norm is diverging and is cut back. Default 1e6.
    pub divergence_ratio: f64,
    /// Floor of the force scale of the force criterion, as a fraction of the
    /// largest force scale met at a converged increment. Default 1e-3.
    pub force_floor: f64,
}

impl Default for NewtonSettings {
    fn default() -> Self {
        NewtonSettings {
            initial_increment: 0.1,
            min_increment: 1e-6,
            max_increment: 0.25,
            max_iterations: 25,
            tol_force: 1e-6,
            tol_energy: 1e-12,
            line_search: true,
            secant_fallback: true,
            max_line_search: 5,
            growth: 1.5,
            growth_iterations: 4,
            cutback: 0.5,
            small_increment: None,
            divergence_ratio: 1e6,
            force_floor: 1e-3,
        }
    }
}

impl NewtonSettings {
    /// The small increment in use: `small_increment` or
    /// `min(initial_increment, 0.01)`.
    pub fn small_increment(&self) -> f64 {
        self.small_increment
            .unwrap_or(self.initial_increment.min(0.01))
    }

    pub(crate) fn validate(&self) -> Result<(), CoreError> {
        let bad = |what: &str| Err(CoreError::Invalid(format!("Newton settings: {what}")));
        let pos = |x: f64| x > 0.0 && x.is_finite();
        if !(pos(self.min_increment) && pos(self.initial_increment) && pos(self.max_increment)) {
            return bad("increments must be positive and finite");
        }
        if self.min_increment > self.initial_increment.min(self.max_increment) {
            return bad("min_increment must not exceed initial_increment and max_increment");
        }
        if !pos(self.small_increment()) || self.small_increment() < self.min_increment {
            return bad("small_increment must be positive and at least min_increment");
        }
        if !(self.cutback > 0.0 && self.cutback < 1.0) {
            return bad("cutback must lie in (0, 1)");
        }
        if !(self.growth >= 1.0 && self.growth.is_finite()) {
            return bad("growth must be >= 1");
        }
        if self.max_iterations == 0 {
            return bad("max_iterations must be >= 1");
        }
        if !(pos(self.tol_force) && pos(self.tol_energy)) {
            return bad("tolerances must be positive");
        }
        if self.divergence_ratio.is_nan()
            || self.divergence_ratio <= 1.0
            || self.force_floor.is_nan()
            || self.force_floor < 0.0
        {
            return bad("divergence_ratio must exceed 1 and force_floor must be >= 0");
        }
        Ok(())
    }
}

/// What the observer wants after an increment.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Control {
    /// Go on with the next increment.
    Continue,
    /// End the run now (the increment just reported is kept).
    Stop,
}

/// Why an increment attempt failed.
#[derive(Debug, Clone, PartialEq)]
pub enum IncrementFailure {
    /// `max_iterations` reached without convergence.
    IterationLimit,
    /// NaN or infinity in the residual or the correction.
    NonFinite,
    /// The relative residual stopped decreasing above `tol_force` (round
    /// off reached, or a tolerance the arithmetic cannot meet).
    Stagnated {
        /// Smallest relative residual reached.
        best: f64,
        /// The tolerance asked for.
        tolerance: f64,
        /// Iterations without a decrease of the best residual by 1 %.
        iterations: usize,
    },
    /// The residual norm grew past `divergence_ratio` times the first one.
    Diverging {
        /// Residual norm reached.
        residual: f64,
        /// First residual norm of the attempt.
        initial: f64,
    },
    /// The linear solver failed (e.g. the tangent is not positive definite).
    Solver(SolverError),
    /// An element failed (e.g. its law), with the message.
    Element(String),
}

impl std::fmt::Display for IncrementFailure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            IncrementFailure::IterationLimit => write!(f, "iteration limit reached"),
            IncrementFailure::NonFinite => write!(f, "residual or correction not finite"),
            IncrementFailure::Stagnated {
                best,
                tolerance,
                iterations,
            } => write!(
                f,
                "stagnated: relative residual {best:.3e} not decreasing for {iterations} iterations, tol_force = {tolerance:.3e} cannot be met"
            ),
            IncrementFailure::Diverging { residual, initial } => write!(
                f,
                "diverging: residual norm {residual:.3e} against {initial:.3e} at the start"
            ),
            IncrementFailure::Solver(e) => write!(f, "linear solver: {e}"),
            IncrementFailure::Element(m) => write!(f, "element: {m}"),
        }
    }
}

/// Failure of a nonlinear analysis.
#[derive(Debug, Error)]
pub enum NonlinearError {
    /// Cut-backs drove the increment below `min_increment`.
    #[error(
        "load increment too small: stopped at lambda = {lambda:.9e} (step {step}), the last \
         attempted increment {increment:.3e} failed with relative residual {last_residual:.3e} \
         after {iterations} iterations: {reason}"
    )]
    IncrementTooSmall {
        /// Step index (0-based) of the failed increment.
        step: usize,
        /// Load factor of the last converged increment.
        lambda: f64,
        /// Load-factor increment of the last failed attempt.
        increment: f64,
        /// Relative force residual at the end of the last failed attempt.
        last_residual: f64,
        /// Iterations made by the last failed attempt.
        iterations: usize,
        /// Why the last attempt failed.
        reason: IncrementFailure,
    },
    /// Model, input or non-recoverable element failure.
    #[error(transparent)]
    Core(#[from] CoreError),
    /// Fatal linear solver failure (the symbolic analysis).
    #[error(transparent)]
    Solver(#[from] SolverError),
}

/// What one converged increment did.
#[derive(Debug, Clone, PartialEq)]
pub struct IncrementReport {
    /// Step index (0-based) in the program.
    pub step: usize,
    /// Global index of the increment (1-based, converged increments only,
    /// counted from the start of the analysis across restarts).
    pub increment_index: usize,
    /// Load factor reached.
    pub lambda: f64,
    /// Load-factor increment.
    pub delta_lambda: f64,
    /// Fraction of the step done after this increment.
    pub step_fraction: f64,
    /// Newton iterations of the converged attempt.
    pub iterations: usize,
    /// Final relative force residual.
    pub residual: f64,
    /// Final relative energy.
    pub energy: f64,
    /// Cut-backs before this increment converged.
    pub cutbacks: usize,
    /// Cycles reached ([`Model::cycles`]; 0 without a fatigue program).
    pub cycles: f64,
    /// Temperature factor reached ([`Model::temperature_factor`]; 1 for a
    /// model without temperature steps).
    pub temperature_factor: f64,
    /// Seconds spent on this increment, failed attempts included
    /// (`analyze` only on the run's first increment; `pattern` unused).
    pub seconds: Timings,
    /// True when this increment was sized by the small-increment rule.
    pub small_increment_mode: bool,
    /// Negative pivots (inertia) of the last tangent factorised in this
    /// increment, when the linear back end reports it (`ldlt`, and 0 from a
    /// successful `cholesky`): a positive count means the tangent is
    /// indefinite (softening past a limit point of the structure or of a
    /// material point).
    pub negative_pivots: Option<usize>,
    /// What constrained the increment: the load factor (load or
    /// displacement control), a cylindrical arc length or the dissipation.
    pub control: crate::arc_length::PathMode,
    /// Energy dissipated in this increment by the energy balance
    /// `½ (lambda_0 Δa - Δlambda a_0 + p_0 Δlambda - lambda_0 Δp)` (see
    /// [`crate::arc_length`]); arc-length runs only.
    pub dissipation: Option<f64>,
    /// On the first increment after the driver changed the control at a
    /// limit point (or back), or switched to the exact tangent: where and
    /// why ([`crate::path_switch`], [`Work::try_exact_tangent`]).
    pub switched: Vec<crate::path_switch::PathSwitch>,
}

/// The driver's position in the program: everything its future depends on.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Cursor {
    pub(crate) step: usize,
    pub(crate) t: f64,
    pub(crate) lambda: f64,
    pub(crate) increment_index: usize,
    pub(crate) size: f64,
    pub(crate) small: bool,
    pub(crate) force_peak: f64,
    /// The exact tangent is in use ([`Work::try_exact_tangent`]).
    pub(crate) exact: bool,
    /// Cut-backs since the last increment that converged at its full size
    /// (load control's limit-point test).
    pub(crate) cutbacks_in_a_row: usize,
    /// Negative pivots of the last converged increment's tangent, when the
    /// back end reports them.
    pub(crate) pivots: Option<usize>,
}

/// A restart point after a converged increment. Serialisable, so that a
/// front end can write it to disk; [`solve_nonlinear`] continues from it
/// with exactly the increments an uninterrupted run would make (same
/// program and settings required).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Checkpoint {
    /// Step index (0-based) of the last converged increment.
    pub step: usize,
    /// Fraction of that step done (1 = step finished).
    pub step_fraction: f64,
    /// Load factor reached.
    pub lambda: f64,
    /// Converged increments so far (global).
    pub increment_index: usize,
    /// Size of the next increment (fraction of the step).
    pub increment_size: f64,
    /// Whether the small-increment rule is active for the next increment.
    pub small_increment_mode: bool,
    /// Largest force scale met so far (floor of the force criterion).
    pub force_peak: f64,
    /// Full displacement vector.
    pub u: Vec<f64>,
    /// Committed state.
    pub state_committed: Vec<f64>,
    /// Path-following state (arc-length runs only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub path: Option<crate::arc_length::PathState>,
    /// The run switched to the exact (nonsymmetric) tangent.
    #[serde(default)]
    pub exact_tangent: bool,
    /// Cut-backs since the last increment that converged at its full size.
    #[serde(default)]
    pub cutbacks_in_a_row: usize,
    /// Negative pivots of the last converged increment's tangent, when
    /// reported.
    #[serde(default)]
    pub negative_pivots: Option<usize>,
    /// What a `control = "auto"` run under load control keeps for a switch
    /// to path following ([`crate::path_switch`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub load_track: Option<crate::path_switch::LoadTrack>,
}

impl Checkpoint {
    pub(crate) fn cursor(&self) -> Cursor {
        Cursor {
            step: self.step,
            t: self.step_fraction,
            lambda: self.lambda,
            increment_index: self.increment_index,
            size: self.increment_size,
            small: self.small_increment_mode,
            force_peak: self.force_peak,
            exact: self.exact_tangent,
            cutbacks_in_a_row: self.cutbacks_in_a_row,
            pivots: self.negative_pivots,
        }
    }

    pub(crate) fn new(
        c: &Cursor,
        u: &[f64],
        state: &StateStore,
        path: Option<&crate::arc_length::PathState>,
        track: Option<&crate::path_switch::LoadTrack>,
    ) -> Self {
        Checkpoint {
            step: c.step,
            step_fraction: c.t,
            lambda: c.lambda,
            increment_index: c.increment_index,
            increment_size: c.size,
            small_increment_mode: c.small,
            force_peak: c.force_peak,
            u: u.to_vec(),
            state_committed: state.committed.clone(),
            path: path.cloned(),
            exact_tangent: c.exact,
            cutbacks_in_a_row: c.cutbacks_in_a_row,
            negative_pivots: c.pivots,
            load_track: track.cloned(),
        }
    }
}

/// What the observer sees after a converged increment.
#[derive(Debug)]
pub struct IncrementView<'a> {
    /// The increment's report.
    pub report: &'a IncrementReport,
    /// Full displacement vector.
    pub u: &'a [f64],
    /// Full residual `f_int - lambda f_ext` (reactions on constrained dofs).
    pub residual: &'a [f64],
    /// State (committed = trial = this increment's).
    pub state: &'a StateStore,
    /// Relative force residual after each iteration of the converged attempt
    /// (index 0: before the first correction).
    pub residual_history: &'a [f64],
    pub(crate) cursor: Cursor,
    pub(crate) path: Option<&'a crate::arc_length::PathState>,
    pub(crate) track: Option<&'a crate::path_switch::LoadTrack>,
}

impl IncrementView<'_> {
    /// A restart point after this increment.
    pub fn checkpoint(&self) -> Checkpoint {
        Checkpoint::new(&self.cursor, self.u, self.state, self.path, self.track)
    }
}

/// Totals of a run (of this call only, for a restarted run).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct NonlinearSummary {
    /// Converged increments.
    pub increments: usize,
    /// Newton iterations, failed attempts included.
    pub newton_iterations_total: usize,
    /// Most iterations of a converged increment.
    pub newton_iterations_max: usize,
    /// Cut-backs.
    pub cutbacks: usize,
    /// Seconds per phase (`pattern`: sparsity pattern; `analyze`: symbolic).
    pub timings: Timings,
    /// Symbolic analyses done (1, or 0 without free dofs / increments).
    pub analyze_count: usize,
    /// Load factor reached.
    pub final_lambda: f64,
    /// True when the observer stopped the run.
    pub stopped_by_observer: bool,
    /// Attempts that switched to the laws' secant tangent because the
    /// consistent one stopped reducing the residual.
    pub secant_attempts: usize,
    /// Linear solves (right-hand sides), failed attempts included: one per
    /// Newton iteration under load control, two under path following.
    pub linear_solves: usize,
}

/// Result of [`solve_nonlinear`] that ran to the end of its program or was
/// stopped by the observer.
#[derive(Debug, Clone)]
pub struct NonlinearRun {
    /// Totals.
    pub summary: NonlinearSummary,
    /// Final full displacement vector.
    pub u: Vec<f64>,
    /// Final full residual `f_int - lambda f_ext`.
    pub residual: Vec<f64>,
    /// Final state.
    pub state: StateStore,
    pub(crate) cursor: Cursor,
    pub(crate) path: Option<crate::arc_length::PathState>,
}

impl NonlinearRun {
    /// A restart point at the end of this run.
    pub fn checkpoint(&self) -> Checkpoint {
        Checkpoint::new(&self.cursor, &self.u, &self.state, self.path.as_ref(), None)
    }
}

/// One residual evaluation.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Eval {
    /// |r_f|
    pub(crate) abs: f64,
    /// |r_f| / scale
    pub(crate) rel: f64,
    /// max(|lambda f_ext,f|, |reactions|)
    pub(crate) scale_now: f64,
}

/// Outcome of one increment attempt.
enum Attempt {
    Converged {
        iterations: usize,
        eval: Eval,
        energy: f64,
    },
    Failed {
        iterations: usize,
        rel: f64,
        reason: IncrementFailure,
    },
}

/// Buffers and counters of one run, allocated once.
pub(crate) struct Work<'m> {
    pub(crate) model: &'m Model,
    pub(crate) asm: Assembler,
    pub(crate) k: SymmetricCsc,
    pub(crate) coords: Vec<[f64; 3]>,
    pub(crate) layout: junta_core::EquationLayout,
    pub(crate) free_dofs: Vec<usize>,
    /// The reduced external force `T^T f_ext` (by equation).
    pub(crate) fext_f: Vec<f64>,
    pub(crate) fext_free_norm: f64,
    /// `|f_th,f|`: the reduced internal force of the temperature field at
    /// zero displacement and temperature factor 1 (0 without one).
    pub(crate) fth_free_norm: f64,
    /// The model's load pattern is zero (no force, no non-zero prescribed
    /// displacement): the load factor moves nothing (a temperature-only
    /// program after its thermal step).
    pub(crate) no_load: bool,
    pub(crate) f_int: Vec<f64>,
    /// `f_int - lambda f_ext` (full length: reactions on constrained dofs).
    pub(crate) res: Vec<f64>,
    /// The reduced residual `T^T res` (by equation): the out-of-balance
    /// force of the equations, linear constraints folded in.
    pub(crate) res_f: Vec<f64>,
    pub(crate) u: Vec<f64>,
    pub(crate) u_base: Vec<f64>,
    pub(crate) u_conv: Vec<f64>,
    pub(crate) du: Vec<f64>,
    pub(crate) r_prev: Vec<f64>,
    /// Some element has finite (large-deformation) kinematics: the line
    /// search takes the full step ([`Work::takes_full_step`]).
    pub(crate) finite_kinematics: bool,
    pub(crate) history: Vec<f64>,
    pub(crate) timings: Timings,
    pub(crate) analyzed: bool,
    /// Symbolic analyses these buffers made (0 when a driver before them
    /// left the solver analysed).
    pub(crate) analyses: usize,
    pub(crate) iterations: usize,
    pub(crate) secant_attempts: usize,
    pub(crate) solves: usize,
    pub(crate) settings: NewtonSettings,
    /// Load factor of the current trial (path following).
    pub(crate) lambda_trial: f64,
    /// The exact (nonsymmetric) tangent is assembled in full and solved by
    /// `exact_solver` ([`Work::try_exact_tangent`]).
    pub(crate) exact: bool,
    /// The `lu` back end of the exact tangent.
    pub(crate) exact_solver: Option<Box<dyn LinearSolver>>,
    /// The switch to the exact tangent, for the next increment's report.
    pub(crate) exact_switch: Option<crate::path_switch::PathSwitch>,
    /// Attempts of the current increment that stalled on the symmetric
    /// part of the tangent (reset when an increment converges).
    pub(crate) stalled_attempts: usize,
}

/// `|f_th,f|` of [`Work::fth_free_norm`]: the free part of
/// [`internal_force_at_zero`] at temperature factor 1 (0 without a
/// temperature field, or if that assembly fails: the run's own assemblies
/// report the error).
fn thermal_force_norm(model: &Model, asm: &Assembler) -> f64 {
    match internal_force_at_zero(model, asm, 1.0) {
        Some(f) => model
            .dofs
            .reduce(&f)
            .iter()
            .map(|v| v * v)
            .sum::<f64>()
            .sqrt(),
        None => 0.0,
    }
}

/// The internal force at zero displacement from the initial state at
/// temperature factor `theta`, by dof: `-f_th`, the thermal force of the
/// solids' temperature change (interfaces carry no thermal strain and no
/// force at zero jump in their initial state). `None` without a
/// temperature field or if the assembly fails.
pub(crate) fn internal_force_at_zero(
    model: &Model,
    asm: &Assembler,
    theta: f64,
) -> Option<Vec<f64>> {
    model.temperature.as_ref()?;
    let ndof = model.dofs.num_dofs();
    let mut f = vec![0.0; ndof];
    let mut state = model.initial_state();
    let u0 = vec![0.0; ndof];
    let step = StepInfo {
        temperature_factor: theta,
        ..StepInfo::default()
    };
    asm.assemble(
        &model.mesh,
        &model.elements,
        &model.dofs,
        &u0,
        &mut state,
        step,
        None,
        &mut f,
    )
    .ok()?;
    Some(f)
}

pub(crate) fn is_element_error(e: &CoreError) -> bool {
    matches!(e, CoreError::Element { .. })
}

impl<'m> Work<'m> {
    /// Buffers of a run starting from the full displacement `u_start`;
    /// `free_dofs[e]` is the dof of equation `e`.
    pub(crate) fn new(
        model: &'m Model,
        asm: Assembler,
        free_dofs: Vec<usize>,
        u_start: Vec<f64>,
        settings: &NewtonSettings,
    ) -> Self {
        let nf = free_dofs.len();
        let fext_f = model.dofs.reduce(&model.f_ext);
        let fext_free_norm = fext_f.iter().map(|v| v * v).sum::<f64>().sqrt();
        let fth_free_norm = thermal_force_norm(model, &asm);
        let no_load = fext_free_norm == 0.0 && model.dofs.prescribed.iter().all(|p| *p == 0.0);
        Work {
            model,
            k: asm.pattern.clone(),
            asm,
            coords: model.dofs.equation_coords(&model.mesh.nodes),
            layout: model.equation_layout(),
            free_dofs,
            fext_f,
            fext_free_norm,
            fth_free_norm,
            no_load,
            f_int: vec![0.0; u_start.len()],
            res: vec![0.0; u_start.len()],
            res_f: vec![0.0; nf],
            u: u_start.clone(),
            u_base: u_start.clone(),
            u_conv: u_start,
            du: vec![0.0; nf],
            r_prev: vec![0.0; nf],
            finite_kinematics: model
                .elements
                .iter()
                .any(|e| e.kinematics() == junta_core::Kinematics::Finite),
            history: Vec::with_capacity(settings.max_iterations + 1),
            timings: Timings::default(),
            analyzed: false,
            analyses: 0,
            iterations: 0,
            secant_attempts: 0,
            solves: 0,
            settings: settings.clone(),
            lambda_trial: 0.0,
            exact: false,
            exact_solver: None,
            exact_switch: None,
            stalled_attempts: 0,
        }
    }

    /// The buffers of a run from the full displacement `u_start`, and the
    /// run's timings with the time of the sparsity pattern (the assembler)
    /// as `pattern`.
    pub(crate) fn for_run(
        model: &'m Model,
        solver: &dyn LinearSolver,
        u_start: Vec<f64>,
        settings: &NewtonSettings,
    ) -> (Self, Timings) {
        let t = Instant::now();
        let asm = model.assembler();
        let timings = Timings {
            pattern: t.elapsed().as_secs_f64(),
            ..Default::default()
        };
        let nf = model.dofs.num_free;
        let mut free_dofs = vec![0; nf];
        for (d, &e) in model.dofs.eq.iter().enumerate() {
            if e != CONSTRAINED {
                free_dofs[e] = d;
            }
        }
        let mut w = Work::new(model, asm, free_dofs, u_start, settings);
        // A nonsymmetric tangent (a law with a general tangent) is stored in
        // full when the back end can solve it; a symmetric back end the user
        // forced gets the symmetric part (Newton then loses its quadratic
        // convergence: the iterations per increment show it).
        w.k.set_general(
            model.matrix_kind() == junta_core::MatrixKind::General
                && solver.accepts(junta_core::MatrixKind::General),
        );
        (w, timings)
    }

    /// Assemble at `self.u` and fill the residual.
    pub(crate) fn evaluate(
        &mut self,
        state: &mut StateStore,
        step: StepInfo,
        lambda: f64,
        force_peak: f64,
    ) -> Result<Eval, CoreError> {
        let m = self.model;
        state.restore();
        let step = StepInfo {
            exact_tangent: self.exact,
            ..step
        };
        let t = Instant::now();
        let r = self.asm.assemble_cached(
            &m.mesh,
            &m.elements,
            &m.dofs,
            &self.u,
            state,
            step,
            Some(&mut self.k),
            &mut self.f_int,
        );
        self.timings.assemble += t.elapsed().as_secs_f64();
        r?;
        let mut reac2 = 0.0;
        let dependents = &m.dofs.dependents;
        for (d, (r, (&fi, &fe))) in self
            .res
            .iter_mut()
            .zip(self.f_int.iter().zip(&m.f_ext))
            .enumerate()
        {
            *r = fi - lambda * fe;
            if m.dofs.eq[d] == CONSTRAINED && !m.dofs.orphan[d] && !dependents.contains(d) {
                reac2 += *r * *r;
            }
        }
        m.dofs.reduce_into(&self.res, &mut self.res_f);
        let free2: f64 = self.res_f.iter().map(|r| r * r).sum();
        let abs = free2.sqrt();
        let scale_now = (lambda.abs() * self.fext_free_norm)
            .max(step.temperature_factor.abs() * self.fth_free_norm)
            .max(reac2.sqrt());
        let scale = scale_now
            .max(self.settings.force_floor * force_peak)
            .max(f64::MIN_POSITIVE);
        Ok(Eval {
            abs,
            rel: abs / scale,
            scale_now,
        })
    }

    /// `u = u_base + s du` on the free dofs (dependents follow).
    fn set_trial(&mut self, s: f64) {
        for (e, &d) in self.free_dofs.iter().enumerate() {
            self.u[d] = self.u_base[d] + s * self.du[e];
        }
        self.model.dofs.fill_dependents(&mut self.u);
    }

    /// The solver's symbolic analysis, on the run's first tangent only.
    pub(crate) fn analyze_once(
        &mut self,
        solver: &mut dyn LinearSolver,
    ) -> Result<(), SolverError> {
        if !self.analyzed {
            let t = Instant::now();
            // every update is checked through the out-of-balance forces
            solver.set_caller_checks_residual(true);
            solver.set_layout(&self.layout);
            solver.analyze(&self.k, Some(&self.coords))?;
            self.timings.analyze += t.elapsed().as_secs_f64();
            self.analyzed = true;
            self.analyses += 1;
        }
        Ok(())
    }

    /// Numeric factorisation of the current tangent (timed).
    pub(crate) fn factorize(&mut self, solver: &mut dyn LinearSolver) -> Result<(), SolverError> {
        let t = Instant::now();
        let r = solver.factorize(&self.k);
        self.timings.factor += t.elapsed().as_secs_f64();
        r
    }

    /// Residual at `u` with the cursor's load factor and no increment (the
    /// starting point of a run, or its last converged state); the trial
    /// state is reset to the committed one afterwards.
    pub(crate) fn evaluate_at_rest(
        &mut self,
        state: &mut StateStore,
        cur: &Cursor,
    ) -> Result<Eval, CoreError> {
        let step = StepInfo::at(cur.increment_index, cur.lambda, 0.0)
            .in_program(self.model, cur.step, cur.t);
        let ev = self.evaluate(state, step, cur.lambda, cur.force_peak)?;
        state.restore();
        Ok(ev)
    }

    /// Assemble and solve the exact tangent in full from now on: the
    /// matrix gets its lower triangle and the `lu` back end takes over
    /// (analysed on the next tangent).
    pub(crate) fn use_exact_tangent(&mut self) {
        self.exact = true;
        self.k.set_general(true);
        self.exact_solver = Some(Box::new(crate::lu::LuSolver::new(Default::default())));
        self.analyzed = false;
    }

    /// After the second attempt of an increment that failed by its
    /// iteration limit or by stagnation on the symmetric part of a tangent
    /// that can be nonsymmetric ([`Model::tangent_symmetrised`]): measure, at the
    /// attempt's last iterate, the largest skew entry of the exact
    /// tangent scaled by its diagonal ([`largest_scaled_skew`]). Above [`EXACT_TANGENT_SKEW`] (mixed-mode
    /// softening: the symmetric part is no Newton tangent any more) the
    /// run switches to the exact tangent ([`Work::use_exact_tangent`]) and
    /// the same increment is tried again; the switch is kept for the next
    /// report. Returns whether it switched.
    pub(crate) fn try_exact_tangent(
        &mut self,
        state: &mut StateStore,
        step: StepInfo,
        reason: &IncrementFailure,
        program_step: usize,
    ) -> Result<bool, CoreError> {
        let stalled = matches!(
            reason,
            IncrementFailure::IterationLimit | IncrementFailure::Stagnated { .. }
        );
        if self.exact || !stalled || !self.model.tangent_symmetrised() {
            return Ok(false);
        }
        // a first failure may be an increment too long: its cut-back
        // decides
        self.stalled_attempts += 1;
        if self.stalled_attempts < STALLS_BEFORE_EXACT_TANGENT {
            return Ok(false);
        }
        self.k.set_general(true);
        self.exact = true;
        let r = self.evaluate(state, step, step.load_factor, 0.0);
        self.exact = false;
        r?;
        let ratio = largest_scaled_skew(&self.k);
        state.restore();
        if ratio <= EXACT_TANGENT_SKEW {
            self.k.set_general(false);
            tracing::info!(
                skew = ratio,
                "stalled on the symmetric tangent, which is close to the exact one"
            );
            return Ok(false);
        }
        self.use_exact_tangent();
        self.exact_switch = Some(crate::path_switch::PathSwitch {
            increment: step.increment.saturating_sub(1),
            step: program_step,
            lambda: step.load_factor - step.delta_load_factor,
            to: "exact_tangent".into(),
            reason: format!(
                "Newton stalled ({reason}) on the symmetric part of a mixed-mode tangent whose skew part is {:.1e} of it: the exact, nonsymmetric tangent (lu) from here",
                ratio
            ),
        });
        tracing::warn!(
            skew = ratio,
            "stalled on the symmetric tangent: switching to the exact tangent"
        );
        Ok(true)
    }

    /// The run's totals: the counters and phase timings of these buffers,
    /// `pattern` from `timings`, the wall time since `t_run`.
    pub(crate) fn close(
        &self,
        summary: &mut NonlinearSummary,
        mut timings: Timings,
        t_run: Instant,
    ) {
        summary.newton_iterations_total = self.iterations;
        summary.analyze_count = self.analyses;
        summary.secant_attempts = self.secant_attempts;
        summary.linear_solves = self.solves;
        timings.assemble = self.timings.assemble;
        timings.analyze = self.timings.analyze;
        timings.factor = self.timings.factor;
        timings.solve = self.timings.solve;
        timings.total = t_run.elapsed().as_secs_f64();
        summary.timings = timings;
    }

    /// One attempt of an increment from the converged state in `u_conv`:
    /// the residual at the new load factor ([`Work::first_residual`]), then
    /// Newton iterations, each a correction ([`Work::newton_correction`]),
    /// an update along it ([`Work::newton_update`]) and the tests of the
    /// module doc ([`Work::newton_checks`]), until the attempt converges or
    /// fails.
    fn attempt(
        &mut self,
        solver: &mut dyn LinearSolver,
        state: &mut StateStore,
        step: StepInfo,
        force_peak: f64,
    ) -> Result<Attempt, NonlinearError> {
        let mut exact = self.exact_solver.take();
        let solver: &mut dyn LinearSolver = match exact.as_deref_mut() {
            Some(lu) => lu,
            None => solver,
        };
        let r = self.attempt_with(solver, state, step, force_peak);
        self.exact_solver = exact;
        r
    }

    /// [`Work::attempt`] with the back end in use.
    fn attempt_with(
        &mut self,
        solver: &mut dyn LinearSolver,
        state: &mut StateStore,
        step: StepInfo,
        force_peak: f64,
    ) -> Result<Attempt, NonlinearError> {
        let mut a = NewtonAttempt {
            step,
            lambda: step.load_factor,
            force_peak,
            ev: Eval {
                abs: f64::NAN,
                rel: f64::NAN,
                scale_now: 0.0,
            },
            rho0: 0.0,
            e_ref: 0.0,
            best_rel: 0.0,
            best_at: 0,
        };
        match self.iterate(solver, state, &mut a) {
            Ok(outcome) | Err(Abort::Failed(outcome)) => Ok(outcome),
            Err(Abort::Fatal(e)) => Err(e),
        }
    }

    /// The body of [`Work::attempt`]; a failed attempt comes back as
    /// [`Abort::Failed`].
    fn iterate(
        &mut self,
        solver: &mut dyn LinearSolver,
        state: &mut StateStore,
        a: &mut NewtonAttempt,
    ) -> Result<Attempt, Abort<Attempt>> {
        if let Some(done) = self.first_residual(state, a)? {
            return Ok(done);
        }
        let max_iterations = self.settings.max_iterations;
        for it in 1..=max_iterations {
            self.newton_correction(solver, a, it)?;
            let s = self.newton_update(state, a, it)?;
            if let Some(done) = self.newton_checks(a, it, s) {
                return Ok(done);
            }
        }
        Ok(failed(
            max_iterations,
            a.ev.rel,
            IncrementFailure::IterationLimit,
        ))
    }

    /// Start of an attempt: `u` = the converged free displacements with the
    /// constrained dofs at `lambda * prescribed` (dependents follow), and
    /// its residual. `Some` when there is nothing to iterate: no free dofs,
    /// or an increment that moves nothing (a zero load-factor increment, or
    /// a model whose load pattern is zero) already in balance.
    fn first_residual(
        &mut self,
        state: &mut StateStore,
        a: &mut NewtonAttempt,
    ) -> Result<Option<Attempt>, Abort<Attempt>> {
        let lambda = a.lambda;
        let m = self.model;
        for (d, u) in self.u.iter_mut().enumerate() {
            *u = if m.dofs.eq[d] == CONSTRAINED {
                lambda * m.dofs.prescribed[d]
            } else {
                self.u_conv[d]
            };
        }
        m.dofs.fill_dependents(&mut self.u);
        self.history.clear();
        a.ev = self.attempt_evaluate(state, a, 0)?;
        if !a.ev.abs.is_finite() {
            return Err(Abort::Failed(failed(
                0,
                a.ev.rel,
                IncrementFailure::NonFinite,
            )));
        }
        self.history.push(a.ev.rel);
        let nf = self.free_dofs.len();
        // an increment that moves nothing (no load-factor change, or a zero
        // load pattern) and starts in balance has converged: its first
        // residual is round-off, whose work ratios mean nothing
        let moves_nothing = a.step.delta_load_factor == 0.0 || self.no_load;
        if nf == 0 || (moves_nothing && a.ev.rel <= self.settings.tol_force) {
            return Ok(Some(Attempt::Converged {
                iterations: 0,
                eval: a.ev,
                energy: 0.0,
            }));
        }
        a.rho0 = a.ev.abs;
        a.e_ref = 0.0;
        a.best_rel = a.ev.rel;
        a.best_at = 0;
        Ok(None)
    }

    /// Evaluate at `u` for the attempt `a`: an element error fails the
    /// attempt (at iteration `it`, with the last residual), any other error
    /// is fatal.
    fn attempt_evaluate(
        &mut self,
        state: &mut StateStore,
        a: &NewtonAttempt,
        it: usize,
    ) -> Result<Eval, Abort<Attempt>> {
        match self.evaluate(state, a.step, a.lambda, a.force_peak) {
            Ok(e) => Ok(e),
            Err(e) if is_element_error(&e) => Err(Abort::Failed(failed(
                it,
                a.ev.rel,
                IncrementFailure::Element(e.to_string()),
            ))),
            Err(e) => Err(e.into()),
        }
    }

    /// The correction of iteration `it`: `K_ff(u_i) du = -r_f(u_i)` with the
    /// tangent assembled at the current iterate (`r_prev` keeps `r_f(u_i)`
    /// for the energy criterion).
    fn newton_correction(
        &mut self,
        solver: &mut dyn LinearSolver,
        a: &NewtonAttempt,
        it: usize,
    ) -> Result<(), Abort<Attempt>> {
        self.iterations += 1;
        self.analyze_once(solver)?;
        if let Err(e) = self.factorize(solver) {
            return Err(Abort::Failed(failed(
                it,
                a.ev.rel,
                IncrementFailure::Solver(e),
            )));
        }
        for (e, &r) in self.res_f.iter().enumerate() {
            self.r_prev[e] = r;
            self.du[e] = -r;
        }
        let clock = SolveClock::start(solver);
        let r = solver.solve_in_place(&self.k, &mut self.du);
        self.solves += 1;
        clock.stop(solver, &mut self.timings);
        if let Err(e) = r {
            return Err(Abort::Failed(failed(
                it,
                a.ev.rel,
                IncrementFailure::Solver(e),
            )));
        }
        if !self.du.iter().all(|v| v.is_finite()) {
            return Err(Abort::Failed(failed(
                it,
                a.ev.rel,
                IncrementFailure::NonFinite,
            )));
        }
        Ok(())
    }

    /// The update of iteration `it`: `u = u_i + s du` with the step length
    /// `s` of the line search ([`Work::line_search`]), and its residual in
    /// `a.ev`. When the consistent tangent did not reduce the residual
    /// (Newton cycling between the branches of a softening point) the laws'
    /// secant tangent is used for the rest of the attempt (linear but
    /// monotone convergence) and reassembled at the new `u`. Returns `s`.
    fn newton_update(
        &mut self,
        state: &mut StateStore,
        a: &mut NewtonAttempt,
        it: usize,
    ) -> Result<f64, Abort<Attempt>> {
        self.u_base.copy_from_slice(&self.u);
        let ls = self.line_search(state, a, it)?;
        // (Only while the force residual is above its tolerance: a
        // residual already at round-off level need not decrease.)
        let switch_to_secant = !ls.decreased
            && !a.step.secant
            && self.settings.secant_fallback
            && a.ev.rel > self.settings.tol_force;
        if switch_to_secant {
            a.step.secant = true;
            self.secant_attempts += 1;
            tracing::debug!(
                iteration = it,
                "no decrease with the consistent tangent: secant tangent from here"
            );
        }
        if ls.s != ls.last_s || switch_to_secant {
            self.set_trial(ls.s);
            a.ev = self.attempt_evaluate(state, a, it)?;
        } else {
            a.ev = ls.eval;
        }
        self.history.push(a.ev.rel);
        if !a.ev.abs.is_finite() {
            return Err(Abort::Failed(failed(
                it,
                a.ev.rel,
                IncrementFailure::NonFinite,
            )));
        }
        Ok(ls.s)
    }

    /// Backtracking line search on `|r_f|` from `u_base` along `du`:
    /// `s = 1, 1/2, 1/4, ...` (at most `max_line_search` halvings; one try
    /// without `line_search`), the first `s` with `|r_f(u_base + s du)| <=
    /// (1 - 1e-4 s) |r_f(u_base)|` (under finite kinematics the full step
    /// whenever it evaluates: [`Work::takes_full_step`]), else the `s` of
    /// the smallest finite residual. Fails when no try gave a finite
    /// residual. `u` is left at the last try.
    fn line_search(
        &mut self,
        state: &mut StateStore,
        a: &NewtonAttempt,
        it: usize,
    ) -> Result<LineSearch, Abort<Attempt>> {
        let rho_prev = a.ev.abs;
        let tries = if self.settings.line_search {
            self.settings.max_line_search + 1
        } else {
            1
        };
        let mut s = 1.0;
        let mut best: Option<(f64, Eval)> = None;
        let mut last_s = f64::NAN;
        let mut last_err: Option<CoreError> = None;
        let mut decreased = false;
        for _ in 0..tries {
            self.set_trial(s);
            last_s = s;
            match self.evaluate(state, a.step, a.lambda, a.force_peak) {
                Ok(e) if e.abs.is_finite() => {
                    if !matches!(best, Some((_, b)) if b.abs <= e.abs) {
                        best = Some((s, e));
                    }
                    if e.abs <= (1.0 - 1e-4 * s) * rho_prev || self.takes_full_step(s) {
                        decreased = true;
                        break;
                    }
                }
                Ok(_) => {}
                Err(e) if is_element_error(&e) => last_err = Some(e),
                Err(e) => return Err(e.into()),
            }
            s *= 0.5;
        }
        let Some((s, eval)) = best else {
            let reason = match last_err {
                Some(e) => IncrementFailure::Element(e.to_string()),
                None => IncrementFailure::NonFinite,
            };
            return Err(Abort::Failed(failed(it, a.ev.rel, reason)));
        };
        Ok(LineSearch {
            s,
            eval,
            last_s,
            decreased,
        })
    }

    /// Under finite kinematics the full Newton step is taken whenever the
    /// elements evaluate at it (step length `s` = 1), as CalculiX and
    /// Abaqus do by default: the residual's norm is no merit function of a
    /// large-rotation problem. The first step of a loaded slender
    /// cantilever bends it and leaves an axial residual from the stretch
    /// of its bent axis hundreds of times the load, and the energy along
    /// the step rises as much; a shortened step (1/16 on the elastica of
    /// `crates/cli/tests/large_deformation.rs`) then needs 13 iterations
    /// where the full ones need 8. The step is still halved when an
    /// element fails (an inverted element, the modes of `h8i` not found).
    pub(crate) fn takes_full_step(&self, s: f64) -> bool {
        self.finite_kinematics && s == 1.0
    }

    /// The tests after iteration `it` (step length `s`): converged when the
    /// force and the energy criteria of the module doc hold; failed when
    /// the relative residual stagnated (its best not lowered by 1 % for
    /// [`STAGNATION_ITERATIONS`], four times as many with the secant
    /// tangent) or grew past `divergence_ratio` times the first one.
    /// `None`: iterate on.
    fn newton_checks(&self, a: &mut NewtonAttempt, it: usize, s: f64) -> Option<Attempt> {
        let st = &self.settings;
        let ev = a.ev;
        let (mut w_new, mut w_old) = (0.0, 0.0);
        for (e, &r) in self.res_f.iter().enumerate() {
            w_new += s * self.du[e] * r;
            w_old += s * self.du[e] * self.r_prev[e];
        }
        if it == 1 {
            a.e_ref = w_old.abs();
        }
        let energy = if a.e_ref > 0.0 {
            w_new.abs() / a.e_ref
        } else {
            0.0
        };
        tracing::debug!(
            iteration = it,
            residual = ev.rel,
            energy,
            step_length = s,
            "Newton iteration"
        );
        if ev.rel <= st.tol_force && energy <= st.tol_energy {
            return Some(Attempt::Converged {
                iterations: it,
                eval: ev,
                energy,
            });
        }
        // (stagnation of the force residual only: once it meets
        // tol_force, the energy criterion needs a step or two more)
        if ev.rel < 0.99 * a.best_rel {
            a.best_rel = ev.rel;
            a.best_at = it;
        } else if ev.rel > st.tol_force
            && it - a.best_at
                >= if a.step.secant {
                    4 * STAGNATION_ITERATIONS
                } else {
                    STAGNATION_ITERATIONS
                }
        {
            return Some(failed(
                it,
                ev.rel,
                IncrementFailure::Stagnated {
                    best: a.best_rel,
                    tolerance: st.tol_force,
                    iterations: it - a.best_at,
                },
            ));
        }
        if ev.abs > st.divergence_ratio * a.rho0 {
            return Some(failed(
                it,
                ev.rel,
                IncrementFailure::Diverging {
                    residual: ev.abs,
                    initial: a.rho0,
                },
            ));
        }
        None
    }
}

/// Why the iterations of an attempt stop early: the attempt failed (`A`,
/// the driver cuts back and retries) or the run cannot go on.
pub(crate) enum Abort<A> {
    Failed(A),
    Fatal(NonlinearError),
}

impl<A> From<NonlinearError> for Abort<A> {
    fn from(e: NonlinearError) -> Self {
        Abort::Fatal(e)
    }
}

impl<A> From<CoreError> for Abort<A> {
    fn from(e: CoreError) -> Self {
        Abort::Fatal(e.into())
    }
}

impl<A> From<SolverError> for Abort<A> {
    fn from(e: SolverError) -> Self {
        Abort::Fatal(e.into())
    }
}

fn failed(iterations: usize, rel: f64, reason: IncrementFailure) -> Attempt {
    Attempt::Failed {
        iterations,
        rel,
        reason,
    }
}

/// The running state of one Newton attempt.
struct NewtonAttempt {
    /// The increment (`secant` set once the fallback is on).
    step: StepInfo,
    /// Load factor of the increment.
    lambda: f64,
    /// Largest force scale met so far (floor of the force criterion).
    force_peak: f64,
    /// Residual of the current iterate.
    ev: Eval,
    /// First residual norm of the attempt (divergence test).
    rho0: f64,
    /// Work of the first iteration (reference of the energy criterion).
    e_ref: f64,
    /// Best relative residual, and the iteration it last fell by 1 %
    /// (stagnation test).
    best_rel: f64,
    best_at: usize,
}

/// Outcome of a line search: step length `s` and its residual, the last
/// step length tried (where `u` is), and whether the residual decreased
/// enough.
struct LineSearch {
    s: f64,
    eval: Eval,
    last_s: f64,
    decreased: bool,
}

/// Wall time of a linear solve. A back end may refactorise inside a solve
/// (the mixed-precision Cholesky falling back to double): that part is
/// booked as factor time.
pub(crate) struct SolveClock {
    start: Instant,
    factor_before: f64,
}

impl SolveClock {
    pub(crate) fn start(solver: &dyn LinearSolver) -> Self {
        SolveClock {
            start: Instant::now(),
            factor_before: solver.report().factor_seconds,
        }
    }

    pub(crate) fn stop(self, solver: &dyn LinearSolver, timings: &mut Timings) {
        let refactor = (solver.report().factor_seconds - self.factor_before).max(0.0);
        timings.factor += refactor;
        timings.solve += self.start.elapsed().as_secs_f64() - refactor;
    }
}

/// The largest skew entry of a nonsymmetric matrix scaled by its
/// diagonal, `max |K_ij - K_ji| / sqrt(|K_ii K_jj|)`: a local measure, so
/// that the skew of a few process-zone points is not lost in the solids'
/// stiffness. Over several ranks each rank holds a part of the tangent:
/// the largest of the parts' measures, the same on every rank.
fn largest_scaled_skew(k: &SymmetricCsc) -> f64 {
    let mut local = [local_scaled_skew(k)];
    if let Some(c) = junta_core::distributed::collective() {
        c.max_in_place(&mut local);
    }
    local[0]
}

/// [`largest_scaled_skew`] of the matrix `k` this process holds.
fn local_scaled_skew(k: &SymmetricCsc) -> f64 {
    let mut diag = vec![0.0; k.n];
    for j in 0..k.n {
        for p in k.col_ptr[j]..k.col_ptr[j + 1] {
            if k.row_idx[p] == j {
                diag[j] = k.values[p].abs();
            }
        }
    }
    let mut largest: f64 = 0.0;
    for j in 0..k.n {
        for p in k.col_ptr[j]..k.col_ptr[j + 1] {
            let scale = (diag[k.row_idx[p]] * diag[j]).sqrt();
            if scale > 0.0 {
                largest = largest.max((k.values[p] - k.lower[p]).abs() / scale);
            }
        }
    }
    largest
}

/// Cut-backs in a row (no increment converging at its full size in
/// between) taken for a limit point under `control = "auto"`: the
/// increments shrink towards a maximum of the load factor
/// ([`crate::path_switch`]).
const LIMIT_CUTBACKS: usize = 6;

/// Stalled attempts of one increment before the exact tangent is tried.
const STALLS_BEFORE_EXACT_TANGENT: usize = 2;

/// Largest skew entry of the exact tangent, scaled by the diagonal
/// ([`largest_scaled_skew`]), above which a Newton attempt stalled on the
/// symmetric part switches to the exact tangent
/// ([`Work::try_exact_tangent`]).
pub(crate) const EXACT_TANGENT_SKEW: f64 = 1e-4;

/// Newton iterations without a 1 % decrease of the best relative residual
/// after which an attempt stops as stagnated (a quadratically converging
/// Newton gains far more per iteration; the secant fallback, which
/// converges linearly, gets four times as many).
const STAGNATION_ITERATIONS: usize = 12;

/// Seconds spent between two snapshots of the run's timings (one
/// increment, failed attempts included; `pattern` unused).
pub(crate) fn increment_timings(now: Timings, before: Timings) -> Timings {
    Timings {
        pattern: 0.0,
        assemble: now.assemble - before.assemble,
        analyze: now.analyze - before.analyze,
        factor: now.factor - before.factor,
        solve: now.solve - before.solve,
        total: (now.assemble + now.analyze + now.factor + now.solve)
            - (before.assemble + before.analyze + before.factor + before.solve),
    }
}

/// A checkpoint's displacement and state sizes must be the model's.
pub(crate) fn check_checkpoint_fits(
    c: &Checkpoint,
    ndof: usize,
    state: &StateStore,
) -> Result<(), NonlinearError> {
    if c.u.len() != ndof || c.state_committed.len() != state.committed.len() {
        return Err(CoreError::Invalid(format!(
            "checkpoint does not fit the model: {} displacements and {} state values, \
             the model has {} dofs and {} state values",
            c.u.len(),
            c.state_committed.len(),
            ndof,
            state.committed.len()
        ))
        .into());
    }
    Ok(())
}

/// Does any element want small increments (committed state)?
pub(crate) fn any_wants_small(model: &Model, state: &StateStore) -> bool {
    model.mesh.blocks.iter().enumerate().any(|(b, block)| {
        let el = &model.elements[b];
        (0..block.len()).any(|e| el.wants_small_increments(&state.committed[state.range(b, e)]))
    })
}

/// Run the load program `program` (end load factor of each step) on `model`
/// with full Newton-Raphson, from the unloaded state or from `restart`.
///
/// `observer` is called after every converged increment and may stop the
/// run ([`Control::Stop`]). Returns the totals and the final state, or an
/// error; when the increment falls below `min_increment` the error is
/// [`NonlinearError::IncrementTooSmall`] and every converged increment has
/// been reported already. See the module documentation for the algorithm.
pub fn solve_nonlinear<F>(
    model: &Model,
    solver: &mut dyn LinearSolver,
    program: &[f64],
    settings: &NewtonSettings,
    restart: Option<&Checkpoint>,
    observer: F,
) -> Result<NonlinearRun, NonlinearError>
where
    F: FnMut(&IncrementView<'_>) -> Control,
{
    let options = LoadOptions {
        analyzed: false,
        stop_at_limit: false,
    };
    match run_load(model, solver, program, settings, restart, observer, options)? {
        LoadOutcome::Finished(run) => Ok(run),
        LoadOutcome::Limit { error, .. } => Err(error),
    }
}

/// How [`run_load`] starts and where it stops.
#[derive(Debug, Clone, Copy)]
pub(crate) struct LoadOptions {
    /// The solver holds the symbolic analysis of this model's pattern
    /// already (a driver before this one analysed it).
    pub(crate) analyzed: bool,
    /// In a step loading away from zero, stop at a limit point
    /// ([`LoadOutcome::Limit`]) as soon as a failed attempt's tangent has
    /// more negative pivots than the last converged increment's, or after
    /// [`LIMIT_CUTBACKS`] cut-backs in a row, instead of cutting back to
    /// `min_increment` first.
    pub(crate) stop_at_limit: bool,
}

/// How a load-controlled run ended.
pub(crate) enum LoadOutcome {
    /// The end of the program, or the observer stopped it.
    Finished(NonlinearRun),
    /// No further increment converges: `run` holds the last converged
    /// increment (its residual evaluated again), `error` the failure
    /// ([`NonlinearError::IncrementTooSmall`]) and `reason` why this is
    /// taken for a limit point.
    Limit {
        run: NonlinearRun,
        error: NonlinearError,
        reason: String,
        /// Taken on an early sign ([`LoadOptions::stop_at_limit`]), not at
        /// `min_increment`: load control could still go on.
        early: bool,
    },
}

/// [`solve_nonlinear`], ending at a limit point with the last converged
/// state instead of only the error.
pub(crate) fn run_load<F>(
    model: &Model,
    solver: &mut dyn LinearSolver,
    program: &[f64],
    settings: &NewtonSettings,
    restart: Option<&Checkpoint>,
    mut observer: F,
    options: LoadOptions,
) -> Result<LoadOutcome, NonlinearError>
where
    F: FnMut(&IncrementView<'_>) -> Control,
{
    let t_run = Instant::now();
    settings.validate()?;
    if program.is_empty() || program.iter().any(|l| !l.is_finite()) {
        return Err(CoreError::Invalid(
            "load program: give at least one finite step end load factor".into(),
        )
        .into());
    }
    let (state, u_start, cur) = load_start(model, program, settings, restart)?;
    let (mut w, timings) = Work::for_run(model, solver, u_start, settings);
    w.analyzed = options.analyzed;
    if cur.exact {
        w.use_exact_tangent();
    }
    let mut run = LoadRun {
        w,
        state,
        cur,
        summary: NonlinearSummary {
            final_lambda: cur.lambda,
            ..Default::default()
        },
        program,
        settings,
        small_size: settings.small_increment(),
        initial_size: settings.initial_increment.min(settings.max_increment),
        stop_at_limit: options.stop_at_limit,
    };
    // residual of the starting point, so that a run with nothing to do
    // still returns a consistent residual
    if restart.is_some() {
        run.w.evaluate_at_rest(&mut run.state, &run.cur)?;
    }
    let mut limit = None;
    while run.advance_step() {
        let before = run.w.timings;
        let inc = match run.converge_increment(solver) {
            Ok(inc) => inc,
            Err((error, Some(sign))) => {
                run.w.evaluate_at_rest(&mut run.state, &run.cur)?;
                limit = Some((error, sign));
                break;
            }
            Err((error, None)) => return Err(error),
        };
        let report = run.commit(solver, &inc, before);
        let view = IncrementView {
            report: &report,
            u: &run.w.u,
            residual: &run.w.res,
            state: &run.state,
            residual_history: &run.w.history,
            cursor: run.cur,
            path: None,
            track: None,
        };
        if observer(&view) == Control::Stop {
            run.summary.stopped_by_observer = true;
            break;
        }
    }
    let LoadRun {
        w,
        state,
        cur,
        mut summary,
        ..
    } = run;
    w.close(&mut summary, timings, t_run);
    let run = NonlinearRun {
        summary,
        u: w.u,
        residual: w.res,
        state,
        cursor: cur,
        path: None,
    };
    Ok(match limit {
        None => LoadOutcome::Finished(run),
        Some((error, sign)) => LoadOutcome::Limit {
            run,
            error,
            reason: sign.why,
            early: sign.early,
        },
    })
}

/// The starting point of a load-controlled run: state, full displacement
/// and cursor, from the unloaded state (first size `small_increment` when
/// an element already wants small increments, else `initial_increment`) or
/// from a checkpoint, checked against the model and the program.
fn load_start(
    model: &Model,
    program: &[f64],
    settings: &NewtonSettings,
    restart: Option<&Checkpoint>,
) -> Result<(StateStore, Vec<f64>, Cursor), NonlinearError> {
    let ndof = model.dofs.num_dofs();
    let mut state = model.initial_state();
    let mut u_start = model.dofs.expand(None, 0.0);
    let cur = match restart {
        Some(c) => {
            check_checkpoint_fits(c, ndof, &state)?;
            if c.step >= program.len() {
                return Err(CoreError::Invalid(format!(
                    "checkpoint is in step {} but the program has {} steps",
                    c.step + 1,
                    program.len()
                ))
                .into());
            }
            state.committed.copy_from_slice(&c.state_committed);
            state.restore();
            u_start.copy_from_slice(&c.u);
            c.cursor()
        }
        None => {
            let small = any_wants_small(model, &state);
            Cursor {
                step: 0,
                t: 0.0,
                lambda: 0.0,
                increment_index: 0,
                size: if small {
                    settings.small_increment()
                } else {
                    settings.initial_increment.min(settings.max_increment)
                },
                small,
                force_peak: 0.0,
                exact: false,
                cutbacks_in_a_row: 0,
                pivots: None,
            }
        }
    };
    Ok((state, u_start, cur))
}

/// A load-controlled run in progress: buffers, state, position in the
/// program and totals.
struct LoadRun<'a> {
    w: Work<'a>,
    state: StateStore,
    cur: Cursor,
    summary: NonlinearSummary,
    program: &'a [f64],
    settings: &'a NewtonSettings,
    /// Increment while an element wants small increments.
    small_size: f64,
    /// First increment of a step.
    initial_size: f64,
    /// See [`LoadOptions::stop_at_limit`].
    stop_at_limit: bool,
}

/// Why a failed increment is taken for a limit point, and whether on an
/// early sign ([`LoadOptions::stop_at_limit`]) rather than below
/// `min_increment`.
struct LimitSign {
    why: String,
    early: bool,
}

/// A converged increment: where it ends (fraction of the step and load
/// factor), its last attempt's iterations, residual and energy, the size
/// that converged and the cut-backs it took.
struct LoadIncrement {
    t_new: f64,
    lambda_new: f64,
    iterations: usize,
    eval: Eval,
    energy: f64,
    size: f64,
    cutbacks: usize,
}

impl LoadRun<'_> {
    /// The largest increment (fraction of a fatigue step of `cycles_span`
    /// cycles) over which no point's damage grows by more than the
    /// program's `max_damage_increment`: `dN = dD_max / max(damage_rate)`
    /// from the committed state ([`junta_core::FatigueProgram`]); 1 when
    /// no point is damaging.
    fn fatigue_size(&self, cycles_span: f64) -> Result<f64, NonlinearError> {
        let model = self.w.model;
        let Some(f) = &model.fatigue else {
            return Ok(1.0);
        };
        let rate = model.max_point_output(
            &self.w.u_conv,
            &self.state,
            junta_core::law::output::DAMAGE_RATE,
        )?;
        Ok(if rate > 0.0 {
            (f.max_damage_increment / (rate * cycles_span)).min(1.0)
        } else {
            1.0
        })
    }

    /// The crack's driving force at the committed state, when the fatigue
    /// program measures it ([`junta_core::FatigueProgram::front_direction`]).
    fn crack_drive(&self) -> Result<Option<junta_core::CrackDrive>, NonlinearError> {
        let model = self.w.model;
        match model.fatigue.as_ref().and_then(|f| f.front_direction) {
            Some(d) => Ok(model.crack_drive(&self.w.u_conv, &self.state, d)?),
            None => Ok(None),
        }
    }

    /// Move on to the next step when the current one is done (its first
    /// increment `initial_increment`, or `small_increment` under the
    /// small-increment rule); false at the end of the program.
    fn advance_step(&mut self) -> bool {
        let cur = &mut self.cur;
        while cur.t >= 1.0 {
            if cur.step + 1 >= self.program.len() {
                return false;
            }
            cur.step += 1;
            cur.t = 0.0;
            cur.size = if cur.small {
                self.small_size
            } else {
                self.initial_size
            };
        }
        true
    }

    /// The next increment from the cursor: attempts of the cursor's size
    /// (the last one of a step shortened to end on the step's load factor),
    /// each failure restoring the converged state and multiplying the size
    /// by `cutback`; below `min_increment` the run stops with
    /// [`NonlinearError::IncrementTooSmall`].
    ///
    /// An [`NonlinearError::IncrementTooSmall`] comes with why it is taken
    /// for a limit point ([`LimitSign`]): the increment fell below
    /// `min_increment`, or (with `stop_at_limit`) an early sign, the failed
    /// attempt's tangent having more negative pivots than the last
    /// converged one's or [`LIMIT_CUTBACKS`] cut-backs in a row.
    fn converge_increment(
        &mut self,
        solver: &mut dyn LinearSolver,
    ) -> Result<LoadIncrement, (NonlinearError, Option<LimitSign>)> {
        let cur = self.cur;
        let start = if cur.step == 0 {
            0.0
        } else {
            self.program[cur.step - 1]
        };
        let end = self.program[cur.step];
        let span = end - start;
        // a step where neither the load factor nor the temperature nor the
        // cycle count moves
        let model = self.w.model;
        let cycles_span = model.cycles(cur.step, 1.0) - model.cycles(cur.step, 0.0);
        let span = if span == 0.0 && model.temperature.is_some() {
            model.temperature_factor(cur.step, 1.0) - model.temperature_factor(cur.step, 0.0)
        } else {
            span
        };
        let span = if span == 0.0 { cycles_span } else { span };
        let mut size = cur.size;
        if cycles_span > 0.0 {
            size = size.min(self.fatigue_size(cycles_span).map_err(|e| (e, None))?);
        }
        // measured in the static steps too: their laws' committed
        // `damage_rate` sizes the first fatigue increment
        let crack_drive = self.crack_drive().map_err(|e| (e, None))?;
        let mut cutbacks = 0;
        loop {
            let t_new = if span == 0.0 || cur.t + size >= 1.0 - 1e-9 {
                1.0
            } else {
                cur.t + size
            };
            let lambda_new = if t_new == 1.0 {
                end
            } else {
                start + t_new * (end - start)
            };
            let step = StepInfo {
                delta_cycles: model.cycles(cur.step, t_new) - model.cycles(cur.step, cur.t),
                crack_drive,
                ..StepInfo::at(cur.increment_index + 1, lambda_new, lambda_new - cur.lambda)
                    .in_program(model, cur.step, t_new)
            };
            let attempt = self
                .w
                .attempt(solver, &mut self.state, step, cur.force_peak)
                .map_err(|e| (e, None))?;
            match attempt {
                Attempt::Converged {
                    iterations,
                    eval,
                    energy,
                } => {
                    return Ok(LoadIncrement {
                        t_new,
                        lambda_new,
                        iterations,
                        eval,
                        energy,
                        size,
                        cutbacks,
                    })
                }
                Attempt::Failed {
                    iterations,
                    rel,
                    reason,
                } => {
                    let exact = self
                        .w
                        .try_exact_tangent(&mut self.state, step, &reason, cur.step)
                        .map_err(|e| (e.into(), None))?;
                    self.state.restore();
                    self.w.u.copy_from_slice(&self.w.u_conv);
                    if exact {
                        // the same increment again, on the exact tangent
                        self.cur.exact = true;
                        continue;
                    }
                    self.summary.cutbacks += 1;
                    cutbacks += 1;
                    let next = (t_new - cur.t) * self.settings.cutback;
                    tracing::warn!(
                        lambda = lambda_new,
                        iterations,
                        residual = rel,
                        next_increment = next,
                        "increment failed ({reason}); cutting back"
                    );
                    let pivots = solver.report().negative_pivots;
                    self.cur.cutbacks_in_a_row += 1;
                    // the early signs of a limit point, where path
                    // following can take over (a step loading away from 0)
                    let early = self.stop_at_limit
                        && crate::path_switch::moves_away_from_zero(self.program, cur.step);
                    let below_min = next < self.settings.min_increment || span == 0.0;
                    let why = if below_min {
                        Some(format!(
                            "the increment was cut back below min_increment = {:e} of the step \
                             ({reason})",
                            self.settings.min_increment
                        ))
                    } else {
                        match (early, cur.pivots, pivots) {
                            (true, Some(before), Some(now)) if now > before => Some(format!(
                                "the tangent's inertia changed: {now} negative pivots in a \
                                 failed attempt against {before} at the last converged increment"
                            )),
                            _ if early && self.cur.cutbacks_in_a_row >= LIMIT_CUTBACKS => {
                                Some(format!(
                                    "{} cut-backs in a row without an increment converging at its \
                                 full size ({reason})",
                                    self.cur.cutbacks_in_a_row
                                ))
                            }
                            _ => None,
                        }
                    };
                    if let Some(why) = why {
                        let error = NonlinearError::IncrementTooSmall {
                            step: cur.step,
                            lambda: cur.lambda,
                            increment: lambda_new - cur.lambda,
                            last_residual: rel,
                            iterations,
                            reason,
                        };
                        let sign = LimitSign {
                            why,
                            early: !below_min,
                        };
                        return Err((error, Some(sign)));
                    }
                    size = next;
                }
            }
        }
    }

    /// Commit a converged increment: state, `u_conv`, cursor and totals.
    /// The next size: `small_increment` while an element wants small
    /// increments, `growth` times larger (at most `max_increment`) after an
    /// increment without cut-back in at most `growth_iterations`
    /// iterations, else unchanged. Returns the increment's report
    /// (`before`: the timings when it started).
    fn commit(
        &mut self,
        solver: &dyn LinearSolver,
        inc: &LoadIncrement,
        before: Timings,
    ) -> IncrementReport {
        let settings = self.settings;
        self.state.commit();
        self.w.u_conv.copy_from_slice(&self.w.u);
        self.w.stalled_attempts = 0;
        let cur = &mut self.cur;
        let delta_lambda = inc.lambda_new - cur.lambda;
        let was_small = cur.small;
        cur.t = inc.t_new;
        cur.lambda = inc.lambda_new;
        cur.increment_index += 1;
        cur.force_peak = cur.force_peak.max(inc.eval.scale_now);
        cur.small = any_wants_small(self.w.model, &self.state);
        cur.size = if cur.small {
            self.small_size
        } else if inc.cutbacks == 0 && inc.iterations <= settings.growth_iterations {
            (inc.size * settings.growth).min(settings.max_increment)
        } else {
            inc.size
        };
        let summary = &mut self.summary;
        summary.increments += 1;
        summary.newton_iterations_max = summary.newton_iterations_max.max(inc.iterations);
        summary.final_lambda = cur.lambda;
        let report = IncrementReport {
            step: cur.step,
            increment_index: cur.increment_index,
            lambda: cur.lambda,
            delta_lambda,
            step_fraction: cur.t,
            temperature_factor: self.w.model.temperature_factor(cur.step, cur.t),
            cycles: self.w.model.cycles(cur.step, cur.t),
            iterations: inc.iterations,
            residual: inc.eval.rel,
            energy: inc.energy,
            cutbacks: inc.cutbacks,
            seconds: increment_timings(self.w.timings, before),
            small_increment_mode: was_small,
            // `lu` (the exact tangent) gives no inertia
            negative_pivots: if inc.iterations > 0 && !self.w.exact {
                solver.report().negative_pivots
            } else {
                None
            },
            control: crate::arc_length::PathMode::Load,
            dissipation: None,
            switched: self.w.exact_switch.take().into_iter().collect(),
        };
        if report.negative_pivots.is_some() {
            self.cur.pivots = report.negative_pivots;
        }
        if inc.cutbacks == 0 {
            self.cur.cutbacks_in_a_row = 0;
        }
        tracing::info!(
            increment = report.increment_index,
            step = report.step,
            lambda = report.lambda,
            delta_lambda,
            iterations = inc.iterations,
            residual = report.residual,
            cutbacks = inc.cutbacks,
            small = was_small,
            "increment converged"
        );
        report
    }
}
