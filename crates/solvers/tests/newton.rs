//! Integration tests of the nonlinear driver (`junta_solvers::newton`).
//!
//! Nonlinear checks use a test-only element, [`Springs`]: axial springs
//! along x between nodes of one Quad4 cell (or between a node and the
//! ground), with linear, cubic-hardening or exponential-softening laws.

use junta_core::element::{ElementContext, ElementError, PointOutput, StepInfo};
use junta_core::mesh::generate::{box_mesh, BoxSpec};
use junta_core::mesh::{ElementBlock, Mesh};
use junta_core::topology::CellShape;
use junta_core::{Element, LinearSolver, Model, SolveReport, SolverError, SymmetricCsc};
use junta_elements::{Integration, Isotropic, SolidElement};
use junta_solvers::linear_static::solve_linear_static;
use junta_solvers::newton::{
    solve_nonlinear, Checkpoint, Control, IncrementFailure, IncrementReport, NewtonSettings,
    NonlinearError, NonlinearRun,
};
use junta_solvers::CholeskySolver;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};

// ---------------------------------------------------------------- helpers

/// Force-elongation law of one spring: `(f, df/dx)`.
#[derive(Debug, Clone, Copy)]
enum Law {
    Linear {
        k: f64,
    },
    /// f = k x + c x^3
    Cubic {
        k: f64,
        c: f64,
    },
    /// f = k x exp(-x / x0): maximum k x0 / e at x = x0.
    Soft {
        k: f64,
        x0: f64,
    },
}

impl Law {
    fn eval(self, x: f64) -> (f64, f64) {
        match self {
            Law::Linear { k } => (k * x, k),
            Law::Cubic { k, c } => (k * x + c * x * x * x, k + 3.0 * c * x * x),
            Law::Soft { k, x0 } => {
                let e = (-x / x0).exp();
                (k * x * e, k * e * (1.0 - x / x0))
            }
        }
    }
}

/// Axial springs along x on the nodes of one Quad4 cell.
///
/// State (3 values): `[0]` load factor of the evaluation, `[1]` largest
/// elongation of the first spring (written only when exceeded: a "lazy"
/// element that relies on the driver's restore), `[2]` a slot written only
/// by a failing evaluation.
#[derive(Debug, Default)]
struct Springs {
    /// (node a or ground, node b, law): elongation = u_b - u_a.
    springs: Vec<(Option<usize>, usize, Law)>,
    /// Wants small increments while the committed load factor is in this range.
    small_between: Option<(f64, f64)>,
    /// Fail (law error) on the first evaluation of this increment index.
    fail_at: Option<usize>,
    failed: AtomicBool,
    /// (increment, load factor, delta) of every evaluation.
    log: Mutex<Vec<StepInfo>>,
}

impl Element for Springs {
    fn key(&self) -> &'static str {
        "test_springs"
    }
    fn shape(&self) -> CellShape {
        CellShape::Quad4
    }
    fn num_points(&self) -> usize {
        1
    }
    fn state_len(&self) -> usize {
        3
    }
    fn compute(
        &self,
        ctx: &ElementContext<'_>,
        trial: &mut [f64],
        f: &mut [f64],
        k: Option<&mut [f64]>,
    ) -> Result<(), ElementError> {
        self.log.lock().unwrap().push(ctx.step);
        if self.fail_at == Some(ctx.step.increment) && !self.failed.swap(true, Ordering::SeqCst) {
            trial[1] = 1e9;
            trial[2] = 7.0;
            return Err(ElementError::Law {
                point: 0,
                message: "test failure".into(),
            });
        }
        trial[0] = ctx.step.load_factor;
        f.iter_mut().for_each(|v| *v = 0.0);
        let nd = f.len();
        let mut kk = k;
        if let Some(k) = kk.as_deref_mut() {
            k.iter_mut().for_each(|v| *v = 0.0);
        }
        for (i, &(a, b, law)) in self.springs.iter().enumerate() {
            let ua = a.map_or(0.0, |a| ctx.disp[3 * a]);
            let x = ctx.disp[3 * b] - ua;
            if i == 0 && x > ctx.state_committed[1] {
                trial[1] = x;
            }
            let (fs, ks) = law.eval(x);
            f[3 * b] += fs;
            if let Some(a) = a {
                f[3 * a] -= fs;
            }
            if let Some(k) = kk.as_deref_mut() {
                k[3 * b * nd + 3 * b] += ks;
                if let Some(a) = a {
                    k[3 * a * nd + 3 * a] += ks;
                    k[3 * a * nd + 3 * b] -= ks;
                    k[3 * b * nd + 3 * a] -= ks;
                }
            }
        }
        Ok(())
    }
    fn check_geometry(&self, _coords: &[[f64; 3]]) -> Result<(), ElementError> {
        Ok(())
    }
    fn point_outputs(&self, _ctx: &ElementContext<'_>) -> Result<Vec<PointOutput>, ElementError> {
        Ok(Vec::new())
    }
    fn wants_small_increments(&self, committed: &[f64]) -> bool {
        self.small_between
            .is_some_and(|(lo, hi)| committed[0] > lo && committed[0] < hi)
    }
}

