//! Load or displacement control that passes limit points by itself: the
//! Newton driver ([`crate::newton`]) runs the program until it meets a
//! limit point, path following ([`crate::arc_length`]) takes over there,
//! and load control takes over again where the path is a stable loading
//! branch once more. A user who prescribes a load or a displacement gets
//! the whole curve to the end of the program, snap-backs included, without
//! choosing a control.
//!
//! # Limit points
//!
//! Under load control the load factor `lambda` is prescribed: at a maximum
//! of the load (load control) or where the prescribed displacement turns
//! back (a snap-back under displacement control) no equilibrium lies
//! beyond the last converged state, every attempt fails, and the driver
//! cuts the increment back. A limit point is taken to be met when
//!
//! - the increment was cut back below `min_increment` (the point where the
//!   Newton driver alone stops with
//!   [`NonlinearError::IncrementTooSmall`]), or
//! - an attempt failed and its last tangent had more negative pivots than
//!   the last converged increment's (the tangent's inertia changed: the
//!   structure is past a stability limit), when the linear back end
//!   reports the inertia (`ldlt`, `cholesky`), or
//! - an attempt failed right after an increment in which the laws
//!   dissipated energy ([`junta_core::Model::dissipated_energy`]): a crack
//!   starting to run, the snap-back of its first elements under
//!   displacement control (the attempt itself stops early when the line
//!   search on the secant tangent finds no descent three times in a row,
//!   [`crate::nonlinear::IncrementFailure::NoDescent`]), or
//! - six cut-backs came in a row with no increment converging at its full
//!   size in between: the increments shrink towards a maximum of the load
//!   factor (the cascade down to `min_increment` would cost about as many
//!   failed attempts again).
//!
//! So on the DCBs and ENFs of `examples/delamination` the switch comes at
//! the first failed attempt, with no cut-back before it. A sign taken
//! from converged increments alone (the share of the load's work the laws
//! dissipate, which jumps from 2 to 7-17 % one to three increments before
//! the DCBs' first failure) was measured and not kept: the ENF with a long
//! precrack reaches 5 % at 86 % of its peak while displacement control
//! passes that peak without a failure, and switching there costs more.
//!
//! The last three apply in a step loading away from zero only (below). When
//! path following cannot make a single increment from a switch taken on
//! one of them (the viscous `examples/delamination/dcb.toml` near 8 mm),
//! load control goes on from the same state without them, cutting back as
//! it would have without the switch.
//!
//! # Switch to path following
//!
//! From the last converged increment, path following continues to the end
//! load factor of the current step, with the cylindrical arc length first
//! (its size the arc length `sqrt(|Δu|^2 + c Δlambda^2)` of the last
//! converged increment, its direction that increment's) and the dissipation
//! constraint as soon as the laws dissipate (see [`crate::arc_length`]).
//! The step must move away from zero (`lambda` from 0, or from
//! `lambda_{s-1}` to `lambda_s` of the same sign and larger magnitude);
//! elsewhere (an unloading step) the run stops as the Newton driver does.
//!
//! # Return to load control
//!
//! Path following hands back when the path has passed the limit and is a
//! stable loading branch again ([`crate::arc_length::LoadReturn`]), or at
//! the end of the step; the following steps start under load control
//! again, with the same switching. So a run ends at the end of its program
//! whenever the structure still carries the load there. It ends earlier
//! only when the load falls back to zero after a maximum under path
//! following (a force-controlled structure that came apart), when path
//! following itself cannot go on, or when its `max_increments` is reached.
//!
//! # Reports
//!
//! The first increment after each switch carries an
//! [`crate::newton::IncrementReport::switched`] record (which increment, load factor,
//! step, the new control and why). A checkpoint taken under path following
//! holds the path state, so a restart continues under it; one taken under
//! load control restarts under load control.

pub use super::vocabulary::{LoadTrack, PathSwitch};

use super::vocabulary::{
    moves_away_from_zero, Checkpoint, Control, IncrementView, LoadReturn, NewtonSettings,
    NonlinearError, NonlinearRun, NonlinearSummary, PathMode, PathState,
};
use crate::arc_length::{run_path, ArcLengthSettings, PathEnd};
use crate::newton::{run_load, LoadOptions, LoadOutcome};
use junta_core::{LinearSolver, Model};

