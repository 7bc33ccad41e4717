//! Tests of the symmetric-indefinite `ldlt` back end: exact inertia of a
//! shifted Laplacian (closed-form eigenvalues), saddle-point systems that
//! need 2x2 pivots, agreement with Cholesky on SPD matrices, singular
//! matrices, Cholesky's refusal naming `ldlt`, and the registry entry.

use junta_core::registry::{entries, find, SolverEntry};
use junta_core::{LinearSolver, MatrixKind, SolverError, SymmetricCsc};
use junta_solvers::gallery::{
    constrained_laplacian as sparse_kkt, grid_3d, grid_3d_neumann, shifted_laplacian, Stencil,
};
use junta_solvers::{
    CholeskySettings, CholeskySolver, LdltSettings, LdltSolver, OrderingKind, Precision,
};

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

/// Eigenvalues of the Laplacian above below `sigma`, and the distance of
/// the nearest one to `sigma`. Closed form: `lambda_{pqr} = mu_p + mu_q +
/// mu_r`, `mu_p = 2 - 2 cos(p pi / (n + 1))`, `p, q, r = 1..n` (the 1D
/// Dirichlet second-difference matrix's eigenvalues, summed over the axes
/// of the Kronecker sum).
fn eigen_count(n: usize, sigma: f64) -> (usize, f64) {
    let mu: Vec<f64> = (1..=n)
        .map(|p| 2.0 - 2.0 * (p as f64 * std::f64::consts::PI / (n as f64 + 1.0)).cos())
        .collect();
    let (mut count, mut gap) = (0, f64::INFINITY);
    for a in &mu {
        for b in &mu {
            for c in &mu {
                let l = a + b + c;
                if l < sigma {
                    count += 1;
                }
                gap = gap.min((l - sigma).abs());
            }
        }
    }
    (count, gap)
}

fn ldlt(ordering: OrderingKind, threads: usize) -> LdltSolver {
    LdltSolver::new(LdltSettings {
        ordering,
        threads,
        ..Default::default()
    })
}

/// Solve `A x = A x*` and return `x`.
fn solve(s: &mut dyn LinearSolver, a: &SymmetricCsc, coords: Option<&[[f64; 3]]>) -> Vec<f64> {
    let xs = exact(a.n);
    let mut x = rhs(a, &xs);
    s.analyze(a, coords).unwrap();
    s.factorize(a).unwrap();
    s.solve_in_place(a, &mut x).unwrap();
    x
}

#[test]
fn shifted_laplacian_inertia_is_exact() {
    // n = 18: the top separator (18^2 = 324 columns) is split into panels.
    for (n, sigmas) in [(10, &[0.5, 3.3, 6.1][..]), (18, &[1.7, 4.9][..])] {
        for &sigma in sigmas {
            let (count, gap) = eigen_count(n, sigma);
            // the shift stays clear of the spectrum, so the count is robust
            assert!(gap > 1e-3, "n {n} sigma {sigma}: gap {gap}");
            assert!(count > 0 && count < n * n * n);
            let (a, coords) = shifted_laplacian(n, sigma);
            let xs = exact(a.n);
            for (ordering, threads) in [
                (OrderingKind::NestedDissection, 1),
                (OrderingKind::NestedDissection, 2),
                (OrderingKind::Amd, 2),
            ] {
                let mut s = ldlt(ordering, threads);
                let x = solve(&mut s, &a, Some(&coords));
                let r = s.report();
                let st = s.stats();
                assert_eq!(
                    r.negative_pivots,
                    Some(count),
                    "n {n} sigma {sigma} {ordering:?} threads {threads}: {st:?}"
                );
                assert_eq!(st.perturbed_pivots, 0);
                assert!(r.warnings.is_empty(), "{:?}", r.warnings);
                assert!(r.residual < 1e-12, "residual {}", r.residual);
                // cond <= 12 / gap: about 1e4 at most here
                let err = max_rel_error(&x, &xs);
                assert!(err < 1e-9, "n {n} sigma {sigma}: error {err}");
                assert_eq!(r.ordering, ordering.name());
                assert_eq!(r.precision, "double");
                assert!(r.factor_nonzeros > a.nnz());
            }
        }
    }
}