/// A one-cell Quad4 model of springs: every dof constrained (to zero)
/// except the x dofs of `free_x`; `prescribed_x` gives (node, value) x
/// displacements at load factor 1; `force_x` (node, value) x forces.
fn spring_model(
    springs: Arc<Springs>,
    free_x: &[usize],
    prescribed_x: &[(usize, f64)],
    force_x: &[(usize, f64)],
) -> Model {
    let mesh = Mesh {
        nodes: vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [2.0, 0.0, 0.0],
            [3.0, 0.0, 0.0],
        ],
        blocks: vec![ElementBlock {
            name: "springs".into(),
            shape: CellShape::Quad4,
            connectivity: vec![0, 1, 2, 3],
            element_type: "test_springs".into(),
            material: "none".into(),
        }],
        ..Default::default()
    };
    let mut cons = Vec::new();
    for d in 0..12 {
        if d % 3 == 0 && free_x.contains(&(d / 3)) {
            continue;
        }
        let v = prescribed_x
            .iter()
            .find(|&&(n, _)| d == 3 * n)
            .map_or(0.0, |&(_, v)| v);
        cons.push((d, v));
    }
    let mut f = vec![0.0; 12];
    for &(n, v) in force_x {
        f[3 * n] = v;
    }
    Model::new(mesh, vec![springs], &cons, f, vec![]).unwrap()
}

/// Run and collect the reports (and the residual histories).
struct Recorded {
    reports: Vec<IncrementReport>,
    histories: Vec<Vec<f64>>,
    /// (u, residual) after every increment.
    fields: Vec<(Vec<f64>, Vec<f64>)>,
    checkpoints: Vec<Checkpoint>,
    result: Result<NonlinearRun, NonlinearError>,
}

fn run(
    model: &Model,
    program: &[f64],
    settings: &NewtonSettings,
    restart: Option<&Checkpoint>,
    stop_after: Option<usize>,
) -> Recorded {
    let mut solver = CholeskySolver::new(Default::default());
    run_with(model, &mut solver, program, settings, restart, stop_after)
}

fn run_with(
    model: &Model,
    solver: &mut dyn LinearSolver,
    program: &[f64],
    settings: &NewtonSettings,
    restart: Option<&Checkpoint>,
    stop_after: Option<usize>,
) -> Recorded {
    let mut reports = Vec::new();
    let mut histories = Vec::new();
    let mut fields = Vec::new();
    let mut checkpoints = Vec::new();
    let result = solve_nonlinear(model, solver, program, settings, restart, |v| {
        reports.push(v.report.clone());
        histories.push(v.residual_history.to_vec());
        fields.push((v.u.to_vec(), v.residual.to_vec()));
        checkpoints.push(v.checkpoint());
        if stop_after == Some(reports.len()) {
            Control::Stop
        } else {
            Control::Continue
        }
    });
    Recorded {
        reports,
        histories,
        fields,
        checkpoints,
        result,
    }
}