/// Run the load program with the Newton driver, switching to path
/// following at limit points and back (module documentation). Returns the
/// final run (its summary the totals of every phase), how the last path
/// following phase ended (`None` when the run ended under load control),
/// or the error that ended it.
pub fn solve_with_path_switch<F>(
    model: &Model,
    solver: &mut dyn LinearSolver,
    program: &[f64],
    settings: &NewtonSettings,
    arc: &ArcLengthSettings,
    restart: Option<&Checkpoint>,
    mut observer: F,
) -> Result<(NonlinearRun, Option<PathEnd>), NonlinearError>
where
    F: FnMut(&IncrementView<'_>) -> Control,
{
    arc.validate()?;
    let mut run = SwitchRun {
        model,
        program,
        settings,
        arc,
        from: restart.cloned(),
        totals: NonlinearSummary::default(),
        analyzed: false,
        pending: None,
        fallback: None,
        early_signs: true,
    };
    loop {
        let path_phase = run.from.as_ref().is_some_and(|c| c.path.is_some());
        let end = if path_phase {
            run.path_phase(solver, &mut observer)?
        } else {
            run.load_phase(solver, &mut observer)?
        };
        if let Some(end) = end {
            return Ok(end);
        }
    }
}

/// A run of [`solve_with_path_switch`] between its phases: the problem,
/// where the next phase starts and what the phases so far left for it.
struct SwitchRun<'a> {
    model: &'a Model,
    program: &'a [f64],
    settings: &'a NewtonSettings,
    arc: &'a ArcLengthSettings,
    /// Start of the next phase (a path state in it: path following).
    from: Option<Checkpoint>,
    /// Counts and timings of the phases so far.
    totals: NonlinearSummary,
    /// The solver holds the symbolic analysis of the model's pattern.
    analyzed: bool,
    /// The switch record for the next increment's report.
    pending: Option<PathSwitch>,
    /// The load-controlled state of a switch taken on an early sign.
    fallback: Option<Checkpoint>,
    /// The load phase stops at the early signs of a limit point (false
    /// after path following could not start from one).
    early_signs: bool,
}

/// How a run of [`solve_with_path_switch`] ended, when it did.
type SwitchEnd = Option<(NonlinearRun, Option<PathEnd>)>;

