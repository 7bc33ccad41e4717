//! Incremental-iterative runs (`[analysis] type = "static"`): the Newton or
//! arc-length driver of `junta_solvers`, with one [`CurveRow`] per converged
//! increment handed to the run's observers.
//!
//! The engine here computes what every observer needs from a converged
//! increment (interface results, failed points, reaction and displacement
//! of the curve, energies), keeps the [`RunLog`], applies the stops that
//! belong to the input (a deck's `*STEP, INC=n`, `stop_when_separated`,
//! `max_increments`), and at the end builds the summary. Files are written
//! by observers (`crate::output::writers`): `curve.csv`, the VTU frames and
//! `results.pvd`, `checkpoint.json`, the print tables, `summary.json` and
//! `curve.svg`.

use crate::error::{err, Result};
use crate::input::scene;
use crate::post::crack::CrackProbe;
use crate::post::curve::{limit_points, CurveRow};
use crate::prepare::Prepared;
use crate::run::checkpoint::{FirstFailure, RestartFile};
use crate::run::observer::{Flow, Increment, RunEnd, RunInfo, RunLog, Stop, Writer};
use crate::run::results::{EndReason, Summary};
use junta_core::element::StepInfo;
use junta_core::state::StateStore;
use junta_core::Model;
use junta_solvers::arc_length::{solve_arc_length, PathEnd};
use junta_solvers::newton::{
    solve_nonlinear, Checkpoint, Control, IncrementView, NonlinearError, NonlinearRun,
};
use junta_solvers::path_switch::solve_with_path_switch;
use serde_json::json;
use std::path::Path;
use std::time::Instant;

/// How the curve's two columns are measured.
#[derive(Debug, Clone)]
pub(crate) struct CurveProbe {
    reaction_set: String,
    reaction_component: usize,
    points: Vec<usize>,
    point_component: usize,
    relative_to: Vec<usize>,
    sign: f64,
    conjugate: bool,
}

impl CurveProbe {
    /// The `[output.curve]` of a scene (or a deck's curve), its sets checked.
    pub(crate) fn of(p: &Prepared, file: &str) -> Result<Option<CurveProbe>> {
        let Some(c) = &p.curve else { return Ok(None) };
        let mesh = &p.model.mesh;
        let rc = scene::component(&c.reaction_component)
            .ok_or_else(|| err!("{file}: key `output.curve.reaction_component`: use x, y or z"))?;
        let pc = scene::component(&c.point_component)
            .ok_or_else(|| err!("{file}: key `output.curve.point_component`: use x, y or z"))?;
        mesh.node_set(&c.reaction_set)
            .map_err(|e| err!("{file}: key `output.curve.reaction_set`: {e}"))?;
        let points = mesh
            .node_set(&c.point_set)
            .map_err(|e| err!("{file}: key `output.curve.point_set`: {e}"))?
            .to_vec();
        let relative_to = match &c.relative_to {
            Some(set) => mesh
                .node_set(set)
                .map_err(|e| err!("{file}: key `output.curve.relative_to`: {e}"))?
                .to_vec(),
            None => Vec::new(),
        };
        Ok(Some(CurveProbe {
            reaction_set: c.reaction_set.clone(),
            reaction_component: rc,
            points,
            point_component: pc,
            relative_to,
            sign: if c.negate { -1.0 } else { 1.0 },
            conjugate: c.conjugate,
        }))
    }

    /// `(reaction, displacement)` of the curve at a converged state.
    fn measure(
        &self,
        model: &Model,
        u: &[f64],
        residual: &[f64],
        lambda: f64,
        conjugate: f64,
    ) -> Result<(f64, f64)> {
        if self.conjugate {
            return Ok((self.sign * lambda, self.sign * conjugate));
        }
        let pc = self.point_component;
        let mean = |nodes: &[usize]| {
            nodes.iter().map(|&n| u[3 * n + pc]).sum::<f64>() / nodes.len().max(1) as f64
        };
        let base = if self.relative_to.is_empty() {
            0.0
        } else {
            mean(&self.relative_to)
        };
        let rc = self.reaction_component;
        // internal force on the set = reaction on supports, applied load on
        // a loaded free set; with equations the reduced system's reaction
        // (the dependents' constraint forces carried onto the dofs they
        // follow: a tied face's force on the node that drives it)
        let generalized;
        let residual = if model.dofs.has_equations() {
            generalized = model.dofs.generalized_reactions(residual);
            &generalized[..]
        } else {
            residual
        };
        let reaction = model.set_total(&self.reaction_set, residual)?[rc]
            + lambda * model.set_total(&self.reaction_set, &model.f_ext)?[rc];
        Ok((
            self.sign * reaction,
            self.sign * (mean(&self.points) - base),
        ))
    }
}