/// A cantilever box of H8 clamped at x = 0, with a prescribed z
/// displacement on the x = 1 face and y forces on the y = 1 face.
fn linear_box() -> Model {
    let mesh = box_mesh(
        &BoxSpec::new([1.0, 0.4, 0.3], [5, 2, 2], CellShape::Hex8),
        "b",
        "h8",
        "steel",
    )
    .unwrap();
    let mat = Arc::new(Isotropic::new(200e9, 0.3).unwrap());
    let el = Arc::new(SolidElement::new(CellShape::Hex8, Integration::Full, mat).unwrap());
    let mut cons = Vec::new();
    for &n in mesh.node_set("x0").unwrap() {
        for c in 0..3 {
            cons.push((3 * n + c, 0.0));
        }
    }
    for &n in mesh.node_set("x1").unwrap() {
        cons.push((3 * n + 2, 1e-4));
    }
    let mut f = vec![0.0; 3 * mesh.nodes.len()];
    for &n in mesh.node_set("y1").unwrap() {
        f[3 * n + 1] = 1e5;
    }
    Model::new(mesh, vec![el], &cons, f, vec![]).unwrap()
}

/// Counts the solver's calls.
#[derive(Debug)]
struct Counting {
    inner: CholeskySolver,
    analyze: usize,
    factorize: usize,
    solve: usize,
}

impl LinearSolver for Counting {
    fn key(&self) -> &'static str {
        "counting"
    }
    fn analyze(&mut self, a: &SymmetricCsc, c: Option<&[[f64; 3]]>) -> Result<(), SolverError> {
        self.analyze += 1;
        self.inner.analyze(a, c)
    }
    fn factorize(&mut self, a: &SymmetricCsc) -> Result<(), SolverError> {
        self.factorize += 1;
        self.inner.factorize(a)
    }
    fn solve_in_place(&mut self, a: &SymmetricCsc, b: &mut [f64]) -> Result<(), SolverError> {
        self.solve += 1;
        self.inner.solve_in_place(a, b)
    }
    fn report(&self) -> SolveReport {
        self.inner.report()
    }
}

// ---------------------------------------------------------------- tests

/// Test 1: A linear model in several increments equals the linear solve, and
/// every increment converges in one iteration.
#[test]
fn linear_model_matches_linear_static_in_one_iteration_per_increment() {
    let model = linear_box();
    let mut s = CholeskySolver::new(Default::default());
    let lin = solve_linear_static(&model, &mut s).unwrap();
    let settings = NewtonSettings {
        initial_increment: 0.2,
        ..Default::default()
    };
    let r = run(&model, &[1.0], &settings, None, None);
    let out = r.result.unwrap();
    let n = r.reports.len();
    assert!(n >= 4, "{n} increments");
    for rep in &r.reports {
        assert_eq!(rep.iterations, 1, "{rep:?}");
        assert!(rep.residual <= 1e-6 && rep.energy <= 1e-12, "{rep:?}");
    }
    assert_eq!(r.reports.last().unwrap().lambda, 1.0);
    let scale = lin.u.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let err = out
        .u
        .iter()
        .zip(&lin.u)
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    assert!(err <= 1e-10 * scale, "error {err:e} (scale {scale:e})");
    // reactions agree too
    let rs = lin.residual.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let rerr = out
        .residual
        .iter()
        .zip(&lin.residual)
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    assert!(rerr <= 1e-8 * rs, "reaction error {rerr:e} (scale {rs:e})");
    assert_eq!(out.summary.increments, n);
    assert_eq!(out.summary.newton_iterations_total, n);
    assert!(!out.summary.stopped_by_observer);
}

/// Real root of k u + c u^3 = f (Cardano; one real root for k, c > 0).
fn cubic_root(k: f64, c: f64, f: f64) -> f64 {
    let (p, q) = (k / c, f / c);
    let d = (q * q / 4.0 + p * p * p / 27.0).sqrt();
    (q / 2.0 + d).cbrt() + (q / 2.0 - d).cbrt()
}

