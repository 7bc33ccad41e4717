//! Tests of the general (nonsymmetric) `lu` back end: nonsymmetric systems
//! solved to round-off against a known solution, a matrix that needs row
//! interchanges (zero diagonal), refactorisation on one analysis, a
//! singular matrix, the refusal of the symmetric back ends naming `lu`,
//! and the registry entry.

use junta_core::registry::find;
use junta_core::{LinearSolver, MatrixKind, SolverError, SymmetricCsc};
use junta_solvers::gallery::{grid_3d, Stencil};
use junta_solvers::{CgSolver, CholeskySolver, LdltSolver, LuSolver};

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

/// A stiffness-like SPD grid matrix made nonsymmetric: `A = K + c S` with
/// `S` skew-symmetric (convection-like) and a nonsymmetric diagonal-block
/// perturbation, so that `A != A^T` in every off-diagonal entry.
fn nonsymmetric_grid(c: f64) -> (SymmetricCsc, Vec<[f64; 3]>) {
    let (mut a, coords) = grid_3d(5, 4, 4, 3, Stencil::Point27);
    a.set_general(true);
    for j in 0..a.n {
        for p in a.col_ptr[j]..a.col_ptr[j + 1] {
            let i = a.row_idx[p];
            if i != j {
                let s = c * (1.0 + ((i + 2 * j) % 7) as f64 / 7.0);
                a.values[p] += s;
                a.lower[p] -= 0.5 * s;
            }
        }
    }
    (a, coords)
}

fn is_nonsymmetric(a: &SymmetricCsc) -> bool {
    a.col_ptr.windows(2).enumerate().any(|(j, w)| {
        (w[0]..w[1]).any(|p| a.row_idx[p] != j && (a.values[p] - a.lower[p]).abs() > 1e-3)
    })
}

#[test]
fn lu_solves_a_nonsymmetric_system_to_round_off() {
    let (a, coords) = nonsymmetric_grid(0.3);
    assert!(is_nonsymmetric(&a));
    let xs = exact(a.n);
    let mut b = rhs(&a, &xs);
    let mut lu = LuSolver::default();
    assert!(lu.accepts(MatrixKind::General));
    lu.analyze(&a, Some(&coords)).unwrap();
    lu.factorize(&a).unwrap();
    lu.solve_in_place(&a, &mut b).unwrap();
    let r = lu.report();
    assert!(r.residual < 1e-13, "residual {}", r.residual);
    assert!(max_rel_error(&b, &xs) < 1e-10, "{}", max_rel_error(&b, &xs));
    assert!(!r.ordering.is_empty());
}

/// `[[0, 1], [2, 0]]` blocks on the diagonal: no elimination without row
/// interchanges (every diagonal entry is zero).
#[test]
fn lu_pivots_on_zero_diagonals() {
    let m = 6; // 2x2 blocks on the diagonal, coupled to the next block
    let n = 2 * m;
    let mut cols = Vec::new();
    for j in 0..n {
        let lo = if j >= 2 { (j / 2 - 1) * 2 } else { 0 };
        cols.push((lo..=j).collect::<Vec<_>>());
    }
    let mut a = SymmetricCsc::from_columns(cols);
    a.set_general(true);
    for j in 0..n {
        for p in a.col_ptr[j]..a.col_ptr[j + 1] {
            let i = a.row_idx[p];
            let (v, l) = if i == j {
                (0.0, 0.0)
            } else if i / 2 == j / 2 {
                (1.0, 2.0)
            } else {
                (0.1 * (i + 1) as f64, -0.05 * (j + 1) as f64)
            };
            a.values[p] = v;
            a.lower[p] = l;
        }
    }
    let xs = exact(n);
    let mut b = rhs(&a, &xs);
    let mut lu = LuSolver::default();
    lu.analyze(&a, None).unwrap();
    lu.factorize(&a).unwrap();
    lu.solve_in_place(&a, &mut b).unwrap();
    assert!(max_rel_error(&b, &xs) < 1e-12, "{}", max_rel_error(&b, &xs));
}

