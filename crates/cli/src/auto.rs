//! `[solver] type = "auto"` for symmetric positive-definite models: the
//! direct supernodal Cholesky unless its factor would not fit, then
//! conjugate gradients with the smoothed-aggregation AMG preconditioner.
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

/// Bytes of memory the system can still give (Linux `MemAvailable`).
fn mem_available() -> Option<u64> {
    let info = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = info.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

/// `Some(reason)` when `auto` should use AMG-CG instead of `cholesky`.
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
    let avail = mem_available()? as f64;
    let gb = |b: f64| b / 1e9;
    if bytes > 0.5 * avail {
        Some(format!(
            "solver auto: the Cholesky factor of {n} equations would hold {nnz_l} non-zeros ({:.1} GB in double precision, nested dissection), more than half of the {:.1} GB available: using cg with the smoothed-aggregation AMG preconditioner",
            gb(bytes),
            gb(avail)
        ))
    } else {
        None
    }
}