/// Saddle-point matrix `[[0, B], [B^T, A]]` (multipliers first), dense:
/// `A` (`na x na`) SPD, `B` (`m x na`) of full row rank (a cosine matrix
/// plus the identity). Inertia: `na`
/// positive and `m` negative eigenvalues (Sylvester's law on the block
/// factorisation `diag(A, -B A^-1 B^T)`).
fn dense_kkt(na: usize, m: usize) -> SymmetricCsc {
    let n = na + m;
    let entry = |i: usize, j: usize| -> f64 {
        let (i, j) = (i.min(j), i.max(j));
        if j < m {
            0.0
        } else if i < m {
            (0.3 * ((i + 1) * (j - m + 1)) as f64).cos() + if i == j - m { 1.0 } else { 0.0 }
        } else {
            // diagonally dominant (0.06 against off-diagonal row sums below
            // 0.01 * 2 * (H_24 - 1) < 0.057), small next to B
            let d = (i as f64 - j as f64).abs();
            0.01 / (1.0 + d) + if i == j { 0.05 } else { 0.0 }
        }
    };
    let mut a = SymmetricCsc::from_columns((0..n).map(|j| (0..=j).collect()).collect());
    let mut p = 0;
    for j in 0..n {
        for i in 0..=j {
            a.values[p] = entry(i, j);
            p += 1;
        }
    }
    a
}

#[test]
fn saddle_point_needs_2x2_pivots() {
    let (na, m) = (24, 9);
    let a = dense_kkt(na, m);
    let xs = exact(a.n);
    let mut s = ldlt(OrderingKind::Natural, 1);
    let x = solve(&mut s, &a, None);
    let st = s.stats().clone();
    let r = s.report();
    // the leading zero block leaves Bunch-Kaufman no acceptable 1x1 pivot
    assert!(st.pivots_2x2 >= 1, "{st:?}");
    assert_eq!(st.perturbed_pivots, 0, "{st:?}");
    assert_eq!(r.negative_pivots, Some(m), "{st:?}");
    assert!(r.residual < 1e-13, "residual {}", r.residual);
    let err = max_rel_error(&x, &xs);
    assert!(err < 1e-11, "error {err}");
    // Cholesky refuses it from the zero diagonal on
    let mut c = CholeskySolver::new(CholeskySettings {
        ordering: OrderingKind::Natural,
        ..Default::default()
    });
    c.analyze(&a, None).unwrap();
    assert!(matches!(
        c.factorize(&a),
        Err(SolverError::NotPositiveDefinite { .. })
    ));
}

#[test]
fn sparse_saddle_point_solves_with_exact_inertia() {
    let m = 20;
    let (a, coords) = sparse_kkt(8, m);
    let xs = exact(a.n);
    for ordering in [
        OrderingKind::NestedDissection,
        OrderingKind::Amd,
        OrderingKind::Natural,
    ] {
        let mut s = ldlt(ordering, 2);
        let x = solve(&mut s, &a, Some(&coords));
        let st = s.stats().clone();
        let r = s.report();
        assert!(r.residual < 1e-12, "{ordering:?}: residual {}", r.residual);
        let err = max_rel_error(&x, &xs);
        assert!(err < 1e-9, "{ordering:?}: error {err}");
        if ordering == OrderingKind::Natural {
            // multipliers last: every pivot is acceptable within its panel
            assert_eq!(st.perturbed_pivots, 0, "{st:?}");
            assert!(r.warnings.is_empty(), "{:?}", r.warnings);
        } else {
            // the fill-reducing orderings eliminate some multipliers before
            // their dofs, in panels of their own: zero pivots, perturbed,
            // then recovered by refinement, with a warning
            assert!(st.perturbed_pivots > 0, "{ordering:?}: {st:?}");
            assert!(r.refinement_steps >= 1);
            assert!(r.warnings.iter().any(|w| w.contains("inertia")));
        }
        // perturbing by delta << min |eigenvalue| keeps the inertia: the
        // multiplier's +delta turns its dofs' pivot negative instead
        assert_eq!(r.negative_pivots, Some(m), "{ordering:?}: {st:?}");
    }
}