/// The stops that belong to the run's input and options.
#[derive(Debug, Clone, Default)]
pub(crate) struct Limits {
    /// Stop after this many increments of this call.
    pub max_increments: Option<usize>,
    /// `[analysis] stop_when_separated`.
    pub stop_when_separated: bool,
    /// Per program step: a deck's `*STEP, INC=n` and the line of the `*STEP`.
    pub increment_limits: Vec<Option<(usize, usize)>>,
}

/// The engine of one incremental run: everything the per-increment
/// callback of the driver reads and updates.
struct Engine<'a> {
    model: &'a Model,
    curve: Option<CurveProbe>,
    limits: Limits,
    log: RunLog,
    /// The last converged `u` and committed state (what a failed run ends on).
    last_u: Vec<f64>,
    last_state: Option<StateStore>,
    error: Option<crate::Error>,
    /// (step, INC, line of its *STEP) when a deck's INC stopped the run.
    inc_reached: Option<(usize, usize, usize)>,
    /// Why an observer stopped the run.
    stop: Option<Stop>,
    /// How the crack front is measured (`None` without interfaces).
    crack: Option<CrackProbe>,
    /// The scene's `[[ply_failure]]` criteria, evaluated after every
    /// increment.
    ply_criteria: &'a [crate::post::ply_failure::PlyCriterionUse],
    /// `u` of the last converged increment (the left end of the external
    /// work's trapezoid; `self.log.external_force` holds its forces).
    prev_u: Vec<f64>,
}

