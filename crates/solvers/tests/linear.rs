//! Integration tests of the linear back ends on model grid matrices.

use junta_core::registry::{entries, find, SolverEntry};
use junta_core::{LinearSolver, SolverError, SymmetricCsc};
use junta_solvers as _;
use junta_solvers::gallery::{grid_3d, grid_3d_neumann, Stencil};
use junta_solvers::ordering::{self, OrderingKind};
use junta_solvers::{
    CgSettings, CgSolver, CholeskySettings, CholeskySolver, Precision, Preconditioner,
};
use std::time::Instant;

/// A known, non-trivial solution.
fn exact(n: usize) -> Vec<f64> {
    (0..n)
        .map(|i| ((i * 37 % 101) as f64 - 50.0) / 25.0 + (i as f64 * 0.01).sin())
        .collect()
}

fn rhs(a: &SymmetricCsc, x: &[f64]) -> Vec<f64> {
    let mut b = vec![0.0; a.n];
    a.mul_vec(x, &mut b);
    b
}

fn max_rel_error(x: &[f64], xs: &[f64]) -> f64 {
    let scale = xs.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    x.iter()
        .zip(xs)
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()))
        / scale
}

fn solve_with(solver: &mut dyn LinearSolver, a: &SymmetricCsc, coords: &[[f64; 3]]) -> Vec<f64> {
    let xs = exact(a.n);
    let mut x = rhs(a, &xs);
    solver.analyze(a, Some(coords)).unwrap();
    solver.factorize(a).unwrap();
    solver.solve_in_place(a, &mut x).unwrap();
    x
}

#[test]
fn cholesky_nd_and_amd_solve_the_grid() {
    let (a, coords) = grid_3d(12, 12, 12, 3, Stencil::Point7);
    let xs = exact(a.n);
    for ordering in [OrderingKind::NestedDissection, OrderingKind::Amd] {
        let mut s = CholeskySolver::new(CholeskySettings {
            ordering,
            ..Default::default()
        });
        let x = solve_with(&mut s, &a, &coords);
        let err = max_rel_error(&x, &xs);
        let r = s.report();
        println!(
            "cholesky {ordering:?}: error {err:.2e}, residual {:.2e}, factor nnz {}",
            r.residual, r.factor_nonzeros
        );
        assert!(err < 1e-10, "{ordering:?}: error {err:e}");
        assert!(r.residual < 1e-12);
        assert!(r.factor_nonzeros > a.nnz());
        assert!(r.warnings.is_empty(), "{:?}", r.warnings);
        assert_eq!(r.solver, "cholesky");
        assert!(s.stats().min_pivot_ratio > 1e-3 && s.stats().min_pivot_ratio <= 1.0);
    }
}

#[test]
fn cg_both_preconditioners_solve_the_grid() {
    let (a, coords) = grid_3d(12, 12, 12, 3, Stencil::Point7);
    let xs = exact(a.n);
    let mut iterations = Vec::new();
    for preconditioner in [Preconditioner::Jacobi, Preconditioner::BlockJacobi] {
        let mut s = CgSolver::new(CgSettings {
            preconditioner,
            tol: 1e-12,
            ..Default::default()
        });
        let x = solve_with(&mut s, &a, &coords);
        let err = max_rel_error(&x, &xs);
        let r = s.report();
        println!(
            "cg {preconditioner:?}: error {err:.2e}, {} iterations, residual {:.2e}",
            r.iterations, r.residual
        );
        assert!(err < 1e-8, "{preconditioner:?}: error {err:e}");
        assert!(r.residual <= 1e-12);
        assert!(r.iterations > 5 && r.iterations < 500);
        iterations.push(r.iterations);
    }
    // The 3x3 node blocks of L ⊗ B are exactly B-scaled: block-Jacobi
    // removes B and needs fewer iterations than scalar Jacobi.
    assert!(iterations[1] < iterations[0], "{iterations:?}");
}

