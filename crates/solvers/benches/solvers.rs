//! Criterion benches of the linear back ends on the 7-point 12^3 grid with
//! 3 dofs per node (5184 equations) and a 27-point 16^3 grid (12288):
//! Cholesky factor + solve with nested dissection vs AMD (analysis done
//! once outside the timed loop), double against mixed precision (nested
//! dissection; the 27-point grid with 24,576 equations), and block-Jacobi /
//! Jacobi CG; Cholesky against the symmetric-indefinite LDL^T on the same
//! SPD grids.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use junta_core::{LinearSolver, SymmetricCsc};
use junta_solvers::gallery::{grid_3d, Stencil};
use junta_solvers::{
    CgSettings, CgSolver, CholeskySettings, CholeskySolver, LdltSettings, LdltSolver, OrderingKind,
    Precision, Preconditioner,
};
use std::hint::black_box;

fn problems() -> Vec<(&'static str, SymmetricCsc, Vec<[f64; 3]>)> {
    let (a, c) = grid_3d(12, 12, 12, 3, Stencil::Point7);
    let (b, d) = grid_3d(16, 16, 16, 3, Stencil::Point27);
    vec![("grid12_p7", a, c), ("grid16_p27", b, d)]
}

fn cholesky(c: &mut Criterion) {
    let mut group = c.benchmark_group("cholesky_factor_solve");
    group.sample_size(10);
    for (name, a, coords) in problems() {
        let rhs = vec![1.0; a.n];
        for ordering in [OrderingKind::NestedDissection, OrderingKind::Amd] {
            let mut s = CholeskySolver::new(CholeskySettings {
                ordering,
                precision: Precision::Double,
                ..Default::default()
            });
            s.analyze(&a, Some(&coords)).unwrap();
            group.bench_function(BenchmarkId::new(ordering.name(), name), |bench| {
                bench.iter(|| {
                    s.factorize(&a).unwrap();
                    let mut x = rhs.clone();
                    s.solve_in_place(&a, &mut x).unwrap();
                    black_box(x)
                })
            });
        }
    }
    group.finish();
}

/// The symmetric-indefinite back end on the same SPD grids: the price of
/// Bunch-Kaufman pivoting (the dense kernels of the panels' diagonal blocks
/// are unblocked) and of the `L D` products in the updates.
fn ldlt_vs_cholesky(c: &mut Criterion) {
    let mut group = c.benchmark_group("ldlt_vs_cholesky");
    group.sample_size(10);
    for (name, a, coords) in problems() {
        let rhs = vec![1.0; a.n];
        let mut chol = CholeskySolver::new(CholeskySettings {
            precision: Precision::Double,
            ..Default::default()
        });
        chol.analyze(&a, Some(&coords)).unwrap();
        group.bench_function(BenchmarkId::new("cholesky", name), |bench| {
            bench.iter(|| {
                chol.factorize(&a).unwrap();
                let mut x = rhs.clone();
                chol.solve_in_place(&a, &mut x).unwrap();
                black_box(x)
            })
        });
        let mut ldlt = LdltSolver::new(LdltSettings::default());
        ldlt.analyze(&a, Some(&coords)).unwrap();
        group.bench_function(BenchmarkId::new("ldlt", name), |bench| {
            bench.iter(|| {
                ldlt.factorize(&a).unwrap();
                let mut x = rhs.clone();
                ldlt.solve_in_place(&a, &mut x).unwrap();
                assert_eq!(ldlt.report().negative_pivots, Some(0));
                black_box(x)
            })
        });
    }
    group.finish();
}

fn precision(c: &mut Criterion) {
    let mut group = c.benchmark_group("cholesky_precision");
    group.sample_size(10);
    let (a, coords) = grid_3d(16, 16, 32, 3, Stencil::Point27);
    let rhs = vec![1.0; a.n];
    for precision in [Precision::Double, Precision::Mixed] {
        let mut s = CholeskySolver::new(CholeskySettings {
            precision,
            ..Default::default()
        });
        s.analyze(&a, Some(&coords)).unwrap();
        group.bench_function(
            BenchmarkId::new(precision.name(), "grid16x16x32_p27"),
            |bench| {
                bench.iter(|| {
                    s.factorize(&a).unwrap();
                    let mut x = rhs.clone();
                    s.solve_in_place(&a, &mut x).unwrap();
                    assert_eq!(s.report().precision, precision.name());
                    black_box(x)
                })
            },
        );
    }
    group.finish();
}

fn cg(c: &mut Criterion) {
    let mut group = c.benchmark_group("cg_solve");
    group.sample_size(10);
    for (name, a, coords) in problems() {
        let rhs = vec![1.0; a.n];
        for preconditioner in [Preconditioner::Jacobi, Preconditioner::BlockJacobi] {
            let mut s = CgSolver::new(CgSettings {
                preconditioner,
                tol: 1e-10,
                ..Default::default()
            });
            s.analyze(&a, Some(&coords)).unwrap();
            s.factorize(&a).unwrap();
            let label = format!("{preconditioner:?}");
            group.bench_function(BenchmarkId::new(label, name), |bench| {
                bench.iter(|| {
                    let mut x = rhs.clone();
                    s.solve_in_place(&a, &mut x).unwrap();
                    black_box(x)
                })
            });
        }
    }
    group.finish();
}

criterion_group!(benches, cholesky, ldlt_vs_cholesky, precision, cg);
criterion_main!(benches);