#[test]
fn spd_matrix_matches_cholesky() {
    let (a, coords) = grid_3d(8, 8, 8, 3, Stencil::Point27);
    let mut c = CholeskySolver::new(CholeskySettings {
        precision: Precision::Double,
        ..Default::default()
    });
    let xc = solve(&mut c, &a, Some(&coords));
    let mut l = ldlt(OrderingKind::NestedDissection, 0);
    let xl = solve(&mut l, &a, Some(&coords));
    let (rc, rl) = (c.report(), l.report());
    assert_eq!(rc.negative_pivots, Some(0));
    assert_eq!(rl.negative_pivots, Some(0));
    assert_eq!(l.stats().pivots_2x2, 0);
    // one shared analysis: same ordering, same factor structure
    assert_eq!(c.permutation(), l.permutation());
    assert_eq!(rc.factor_nonzeros, rl.factor_nonzeros);
    assert_eq!(rc.ordering, rl.ordering);
    assert!(rl.residual < 1e-13, "{}", rl.residual);
    let err = max_rel_error(&xl, &xc);
    assert!(err < 1e-11, "ldlt vs cholesky: {err}");
    assert!(l.accepts(MatrixKind::SymmetricIndefinite));
    assert!(l.accepts(MatrixKind::SymmetricPositiveDefinite));
    assert!(!l.accepts(MatrixKind::General));
    assert!(!c.accepts(MatrixKind::SymmetricIndefinite));
}

#[test]
fn cholesky_refuses_indefinite_and_names_ldlt() {
    let (a, coords) = shifted_laplacian(8, 2.5);
    let mut c = CholeskySolver::default();
    c.analyze(&a, Some(&coords)).unwrap();
    let err = c.factorize(&a).unwrap_err();
    assert!(
        matches!(err, SolverError::NotPositiveDefinite { .. }),
        "{err:?}"
    );
    let msg = err.to_string();
    assert!(msg.contains("indefinite or singular"), "{msg}");
    assert!(msg.contains("equation"), "{msg}");
    assert!(msg.contains("type = \"ldlt\""), "{msg}");
    assert_eq!(c.report().negative_pivots, None);
}

#[test]
fn singular_matrix_is_an_error_not_nan() {
    // Neumann Laplacian: constants span the kernel; e_0 is not in the range
    let (a, coords) = grid_3d_neumann(6, 6, 6, 1, Stencil::Point7);
    let mut s = ldlt(OrderingKind::NestedDissection, 1);
    s.analyze(&a, Some(&coords)).unwrap();
    s.factorize(&a).unwrap();
    let mut b = vec![0.0; a.n];
    b[0] = 1.0;
    let err = s.solve_in_place(&a, &mut b).unwrap_err();
    let msg = err.to_string();
    assert!(msg.contains("singular"), "{msg}");
    assert!(b.iter().all(|v| v.is_finite()));
    // an all-zero matrix too
    let mut z = a.clone();
    z.values.fill(0.0);
    assert!(matches!(
        s.factorize(&z),
        Err(SolverError::NotPositiveDefinite { .. })
    ));
}

#[test]
fn zero_leading_diagonal_takes_a_2x2_pivot() {
    // [[0, 1, 0], [1, 0, 1], [0, 1, 1]] in natural order (one supernode):
    // a zero leading diagonal and column max 1 -> 2x2 pivot. Inertia by
    // hand: the block D1 = [[0, 1], [1, 0]] (eigenvalues +-1) and its Schur
    // complement 1 - [0, 1] D1^-1 [0, 1]^T = 1: one negative eigenvalue
    // (det = -1 < 0, trace 1).
    let mut a = SymmetricCsc::from_columns(vec![vec![0], vec![0, 1], vec![1, 2]]);
    a.values = vec![0.0, 1.0, 0.0, 1.0, 1.0];
    let xs = [1.0, -2.0, 3.0];
    let mut b = rhs(&a, &xs);
    let mut s = ldlt(OrderingKind::Natural, 1);
    s.analyze(&a, None).unwrap();
    s.factorize(&a).unwrap();
    s.solve_in_place(&a, &mut b).unwrap();
    for (x, e) in b.iter().zip(xs) {
        assert!((x - e).abs() < 1e-12, "{b:?}");
    }
    assert_eq!(s.report().negative_pivots, Some(1));
    assert_eq!(s.stats().pivots_2x2, 1);
    assert_eq!(s.stats().perturbed_pivots, 0);
}