/// Test 2: Hardening spring under force control: quadratic convergence and the
/// closed-form root.
#[test]
fn hardening_spring_converges_quadratically_to_the_root() {
    let (k, c, f) = (1.0, 1.0, 10.0);
    let sp = Arc::new(Springs {
        springs: vec![(None, 1, Law::Cubic { k, c })],
        ..Default::default()
    });
    let model = spring_model(sp, &[1], &[], &[(1, f)]);
    let settings = NewtonSettings {
        initial_increment: 0.5,
        max_increment: 1.0,
        tol_force: 1e-12,
        ..Default::default()
    };
    let r = run(&model, &[1.0], &settings, None, None);
    let out = r.result.unwrap();
    let mut quadratic_pairs = 0;
    for (rep, h) in r.reports.iter().zip(&r.histories) {
        println!(
            "lambda {} iterations {} history {h:?}",
            rep.lambda, rep.iterations
        );
        assert!(rep.iterations <= 6, "{rep:?}");
        assert_eq!(h.len(), rep.iterations + 1);
        // in the quadratic regime, r_{i+1} <= C r_i^2
        for w in h.windows(2) {
            if w[0] < 1e-2 && w[1] > 1e-15 {
                assert!(w[1] <= 10.0 * w[0] * w[0], "not quadratic: {h:?}");
                quadratic_pairs += 1;
            }
        }
    }
    assert!(quadratic_pairs >= 1);
    let root = cubic_root(k, c, f);
    assert!((root - 2.0).abs() < 1e-12);
    assert!((out.u[3] - root).abs() <= 1e-10 * root, "u = {}", out.u[3]);
}

/// Test 3: Force control past a limit point: cut-backs, then IncrementTooSmall
/// at the limit; every converged increment was reported.
#[test]
fn force_control_stops_at_the_limit_point_with_its_numbers() {
    let (k, x0) = (1.0, 1.0);
    let fmax = k * x0 / std::f64::consts::E;
    let sp = Arc::new(Springs {
        springs: vec![(None, 1, Law::Soft { k, x0 })],
        ..Default::default()
    });
    let model = spring_model(sp, &[1], &[], &[(1, 1.0)]);
    let settings = NewtonSettings {
        min_increment: 1e-5,
        ..Default::default()
    };
    let end = 1.2 * fmax;
    let r = run(&model, &[end], &settings, None, None);
    let Err(NonlinearError::IncrementTooSmall {
        lambda,
        increment,
        last_residual,
        iterations,
        reason,
        step,
    }) = &r.result
    else {
        panic!(
            "expected IncrementTooSmall, got {:?}",
            r.result.as_ref().map(|x| &x.summary)
        );
    };
    let msg = r.result.as_ref().unwrap_err().to_string();
    println!("{msg}");
    println!("reason {reason:?}, {iterations} iterations, residual {last_residual:e}");
    assert_eq!(*step, 0);
    assert!(*lambda < fmax, "{lambda} >= {fmax}");
    // within two minimum increments of the limit
    assert!(
        fmax - lambda <= 2.0 * settings.min_increment * end,
        "{lambda} vs {fmax}"
    );
    // the failed attempt was at least the minimum; its cut-back would not be
    let inc = increment.abs() / end;
    assert!(inc >= settings.min_increment && inc * settings.cutback < settings.min_increment);
    assert!(msg.contains("lambda") && msg.contains(&format!("{lambda:.9e}")));
    assert!(!matches!(reason, IncrementFailure::Element(_)));
    // reported increments: increasing lambda, the last one is the error's
    assert!(r.reports.len() > 5);
    assert!(r.reports.windows(2).all(|w| w[1].lambda > w[0].lambda));
    assert_eq!(r.reports.last().unwrap().lambda, *lambda);
    assert!(r.reports.iter().any(|rep| rep.cutbacks > 0));
    for (i, rep) in r.reports.iter().enumerate() {
        assert_eq!(rep.increment_index, i + 1);
    }
    // the last converged state is on the curve: f(u) = lambda
    let (u, _) = r.fields.last().unwrap();
    let (fu, _) = Law::Soft { k, x0 }.eval(u[3]);
    assert!((fu - lambda).abs() <= 1e-5 * fmax, "{fu} vs {lambda}");
    assert!(u[3] < x0);
}

