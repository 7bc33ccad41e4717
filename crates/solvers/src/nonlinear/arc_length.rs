//! Path following: the load factor becomes an unknown, so that a run can
//! pass load maxima (limit points) and follow snap-backs, where the load
//! *and* the displacement decrease together.
//!
//! # Equations
//!
//! Everything the model applies is scaled by the load factor `lambda`
//! (forces `lambda f_ext`, prescribed displacements `u_c = lambda ubar_c`),
//! exactly as in [`crate::newton`]. The unknowns of an increment are the
//! free displacements `u` and `lambda`; the residual and its linearisation
//! are
//!
//! ```text
//! r(u, lambda) = f_int,f(u, lambda ubar_c) - lambda f_ext,f
//! K du - q dlambda = -r,     q = f_ext,f - K_fc ubar_c
//! ```
//!
//! (`K = K_ff` the tangent on the free dofs, `K_fc` its coupling to the
//! prescribed dofs, evaluated element by element on the few elements that
//! touch a prescribed displacement). One factorisation of `K` and two
//! solves per iteration give `du = du_I + dlambda du_II` with
//! `du_I = -K^-1 r`, `du_II = K^-1 q` (no bordered matrix, so every back end
//! works, `ldlt` included); a scalar constraint `phi(Δu, Δlambda) = 0` on
//! the increment `Δ` (from the last converged state, index 0) fixes
//! `dlambda`.
//!
//! # Constraints
//!
//! *Cylindrical arc length* (Crisfield 1981), on the elastic branch and
//! wherever nothing dissipates:
//!
//! ```text
//! |Δu|^2 + c Δlambda^2 = Δl^2,      c = |ubar_c|^2
//! ```
//!
//! (the norm of the increment of *all* displacements, prescribed ones
//! included). It is quadratic in `dlambda`; of its two roots the one whose
//! increment makes the smaller angle with the current one is taken, and the
//! predictor's sign follows the previous converged increment
//! (`du_II . Δu_prev + c Δlambda_prev > 0`). Where the quadratic of an
//! iteration has no real root the attempt fails and is cut back. Under
//! large deformation (the interface balance below), when the cut-backs
//! reach the floor (`min_step`) on that failure, the increment is tried
//! once more from its first length with the constraint linearised at the
//! current increment wherever the quadratic has no root,
//!
//! ```text
//! |Δu|^2 + c Δlambda^2 + 2 (Δu . du + c Δlambda dlambda) = Δl^2
//! ```
//!
//! (Newton on the constraint: met as the iterations converge), rather than
//! stopping. (Not under small kinematics: there a stop on it hands the run
//! back to load control under `auto`, e.g. the viscous
//! `examples/delamination/dcb.toml` near 8 mm, whose results are kept.)
//!
//! *Dissipation* (Gutierrez 2004; Verhoosel, Remmers and Gutierrez 2009),
//! once the laws dissipate. For laws with secant unloading
//! (`t = S(state) delta`: the bilinear and exponential cohesive laws, their
//! contact branch, the viscous regularisation) and linear solids, the
//! stored energy is `U = ½ u . f_int` (Clapeyron) and the energy balance
//! `D = W_ext - U` gives, with `a = f_ext,f . u_f` (work-conjugate of the
//! load factor for applied forces) and `p = ubar_c . f_int,c` (the reaction
//! conjugate to the prescribed displacements),
//!
//! ```text
//! dD/dt = ½ (lambda da/dt - a dlambda/dt) + ½ (p dlambda/dt - lambda dp/dt)
//! ΔD ≈ ½ (lambda_0 Δa - Δlambda a_0 + p_0 Δlambda - lambda_0 Δp) = tau
//! ```
//!
//! With a temperature change held over the step (a cure cool-down before
//! the load) the solids' internal force is `K u - f_th`, and the stored
//! energy `½ u . f_int - ½ u . f_th` (up to a constant): the balance gains
//! the term `½ f_th . Δu` (all dofs, prescribed ones included), linear in
//! `du` and `dlambda` like the rest. `f_th` is minus the internal force at
//! zero displacement at the step's temperature.
//!
//! For pure force control this is Verhoosel's
//! `½ f^T (lambda_0 Δu - Δlambda u_0)`; for pure displacement control its
//! mirror in the reaction. It is linear in `Δu` and `Δlambda` except for
//! `Δp`, which is linearised with `dp = g . du + h dlambda`
//! (`g = K_cf^T ubar_c`, `h = ubar_c . K_cc ubar_c`, the same element
//! matrices as `q`). On an elastic branch the balance is identically zero,
//! so the dissipation constraint cannot drive a run there: the driver
//! starts with the cylindrical arc length and switches to the dissipation
//! when a converged increment dissipated more than `switch_dissipation`
//! times the stored energy *and* the laws' own state reports dissipated
//! energy ([`junta_core::Model::dissipated_energy`]); a model whose laws
//! dissipate nothing stays on the cylindrical constraint.
//!
//! *Large deformation.* Under finite kinematics (any element with
//! [`Kinematics::Finite`](junta_core::element::Kinematics::Finite), scene
//! `nlgeom`) the solids' stored energy is not `½ u . f_int`, and the
//! balance above does not hold (`energy_balance_holds` in
//! [`crate::nonlinear::vocabulary`]). The dissipation constraint then reads
//! the interfaces' balance alone, `ΔD_I = ½ (f_I,0 . u - f_I . u_0) = tau`
//! with `f_I` the interface elements' internal force, linearised with their
//! tangent `K_I` (`dΔD_I = ½ (f_I,0 - K_I^T u_0) . du`); both come from the
//! same assembly pass as the residual. The maths, and why this and not the
//! laws' own dissipation, are in `nonlinear/balance.rs`. The
//! switch, the rescue and the fall-back are as under small kinematics; the
//! `max_arc_dissipation` test is not made, and the switch to the
//! dissipation constraint weighs an increment's dissipation against the
//! largest `½ lambda (a + p)` met, not the current one: under large
//! deformation that measure is no stored energy (at the end of a peel, the
//! tape hanging free under a vanishing load, the current one is near zero,
//! and every arc would be cut back or switched for the last traces of
//! dissipation). One test is
//! added: an increment under the interface balance whose laws' own
//! dissipated energy grew by less than half its `tau` counts as failed
//! (the balance is approximate under large rotation, and a long Newton walk
//! can meet it on an elastic branch).
//!
//! When the
//! dissipation constraint cannot be met any more (nothing left that can
//! dissipate, e.g. the crack stopped under a contact zone: the dissipation
//! constraint's correction is not finite, or `tau` fell below 1e-3 of its
//! first value), the driver goes back to the cylindrical constraint, whose
//! predictor then loads (`dlambda` of the sign of the end load factor):
//! unloading would only retrace the path.
//!
//! *Sharp turns.* An arc can jump across a snap-back to another
//! equilibrium branch (e.g. the fully cracked one): an arc-length increment
//! that dissipates more than `max_arc_dissipation` times the stored energy
//! is redone shorter. A snap-back right at damage onset (the loading and
//! the softening branches meet at more than 90 degrees, so the arc's root
//! selection keeps pointing forward and Newton cycles) is entered under the
//! dissipation constraint, started from the failed arc's last iterate,
//! where the tangent is no longer the secant one. The laws give the
//! loading tangent on the damage surface itself (`d_B = d_committed`, the
//! state an increment starts from), so the first iteration of an increment
//! sees the softening.
//!
//! *Iterations.* From the second iteration on, a backtracking line search
//! on `|r|` along `(du, dlambda)` (Newton settings `line_search`,
//! `max_line_search`) breaks the two-cycles of a law's kink; the damped step
//! leaves the constraint unmet and the next iteration, whose constraint is
//! written on the accumulated increment, restores it. Under the arc length
//! (not under the dissipation constraint, whose linearisation degenerates
//! with secant tangents) an iteration that does not reduce the residual
//! switches to the laws' secant tangent for the rest of the attempt, as in
//! [`crate::newton`]. Convergence: the force criterion of
//! [`crate::newton`] (`tol_force`) and, under the dissipation constraint,
//! `|ΔD - tau| <= 1e-6 tau`.
//!
//! This driver shares with [`crate::newton`] the assembly and residual
//! buffers (`Work`, in the crate's `nonlinear::engine`), and the
//! [`Checkpoint`], the observer and its [`IncrementView`] and the restart
//! ([`crate::nonlinear::vocabulary`]); it imports those two modules, not
//! the Newton driver, and has its own increment loop (the constraint, the
//! size rule, the switching and the end of the run).
//!
//! # Increments
//!
//! The first increment is load-controlled with the Newton driver's
//! `initial_increment` (fraction of the step); its displacement norm is the
//! first arc length `Δl_0`. Under the dissipation constraint an increment's
//! iterations start from the converged state, or with `predictor =
//! "secant"` from the last converged increment extrapolated to this one's
//! dissipation step, `u = u_n + (tau / tau_n) Δu_n`, `lambda = lambda_n +
//! (tau / tau_n) Δlambda_n`. Where a crack runs steadily through a fine mesh
//! this start is close (a sixth fewer iterations on the 50k-dof DCB of
//! `bench/dcb_50k.toml`); on a coarse mesh the extrapolation runs past the
//! turning points of the element-by-element saw-tooth and can land on
//! another branch (`examples/delamination/dcb_coarse.toml` unloads to zero
//! with it), so it is not the default. When a secant start fails, the same
//! step is retried from the converged state before any cut-back. After each converged increment the size of the
//! next one (`Δl` or `tau`) is scaled by `sqrt(target_iterations /
//! iterations)`, clamped to `[1/growth, growth]` (Newton settings `growth`)
//! and `tau <= max_dissipation` when given. A failed attempt (same causes
//! as in [`crate::newton`]: iteration limit, divergence, solver or element
//! failure, or a cylindrical constraint without a real root) restores the
//! last converged state and retries with the size times `cutback`; below
//! `min_step` times its first value it stops with
//! [`NonlinearError::IncrementTooSmall`].
//!
//! The run ends when `lambda` reaches the end of the (single-step) program:
//! the increment that would cross it is redone under load control to end
//! exactly there. It also ends when `lambda` falls back to zero after a
//! maximum (the structure carries no load any more: below 1e-6 of its
//! maximum, 1e-4 under the interface balance, where a peeled tape pulled
//! by a dead force hangs from the last softening points of its bond and
//! their traction decays by a few per mille an increment), or after
//! `max_increments` increments. Two rules make that end the end of a
//! crack's run where the structure has not come apart: a
//! dissipation-controlled increment that carries the load factor through
//! zero after its maximum is refused and cut back (up to
//! `ZERO_CROSSING_TRIES` times), and a dissipation constraint that cannot
//! be met (its step below 1e-3 of its first) at a load below
//! `UNLOADED_NO_DISSIPATION` of the maximum ends the run instead of handing
//! over to the arc length, which would reload the delaminated structure
//! (`examples/laminates/curved_beam_plane.toml`: the crack runs out
//! through the loaded end at 3.3e-4 of the peak).
//!
//! # Restart
//!
//! The path state (constraint in use, next size, first arc length, the
//! previous converged displacement and load factor for the predictor's
//! sign) is part of the [`Checkpoint`], so a restarted run computes the
//! increments of an uninterrupted one.