#[test]
fn parameters_and_registry() {
    let t: toml::Table =
        toml::from_str("ordering = \"amd\"\npivot_threshold = 0.5\nthreads = 1").unwrap();
    let s = LdltSolver::from_table(&t).unwrap();
    assert_eq!(s.settings().ordering, OrderingKind::Amd);
    assert_eq!(s.settings().pivot_threshold, 0.5);
    // the default alpha is (1 + sqrt(17)) / 8
    let alpha = LdltSettings::default().pivot_threshold;
    assert!((alpha - (1.0 + 17f64.sqrt()) / 8.0).abs() < 1e-16);
    let bad: toml::Table = toml::from_str("pivot_treshold = 0.5").unwrap();
    let err = LdltSolver::from_table(&bad).unwrap_err();
    assert!(err.to_string().contains("pivot_treshold"), "{err}");
    let bad: toml::Table = toml::from_str("pivot_threshold = 1.5").unwrap();
    assert!(LdltSolver::from_table(&bad).is_err());
    let keys: Vec<&str> = entries::<SolverEntry>().iter().map(|e| e.key).collect();
    assert!(keys.contains(&"ldlt"), "{keys:?}");
    let entry = find::<SolverEntry>("ldlt").unwrap();
    for p in ["ordering", "pivot_threshold"] {
        assert!(entry.params.iter().any(|d| d.name == p), "{p}");
    }
    let mut l = (entry.build)(&toml::Table::new()).unwrap();
    assert_eq!(l.key(), "ldlt");
    // sigma = 3.1 lies 0.1 from the nearest eigenvalue (3 = 1 + 1 + 1)
    let (count, gap) = eigen_count(5, 3.1);
    assert!(gap > 0.05);
    let (a, coords) = shifted_laplacian(5, 3.1);
    let xs = exact(a.n);
    let x = solve(l.as_mut(), &a, Some(&coords));
    assert!(max_rel_error(&x, &xs) < 1e-10);
    assert_eq!(l.report().negative_pivots, Some(count));
}

/// A softening-like tangent: an SPD 27-point grid (3 dofs per node) with
/// negative springs `-k (u_p - u_q)^2` between neighbouring dofs, as a
/// cohesive law on its descending branch adds. Reference inertia: the
/// eigenvalues of the dense matrix (nalgebra's symmetric eigensolver).
#[test]
fn softening_springs_inertia_matches_dense_eigenvalues() {
    let (mut a, coords) = grid_3d(5, 5, 5, 3, Stencil::Point27);
    let n = a.n;
    // springs between dof c of node i and dof c of node i + 1 (x neighbour)
    for (t, node) in (0..125).step_by(7).enumerate() {
        if node % 5 == 4 {
            continue;
        }
        let c = t % 3;
        let (p, q) = (3 * node + c, 3 * (node + 1) + c);
        let k = 30.0 + (t % 4) as f64 * 9.0;
        for (i, j, v) in [(p, p, -k), (q, q, -k), (p, q, k)] {
            let pos = a.position(i, j).expect("in the pattern");
            a.values[pos] += v;
        }
    }
    let mut dense = nalgebra::DMatrix::<f64>::zeros(n, n);
    for j in 0..n {
        for p in a.col_ptr[j]..a.col_ptr[j + 1] {
            let i = a.row_idx[p];
            dense[(i, j)] = a.values[p];
            dense[(j, i)] = a.values[p];
        }
    }
    let eig = nalgebra::SymmetricEigen::new(dense).eigenvalues;
    let negative = eig.iter().filter(|&&l| l < 0.0).count();
    let gap = eig.iter().fold(f64::INFINITY, |m, l| m.min(l.abs()));
    assert!(negative > 0 && gap > 1e-6, "{negative} negative, gap {gap}");
    eprintln!("{negative} negative eigenvalues of {n}, smallest |eigenvalue| {gap:.3e}");
    let xs = exact(n);
    for ordering in [OrderingKind::NestedDissection, OrderingKind::Amd] {
        let mut s = ldlt(ordering, 2);
        let x = solve(&mut s, &a, Some(&coords));
        assert_eq!(s.report().negative_pivots, Some(negative), "{ordering:?}");
        assert_eq!(s.stats().perturbed_pivots, 0);
        assert!(max_rel_error(&x, &xs) < 1e-9);
    }
}