impl SwitchRun<'_> {
    /// A load-controlled phase from `from` to the end of the program or to
    /// a limit point, where the next phase (path following) is set up.
    fn load_phase<F>(
        &mut self,
        solver: &mut dyn LinearSolver,
        observer: &mut F,
    ) -> Result<SwitchEnd, NonlinearError>
    where
        F: FnMut(&IncrementView<'_>) -> Control,
    {
        let (model, program, settings) = (self.model, self.program, self.settings);
        let mut track = match &self.from {
            Some(c) => c
                .load_track
                .clone()
                .map_or_else(LoadTrack::default, |mut t| {
                    t.u_last = c.u.clone();
                    t
                }),
            None => LoadTrack::default(),
        };
        let outcome = {
            let pending = &mut self.pending;
            let mut obs = |v: &IncrementView<'_>| {
                track.record(v, program, model);
                let view = IncrementView {
                    track: Some(&track),
                    ..*v
                };
                forward(observer, &view, pending)
            };
            let options = LoadOptions {
                analyzed: self.analyzed,
                stop_at_limit: self.early_signs,
            };
            run_load(
                model,
                solver,
                program,
                settings,
                self.from.as_ref(),
                &mut obs,
                options,
            )?
        };
        self.analyzed |= match &outcome {
            LoadOutcome::Finished(run) | LoadOutcome::Limit { run, .. } => {
                run.summary.analyze_count > 0
            }
        };
        match outcome {
            LoadOutcome::Finished(run) => Ok(Some((add_totals(&mut self.totals, run), None))),
            LoadOutcome::Limit {
                run,
                error,
                reason,
                early,
            } => {
                let c = run.checkpoint();
                if !moves_away_from_zero(program, c.step) {
                    return Err(error);
                }
                self.early_signs = true;
                self.fallback = early.then(|| Checkpoint {
                    load_track: Some(track.clone()),
                    ..c.clone()
                });
                add_totals(&mut self.totals, run);
                let switch = PathSwitch {
                    increment: c.increment_index,
                    step: c.step,
                    lambda: c.lambda,
                    to: "arc_length".into(),
                    reason,
                };
                tracing::warn!(
                    lambda = switch.lambda,
                    increment = switch.increment,
                    "limit point ({}): path following takes over",
                    switch.reason
                );
                self.from = Some(track.path_checkpoint(c, model, settings));
                self.pending = Some(switch);
                Ok(None)
            }
        }
    }

    /// A path-following phase from `from` (a checkpoint with a path state)
    /// to the end of its step, or to where load control takes over again
    /// (set up as the next phase).
    fn path_phase<F>(
        &mut self,
        solver: &mut dyn LinearSolver,
        observer: &mut F,
    ) -> Result<SwitchEnd, NonlinearError>
    where
        F: FnMut(&IncrementView<'_>) -> Control,
    {
        let (program, settings) = (self.program, self.settings);
        let c = self
            .from
            .take()
            .expect("a path phase starts from a checkpoint");
        let end = program[c.step.min(program.len() - 1)];
        let result = {
            let pending = &mut self.pending;
            let obs = |v: &IncrementView<'_>| forward(observer, v, pending);
            run_path(
                self.model,
                solver,
                end,
                settings,
                self.arc,
                Some(&c),
                obs,
                self.analyzed,
            )
        };
        let (run, end_reason) = match result {
            Ok(r) => r,
            // path following could not make a single increment from a
            // switch taken on an early sign: load control goes on
            // cutting back, as without the switch
            Err(NonlinearError::IncrementTooSmall { .. })
                if self.pending.is_some() && self.fallback.is_some() =>
            {
                let back = self.fallback.take().expect("checked");
                tracing::warn!(
                    lambda = back.lambda,
                    "path following could not start: load control goes on"
                );
                self.pending = None;
                self.early_signs = false;
                self.analyzed = true;
                self.from = Some(back);
                return Ok(None);
            }
            Err(e) => return Err(e),
        };
        self.fallback = None;
        self.analyzed |= run.summary.analyze_count > 0;
        let done = run.cursor.step + 1 >= program.len();
        match end_reason {
            PathEnd::ReturnToLoad => {
                let back = load_checkpoint(run.checkpoint(), program, settings);
                self.pending = Some(PathSwitch {
                    increment: back.increment_index,
                    step: back.step,
                    lambda: back.lambda,
                    to: "load".into(),
                    reason: "past the limit point the path loads again on a stable branch".into(),
                });
                tracing::warn!(
                    lambda = back.lambda,
                    "the path is a stable loading branch again: load control takes over"
                );
                add_totals(&mut self.totals, run);
                self.from = Some(back);
                Ok(None)
            }
            PathEnd::Completed if !done => {
                let back = load_checkpoint(run.checkpoint(), program, settings);
                add_totals(&mut self.totals, run);
                self.from = Some(back);
                Ok(None)
            }
            _ => Ok(Some((add_totals(&mut self.totals, run), Some(end_reason)))),
        }
    }
}