pub use super::arc_length_settings::{ArcLengthSettings, Predictor, PARAMETERS};
pub use super::vocabulary::{LoadReturn, PathMode, PathState};

use super::balance::{
    interface_dissipation, interface_gradient, work_measures, Balance, Base, Coupling,
};
use super::engine::{
    internal_force_at_zero, is_element_error, Abort, Eval, InterfaceShareBuffers, SolveClock, Work,
};
use super::vocabulary::{
    any_wants_small, check_checkpoint_fits, increment_timings, Checkpoint, Control, Cursor,
    IncrementFailure, IncrementReport, IncrementView, NewtonSettings, NonlinearError, NonlinearRun,
    NonlinearSummary,
};
use crate::linear_static::Timings;
use junta_core::dof::CONSTRAINED;
use junta_core::element::StepInfo;
use junta_core::state::StateStore;
use junta_core::{CoreError, LinearSolver, Model};
use std::time::Instant;

/// The failure of an arc-length iteration whose quadratic has no real root.
const NO_REAL_ROOT: &str = "arc-length constraint has no real root";

/// [`PathRun::rescue`]: tries, each a quarter of the last's `tau`.
const RESCUE_TRIES: usize = 3;

/// The load factor, as a share of its maximum, below which a run whose
/// next increment cannot be made (or cannot dissipate) has come to the end
/// of its path: [`PathEnd::Unloaded`].
const UNLOADED_NO_DISSIPATION: f64 = 1e-3;

/// After a maximum, the converged load factor `cur.lambda` lies below
/// [`UNLOADED_NO_DISSIPATION`] of it (on the side of the end load `end`).
fn all_but_unloaded(path: &PathState, cur: &Cursor, end: f64) -> bool {
    path.lambda_max > 0.0 && cur.lambda * end.signum() <= UNLOADED_NO_DISSIPATION * path.lambda_max
}

/// Dissipation attempts of one increment refused for crossing zero
/// ([`PathRun::crosses_zero`]) before a crossing is accepted (the run then
/// ends, [`PathEnd::Unloaded`]).
const ZERO_CROSSING_TRIES: usize = 4;

/// Why a path-following run ended without error.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PathEnd {
    /// The load factor reached the end of the program.
    Completed,
    /// The load factor fell back to zero after a maximum (below 1e-6 times
    /// its maximum, 1e-4 under the interfaces' energy balance, or below
    /// 1e-3 of it when no further increment converges).
    Unloaded,
    /// `max_increments` reached.
    IncrementLimit,
    /// The observer stopped the run.
    Observer,
    /// The path is a stable loading branch again after the limit point
    /// where path following took over ([`LoadReturn`]): load control goes
    /// on from here.
    ReturnToLoad,
}

/// The constraint of one attempt.
#[derive(Debug, Clone, Copy)]
enum Constraint {
    /// Fixed load factor.
    Load(f64),
    /// Cylindrical arc length `Δl`; with `Some(sign)` the predictor goes
    /// in the direction of that sign of `dlambda` (loading), whatever the
    /// previous increment did; `true`: an iteration whose quadratic has no
    /// real root takes the linearised constraint instead
    /// ([`PathAttempt::arc_dlambda`]).
    Arc(f64, Option<f64>, bool),
    /// Dissipation `tau`.
    Dissipation(f64),
}

/// Work vectors of the path-following iteration (by equation).
struct PathWork {
    q: Vec<f64>,
    g: Vec<f64>,
    du2: Vec<f64>,
    /// `du` and `du2` side by side for one two-column solve.
    pair: Vec<f64>,
    /// Δu of the current attempt (by equation).
    delta: Vec<f64>,
    /// Δu of the previous converged increment (by equation).
    delta_prev: Vec<f64>,
    delta_lambda_prev: f64,
    /// Start the next attempt from the secant prediction: the dissipation
    /// step of the previous increment (set per attempt by the increment
    /// loop from [`PathState::last_tau`]).
    extrapolate_from: Option<f64>,
    /// Under the interface balance: `f_I,0`, the interface force of the
    /// converged state (by dof; empty under the global balance).
    interface_base: Vec<f64>,
    /// Under the interface balance: the constraint's gradient `w` by dof
    /// (scratch) and by equation.
    w_full: Vec<f64>,
    w_eq: Vec<f64>,
}

/// What a converged attempt reached.
#[derive(Debug, Clone, Copy)]
struct Convergence {
    iterations: usize,
    /// Relative force residual.
    rel: f64,
    /// Force scale `max(|lambda f_ext,f|, |reactions|)`.
    scale_now: f64,
    /// `ΔD` of the energy balance (module doc).
    dissipation: f64,
}

/// Outcome of one attempt.
enum Attempt {
    Converged(Convergence),
    Failed {
        iterations: usize,
        rel: f64,
        reason: IncrementFailure,
    },
}

fn failed(iterations: usize, rel: f64, reason: IncrementFailure) -> Attempt {
    Attempt::Failed {
        iterations,
        rel,
        reason,
    }
}