/// Test 4: Displacement control through the softening spring (in series with a
/// linear one) passes the limit point; the reaction follows f(u).
#[test]
fn displacement_control_passes_the_limit_point() {
    let (k, x0) = (1.0, 1.0);
    let fmax = k * x0 / std::f64::consts::E;
    let sp = Arc::new(Springs {
        springs: vec![
            (None, 1, Law::Soft { k, x0 }),
            (Some(1), 2, Law::Linear { k }),
        ],
        ..Default::default()
    });
    // node 2 prescribed (u = lambda), node 1 free
    let model = spring_model(sp, &[1], &[(2, 1.0)], &[]);
    let settings = NewtonSettings {
        max_increment: 0.05,
        ..Default::default()
    };
    let r = run(&model, &[4.0 * x0], &settings, None, None);
    let out = r.result.unwrap();
    assert_eq!(out.summary.final_lambda, 4.0 * x0);
    let mut peak: f64 = 0.0;
    for (rep, (u, res)) in r.reports.iter().zip(&r.fields) {
        let reaction = res[6];
        let (fu, _) = Law::Soft { k, x0 }.eval(u[3]);
        assert_eq!(u[6], rep.lambda);
        assert!((reaction - fu).abs() <= 1e-6 * fmax, "{reaction} vs {fu}");
        assert!((reaction - k * (u[6] - u[3])).abs() <= 1e-12);
        peak = peak.max(reaction);
    }
    let last = r.fields.last().unwrap().1[6];
    assert!(peak > 0.97 * fmax && peak <= fmax * (1.0 + 1e-9), "{peak}");
    assert!(
        last < 0.5 * fmax,
        "final reaction {last} not on the descending branch"
    );
    assert_eq!(out.summary.cutbacks, 0);
}

/// Test 5: The symbolic analysis is done once per run.
#[test]
fn symbolic_analysis_is_done_once_per_run() {
    let sp = Arc::new(Springs {
        springs: vec![
            (None, 1, Law::Cubic { k: 1.0, c: 1.0 }),
            (Some(1), 2, Law::Linear { k: 2.0 }),
        ],
        ..Default::default()
    });
    let model = spring_model(sp, &[1, 2], &[], &[(2, 10.0)]);
    let mut solver = Counting {
        inner: CholeskySolver::new(Default::default()),
        analyze: 0,
        factorize: 0,
        solve: 0,
    };
    let settings = NewtonSettings {
        initial_increment: 0.02,
        max_increment: 0.05,
        ..Default::default()
    };
    let r = run_with(&model, &mut solver, &[1.0, 0.5], &settings, None, None);
    let out = r.result.unwrap();
    assert!(out.summary.increments >= 20, "{}", out.summary.increments);
    assert_eq!(solver.analyze, 1);
    assert_eq!(out.summary.analyze_count, 1);
    assert_eq!(solver.factorize, out.summary.newton_iterations_total);
    assert_eq!(solver.solve, out.summary.newton_iterations_total);
    assert!(out.summary.newton_iterations_total > out.summary.increments);
    let total: usize = r.reports.iter().map(|r| r.iterations).sum();
    assert_eq!(total, out.summary.newton_iterations_total);
    assert_eq!(out.summary.final_lambda, 0.5);
}