#[test]
fn symbolic_analysis_is_reused_across_factorisations() {
    let (a, coords) = grid_3d(8, 7, 6, 3, Stencil::Point27);
    let mut s = CholeskySolver::new(Default::default());
    s.analyze(&a, Some(&coords)).unwrap();
    let analyze_seconds = s.report().analyze_seconds;
    // Two matrices with the same pattern: A and 3 A + 2 I.
    let mut a2 = a.clone();
    for v in &mut a2.values {
        *v *= 3.0;
    }
    for j in 0..a2.n {
        let p = a2.position(j, j).unwrap();
        a2.values[p] += 2.0;
    }
    let xs = exact(a.n);
    for m in [&a, &a2, &a] {
        s.factorize(m).unwrap();
        let mut x = rhs(m, &xs);
        s.solve_in_place(m, &mut x).unwrap();
        assert!(max_rel_error(&x, &xs) < 1e-10);
    }
    let st = s.stats();
    assert_eq!(st.analyze_count, 1);
    assert_eq!(st.factor_count, 3);
    assert_eq!(st.solve_count, 3);
    assert_eq!(s.report().analyze_seconds, analyze_seconds);
    assert!(s.report().factor_seconds > 0.0);

    // A different pattern is refused, not silently mis-factorised.
    let (b, _) = grid_3d(8, 7, 5, 3, Stencil::Point27);
    assert!(matches!(s.factorize(&b), Err(SolverError::Usage(_))));

    // CG too analyses once.
    let mut cg = CgSolver::new(Default::default());
    cg.analyze(&a, Some(&coords)).unwrap();
    for m in [&a, &a2] {
        cg.factorize(m).unwrap();
        let mut x = rhs(m, &xs);
        cg.solve_in_place(m, &mut x).unwrap();
        assert!(max_rel_error(&x, &xs) < 1e-8);
    }
    assert_eq!(cg.analyze_count(), 1);
}

#[test]
fn nested_dissection_is_a_permutation_with_less_fill() {
    let (a, coords) = grid_3d(12, 12, 12, 3, Stencil::Point7);
    let t = Instant::now();
    let nd = ordering::nested_dissection(&a, Some(&coords));
    let t_nd = t.elapsed().as_secs_f64();
    let nd_graph = ordering::nested_dissection(&a, None);
    let amd = ordering::amd_ordering(&a);
    for p in [&nd, &nd_graph, &amd] {
        assert!(ordering::is_permutation(p, a.n));
    }
    let natural = ordering::factor_nonzeros(&a, None);
    let f_nd = ordering::factor_nonzeros(&a, Some(&nd));
    let f_graph = ordering::factor_nonzeros(&a, Some(&nd_graph));
    let f_amd = ordering::factor_nonzeros(&a, Some(&amd));
    println!(
        "12^3 grid, 7-point, 3 dofs/node (n = {}, nnz(A upper) = {}): nnz(L) natural {natural}, \
         ND geometric {f_nd} ({t_nd:.3} s), ND graph {f_graph}, AMD {f_amd}",
        a.n,
        a.nnz()
    );
    assert!(f_nd < natural);
    assert!(f_graph < natural);
    // faer's own symbolic factor agrees with the ordering module's count
    // (within supernode relaxation, which only adds explicit zeros).
    let mut s = CholeskySolver::new(CholeskySettings {
        ordering: OrderingKind::NestedDissection,
        ..Default::default()
    });
    s.analyze(&a, Some(&coords)).unwrap();
    assert!(s.stats().factor_nonzeros >= f_nd);
    assert!(s.stats().factor_nonzeros < 2 * f_nd);
    assert_eq!(s.permutation(), nd.as_slice());
    // the default (auto) keeps whichever of the two predicts fewer flops
    let mut auto = CholeskySolver::new(Default::default());
    auto.analyze(&a, Some(&coords)).unwrap();
    let kept = match auto.stats().ordering {
        "nested_dissection" => &nd,
        "amd" => &amd,
        other => panic!("auto kept {other}"),
    };
    assert_eq!(auto.permutation(), kept.as_slice());
}