/// Hand a converged increment to the caller's observer, with the pending
/// switch record on its report.
fn forward<F>(observer: &mut F, v: &IncrementView<'_>, pending: &mut Option<PathSwitch>) -> Control
where
    F: FnMut(&IncrementView<'_>) -> Control,
{
    let Some(switch) = pending.take() else {
        return observer(v);
    };
    let mut report = v.report.clone();
    report.switched.insert(0, switch);
    observer(&IncrementView {
        report: &report,
        ..*v
    })
}

impl LoadTrack {
    fn record(&mut self, v: &IncrementView<'_>, program: &[f64], model: &Model) {
        std::mem::swap(&mut self.u_last, &mut self.u_before);
        self.u_last.clear();
        self.u_last.extend_from_slice(v.u);
        self.lambda_before = self.lambda_last;
        self.lambda_last = v.report.lambda;
        let sign = program.get(v.report.step).map_or(1.0, |e| e.signum());
        self.lambda_max = self.lambda_max.max(v.report.lambda * sign);
        self.pivots_last = v.report.negative_pivots;
        if self.u_before.len() == self.u_last.len() {
            self.arc_max = self.arc_max.max(distance(&self.u_before, &self.u_last));
        }
        // a law that cannot report it counts as not dissipating
        let d = model.dissipated_energy(v.u, v.state).unwrap_or(0.0);
        self.dissipating = d > self.dissipated;
        self.tau_max = self.tau_max.max(d - self.dissipated);
        self.dissipated = d;
    }

    /// The checkpoint `c` (the last converged load-controlled increment)
    /// with the path state that continues from it: cylindrical arc length
    /// of the last increment's size and direction.
    fn path_checkpoint(
        &self,
        mut c: Checkpoint,
        model: &Model,
        settings: &NewtonSettings,
    ) -> Checkpoint {
        let have_two = self.u_before.len() == c.u.len() && self.u_last.len() == c.u.len();
        let (u_prev, lambda_prev) = if have_two {
            (self.u_before.clone(), self.lambda_before)
        } else {
            // a single converged increment (or a restart right before the
            // limit): the unloaded state before it
            (model.dofs.expand(None, 0.0), 0.0)
        };
        // the norm over all dofs, prescribed ones included, is the
        // cylindrical arc length `sqrt(|Δu_f|^2 + c Δlambda^2)`
        let arc_last = distance(&u_prev, &c.u);
        let arc0 = self.arc_max.max(arc_last);
        // the last increments before a limit point are cut back: restart
        // from a quarter of the largest increment, the driver adapts it
        let mut arc = arc_last.max(FIRST_ARC_OF_LARGEST * arc0);
        if !(arc > 0.0 && arc.is_finite()) {
            arc = settings.min_increment.max(1e-12);
        }
        // where the laws dissipate, the limit is a crack starting to run:
        // the dissipation constraint follows it where the arc may turn
        // back onto the loading branch (a snap-back at more than 90
        // degrees); its size a quarter of the largest increment's
        // dissipation, the driver adapts it (under large deformation on the
        // interfaces' energy balance: `crate::nonlinear::balance`)
        let (mode, size, tau0) = if self.dissipating && self.tau_max > 0.0 {
            let tau = FIRST_ARC_OF_LARGEST * self.tau_max;
            (PathMode::Dissipation, tau, tau)
        } else {
            (PathMode::Arc, arc, 0.0)
        };
        c.path = Some(PathState {
            mode,
            size,
            arc0: arc0.max(arc),
            tau0,
            arc_last: arc,
            previous_lambda: lambda_prev,
            previous_u: u_prev,
            lambda_max: self.lambda_max,
            stored_max: 0.0,
            last_tau: 0.0,
            return_to_load: Some(LoadReturn {
                lambda_switch: c.lambda,
                pivots_switch: self.pivots_last,
                passed: false,
                rising: 0,
            }),
        });
        c
    }
}

/// The first arc length (or dissipation) after a switch, as a fraction of
/// the largest load-controlled increment's (when the last one is
/// shorter).
const FIRST_ARC_OF_LARGEST: f64 = 0.25;

/// Euclidean distance of two vectors.
fn distance(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y) * (x - y))
        .sum::<f64>()
        .sqrt()
}

/// A path-following checkpoint made a load-controlled one: the fraction of
/// its step from the load factor, the next increment the last one's share
/// of the step (within the Newton settings' bounds).
fn load_checkpoint(mut c: Checkpoint, program: &[f64], settings: &NewtonSettings) -> Checkpoint {
    let end = program[c.step];
    let start = if c.step == 0 {
        0.0
    } else {
        program[c.step - 1]
    };
    let span = end - start;
    let previous_lambda = c.path.as_ref().map_or(start, |p| p.previous_lambda);
    c.step_fraction = if c.lambda == end {
        1.0
    } else {
        ((c.lambda - start) / span).clamp(0.0, 1.0 - 1e-12)
    };
    c.increment_size = ((c.lambda - previous_lambda).abs() / span.abs())
        .clamp(settings.min_increment, settings.max_increment);
    c.path = None;
    // load control's limit-point tests start afresh
    c.cutbacks_in_a_row = 0;
    c.negative_pivots = None;
    c
}

/// Add a phase's counts and timings to `totals`; the run with the totals.
fn add_totals(totals: &mut NonlinearSummary, mut run: NonlinearRun) -> NonlinearRun {
    let s = &run.summary;
    totals.increments += s.increments;
    totals.newton_iterations_total += s.newton_iterations_total;
    totals.newton_iterations_max = totals.newton_iterations_max.max(s.newton_iterations_max);
    totals.cutbacks += s.cutbacks;
    totals.timings.pattern += s.timings.pattern;
    totals.timings.assemble += s.timings.assemble;
    totals.timings.analyze += s.timings.analyze;
    totals.timings.factor += s.timings.factor;
    totals.timings.solve += s.timings.solve;
    totals.timings.total += s.timings.total;
    totals.analyze_count += s.analyze_count;
    totals.final_lambda = s.final_lambda;
    totals.stopped_by_observer = s.stopped_by_observer;
    totals.secant_attempts += s.secant_attempts;
    totals.linear_solves += s.linear_solves;
    run.summary = totals.clone();
    run
}