/// One analysis, several matrices with the pattern (a Newton run): each
/// solve to round-off; a symmetric matrix (empty `lower`) is solved too.
#[test]
fn lu_refactorises_on_one_analysis() {
    let (mut a, coords) = nonsymmetric_grid(0.1);
    let mut lu = LuSolver::default();
    lu.analyze(&a, Some(&coords)).unwrap();
    for c in [0.1, 0.5, -0.4] {
        for (p, v) in a.lower.iter_mut().enumerate() {
            *v += c * ((p % 5) as f64 - 2.0) * 0.01;
        }
        // keep the diagonal consistent (lower[diag] = values[diag])
        for j in 0..a.n {
            let d = a.col_ptr[j + 1] - 1;
            a.lower[d] = a.values[d];
        }
        let xs = exact(a.n);
        let mut b = rhs(&a, &xs);
        lu.factorize(&a).unwrap();
        lu.solve_in_place(&a, &mut b).unwrap();
        assert!(max_rel_error(&b, &xs) < 1e-10);
    }
    let (s, _) = grid_3d(5, 4, 4, 3, Stencil::Point27);
    let xs = exact(s.n);
    let mut b = rhs(&s, &xs);
    lu.factorize(&s).unwrap();
    lu.solve_in_place(&s, &mut b).unwrap();
    assert!(max_rel_error(&b, &xs) < 1e-10);
    assert_eq!(lu.permutation().len(), s.n);
}

#[test]
fn lu_reports_a_singular_matrix() {
    // rank one 2x2 block: [[1, 2], [2, 4]] stored general, plus an identity
    let mut a = SymmetricCsc::from_columns(vec![vec![0], vec![0, 1], vec![2]]);
    a.set_general(true);
    a.values = vec![1.0, 2.0, 4.0, 1.0];
    a.lower = vec![1.0, 2.0, 4.0, 1.0];
    let mut lu = LuSolver::default();
    lu.analyze(&a, None).unwrap();
    let mut b = vec![1.0, 0.0, 1.0];
    let r = lu.factorize(&a).and_then(|_| lu.solve_in_place(&a, &mut b));
    assert!(
        matches!(
            r,
            Err(SolverError::NonFinite { .. }) | Err(SolverError::NotPositiveDefinite { .. })
        ),
        "{r:?}"
    );
}

/// The symmetric back ends refuse a nonsymmetric matrix, naming `lu`.
#[test]
fn symmetric_back_ends_refuse_a_general_matrix_naming_lu() {
    let (a, coords) = nonsymmetric_grid(0.3);
    let mut solvers: Vec<Box<dyn LinearSolver>> = vec![
        Box::new(CholeskySolver::new(Default::default())),
        Box::new(LdltSolver::new(Default::default())),
        Box::new(CgSolver::new(Default::default())),
    ];
    for s in &mut solvers {
        assert!(!s.accepts(MatrixKind::General));
        let e = s.analyze(&a, Some(&coords)).unwrap_err();
        let msg = e.to_string();
        assert!(matches!(e, SolverError::Usage(_)), "{msg}");
        assert!(
            msg.contains("nonsymmetric") && msg.contains("`lu`"),
            "{msg}"
        );
        // analysed on the symmetric part, then given the general matrix
        let mut sym = a.clone();
        sym.set_general(false);
        s.analyze(&sym, Some(&coords)).unwrap();
        let e = s.factorize(&a).unwrap_err();
        assert!(e.to_string().contains("`lu`"), "{e}");
    }
}

#[test]
fn lu_is_registered() {
    let e = find::<junta_core::registry::SolverEntry>("lu").unwrap();
    let s = (e.build)(&toml::Table::new()).unwrap();
    assert_eq!(s.key(), "lu");
    assert!(s.accepts(MatrixKind::General));
    let bad: toml::Table = toml::from_str("pivot = 1").unwrap();
    assert!((e.build)(&bad).is_err());
}

