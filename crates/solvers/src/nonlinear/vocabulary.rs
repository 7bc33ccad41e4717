//! The shared vocabulary of the nonlinear drivers: what load control
//! ([`crate::newton`]), path following ([`crate::arc_length`]) and the
//! switch between them ([`crate::path_switch`]) say to each other and to
//! their caller. Each driver imports this module and the Newton engine
//! (`super::engine`); no driver imports another, so there is no import
//! circle (`path_switch` calls both drivers, neither calls it).
//!
//! | items | what |
//! |---|---|
//! | [`NewtonSettings`] | settings of the Newton iterations and the increment size rule |
//! | [`Control`], [`IncrementView`] | the observer's protocol |
//! | [`IncrementFailure`], [`NonlinearError`] | why an attempt or a run failed |
//! | [`IncrementReport`], [`NonlinearSummary`], [`NonlinearRun`] | what an increment and a run did |
//! | [`Checkpoint`] (and the crate's `Cursor`) | the restart point: where a run is in its program |
//! | [`PathMode`], [`PathState`], [`LoadReturn`] | the path-following part of a report and a checkpoint |
//! | [`PathSwitch`], [`LoadTrack`] | the record of a change of control, and what load control keeps for one |
//! | `check_checkpoint_fits`, `increment_timings`, `any_wants_small`, `moves_away_from_zero`, `energy_balance_holds` | small rules every driver applies |
//!
//! The public items are re-exported under the drivers' paths they had
//! before this module existed (`junta_solvers::newton::NewtonSettings`,
//! `junta_solvers::arc_length::PathState`,
//! `junta_solvers::path_switch::PathSwitch`, ...).

use crate::linear_static::Timings;
pub(crate) use crate::nonlinear::engine::Predictor;
use junta_core::element::Kinematics;
use junta_core::state::StateStore;
use junta_core::{CoreError, Model, SolverError};
use serde::{Deserialize, Serialize};
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
    /// On the secant tangent (the fallback of a softening law) the line
    /// search found no decrease of the residual at any step length, this
    /// many iterations in a row: no equilibrium within the increment.
    NoDescent {
        /// Iterations in a row without a decrease.
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
            IncrementFailure::NoDescent { iterations } => write!(
                f,
                "no descent: the line search found no lower residual on the secant tangent for {iterations} iterations in a row"
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
    pub control: PathMode,
    /// Energy dissipated in this increment by the energy balance
    /// `½ (lambda_0 Δa - Δlambda a_0 + p_0 Δlambda - lambda_0 Δp)` (see
    /// [`crate::arc_length`]); arc-length runs only.
    pub dissipation: Option<f64>,
    /// On the first increment after the driver changed the control at a
    /// limit point (or back), or switched to the exact tangent: where and
    /// why ([`crate::path_switch`], `Work::try_exact_tangent` of the engine).
    pub switched: Vec<PathSwitch>,
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
    /// The exact tangent is in use (`Work::try_exact_tangent` of the engine).
    pub(crate) exact: bool,
    /// Cut-backs since the last increment that converged at its full size
    /// (load control's limit-point test).
    pub(crate) cutbacks_in_a_row: usize,
    /// Negative pivots of the last converged increment's tangent, when the
    /// back end reports them.
    pub(crate) pivots: Option<usize>,
}

/// A restart point after a converged increment. Serialisable, so that a
/// front end can write it to disk; [`solve_nonlinear`](crate::newton::solve_nonlinear) continues from it
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
    #[serde(with = "super::packed")]
    pub u: Vec<f64>,
    /// Committed state.
    #[serde(with = "super::packed")]
    pub state_committed: Vec<f64>,
    /// Path-following state (arc-length runs only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub path: Option<PathState>,
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
    pub load_track: Option<LoadTrack>,
    /// The last increment, which the next one's start extrapolates
    /// (finite kinematics under load control only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(crate) predictor: Option<Predictor>,
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
        path: Option<&PathState>,
        track: Option<&LoadTrack>,
        predictor: Option<&Predictor>,
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
            predictor: predictor.cloned(),
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
    pub(crate) path: Option<&'a PathState>,
    pub(crate) track: Option<&'a LoadTrack>,
    pub(crate) predictor: Option<&'a Predictor>,
}

impl IncrementView<'_> {
    /// A restart point after this increment.
    pub fn checkpoint(&self) -> Checkpoint {
        Checkpoint::new(
            &self.cursor,
            self.u,
            self.state,
            self.path,
            self.track,
            self.predictor,
        )
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

/// Result of [`solve_nonlinear`](crate::newton::solve_nonlinear) that ran to the end of its program or was
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
    pub(crate) path: Option<PathState>,
}

impl NonlinearRun {
    /// A restart point at the end of this run.
    pub fn checkpoint(&self) -> Checkpoint {
        Checkpoint::new(
            &self.cursor,
            &self.u,
            &self.state,
            self.path.as_ref(),
            None,
            None,
        )
    }
}

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

/// What constrains an increment.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PathMode {
    /// The load factor is prescribed (load or displacement control).
    #[default]
    Load,
    /// Cylindrical arc length on the displacements.
    Arc,
    /// Energy dissipated in the increment.
    Dissipation,
}

impl PathMode {
    /// Name written to `curve.csv`.
    pub fn name(self) -> &'static str {
        match self {
            PathMode::Load => "load",
            PathMode::Arc => "arc",
            PathMode::Dissipation => "dissipation",
        }
    }
}