/// Partial refactorisation: after a factorisation, soften springs at one
/// end of a long grid (as a process zone does), then factorise again. The
/// second factorisation redoes only the panels that depend on the changed
/// entries, and its solution and inertia are those of a complete
/// factorisation of the new matrix, bit for bit. A change everywhere redoes
/// all the work; an unchanged matrix redoes none of it.
#[test]
fn partial_refactorisation_equals_complete_factorisation() {
    let (a0, coords) = grid_3d(3, 3, 60, 3, Stencil::Point27);
    let n = a0.n;
    let soften = |a: &mut SymmetricCsc, k: f64| {
        // springs in z between the first nodes along z (one end of the bar)
        for node in 0..12 {
            let (p, q) = (3 * node + 2, 3 * (node + 9) + 2);
            for (i, j, v) in [(p, p, -k), (q, q, -k), (p, q, k)] {
                let pos = a.position(i, j).expect("in the pattern");
                a.values[pos] += v;
            }
        }
    };
    let mut a1 = a0.clone();
    soften(&mut a1, 40.0);
    let xs = exact(n);
    for ordering in [OrderingKind::NestedDissection, OrderingKind::Amd] {
        let mut partial = ldlt(ordering, 2);
        partial.analyze(&a0, Some(&coords)).unwrap();
        partial.factorize(&a0).unwrap();
        partial.factorize(&a1).unwrap();
        let mut complete = LdltSolver::new(LdltSettings {
            ordering,
            threads: 2,
            partial_refactor: false,
            ..Default::default()
        });
        complete.analyze(&a1, Some(&coords)).unwrap();
        complete.factorize(&a1).unwrap();
        let b = rhs(&a1, &xs);
        let (mut x_p, mut x_c) = (b.clone(), b.clone());
        partial.solve_in_place(&a1, &mut x_p).unwrap();
        complete.solve_in_place(&a1, &mut x_c).unwrap();
        assert_eq!(x_p, x_c, "{ordering:?}: partial and complete differ");
        assert!(max_rel_error(&x_p, &xs) < 1e-9);
        let (rp, rc) = (partial.report(), complete.report());
        assert_eq!(rp.negative_pivots, rc.negative_pivots);
        assert!(
            rp.negative_pivots.unwrap() > 0,
            "the springs make it indefinite"
        );
        assert_eq!((rp.factorizations, rp.partial_factorizations), (2, 1));
        assert_eq!(rc.partial_factorizations, 0);
        let share = rp.refactored_work;
        eprintln!(
            "{ordering:?}: partial refactorisation did {:.1} % of the work",
            100.0 * share
        );
        assert!(share > 0.0 && share < 1.0, "{ordering:?}: share {share}");
        if ordering == OrderingKind::NestedDissection {
            // changes at one end of a bar: a branch of the dissection tree
            assert!(share < 0.5, "share {share}");
        }
        // the same matrix again: nothing to redo
        partial.factorize(&a1).unwrap();
        assert_eq!(partial.report().refactored_work, share);
        // every diagonal changed: all the work
        let mut a2 = a1.clone();
        for j in 0..n {
            let pos = a2.position(j, j).unwrap();
            a2.values[pos] *= 1.0 + 1e-3;
        }
        partial.factorize(&a2).unwrap();
        let all = partial.report().refactored_work - share;
        assert!((all - 1.0).abs() < 1e-12, "{ordering:?}: {all}");
    }
}

/// Two right-hand sides in one call (`solve_many_in_place`, one pass over
/// the factor) give the solutions of two separate solves, bit for bit.
#[test]
fn two_right_hand_sides_in_one_pass_equal_two_solves() {
    let (a, coords) = grid_3d(5, 5, 5, 3, Stencil::Point27);
    let n = a.n;
    let mut s = ldlt(OrderingKind::Auto, 2);
    s.analyze(&a, Some(&coords)).unwrap();
    s.factorize(&a).unwrap();
    let x1 = exact(n);
    let x2: Vec<f64> = (0..n).map(|i| (0.37 * i as f64).cos()).collect();
    let (b1, b2) = (rhs(&a, &x1), rhs(&a, &x2));
    let mut both: Vec<f64> = b1.iter().chain(&b2).copied().collect();
    s.solve_many_in_place(&a, &mut both).unwrap();
    let (mut y1, mut y2) = (b1.clone(), b2.clone());
    s.solve_in_place(&a, &mut y1).unwrap();
    s.solve_in_place(&a, &mut y2).unwrap();
    assert_eq!(&both[..n], &y1[..]);
    assert_eq!(&both[n..], &y2[..]);
    assert!(max_rel_error(&y2, &x2) < 1e-10);
    // a length that is not a multiple of n is a usage error, not a panic
    let mut bad = vec![1.0; n + 1];
    assert!(matches!(
        s.solve_many_in_place(&a, &mut bad),
        Err(SolverError::Usage(_))
    ));
}

