//! The Newton engine the nonlinear drivers share: the buffers of a run
//! ([`Work`]: tangent, residuals, displacements, counters and timings,
//! allocated once), the residual evaluation with its force scale, one
//! Newton attempt of an increment at a prescribed load factor (correction,
//! line search, secant fallback, the convergence, divergence and
//! stagnation tests), the switch to the exact (nonsymmetric) tangent, and
//! the timing of the linear back end. The equations and tests are those of
//! the module documentation of [`crate::newton`]; path following
//! ([`crate::arc_length`]) runs its own attempts on the same buffers.
//!
//! The engine reaches linear back ends only through
//! [`junta_core::LinearSolver`]: the caller's back end, and for the exact
//! tangent the one the registry holds under [`EXACT_TANGENT_SOLVER`].

use super::vocabulary::{
    Cursor, IncrementFailure, NewtonSettings, NonlinearError, NonlinearSummary, PathSwitch,
};
use crate::linear_static::Timings;
use junta_core::assembly::Assembler;
use junta_core::dof::CONSTRAINED;
use junta_core::element::StepInfo;
use junta_core::state::StateStore;
use junta_core::{CoreError, LinearSolver, Model, SolverError, SymmetricCsc};
use std::time::Instant;

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
pub(crate) enum Attempt {
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
    /// The last converged increment under finite kinematics, which the
    /// next attempt's start extrapolates ([`Predictor`]).
    pub(crate) predictor: Predictor,
    /// The evaluations of the current attempt leave the tangent out and
    /// its corrections reuse the factorisation ([`Work::chord_next`]).
    chord: bool,
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
    pub(crate) exact_switch: Option<PathSwitch>,
    /// Attempts of the current increment that stalled on the symmetric
    /// part of the tangent (reset when an increment converges).
    pub(crate) stalled_attempts: usize,
    /// Contact iterations an attempt may take on top of `max_iterations`
    /// ([`contact_allowance`]; 0 for a model without a contact switch).
    pub(crate) contact_allowance: usize,
    /// The contact status of every point with a contact switch at the
    /// current iterate ([`Model::contact_statuses`]), and the buffer of
    /// the next one.
    pub(crate) contact_status: Vec<bool>,
    contact_next: Vec<bool>,
    /// The interface elements' share of every assembly, when path
    /// following asks for it ([`InterfaceShareBuffers`]).
    pub(crate) interface_share: Option<InterfaceShareBuffers>,
}

/// The start of an attempt under finite kinematics: the free dofs
/// extrapolated from the last converged increment of the same step,
/// `u = u_conv + (dlambda / dlambda_last) du_last`, the constrained ones
/// at `lambda * prescribed` as always.
///
/// Why: from `u_conv` with only the constrained dofs moved, the elements
/// next to a prescribed face are kinked by the whole increment. Under
/// small strain that costs nothing (the solids are linear and the first
/// correction removes the kink exactly); under finite kinematics the
/// kinked elements' geometric terms pollute the first correction. On a
/// slender arm the kink's forces are those of a short stiff element
/// against the bending reaction of the whole arm: measured on
/// `dcb_h8.toml` under nlgeom, a relative residual of 35 after the first
/// correction and four iterations per elastic increment. Extrapolated,
/// the start is smooth and only the increment's true nonlinearity is left.
///
/// None (the converged displacement) for the first increment of a step,
/// under small strain, and when the load factor does not move (`ratio`).
/// A restart point carries it ([`crate::nonlinear::Checkpoint`]), so that
/// a restarted run makes the increments of the uninterrupted one.
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Predictor {
    /// Full-length displacement change of the last converged increment.
    pub(crate) delta_u: Vec<f64>,
    /// Its load-factor change (0: nothing to extrapolate).
    pub(crate) delta_lambda: f64,
    /// It converged without cut-back in at most
    /// [`CHORD_AFTER_ITERATIONS`] iterations: the next one may take chord
    /// steps ([`Work::chord_next`]).
    #[serde(default)]
    pub(crate) chord: bool,
}

