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
//!   half of the memory available ([`crate::prepare::limits::machine_memory`]): such
//!   a factor is never attempted; or
//! - for positive-definite models only, AMG-CG is predicted faster than
//!   the direct solver by the cost model of [`predicted_seconds`]: the
//!   factorisation's flops and the factor's size against the matrix's
//!   entries times the iterations of a set-up and a solve. Softening models
//!   keep `ldlt` there: GMRES on an indefinite tangent is not measured to
//!   be faster.
//!
//! When the direct solver is kept, the dissection is handed to it
//! ([`junta_core::LinearSolver::offer_dissection`]), so the run orders the
//! model once. The decision's time is the `choose_solver` entry of
//! `summary.json` `timings`.

use junta_core::{Model, PrecomputedDissection};
use junta_solvers::ordering::{self, OrderingKind};

/// Up to this many equations `auto` keeps the direct solver.
pub const DIRECT_ALWAYS: usize = 100_000;

/// Floating-point operations per second of the direct factorisation
/// (the `flops` of [`ordering::FillEstimate`], mixed precision, 2
/// threads). Measured with `bench/cube_vs_calculix.sh` (2026-11-26): H20
/// cube n=20, 3.2e11 in 2.39 s; H8 n=40, 7.5e11 in 5.99 s.
pub const DIRECT_FLOPS_PER_SECOND: f64 = 1.3e11;

/// Seconds per factor non-zero of the rest of a direct solve (symbolic
/// analysis, triangular solves, refinement). Same runs: 1.02 s for 125M
/// non-zeros, 1.55 s for 233M.
pub const DIRECT_SECONDS_PER_FACTOR_ENTRY: f64 = 7e-9;

/// Seconds per stored (upper-triangle) matrix entry of one AMG-CG
/// iteration. Same decks (medians of 3): H20 0.087 s per iteration for
/// 8.26M entries, H8 0.108 s for 7.79M.
pub const AMG_SECONDS_PER_ENTRY: f64 = 1.2e-8;

/// The AMG set-up costs about this many iterations (same runs: H20 1.12 s,
/// H8 1.40 s: 12.9 and 13.0 iterations).
pub const AMG_SETUP_ITERATIONS: f64 = 13.0;

/// Iterations assumed for AMG-CG to a relative residual of 1e-10: 16 were
/// measured on the H8 cube n=40, 35 on the H20 cube n=20 (quadratic
/// elements couple farther and coarsen less well).
pub const AMG_ITERATIONS: f64 = 25.0;

/// Predicted seconds of the direct solver and of AMG-CG for a factor of
/// `factor` (non-zeros and flops) and a matrix of `entries` stored
/// entries (upper triangle): `flops / DIRECT_FLOPS_PER_SECOND + nnz(L)
/// DIRECT_SECONDS_PER_FACTOR_ENTRY` against `entries
/// AMG_SECONDS_PER_ENTRY (AMG_SETUP_ITERATIONS + AMG_ITERATIONS)`. On
/// the benchmark cubes (analysis, factorisation or set-up, and solve): H20
/// n=20 3.3 s direct against 3.8 s AMG (measured 3.9 s and 4.2 s), H8
/// n=40 7.4 s against 3.6 s (measured 7.5 s and 3.1 s).
pub fn predicted_seconds(factor: &ordering::FillEstimate, entries: usize) -> (f64, f64) {
    let direct = factor.flops / DIRECT_FLOPS_PER_SECOND
        + factor.nonzeros as f64 * DIRECT_SECONDS_PER_FACTOR_ENTRY;
    let amg = entries as f64 * AMG_SECONDS_PER_ENTRY * (AMG_SETUP_ITERATIONS + AMG_ITERATIONS);
    (direct, amg)
}

/// What `auto` decided for a symmetric model.
#[derive(Debug, Clone, Default)]
pub struct Decision {
    /// `Some(reason)` when AMG replaces the direct factor (the reason names
    /// the factor's predicted size against the memory available).
    pub amg_reason: Option<String>,
    /// The nested dissection computed to decide, for the direct solver
    /// (`None` when AMG was chosen or no analysis was needed).
    pub dissection: Option<PrecomputedDissection>,
}

/// [`decide_above`] with the threshold [`DIRECT_ALWAYS`].
pub fn decide(model: &Model, positive_definite: bool) -> Decision {
    decide_above(model, positive_definite, DIRECT_ALWAYS)
}

/// The direct factor or AMG for `model`; models of at most
/// `direct_always` equations keep the direct factor without analysis.
pub fn decide_above(model: &Model, positive_definite: bool, direct_always: usize) -> Decision {
    let n = model.dofs.num_free;
    if n <= direct_always {
        return Decision::default();
    }
    let asm = model.assembler();
    let coords = model.dofs.equation_coords(&model.mesh.nodes);
    let choice = ordering::choose(OrderingKind::NestedDissection, &asm.pattern, Some(&coords));
    let estimate = choice.estimate();
    let amg_reason = amg_reason(n, &estimate, asm.pattern.nnz(), positive_definite);
    // the run assembles into this pattern: built once
    model.keep_assembler(asm);
    let dissection = match amg_reason {
        Some(_) => None,
        None => Some(PrecomputedDissection {
            perm: choice.perm,
            nonzeros: estimate.nonzeros,
            flops: estimate.flops,
        }),
    };
    Decision {
        amg_reason,
        dissection,
    }
}

/// `Some(reason)` when a direct factor `factor` for `n` equations and a
/// matrix of `entries` stored entries should give way to AMG (see the
/// module docs).
fn amg_reason(
    n: usize,
    factor: &ordering::FillEstimate,
    entries: usize,
    positive_definite: bool,
) -> Option<String> {
    let nnz_l = factor.nonzeros;
    let bytes = 8.0 * nnz_l as f64;
    let avail = crate::prepare::limits::machine_memory().unwrap_or(f64::INFINITY);
    let gb = |b: f64| b / 1e9;
    let (direct, amg) = predicted_seconds(factor, entries);
    if bytes > 0.5 * avail {
        Some(format!(
            "solver auto: the direct factor of {n} equations would hold {nnz_l} non-zeros ({:.1} GB in double precision, nested dissection), more than half of the {:.1} GB available",
            gb(bytes),
            gb(avail)
        ))
    } else if positive_definite && amg < direct {
        Some(format!(
            "solver auto: AMG-CG is predicted faster than the direct factor of {n} equations ({nnz_l} non-zeros, {:.1e} flops: about {direct:.1} s, against {amg:.1} s for {entries} matrix entries and {AMG_ITERATIONS:.0} iterations; {:.1} GB would fit in the {:.1} GB available)",
            factor.flops,
            gb(bytes),
            gb(avail)
        ))
    } else {
        None
    }
}