impl Engine<'_> {
    /// Called by the driver after each converged increment.
    fn on_increment(
        &mut self,
        v: &IncrementView<'_>,
        reporters: &mut [&mut dyn Writer],
    ) -> Control {
        let r = v.report;
        for s in &r.switched {
            let what = match s.to.as_str() {
                "load" => format!("{}; load control from here", s.reason),
                "arc_length" => format!("limit point ({}); path following from here", s.reason),
                _ => s.reason.clone(),
            };
            tracing::warn!(
                "increment {} at load factor {:.6e}: {what}",
                s.increment,
                s.lambda
            );
            self.log.path_switches.push(s.clone());
        }
        let flow = self.increment(v, reporters);
        self.log.last_increment = r.increment_index;
        let flow = match flow {
            Ok(f) => f,
            Err(e) => {
                self.error = Some(e);
                return Control::Stop;
            }
        };
        if let Some(stop) = flow.stop() {
            self.stop.get_or_insert(stop);
            return Control::Stop;
        }
        if self.increment_limit_reached(r) {
            return Control::Stop;
        }
        let l = &self.limits;
        if (l.stop_when_separated && self.log.separated)
            || l.max_increments
                .is_some_and(|m| r.increment_index - self.log.start_increment >= m)
        {
            return Control::Stop;
        }
        Control::Continue
    }

    /// The row of a converged increment, then every reporter in order (the
    /// standard writers, then the caller's observers).
    fn increment(
        &mut self,
        v: &IncrementView<'_>,
        reporters: &mut [&mut dyn Writer],
    ) -> Result<Flow> {
        let r = v.report;
        let model = self.model;
        let step = StepInfo {
            temperature_factor: r.temperature_factor,
            cycles: r.cycles,
            load_ratio: model.load_ratio(r.step),
            ..StepInfo::at(r.increment_index, r.lambda, r.delta_lambda)
        };
        let ifs = crate::post::fields::interface_results_at(model, v.u, v.state, step)?;
        let row = self.row_of(v, &ifs)?;
        let ply = crate::post::ply_failure::evaluate(model, v.u, v.state, step, self.ply_criteria)?;
        self.log.ply_failure.record(&row, &ply);
        self.log.rows.push(row.clone());
        self.last_u.clear();
        self.last_u.extend_from_slice(v.u);
        match &mut self.last_state {
            Some(s) => s.committed.copy_from_slice(&v.state.committed),
            None => self.last_state = Some(v.state.clone()),
        }
        let inc = Increment {
            model,
            report: r,
            row: &row,
            u: v.u,
            residual: v.residual,
            state: v.state,
            interfaces: &ifs,
            step,
            ply_failure: &ply,
            view: v,
        };
        let mut flow = Flow::Continue;
        for o in reporters.iter_mut() {
            let f = o.on_increment(&inc, &mut self.log)?;
            if matches!(flow, Flow::Continue) {
                flow = f;
            }
        }
        Ok(flow)
    }

    /// The curve row of a converged increment; updates the first failure
    /// and the separation flag.
    fn row_of(
        &mut self,
        v: &IncrementView<'_>,
        ifs: &[crate::post::fields::InterfaceResults],
    ) -> Result<CurveRow> {
        let (r, model) = (v.report, self.model);
        let points: usize = ifs.iter().map(|i| i.points.len()).sum();
        let failed: usize = ifs
            .iter()
            .flat_map(|i| i.points.iter())
            .filter(|pt| pt.get("failed").is_some_and(|f| f[0] > 0.5))
            .count();
        let conjugate: f64 = model.f_ext.iter().zip(v.u).map(|(f, u)| f * u).sum();
        let (reaction, displacement) = match &self.curve {
            Some(c) => {
                let (f, d) = c.measure(model, v.u, v.residual, r.lambda, conjugate)?;
                (Some(f), Some(d))
            }
            None => (None, None),
        };
        if failed > 0 && self.log.first_failure.is_none() {
            self.log.first_failure = Some(FirstFailure {
                increment: r.increment_index,
                load_factor: r.lambda,
                reaction,
                displacement,
            });
        }
        // split: every point failed and none is still being released
        self.log.separated = points > 0
            && failed == points
            && !model.mesh.blocks.iter().enumerate().any(|(b, block)| {
                block.shape.is_interface()
                    && (0..block.len()).any(|e| {
                        model.elements[b]
                            .wants_small_increments(&v.state.committed[v.state.range(b, e)])
                    })
            });
        let energy = total_energy(ifs);
        let external_work = self.external_work(v, r.lambda);
        let crack = self.crack.as_mut().and_then(|c| c.measure(ifs));
        let drive = self
            .model
            .fatigue
            .as_ref()
            .and_then(|f| f.front_direction)
            .and_then(|d| {
                junta_core::crack_drive::crack_drive_of(ifs.iter().flat_map(|i| &i.points), d)
            });
        let crack_growth_rate =
            crate::post::crack::growth_rate(&self.log.rows, crack.map(|c| c.length), r.cycles);
        Ok(CurveRow {
            increment: r.increment_index,
            step: r.step,
            lambda: r.lambda,
            reaction,
            displacement,
            failed,
            points,
            iterations: r.iterations,
            cutbacks: r.cutbacks,
            seconds: r.seconds.total,
            small: r.small_increment_mode,
            dissipated: energy.dissipated_energy,
            damaged_area: energy.damaged_area,
            negative_pivots: r.negative_pivots,
            load_sign: if r.delta_lambda > 0.0 {
                1
            } else if r.delta_lambda < 0.0 {
                -1
            } else {
                0
            },
            control: r.control.name().to_string(),
            conjugate,
            frictional: energy.frictional_dissipation,
            temperature_factor: r.temperature_factor,
            viscous: energy.viscous_energy,
            external_work,
            crack_length: crack.map(|c| c.length),
            crack_front: crack.and_then(|c| c.front),
            process_zone_length: crack.map(|c| c.process_zone_length),
            process_zone_points: crack.map(|c| c.process_zone_points),
            cycles: r.cycles,
            energy_release_rate: drive.map(|c| c.energy_release_rate),
            crack_mode_ratio: drive.map(|c| c.mode_ratio),
            crack_growth_rate,
        })
    }

    /// The external work after the converged increment `v`: the last
    /// row's plus the trapezoid `sum_i (F_i + F_i^prev) / 2 (u_i -
    /// u_i^prev)` over every dof, with `F` the external force: the
    /// reaction (`residual + lambda f_ext`, the internal force) on a
    /// prescribed dof, the applied load `lambda f_ext` on a free one.
    /// With `*EQUATION`s the reaction on a prescribed dof is the reduced
    /// system's, `r_p + sum_d c_dp r_d` (the dependents' constraint forces
    /// carried onto the dof they follow; derivation at
    /// [`junta_core::dof::DofMap::generalized_reactions_into`]), so that the
    /// work holds with equations; a dependent dof gets only its load.
    /// Updates the previous state to this one.
    fn external_work(&mut self, v: &IncrementView<'_>, lambda: f64) -> f64 {
        let dofs = &self.model.dofs;
        let f_ext = &self.model.f_ext;
        let n = v.u.len();
        let generalized;
        let reaction: &[f64] = if dofs.has_equations() {
            generalized = dofs.generalized_reactions(v.residual);
            &generalized
        } else {
            v.residual
        };
        let force: Vec<f64> = (0..n)
            .map(|i| {
                let load = lambda * f_ext.get(i).copied().unwrap_or(0.0);
                let prescribed = dofs.eq[i] == junta_core::dof::CONSTRAINED
                    && !dofs.orphan.get(i).copied().unwrap_or(false)
                    && !dofs.dependents.contains(i);
                if prescribed {
                    reaction[i] + load
                } else {
                    load
                }
            })
            .collect();
        if self.prev_u.len() != n {
            self.prev_u = vec![0.0; n];
        }
        // a restart from a checkpoint of an older run has no forces: the
        // first increment's trapezoid then takes this increment's forces
        // at both ends
        if self.log.external_force.len() != n {
            self.log.external_force = if self.log.rows.is_empty() {
                vec![0.0; n]
            } else {
                force.clone()
            };
        }
        let prev_f = &self.log.external_force;
        let work: f64 = (0..n)
            .map(|i| 0.5 * (force[i] + prev_f[i]) * (v.u[i] - self.prev_u[i]))
            .sum();
        let past = self.log.rows.last().map_or(0.0, |r| r.external_work);
        self.prev_u.copy_from_slice(v.u);
        self.log.external_force = force;
        past + work
    }

    /// A deck's `*STEP, INC=n`: at most n increments in that step.
    fn increment_limit_reached(&mut self, r: &junta_solvers::newton::IncrementReport) -> bool {
        let limits = &self.limits.increment_limits;
        let Some(&Some((n, line))) = limits.get(r.step) else {
            return false;
        };
        // the deck step's program steps (one per amplitude segment) share
        // its limit, identified by its line
        let same = |k: usize| limits.get(k) == Some(&Some((n, line)));
        let in_step = self.log.rows.iter().filter(|row| same(row.step)).count();
        let last_segment = !same(r.step + 1);
        if in_step >= n && !(last_segment && r.step_fraction >= 1.0 - 1e-12) {
            self.inc_reached = Some((r.step, n, line));
            return true;
        }
        false
    }
}

