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
//! residual through `f_int`, exactly as in [`crate::linear_static`]).
//! Under finite kinematics (nlgeom) the free displacements are
//! extrapolated from the last increment of the same step instead
//! ([`crate::nonlinear::engine::Predictor`]), and after an increment that
//! converged in at most three iterations the next one's corrections reuse
//! its first factorisation for as long as each gains a digit (chord steps,
//! `Work::chord_next` of the engine). Full Newton then iterates with the
//! consistent tangent `K = d f_int / d u` assembled by the elements:
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
//! # Contact iterations
//!
//! A law with a unilateral contact switch (`contact`:
//! [`junta_core::InterfaceLaw::contact_closed`]) makes Newton a
//! semi-smooth Newton on the contact status: each iteration solves with
//! the status of the last iterate. An iteration after which some point's
//! status differs from the last iterate's is a *contact iteration* (the
//! "severe discontinuity iteration" of Abaqus/Standard): it does not count
//! against `max_iterations`, it restarts the stagnation test from its
//! residual, and the divergence test measures against the largest
//! residual so far. It is not divergence: the correction solved a
//! different linear problem than the one the new status poses, so neither
//! the size nor the decrease of its residual says anything about the
//! convergence of the smooth problem that follows. Convergence is tested
//! as in any iteration. An attempt takes at most `max_iterations` plus
//! twice the number of contact points iterations in all. The attempts of
//! path following ([`crate::arc_length`]) count them the same way. A
//! model without such a law iterates exactly as before. Why the status can need many
//! iterations (a grazing precrack, e.g. an ENF's): the doc of the
//! `contact` law.
//!
//! # Cut-back
//!
//! An attempt fails on: the iteration limit, a non-finite residual or
//! correction, a residual growing past `divergence_ratio` times the first
//! one of the attempt, a linear-solver error (e.g. a tangent that is not
//! positive definite past a limit point), an element error (e.g. a law
//! failure), stagnation (no 1 % decrease of the best residual over 12
//! iterations, 48 on the secant tangent), or no descent: three in a row on the secant
//! tangent whose line search finds no lower residual at any step
//! ([`IncrementFailure::NoDescent`]; past a snap-back under displacement
//! control no equilibrium lies within the increment, and the attempt need
//! not run to the iteration limit). The driver then restores the trial state
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
//! # Where the parts live
//!
//! This file holds the load-controlled driver ([`solve_nonlinear`]: the
//! increment loop, its cut-backs, size rule and limit-point signs). The
//! words every driver shares (settings, observer protocol, reports,
//! checkpoints, errors) are in [`crate::nonlinear::vocabulary`] and
//! re-exported here under their old paths; the Newton iterations of one
//! increment (`Work`: assembly, residual, line search, secant fallback,
//! exact tangent) are in the crate's `nonlinear::engine` module.
//!
//! [`Element::wants_small_increments`]: junta_core::Element::wants_small_increments

pub use super::vocabulary::{
    Checkpoint, Control, IncrementFailure, IncrementReport, IncrementView, NewtonSettings,
    NonlinearError, NonlinearRun, NonlinearSummary,
};

use super::engine::{Attempt, Eval, Work};
use super::vocabulary::{
    any_wants_small, check_checkpoint_fits, increment_timings, moves_away_from_zero, Cursor,
    PathMode,
};
use crate::linear_static::Timings;
use junta_core::element::StepInfo;
use junta_core::law::output::VISCOUS_ENERGY;
use junta_core::state::StateStore;
use junta_core::{CoreError, LinearSolver, Model};
use std::time::Instant;

