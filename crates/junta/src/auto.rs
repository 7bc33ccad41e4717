//! `[solver] type = "auto"` for symmetric models: the direct supernodal
//! Cholesky (`ldlt` when a law can soften) unless its factor would not fit,
//! then the smoothed-aggregation AMG preconditioner with conjugate
//! gradients (`cg`), or with GMRES (`gmres`) when the tangent can be
//! indefinite.
//!
//! Models of at most [`DIRECT_ALWAYS`] equations keep the direct solver
//! without any analysis (their factor is small; existing results stay bit
//! for bit). Above, the factor's non-zeros are counted exactly on the
//! nested-dissection ordering (elimination tree and column counts,
//! `O(nnz(A))`), and AMG is chosen, with the numbers in the run's notes
//! (`summary.json` `notes`), when
//! - the factor's memory (8 bytes per non-zero, double precision) exceeds
//!   half of the memory available ([`crate::limits::machine_memory`]): such
//!   a factor is never attempted; or
//! - for positive-definite models only, the factor holds more than
//!   [`AMG_FILL_PER_EQUATION`] non-zeros per equation (a compact 3D solid,
//!   where AMG-CG is measured faster). Softening models keep `ldlt` there:
//!   GMRES on an indefinite tangent is not measured to be faster.

use junta_core::Model;
use junta_solvers::ordering;

/// Up to this many equations `auto` keeps the direct solver.
pub const DIRECT_ALWAYS: usize = 100_000;

/// Above [`DIRECT_ALWAYS`], a factor with more non-zeros per equation than
/// this (a compact 3D solid, whose fill grows like `n^(1/3)`) is slower
/// than AMG: measured with `bench/cube_vs_calculix.sh` (2 cores), H20 cube
/// n=20 (102,039 equations, 1,230 factor entries per equation) AMG-CG 4.5 s
/// against the direct solver's 5.6 s, H8 n=40 (200,039 equations, 1,170
/// per equation) 3.5 s against 10.2 s. Slender and layered models fill
/// far less and stay direct.
pub const AMG_FILL_PER_EQUATION: f64 = 1000.0;

/// `Some(reason)` when `auto` should use AMG instead of the direct factor
/// (the reason names the factor's size against the memory available,
/// [`crate::limits::machine_memory`], which `JUNTA_MEMORY_LIMIT` sets).
pub fn prefer_amg(model: &Model, positive_definite: bool) -> Option<String> {
    let n = model.dofs.num_free;
    if n <= DIRECT_ALWAYS {
        return None;
    }
    let pattern = model.assembler().pattern;
    let coords = model.dofs.equation_coords(&model.mesh.nodes);
    let perm = ordering::nested_dissection(&pattern, Some(&coords));
    let nnz_l = ordering::factor_nonzeros(&pattern, Some(&perm));
    let bytes = 8.0 * nnz_l as f64;
    let avail = crate::limits::machine_memory().unwrap_or(f64::INFINITY);
    let gb = |b: f64| b / 1e9;
    let fill = nnz_l as f64 / n as f64;
    if bytes > 0.5 * avail {
        Some(format!(
            "solver auto: the direct factor of {n} equations would hold {nnz_l} non-zeros ({:.1} GB in double precision, nested dissection), more than half of the {:.1} GB available",
            gb(bytes),
            gb(avail)
        ))
    } else if positive_definite && fill > AMG_FILL_PER_EQUATION {
        Some(format!(
            "solver auto: the direct factor of {n} equations would hold {nnz_l} non-zeros ({fill:.0} per equation, above {AMG_FILL_PER_EQUATION:.0}: a compact 3D model, on which AMG is the faster; {:.1} GB would fit in the {:.1} GB available)",
            gb(bytes),
            gb(avail)
        ))
    } else {
        None
    }
}
