//! `[solver] type = "auto"` for symmetric models: the direct supernodal
//! Cholesky (`ldlt` when a law can soften) unless its factor would not fit,
//! then the smoothed-aggregation AMG preconditioner with conjugate
//! gradients (`cg`), or with GMRES (`gmres`) when the tangent can be
//! indefinite.
//!
//! Models of at most [`DIRECT_ALWAYS`] equations keep `cholesky` without
//! any analysis (their factor is small; existing results stay bit for bit).
//! Above, the factor's non-zeros are counted exactly on the nested-dissection
//! ordering (elimination tree and column counts, `O(nnz(A))`), its memory
//! (8 bytes per non-zero, double precision) is compared with half of the
//! memory available (`MemAvailable`): a factor that does not fit that
//! budget is never attempted, and AMG-CG is chosen with the numbers in the
//! run's notes (`summary.json` `notes`).

use junta_core::Model;
use junta_solvers::ordering;

/// Up to this many equations `auto` keeps the direct solver.
pub const DIRECT_ALWAYS: usize = 150_000;

/// `Some(reason)` when `auto` should use AMG instead of the direct factor
/// (the reason names the factor's size against the memory available,
/// [`crate::limits::machine_memory`], which `JUNTA_MEMORY_LIMIT` sets).
pub fn prefer_amg(model: &Model) -> Option<String> {
    let n = model.dofs.num_free;
    if n <= DIRECT_ALWAYS {
        return None;
    }
    let pattern = model.assembler().pattern;
    let coords = model.dofs.equation_coords(&model.mesh.nodes);
    let perm = ordering::nested_dissection(&pattern, Some(&coords));
    let nnz_l = ordering::factor_nonzeros(&pattern, Some(&perm));
    let bytes = 8.0 * nnz_l as f64;
    let avail = crate::limits::machine_memory()?;
    let gb = |b: f64| b / 1e9;
    if bytes > 0.5 * avail {
        Some(format!(
            "solver auto: the direct factor of {n} equations would hold {nnz_l} non-zeros ({:.1} GB in double precision, nested dissection), more than half of the {:.1} GB available",
            gb(bytes),
            gb(avail)
        ))
    } else {
        None
    }
}