/// The path-following part of a restart point.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PathState {
    /// Constraint of the next increment.
    pub mode: PathMode,
    /// Size of the next increment: arc length `Δl` or dissipation `tau`.
    pub size: f64,
    /// First arc length `Δl_0` (0 before the first increment).
    pub arc0: f64,
    /// First dissipation step `tau_0` of the current dissipation phase.
    pub tau0: f64,
    /// Arc length of the last converged increment.
    pub arc_last: f64,
    /// Load factor of the converged increment before the last one.
    pub previous_lambda: f64,
    /// Full displacement of the converged increment before the last one.
    #[serde(with = "super::packed")]
    pub previous_u: Vec<f64>,
    /// Largest load factor reached.
    pub lambda_max: f64,
    /// Largest stored energy met at a converged increment (floor of the
    /// energy scale of the dissipation tests once the load has dropped).
    #[serde(default)]
    pub stored_max: f64,
    /// Dissipation step of the last converged increment when it ran
    /// under the dissipation constraint, else 0 (the secant predictor).
    #[serde(default)]
    pub last_tau: f64,
    /// When path following took over from load control at a limit point
    /// ([`crate::path_switch`]): what tells when load control can take
    /// over again.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub return_to_load: Option<LoadReturn>,
}

/// When path following that took over at a limit point hands back to load
/// (or displacement) control: after it has passed the limit (an increment
/// with a falling load factor, or one under the dissipation constraint),
/// at the second consecutive cylindrical arc-length increment whose load
/// factor rises past the one at the switch, with a tangent whose inertia
/// is back to the one before the switch (when the back end reports it).
/// There the path is a stable, loading branch again, which load control
/// follows.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LoadReturn {
    /// Load factor at the switch (the last converged load-controlled
    /// increment).
    pub lambda_switch: f64,
    /// Negative pivots of the tangent there, when reported.
    pub pivots_switch: Option<usize>,
    /// The path has passed the limit point.
    pub passed: bool,
    /// Consecutive rising arc-length increments past `lambda_switch`.
    pub rising: usize,
}

impl LoadReturn {
    /// Rising increments in a row before load control takes over again.
    const RISING_INCREMENTS: usize = 2;

    /// Account for a converged increment; true when load control can take
    /// over from here.
    pub(crate) fn update(&mut self, r: &IncrementReport, end: f64) -> bool {
        let sign = end.signum();
        let falling = r.delta_lambda * sign < 0.0;
        if falling || r.control == PathMode::Dissipation {
            self.passed = true;
        }
        let stable = match (self.pivots_switch, r.negative_pivots) {
            (Some(before), Some(now)) => now <= before,
            _ => true,
        };
        let rising = r.control == PathMode::Arc
            && r.delta_lambda * sign > 0.0
            && (r.lambda - self.lambda_switch) * sign > 0.0
            && stable;
        self.rising = if rising { self.rising + 1 } else { 0 };
        self.ready()
    }

    /// Load control can take over (also at the start of a run restarted
    /// from a checkpoint taken right where it could).
    pub(crate) fn ready(&self) -> bool {
        self.passed && self.rising >= Self::RISING_INCREMENTS
    }
}

/// Whether the dissipation constraint's global energy balance holds for
/// `model`: the stored energy is `½ u . f_int` (Clapeyron) only where the
/// solids are linear, i.e. every element under small kinematics. Under
/// large deformation (`nlgeom`) it is not: on an elastic path that stiffens
/// as it turns (a peeled arm swinging round to its load) the balance reads
/// unloading as dissipation, and a dissipation-controlled run unloads
/// elastically while it believes a crack is running. Such a model's
/// dissipation constraint (its switch and its rescue) reads the
/// interfaces' energy balance instead (`crate::nonlinear::balance`), and
/// the `max_arc_dissipation` test, which weighs against `½ lambda (a + p)`,
/// is not made.
pub(crate) fn energy_balance_holds(model: &Model) -> bool {
    model
        .elements
        .iter()
        .all(|e| e.kinematics() == Kinematics::Small)
}

/// A change of control at a limit point, or back.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PathSwitch {
    /// The last converged increment before the switch.
    pub increment: usize,
    /// Step (0-based) of the program.
    pub step: usize,
    /// Load factor there.
    pub lambda: f64,
    /// The control after the switch: `arc_length` or `load`.
    pub to: String,
    /// Why.
    pub reason: String,
}

/// Whether step `step` of `program` loads away from zero (path following
/// runs to its end load factor from any point of it).
pub(crate) fn moves_away_from_zero(program: &[f64], step: usize) -> bool {
    let Some(&end) = program.get(step) else {
        return false;
    };
    let start = if step == 0 { 0.0 } else { program[step - 1] };
    end != 0.0 && (start == 0.0 || (start * end > 0.0 && end.abs() > start.abs()))
}

/// The last two converged increments of a load-controlled phase: what
/// path following needs to start from the last one. Part of a
/// load-controlled checkpoint of a `control = "auto"` run, so that a
/// restarted run switches where an uninterrupted one does.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct LoadTrack {
    /// The last increment's displacement (the checkpoint's own `u`).
    #[serde(skip)]
    pub(crate) u_last: Vec<f64>,
    #[serde(with = "super::packed")]
    pub(crate) u_before: Vec<f64>,
    pub(crate) lambda_last: f64,
    pub(crate) lambda_before: f64,
    pub(crate) lambda_max: f64,
    pub(crate) pivots_last: Option<usize>,
    /// Largest arc length of an increment so far.
    pub(crate) arc_max: f64,
    /// Energy the laws report dissipated at the last increment.
    pub(crate) dissipated: f64,
    /// The last increment dissipated (the laws' energy grew).
    pub(crate) dissipating: bool,
    /// Largest energy the laws dissipated in one increment.
    pub(crate) tau_max: f64,
}