/// The triangular solves split at the first branching of the elimination
/// tree (`parallel_solve_entries`): the subtrees in parallel, each adding
/// its updates of the separator's rows into its own buffer. On an
/// indefinite shifted Laplacian (nested dissection: a real tree) the split
/// solve gives the serial one's solution to round-off, for one and for two
/// right-hand sides, and the exact solution to the factor's accuracy.
#[test]
fn parallel_triangular_solves_equal_the_serial_ones() {
    let (a, coords) = shifted_laplacian(14, 1.0);
    let n = a.n;
    let make = |entries: usize| {
        let mut s = LdltSolver::new(LdltSettings {
            ordering: OrderingKind::NestedDissection,
            threads: 2,
            parallel_solve_entries: entries,
            // the solves themselves, without refinement to mend them
            max_refinements: 0,
            ..Default::default()
        });
        s.analyze(&a, Some(&coords)).unwrap();
        s.factorize(&a).unwrap();
        s
    };
    let (mut serial, mut parallel) = (make(usize::MAX), make(0));
    let x1 = exact(n);
    let x2: Vec<f64> = (0..n).map(|i| (0.37 * i as f64).cos()).collect();
    let b: Vec<f64> = rhs(&a, &x1).into_iter().chain(rhs(&a, &x2)).collect();
    let (mut ys, mut yp) = (b.clone(), b.clone());
    serial.solve_many_in_place(&a, &mut ys).unwrap();
    parallel.solve_many_in_place(&a, &mut yp).unwrap();
    assert_eq!(serial.stats().solve_tasks, 0);
    assert!(
        parallel.stats().solve_tasks >= 2,
        "{} subtrees",
        parallel.stats().solve_tasks
    );
    assert!(max_rel_error(&yp, &ys) < 1e-12);
    assert!(max_rel_error(&yp[..n], &x1) < 1e-9);
    assert!(max_rel_error(&yp[n..], &x2) < 1e-9);
    assert!(parallel.report().negative_pivots.unwrap() > 0);
    let mut one = rhs(&a, &x2);
    parallel.solve_in_place(&a, &mut one).unwrap();
    assert!(max_rel_error(&one, &ys[n..]) < 1e-12);
}

/// Under a caller that checks its own residual (a Newton driver), a solve
/// skips its residual check only when the factor is above doubt: on a
/// shifted Laplacian (growth near 1) every solve goes unchecked and is
/// still accurate; on a saddle point whose multipliers carry a small
/// diagonal `delta` and are eliminated in panels of their own (restricted
/// pivoting: multipliers `1 / delta` in `L_RJ`, growth far above
/// `UNCHECKED_GROWTH_LIMIT`), every solve is checked and refined to the
/// exact solution; `residual_check = "always"` checks every solve.
#[test]
fn residual_check_is_skipped_only_for_a_factor_above_doubt() {
    use junta_solvers::{ResidualCheck, UNCHECKED_GROWTH_LIMIT};
    let run = |a: &SymmetricCsc, coords: &[[f64; 3]], check: ResidualCheck| {
        let mut s = LdltSolver::new(LdltSettings {
            ordering: OrderingKind::NestedDissection,
            residual_check: check,
            ..Default::default()
        });
        s.set_caller_checks_residual(true);
        let xs = exact(a.n);
        let mut x = rhs(a, &xs);
        s.analyze(a, Some(coords)).unwrap();
        s.factorize(a).unwrap();
        s.solve_in_place(a, &mut x).unwrap();
        (max_rel_error(&x, &xs), s.stats().clone(), s.report())
    };
    let (lap, coords) = shifted_laplacian(8, 0.5);
    let (err, st, r) = run(&lap, &coords, ResidualCheck::Auto);
    assert!(st.growth < 100.0, "{st:?}");
    assert_eq!(r.unchecked_solves, 1);
    assert!(err < 1e-10, "error {err}");
    let (_, _, r) = run(&lap, &coords, ResidualCheck::Always);
    assert_eq!(r.unchecked_solves, 0);
    assert!(r.residual < 1e-12, "{}", r.residual);

    let m = 20;
    let (mut kkt, coords) = sparse_kkt(8, m);
    let delta = 1e-7;
    for j in kkt.n - m..kkt.n {
        let p = kkt.position(j, j).unwrap();
        kkt.values[p] = delta;
    }
    let (err, st, r) = run(&kkt, &coords, ResidualCheck::Auto);
    assert_eq!(st.perturbed_pivots, 0, "{st:?}");
    assert!(st.min_pivot_ratio > 1e-12, "{st:?}");
    assert!(st.growth > UNCHECKED_GROWTH_LIMIT, "{st:?}");
    assert_eq!(r.unchecked_solves, 0);
    assert!(r.residual < 1e-10, "{}", r.residual);
    // the exact solution of the system with the delta diagonal
    assert!(err < 1e-8, "error {err}");
}