/// Cut-backs in a row (no increment converging at its full size in
/// between) taken for a limit point under `control = "auto"`: the
/// increments shrink towards a maximum of the load factor
/// ([`crate::path_switch`]).
const LIMIT_CUTBACKS: usize = 6;

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
    /// more negative pivots than the last converged increment's, as soon
    /// as an attempt fails after an increment that dissipated, or after
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
        w.use_exact_tangent()?;
    }
    if let Some(p) = restart.and_then(|c| c.predictor.as_ref()) {
        w.predictor = p.clone();
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
        dissipation: Dissipation::default(),
    };
    // residual of the starting point, so that a run with nothing to do
    // still returns a consistent residual
    if let Some(c) = restart {
        run.w.evaluate_at_rest(&mut run.state, &run.cur)?;
        if run.stop_at_limit {
            run.dissipation = run.dissipation_at_restart(c);
        }
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
        let report = run.commit(solver, &inc, before)?;
        let view = IncrementView {
            report: &report,
            u: &run.w.u,
            residual: &run.w.res,
            state: &run.state,
            residual_history: &run.w.history,
            cursor: run.cur,
            path: None,
            track: None,
            predictor: run.w.finite_kinematics.then_some(&run.w.predictor),
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
    /// What the laws dissipated up to the last converged increment, and
    /// whether that increment added to it (kept with `stop_at_limit`).
    dissipation: Dissipation,
}

/// The energy the laws report dissipated at the last converged increment
/// ([`Model::dissipated_energy`]; a law that cannot report it counts as
/// not dissipating), and whether that increment added to it: the sign
/// that a failed attempt under `control = "auto"` meets a crack starting
/// to run ([`LoadRun::limit_reason`]).
///
/// A viscous regularisation (a law's `viscosity`) is there to carry load
/// control past the snap-back: where its points report viscous energy,
/// failed attempts are cut back as before, and the other signs apply
/// (measured: the viscous `examples/delamination/dcb.toml`, switched at
/// its first failure at 4.2 mm, found no path ahead, its first
/// dissipation step converging to lambda = -1.67).
#[derive(Debug, Clone, Copy, Default)]
struct Dissipation {
    energy: f64,
    growing: bool,
}

impl Dissipation {
    /// The dissipation at the converged `u` (committed `state`), after the
    /// increment from `self`.
    fn after(&self, model: &Model, u: &[f64], state: &StateStore) -> Dissipation {
        Dissipation::at(model, u, state, |energy| energy > self.energy)
    }

    /// The dissipation at `u` (committed `state`); `dissipated(energy)`:
    /// whether the increment to it added to the energy (read as not
    /// growing where viscous points report energy).
    fn at(
        model: &Model,
        u: &[f64],
        state: &StateStore,
        dissipated: impl FnOnce(f64) -> bool,
    ) -> Dissipation {
        let energy = model.dissipated_energy(u, state).unwrap_or(0.0);
        let viscous = model
            .max_law_output(u, state, VISCOUS_ENERGY)
            .unwrap_or(0.0)
            > 0.0;
        Dissipation {
            energy,
            growing: !viscous && dissipated(energy),
        }
    }
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
        let rate = model.max_law_output(
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
    /// converged one's, a failure after an increment that dissipated, or
    /// [`LIMIT_CUTBACKS`] cut-backs in a row.
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
                    let below_min = next < self.settings.min_increment || span == 0.0;
                    let why = self.limit_reason(below_min, pivots, &reason);
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

    /// The dissipation at a restart from `c` (its residual at rest
    /// evaluated): the energy recomputed from its `u` and state, whether
    /// its increment dissipated from the switch's track in it.
    fn dissipation_at_restart(&self, c: &Checkpoint) -> Dissipation {
        let dissipating = c.load_track.as_ref().is_some_and(|t| t.dissipating);
        Dissipation::at(self.w.model, &self.w.u, &self.state, |_| dissipating)
    }

    /// Why a failed attempt (its tangent's negative `pivots`, when
    /// reported; `below_min`: the next size would fall below
    /// `min_increment`) is taken for a limit point ([`LimitSign`]), or
    /// `None` to cut back and go on. Besides `below_min`, the early signs
    /// (with `stop_at_limit`, in a step loading away from zero, where path
    /// following can take over): the tangent has more negative pivots than
    /// the last converged one's, the last converged increment dissipated
    /// ([`Dissipation`]: a crack starting to run), or [`LIMIT_CUTBACKS`]
    /// cut-backs in a row.
    fn limit_reason(
        &self,
        below_min: bool,
        pivots: Option<usize>,
        reason: &IncrementFailure,
    ) -> Option<String> {
        let cur = &self.cur;
        // the early signs of a limit point, where path
        // following can take over (a step loading away from 0)
        let early = self.stop_at_limit && moves_away_from_zero(self.program, cur.step);
        if below_min {
            return Some(format!(
                "the increment was cut back below min_increment = {:e} of the step \
                 ({reason})",
                self.settings.min_increment
            ));
        }
        match (early, cur.pivots, pivots) {
            (true, Some(before), Some(now)) if now > before => Some(format!(
                "the tangent's inertia changed: {now} negative pivots in a \
                 failed attempt against {before} at the last converged increment"
            )),
            _ if early && self.dissipation.growing => Some(format!(
                "an attempt failed ({reason}) while the interfaces dissipate: \
                 a crack starting to run"
            )),
            _ if early && cur.cutbacks_in_a_row >= LIMIT_CUTBACKS => Some(format!(
                "{} cut-backs in a row without an increment converging at its \
                 full size ({reason})",
                cur.cutbacks_in_a_row
            )),
            _ => None,
        }
    }

    /// Commit a converged increment: state, `u_conv`, cursor and totals.
    /// The next size: `small_increment` while an element wants small
    /// increments, `growth` times larger (at most `max_increment`) after an
    /// increment without cut-back in at most `growth_iterations`
    /// iterations, else unchanged. Under finite kinematics, the interface
    /// tangents' skew decides the tangent of the next increments
    /// ([`Work::committed`]), and the increment is kept for the next one's
    /// start ([`crate::nonlinear::engine::Predictor`]). Returns the
    /// increment's report (`before`: the timings when it started).
    fn commit(
        &mut self,
        solver: &dyn LinearSolver,
        inc: &LoadIncrement,
        before: Timings,
    ) -> Result<IncrementReport, NonlinearError> {
        let settings = self.settings;
        self.state.commit();
        let cur = self.cur;
        self.w
            .committed(cur.increment_index + 1, cur.step, inc.lambda_new)?;
        if self.w.finite_kinematics {
            let delta_lambda = inc.lambda_new - self.cur.lambda;
            let w = &mut self.w;
            let same_step = inc.t_new < 1.0;
            let effort = (inc.iterations, inc.cutbacks);
            w.predictor
                .record(&w.u_conv, &w.u, delta_lambda, same_step, effort);
        }
        self.w.u_conv.copy_from_slice(&self.w.u);
        if self.stop_at_limit {
            self.dissipation = self.dissipation.after(self.w.model, &self.w.u, &self.state);
        }
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
            control: PathMode::Load,
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
        Ok(report)
    }
}