/// Interface energies summed over the blocks.
fn total_energy(
    ifs: &[crate::post::fields::InterfaceResults],
) -> crate::post::fields::InterfaceEnergy {
    ifs.iter().map(crate::post::fields::interface_energy).fold(
        crate::post::fields::InterfaceEnergy::default(),
        |a, e| crate::post::fields::InterfaceEnergy {
            dissipated_energy: a.dissipated_energy + e.dissipated_energy,
            viscous_energy: a.viscous_energy + e.viscous_energy,
            damaged_area: a.damaged_area + e.damaged_area,
            process_zone_area: a.process_zone_area + e.process_zone_area,
            has_damage: a.has_damage || e.has_damage,
            frictional_dissipation: a.frictional_dissipation + e.frictional_dissipation,
            has_friction: a.has_friction || e.has_friction,
        },
    )
}

/// How an incremental run ended.
pub(crate) struct Ending {
    /// Why the run ended.
    pub reason: EndReason,
    /// Its status line ([`EndReason::line`]).
    pub status: String,
    /// The driver's failure (an increment below the smallest size).
    pub failure: Option<NonlinearError>,
    /// Whether an observer interrupted the run (Ctrl-C).
    pub interrupted: bool,
    /// Warnings for the user about the end state (a small-strain run past
    /// the rotation limit: [`crate::post::rotation`]).
    pub warnings: Vec<String>,
}