#[test]
fn singular_matrices_are_refused() {
    // Neumann grid: constants in the kernel; floating-point elimination
    // meets a tiny (not necessarily negative) last pivot.
    let (a, coords) = grid_3d_neumann(6, 6, 6, 3, Stencil::Point27);
    for ordering in [OrderingKind::NestedDissection, OrderingKind::Amd] {
        let mut s = CholeskySolver::new(CholeskySettings {
            ordering,
            ..Default::default()
        });
        s.analyze(&a, Some(&coords)).unwrap();
        match s.factorize(&a) {
            Err(SolverError::NotPositiveDefinite { detail }) => {
                println!("{ordering:?}: {detail}")
            }
            other => panic!("{ordering:?}: expected NotPositiveDefinite, got {other:?}"),
        }
        // no usable factor: solving is a usage error, not NaN
        let mut b = vec![1.0; a.n];
        assert!(matches!(
            s.solve_in_place(&a, &mut b),
            Err(SolverError::Usage(_))
        ));
        assert!(b.iter().all(|v| *v == 1.0));
    }
    // A zero column (an equation without stiffness).
    let (mut z, zc) = grid_3d(4, 4, 4, 3, Stencil::Point7);
    let k = 40;
    for j in 0..z.n {
        for p in z.col_ptr[j]..z.col_ptr[j + 1] {
            if j == k || z.row_idx[p] == k {
                z.values[p] = 0.0;
            }
        }
    }
    let mut s = CholeskySolver::new(Default::default());
    s.analyze(&z, Some(&zc)).unwrap();
    let e = s.factorize(&z).unwrap_err();
    assert!(matches!(e, SolverError::NotPositiveDefinite { .. }));
    assert!(e.to_string().contains("equation 40"), "{e}");
}

/// The grid matrix with huge penalties coupling a few node pairs.
fn penalised(p: f64) -> (SymmetricCsc, Vec<[f64; 3]>) {
    let (mut a, coords) = grid_3d(8, 8, 8, 3, Stencil::Point7);
    // couple dof (node, 0) with dof (node + 1, 0): k (u_i - u_j)^2
    for node in [10usize, 100, 200, 300] {
        let (i, j) = (3 * node, 3 * (node + 1));
        let pij = a.position(i, j).expect("grid neighbours are coupled");
        let pii = a.position(i, i).unwrap();
        let pjj = a.position(j, j).unwrap();
        a.values[pii] += p;
        a.values[pjj] += p;
        a.values[pij] -= p;
    }
    (a, coords)
}

#[test]
fn cg_on_an_ill_conditioned_matrix_reports_non_convergence() {
    let budget = 300;
    let settings = CgSettings {
        preconditioner: Preconditioner::Jacobi,
        tol: 1e-10,
        max_iterations: Some(budget),
        ..Default::default()
    };
    // A unit load on every dof.
    let b = |n: usize| vec![1.0; n];
    // Without the penalty the budget is ample.
    let (a0, coords) = penalised(0.0);
    let mut s = CgSolver::new(settings);
    s.analyze(&a0, Some(&coords)).unwrap();
    s.factorize(&a0).unwrap();
    let mut x = b(a0.n);
    s.solve_in_place(&a0, &mut x).unwrap();
    let its0 = s.report().iterations;
    assert!(its0 < budget / 2, "{its0}");
    // With a penalty of 1e12 (still SPD in floating point), CG runs out of
    // iterations and says so with its numbers.
    let (a, _) = penalised(1e12);
    s.factorize(&a).unwrap();
    let rhs = b(a.n);
    let mut x = rhs.clone();
    match s.solve_in_place(&a, &mut x) {
        Err(SolverError::NotConverged {
            iterations,
            residual,
            tolerance,
            ..
        }) => {
            println!(
                "cg penalty 1e12: {iterations} iterations, residual {residual:.3e} (unpenalised: {its0} iterations)"
            );
            assert!(iterations <= budget);
            assert!(residual > tolerance && residual.is_finite());
        }
        other => panic!(
            "expected NotConverged, got {other:?} after {} iterations, residual {:e}",
            s.report().iterations,
            s.report().residual
        ),
    }
    assert_eq!(x, rhs, "the right-hand side is left untouched on failure");
    assert!(s.report().residual > 1e-10);
    // A penalty of 1e20 against unit stiffness: the stored matrix is not
    // even positive definite any more (12 + 1e20 rounds to 1e20). CG must
    // fail loudly (breakdown or non-convergence), never return an x.
    let (a, _) = penalised(1e20);
    s.factorize(&a).unwrap();
    assert!(
        !s.report().warnings.is_empty(),
        "diagonal spread is flagged"
    );
    let mut x = rhs.clone();
    let e = s.solve_in_place(&a, &mut x).unwrap_err();
    println!("cg penalty 1e20: {e}");
    assert!(matches!(
        e,
        SolverError::NotConverged { .. } | SolverError::NotPositiveDefinite { .. }
    ));
    assert_eq!(x, rhs);
}