impl Predictor {
    /// The extrapolation factor for an increment of `delta_lambda`.
    pub(crate) fn ratio(&self, delta_lambda: f64) -> Option<f64> {
        (self.delta_lambda != 0.0 && delta_lambda != 0.0 && !self.delta_u.is_empty())
            .then(|| delta_lambda / self.delta_lambda)
    }

    /// Keep the increment from `u_conv` to `u` of `delta_lambda` (with
    /// `same_step`: the next increment continues this step).
    pub(crate) fn record(
        &mut self,
        u_conv: &[f64],
        u: &[f64],
        delta_lambda: f64,
        same_step: bool,
        (iterations, cutbacks): (usize, usize),
    ) {
        self.chord = cutbacks == 0 && iterations <= CHORD_AFTER_ITERATIONS;
        if !same_step {
            self.delta_lambda = 0.0;
            return;
        }
        self.delta_u.resize(u.len(), 0.0);
        for ((d, &a), &b) in self.delta_u.iter_mut().zip(u_conv).zip(u) {
            *d = b - a;
        }
        self.delta_lambda = delta_lambda;
    }
}

/// The contact iterations an attempt of a model with `points` integration
/// points on interfaces with a contact switch may take on top of
/// `max_iterations`: twice the points. A status that walks across the
/// whole contact surface moves by one element row or more per iteration
/// once it has settled, after some back and forth at the start (measured
/// on ENF precracks: 100 iterations for 120 points on 3.75 mm elements,
/// 169 for 900 on 0.5 mm; see the module doc of [`crate::newton`]). Over
/// several ranks, the points of all the ranks (the same on every rank).
fn contact_allowance(points: usize) -> usize {
    let mut n = [points as f64];
    if let Some(c) = junta_core::distributed::collective() {
        c.sum_in_place(&mut n);
    }
    2 * n[0] as usize
}

/// Buffers of the interface elements' share of an assembly
/// ([`junta_core::assembly::InterfaceShare`]), full length (by dof): the
/// probe `x` (set by the caller), and after each [`Work::evaluate`] the
/// interface force `f_I` and `K_I^T x` at the evaluated point.
pub(crate) struct InterfaceShareBuffers {
    pub(crate) probe: Vec<f64>,
    pub(crate) force: Vec<f64>,
    pub(crate) tangent_probe: Vec<f64>,
}

impl InterfaceShareBuffers {
    /// Zeroed buffers for `ndof` dofs.
    pub(crate) fn new(ndof: usize) -> Self {
        InterfaceShareBuffers {
            probe: vec![0.0; ndof],
            force: vec![0.0; ndof],
            tangent_probe: vec![0.0; ndof],
        }
    }
}

/// Registry key of the back end of the exact (nonsymmetric) tangent
/// ([`Work::use_exact_tangent`]): the general sparse LU of the linear half
/// of the crate, looked up in the plugin registry
/// ([`junta_core::registry`]) so that the drivers name no concrete back
/// end.
pub(crate) const EXACT_TANGENT_SOLVER: &str = "lu";