/// Run the incremental analysis of `p`, from the start or from `restart`
/// (its rows in `past_rows`), reporting to `reporters` in order: the
/// standard writers, then the caller's observers behind [`crate::run::observer::ReadOnly`].
pub(crate) fn run_incremental(
    input: &Path,
    p: &mut Prepared,
    restart: Option<(RestartFile, Vec<CurveRow>)>,
    limits: Limits,
    reporters: &mut [&mut dyn Writer],
) -> Result<(Ending, Summary, RunLog)> {
    let t0 = Instant::now();
    let file = input.display().to_string();
    let curve = CurveProbe::of(p, &file)?;
    let crack = CrackProbe::of(&p.model, p.crack.as_ref(), &file)?;
    let analysis = p.analysis.clone();
    let (checkpoint, log) = match restart {
        Some((r, rows)) => {
            let start = r.checkpoint.increment_index;
            let log = RunLog {
                rows,
                frames: r.frames,
                first_failure: r.first_failure,
                path_switches: r.path_switches,
                start_increment: start,
                last_increment: start,
                external_force: r.external_force,
                ply_failure: r.ply_failure,
                ..RunLog::default()
            };
            (Some(r.checkpoint), log)
        }
        None => (None, RunLog::default()),
    };
    let prev_u = checkpoint.as_ref().map(|c| c.u.clone()).unwrap_or_default();
    let info = RunInfo {
        input,
        title: &p.title,
        model: &p.model,
        steps: &p.analysis.steps,
        solver: p.solver.key(),
        start_increment: log.start_increment,
    };
    for o in reporters.iter_mut() {
        o.on_start(&info, &log)?;
    }
    // SAFETY of the borrow: the engine holds the observers for the run only
    let model = &p.model;
    let mut engine = Engine {
        model,
        curve,
        limits,
        log,
        last_u: Vec::new(),
        last_state: None,
        error: None,
        inc_reached: None,
        stop: None,
        crack,
        ply_criteria: &p.ply_criteria,
        prev_u,
    };
    let result = drive(
        model,
        p.solver.as_mut(),
        &analysis,
        checkpoint.as_ref(),
        &mut engine,
        reporters,
    );
    if let Some(e) = engine.error.take() {
        return Err(e.context("writing the results of an increment"));
    }
    let (run, path_end, failure) = match result {
        Ok((run, end)) => (Some(run), end, None),
        Err(e @ NonlinearError::IncrementTooSmall { .. }) => (None, None, Some(e)),
        Err(e) => return Err(crate::Error::from(e).context(format!("solving {file}"))),
    };
    let ending = ending_of(&engine, &analysis, run.as_ref(), path_end, failure);
    finish(input, p, engine, reporters, run, ending, t0)
}

/// The driver the analysis asks for, with the engine as its callback.
fn drive(
    model: &Model,
    solver: &mut dyn junta_core::LinearSolver,
    analysis: &scene::AnalysisSpec,
    checkpoint: Option<&Checkpoint>,
    engine: &mut Engine<'_>,
    reporters: &mut [&mut dyn Writer],
) -> Result<(NonlinearRun, Option<PathEnd>), NonlinearError> {
    let mut callback = |v: &IncrementView<'_>| engine.on_increment(v, reporters);
    match analysis.control {
        scene::Control::Auto => solve_with_path_switch(
            model,
            solver,
            &analysis.steps,
            &analysis.newton,
            &analysis.arc_length,
            checkpoint,
            &mut callback,
        ),
        scene::Control::Load => solve_nonlinear(
            model,
            solver,
            &analysis.steps,
            &analysis.newton,
            checkpoint,
            &mut callback,
        )
        .map(|r| (r, None)),
        scene::Control::ArcLength => solve_arc_length(
            model,
            solver,
            &analysis.steps,
            &analysis.newton,
            &analysis.arc_length,
            checkpoint,
            &mut callback,
        )
        .map(|(r, end)| (r, Some(end))),
    }
}

/// The status line of a run that returned from the driver (`run`), or
/// failed with `failure`.
fn ending_of(
    engine: &Engine<'_>,
    analysis: &scene::AnalysisSpec,
    run: Option<&NonlinearRun>,
    path_end: Option<PathEnd>,
    failure: Option<NonlinearError>,
) -> Ending {
    let interrupted = matches!(engine.stop, Some(Stop::Interrupted));
    let reason = match (&failure, run) {
        (Some(e), _) => EndReason::Failed(e.to_string()),
        (None, run) => {
            let stopped = run.is_some_and(|r| r.summary.stopped_by_observer);
            if interrupted {
                EndReason::Interrupted
            } else if let Some((_, n, line)) = engine.inc_reached {
                EndReason::DeckIncrementLimit {
                    increments: n,
                    line,
                }
            } else if let Some(Stop::Requested(why)) = &engine.stop {
                EndReason::Requested(why.clone())
            } else if stopped && engine.log.separated && analysis.stop_when_separated {
                EndReason::Separated
            } else if stopped {
                EndReason::IncrementLimit
            } else if path_end == Some(PathEnd::Unloaded) {
                let last = engine.log.rows.last();
                EndReason::Unloaded {
                    failed: last.map_or(0, |r| r.failed),
                    points: last.map_or(0, |r| r.points),
                }
            } else if path_end == Some(PathEnd::IncrementLimit) {
                EndReason::ArcLengthLimit(analysis.arc_length.max_increments)
            } else {
                EndReason::EndOfProgram
            }
        }
    };
    Ending {
        status: reason.line(),
        reason,
        failure,
        interrupted,
        warnings: Vec::new(),
    }
}