/// Cost of `lu` against `ldlt` and `cholesky` on one SPD 3D grid matrix
/// (27-point stencil, 3 dofs per node), all three back ends on the same
/// ordering. Not a timed test: prints the seconds for the benchmark note
/// in README.md (`cargo test -p junta-solvers --test lu -- --ignored
/// --nocapture`).
#[test]
#[ignore = "benchmark, prints timings"]
fn lu_against_ldlt_cost() {
    for m in [10, 14] {
        let (a, coords) = grid_3d(m, m, m, 3, Stencil::Point27);
        let xs = exact(a.n);
        let mut solvers: Vec<Box<dyn LinearSolver>> = vec![
            Box::new(CholeskySolver::new(Default::default())),
            Box::new(LdltSolver::new(Default::default())),
            Box::new(LuSolver::default()),
        ];
        for s in &mut solvers {
            let mut b = rhs(&a, &xs);
            let t = std::time::Instant::now();
            s.analyze(&a, Some(&coords)).unwrap();
            let t_an = t.elapsed().as_secs_f64();
            let t = std::time::Instant::now();
            for _ in 0..3 {
                s.factorize(&a).unwrap();
            }
            let t_f = t.elapsed().as_secs_f64() / 3.0;
            let t = std::time::Instant::now();
            s.solve_in_place(&a, &mut b).unwrap();
            let t_s = t.elapsed().as_secs_f64();
            println!(
                "n = {:6} {:9}: analyze {t_an:.4} s, factorize {t_f:.4} s, solve {t_s:.4} s, error {:.1e}",
                a.n,
                s.key(),
                max_rel_error(&b, &xs)
            );
        }
    }
}

/// Restricted pivoting on the symmetric structure (the default) solves a
/// nonsymmetric grid matrix to round-off like faer's unrestricted partial
/// pivoting, storing fewer entries than the latter's `A^T A` structure.
/// A saddle point whose multipliers (zero diagonal) a dissection ordering
/// eliminates in panels of their own has no acceptable pivot within those
/// panels: `auto` refactorises with partial pivoting and says so,
/// `restricted` perturbs the pivots and refines; both reach the solution.
#[test]
fn restricted_pivoting_matches_partial_pivoting_and_falls_back() {
    use junta_solvers::gallery::constrained_laplacian;
    use junta_solvers::{LuPivoting, LuSettings, OrderingKind};
    let solve = |a: &SymmetricCsc, coords: &[[f64; 3]], pivoting| {
        let mut lu = LuSolver::new(LuSettings {
            pivoting,
            ordering: OrderingKind::NestedDissection,
            ..Default::default()
        });
        let xs = exact(a.n);
        let mut b = rhs(a, &xs);
        lu.analyze(a, Some(coords)).unwrap();
        lu.factorize(a).unwrap();
        lu.solve_in_place(a, &mut b).unwrap();
        (max_rel_error(&b, &xs), lu.report())
    };
    let (a, coords) = nonsymmetric_grid(0.3);
    let (e_auto, r_auto) = solve(&a, &coords, LuPivoting::Auto);
    let (e_part, r_part) = solve(&a, &coords, LuPivoting::Partial);
    assert!(e_auto < 1e-11 && e_part < 1e-11, "{e_auto} {e_part}");
    assert!(r_auto.residual < 1e-13, "{}", r_auto.residual);
    assert!(!r_auto.notes.iter().any(|n| n.contains("unrestricted")));
    assert!(
        r_auto.factor_nonzeros < r_part.factor_nonzeros,
        "{} {}",
        r_auto.factor_nonzeros,
        r_part.factor_nonzeros
    );

    let (mut kkt, coords) = constrained_laplacian(8, 20);
    kkt.set_general(true);
    let (e, r) = solve(&kkt, &coords, LuPivoting::Auto);
    assert!(e < 1e-10, "auto: {e}");
    assert!(
        r.notes
            .iter()
            .any(|n| n.contains("unrestricted partial pivoting")),
        "{:?}",
        r.notes
    );
    assert_eq!(r.factorizations, 2);
    let (e, r) = solve(&kkt, &coords, LuPivoting::Restricted);
    assert!(e < 1e-9, "restricted: {e}");
    assert!(r.refinement_steps >= 1);
    assert!(
        r.warnings.iter().any(|w| w.contains("perturbed")),
        "{:?}",
        r.warnings
    );
}