#[test]
fn cholesky_warns_on_a_penalty_that_ruins_digits() {
    // Moderate penalty: solvable, no warning.
    let (a, coords) = penalised(1e6);
    let xs = exact(a.n);
    let mut s = CholeskySolver::new(Default::default());
    s.analyze(&a, Some(&coords)).unwrap();
    s.factorize(&a).unwrap();
    let mut x = rhs(&a, &xs);
    s.solve_in_place(&a, &mut x).unwrap();
    assert!(s.report().warnings.is_empty(), "{:?}", s.report().warnings);
    assert!(max_rel_error(&x, &xs) < 1e-6);
    // 1e20 against unit stiffness: the pair's Schur complement (2 + ...)
    // is lost to rounding in 1e20; either the factorisation is refused as
    // singular or the report carries a warning with the numbers.
    let (a, _) = penalised(1e20);
    s.factorize(&a).map_or_else(
        |e| {
            println!("penalty 1e20: {e}");
            assert!(matches!(e, SolverError::NotPositiveDefinite { .. }));
        },
        |_| {
            let mut x = rhs(&a, &xs);
            let res = s.solve_in_place(&a, &mut x);
            println!("penalty 1e20: {res:?} {:?}", s.report().warnings);
            assert!(!s.report().warnings.is_empty());
        },
    );
}

/// The mixed mode (single-precision factor, refinement in double) reaches
/// the accuracy of the double factor on a well-conditioned matrix, and
/// falls back to double by itself where single precision cannot work: a
/// penalty (caught by the pivot ratio of the single factor) and an
/// ill-conditioned chain with a uniform diagonal (caught by refinement
/// that does not converge).
/// The triangular solves split at the first branching of the elimination
/// tree (`parallel_solve_entries`): the subtrees in parallel, each adding
/// its updates of the separator's rows into its own buffer. With nested
/// dissection (a real tree) the split solve gives the serial one's solution
/// to round-off, in double and in single precision, and the exact solution
/// to the factor's accuracy (no refinement to mend it).
#[test]
fn parallel_cholesky_solves_equal_the_serial_ones() {
    let (a, coords) = grid_3d(12, 12, 12, 3, Stencil::Point27);
    let xs = exact(a.n);
    let b = rhs(&a, &xs);
    for precision in [Precision::Double, Precision::Mixed] {
        let solve = |entries: usize| {
            let mut s = CholeskySolver::new(CholeskySettings {
                ordering: OrderingKind::NestedDissection,
                threads: 2,
                parallel_solve_entries: entries,
                precision,
                mixed_min_equations: 0,
                max_refinements: 0,
                ..Default::default()
            });
            s.analyze(&a, Some(&coords)).unwrap();
            s.factorize(&a).unwrap();
            let mut x = b.clone();
            s.solve_in_place(&a, &mut x).unwrap();
            (x, s.stats().solve_tasks)
        };
        let ((xs1, serial_tasks), (xp, parallel_tasks)) = (solve(usize::MAX), solve(0));
        assert_eq!(serial_tasks, 0);
        assert!(
            parallel_tasks >= 2,
            "{precision:?}: {parallel_tasks} subtrees"
        );
        let apart = max_rel_error(&xp, &xs1);
        assert!(apart < 1e-12, "{precision:?}: {apart:e}");
        assert!(
            max_rel_error(&xp, &xs) < 1e-10,
            "{precision:?}: {:e}",
            max_rel_error(&xp, &xs)
        );
    }
}