/// The summary of the run and the observers' `on_end`.
fn finish(
    input: &Path,
    p: &Prepared,
    engine: Engine<'_>,
    reporters: &mut [&mut dyn Writer],
    run: Option<NonlinearRun>,
    mut ending: Ending,
    t0: Instant,
) -> Result<(Ending, Summary, RunLog)> {
    let Engine {
        mut log,
        last_u,
        mut last_state,
        crack,
        ..
    } = engine;
    if let Some(s) = &mut last_state {
        s.restore();
    }
    let model = &p.model;
    let mut summary = base_summary(input, p, &log, &ending.status);
    let step = StepInfo {
        temperature_factor: log.rows.last().map_or(0.0, |r| r.temperature_factor),
        ..StepInfo::at(
            log.last_increment,
            log.rows.last().map_or(0.0, |r| r.lambda),
            0.0,
        )
    };
    // the state the run ends on: the driver's, else the last converged one
    let converged_here = log.last_increment > log.start_increment;
    let (u, state, residual) = match &run {
        Some(run) => (Some(&run.u), Some(&run.state), Some(&run.residual)),
        None if converged_here => (Some(&last_u), last_state.as_ref(), None),
        None => (None, None, None),
    };
    let mut interfaces = Vec::new();
    if let (Some(u), Some(state)) = (u, state) {
        interfaces = crate::post::fields::interface_results_at(model, u, state, step)?;
        summary["interfaces"] = crate::output::summary::interface_summary(model, &interfaces);
        if !p.ply_criteria.is_empty() {
            // at the state the run ends on, with each criterion's first failure
            let ply = crate::post::ply_failure::evaluate(model, u, state, step, &p.ply_criteria)?;
            summary["ply_failure"] = crate::post::ply_failure::summary(&ply, false);
            for r in &ply {
                summary["ply_failure"][&r.name]["first_failure"] =
                    json!(log.ply_failure.first_failure(&r.name));
            }
        }
    }
    if let Some(u) = u.filter(|_| !p.probes.is_empty()) {
        // `[output] probes` at the state the run ends on (a linear run's
        // are of its one solution)
        summary["probes"] = crate::output::summary::probes(model, &p.probes, u)
            .map_err(|e| err!("key `output.probes`: {e}"))?;
    }
    match &run {
        Some(run) => run_totals(&mut summary, p, run, t0)?,
        None => {
            if let Some(last) = log.rows.last() {
                summary["failed_points_at_last_increment"] = json!(last.failed);
            }
        }
    }
    advice_and_solver(&mut summary, p, &log)?;
    // a warning of the run's end is returned (the CLI prints it once), not
    // also logged as a warning
    if let Some(w) = crack_and_energy(&mut summary, crack.as_ref(), &log) {
        tracing::debug!("{w}");
        ending.warnings.push(w);
    }
    if let Some(w) = fatigue_share(&mut summary, p, &interfaces) {
        tracing::debug!("{w}");
        ending.warnings.push(w);
    }
    if let Some(w) = crate::post::crack::steady_zone_warning(&log.rows) {
        match summary["warnings"].as_array_mut() {
            Some(list) => list.push(json!(w)),
            None => summary["warnings"] = json!([w]),
        }
        ending.warnings.push(w);
    }
    if let Some(u) = u {
        let (rotation, warning) =
            crate::post::rotation::summary_entry(model, u, crate::post::rotation::is_deck(input));
        summary["largest_rotation"] = rotation;
        if let Some(w) = warning {
            match summary["warnings"].as_array_mut() {
                Some(list) => list.push(json!(w)),
                None => summary["warnings"] = json!([w]),
            }
            ending.warnings.push(w);
        }
    }
    let summary = Summary::from_json(summary)?;
    let end = RunEnd {
        model: &p.model,
        u: u.map(|v| v.as_slice()),
        state,
        residual: residual.map(|v| v.as_slice()),
        interfaces: &interfaces,
        step,
        converged_here,
        status: &ending.status,
        reason: &ending.reason,
        summary: &summary,
    };
    for o in reporters.iter_mut() {
        o.on_end(&end, &mut log)?;
    }
    Ok((ending, summary, log))
}