/// `nonsymmetric_grid` with a decoupled 3 x 3 block of rank one
/// appended: `[[2, 1, 1], [2, 1, 1], [4, 2, 2]]`, a part that nothing
/// holds (its elimination leaves exact zeros).
fn singular_grid() -> (SymmetricCsc, Vec<[f64; 3]>) {
    let (a, mut coords) = nonsymmetric_grid(0.3);
    let n = a.n;
    let mut cols: Vec<Vec<usize>> = (0..n)
        .map(|j| a.row_idx[a.col_ptr[j]..a.col_ptr[j + 1]].to_vec())
        .collect();
    cols.extend([vec![n], vec![n, n + 1], vec![n, n + 1, n + 2]]);
    let mut s = SymmetricCsc::from_columns(cols);
    s.set_general(true);
    let block = [[2.0, 1.0, 1.0], [2.0, 1.0, 1.0], [4.0, 2.0, 2.0]];
    let (mut upper, mut lower) = (a.values.clone(), a.lower.clone());
    for j in 0..3 {
        for i in 0..=j {
            upper.push(block[i][j]);
            lower.push(block[j][i]);
        }
    }
    s.values = upper;
    s.lower = lower;
    coords.extend([[9.0, 0.0, 0.0], [9.0, 1.0, 0.0], [9.0, 2.0, 0.0]]);
    (s, coords)
}

/// A singular matrix (a floating body: `A 1 = 0`) stops `auto` at its
/// first factorisation, naming the pivot's step and equation, without
/// the fallback to unrestricted pivoting (which cannot help and, on a
/// mixed-mode bending model with a floating box, ran for minutes).
#[test]
fn auto_stops_at_a_singular_matrix_without_falling_back() {
    let (a, coords) = singular_grid();
    let mut lu = LuSolver::default();
    lu.analyze(&a, Some(&coords)).unwrap();
    let r = lu.factorize(&a);
    let Err(SolverError::NotPositiveDefinite { detail }) = &r else {
        panic!("expected a singular matrix, got {r:?}");
    };
    assert!(detail.contains("numerically singular"), "{detail}");
    assert!(detail.contains("elimination step"), "{detail}");
    assert!(detail.contains("equation"), "{detail}");
    let rep = lu.report();
    assert_eq!(rep.factorizations, 1, "no refactorisation");
    assert!(
        !rep.notes.iter().any(|n| n.contains("unrestricted")),
        "{:?}",
        rep.notes
    );
    // the same matrix with a regular block factorises
    let (mut b, _) = singular_grid();
    let m = b.values.len();
    b.values[m - 1] = 3.0; // A[n+2][n+2]: the block's rank is three
    b.values[m - 4] = 5.0; // A[n+1][n+1]
    b.lower[m - 1] = 3.0;
    b.lower[m - 4] = 5.0;
    let mut lu = LuSolver::default();
    lu.analyze(&b, Some(&coords)).unwrap();
    lu.factorize(&b).unwrap();
}

/// The fallback's factor is predicted before any numeric work; above
/// `max_fallback_fill` times the restricted factor it is refused with the
/// numbers and the remedy.
#[test]
fn auto_refuses_a_fallback_whose_fill_runs_away() {
    use junta_solvers::gallery::constrained_laplacian;
    use junta_solvers::{LuPivoting, LuSettings, OrderingKind};
    let (mut kkt, coords) = constrained_laplacian(8, 20);
    kkt.set_general(true);
    let mut lu = LuSolver::new(LuSettings {
        pivoting: LuPivoting::Auto,
        ordering: OrderingKind::NestedDissection,
        max_fallback_fill: 1.0,
        ..Default::default()
    });
    lu.analyze(&kkt, Some(&coords)).unwrap();
    let r = lu.factorize(&kkt);
    let Err(SolverError::FillLimit { detail }) = &r else {
        panic!("expected the fill limit, got {r:?}");
    };
    assert!(detail.contains("max_fallback_fill = 1"), "{detail}");
    assert!(detail.contains("pivoting = \"restricted\""), "{detail}");
    // the entries predicted are more than the restricted factor's
    let nums: Vec<f64> = detail
        .split(|c: char| !(c.is_ascii_digit() || c == '.'))
        .filter_map(|w| w.parse().ok())
        .collect();
    assert!(nums.len() > 3, "{detail}");
}