#[test]
fn mixed_precision_refines_to_double_accuracy_or_falls_back() {
    // auto's size threshold off, so that these small matrices qualify
    let solver = |precision| {
        CholeskySolver::new(CholeskySettings {
            precision,
            mixed_min_equations: 0,
            ..Default::default()
        })
    };
    // 1. well conditioned: mixed (forced, and chosen by auto)
    let (a, coords) = grid_3d(12, 12, 12, 3, Stencil::Point27);
    let xs = exact(a.n);
    let mut d = solver(Precision::Double);
    let xd = solve_with(&mut d, &a, &coords);
    assert_eq!(d.report().precision, "double");
    // the default auto keeps 5184 equations (< mixed_min_equations) in double
    let mut d = CholeskySolver::new(Default::default());
    solve_with(&mut d, &a, &coords);
    assert_eq!(d.report().precision, "double");
    for precision in [Precision::Mixed, Precision::Auto] {
        let mut s = solver(precision);
        let x = solve_with(&mut s, &a, &coords);
        let r = s.report();
        println!(
            "{precision:?}: {} with {} refinement steps, residual {:.2e}, error {:.2e} (double: {:.2e})",
            r.precision,
            r.refinement_steps,
            r.residual,
            max_rel_error(&x, &xs),
            max_rel_error(&xd, &xs)
        );
        assert_eq!(r.precision, "mixed");
        // a single-precision solve alone leaves a residual near 1e-7
        assert!(r.refinement_steps >= 1);
        assert!(r.residual <= 1e-12, "{}", r.residual);
        assert!(max_rel_error(&x, &xs) < 1e-10);
        assert!(max_rel_error(&x, &xd) < 1e-12);
        assert_eq!(s.stats().mixed_fallbacks, 0);
        assert!(r.warnings.is_empty(), "{:?}", r.warnings);
        // a right-hand side far below single precision's range (1e-38) is
        // scaled before it meets the single-precision factor
        let mut tiny = rhs(&a, &xs);
        tiny.iter_mut().for_each(|v| *v *= 1e-42);
        s.solve_in_place(&a, &mut tiny).unwrap();
        let back: Vec<f64> = tiny.iter().map(|v| v * 1e42).collect();
        assert!(max_rel_error(&back, &xs) < 1e-10);
        assert_eq!(s.report().precision, "mixed");
        assert_eq!(s.stats().mixed_fallbacks, 0);
    }
    // 2. a penalty of 1e6 on unit stiffness: the diagonal spread (~1e5)
    // lets auto try single precision, whose pivot ratio (~1e-5) is refused
    let (a, coords) = penalised(1e6);
    let xs = exact(a.n);
    let mut s = solver(Precision::Auto);
    let x = solve_with(&mut s, &a, &coords);
    println!("penalty 1e6: {}", s.stats().mixed_fallback_reason);
    assert_eq!(s.report().precision, "double");
    assert_eq!(s.stats().mixed_fallbacks, 1);
    assert!(s.stats().mixed_fallback_reason.contains("pivot"));
    assert!(max_rel_error(&x, &xs) < 1e-6);
    // ... while a higher penalty (spread > mixed_max_spread) goes straight
    // to double
    let (a, coords) = penalised(1e9);
    let mut s = solver(Precision::Auto);
    solve_with(&mut s, &a, &coords);
    assert_eq!(s.report().precision, "double");
    assert_eq!(s.stats().mixed_fallbacks, 0);
    // 3. the 1D chain tridiag(-1, 2, -1) in its natural order: pivots
    // (k+1)/k are harmless but cond = 4 n^2 / pi^2 = 1.6e8 makes refinement
    // diverge (rate ~ cond eps_32 = 10); the solve refactorises in double
    // and stays there
    let n = 20_000;
    let mut a = SymmetricCsc::from_columns(
        (0..n)
            .map(|j| if j == 0 { vec![0] } else { vec![j - 1, j] })
            .collect(),
    );
    for j in 0..n {
        for p in a.col_ptr[j]..a.col_ptr[j + 1] {
            a.values[p] = if a.row_idx[p] == j { 2.0 } else { -1.0 };
        }
    }
    let coords: Vec<[f64; 3]> = (0..n).map(|i| [i as f64, 0.0, 0.0]).collect();
    let xs = exact(n);
    let mut s = CholeskySolver::new(CholeskySettings {
        precision: Precision::Mixed,
        ordering: OrderingKind::Natural,
        ..Default::default()
    });
    let x = solve_with(&mut s, &a, &coords);
    println!("chain: {}", s.stats().mixed_fallback_reason);
    assert_eq!(s.report().precision, "double");
    assert_eq!(s.stats().mixed_fallbacks, 1);
    assert!(s.stats().mixed_fallback_reason.contains("refinement"));
    // double precision: error ~ cond eps_64 = 2e-8
    assert!(max_rel_error(&x, &xs) < 1e-6, "{}", max_rel_error(&x, &xs));
    // the fallback is for good: the next factorisation is double at once
    s.factorize(&a).unwrap();
    assert_eq!(s.report().precision, "double");
    assert_eq!(s.stats().mixed_fallbacks, 1);
}

