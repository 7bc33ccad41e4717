//! Compare orderings on grid matrices: factor non-zeros and factor time.
//!
//! `cargo run --release -p junta-solvers --example nd_vs_amd -- [m] [7|27] [factor]`
//! (grid m^3 nodes, 3 dofs per node; default 41, 27-point, with factorisation:
//! about 207k dofs, like the H8 n=40 cube of BENCHMARKS.md).

use junta_core::LinearSolver;
use junta_solvers::gallery::{grid_3d, Stencil};
use junta_solvers::ordering::{self, OrderingKind};
use junta_solvers::{CholeskySettings, CholeskySolver};
use std::time::Instant;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let m: usize = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(41);
    let stencil = match args.get(2).map(String::as_str) {
        Some("7") => Stencil::Point7,
        _ => Stencil::Point27,
    };
    let factor = args.get(3).map(String::as_str) != Some("nofactor");
    let (a, coords) = grid_3d(m, m, m, 3, stencil);
    println!(
        "grid {m}^3 {stencil:?}, 3 dofs/node: n = {}, nnz(upper) = {}",
        a.n,
        a.nnz()
    );
    for name in ["nd_geometric", "nd_graph", "amd"] {
        let t = Instant::now();
        let p = match name {
            "nd_geometric" => ordering::nested_dissection(&a, Some(&coords)),
            "nd_graph" => ordering::nested_dissection(&a, None),
            _ => ordering::amd_ordering(&a),
        };
        let secs = t.elapsed().as_secs_f64();
        let nnz = ordering::factor_nonzeros(&a, Some(&p));
        println!(
            "{name:>14}: ordering {secs:.3} s, nnz(L) = {nnz} ({:.2} GB)",
            nnz as f64 * 8e-9
        );
    }
    if !factor {
        return;
    }
    for kind in [OrderingKind::NestedDissection, OrderingKind::Amd] {
        let mut s = CholeskySolver::new(CholeskySettings {
            ordering: kind,
            ..Default::default()
        });
        s.analyze(&a, Some(&coords)).unwrap();
        let t = Instant::now();
        s.factorize(&a).unwrap();
        let tf = t.elapsed().as_secs_f64();
        let mut x = vec![1.0; a.n];
        s.solve_in_place(&a, &mut x).unwrap();
        let r = s.report();
        println!(
            "cholesky {:>18}: analyze {:.2} s, factor {tf:.2} s, solve {:.3} s, stored nnz(L) {}, residual {:.1e}",
            kind.name(),
            r.analyze_seconds,
            r.solve_seconds,
            r.factor_nonzeros,
            r.residual
        );
    }
}