/// `summary.json` `energy` (the last row's external work and the
/// interfaces' dissipated, viscous and frictional energy) and `crack` (the
/// crack probe and the last row's crack); the process-zone warning, also
/// added to `warnings`.
fn crack_and_energy(
    summary: &mut serde_json::Value,
    crack: Option<&CrackProbe>,
    log: &RunLog,
) -> Option<String> {
    let last = log.rows.last()?;
    summary["energy"] = json!({
        "external_work": last.external_work,
        "dissipated_energy": last.dissipated,
        "viscous_energy": last.viscous,
        "frictional_dissipation": last.frictional,
    });
    let crack = crack?;
    last.crack_length?;
    // the width: the scene's, else the default fixed at the first row
    let mut entry = crack.describe();
    entry["crack_length"] = json!(last.crack_length);
    entry["crack_front"] = json!(last.crack_front);
    entry["process_zone_length"] = json!(last.process_zone_length);
    entry["process_zone_points"] = json!(last.process_zone_points);
    // the fewest process-zone points in a row in which the crack grew
    let growing = log
        .rows
        .windows(2)
        .filter(|w| matches!((w[0].crack_length, w[1].crack_length), (Some(a), Some(b)) if b > a));
    entry["process_zone_points_min_while_growing"] =
        json!(growing.filter_map(|w| w[1].process_zone_points).min());
    entry["min_process_zone_points"] = json!(crate::post::crack::MIN_PROCESS_ZONE_POINTS);
    summary["crack"] = entry;
    let warning = crate::post::crack::process_zone_warning(&log.rows)?;
    match summary["warnings"].as_array_mut() {
        Some(list) => list.push(json!(warning)),
        None => summary["warnings"] = json!([warning]),
    }
    Some(warning)
}

/// `summary.json` `fatigue.static_share` and `fatigue.failed_points` of a
/// fatigue run ([`crate::post::crack::fatigue_static_share`]); the warning when
/// a measured-crack run's share is large, also added to `warnings`.
fn fatigue_share(
    summary: &mut serde_json::Value,
    p: &Prepared,
    interfaces: &[crate::post::fields::InterfaceResults],
) -> Option<String> {
    let measured = p.model.fatigue.as_ref()?.front_direction.is_some();
    let (share, points) = crate::post::crack::fatigue_static_share(interfaces)?;
    summary["fatigue"]["static_share"] = json!(share);
    summary["fatigue"]["failed_points"] = json!(points);
    let warning = crate::post::crack::static_share_warning(share, points).filter(|_| measured)?;
    match summary["warnings"].as_array_mut() {
        Some(list) => list.push(json!(warning)),
        None => summary["warnings"] = json!([warning]),
    }
    Some(warning)
}

/// The summary fields every incremental run has.
fn base_summary(input: &Path, p: &Prepared, log: &RunLog, status: &str) -> serde_json::Value {
    let model = &p.model;
    let rows = &log.rows;
    let total_iterations: usize = rows.iter().map(|r| r.iterations).sum();
    let max_iterations = rows.iter().map(|r| r.iterations).max().unwrap_or(0);
    json!({
        "input": input.display().to_string(),
        "title": p.title,
        "units": p.units,
        "analysis": "static",
        "status": status,
        "nodes": model.mesh.nodes.len(),
        "dofs": model.dofs.num_dofs(),
        "equations": model.dofs.num_free,
        "elements": crate::output::summary::element_counts(model),
        "distributed": crate::output::summary::distributed_summary(model),
        "plane": crate::output::summary::plane_summary(model),
        "increments": log.last_increment,
        "newton_iterations": {
            "total": total_iterations,
            "max_per_increment": max_iterations,
            "mean_per_increment": total_iterations as f64 / rows.len().max(1) as f64,
            "per_increment": rows.iter().map(|r| r.iterations).collect::<Vec<_>>(),
        },
        "load_factor": rows.last().map(|r| r.lambda),
        "first_failure": log.first_failure,
        "restarted_from_increment": if log.start_increment > 0 { Some(log.start_increment) } else { None },
        "control": p.analysis.control,
        "limit_points": limit_points(rows),
        "path_switches": log.path_switches,
        "temperature": p.temperature.clone().map(|mut t| {
            // the fraction of the change applied at the end, and the
            // increments that moved the temperature with the loads held
            t["factor"] = json!(rows.last().map(|r| r.temperature_factor));
            let thermal = |r: &CurveRow| r.lambda == 0.0 && r.step == 0;
            t["thermal_step_increments"] = json!(rows.iter().filter(|r| thermal(r)).count());
            t
        }),
        "fatigue": p.model.fatigue.as_ref().map(|f| {
            // the fatigue steps: those whose cycle count moves
            let moves = |s: usize| f.cycle_steps[s] > if s == 0 { 0.0 } else { f.cycle_steps[s - 1] };
            let fatigue_steps: Vec<usize> = (0..f.cycle_steps.len()).filter(|&s| moves(s)).collect();
            json!({
                "cycles_end": f.cycle_steps.last(),
                "cycles": rows.last().map(|r| r.cycles),
                "load_ratio": fatigue_steps.first().map(|&s| f.load_ratios[s]),
                "blocks": fatigue_steps.iter().map(|&s| json!({
                    "step": s,
                    "load_factor": p.analysis.steps.get(s),
                    "cycles_end": f.cycle_steps[s],
                    "load_ratio": f.load_ratios[s],
                })).collect::<Vec<_>>(),
                "max_damage_increment": f.max_damage_increment,
                "increments": rows.iter().filter(|r| fatigue_steps.contains(&r.step)).count(),
            })
        }),
    })
}

