//! `[solver] type = "auto"` for symmetric models: the direct supernodal
//! Cholesky (`ldlt` when a law can soften) unless its factor would not fit,
//! then the smoothed-aggregation AMG preconditioner with conjugate
//! gradients (`cg`), or with GMRES (`gmres`) when the tangent can be
//! indefinite.
//!
//! Models of at most [`DIRECT_ALWAYS`] equations keep the direct solver
//! without any analysis (their factor is small; existing results stay bit
//! for bit). Above, the model is ordered by nested dissection (the
//! ordering the direct solver would compute first) and the factor's size is
//! predicted on that ordering by weighted column counts over the node graph
//! ([`ordering::choose_reusing`]: `O(nnz(A))`, exact for an ordering that
//! keeps each node's equations together). AMG is chosen, with the numbers
//! in the run's notes (`summary.json` `notes`), when
//! - the factor's memory (8 bytes per non-zero, double precision) exceeds
//!   half of the memory available ([`crate::limits::machine_memory`]): such
//!   a factor is never attempted; or
//! - for positive-definite models only, the factor holds more than
//!   [`AMG_FILL_PER_EQUATION`] non-zeros per equation (a compact 3D solid,
//!   where AMG-CG is measured faster). Softening models keep `ldlt` there:
//!   GMRES on an indefinite tangent is not measured to be faster.
//!
//! When the direct solver is kept, the dissection is handed to it
//! ([`junta_core::LinearSolver::offer_dissection`]), so the run orders the
//! model once. The decision's time is the `choose_solver` entry of
//! `summary.json` `timings`.

use junta_core::{Model, PrecomputedDissection};
use junta_solvers::ordering::{self, OrderingKind};

/// Up to this many equations `auto` keeps the direct solver.
pub const DIRECT_ALWAYS: usize = 100_000;

/// Above [`DIRECT_ALWAYS`], a factor with more non-zeros per equation than
/// this (a compact 3D solid, whose fill grows like `n^(1/3)`) is slower
/// than AMG: measured with `bench/cube_vs_calculix.sh` (2 cores), H20 cube
/// n=20 (102,039 equations, 1,227 factor entries per equation) and H8 n=40
/// (200,039 equations, 1,163 per equation): see `docs/performance.md` for
/// the times of both back ends. Slender and layered models fill far less
/// and stay direct.
pub const AMG_FILL_PER_EQUATION: f64 = 1000.0;

/// What `auto` decided for a symmetric model.
#[derive(Debug, Clone, Default)]
pub struct Decision {
    /// `Some(reason)` when AMG replaces the direct factor (the reason names
    /// the factor's predicted size against the memory available).
    pub amg_reason: Option<String>,
    /// The nested dissection computed to decide, for the direct solver
    /// (`None` when AMG was chosen or no analysis was needed).
    pub dissection: Option<PrecomputedDissection>,
    /// Seconds spent deciding.
    pub seconds: f64,
}

/// [`decide_above`] with the threshold [`DIRECT_ALWAYS`].
pub fn decide(model: &Model, positive_definite: bool) -> Decision {
    decide_above(model, positive_definite, DIRECT_ALWAYS)
}

/// The direct factor or AMG for `model`; models of at most
/// `direct_always` equations keep the direct factor without analysis.
pub fn decide_above(model: &Model, positive_definite: bool, direct_always: usize) -> Decision {
    let t0 = std::time::Instant::now();
    let n = model.dofs.num_free;
    if n <= direct_always {
        return Decision::default();
    }
    let pattern = model.assembler().pattern;
    let coords = model.dofs.equation_coords(&model.mesh.nodes);
    let choice = ordering::choose(OrderingKind::NestedDissection, &pattern, Some(&coords));
    let estimate = choice.estimate();
    let amg_reason = amg_reason(n, estimate.nonzeros, positive_definite);
    let dissection = amg_reason.is_none().then(|| PrecomputedDissection {
        perm: choice.perm,
        nonzeros: estimate.nonzeros,
        flops: estimate.flops,
        seconds: choice.seconds,
    });
    Decision {
        amg_reason,
        dissection,
        seconds: t0.elapsed().as_secs_f64(),
    }
}

/// `Some(reason)` when a direct factor of `nnz_l` non-zeros for `n`
/// equations should give way to AMG (see the module docs).
fn amg_reason(n: usize, nnz_l: usize, positive_definite: bool) -> Option<String> {
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