#[test]
fn non_finite_values_are_errors() {
    let (mut a, coords) = grid_3d(3, 3, 3, 3, Stencil::Point7);
    let mut s = CholeskySolver::new(Default::default());
    s.analyze(&a, Some(&coords)).unwrap();
    a.values[5] = f64::NAN;
    assert!(matches!(
        s.factorize(&a),
        Err(SolverError::NonFinite { .. })
    ));
    let mut cg = CgSolver::new(Default::default());
    cg.analyze(&a, Some(&coords)).unwrap();
    assert!(matches!(
        cg.factorize(&a),
        Err(SolverError::NonFinite { .. })
    ));
}

#[test]
fn registry_holds_both_solvers() {
    let keys: Vec<&str> = entries::<SolverEntry>().iter().map(|e| e.key).collect();
    assert!(keys.contains(&"cholesky"), "{keys:?}");
    assert!(keys.contains(&"cg"), "{keys:?}");
    let table: toml::Table = toml::from_str("preconditioner = \"jacobi\"\ntol = 1e-9").unwrap();
    let mut cg = (find::<SolverEntry>("cg").unwrap().build)(&table).unwrap();
    assert_eq!(cg.key(), "cg");
    let (a, coords) = grid_3d(4, 4, 4, 3, Stencil::Point7);
    let xs = exact(a.n);
    let x = solve_with(cg.as_mut(), &a, &coords);
    assert!(max_rel_error(&x, &xs) < 1e-7);
    let bad: toml::Table = toml::from_str("tolerance = 1e-9").unwrap();
    let err = (find::<SolverEntry>("cg").unwrap().build)(&bad).unwrap_err();
    assert!(err.to_string().contains("tolerance"), "{err}");
    let chol = (find::<SolverEntry>("cholesky").unwrap().build)(&toml::Table::new()).unwrap();
    assert_eq!(chol.key(), "cholesky");
}

/// Timing on a ~200k-dof hex8-like problem (27-point stencil, 3 dofs per
/// node). Not a test: `cargo test -p junta-solvers --release -- --ignored
/// --nocapture big_problem_timing`. Set `JUNTA_BIG_N` to change the grid.
#[test]
#[ignore]
fn big_problem_timing() {
    let m: usize = std::env::var("JUNTA_BIG_N")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(41);
    let (a, coords) = grid_3d(m, m, m, 3, Stencil::Point27);
    println!(
        "grid {m}^3, 27-point, 3 dofs/node: n = {}, nnz(upper) = {}",
        a.n,
        a.nnz()
    );
    let xs = exact(a.n);
    let b = rhs(&a, &xs);
    for ordering in [OrderingKind::NestedDissection, OrderingKind::Amd] {
        let mut s = CholeskySolver::new(CholeskySettings {
            ordering,
            ..Default::default()
        });
        s.analyze(&a, Some(&coords)).unwrap();
        s.factorize(&a).unwrap();
        let mut x = b.clone();
        s.solve_in_place(&a, &mut x).unwrap();
        let r = s.report();
        println!(
            "{:>18}: ordering {:.3} s, analyze {:.3} s, factor {:.2} s, solve {:.3} s, nnz(L) {} ({:.2} GB), residual {:.1e}, error {:.1e}",
            ordering.name(),
            s.stats().ordering_seconds,
            r.analyze_seconds,
            r.factor_seconds,
            r.solve_seconds,
            r.factor_nonzeros,
            r.factor_nonzeros as f64 * 8e-9,
            r.residual,
            max_rel_error(&x, &xs)
        );
    }
    for preconditioner in [Preconditioner::Jacobi, Preconditioner::BlockJacobi] {
        let mut s = CgSolver::new(CgSettings {
            preconditioner,
            tol: 1e-8,
            ..Default::default()
        });
        s.analyze(&a, Some(&coords)).unwrap();
        s.factorize(&a).unwrap();
        let mut x = b.clone();
        s.solve_in_place(&a, &mut x).unwrap();
        let r = s.report();
        println!(
            "cg {preconditioner:?}: {} iterations, {:.2} s, residual {:.1e}",
            r.iterations, r.solve_seconds, r.residual
        );
    }
}