/// Test 6: While an element wants small increments, they are constant and
/// small; afterwards the adaptive size grows again.
#[test]
fn small_increments_while_an_element_asks() {
    let sp = Arc::new(Springs {
        springs: vec![(None, 1, Law::Cubic { k: 1.0, c: 0.1 })],
        small_between: Some((0.4, 0.7)),
        ..Default::default()
    });
    let model = spring_model(sp, &[1], &[], &[(1, 1.0)]);
    let settings = NewtonSettings::default();
    let small = settings.small_increment();
    assert_eq!(small, 0.01);
    let r = run(&model, &[1.0], &settings, None, None);
    r.result.unwrap();
    let reps = &r.reports;
    for w in reps.windows(2) {
        let prev_in = w[0].lambda > 0.4 && w[0].lambda < 0.7;
        assert_eq!(w[1].small_increment_mode, prev_in, "{:?}", w[1]);
        if prev_in {
            assert!((w[1].delta_lambda - small).abs() < 1e-12, "{:?}", w[1]);
        }
    }
    let n_small = reps.iter().filter(|r| r.small_increment_mode).count();
    assert!(n_small >= 15, "{n_small} small increments");
    // before: the normal size (>= 0.1); after: growth from the small size
    assert!(reps[0].delta_lambda >= 0.1);
    let first_after = reps
        .iter()
        .position(|r| r.lambda >= 0.7 && !r.small_increment_mode)
        .unwrap();
    assert!((reps[first_after].delta_lambda - 1.5 * small).abs() < 1e-12);
    assert!(reps[first_after + 1].delta_lambda > reps[first_after].delta_lambda);
}

/// Test 7: Restart: stopping after increment j and restarting from the
/// checkpoint (through TOML) gives exactly the uninterrupted increments.
#[test]
fn restart_gives_the_uninterrupted_increments() {
    let mk = || {
        let sp = Arc::new(Springs {
            springs: vec![
                (None, 1, Law::Soft { k: 1.0, x0: 1.0 }),
                (Some(1), 2, Law::Linear { k: 1.0 }),
            ],
            small_between: Some((1.5, 2.0)),
            ..Default::default()
        });
        spring_model(sp, &[1], &[(2, 1.0)], &[])
    };
    let model = mk();
    let program = [3.0, 1.0];
    let settings = NewtonSettings::default();
    let full = run(&model, &program, &settings, None, None);
    let full_out = full.result.unwrap();
    let n = full.reports.len();
    assert!(n > 10);
    assert!(full.reports.iter().any(|r| r.small_increment_mode));
    assert!(full.reports.iter().any(|r| r.step == 1));
    let key = |r: &IncrementReport| {
        (
            r.step,
            r.increment_index,
            r.lambda,
            r.delta_lambda,
            r.iterations,
            r.cutbacks,
            r.small_increment_mode,
        )
    };
    // every stopping point: inside steps, at the step boundary, in and
    // out of the small-increment mode, at the very end
    for j in 1..=n {
        let model = mk();
        let first = run(&model, &program, &settings, None, Some(j));
        let out = first.result.unwrap();
        assert!(out.summary.stopped_by_observer);
        assert_eq!(first.reports.len(), j);
        let ck = first.checkpoints.last().unwrap().clone();
        assert_eq!(ck, out.checkpoint());
        let text = toml::to_string(&ck).unwrap();
        let ck2: Checkpoint = toml::from_str(&text).unwrap();
        assert_eq!(ck2, ck);
        let second = run(&model, &program, &settings, Some(&ck2), None);
        let out2 = second.result.unwrap();
        let joined: Vec<_> = first
            .reports
            .iter()
            .chain(&second.reports)
            .map(key)
            .collect();
        let expect: Vec<_> = full.reports.iter().map(key).collect();
        assert_eq!(joined, expect, "restart after {j}");
        for (a, b) in out2.u.iter().zip(&full_out.u) {
            assert!((a - b).abs() <= 1e-14, "u differs after restart at {j}");
        }
        assert_eq!(out2.state.committed, full_out.state.committed);
    }
}