/// Run the single-step load program `program` (its end load factor) on
/// `model` with path following, from the unloaded state or from `restart`.
/// See the module documentation for the method; `settings` are the Newton
/// driver's (tolerances, iteration limit, first increment, growth, cut-back).
/// The observer is called after every converged increment as in
/// [`crate::newton::solve_nonlinear`].
pub fn solve_arc_length<F>(
    model: &Model,
    solver: &mut dyn LinearSolver,
    program: &[f64],
    settings: &NewtonSettings,
    arc: &ArcLengthSettings,
    restart: Option<&Checkpoint>,
    observer: F,
) -> Result<(NonlinearRun, PathEnd), NonlinearError>
where
    F: FnMut(&IncrementView<'_>) -> Control,
{
    if program.len() != 1 || !program[0].is_finite() || program[0] == 0.0 {
        return Err(CoreError::Invalid(format!(
            "path following needs a single step with a finite, non-zero end load factor \
             (`steps = [lambda_end]`); the program has {} step(s): {program:?}",
            program.len()
        ))
        .into());
    }
    run_path(
        model, solver, program[0], settings, arc, restart, observer, false,
    )
}

/// [`solve_arc_length`] to the end load factor `end` of the step the
/// cursor is in (`restart`, whose step may be any step of a longer
/// program); `analyzed`: the solver holds the symbolic analysis already.
#[allow(clippy::too_many_arguments)]
pub(crate) fn run_path<F>(
    model: &Model,
    solver: &mut dyn LinearSolver,
    end: f64,
    settings: &NewtonSettings,
    arc: &ArcLengthSettings,
    restart: Option<&Checkpoint>,
    mut observer: F,
    analyzed: bool,
) -> Result<(NonlinearRun, PathEnd), NonlinearError>
where
    F: FnMut(&IncrementView<'_>) -> Control,
{
    let t_run = Instant::now();
    arc.validate()?;
    settings.validate()?;
    let (state, u_start, cur, path) = path_start(model, settings, end, restart)?;
    if model.temperature.is_some()
        && model.temperature_factor(cur.step, 0.0) != model.temperature_factor(cur.step, 1.0)
    {
        return Err(CoreError::Invalid(format!(
            "step {} of the program changes the temperature: path following needs the \
             temperature held (a thermal step runs under load control: control = \"auto\" or \
             \"load\")",
            cur.step + 1
        ))
        .into());
    }
    if model.cycles(cur.step, 0.0) != model.cycles(cur.step, 1.0) {
        return Err(CoreError::Invalid(format!(
            "step {} of the program is a fatigue step (the load held while the cycles run): \
             path following cannot drive it; it runs under load control (control = \"auto\" or \
             \"load\")",
            cur.step + 1
        ))
        .into());
    }
    let (mut w, timings) = Work::for_run(model, solver, u_start, settings);
    w.analyzed = analyzed;
    if cur.exact {
        w.use_exact_tangent()?;
    }
    let mut run = PathRun::new(w, state, cur, path, settings, arc, end)?;
    let mut end_reason = PathEnd::Completed;
    if run
        .path
        .return_to_load
        .as_ref()
        .is_some_and(LoadReturn::ready)
        && run.cur.t < 1.0
    {
        // restarted where load control was to take over
        return run.finish(PathEnd::ReturnToLoad, timings, t_run);
    }
    while run.cur.t < 1.0 {
        if run.cur.increment_index >= arc.max_increments {
            end_reason = PathEnd::IncrementLimit;
            break;
        }
        let before = run.w.timings;
        let Some(inc) = run.converge_increment(solver)? else {
            end_reason = PathEnd::Unloaded;
            break;
        };
        let committed = run.commit(&inc)?;
        run.next_size(&inc, &committed);
        let report = run.report(solver, &inc, &committed, before);
        let hand_back = match &mut run.path.return_to_load {
            Some(r) => r.update(&report, end),
            None => false,
        };
        let view = IncrementView {
            report: &report,
            u: &run.w.u,
            residual: &run.w.res,
            state: &run.state,
            residual_history: &run.w.history,
            cursor: run.cur,
            path: Some(&run.path),
            track: None,
            predictor: None,
        };
        if observer(&view) == Control::Stop {
            run.summary.stopped_by_observer = true;
            end_reason = PathEnd::Observer;
            break;
        }
        let unloaded = match run.balance {
            Balance::Global => 1e-6,
            // a force-pulled arm hanging from the last softening points of
            // a peeled bond: their traction decays along the path by a few
            // per mille an increment
            Balance::Interface => 1e-4,
        };
        if run.path.lambda_max > 0.0
            && run.cur.lambda * end.signum() <= unloaded * run.path.lambda_max
        {
            end_reason = PathEnd::Unloaded;
            break;
        }
        if hand_back && run.cur.t < 1.0 {
            end_reason = PathEnd::ReturnToLoad;
            break;
        }
    }
    run.finish(end_reason, timings, t_run)
}

/// The starting point of a path-following run: state, full displacement,
/// cursor and path state, from the unloaded state (the first increment
/// load-controlled with `initial_increment`) or from a checkpoint of a
/// path-following run, checked against the model.
fn path_start(
    model: &Model,
    settings: &NewtonSettings,
    end: f64,
    restart: Option<&Checkpoint>,
) -> Result<(StateStore, Vec<f64>, Cursor, PathState), NonlinearError> {
    let ndof = model.dofs.num_dofs();
    let mut state = model.initial_state();
    let mut u_start = model.dofs.expand(None, 0.0);
    match restart {
        Some(c) => {
            check_checkpoint_fits(c, ndof, &state)?;
            let Some(p) = &c.path else {
                return Err(CoreError::Invalid(
                    "checkpoint of a load-controlled run: restart it with the same control".into(),
                )
                .into());
            };
            if p.previous_u.len() != ndof || p.size.is_nan() || p.size <= 0.0 {
                return Err(CoreError::Invalid(
                    "checkpoint: path state does not fit the model".into(),
                )
                .into());
            }
            state.committed.copy_from_slice(&c.state_committed);
            state.restore();
            u_start.copy_from_slice(&c.u);
            Ok((state, u_start, c.cursor(), p.clone()))
        }
        None => {
            let cur = Cursor {
                step: 0,
                t: 0.0,
                lambda: 0.0,
                increment_index: 0,
                size: settings.initial_increment.min(settings.max_increment),
                small: false,
                force_peak: 0.0,
                exact: false,
                cutbacks_in_a_row: 0,
                pivots: None,
            };
            let path = PathState {
                mode: PathMode::Load,
                size: settings.initial_increment.min(settings.max_increment) * end.abs(),
                arc0: 0.0,
                tau0: 0.0,
                arc_last: 0.0,
                previous_lambda: 0.0,
                previous_u: u_start.clone(),
                lambda_max: 0.0,
                stored_max: 0.0,
                last_tau: 0.0,
                return_to_load: None,
            };
            Ok((state, u_start, cur, path))
        }
    }
}

/// A path-following run in progress.
struct PathRun<'a> {
    model: &'a Model,
    settings: &'a NewtonSettings,
    arc: &'a ArcLengthSettings,
    /// End load factor of the program.
    end: f64,
    w: Work<'a>,
    pw: PathWork,
    coupling: Coupling,
    state: StateStore,
    cur: Cursor,
    path: PathState,
    /// The converged state the next increment starts from.
    base: Base,
    /// Energy the laws' state reports dissipated at the last converged
    /// increment.
    dissipated_laws: f64,
    /// The energy balance of the dissipation constraint.
    balance: Balance,
    summary: NonlinearSummary,
}

/// What is being tried for one increment: the constraint and its size, and
/// what was tried already.
struct Retry {
    mode: PathMode,
    size: f64,
    /// First size of the constraint's phase (the cut-backs' floor is
    /// `min_step` times it).
    first_size: f64,
    cutbacks: usize,
    /// The dissipation constraint could not be met: the arc length took
    /// over.
    fell_back: bool,
    /// The dissipation rescue of a failed arc was tried.
    rescued: bool,
    /// Start dissipation attempts from the secant prediction.
    extrapolate: bool,
    /// The arc length's iterations without a real root take the
    /// linearised constraint (after the cut-backs of an arc that had none
    /// reached the floor).
    linearised: bool,
    /// The arc length this increment's arc-length phase started with.
    arc_start: f64,
    /// Dissipation attempts of this increment refused for carrying the
    /// load factor through zero ([`PathRun::crosses_zero`]).
    crossings: usize,
}

/// A converged increment: its attempt, what constrained it, the size that
/// converged, its cut-backs, and whether the arc length took over from the
/// dissipation constraint.
struct PathIncrement {
    conv: Convergence,
    control: PathMode,
    size: f64,
    cutbacks: usize,
    fell_back: bool,
}

/// Measures of a committed increment for the next size and the report.
struct Committed {
    delta_lambda: f64,
    /// `sqrt(|Δu|^2 + c Δlambda^2)`.
    arc_len: f64,
    /// Stored energy `½ lambda (a + p)` (floored by the largest met);
    /// under the interface balance the largest met.
    stored: f64,
    /// The laws' own dissipated energy grew.
    laws_dissipate: bool,
}

impl<'a> PathRun<'a> {
    /// The run's work vectors, coupling terms and the energy measures of
    /// the starting point.
    fn new(
        mut w: Work<'a>,
        mut state: StateStore,
        cur: Cursor,
        path: PathState,
        settings: &'a NewtonSettings,
        arc: &'a ArcLengthSettings,
        end: f64,
    ) -> Result<Self, NonlinearError> {
        let model = w.model;
        let nf = model.dofs.num_free;
        let theta = model.temperature_factor(cur.step, 1.0);
        let coupling = Coupling::new(model, internal_force_at_zero(model, &w.asm, theta));
        let balance = Balance::of(model);
        let ndof = model.dofs.num_dofs();
        let interface = balance == Balance::Interface;
        if interface {
            // the probe of every assembly is the converged state u_0
            let mut share = InterfaceShareBuffers::new(ndof);
            share.probe.copy_from_slice(&w.u_conv);
            w.interface_share = Some(share);
        }
        let sized = |n: usize| if interface { vec![0.0; n] } else { Vec::new() };
        let mut pw = PathWork {
            q: vec![0.0; nf],
            g: vec![0.0; nf],
            du2: vec![0.0; nf],
            pair: vec![0.0; 2 * nf],
            delta: vec![0.0; nf],
            delta_prev: vec![0.0; nf],
            delta_lambda_prev: cur.lambda - path.previous_lambda,
            extrapolate_from: None,
            interface_base: sized(ndof),
            w_full: sized(ndof),
            w_eq: sized(nf),
        };
        for (e, &d) in w.free_dofs.iter().enumerate() {
            pw.delta_prev[e] = w.u_conv[d] - path.previous_u[d];
        }
        let summary = NonlinearSummary {
            final_lambda: cur.lambda,
            ..Default::default()
        };
        // state and measures of the starting point
        w.evaluate_at_rest(&mut state, &cur)?;
        if let Some(share) = &w.interface_share {
            pw.interface_base.copy_from_slice(&share.force);
        }
        let (a0, p0, t0) = work_measures(model, &coupling, &w.u, &w.f_int);
        let base = Base {
            lambda: cur.lambda,
            a: a0,
            p: p0,
            t: t0,
        };
        let dissipated_laws = model.dissipated_energy(&w.u_conv, &state)?;
        Ok(PathRun {
            model,
            settings,
            arc,
            end,
            w,
            pw,
            coupling,
            state,
            cur,
            path,
            base,
            dissipated_laws,
            balance,
            summary,
        })
    }

    /// The next increment under the path state's constraint and size. A
    /// failed attempt is retried: from the converged state after a failed
    /// secant start; under the dissipation constraint from the failed
    /// arc's last iterate once ([`PathRun::rescue`]); else cut back
    /// ([`PathRun::cut_back`]). `None`: the load has all but vanished (the
    /// run ends unloaded).
    fn converge_increment(
        &mut self,
        solver: &mut dyn LinearSolver,
    ) -> Result<Option<PathIncrement>, NonlinearError> {
        let path = &self.path;
        let mut r = Retry {
            mode: path.mode,
            size: path.size,
            first_size: match path.mode {
                PathMode::Load => path.size,
                PathMode::Arc => path.arc0,
                PathMode::Dissipation => path.tau0,
            },
            cutbacks: 0,
            fell_back: false,
            rescued: false,
            extrapolate: self.arc.predictor == Predictor::Secant,
            linearised: false,
            arc_start: path.size,
            crossings: 0,
        };
        loop {
            let (outcome, control) = self.try_increment(solver, &mut r)?;
            let (iterations, rel, reason) = match outcome {
                Attempt::Converged(conv) => {
                    return Ok(Some(PathIncrement {
                        conv,
                        control,
                        size: r.size,
                        cutbacks: r.cutbacks,
                        fell_back: r.fell_back,
                    }))
                }
                Attempt::Failed {
                    iterations,
                    rel,
                    reason,
                } => (iterations, rel, reason),
            };
            if self.try_exact_tangent(&reason)? {
                // the same increment again, on the exact tangent
                continue;
            }
            // a failed secant start: the same step again from the
            // converged state before any cut-back
            if self.pw.extrapolate_from.is_some() {
                tracing::info!(
                    lambda = self.cur.lambda,
                    size = r.size,
                    "path increment failed from the secant prediction ({reason}); retrying from the converged state"
                );
                restore(&mut self.w, &mut self.state);
                r.extrapolate = false;
                continue;
            }
            if r.mode == PathMode::Arc && !r.rescued {
                r.rescued = true;
                if let Some((conv, tau)) = self.rescue(solver)? {
                    return Ok(Some(PathIncrement {
                        conv,
                        control: PathMode::Dissipation,
                        size: tau,
                        cutbacks: r.cutbacks,
                        fell_back: r.fell_back,
                    }));
                }
            }
            if !self.cut_back(&mut r, iterations, rel, reason)? {
                return Ok(None);
            }
        }
    }

    /// The constraint of an attempt of size `r.size`: a load step (ending
    /// on the end of the program at the latest), the arc length (loading,
    /// `dlambda` of the sign of the end, after a dissipation phase: nothing
    /// more dissipates on this path, and unloading would retrace it), or
    /// the dissipation.
    fn constraint(&self, r: &Retry) -> Constraint {
        let end = self.end;
        match r.mode {
            PathMode::Load => {
                let l = self.cur.lambda + r.size.copysign(end);
                Constraint::Load(if (l - end) * end.signum() > 0.0 {
                    end
                } else {
                    l
                })
            }
            PathMode::Arc => Constraint::Arc(
                r.size,
                (self.path.tau0 > 0.0).then_some(end.signum()),
                r.linearised,
            ),
            PathMode::Dissipation => Constraint::Dissipation(r.size),
        }
    }

    /// One attempt of the increment `r`, and what constrained it. A
    /// converged increment that crosses the end of the program is redone
    /// under load control to end exactly there; an arc-length or load
    /// increment that dissipated more than `max_arc_dissipation` times the
    /// stored energy counts as failed (a long arc may have jumped to
    /// another branch across a snap-back: a shorter one follows); so does
    /// a dissipation increment that carries the load factor through zero
    /// after its maximum, up to `ZERO_CROSSING_TRIES` times an increment
    /// (counted in `r.crossings`).
    fn try_increment(
        &mut self,
        solver: &mut dyn LinearSolver,
        r: &mut Retry,
    ) -> Result<(Attempt, PathMode), NonlinearError> {
        let end = self.end;
        let constraint = self.constraint(r);
        self.pw.extrapolate_from =
            (r.extrapolate && r.mode == PathMode::Dissipation && self.path.last_tau > 0.0)
                .then_some(self.path.last_tau);
        let mut outcome = self.attempt(solver, constraint, false)?;
        if let Attempt::Converged(_) = outcome {
            let lam = lambda_now(&self.w);
            if r.mode != PathMode::Load && (lam - end) * end.signum() > 0.0 {
                restore(&mut self.w, &mut self.state);
                outcome = self.attempt(solver, Constraint::Load(end), false)?;
                if let Attempt::Converged(_) = outcome {
                    return Ok((outcome, PathMode::Load));
                }
            }
        }
        if let Attempt::Converged(c) = outcome {
            let (a1, p1, _) = work_measures(self.model, &self.coupling, &self.w.u, &self.w.f_int);
            let stored = (0.5 * lambda_now(&self.w) * (a1 + p1))
                .abs()
                .max(1e-9 * self.path.stored_max);
            let dissipation = c.dissipation;
            if r.mode != PathMode::Dissipation
                && self.balance == Balance::Global
                && dissipation > self.arc.max_arc_dissipation * stored
            {
                outcome = failed(
                    c.iterations,
                    c.rel,
                    IncrementFailure::Element(format!(
                        "the increment dissipated {dissipation:.3e}, {:.1} % of the stored \
                         energy {stored:.3e} (limit max_arc_dissipation = {}): shorter arc",
                        100.0 * dissipation / stored.abs().max(f64::MIN_POSITIVE),
                        self.arc.max_arc_dissipation
                    )),
                );
            } else if r.mode == PathMode::Dissipation
                && r.crossings < ZERO_CROSSING_TRIES
                && self.crosses_zero()
            {
                r.crossings += 1;
                outcome = failed(
                    c.iterations,
                    c.rel,
                    IncrementFailure::Element(format!(
                        "the increment carried the load factor through zero after its maximum \
                         ({:.3e} -> {:.3e}): a shorter dissipation step finds where the crack's \
                         run ends",
                        self.cur.lambda,
                        lambda_now(&self.w)
                    )),
                );
            } else if let Some(reason) = self.laws_disagree(&r.mode, dissipation)? {
                outcome = failed(c.iterations, c.rel, reason);
            }
        }
        Ok((outcome, r.mode))
    }

    /// The trial load factor lies on the other side of zero from the
    /// converged one, after a maximum: the dissipation step ran past the
    /// end of a crack's run (where the load returns to zero with the
    /// structure still whole, e.g. the curved beam of
    /// `examples/laminates/curved_beam_plane.toml`, whose crack runs out
    /// through the loaded end) onto a branch of reversed load.
    fn crosses_zero(&self) -> bool {
        let sign = self.end.signum();
        self.path.lambda_max > 0.0
            && self.cur.lambda * sign > 0.0
            && lambda_now(&self.w) * sign < 0.0
    }

    /// Under the interface balance, a dissipation-controlled increment
    /// whose laws' own dissipation (from the trial state,
    /// [`Model::dissipated_energy`]) grew by less than half its `tau`: the
    /// balance is exact for small interface kinematics only, and a long
    /// Newton walk (the arms swinging back through a large rotation) can
    /// meet `ΔD_I = tau` on an elastic branch where nothing dissipates. The
    /// increment then counts as failed, and a shorter one follows.
    fn laws_disagree(
        &mut self,
        mode: &PathMode,
        tau: f64,
    ) -> Result<Option<IncrementFailure>, NonlinearError> {
        if *mode != PathMode::Dissipation || self.balance != Balance::Interface {
            return Ok(None);
        }
        // the laws read the committed state: hand them the trial one
        std::mem::swap(&mut self.state.committed, &mut self.state.trial);
        let d = self.model.dissipated_energy(&self.w.u, &self.state);
        std::mem::swap(&mut self.state.committed, &mut self.state.trial);
        let d_laws = d? - self.dissipated_laws;
        Ok((d_laws < 0.5 * tau).then(|| {
            IncrementFailure::Element(format!(
                "the laws dissipated {d_laws:.3e} in an increment whose interface balance \
                 dissipated {tau:.3e}: another branch; shorter step"
            ))
        }))
    }

    /// [`Work::try_exact_tangent`] at the failed attempt's last iterate;
    /// on a switch the converged state is restored.
    fn try_exact_tangent(&mut self, reason: &IncrementFailure) -> Result<bool, NonlinearError> {
        let lambda = lambda_now(&self.w);
        let step = StepInfo::at(
            self.cur.increment_index + 1,
            lambda,
            lambda - self.cur.lambda,
        )
        .in_program(self.w.model, self.cur.step, 1.0);
        let program_step = self.cur.step;
        if !self
            .w
            .try_exact_tangent(&mut self.state, step, reason, program_step)?
        {
            return Ok(false);
        }
        restore(&mut self.w, &mut self.state);
        self.cur.exact = true;
        Ok(true)
    }

    /// An arc that failed at a sharp turn (module docs, *Sharp turns*) with
    /// a damaging last iterate: from there the dissipation constraint is
    /// tried warm with `tau` = the iterate's dissipation (at most
    /// `max_arc_dissipation` times the stored energy), then a quarter and a
    /// sixteenth of it (a whole front softening at once can overshoot).
    /// Returns the converged increment and `tau`.
    fn rescue(
        &mut self,
        solver: &mut dyn LinearSolver,
    ) -> Result<Option<(Convergence, f64)>, NonlinearError> {
        let base = self.base;
        let d_try = balance_dissipation(
            self.balance,
            &self.w,
            &self.pw,
            &self.coupling,
            &base,
            lambda_now(&self.w),
        );
        let stored = 0.5 * base.lambda * (base.a + base.p);
        if !(d_try.is_finite() && d_try > self.arc.switch_dissipation * stored.abs()) {
            return Ok(None);
        }
        let mut tau = d_try.min(self.arc.max_arc_dissipation * stored.abs());
        let (u_iterate, lambda_iterate) = (self.w.u.clone(), self.w.lambda_trial);
        for k in 0..RESCUE_TRIES {
            if k > 0 {
                self.w.u.copy_from_slice(&u_iterate);
                self.w.lambda_trial = lambda_iterate;
            }
            if let Attempt::Converged(conv) =
                self.attempt(solver, Constraint::Dissipation(tau), true)?
            {
                if self.crosses_zero() {
                    tau *= 0.25;
                    continue;
                }
                tracing::info!(
                    tau,
                    "arc length failed at a sharp turn: continued under dissipation control"
                );
                return Ok(Some((conv, tau)));
            }
            tau *= 0.25;
        }
        Ok(None)
    }

    /// After a failed attempt: restore the converged state and shorten the
    /// step. A dissipation constraint that cannot be met (its correction
    /// not finite, or `tau` below 1e-3 of its first value) gives way once to
    /// the arc length, with the last increment's length; otherwise the size
    /// is multiplied by `cutback`. Below `min_step` times the first size
    /// (`min_increment` under load control) the run ends: `Ok(false)` when
    /// the load has all but vanished after its maximum (the structure came
    /// apart), else [`NonlinearError::IncrementTooSmall`].
    fn cut_back(
        &mut self,
        r: &mut Retry,
        iterations: usize,
        rel: f64,
        reason: IncrementFailure,
    ) -> Result<bool, NonlinearError> {
        let (settings, arc, end) = (self.settings, self.arc, self.end);
        let (path, cur) = (&self.path, &self.cur);
        restore(&mut self.w, &mut self.state);
        self.summary.cutbacks += 1;
        r.cutbacks += 1;
        tracing::warn!(
            lambda = cur.lambda,
            iterations,
            residual = rel,
            control = r.mode.name(),
            size = r.size,
            "path increment failed ({reason}); cutting back"
        );
        if r.mode == PathMode::Dissipation
            && !r.fell_back
            && (r.size * settings.cutback < 1e-3 * path.tau0
                || matches!(reason, IncrementFailure::NonFinite))
            && path.arc_last > 0.0
        {
            if all_but_unloaded(path, cur, end) {
                // the end of a crack's run: the load is all but gone and
                // nothing dissipates at a positive load any more; an arc
                // from here would reload another structure (the
                // delaminated one), not continue this crack
                return Ok(false);
            }
            r.fell_back = true;
            r.mode = PathMode::Arc;
            r.size = path.arc_last;
            r.arc_start = path.arc_last;
            return Ok(true);
        }
        r.size *= settings.cutback;
        let floor = match r.mode {
            PathMode::Load => settings.min_increment * end.abs(),
            PathMode::Arc if r.fell_back => path.arc0 * arc.min_step,
            _ => r.first_size * arc.min_step,
        };
        if r.size < floor {
            // e.g. a fully cracked interface under force control, where
            // no equilibrium carries a load any more
            if all_but_unloaded(path, cur, end) {
                return Ok(false);
            }
            if r.mode == PathMode::Arc
                && !r.linearised
                && self.balance == Balance::Interface
                && matches!(&reason, IncrementFailure::Element(m) if m == NO_REAL_ROOT)
            {
                // the arc could not be met at any length: once more from its
                // first length, with the linearised constraint where the
                // quadratic has no root, rather than stopping
                tracing::warn!(
                    lambda = cur.lambda,
                    size = r.arc_start,
                    "{NO_REAL_ROOT} down to the smallest arc: the linearised arc-length constraint from the first length"
                );
                r.linearised = true;
                r.size = r.arc_start;
                return Ok(true);
            }
            return Err(NonlinearError::IncrementTooSmall {
                step: cur.step,
                lambda: cur.lambda,
                increment: r.size,
                last_residual: rel,
                iterations,
                reason,
            });
        }
        Ok(true)
    }

    /// Commit a converged increment: the state, `u_conv` and the previous
    /// increment (for the predictor's sign and the secant start), the
    /// energy measures of the new base state, the cursor and the path's
    /// records (last arc length, largest load factor and stored energy).
    fn commit(&mut self, inc: &PathIncrement) -> Result<Committed, NonlinearError> {
        let (model, end) = (self.model, self.end);
        let (w, pw, path, cur) = (&mut self.w, &mut self.pw, &mut self.path, &mut self.cur);
        self.state.commit();
        let lambda_new = lambda_now(w);
        w.committed(cur.increment_index + 1, cur.step, lambda_new)?;
        for (e, &d) in w.free_dofs.iter().enumerate() {
            pw.delta_prev[e] = w.u[d] - w.u_conv[d];
        }
        let arc_len = (pw.delta_prev.iter().map(|v| v * v).sum::<f64>()
            + self.coupling.c * (lambda_new - cur.lambda).powi(2))
        .sqrt();
        pw.delta_lambda_prev = lambda_new - cur.lambda;
        path.last_tau = if inc.control == PathMode::Dissipation {
            inc.size
        } else {
            0.0
        };
        path.previous_u.copy_from_slice(&w.u_conv);
        path.previous_lambda = cur.lambda;
        w.u_conv.copy_from_slice(&w.u);
        if let Some(share) = &mut w.interface_share {
            // the new base of the interface balance: f_I,0 and u_0
            share.probe.copy_from_slice(&w.u);
            pw.interface_base.copy_from_slice(&share.force);
        }
        let delta_lambda = lambda_new - cur.lambda;
        let (a1, p1, t1) = work_measures(model, &self.coupling, &w.u, &w.f_int);
        let stored = (0.5 * lambda_new * (a1 + p1)).abs();
        path.stored_max = path.stored_max.max(stored);
        let stored = match self.balance {
            Balance::Global => stored.max(1e-9 * path.stored_max),
            // `½ lambda (a + p)` is no stored energy under large
            // deformation: the switch weighs against the largest met
            Balance::Interface => path.stored_max,
        };
        let d_laws = model.dissipated_energy(&w.u, &self.state)?;
        let laws_dissipate = d_laws > self.dissipated_laws;
        self.dissipated_laws = d_laws;
        self.base = Base {
            lambda: lambda_new,
            a: a1,
            p: p1,
            t: t1,
        };
        cur.lambda = lambda_new;
        cur.t = if inc.control == PathMode::Load && lambda_new == end {
            1.0
        } else {
            (lambda_new / end).clamp(-1.0, 1.0 - 1e-12)
        };
        cur.increment_index += 1;
        cur.force_peak = cur.force_peak.max(inc.conv.scale_now);
        cur.small = any_wants_small(model, &self.state);
        path.arc_last = arc_len;
        path.lambda_max = path.lambda_max.max(lambda_new * end.signum());
        Ok(Committed {
            delta_lambda,
            arc_len,
            stored,
            laws_dissipate,
        })
    }

    /// The constraint and size of the next increment. The size is scaled by
    /// `sqrt(target_iterations / iterations)` within `[1/growth, growth]`
    /// (not above 1 after a cut-back). The first, load-controlled increment
    /// sets the first arc length; an increment that dissipated more than
    /// `switch_dissipation` times the stored energy, with the laws
    /// reporting dissipation, switches to the dissipation constraint (`tau`
    /// = that dissipation, at most `max_dissipation`); an arc that took
    /// over from the dissipation constraint stays until the laws dissipate
    /// again.
    fn next_size(&mut self, inc: &PathIncrement, c: &Committed) {
        let (settings, arc, path) = (self.settings, self.arc, &mut self.path);
        let (control, size, dissipation) = (inc.control, inc.size, inc.conv.dissipation);
        let scale = ((arc.target_iterations as f64) / (inc.conv.iterations.max(1) as f64))
            .sqrt()
            .clamp(1.0 / settings.growth.max(1.0 + 1e-9), settings.growth);
        let scale = if inc.cutbacks > 0 {
            scale.min(1.0)
        } else {
            scale
        };
        match control {
            PathMode::Load if path.mode == PathMode::Load => {
                // first increment: it sets the arc length
                path.arc0 = c.arc_len;
                path.mode = PathMode::Arc;
                path.size = c.arc_len;
            }
            PathMode::Load => {}
            PathMode::Arc => {
                path.mode = PathMode::Arc;
                path.size = (size * scale).min(arc.max_arc * path.arc0);
            }
            PathMode::Dissipation => {
                if path.mode != PathMode::Dissipation {
                    // entered by the rescue of a failed arc
                    path.mode = PathMode::Dissipation;
                    path.tau0 = size;
                }
                path.size = size * scale;
                if let Some(m) = arc.max_dissipation {
                    path.size = path.size.min(m);
                }
            }
        }
        if control != PathMode::Dissipation
            && c.laws_dissipate
            && dissipation > arc.switch_dissipation * c.stored.abs()
        {
            path.mode = PathMode::Dissipation;
            path.tau0 = dissipation;
            path.size = dissipation;
            if let Some(m) = arc.max_dissipation {
                path.size = path.size.min(m);
            }
        }
        if control == PathMode::Arc && inc.fell_back {
            // stay on the arc length until the laws dissipate again
            path.mode = PathMode::Arc;
            path.size = size;
            if c.laws_dissipate && dissipation > arc.switch_dissipation * c.stored.abs() {
                path.mode = PathMode::Dissipation;
                path.tau0 = dissipation;
                path.size = dissipation;
            }
        }
    }

    /// Count a committed increment in the totals and report it (`before`:
    /// the timings when it started).
    fn report(
        &mut self,
        solver: &dyn LinearSolver,
        inc: &PathIncrement,
        c: &Committed,
        before: Timings,
    ) -> IncrementReport {
        let (cur, conv) = (&self.cur, &inc.conv);
        let summary = &mut self.summary;
        summary.increments += 1;
        summary.newton_iterations_max = summary.newton_iterations_max.max(conv.iterations);
        summary.final_lambda = cur.lambda;
        let report = IncrementReport {
            step: cur.step,
            increment_index: cur.increment_index,
            lambda: cur.lambda,
            delta_lambda: c.delta_lambda,
            step_fraction: cur.t,
            temperature_factor: self.w.model.temperature_factor(cur.step, 1.0),
            cycles: self.w.model.cycles(cur.step, 1.0),
            iterations: conv.iterations,
            residual: conv.rel,
            energy: 0.0,
            cutbacks: inc.cutbacks,
            seconds: increment_timings(self.w.timings, before),
            small_increment_mode: false,
            // `lu` (the exact tangent) gives no inertia
            negative_pivots: if self.w.exact {
                None
            } else {
                solver.report().negative_pivots
            },
            control: inc.control,
            dissipation: Some(conv.dissipation),
            switched: self.w.exact_switch.take().into_iter().collect(),
        };
        tracing::info!(
            increment = report.increment_index,
            lambda = report.lambda,
            delta_lambda = c.delta_lambda,
            iterations = conv.iterations,
            control = inc.control.name(),
            dissipation = conv.dissipation,
            "path increment converged"
        );
        report
    }

    /// The end of the run: the residual (reactions) of the last converged
    /// state (an attempt that failed after it may have left its own in the
    /// buffers) and the totals.
    fn finish(
        self,
        end_reason: PathEnd,
        timings: Timings,
        t_run: Instant,
    ) -> Result<(NonlinearRun, PathEnd), NonlinearError> {
        let PathRun {
            mut w,
            mut state,
            cur,
            path,
            mut summary,
            ..
        } = self;
        w.u.copy_from_slice(&w.u_conv);
        w.evaluate_at_rest(&mut state, &cur)?;
        w.close(&mut summary, timings, t_run);
        Ok((
            NonlinearRun {
                summary,
                u: w.u,
                residual: w.res,
                state,
                cursor: cur,
                path: Some(path),
            },
            end_reason,
        ))
    }

    /// One attempt of an increment from the converged state (`w.u_conv`,
    /// `cur.lambda`) under `constraint` ([`PathAttempt`]); `warm`: from the
    /// current trial instead. On success `w.u`, `w.lambda_trial`, `w.res`,
    /// `w.f_int` and the trial state hold the converged increment.
    fn attempt(
        &mut self,
        solver: &mut dyn LinearSolver,
        constraint: Constraint,
        warm: bool,
    ) -> Result<Attempt, NonlinearError> {
        let mut exact = self.w.exact_solver.take();
        let solver: &mut dyn LinearSolver = match exact.as_deref_mut() {
            Some(lu) => lu,
            None => solver,
        };
        let r = self.attempt_with(solver, constraint, warm);
        self.w.exact_solver = exact;
        r
    }

    /// [`PathRun::attempt`] with the back end in use.
    fn attempt_with(
        &mut self,
        solver: &mut dyn LinearSolver,
        constraint: Constraint,
        warm: bool,
    ) -> Result<Attempt, NonlinearError> {
        let mut a = PathAttempt {
            w: &mut self.w,
            pw: &mut self.pw,
            coupling: &mut self.coupling,
            solver,
            state: &mut self.state,
            cur: &self.cur,
            base: self.base,
            balance: self.balance,
            constraint,
            lambda: 0.0,
            secant: false,
            ev: Eval {
                abs: f64::NAN,
                rel: f64::NAN,
                scale_now: 0.0,
            },
        };
        match a.run(warm) {
            Ok(outcome) | Err(Abort::Failed(outcome)) => Ok(outcome),
            Err(Abort::Fatal(e)) => Err(e),
        }
    }
}

/// `ΔD` of `balance` from the converged state `base` to the trial point
/// (`w.u`, `lambda`) whose assembly `w` holds.
fn balance_dissipation(
    balance: Balance,
    w: &Work<'_>,
    pw: &PathWork,
    coupling: &Coupling,
    base: &Base,
    lambda: f64,
) -> f64 {
    match (balance, &w.interface_share) {
        (Balance::Interface, Some(share)) => interface_dissipation(&pw.interface_base, &w.u, share),
        _ => {
            let (a, p, t) = work_measures(w.model, coupling, &w.u, &w.f_int);
            base.dissipation(a, p, t, lambda)
        }
    }
}

/// The load factor of the current trial (set by [`PathRun::attempt`]).
fn lambda_now(w: &Work<'_>) -> f64 {
    w.lambda_trial
}

fn restore(w: &mut Work<'_>, state: &mut StateStore) {
    state.restore();
    w.u.copy_from_slice(&w.u_conv);
}

/// One attempt in progress: the run's buffers, the constraint, and the
/// trial point (`w.u`, `lambda`) with its residual.
struct PathAttempt<'r, 'm> {
    w: &'r mut Work<'m>,
    pw: &'r mut PathWork,
    coupling: &'r mut Coupling,
    solver: &'r mut dyn LinearSolver,
    state: &'r mut StateStore,
    /// The converged state the increment starts from.
    cur: &'r Cursor,
    base: Base,
    balance: Balance,
    constraint: Constraint,
    /// Load factor of the trial point.
    lambda: f64,
    /// The laws' secant tangent is in use (fallback).
    secant: bool,
    /// Residual at the trial point.
    ev: Eval,
}

impl PathAttempt<'_, '_> {
    /// The attempt: the start ([`PathAttempt::start`]), then iterations of
    /// tangent, the two solves, `dlambda` from the constraint, line search
    /// and the secant fallback, until the force criterion (and under the
    /// dissipation constraint `|ΔD - tau| <= 1e-6 tau`) holds or the
    /// attempt fails (iteration limit, divergence past `divergence_ratio`
    /// times the first iteration's residual, solver or element failure,
    /// no real root of the arc length, a non-finite correction).
    fn run(&mut self, warm: bool) -> Result<Attempt, Abort<Attempt>> {
        self.start(warm);
        self.evaluate(0)?;
        self.w.history.push(self.ev.rel);
        let rho0 = self.ev.abs.max(f64::MIN_POSITIVE);
        let nf = self.w.free_dofs.len();
        let mut rho_first = 0.0;
        let mut rho_prev = f64::INFINITY;
        let max_iterations = self.w.settings.max_iterations;
        if self.w.contact_allowance > 0 {
            let w = &mut *self.w;
            w.model
                .contact_statuses(&w.u, self.state, &mut w.contact_status)?;
        }
        // contact iterations do not count (the `newton` module doc)
        let (mut counted, mut it) = (0, 0);
        while counted < max_iterations && it < max_iterations + self.w.contact_allowance {
            it += 1;
            self.w.iterations += 1;
            let h = self.tangent(it)?;
            self.solve(it)?;
            let dl = self.dlambda(it, h)?;
            // du = du_I + dlambda du_II
            for e in 0..nf {
                self.w.du[e] += dl * self.pw.du2[e];
            }
            if !self.w.du.iter().all(|v| v.is_finite()) {
                return Err(self.fail(it, IncrementFailure::NonFinite));
            }
            self.line_search(it, dl)?;
            self.secant_fallback(it, rho_prev)?;
            rho_prev = self.ev.abs;
            if it == 1 {
                rho_first = self.ev.abs.max(rho0);
            }
            if self.w.contact_switches(self.state)? > 0 {
                rho_first = rho_first.max(self.ev.abs);
            } else {
                counted += 1;
            }
            if let Some(done) = self.checks(it, rho_first) {
                return Ok(done);
            }
        }
        Ok(failed(it, self.ev.rel, IncrementFailure::IterationLimit))
    }

    /// The first trial point: the converged displacements with the load
    /// factor unchanged (the first iteration's constraint gives the
    /// predictor) or the prescribed one. With the secant predictor under
    /// the dissipation constraint: the last increment scaled to this one's
    /// dissipation step, `u = u_n + (tau / tau_n) Δu_n`, `lambda = lambda_n
    /// + (tau / tau_n) Δlambda_n`. `warm`: the current trial (`w.u`,
    /// `w.lambda_trial`).
    fn start(&mut self, warm: bool) {
        let cur_lambda = self.cur.lambda;
        self.lambda = match self.constraint {
            Constraint::Load(l) => l,
            _ if warm => self.w.lambda_trial,
            _ => cur_lambda,
        };
        if !warm {
            self.w.u.copy_from_slice(&self.w.u_conv);
            if let Constraint::Dissipation(tau) = self.constraint {
                if let Some(last_tau) = self.pw.extrapolate_from {
                    // the last increment, scaled to this one's dissipation
                    let s = tau / last_tau;
                    for (e, &d) in self.w.free_dofs.iter().enumerate() {
                        self.w.u[d] += s * self.pw.delta_prev[e];
                    }
                    self.lambda = cur_lambda + s * self.pw.delta_lambda_prev;
                }
            }
        }
        self.set_prescribed();
        self.w.lambda_trial = self.lambda;
        for (e, &d) in self.w.free_dofs.iter().enumerate() {
            self.pw.delta[e] = self.w.u[d] - self.w.u_conv[d];
        }
        self.w.history.clear();
    }

    /// The prescribed dofs at `lambda * ubar`; the dependents of linear
    /// equations follow their free and prescribed terms.
    fn set_prescribed(&mut self) {
        let model = self.w.model;
        for (d, u) in self.w.u.iter_mut().enumerate() {
            if model.dofs.eq[d] == CONSTRAINED {
                *u = self.lambda * model.dofs.prescribed[d];
            }
        }
        model.dofs.fill_dependents(&mut self.w.u);
    }

    /// The trial point `u = u_base + s du`, `lambda = lambda_base + s
    /// dlambda`.
    fn move_to(&mut self, s: f64, lambda_base: f64, dl: f64) {
        for (e, &d) in self.w.free_dofs.iter().enumerate() {
            self.w.u[d] = self.w.u_base[d] + s * self.w.du[e];
        }
        self.lambda = lambda_base + s * dl;
        self.set_prescribed();
    }

    fn step(&self) -> StepInfo {
        StepInfo {
            secant: self.secant,
            ..StepInfo::at(
                self.cur.increment_index + 1,
                self.lambda,
                self.lambda - self.cur.lambda,
            )
            .in_program(self.w.model, self.cur.step, 1.0)
        }
    }

    /// The attempt failed at iteration `it` (with the last residual).
    fn fail(&self, it: usize, reason: IncrementFailure) -> Abort<Attempt> {
        Abort::Failed(failed(it, self.ev.rel, reason))
    }

    /// Assemble and evaluate the residual at the trial point into `ev`. An
    /// element error fails the attempt (iteration `it`), any other error is
    /// fatal.
    fn evaluate(&mut self, it: usize) -> Result<(), Abort<Attempt>> {
        let step = self.step();
        match self
            .w
            .evaluate(self.state, step, self.lambda, self.cur.force_peak)
        {
            Ok(e) => {
                self.ev = e;
                Ok(())
            }
            Err(e) if is_element_error(&e) => {
                Err(self.fail(it, IncrementFailure::Element(e.to_string())))
            }
            Err(e) => Err(e.into()),
        }
    }

    /// Factorise the tangent at the trial point and, off load control,
    /// compute `q`, `g` and `h` there (element matrices at the trial `u`;
    /// module doc). Returns `h`.
    fn tangent(&mut self, it: usize) -> Result<f64, Abort<Attempt>> {
        self.w.analyze_once(self.solver)?;
        if let Err(e) = self.w.factorize(self.solver) {
            return Err(self.fail(it, IncrementFailure::Solver(e)));
        }
        if matches!(self.constraint, Constraint::Load(_)) {
            return Ok(0.0);
        }
        let step = self.step();
        match self.coupling.compute(
            self.w.model,
            &self.w.u,
            self.state,
            step,
            &mut self.pw.q,
            &mut self.pw.g,
        ) {
            Ok(h) => Ok(h),
            Err(e) if is_element_error(&e) => {
                Err(self.fail(it, IncrementFailure::Element(e.to_string())))
            }
            Err(e) => Err(e.into()),
        }
    }

    /// `du_I = -K^-1 r` into `w.du` and, off load control, `du_II = K^-1 q`
    /// into `pw.du2` (both right-hand sides in one pass over the factor).
    fn solve(&mut self, it: usize) -> Result<(), Abort<Attempt>> {
        let (w, pw) = (&mut *self.w, &mut *self.pw);
        for (du, &r) in w.du.iter_mut().zip(&w.res_f) {
            *du = -r;
        }
        let clock = SolveClock::start(self.solver);
        let r = if matches!(self.constraint, Constraint::Load(_)) {
            w.solves += 1;
            self.solver.solve_in_place(&w.k, &mut w.du)
        } else {
            let nf = w.free_dofs.len();
            let (p1, p2) = pw.pair.split_at_mut(nf);
            p1.copy_from_slice(&w.du);
            p2.copy_from_slice(&pw.q);
            w.solves += 2;
            let r = self.solver.solve_many_in_place(&w.k, &mut pw.pair);
            let (p1, p2) = pw.pair.split_at(nf);
            w.du.copy_from_slice(p1);
            pw.du2.copy_from_slice(p2);
            r
        };
        clock.stop(self.solver, &mut w.timings);
        if let Err(e) = r {
            return Err(self.fail(it, IncrementFailure::Solver(e)));
        }
        Ok(())
    }

    /// `dlambda` of iteration `it` from the constraint: 0 under load
    /// control, else [`PathAttempt::arc_dlambda`] or
    /// [`PathAttempt::dissipation_dlambda`].
    fn dlambda(&mut self, it: usize, h: f64) -> Result<f64, Abort<Attempt>> {
        match self.constraint {
            Constraint::Load(_) => Ok(0.0),
            Constraint::Arc(len, forward, linearised) => {
                self.arc_dlambda(it, len, forward, linearised)
            }
            Constraint::Dissipation(tau) => self.dissipation_dlambda(it, tau, h),
        }
    }

    /// The cylindrical arc length `|Δu + du_I + dlambda du_II|^2 + c
    /// (Δlambda + dlambda)^2 = Δl^2`, quadratic in `dlambda`. First
    /// iteration (predictor): the root nearest `sign Δl / |(du_II, sqrt
    /// c)|`, the sign `forward` or else that of the previous increment's
    /// direction (that value itself without a real root). Later iterations:
    /// the root whose increment makes the smaller angle with the current
    /// one. No real root fails the attempt, or with `linearised` takes the
    /// constraint linearised at the current increment `(Δ, Δlambda)`,
    /// `|Δ|^2 + c Δlambda^2 + 2 (Δ . du + c Δlambda dlambda) = Δl^2`
    /// (Newton on the constraint, which it meets as the iterations
    /// converge), for this iteration.
    fn arc_dlambda(
        &self,
        it: usize,
        len: f64,
        forward: Option<f64>,
        linearised: bool,
    ) -> Result<f64, Abort<Attempt>> {
        let (w, pw) = (&*self.w, &*self.pw);
        let c = self.coupling.c;
        let dlam0 = self.lambda - self.cur.lambda;
        let nf = w.free_dofs.len();
        if it == 1 {
            // predictor: along du_II with the sign of the path
            let norm = (dot(&pw.du2, &pw.du2) + c).sqrt();
            let dir = dot(&pw.du2, &pw.delta_prev) + c * pw.delta_lambda_prev;
            let sign = match forward {
                Some(s) => s,
                None if dir < 0.0 => -1.0,
                None => 1.0,
            };
            // du_I is round-off here; keep it in the quadratic below
            let (a1, a2, a3) = quadratic(&pw.delta, &w.du, &pw.du2, c, dlam0, len);
            return Ok(match roots(a1, a2, a3) {
                Some((r1, r2)) => {
                    if (r1 - sign * len / norm).abs() < (r2 - sign * len / norm).abs() {
                        r1
                    } else {
                        r2
                    }
                }
                None => sign * len / norm,
            });
        }
        let (a1, a2, a3) = quadratic(&pw.delta, &w.du, &pw.du2, c, dlam0, len);
        match roots(a1, a2, a3) {
            Some((r1, r2)) => {
                // the root whose increment is closest in angle to the
                // current one
                let cos = |dl: f64| {
                    let mut s = c * dlam0 * (dlam0 + dl);
                    for e in 0..nf {
                        s += pw.delta[e] * (pw.delta[e] + w.du[e] + dl * pw.du2[e]);
                    }
                    s
                };
                Ok(if cos(r1) >= cos(r2) { r1 } else { r2 })
            }
            None if linearised => {
                let (d2, dd1, dd2) = (
                    dot(&pw.delta, &pw.delta) + c * dlam0 * dlam0,
                    dot(&pw.delta, &w.du),
                    dot(&pw.delta, &pw.du2) + c * dlam0,
                );
                let dl = (0.5 * (len * len - d2) - dd1) / dd2;
                if dl.is_finite() {
                    Ok(dl)
                } else {
                    Err(self.fail(it, IncrementFailure::NonFinite))
                }
            }
            None => Err(self.fail(it, IncrementFailure::Element(NO_REAL_ROOT.into()))),
        }
    }

    /// The dissipation constraint `phi = ΔD - tau = 0`, linearised: `phi +
    /// w . du + c_l dlambda = 0`. Global balance: `w = ½ lambda_0 (f_ext,f -
    /// g) + ½ f_th,f` and `c_l = ½ (p_0 - a_0 - lambda_0 h + f_th .
    /// ubar_c)` (module doc; `f_th` = 0 without a temperature change).
    /// Interface balance: `w = T^T ½ (f_I,0 - K_I^T u_0)`, `c_l = ½ (f_I,0
    /// - K_I^T u_0) . ubar` (`nonlinear/balance.rs`). A non-finite or
    /// degenerate solution fails the attempt.
    fn dissipation_dlambda(&mut self, it: usize, tau: f64, h: f64) -> Result<f64, Abort<Attempt>> {
        let phi = self.dissipation() - tau; // dphi = w . du + c_l dlambda
        let mut wdu1 = 0.0;
        let mut wdu2 = 0.0;
        let c_l;
        if let (Balance::Interface, Some(share)) = (self.balance, &self.w.interface_share) {
            let pw = &mut *self.pw;
            c_l = interface_gradient(
                self.w.model,
                &pw.interface_base,
                share,
                &self.coupling.ubar,
                &mut pw.w_full,
                &mut pw.w_eq,
            );
            wdu1 = dot(&pw.w_eq, &self.w.du);
            wdu2 = dot(&pw.w_eq, &pw.du2);
        } else {
            let (w, pw, base) = (&*self.w, &*self.pw, self.base);
            let thermal = self.coupling.thermal.as_ref();
            for e in 0..w.free_dofs.len() {
                let fth = thermal.map_or(0.0, |t| t.by_equation[e]);
                let wv = 0.5 * (base.lambda * (w.fext_f[e] - pw.g[e]) + fth);
                wdu1 += wv * w.du[e];
                wdu2 += wv * pw.du2[e];
            }
            let fth_c = thermal.map_or(0.0, |t| t.prescribed);
            c_l = 0.5 * (base.p - base.a - base.lambda * h + fth_c);
        }
        let den = wdu2 + c_l;
        let dl = -(phi + wdu1) / den;
        if !dl.is_finite() || den.abs() <= 1e-14 * (wdu2.abs() + c_l.abs()) {
            return Err(self.fail(it, IncrementFailure::NonFinite));
        }
        Ok(dl)
    }

    /// `ΔD` from the base state to the trial point.
    fn dissipation(&self) -> f64 {
        balance_dissipation(
            self.balance,
            self.w,
            self.pw,
            self.coupling,
            &self.base,
            self.lambda,
        )
    }

    /// Backtracking line search on `|r_f|` along `(du, dlambda)`, from the
    /// second iteration on (the predictor starts from equilibrium, so any
    /// step raises the residual): the first `s = 1, 1/2, ...` (at most
    /// `max_line_search` halvings) with `|r_f| <= (1 - 1e-4 s) |r_f|` of
    /// the start, else the `s` of the smallest finite residual. A damped
    /// step leaves the constraint unmet; the next iteration's constraint,
    /// written on the accumulated increment, restores it. This breaks the
    /// two-cycle of Newton across the kink of a softening law (elastic <->
    /// damaging). Under finite kinematics the full step is taken whenever
    /// the elements evaluate at it, as in the Newton driver
    /// (`Work::takes_full_step`). The trial point and `Δu` move by
    /// `s (du, dlambda)`.
    fn line_search(&mut self, it: usize, dl: f64) -> Result<(), Abort<Attempt>> {
        self.w.u_base.copy_from_slice(&self.w.u);
        let lambda_base = self.lambda;
        let rho_before = self.ev.abs;
        let st = &self.w.settings;
        let tries = if st.line_search && it >= 2 {
            st.max_line_search + 1
        } else {
            1
        };
        let mut step_len = 1.0;
        let mut best: Option<(f64, f64)> = None;
        let mut last = f64::NAN;
        for _ in 0..tries {
            self.move_to(step_len, lambda_base, dl);
            last = step_len;
            self.evaluate(it)?;
            let ev = self.ev;
            if ev.abs.is_finite() {
                if !matches!(best, Some((_, b)) if b <= ev.abs) {
                    best = Some((step_len, ev.abs));
                }
                if ev.abs <= (1.0 - 1e-4 * step_len) * rho_before
                    || self.w.takes_full_step(step_len)
                {
                    break;
                }
            }
            step_len *= 0.5;
        }
        if let Some((sb, _)) = best {
            if sb != last {
                step_len = sb;
                self.move_to(step_len, lambda_base, dl);
                self.evaluate(it)?;
            } else {
                step_len = last;
            }
        }
        for e in 0..self.w.free_dofs.len() {
            self.pw.delta[e] += step_len * self.w.du[e];
        }
        self.w.lambda_trial = self.lambda;
        self.w.history.push(self.ev.rel);
        if !self.ev.abs.is_finite() {
            return Err(self.fail(it, IncrementFailure::NonFinite));
        }
        Ok(())
    }

    /// The consistent tangent did not reduce the residual: Newton is
    /// cycling between the branches of a softening point (elastic and
    /// damaging). As in the Newton driver, the laws' secant tangent is used
    /// for the rest of the attempt (linear, monotone convergence),
    /// reassembled at the trial point. (Not under the dissipation
    /// constraint: with secant tangents its linearisation degenerates, as
    /// on an elastic branch.)
    fn secant_fallback(&mut self, it: usize, rho_prev: f64) -> Result<(), Abort<Attempt>> {
        let st = &self.w.settings;
        if it >= 2
            && !self.secant
            && st.secant_fallback
            && !matches!(self.constraint, Constraint::Dissipation(_))
            && self.ev.abs >= rho_prev
            && self.ev.rel > st.tol_force
        {
            self.secant = true;
            self.w.secant_attempts += 1;
            self.evaluate(it)?;
        }
        Ok(())
    }

    /// The tests after iteration `it`: converged (force criterion, and the
    /// dissipation constraint met to 1e-6), diverging (residual above
    /// `divergence_ratio` times `rho_first`), or `None`: iterate on.
    fn checks(&self, it: usize, rho_first: f64) -> Option<Attempt> {
        let (st, ev) = (&self.w.settings, self.ev);
        let constraint_ok = match self.constraint {
            Constraint::Dissipation(tau) => (self.dissipation() - tau).abs() <= 1e-6 * tau.abs(),
            _ => true,
        };
        tracing::debug!(
            iteration = it,
            residual = ev.rel,
            lambda = self.lambda,
            "path iteration"
        );
        if ev.rel <= st.tol_force && constraint_ok {
            return Some(Attempt::Converged(Convergence {
                iterations: it,
                rel: ev.rel,
                scale_now: ev.scale_now,
                dissipation: self.dissipation(),
            }));
        }
        if ev.abs > st.divergence_ratio * rho_first {
            return Some(failed(
                it,
                ev.rel,
                IncrementFailure::Diverging {
                    residual: ev.abs,
                    initial: rho_first,
                },
            ));
        }
        None
    }
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// Coefficients of `|delta + du1 + x du2|^2 + c (dlam0 + x)^2 - len^2`.
fn quadratic(
    delta: &[f64],
    du1: &[f64],
    du2: &[f64],
    c: f64,
    dlam0: f64,
    len: f64,
) -> (f64, f64, f64) {
    let (mut a1, mut a2, mut a3) = (c, 2.0 * c * dlam0, c * dlam0 * dlam0 - len * len);
    for e in 0..delta.len() {
        let v = delta[e] + du1[e];
        a1 += du2[e] * du2[e];
        a2 += 2.0 * du2[e] * v;
        a3 += v * v;
    }
    (a1, a2, a3)
}

/// Real roots of `a x^2 + b x + c`, if any.
fn roots(a: f64, b: f64, c: f64) -> Option<(f64, f64)> {
    if a <= 0.0 {
        return None;
    }
    let disc = b * b - 4.0 * a * c;
    if disc < 0.0 {
        return None;
    }
    let s = disc.sqrt();
    // stable form
    let qv = -0.5 * (b + s.copysign(b));
    if qv == 0.0 {
        return Some((0.0, 0.0));
    }
    Some((qv / a, c / qv))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The roots of the arc-length quadratic, in the stable form.
    #[test]
    fn quadratic_roots() {
        let (r1, r2) = roots(1.0, -3.0, 2.0).unwrap();
        let (lo, hi) = (r1.min(r2), r1.max(r2));
        assert!((lo - 1.0).abs() < 1e-15 && (hi - 2.0).abs() < 1e-15);
        assert!(roots(1.0, 0.0, 1.0).is_none());
        // no cancellation for a tiny root
        let (r1, r2) = roots(1.0, 1e8, 1.0).unwrap();
        let small = if r1.abs() < r2.abs() { r1 } else { r2 };
        assert!((small + 1e-8).abs() < 1e-22, "{small}");
    }
}