/// A fresh back end for the exact tangent: the registry's
/// [`EXACT_TANGENT_SOLVER`] entry built from an empty parameter table (its
/// default settings). An error only if no such back end is registered.
pub(crate) fn exact_tangent_solver() -> Result<Box<dyn LinearSolver>, CoreError> {
    let entry =
        junta_core::registry::find::<junta_core::registry::SolverEntry>(EXACT_TANGENT_SOLVER)?;
    (entry.build)(&toml::Table::new())
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
        let contact_points = model
            .elements
            .iter()
            .zip(&model.mesh.blocks)
            .filter(|(e, _)| e.has_contact_switch())
            .map(|(e, b)| e.num_points() * b.len())
            .sum::<usize>();
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
            predictor: Predictor::default(),
            chord: false,
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
            contact_allowance: contact_allowance(contact_points),
            contact_status: Vec::with_capacity(contact_points),
            contact_next: Vec::with_capacity(contact_points),
            interface_share: None,
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

    /// Assemble at `self.u` and fill the residual (and the interface
    /// elements' share, when [`Work::interface_share`] is set).
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
        let share = self
            .interface_share
            .as_mut()
            .map(|b| junta_core::assembly::InterfaceShare {
                probe: &b.probe,
                force: &mut b.force,
                tangent_probe: &mut b.tangent_probe,
            });
        let r = self.asm.assemble_cached_sharing(
            &m.mesh,
            &m.elements,
            &m.dofs,
            &self.u,
            state,
            step,
            (!self.chord).then_some(&mut self.k),
            &mut self.f_int,
            share,
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
    /// matrix gets its lower triangle and the back end of the exact tangent
    /// ([`exact_tangent_solver`]) takes over (analysed on the next tangent).
    pub(crate) fn use_exact_tangent(&mut self) -> Result<(), CoreError> {
        let solver = exact_tangent_solver()?;
        self.exact = true;
        self.k.set_general(true);
        self.exact_solver = Some(solver);
        self.analyzed = false;
        Ok(())
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
            IncrementFailure::IterationLimit
                | IncrementFailure::Stagnated { .. }
                | IncrementFailure::NoDescent { .. }
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
        self.use_exact_tangent()?;
        self.exact_switch = Some(PathSwitch {
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

    /// After a converged increment (`increment`, of program step `step`,
    /// at `lambda`): a new increment's stall count, and under finite
    /// kinematics on the symmetric part of the tangent, the largest scaled
    /// skew the interface elements measured on their exact tangents during
    /// the increment ([`Model::take_symmetrised_skew`]). Above
    /// [`SYMMETRISED_SKEW_LIMIT`] the run goes on with the exact tangent
    /// (`lu`, [`Work::use_exact_tangent`]), reported as a switch.
    pub(crate) fn committed(
        &mut self,
        increment: usize,
        step: usize,
        lambda: f64,
    ) -> Result<(), CoreError> {
        self.stalled_attempts = 0;
        if !self.finite_kinematics || self.exact {
            return Ok(());
        }
        let skew = self.model.take_symmetrised_skew();
        if skew <= SYMMETRISED_SKEW_LIMIT {
            return Ok(());
        }
        self.use_exact_tangent()?;
        self.exact_switch = Some(PathSwitch {
            increment,
            step,
            lambda,
            to: "exact_tangent".into(),
            reason: format!(
                "large deformation: the interface tangents' skew part reached {skew:.1e} of them (above {SYMMETRISED_SKEW_LIMIT:.0e}), so their symmetric part is no Newton tangent any more: the exact, nonsymmetric tangent (lu) from here"
            ),
        });
        tracing::warn!(
            skew,
            "large deformation: the interface tangent's skew part is large; switching to the exact tangent"
        );
        Ok(())
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
    pub(crate) fn attempt(
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
            no_descent: 0,
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
        if self.contact_allowance > 0 {
            self.model
                .contact_statuses(&self.u, state, &mut self.contact_status)?;
        }
        // iterations that count against `max_iterations`: those that
        // change no contact status
        let mut counted = 0;
        let mut it = 0;
        while counted < max_iterations && it < max_iterations + self.contact_allowance {
            it += 1;
            self.newton_correction(solver, a, it)?;
            self.chord = self.chord_next(a, it);
            let s = self.newton_update(state, a, it)?;
            let switched = self.contact_switches(state)?;
            if switched == 0 {
                counted += 1;
            }
            if let Some(done) = self.newton_checks(a, it, s, switched) {
                self.chord = false;
                return Ok(done);
            }
            if self.chord && (switched > 0 || !self.chord_contracted()) {
                // back to Newton: the tangent at this iterate
                self.chord = false;
                a.ev = self.attempt_evaluate(state, a, it)?;
            }
        }
        self.chord = false;
        Ok(failed(it, a.ev.rel, IncrementFailure::IterationLimit))
    }

    /// The number of points whose contact status changed from the last
    /// iterate to `u` (the largest over the ranks); the status of `u`
    /// becomes the current one. 0 for a model without a contact switch.
    pub(crate) fn contact_switches(&mut self, state: &StateStore) -> Result<usize, CoreError> {
        if self.contact_allowance == 0 {
            return Ok(0);
        }
        self.model
            .contact_statuses(&self.u, state, &mut self.contact_next)?;
        let changed = self
            .contact_status
            .iter()
            .zip(&self.contact_next)
            .filter(|(a, b)| a != b)
            .count();
        std::mem::swap(&mut self.contact_status, &mut self.contact_next);
        let mut n = [changed as f64];
        if let Some(c) = junta_core::distributed::collective() {
            c.max_in_place(&mut n);
        }
        Ok(n[0] as usize)
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
        let ratio = self.predictor.ratio(a.step.delta_load_factor);
        for (d, u) in self.u.iter_mut().enumerate() {
            *u = if m.dofs.eq[d] == CONSTRAINED {
                lambda * m.dofs.prescribed[d]
            } else {
                match ratio {
                    Some(r) => self.u_conv[d] + r * self.predictor.delta_u[d],
                    None => self.u_conv[d],
                }
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
        // (a chord step: the last evaluation left the tangent out, and the
        // factorisation of the attempt's first tangent serves again)
        if !self.chord {
            if let Err(e) = self.factorize(solver) {
                return Err(Abort::Failed(failed(
                    it,
                    a.ev.rel,
                    IncrementFailure::Solver(e),
                )));
            }
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

    /// Whether the evaluations after correction `it` leave the tangent out
    /// (a chord step: the next correction reuses the factorisation of the
    /// attempt's first tangent). Only under finite kinematics, on the
    /// consistent tangent, after an increment that converged fast
    /// ([`Predictor::chord`]), from the first correction on and for as
    /// long as the chord steps contract ([`Work::chord_contracted`]).
    ///
    /// Why: under nlgeom an elastic increment needs two Newton corrections
    /// where small strain needs one (the energy test asks for the second),
    /// and each tangent costs a total-Lagrangian assembly and a full
    /// refactorisation. Within one short increment the tangent hardly
    /// changes: on `dcb_h8.toml` the first correction leaves a relative
    /// residual of about 1e-6, and the chord step from the same factor
    /// converges as the second Newton step did. Code_Aster's
    /// `STAT_NON_LINE` reassembles once per increment by default
    /// (`REAC_ITER = 0`); here the tangent comes back as soon as a chord
    /// step fails.
    fn chord_next(&self, a: &NewtonAttempt, it: usize) -> bool {
        self.finite_kinematics && self.predictor.chord && !a.step.secant && (it == 1 || self.chord)
    }

    /// The last chord step reduced the relative residual at least
    /// [`CHORD_CONTRACTION`] times.
    fn chord_contracted(&self) -> bool {
        match self.history.as_slice() {
            [.., before, last] => *last <= CHORD_CONTRACTION * before,
            _ => false,
        }
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
        a.no_descent = if a.step.secant && !ls.decreased {
            a.no_descent + 1
        } else {
            0
        };
        // a chord step that does not descend: Newton from here, with the
        // tangent at the iterate evaluated below
        let chord_failed = self.chord && !ls.decreased;
        if chord_failed {
            self.chord = false;
        }
        // (Only while the force residual is above its tolerance: a
        // residual already at round-off level need not decrease.)
        let switch_to_secant = !chord_failed
            && !ls.decreased
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
        if ls.s != ls.last_s || switch_to_secant || chord_failed {
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
    fn newton_checks(
        &self,
        a: &mut NewtonAttempt,
        it: usize,
        s: f64,
        contact_switches: usize,
    ) -> Option<Attempt> {
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
            contact_switches,
            "Newton iteration"
        );
        if ev.rel <= st.tol_force && energy <= st.tol_energy {
            return Some(Attempt::Converged {
                iterations: it,
                eval: ev,
                energy,
            });
        }
        if contact_switches > 0 {
            // a new contact status, a new smooth problem: the stagnation
            // test starts again from this iterate, and the divergence
            // test measures against the largest residual so far
            a.best_rel = ev.rel;
            a.best_at = it;
            a.rho0 = a.rho0.max(ev.abs);
            a.no_descent = 0;
            return None;
        }
        // (far from equilibrium only: near round-off a line search that
        // finds nothing lower is the arithmetic, which the stagnation
        // test below reports with the tolerance that cannot be met)
        if a.no_descent >= NO_DESCENT_ITERATIONS && ev.rel > st.tol_force.max(f64::EPSILON.sqrt()) {
            return Some(failed(
                it,
                ev.rel,
                IncrementFailure::NoDescent {
                    iterations: a.no_descent,
                },
            ));
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
    /// Iterations in a row on the secant tangent whose line search found
    /// no decrease (the no-descent test).
    no_descent: usize,
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

/// Stalled attempts of one increment before the exact tangent is tried.
const STALLS_BEFORE_EXACT_TANGENT: usize = 2;

/// Largest skew entry of the exact tangent, scaled by the diagonal
/// ([`largest_scaled_skew`]), above which a Newton attempt stalled on the
/// symmetric part switches to the exact tangent
/// ([`Work::try_exact_tangent`]).
pub(crate) const EXACT_TANGENT_SKEW: f64 = 1e-4;

/// Largest scaled skew `max |k_ij - k_ji| / sqrt(|k_ii k_jj|)` of an
/// interface element's exact tangent under finite kinematics for which its
/// symmetric part is assembled ([`Work::committed`]). The skew part is
/// the tangent's error then, and Newton on the symmetric part gains about
/// `-log10(skew)` digits per iteration over the exact tangent's quadratic
/// rate; at 0.1 that is one digit, where the exact tangent's `lu` pays for
/// itself. Measured on `dcb_h8.toml` under nlgeom: 3e-6 while the bond is
/// elastic, 1e-3 at damage onset, 2e-2 with a process zone, all converging
/// in 2 iterations per increment like the exact tangent.
pub(crate) const SYMMETRISED_SKEW_LIMIT: f64 = 0.1;

/// Least reduction of the relative residual by a chord step
/// ([`Work::chord_next`]) for the next one to reuse the factorisation
/// again; Newton's own steps gain three digits or more on these
/// increments.
const CHORD_CONTRACTION: f64 = 0.1;

/// Iterations of a converged increment (without cut-back) up to which the
/// next one may take chord steps ([`Predictor::chord`]).
const CHORD_AFTER_ITERATIONS: usize = 3;

/// Newton iterations without a 1 % decrease of the best relative residual
/// after which an attempt stops as stagnated (a quadratically converging
/// Newton gains far more per iteration; the secant fallback, which
/// converges linearly, gets four times as many).
const STAGNATION_ITERATIONS: usize = 12;

/// Iterations in a row on the secant tangent whose line search finds no
/// decrease of the residual at any step length after which an attempt
/// stops ([`IncrementFailure::NoDescent`]). The secant tangent of a
/// softening law is the fallback that converges monotonically where an
/// equilibrium lies within reach; when even it finds no descent three
/// times in a row, none does (a snap-back under displacement control: the
/// iterations of `examples/delamination/dcb_plain.toml` past its peak sat
/// at the shortest step for 15 iterations, up to the iteration limit).
const NO_DESCENT_ITERATIONS: usize = 3;