/// Test 8: A failing evaluation's trial state does not leak into the committed
/// state; the retry keeps the increment index.
#[test]
fn cutback_restores_the_trial_state() {
    let mk = |fail_at| {
        Arc::new(Springs {
            springs: vec![(None, 1, Law::Cubic { k: 1.0, c: 0.5 })],
            fail_at,
            ..Default::default()
        })
    };
    let failing = mk(Some(2));
    let clean = mk(None);
    let m_fail = spring_model(failing.clone(), &[1], &[], &[(1, 2.0)]);
    let m_clean = spring_model(clean, &[1], &[], &[(1, 2.0)]);
    let settings = NewtonSettings::default();
    let a = run(&m_fail, &[1.0], &settings, None, None);
    let b = run(&m_clean, &[1.0], &settings, None, None);
    let (a_out, b_out) = (a.result.unwrap(), b.result.unwrap());
    assert!(failing.failed.load(Ordering::SeqCst));
    assert_eq!(a_out.summary.cutbacks, 1);
    assert_eq!(b_out.summary.cutbacks, 0);
    assert_eq!(a.reports[1].cutbacks, 1);
    assert_eq!(a.reports[1].increment_index, 2);
    // garbage slot never committed, history variable path-independent
    let (sa, sb) = (&a_out.state.committed, &b_out.state.committed);
    assert_eq!(sa[2], 0.0);
    assert_eq!(sa[0], 1.0);
    assert_eq!(sa[0], sb[0]);
    assert!((sa[1] - sb[1]).abs() <= 1e-9 * sb[1], "{sa:?} vs {sb:?}");
    assert!((sa[1] - a_out.u[3]).abs() <= 1e-15);
    assert_eq!(a_out.state.trial, a_out.state.committed);
    // every evaluation of increment 2 (failed try and retry) says 2; the
    // retry has half the load-factor increment
    let log = failing.log.lock().unwrap();
    let inc2: Vec<&StepInfo> = log.iter().filter(|s| s.increment == 2).collect();
    let failed = inc2[0];
    let retry = inc2.last().unwrap();
    assert!((retry.delta_load_factor - 0.5 * failed.delta_load_factor).abs() < 1e-15);
    assert_eq!(retry.load_factor, a.reports[1].lambda);
    assert_eq!(log.first().unwrap().increment, 1);
    assert!(log.windows(2).all(|w| w[1].increment >= w[0].increment));
}

/// Zero-length steps and bad input.
#[test]
fn bad_program_and_checkpoint_are_errors() {
    let sp = Arc::new(Springs {
        springs: vec![(None, 1, Law::Linear { k: 1.0 })],
        ..Default::default()
    });
    let model = spring_model(sp, &[1], &[], &[(1, 1.0)]);
    let s = NewtonSettings::default();
    assert!(matches!(
        run(&model, &[], &s, None, None).result,
        Err(NonlinearError::Core(_))
    ));
    let bad = NewtonSettings {
        cutback: 1.5,
        ..Default::default()
    };
    assert!(matches!(
        run(&model, &[1.0], &bad, None, None).result,
        Err(NonlinearError::Core(_))
    ));
    let mut ck = run(&model, &[1.0], &s, None, Some(1)).checkpoints[0].clone();
    ck.u.pop();
    assert!(matches!(
        run(&model, &[1.0], &s, Some(&ck), None).result,
        Err(NonlinearError::Core(_))
    ));
    // a hold step (same end) is one increment with no iteration
    let r = run(&model, &[1.0, 1.0], &s, None, None);
    r.result.unwrap();
    let last = r.reports.last().unwrap();
    assert_eq!((last.step, last.iterations, last.delta_lambda), (1, 0, 0.0));
}

/// A tolerance below round-off (`tol_force = 1e-300`) with a huge iteration
/// limit: every attempt stops as stagnated after a few iterations, and the
/// run ends with an error carrying the numbers instead of iterating 1e8
/// times per attempt.
#[test]
fn unreachable_tolerance_stops_on_stagnation_with_its_numbers() {
    let sp = Arc::new(Springs {
        springs: vec![(None, 1, Law::Cubic { k: 1.0, c: 1.0 })],
        ..Default::default()
    });
    let model = spring_model(sp, &[1], &[], &[(1, 10.0)]);
    let settings = NewtonSettings {
        tol_force: 1e-300,
        max_iterations: 100_000_000,
        ..Default::default()
    };
    let r = run(&model, &[1.0], &settings, None, None);
    let e = r.result.unwrap_err().to_string();
    assert!(e.contains("stagnated") && e.contains("1.000e-300"), "{e}");
    // increments that reach a residual of exactly 0 converge; none took
    // more iterations than the stagnation window allows
    assert!(
        r.reports.iter().all(|rep| rep.iterations < 100),
        "{:?}",
        r.reports
    );
}