/// Reactions, timings and driver counts of a run the driver returned.
fn run_totals(
    summary: &mut serde_json::Value,
    p: &Prepared,
    run: &NonlinearRun,
    t0: Instant,
) -> Result<()> {
    let model = &p.model;
    summary["reactions"] = crate::output::summary::reactions(model, &run.residual)?;
    crate::post::constraint_force::add_generalized_reactions(summary, model, &run.residual)?;
    summary["displacement_max"] = json!(crate::output::summary::displacement_max(&run.u));
    let t = run.summary.timings;
    summary["timings"] = json!({
        "read": p.read_seconds, "choose_solver": p.choose_solver_seconds,
        "build": p.build.map(|b| b.seconds),
        "build_peak_bytes": p.build.and_then(|b| b.peak_bytes),
        "assemble": t.assemble, "analyze": t.analyze, "factor": t.factor, "solve": t.solve,
        "driver_total": t.total,
        "total": p.read_seconds + p.choose_solver_seconds + t0.elapsed().as_secs_f64(),
    });
    summary["symbolic_analyses"] = json!(run.summary.analyze_count);
    summary["cutbacks"] = json!(run.summary.cutbacks);
    // of this call (a restarted run counts from its restart)
    summary["driver"] = json!({
        "newton_iterations_with_failed_attempts": run.summary.newton_iterations_total,
        "linear_solves": run.summary.linear_solves,
        "secant_attempts": run.summary.secant_attempts,
    });
    Ok(())
}

/// Mesh advice, law and mesh warnings and the linear solver's report.
fn advice_and_solver(summary: &mut serde_json::Value, p: &Prepared, log: &RunLog) -> Result<()> {
    use junta_core::MatrixKind;
    let model = &p.model;
    let (zone, zone_lines, mut warnings) = crate::output::summary::cohesive_zone_advice(model)?;
    if !zone_lines.is_empty() {
        summary["mesh_advice"] = zone;
    }
    warnings.extend(crate::prepare::bending::bending_warnings(model));
    if !warnings.is_empty() {
        summary["warnings"] = json!(warnings);
    }
    let report = p.solver.report();
    let mut notes = p.notes.clone();
    notes.extend(report.notes.iter().cloned());
    let rows = &log.rows;
    if model.matrix_kind() == MatrixKind::General {
        summary["frictional_dissipation"] = json!(rows.last().map_or(0.0, |r| r.frictional));
    }
    summary["solver"] = json!({
        "name": report.solver,
        "ordering": report.ordering,
        "predicted_factor_nonzeros": crate::output::summary::ordering_candidates(&report),
        "precision": report.precision,
        "factor_nonzeros": report.factor_nonzeros,
        "factorizations": report.factorizations,
        "partial_factorizations": report.partial_factorizations,
        // mean share of a complete factorisation's work a partial one redid
        "partial_work_mean": if report.partial_factorizations > 0 {
            json!(report.refactored_work / report.partial_factorizations as f64)
        } else {
            json!(null)
        },
        "negative_pivots_max": rows.iter().filter_map(|r| r.negative_pivots).max(),
        // solves whose residual ||b - A x|| the back end left to the
        // driver's own force check (factor above doubt; `ldlt`
        // `residual_check`)
        "unchecked_solves": report.unchecked_solves,
        "matrix_kind": model.matrix_kind().name(),
        // a general tangent is assembled in full only for a back end that
        // solves general matrices; otherwise its symmetric part is used
        "tangent": if model.matrix_kind() != MatrixKind::General {
            "symmetric"
        } else if p.solver.accepts(MatrixKind::General) {
            "consistent (nonsymmetric, full storage)"
        } else {
            "symmetric part of the nonsymmetric tangent (Newton converges linearly)"
        },
        "warnings": report.warnings,
        "notes": notes,
    });
    Ok(())
}
