//! Sparse direct solver for symmetric indefinite matrices: supernodal
//! `L D L^T` with Bunch-Kaufman 1x1/2x2 pivoting inside each panel
//! (registry key `ldlt`), for the tangents of softening cohesive laws that
//! Cholesky refuses.
//!
//! # Factorisation
//!
//! The ordering `P` and the symbolic structure are those of
//! [`crate::CholeskySolver`] (one shared analysis, `crate::supernodal::analyze`:
//! fill-reducing ordering, the supernodal symbolic Cholesky, supernodes
//! split into panels of at most 256 columns). Column by column the numeric
//! factor is a block elimination of `P A P^T`: for panel `s` with columns
//! `J` and rows `R` below,
//!
//! ```text
//! S = A[J+R, J] - sum_d L[J+R, K_d] D_d L[J, K_d]^T      (left-looking update)
//! Q_s S_JJ Q_s^T = L_JJ D_J L_JJ^T                        (dense Bunch-Kaufman)
//! L_RJ = S_RJ Q_s^T L_JJ^-T D_J^-1                        (triangular solve)
//! ```
//!
//! where `L_JJ` is unit lower triangular, `D_J` block diagonal with 1x1 and
//! 2x2 blocks, and `Q_s` a permutation of the panel's own columns. The rows
//! `R` stay in the symbolic order, so the structure of `L` is exactly the
//! Cholesky one and the descendants of a panel never see its pivoting; the
//! solve applies `Q_s` per panel: `y_J = L_JJ^-1 Q_s b_J`, `b_R -= L_RJ y_J`
//! going forward, `y <- D^-1 y`, then `x_J = Q_s^T L_JJ^-T (y_J - L_RJ^T
//! x_R)` going backward.
//!
//! # Bunch-Kaufman choice rule
//!
//! At step `k` of the dense block (`alpha = pivot_threshold`, by default
//! `(1 + sqrt(17)) / 8 ~ 0.64`, which minimises the bound on element
//! growth): `colmax = max_{i>k} |a_ik|` (row `r`), `rowmax = max_{j != r}
//! |a_rj|`.
//! 1. `|a_kk| >= alpha colmax`, or `|a_kk| rowmax >= alpha colmax^2`: 1x1
//!    pivot `a_kk`;
//! 2. else `|a_rr| >= alpha rowmax`: swap `k <-> r`, 1x1 pivot `a_rr`;
//! 3. else swap `k+1 <-> r`, 2x2 pivot `[[a_kk, a_rk], [a_rk, a_rr]]`,
//!    whose determinant satisfies `|det| > (1 - alpha^2) a_rk^2`, so it is
//!    never tiny next to its off-diagonal entry.
//!
//! Each step grows the entries by at most `1 + 1/alpha` (1x1) or
//! `(1 + 1/alpha)^2` per two columns (2x2), as with partial pivoting in LU.
//!
//! # Restricted pivoting and its limits
//!
//! Pivots are looked for only inside the diagonal block of the panel (no
//! delayed pivots, unlike MUMPS or MA57): the rows `R` below do not take
//! part in the choice, so the bound above holds for `L_JJ` and `D` but not
//! for `L_RJ`, and a panel whose Schur complement block `S_JJ` is singular
//! while `A` is not has no acceptable pivot. Then a pivot with
//! `max(|a_kk|, colmax) <= tiny_pivot ||A||_inf` (default `eps ||A||`) is
//! replaced by the static perturbation `sign(a_kk) perturbation ||A||_inf`
//! (default `sqrt(eps) ||A||`, as in Pardiso's static pivoting), the report
//! warns with the count and sizes, and iterative refinement recovers the
//! solution of the unperturbed system when the perturbation was only due to
//! the restriction. When refinement cannot bring the residual below
//! `warn_tol` and pivots were perturbed or the smallest pivot is below
//! `pivot_warn ||A||_inf`, the matrix is numerically singular: an error
//! with its numbers, never NaN. Saddle-point (KKT) matrices whose zero block is
//! ordered before the rows coupled to it are the typical weak case;
//! finite-element tangents of softening laws have non-zero diagonals and
//! need few 2x2 pivots.
//!
//! # Inertia
//!
//! `P A P^T = (L Q) D (L Q)^T` with a congruence, so by Sylvester's law of
//! inertia `A` and `D` have as many negative eigenvalues: a 1x1 pivot
//! counts one if negative; a 2x2 block counts one if its determinant is
//! negative (eigenvalues of both signs), two if its determinant is positive
//! and its trace negative. The count is reported as
//! [`SolveReport::negative_pivots`] (unreliable when pivots were perturbed:
//! the report says so). Continuation and arc-length drivers use it to
//! detect limit and bifurcation points.
//!
//! # Partial refactorisation
//!
//! Panel `s` of the factor depends on the entries of `A` in its own columns
//! and, through the updates, on those of its descendants in the panel
//! elimination tree only. When a Newton iteration changes a few entries (a
//! softening interface between elastic solids: only the integration points
//! in the process zone change their tangent), the panels holding a changed
//! entry and their ancestors are refactorised and the others kept, with
//! their pivots: the factor is the one a complete factorisation gives, bit
//! for bit. Changes are found by comparing the values with those of the
//! last factorisation; the report counts the partial factorisations and
//! the share of the complete work they did (`partial_refactor = false`
//! turns this off).
//!
//! # Solve
//!
//! `x = P^T (L Q)^-T D^-1 (L Q)^-1 P b`, the relative residual
//! `rho = ||b - A x|| / ||b||`, and iterative refinement `x <- x + (L D
//! L^T)^-1 (b - A x)` while `rho > refine_tol` (at most `max_refinements`
//! steps, stopping when a step no longer lowers `rho`). Double precision
//! only. The residuals of all right-hand sides of a call come from one
//! pass over the matrix. That pass costs as much as a triangular sweep;
//! under a caller that checks its own residual (the Newton and arc-length
//! drivers, [`LinearSolver::set_caller_checks_residual`]) it is skipped
//! when the factor is above doubt ([`ResidualCheck::Auto`]): no perturbed
//! pivot, no pivot below `pivot_warn ||A||_inf`, and growth
//! `max(1, max|L|)^2 max|D| / ||A||_inf` at most [`UNCHECKED_GROWTH_LIMIT`]
//! (the largest multiplier of each panel is measured after its
//! factorisation, because the restricted pivoting does not bound `L_RJ`).
//! On the 50k-dof DCB the growth stays below 900 through the softening and
//! the run is 10 % faster with the same curve, bit for bit. On factors of at least `parallel_solve_entries`
//! stored entries, the solves split the panel elimination tree at its
//! first branching (`SolvePlan` in `supernodal.rs`): the subtrees below it run in parallel
//! (forward: each adds its updates of the separator's rows into its own
//! buffer, summed before the separator's panels; backward: the separator
//! first, then the subtrees, which only read its rows).
//!
//! The matrix norm `||A||_inf` behind the pivot thresholds is kept as the
//! row sums of `|A|`, updated with the entries that changed.

use crate::common::{
    inf_norm, nan_max, norm2, residual, symmetric_only, symmetric_row_sums, validate, Pattern,
};
use crate::ordering::OrderingKind;
use crate::supernodal::{PanelFactor, ScatterIndex, SharedPtr, SolvePlan, PARALLEL_SOLVE_ENTRIES};
use faer::linalg::triangular_solve as tri;
use faer::reborrow::{Reborrow, ReborrowMut};
use faer::{MatMut, MatRef, Par};
use junta_core::registry::{parse_params, ParamDoc, SolverEntry};
use junta_core::{
    LinearSolver, MatrixKind, PrecomputedDissection, SolveReport, SolverError, SymmetricCsc,
};
use rayon::prelude::*;
use serde::Deserialize;
use std::time::Instant;

/// Settings of [`LdltSolver`] (TOML parameters of the `ldlt` key).
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct LdltSettings {
    /// Fill-reducing ordering: `"auto"` (default), `"nested_dissection"`, `"amd"` or
    /// `"natural"` (the same analysis as `cholesky`).
    pub ordering: OrderingKind,
    /// Bunch-Kaufman `alpha` in `(0, 1)`: default `(1 + sqrt(17)) / 8`.
    pub pivot_threshold: f64,
    /// Pivots with `max(|a_kk|, colmax) <= tiny_pivot ||A||_inf` are
    /// perturbed (default `f64::EPSILON`).
    pub tiny_pivot: f64,
    /// Size of a perturbed pivot relative to `||A||_inf` (default
    /// `sqrt(f64::EPSILON)`, about 1.5e-8), sign kept.
    pub perturbation: f64,
    /// Relative residual above which iterative refinement runs (1e-10).
    pub refine_tol: f64,
    /// Maximum refinement steps per solve (3; 10 when pivots were perturbed).
    pub max_refinements: usize,
    /// Relative residual after refinement above which the report warns, or,
    /// with perturbed pivots, the matrix is refused as singular (1e-6).
    pub warn_tol: f64,
    /// Smallest unperturbed pivot `|eigenvalue| / ||A||_inf` below which the
    /// report warns of a near-singular matrix, and a solve that then misses
    /// `warn_tol` is refused as singular (1e-12).
    pub pivot_warn: f64,
    /// Threads for the numeric factorisation (0: rayon's pool).
    pub threads: usize,
    /// Refactorise only the panels whose entries changed since the last
    /// factorisation, and their ancestors (default true; see the module
    /// docs, "Partial refactorisation").
    pub partial_refactor: bool,
    /// Stored factor entries from which the triangular solves run the
    /// independent subtrees of the elimination tree in parallel (default
    /// 2^20; below it a solve is too short to split).
    pub parallel_solve_entries: usize,
    /// When a solve computes its residual `||b - A x|| / ||b||` (see
    /// [`ResidualCheck`]; default `auto`).
    pub residual_check: ResidualCheck,
}

/// When [`LdltSolver`] checks the residual of a solve (and refines).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ResidualCheck {
    /// Every solve, unless the caller checks its own residual
    /// ([`LinearSolver::set_caller_checks_residual`], the Newton and
    /// arc-length drivers) and the factor is above doubt: no perturbed
    /// pivot, smallest pivot above `pivot_warn`, and growth
    /// [`LdltStats::growth`] at most [`UNCHECKED_GROWTH_LIMIT`].
    #[default]
    Auto,
    /// Every solve.
    Always,
}

/// Largest growth `max|L|^2 max|D| / ||A||_inf` ([`LdltStats::growth`]) of
/// a factor whose solves may go unchecked under a caller that checks its
/// own residual. The backward error of `L D L^T` is bounded by a modest
/// multiple of `eps |L| |D| |L^T|` (Higham, *Accuracy and Stability of
/// Numerical Algorithms*, 2nd ed., section 11.1), so below this growth a
/// solve loses no more than about 4 of its 16 digits to the factor; the
/// restricted pivoting ([module docs](self)) bounds `L_JJ` but not `L_RJ`,
/// which is why the growth is measured rather than assumed.
pub const UNCHECKED_GROWTH_LIMIT: f64 = 1e4;

/// Weight of nested dissection's predicted flops when `"auto"` compares it
/// with minimum degree and partial refactorisation is on
/// ([`crate::ordering::choose_weighted`]): dissection is kept unless
/// minimum degree needs less than a quarter of its flops.
const ND_WEIGHT_PARTIAL: f64 = 0.25;

/// Bunch-Kaufman's `alpha = (1 + sqrt(17)) / 8`.
pub const BUNCH_KAUFMAN_ALPHA: f64 = 0.640_388_203_202_207_6;

impl Default for LdltSettings {
    fn default() -> Self {
        LdltSettings {
            ordering: OrderingKind::default(),
            pivot_threshold: BUNCH_KAUFMAN_ALPHA,
            tiny_pivot: f64::EPSILON,
            perturbation: f64::EPSILON.sqrt(),
            refine_tol: 1e-10,
            max_refinements: 3,
            warn_tol: 1e-6,
            pivot_warn: 1e-12,
            threads: 0,
            partial_refactor: true,
            parallel_solve_entries: PARALLEL_SOLVE_ENTRIES,
            residual_check: ResidualCheck::Auto,
        }
    }
}

/// Parameter documentation of the `ldlt` registry entry.
pub const LDLT_PARAMS: &[ParamDoc] = &[
    ParamDoc {
        name: "ordering",
        doc: "fill-reducing ordering: \"auto\" (default: nested dissection or AMD, whichever is predicted to cost fewer flops), \"nested_dissection\", \"amd\", \"natural\" (same analysis as cholesky)",
    },
    ParamDoc {
        name: "pivot_threshold",
        doc: "Bunch-Kaufman alpha in (0, 1): a 1x1 pivot is kept when |a_kk| >= alpha * column max (default (1+sqrt(17))/8 = 0.6404)",
    },
    ParamDoc {
        name: "tiny_pivot",
        doc: "pivots (and their columns) below tiny_pivot * ||A||_inf within a panel are perturbed, with a warning (default 2.2e-16)",
    },
    ParamDoc {
        name: "perturbation",
        doc: "size of a perturbed pivot relative to ||A||_inf, sign kept (default 1.5e-8)",
    },
    ParamDoc {
        name: "refine_tol",
        doc: "relative residual above which iterative refinement runs (default 1e-10)",
    },
    ParamDoc {
        name: "max_refinements",
        doc: "maximum iterative-refinement steps per solve (default 3; at least 10 when pivots were perturbed)",
    },
    ParamDoc {
        name: "warn_tol",
        doc: "relative residual after refinement above which a warning is reported, or with perturbed pivots the matrix is refused as singular (default 1e-6)",
    },
    ParamDoc {
        name: "pivot_warn",
        doc: "smallest pivot |eigenvalue| / ||A||_inf below which a near-singular warning is reported; a solve missing warn_tol is then refused as singular (default 1e-12)",
    },
    ParamDoc {
        name: "threads",
        doc: "threads for the factorisation, 0 = all of rayon's pool (default 0)",
    },
    ParamDoc {
        name: "parallel_solve_entries",
        doc: "stored factor entries from which the triangular solves run independent subtrees in parallel (default 1048576)",
    },
    ParamDoc {
        name: "residual_check",
        doc: "\"auto\" (default): every solve computes its residual ||b - A x|| / ||b|| and refines, except under a Newton or arc-length driver (which checks its own residual) when the factor has no perturbed pivot, no pivot below pivot_warn and growth max|L|^2 max|D| / ||A||_inf <= 1e4; \"always\": every solve",
    },
    ParamDoc {
        name: "partial_refactor",
        doc: "refactorise only the part of the factor that depends on the entries changed since the last factorisation (a softening interface in elastic solids; default true, the result is the same to the last bit)",
    },
];

/// Numbers describing the last analysis and factorisation.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct LdltStats {
    /// Ordering used.
    pub ordering: &'static str,
    /// Number of symbolic analyses so far.
    pub analyze_count: usize,
    /// Of those, analyses that took the caller's nested dissection
    /// ([`LinearSolver::offer_dissection`]) instead of computing it.
    pub dissections_reused: usize,
    /// Number of numeric factorisations so far.
    pub factor_count: usize,
    /// Number of solves so far.
    pub solve_count: usize,
    /// Non-zeros of `L` as stored (lower trapezoids of the panels).
    pub factor_nonzeros: usize,
    /// Negative eigenvalues of the last matrix (from `D`).
    pub negative_pivots: usize,
    /// Number of 1x1 pivots of the last factor.
    pub pivots_1x1: usize,
    /// Number of 2x2 pivot blocks of the last factor (each covers two
    /// equations).
    pub pivots_2x2: usize,
    /// Pivots replaced by a static perturbation.
    pub perturbed_pivots: usize,
    /// Smallest `|eigenvalue|` of an unperturbed pivot block over `||A||_inf`.
    pub min_pivot_ratio: f64,
    /// `||A||_inf` of the last matrix.
    pub matrix_norm_inf: f64,
    /// Refinement steps of the last solve.
    pub refinement_steps: usize,
    /// Subtrees the last solve ran in parallel (0: one pass in panel
    /// order).
    pub solve_tasks: usize,
    /// Largest multiplier `|l_ij|` of the last factor.
    pub max_multiplier: f64,
    /// Largest `|eigenvalue|` of a pivot block of the last factor.
    pub max_pivot: f64,
    /// Growth of the last factor, `max(1, max|L|)^2 max|D| / ||A||_inf`
    /// (1 for a diagonal matrix; large when the restricted pivoting let the
    /// factor grow): see [`ResidualCheck::Auto`].
    pub growth: f64,
}

/// Kind of a pivot position (`Pivots::kind`).
const ONE: u8 = 0;
const FIRST: u8 = 1;
const SECOND: u8 = 2;
const PERTURBED: u8 = 4;

/// Block-diagonal `D` and the panel-local permutations `Q_s`, in the
/// permuted numbering: `kind[k]` is `ONE` (1x1 pivot `diag[k]`), `FIRST` /
/// `SECOND` (2x2 block `[[diag[k], sub[k]], [sub[k], diag[k+1]]]`), or
/// `ONE | PERTURBED`; `lperm[b + i]` is the panel-local column (of the
/// symbolic order) eliminated at position `i` of panel `[b, e)`.
#[derive(Debug, Default)]
struct Pivots {
    diag: Vec<f64>,
    sub: Vec<f64>,
    kind: Vec<u8>,
    lperm: Vec<u32>,
}

impl Pivots {
    fn resize(&mut self, n: usize) {
        self.diag.resize(n, 0.0);
        self.sub.resize(n, 0.0);
        self.kind.resize(n, ONE);
        self.lperm.resize(n, 0);
    }
}

/// Raw pointers into [`Pivots`] for the panel tasks (each writes its own
/// columns and reads those of its finished descendants).
#[derive(Clone, Copy)]
struct PivotPtrs {
    diag: SharedPtr<f64>,
    sub: SharedPtr<f64>,
    kind: SharedPtr<u8>,
    lperm: SharedPtr<u32>,
}

/// Per-task scratch of the numeric factorisation.
#[derive(Default)]
struct Scratch {
    tmp: Vec<f64>,
    wbuf: Vec<f64>,
    cols: Vec<f64>,
}

/// Pivoting constants of one factorisation.
#[derive(Clone, Copy, PartialEq)]
struct PivotRule {
    alpha: f64,
    tiny: f64,
    perturb: f64,
}

/// Sparse symmetric-indefinite `L D L^T` back end (registry key `"ldlt"`).
pub struct LdltSolver {
    settings: LdltSettings,
    pattern: Option<Pattern>,
    /// `perm[new] = old`, and its inverse.
    perm: Vec<usize>,
    perm_inv: Vec<usize>,
    factor: Option<PanelFactor>,
    values: Vec<f64>,
    pivots: Pivots,
    factored: bool,
    /// Where each matrix entry goes in `values` (built at the first
    /// factorisation after an analysis).
    scatter_index: Option<ScatterIndex>,
    /// Matrix values and pivoting constants of the last successful
    /// factorisation (empty when the next one must be complete).
    factored_matrix: Vec<f64>,
    factored_rule: Option<PivotRule>,
    /// Panels to refactorise (scratch of a partial refactorisation), as
    /// flags and as a list.
    dirty: Vec<bool>,
    dirty_list: Vec<u32>,
    /// Absolute row sums of the last factorised matrix (`||A||_inf` is
    /// their maximum), updated with the changed entries.
    row_sums: Vec<f64>,
    /// Independent parts of the triangular solves.
    plan: Option<SolvePlan>,
    /// Storage of the matrix of the last successful factorisation
    /// ([`storage_id`]): a solve given the same storage skips the pattern
    /// check.
    factored_id: Option<(usize, usize, usize, usize)>,
    /// Total work of a complete factorisation (multiply-adds).
    total_work: f64,
    /// Largest `|l_ij|` of each panel of the factor.
    panel_max_multiplier: Vec<f64>,
    /// The caller checks its own residual
    /// ([`LinearSolver::set_caller_checks_residual`]).
    caller_checks: bool,
    stats: LdltStats,
    /// A nested dissection offered by the caller, taken by the next
    /// analysis.
    dissection: Option<PrecomputedDissection>,
    report: SolveReport,
}

impl std::fmt::Debug for LdltSolver {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("LdltSolver")
            .field("settings", &self.settings)
            .field("n", &self.perm.len())
            .field("factored", &self.factored)
            .field("stats", &self.stats)
            .finish_non_exhaustive()
    }
}

impl Default for LdltSolver {
    fn default() -> Self {
        Self::new(LdltSettings::default())
    }
}

impl LdltSolver {
    /// A solver with the given settings.
    pub fn new(settings: LdltSettings) -> Self {
        LdltSolver {
            settings,
            pattern: None,
            perm: Vec::new(),
            perm_inv: Vec::new(),
            factor: None,
            values: Vec::new(),
            pivots: Pivots::default(),
            factored: false,
            scatter_index: None,
            row_sums: Vec::new(),
            dirty_list: Vec::new(),
            plan: None,
            factored_id: None,
            factored_matrix: Vec::new(),
            factored_rule: None,
            dirty: Vec::new(),
            total_work: 0.0,
            panel_max_multiplier: Vec::new(),
            caller_checks: false,
            stats: LdltStats::default(),
            dissection: None,
            report: SolveReport {
                solver: "ldlt".into(),
                precision: "double".into(),
                ..Default::default()
            },
        }
    }

    /// From a TOML parameter table (unknown keys and out-of-range values
    /// are an error).
    pub fn from_table(table: &toml::Table) -> Result<Self, junta_core::CoreError> {
        let settings: LdltSettings = parse_params("solver", "ldlt", table)?;
        settings
            .check()
            .map_err(|message| junta_core::CoreError::InvalidParameters {
                kind: "solver",
                key: "ldlt".into(),
                message,
            })?;
        Ok(Self::new(settings))
    }

    /// The settings.
    pub fn settings(&self) -> &LdltSettings {
        &self.settings
    }

    /// Statistics of the analysis, last factorisation and last solve.
    pub fn stats(&self) -> &LdltStats {
        &self.stats
    }

    /// The ordering of the last analysis (`perm[new] = old`).
    pub fn permutation(&self) -> &[usize] {
        &self.perm
    }

    fn threads(&self) -> usize {
        if self.settings.threads == 0 {
            rayon::current_num_threads()
        } else {
            self.settings.threads
        }
    }

    fn push_warning(&mut self, w: String) {
        tracing::warn!("{w}");
        if !self.report.warnings.contains(&w) && self.report.warnings.len() < 32 {
            self.report.warnings.push(w);
        }
    }

    /// `x <- (L D L^T)^-1 x` through the permutations for the `x.len() / n`
    /// right-hand sides stored one after another in `x` (`work`, `tmp`:
    /// scratch).
    fn apply_inverse(&self, x: &mut [f64], work: &mut Vec<f64>, tmp: &mut Vec<f64>) {
        let n = self.perm.len();
        work.clear();
        for col in x.chunks(n) {
            work.extend(self.perm.iter().map(|&old| col[old]));
        }
        self.solve_permuted(work, tmp);
        for (col, w) in x.chunks_mut(n).zip(work.chunks(n)) {
            for (i, xi) in col.iter_mut().enumerate() {
                *xi = w[self.perm_inv[i]];
            }
        }
    }

    /// The plan of a parallel solve, when the factor is large enough
    /// ([`LdltSettings::parallel_solve_entries`]) and there are threads.
    fn parallel_plan(&self) -> Option<&SolvePlan> {
        self.plan.as_ref().filter(|p| {
            p.groups.len() > 1
                && self.threads() > 1
                && self.values.len() >= self.settings.parallel_solve_entries
        })
    }

    /// `x <- (Q L D L^T Q^T)^-1 x` in the symbolic (permuted) numbering, for
    /// the right-hand sides stored one after another in `x`. Each column of
    /// a panel is read once for all of them (a solve is memory-bound: two
    /// right-hand sides cost little more than one). On large factors with
    /// more than one thread, the independent subtrees of the [`SolvePlan`]
    /// run in parallel.
    fn solve_permuted(&self, x: &mut [f64], tmp: &mut Vec<f64>) {
        let f = self.factor.as_ref().expect("analysed");
        let n = f.n;
        if n == 0 {
            return;
        }
        let rhs = Rhs {
            ptr: SharedPtr(x.as_mut_ptr()),
            n,
            k: x.len() / n,
        };
        let k = rhs.k;
        let panels = PanelSolve {
            f,
            values: &self.values,
            lperm: &self.pivots.lperm,
        };
        let plan = self.parallel_plan();
        // SAFETY (all blocks below): the panel steps write only their own
        // columns, the rows their plan lets them, or their own buffer.
        // forward: y_J = L_JJ^-1 Q_s x_J, x_R -= L_RJ y_J
        match plan {
            Some(plan) => {
                let accs = plan.forward_tasks(&f.begin, k, |s, own_end, acc, t0, tmp| unsafe {
                    panels.forward(s, rhs, own_end, acc, t0, tmp)
                });
                for (ti, acc) in &accs {
                    let (t0, t1) = plan.top_columns(&f.begin, plan.tasks[*ti].top);
                    for r in 0..k {
                        let len = t1 - t0;
                        for (i, a) in acc[r * len..(r + 1) * len].iter().enumerate() {
                            unsafe { *rhs.at(r, t0 + i) -= a };
                        }
                    }
                }
                for &(lo, hi) in &plan.tops {
                    for s in lo..=hi {
                        unsafe { panels.forward(s, rhs, n, &mut [], 0, tmp) };
                    }
                }
            }
            None => {
                for s in 0..f.n_panels() {
                    unsafe { panels.forward(s, rhs, n, &mut [], 0, tmp) };
                }
            }
        }
        // y <- D^-1 y
        let piv = &self.pivots;
        for r in 0..k {
            let x = unsafe { rhs.range(r, 0, n) };
            let mut i = 0;
            while i < n {
                if piv.kind[i] == FIRST {
                    let (a, b, c) = (piv.diag[i], piv.sub[i], piv.diag[i + 1]);
                    let det = a * c - b * b;
                    let (u, v) = (x[i], x[i + 1]);
                    x[i] = (c * u - b * v) / det;
                    x[i + 1] = (a * v - b * u) / det;
                    i += 2;
                } else {
                    x[i] /= piv.diag[i];
                    i += 1;
                }
            }
        }
        // backward: x_J = Q_s^T L_JJ^-T (y_J - L_RJ^T x_R)
        match plan {
            Some(plan) => {
                for &(lo, hi) in plan.tops.iter().rev() {
                    for s in (lo..=hi).rev() {
                        unsafe { panels.backward(s, rhs, tmp) };
                    }
                }
                plan.backward_tasks(|s, tmp| unsafe { panels.backward(s, rhs, tmp) });
            }
            None => {
                for s in (0..f.n_panels()).rev() {
                    unsafe { panels.backward(s, rhs, tmp) };
                }
            }
        }
    }

    /// Residual check and iterative refinement of one solution `x` of `A x
    /// = rhs`, whose residual `rhs - A x` is `r` (see the module docs), with
    /// the warnings and errors of a solve; on error `x` is left as `rhs`.
    fn refine(
        &mut self,
        matrix: &SymmetricCsc,
        x: &mut [f64],
        rhs: &[f64],
        mut r: Vec<f64>,
        work: &mut Vec<f64>,
        tmp: &mut Vec<f64>,
    ) -> Result<(), SolverError> {
        let n = x.len();
        let bnorm = norm2(rhs);
        if bnorm == 0.0 {
            x.fill(0.0);
            self.report.residual = 0.0;
            self.report.refinement_steps = 0;
            return Ok(());
        }
        let mut rel = norm2(&r) / bnorm;
        let perturbed = self.stats.perturbed_pivots;
        let max_steps = if perturbed > 0 {
            self.settings.max_refinements.max(10)
        } else {
            self.settings.max_refinements
        };
        let mut steps = 0;
        if rel.is_finite() && rel > self.settings.refine_tol && max_steps > 0 {
            let (mut trial, mut r2) = (vec![0.0; n], vec![0.0; n]);
            while rel.is_finite() && rel > self.settings.refine_tol && steps < max_steps {
                self.apply_inverse(&mut r, work, tmp);
                for ((t, bi), d) in trial.iter_mut().zip(x.iter()).zip(&r) {
                    *t = bi + d;
                }
                let rel2 = residual(matrix, &trial, rhs, &mut r2) / bnorm;
                steps += 1;
                if rel2.is_nan() || rel2 >= rel {
                    break;
                }
                x.copy_from_slice(&trial);
                std::mem::swap(&mut r, &mut r2);
                rel = rel2;
            }
        }
        self.stats.refinement_steps = steps;
        self.report.refinement_steps = steps;
        self.report.residual = rel;
        if !rel.is_finite() || x.iter().any(|v| !v.is_finite()) {
            x.copy_from_slice(rhs);
            return Err(SolverError::NonFinite {
                method: "ldlt solve".into(),
            });
        }
        if rel > self.settings.warn_tol {
            let st = &self.stats;
            if perturbed > 0 || st.min_pivot_ratio < self.settings.pivot_warn {
                x.copy_from_slice(rhs);
                return Err(SolverError::NotPositiveDefinite {
                    detail: format!(
                        ": ldlt: the matrix is numerically singular: {perturbed} pivot(s) below {:.1e} * ||A||_inf were perturbed, smallest other pivot |eigenvalue| / ||A||_inf = {:.3e} (||A||_inf = {:.3e}), and iterative refinement stalled at relative residual {rel:.3e} after {steps} steps (warn_tol {:.1e})",
                        self.settings.tiny_pivot, st.min_pivot_ratio, st.matrix_norm_inf, self.settings.warn_tol
                    ),
                });
            }
            let w = format!(
                "ldlt: direct solve lost digits: residual {rel:.3e} after {steps} refinement steps (warn_tol {:.1e}); smallest pivot |eigenvalue| / ||A||_inf = {:.3e}: the matrix is ill-conditioned or nearly singular",
                self.settings.warn_tol, st.min_pivot_ratio
            );
            self.push_warning(w);
        }
        Ok(())
    }

    /// The matrix entries of a numeric factorisation, in one pass: with
    /// `incremental` (a previous factorisation of this pattern exists), the
    /// entries that changed since it are checked for finiteness, copied
    /// into `kept`, their panels marked in `dirty` and the row sums of
    /// `|A|` updated with them; otherwise every entry is new (checked,
    /// copied, row sums computed afresh).
    fn take_entries(
        &mut self,
        matrix: &SymmetricCsc,
        kept: &mut Vec<f64>,
        incremental: bool,
    ) -> Result<(), SolverError> {
        let f = self.factor.as_ref().expect("analysed");
        let index = self.scatter_index.as_ref().expect("built above");
        if incremental {
            let changed = changed_entries(matrix, kept);
            self.dirty.clear();
            self.dirty.resize(f.n_panels(), false);
            for &(p, i, j, delta) in &changed {
                if !matrix.values[p].is_finite() {
                    return Err(non_finite_entry(matrix, p, i, j));
                }
                self.dirty[index.panel[p] as usize] = true;
                self.row_sums[i] += delta;
                if i != j {
                    self.row_sums[j] += delta;
                }
            }
        } else {
            if let Some(p) = matrix.values.par_iter().position_first(|v| !v.is_finite()) {
                let j = matrix.col_ptr.partition_point(|&c| c <= p) - 1;
                return Err(non_finite_entry(matrix, p, matrix.row_idx[p], j));
            }
            self.row_sums = symmetric_row_sums(matrix);
            kept.clear();
            kept.extend_from_slice(&matrix.values);
        }
        Ok(())
    }

    /// Checks and statistics of the numeric factorisation just done
    /// (`partial`: only the panels of `dirty_list` were refactorised): a
    /// pivot or multiplier that is not finite is an error; the pivot
    /// statistics (inertia, smallest pivot, growth) are computed, and
    /// perturbed pivots or a near-singular matrix give a warning.
    fn check_factor(
        &mut self,
        n: usize,
        partial: bool,
        rule: PivotRule,
    ) -> Result<(), SolverError> {
        let f = self.factor.as_ref().expect("analysed");
        if let Some(k) = self.pivots.diag.iter().position(|v| !v.is_finite()) {
            return Err(SolverError::NonFinite {
                method: format!(
                    "ldlt factorisation: pivot {} at elimination step {k} of {n} (about equation {})",
                    self.pivots.diag[k], self.perm[k]
                ),
            });
        }
        // largest multiplier of each refactorised panel (not finite: the
        // factor overflowed); the kept panels keep theirs
        self.panel_max_multiplier.resize(f.n_panels(), 0.0);
        let panel_max = |s: usize| max_multiplier(f, &self.values, s);
        if partial {
            let maxima: Vec<f64> = self
                .dirty_list
                .par_iter()
                .map(|&s| panel_max(s as usize))
                .collect();
            for (&s, m) in self.dirty_list.iter().zip(maxima) {
                self.panel_max_multiplier[s as usize] = m;
            }
        } else {
            self.panel_max_multiplier
                .par_iter_mut()
                .enumerate()
                .for_each(|(s, m)| *m = panel_max(s));
        }
        if self.panel_max_multiplier.iter().any(|m| !m.is_finite()) {
            return Err(SolverError::NonFinite {
                method: "ldlt factorisation: the factor overflowed".into(),
            });
        }
        self.pivot_statistics();
        let st = &self.stats;
        tracing::info!(
            negative_pivots = st.negative_pivots,
            pivots_2x2 = st.pivots_2x2,
            perturbed = st.perturbed_pivots,
            min_pivot_ratio = st.min_pivot_ratio,
            growth = st.growth,
            "ldlt: numeric factorisation"
        );
        if st.perturbed_pivots > 0 {
            let w = format!(
                "ldlt: {} pivot(s) below {:.1e} * ||A||_inf = {:.3e} within their panel (restricted pivoting) were replaced by +-{:.3e}; the inertia ({} negative pivots) may be unreliable and the solution relies on iterative refinement",
                st.perturbed_pivots,
                self.settings.tiny_pivot,
                rule.tiny,
                rule.perturb,
                st.negative_pivots
            );
            self.push_warning(w);
        }
        if self.stats.min_pivot_ratio < self.settings.pivot_warn {
            let w = format!(
                "ldlt: near-singular matrix: smallest pivot |eigenvalue| / ||A||_inf = {:.3e} (||A||_inf = {:.3e}); expect to lose about {:.0} digits",
                self.stats.min_pivot_ratio,
                self.stats.matrix_norm_inf,
                -self.stats.min_pivot_ratio.log10()
            );
            self.push_warning(w);
        }
        Ok(())
    }

    /// Inertia and pivot statistics of the current `D`.
    fn pivot_statistics(&mut self) {
        let piv = &self.pivots;
        let (mut neg, mut n1, mut n2, mut pert) = (0, 0, 0, 0);
        let mut min_eig = f64::INFINITY;
        let mut max_eig = 0.0f64;
        let mut k = 0;
        while k < piv.diag.len() {
            if piv.kind[k] == FIRST {
                let (a, b, c) = (piv.diag[k], piv.sub[k], piv.diag[k + 1]);
                let det = a * c - b * b;
                let tr = a + c;
                if det < 0.0 {
                    neg += 1;
                } else if tr < 0.0 {
                    neg += 2;
                }
                // eigenvalues m +- r: the smaller magnitude is |det| / (|m| + r)
                let (m, r) = (0.5 * tr, (0.5 * (a - c)).hypot(b));
                min_eig = min_eig.min(det.abs() / (m.abs() + r));
                max_eig = max_eig.max(m.abs() + r);
                n2 += 1;
                k += 2;
            } else {
                let d = piv.diag[k];
                if d < 0.0 {
                    neg += 1;
                }
                if piv.kind[k] & PERTURBED != 0 {
                    pert += 1;
                } else {
                    min_eig = min_eig.min(d.abs());
                }
                max_eig = max_eig.max(d.abs());
                n1 += 1;
                k += 1;
            }
        }
        self.stats.negative_pivots = neg;
        self.stats.pivots_1x1 = n1;
        self.stats.pivots_2x2 = n2;
        self.stats.perturbed_pivots = pert;
        self.stats.min_pivot_ratio = min_eig / self.stats.matrix_norm_inf;
        self.stats.max_pivot = max_eig;
        let max_l = self
            .panel_max_multiplier
            .iter()
            .fold(0.0f64, |m, &v| m.max(v));
        self.stats.max_multiplier = max_l;
        self.stats.growth = max_l.max(1.0).powi(2) * max_eig / self.stats.matrix_norm_inf;
    }

    /// A factor whose solves are checked even when the caller checks its
    /// own residual ([`ResidualCheck::Auto`]).
    fn doubtful(&self) -> bool {
        let st = &self.stats;
        st.perturbed_pivots > 0
            || !(st.min_pivot_ratio >= self.settings.pivot_warn)
            || !(st.growth <= UNCHECKED_GROWTH_LIMIT)
    }
}

impl LdltSettings {
    /// Range checks of the parameters.
    fn check(&self) -> Result<(), String> {
        let a = self.pivot_threshold;
        if !(a > 0.0 && a < 1.0) {
            return Err(format!("pivot_threshold = {a} must lie in (0, 1)"));
        }
        if !(self.tiny_pivot >= 0.0 && self.tiny_pivot < 1.0) {
            return Err(format!(
                "tiny_pivot = {} must lie in [0, 1)",
                self.tiny_pivot
            ));
        }
        if !(self.perturbation > 0.0 && self.perturbation < 1.0) {
            return Err(format!(
                "perturbation = {} must lie in (0, 1)",
                self.perturbation
            ));
        }
        Ok(())
    }
}

/// Symmetric interchange of rows/columns `p < q` of the lower triangle of
/// the `w x w` block stored column-major with leading dimension `m`
/// (including the finished columns of `L` to the left, as in LAPACK).
fn swap_symmetric(a: &mut [f64], m: usize, w: usize, p: usize, q: usize) {
    debug_assert!(p < q && q < w);
    for j in 0..p {
        a.swap(p + j * m, q + j * m);
    }
    for i in q + 1..w {
        a.swap(i + p * m, i + q * m);
    }
    a.swap(p + p * m, q + q * m);
    for t in p + 1..q {
        a.swap(t + p * m, q + t * m);
    }
}

/// Dense Bunch-Kaufman `Q S Q^T = L D L^T` of the `w x w` lower triangle at
/// the top of a panel (column-major, leading dimension `m`), right-looking
/// and unblocked: `L` (unit, implicit diagonal) overwrites the strict lower
/// triangle, `D` goes to `diag`/`sub`/`kind`, `Q` to `lperm`.
#[allow(clippy::too_many_arguments)]
fn bunch_kaufman(
    a: &mut [f64],
    m: usize,
    w: usize,
    rule: PivotRule,
    diag: &mut [f64],
    sub: &mut [f64],
    kind: &mut [u8],
    lperm: &mut [u32],
) {
    for (i, p) in lperm.iter_mut().enumerate() {
        *p = i as u32;
    }
    let alpha = rule.alpha;
    let mut k = 0;
    while k < w {
        let akk = a[k + k * m].abs();
        let (mut imax, mut colmax) = (k, 0.0f64);
        for i in k + 1..w {
            let v = a[i + k * m].abs();
            if v > colmax {
                colmax = v;
                imax = i;
            }
        }
        let mut two = false;
        let tiny = akk.max(colmax) <= rule.tiny;
        if !tiny && akk < alpha * colmax {
            let mut rowmax = 0.0f64;
            for j in k..imax {
                rowmax = rowmax.max(a[imax + j * m].abs());
            }
            for i in imax + 1..w {
                rowmax = rowmax.max(a[i + imax * m].abs());
            }
            if akk * rowmax >= alpha * colmax * colmax {
                // 1x1 pivot a_kk
            } else if a[imax + imax * m].abs() >= alpha * rowmax {
                swap_symmetric(a, m, w, k, imax);
                lperm.swap(k, imax);
            } else {
                if imax != k + 1 {
                    swap_symmetric(a, m, w, k + 1, imax);
                    lperm.swap(k + 1, imax);
                }
                two = true;
            }
        }
        if !two {
            let mut d = a[k + k * m];
            if tiny {
                d = if d < 0.0 { -rule.perturb } else { rule.perturb };
            }
            a[k + k * m] = d;
            diag[k] = d;
            sub[k] = 0.0;
            kind[k] = if tiny { ONE | PERTURBED } else { ONE };
            let (left, right) = a.split_at_mut((k + 1) * m);
            let ck = &mut left[k * m..];
            let inv = 1.0 / d;
            for v in &mut ck[k + 1..w] {
                *v *= inv;
            }
            for j in k + 1..w {
                let t = ck[j] * d;
                if t == 0.0 {
                    continue;
                }
                let cj = &mut right[(j - k - 1) * m..(j - k) * m];
                for (x, l) in cj[j..w].iter_mut().zip(&ck[j..w]) {
                    *x -= l * t;
                }
            }
            k += 1;
        } else {
            let (d11, d21, d22) = (a[k + k * m], a[k + 1 + k * m], a[k + 1 + (k + 1) * m]);
            let det = d11 * d22 - d21 * d21;
            let (i11, i21, i22) = (d22 / det, -d21 / det, d11 / det);
            let (left, right) = a.split_at_mut((k + 2) * m);
            let (ck, ck1) = left[k * m..].split_at_mut(m);
            for i in k + 2..w {
                let (u, v) = (ck[i], ck1[i]);
                ck[i] = u * i11 + v * i21;
                ck1[i] = u * i21 + v * i22;
            }
            for j in k + 2..w {
                let (l0, l1) = (ck[j], ck1[j]);
                let (u, v) = (d11 * l0 + d21 * l1, d21 * l0 + d22 * l1);
                let cj = &mut right[(j - k - 2) * m..(j - k - 1) * m];
                for ((x, p), q) in cj[j..w].iter_mut().zip(&ck[j..w]).zip(&ck1[j..w]) {
                    *x -= p * u + q * v;
                }
            }
            ck[k + 1] = 0.0;
            diag[k] = d11;
            diag[k + 1] = d22;
            sub[k] = d21;
            sub[k + 1] = 0.0;
            kind[k] = FIRST;
            kind[k + 1] = SECOND;
            k += 2;
        }
    }
}

/// `out = L[J, K_d] D_d` for the columns of panel `d` (`begin..`), the
/// block-diagonal pivots read from `piv`.
fn scale_by_d(piv: PivotPtrs, col0: usize, rhs: MatRef<'_, f64>, mut out: MatMut<'_, f64>) {
    let wd = rhs.ncols();
    // SAFETY: panel d is finished; its pivots are only read.
    let (diag, sub, kind) = unsafe {
        (
            std::slice::from_raw_parts(piv.diag.get().add(col0) as *const f64, wd),
            std::slice::from_raw_parts(piv.sub.get().add(col0) as *const f64, wd),
            std::slice::from_raw_parts(piv.kind.get().add(col0) as *const u8, wd),
        )
    };
    let col = |c: usize| rhs.col(c).try_as_col_major().unwrap().as_slice();
    let mut c = 0;
    while c < wd {
        if kind[c] == FIRST {
            let (a, b, d) = (diag[c], sub[c], diag[c + 1]);
            let (u, v) = (col(c), col(c + 1));
            let (mut o0, mut o1) = out.rb_mut().split_at_col_mut(c + 1);
            let o0 = o0
                .rb_mut()
                .col_mut(c)
                .try_as_col_major_mut()
                .unwrap()
                .as_slice_mut();
            let o1 = o1
                .rb_mut()
                .col_mut(0)
                .try_as_col_major_mut()
                .unwrap()
                .as_slice_mut();
            for i in 0..u.len() {
                o0[i] = u[i] * a + v[i] * b;
                o1[i] = u[i] * b + v[i] * d;
            }
            c += 2;
        } else {
            let a = diag[c];
            let o = out
                .rb_mut()
                .col_mut(c)
                .try_as_col_major_mut()
                .unwrap()
                .as_slice_mut();
            for (o, u) in o.iter_mut().zip(col(c)) {
                *o = u * a;
            }
            c += 1;
        }
    }
}

/// `k` right-hand sides of length `n` stored one after another, shared by
/// the tasks of a solve (each writes its own rows).
#[derive(Clone, Copy)]
struct Rhs {
    ptr: SharedPtr<f64>,
    n: usize,
    k: usize,
}

impl Rhs {
    /// Entry `i` of right-hand side `r`.
    #[inline]
    unsafe fn at(self, r: usize, i: usize) -> *mut f64 {
        self.ptr.get().add(r * self.n + i)
    }

    /// Entries `i0..i1` of right-hand side `r`; the caller guarantees that
    /// no other task touches them meanwhile.
    #[inline]
    unsafe fn range<'a>(self, r: usize, i0: usize, i1: usize) -> &'a mut [f64] {
        std::slice::from_raw_parts_mut(self.at(r, i0), i1 - i0)
    }
}

/// The panel steps of the triangular solves with `L Q` (hand-written loops
/// over a panel's columns: most panels of a finite-element factor are a
/// few columns wide, where a call into a dense kernel costs more than its
/// arithmetic).
struct PanelSolve<'a> {
    f: &'a PanelFactor,
    values: &'a [f64],
    lperm: &'a [u32],
}

impl PanelSolve<'_> {
    /// Columns `b..e`, rows `m` (diagonal block and below), pattern and
    /// values of panel `s`.
    #[inline]
    fn panel(&self, s: usize) -> (usize, usize, usize, &[u32], &[f64]) {
        let f = self.f;
        let (b, e) = (f.begin[s], f.begin[s + 1]);
        let pat = f.pattern(s);
        let m = (e - b) + pat.len();
        let v = &self.values[f.val_ptr[s]..f.val_ptr[s] + m * (e - b)];
        (b, e, m, pat, v)
    }

    /// Forward step of panel `s`: `y_J = L_JJ^-1 Q_s x_J`, then `x_R -= L_RJ
    /// y_J`, where a row `>= own_end` is subtracted later: its update is
    /// added to `acc` (rows from `acc_begin` on, `acc.len() / k` per
    /// right-hand side) instead.
    ///
    /// # Safety
    /// No other task may touch the columns of `s` or the rows below
    /// `own_end` that it updates.
    unsafe fn forward(
        &self,
        s: usize,
        x: Rhs,
        own_end: usize,
        acc: &mut [f64],
        acc_begin: usize,
        tmp: &mut Vec<f64>,
    ) {
        let (b, e, m, pat, v) = self.panel(s);
        let w = e - b;
        let k = x.k;
        let lp = &self.lperm[b..e];
        for r in 0..k {
            let xj = x.range(r, b, e);
            tmp.clear();
            tmp.extend(lp.iter().map(|&i| xj[i as usize]));
            xj.copy_from_slice(tmp);
        }
        for c in 0..w {
            let col = &v[c * m + c + 1..c * m + w];
            for r in 0..k {
                let xj = x.range(r, b, e);
                let xc = xj[c];
                if xc != 0.0 {
                    for (xi, l) in xj[c + 1..].iter_mut().zip(col) {
                        *xi -= l * xc;
                    }
                }
            }
        }
        let plen = pat.len();
        if plen == 0 {
            return;
        }
        tmp.clear();
        tmp.resize(k * plen, 0.0);
        let below = |c: usize| &v[c * m + w..c * m + m];
        // four columns at a time: the buffer is read and written once for
        // four columns of L
        let mut c = 0;
        while c + 4 <= w {
            let cols = [below(c), below(c + 1), below(c + 2), below(c + 3)];
            for r in 0..k {
                let a = [0, 1, 2, 3].map(|j| *x.at(r, b + c + j));
                if a != [0.0; 4] {
                    axpy4(&mut tmp[r * plen..(r + 1) * plen], cols, a);
                }
            }
            c += 4;
        }
        for c in c..w {
            let col = below(c);
            for r in 0..k {
                let xc = *x.at(r, b + c);
                if xc != 0.0 {
                    for (t, l) in tmp[r * plen..(r + 1) * plen].iter_mut().zip(col) {
                        *t += l * xc;
                    }
                }
            }
        }
        let alen = acc.len() / k.max(1);
        for r in 0..k {
            for (&g, &t) in pat.iter().zip(&tmp[r * plen..(r + 1) * plen]) {
                let g = g as usize;
                if g < own_end {
                    *x.at(r, g) -= t;
                } else {
                    debug_assert!(g >= acc_begin && g - acc_begin < alen);
                    acc[r * alen + g - acc_begin] += t;
                }
            }
        }
    }

    /// Backward step of panel `s`: `x_J = Q_s^T L_JJ^-T (y_J - L_RJ^T x_R)`.
    ///
    /// # Safety
    /// No other task may touch the columns of `s`, or write the rows of its
    /// pattern, meanwhile.
    unsafe fn backward(&self, s: usize, x: Rhs, tmp: &mut Vec<f64>) {
        let (b, e, m, pat, v) = self.panel(s);
        let w = e - b;
        let k = x.k;
        let plen = pat.len();
        if plen > 0 {
            tmp.clear();
            for r in 0..k {
                tmp.extend(pat.iter().map(|&g| *x.at(r, g as usize)));
            }
            let below = |c: usize| &v[c * m + w..c * m + m];
            let mut c = 0;
            while c + 4 <= w {
                let cols = [below(c), below(c + 1), below(c + 2), below(c + 3)];
                for r in 0..k {
                    let d = dot4(cols, &tmp[r * plen..(r + 1) * plen]);
                    for (j, dj) in d.iter().enumerate() {
                        *x.at(r, b + c + j) -= dj;
                    }
                }
                c += 4;
            }
            for c in c..w {
                for r in 0..k {
                    *x.at(r, b + c) -= dot_lanes(below(c), &tmp[r * plen..(r + 1) * plen]);
                }
            }
        }
        for c in (0..w).rev() {
            let col = &v[c * m + c + 1..c * m + w];
            for r in 0..k {
                let xj = x.range(r, b, e);
                xj[c] -= dot_lanes(col, &xj[c + 1..]);
            }
        }
        let lp = &self.lperm[b..e];
        for r in 0..k {
            let xj = x.range(r, b, e);
            tmp.clear();
            tmp.extend_from_slice(xj);
            for (i, &li) in lp.iter().enumerate() {
                xj[li as usize] = tmp[i];
            }
        }
    }
}

/// `t += sum_j a_j cols_j` over four columns (each at least as long as
/// `t`).
#[inline]
fn axpy4(t: &mut [f64], cols: [&[f64]; 4], a: [f64; 4]) {
    let n = t.len();
    let [c0, c1, c2, c3] = cols.map(|c| &c[..n]);
    for ((((ti, l0), l1), l2), l3) in t.iter_mut().zip(c0).zip(c1).zip(c2).zip(c3) {
        *ti += l0 * a[0] + l1 * a[1] + l2 * a[2] + l3 * a[3];
    }
}

/// The four dot products `cols_j . t` (each column at least as long as
/// `t`), each in four interleaved partial sums as in [`dot_lanes`]: `t` is
/// read once for the four.
#[inline]
fn dot4(cols: [&[f64]; 4], t: &[f64]) -> [f64; 4] {
    let n = t.len();
    let [c0, c1, c2, c3] = cols.map(|c| &c[..n]);
    let mut acc = [[0.0f64; 4]; 4];
    for ((((tc, x0), x1), x2), x3) in t
        .chunks_exact(4)
        .zip(c0.chunks_exact(4))
        .zip(c1.chunks_exact(4))
        .zip(c2.chunks_exact(4))
        .zip(c3.chunks_exact(4))
    {
        for l in 0..4 {
            acc[0][l] += x0[l] * tc[l];
            acc[1][l] += x1[l] * tc[l];
            acc[2][l] += x2[l] * tc[l];
            acc[3][l] += x3[l] * tc[l];
        }
    }
    let tail = n - n % 4;
    let mut out = [0.0; 4];
    for (j, c) in [c0, c1, c2, c3].iter().enumerate() {
        let a = &acc[j];
        out[j] = (a[0] + a[2]) + (a[1] + a[3]);
        for i in tail..n {
            out[j] += c[i] * t[i];
        }
    }
    out
}

/// `sum_i a_i b_i` over the shorter length, in four interleaved partial
/// sums (which the compiler vectorises; a single running sum it cannot).
#[inline]
fn dot_lanes(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len().min(b.len());
    let (a, b) = (&a[..n], &b[..n]);
    let mut acc = [0.0f64; 4];
    let (ca, cb) = (a.chunks_exact(4), b.chunks_exact(4));
    let (ra, rb) = (ca.remainder(), cb.remainder());
    for (x, y) in ca.zip(cb) {
        for l in 0..4 {
            acc[l] += x[l] * y[l];
        }
    }
    let mut tail = 0.0;
    for (x, y) in ra.iter().zip(rb) {
        tail += x * y;
    }
    (acc[0] + acc[2]) + (acc[1] + acc[3]) + tail
}

/// The entries of `a` whose value differs (bit for bit) from `kept`, as
/// `(entry, row, column, |new| - |old|)`; `kept` receives the new values.
/// Columns in parallel.
fn changed_entries(a: &SymmetricCsc, kept: &mut [f64]) -> Vec<(usize, usize, usize, f64)> {
    let ptr = SharedPtr(kept.as_mut_ptr());
    (0..a.n)
        .into_par_iter()
        .with_min_len(1024)
        .fold(Vec::new, |mut out, j| {
            for p in a.col_ptr[j]..a.col_ptr[j + 1] {
                let v = a.values[p];
                // SAFETY: entry p belongs to column j, visited by one task.
                let old = unsafe { &mut *ptr.get().add(p) };
                if v.to_bits() != old.to_bits() {
                    out.push((p, a.row_idx[p], j, v.abs() - old.abs()));
                    *old = v;
                }
            }
            out
        })
        .reduce(Vec::new, |mut x, mut y| {
            if x.len() < y.len() {
                std::mem::swap(&mut x, &mut y);
            }
            x.extend_from_slice(&y);
            x
        })
}

/// Addresses and sizes of the pattern arrays of `a`: a matrix whose
/// pattern was checked at a factorisation and that is passed again to
/// the solves after it is known by them.
fn storage_id(a: &SymmetricCsc) -> (usize, usize, usize, usize) {
    (
        a.col_ptr.as_ptr() as usize,
        a.row_idx.as_ptr() as usize,
        a.n,
        a.row_idx.len(),
    )
}

/// The error for a non-finite matrix entry `p` at `(i, j)`.
fn non_finite_entry(a: &SymmetricCsc, p: usize, i: usize, j: usize) -> SolverError {
    SolverError::NonFinite {
        method: format!(
            "ldlt factorisation: the matrix holds {} at entry ({i}, {j})",
            a.values[p]
        ),
    }
}

/// Update, Bunch-Kaufman and below-block solve of panel `s` (see the
/// module docs).
/// Largest `|l_ij|` of panel `s` (its strict lower trapezoid; the diagonal
/// and upper triangle of its block hold no part of `L`); NaN or infinite
/// when an entry is.
fn max_multiplier(f: &PanelFactor, values: &[f64], s: usize) -> f64 {
    let (b, e) = (f.begin[s], f.begin[s + 1]);
    let w = e - b;
    let m = w + f.pattern(s).len();
    let panel = &values[f.val_ptr[s]..f.val_ptr[s] + m * w];
    (0..w).fold(0.0, |max, j| {
        panel[j * m + j + 1..(j + 1) * m]
            .iter()
            .fold(max, |a, v| nan_max(a, v.abs()))
    })
}

fn factor_panel(
    f: &PanelFactor,
    s: usize,
    ptr: SharedPtr<f64>,
    piv: PivotPtrs,
    threads: usize,
    rule: PivotRule,
    scratch: &mut Scratch,
) {
    let (b, e) = (f.begin[s], f.begin[s + 1]);
    let w = e - b;
    let r = f.pattern(s).len();
    let m = w + r;
    let scale = |d: usize, rhs: MatRef<'_, f64>, out: MatMut<'_, f64>| {
        scale_by_d(piv, f.begin[d], rhs, out)
    };
    f.update_panel(
        s,
        ptr,
        threads,
        &mut scratch.tmp,
        &mut scratch.wbuf,
        Some(&scale),
    );
    // SAFETY: panel s and its pivots are written only here.
    let (ls, diag, sub, kind, lperm) = unsafe {
        (
            std::slice::from_raw_parts_mut(ptr.get().add(f.val_ptr[s]), m * w),
            std::slice::from_raw_parts_mut(piv.diag.get().add(b), w),
            std::slice::from_raw_parts_mut(piv.sub.get().add(b), w),
            std::slice::from_raw_parts_mut(piv.kind.get().add(b), w),
            std::slice::from_raw_parts_mut(piv.lperm.get().add(b), w),
        )
    };
    bunch_kaufman(ls, m, w, rule, diag, sub, kind, lperm);
    if r == 0 {
        return;
    }
    // S_RJ Q^T: column i <- column lperm[i]
    if lperm.iter().enumerate().any(|(i, &p)| p as usize != i) {
        let cols = &mut scratch.cols;
        cols.clear();
        for j in 0..w {
            cols.extend_from_slice(&ls[j * m + w..(j + 1) * m]);
        }
        for (i, &p) in lperm.iter().enumerate() {
            let p = p as usize;
            ls[i * m + w..(i + 1) * m].copy_from_slice(&cols[p * r..(p + 1) * r]);
        }
    }
    let big = threads > 1 && m * w >= 128 * 128;
    let par = if big { Par::rayon(threads) } else { Par::Seq };
    let mut panel = MatMut::from_column_major_slice_mut(ls, m, w);
    let (top, mut bot) = panel.rb_mut().split_at_row_mut(w);
    // X L_JJ^T = S_RJ Q^T
    tri::solve_unit_lower_triangular_in_place(top.rb(), bot.rb_mut().transpose_mut(), par);
    // L_RJ = X D^-1
    let mut c = 0;
    while c < w {
        if kind[c] == FIRST {
            let (a, bb, d) = (diag[c], sub[c], diag[c + 1]);
            let det = a * d - bb * bb;
            let (i11, i21, i22) = (d / det, -bb / det, a / det);
            for i in 0..r {
                let (u, v) = (bot[(i, c)], bot[(i, c + 1)]);
                bot[(i, c)] = u * i11 + v * i21;
                bot[(i, c + 1)] = u * i21 + v * i22;
            }
            c += 2;
        } else {
            let inv = 1.0 / diag[c];
            for i in 0..r {
                bot[(i, c)] *= inv;
            }
            c += 1;
        }
    }
}

impl LinearSolver for LdltSolver {
    fn key(&self) -> &'static str {
        "ldlt"
    }

    fn accepts(&self, kind: MatrixKind) -> bool {
        matches!(
            kind,
            MatrixKind::SymmetricPositiveDefinite | MatrixKind::SymmetricIndefinite
        )
    }

    fn analyze(
        &mut self,
        matrix: &SymmetricCsc,
        coords: Option<&[[f64; 3]]>,
    ) -> Result<(), SolverError> {
        let t0 = Instant::now();
        validate(matrix)?;
        symmetric_only(matrix, "ldlt")?;
        self.settings
            .check()
            .map_err(|m| SolverError::Usage(format!("ldlt: {m}")))?;
        self.factored = false;
        // partial refactorisation redoes one path of a dissection tree
        let nd_weight = if self.settings.partial_refactor {
            ND_WEIGHT_PARTIAL
        } else {
            1.0
        };
        let a = crate::supernodal::analyze(
            self.settings.ordering,
            matrix,
            coords,
            nd_weight,
            self.dissection.take().as_ref(),
        )?;
        self.stats.dissections_reused += usize::from(a.dissection_reused);
        self.stats.factor_nonzeros = a.factor.nonzeros();
        self.stats.ordering = a.kind.name();
        self.stats.analyze_count += 1;
        self.report.notes.retain(|n| !n.starts_with("ordering "));
        self.report.notes.push(a.ordering_note.clone());
        self.report.ordering_candidates = a
            .candidates
            .iter()
            .map(|(k, e)| (k.name().to_string(), e.nonzeros))
            .collect();
        self.total_work = a.factor.work.iter().sum();
        self.factor = Some(a.factor);
        self.perm = a.perm;
        self.perm_inv = a.perm_inv;
        self.values = Vec::new();
        self.pivots = Pivots::default();
        self.scatter_index = None;
        self.row_sums = Vec::new();
        self.plan = self.factor.as_ref().and_then(|f| f.solve_plan());
        let threads = self.threads();
        if let Some(plan) = self.plan.as_mut() {
            plan.balance(threads);
        }
        self.factored_matrix = Vec::new();
        self.factored_rule = None;
        self.pattern = Some(Pattern::of(matrix));
        let secs = t0.elapsed().as_secs_f64();
        self.report.analyze_seconds += secs;
        self.report.factor_nonzeros = self.stats.factor_nonzeros;
        self.report.ordering = self.stats.ordering.into();
        let f = self.factor.as_ref().expect("set above");
        tracing::info!(
            n = matrix.n,
            nnz = matrix.nnz(),
            panels = f.n_panels(),
            ordering = self.stats.ordering,
            ordering_seconds = a.ordering_seconds,
            analyze_seconds = secs,
            factor_nonzeros = self.stats.factor_nonzeros,
            "ldlt: symbolic analysis"
        );
        Ok(())
    }

    fn offer_dissection(&mut self, dissection: PrecomputedDissection) {
        self.dissection = Some(dissection);
    }

    fn factorize(&mut self, matrix: &SymmetricCsc) -> Result<(), SolverError> {
        symmetric_only(matrix, "ldlt")?;
        let t0 = Instant::now();
        let Some(pattern) = &self.pattern else {
            return Err(SolverError::Usage(
                "ldlt: factorize called before analyze".into(),
            ));
        };
        pattern.check(matrix, "ldlt factorize")?;
        self.factored = false;
        self.factored_id = None;
        self.report.warnings.clear();
        self.report.negative_pivots = None;
        // the previous factor is about to be overwritten: until this one
        // succeeds, the next factorisation must be complete
        let mut kept = std::mem::take(&mut self.factored_matrix);
        let previous_rule = self.factored_rule.take();
        let previous_norm = self.stats.matrix_norm_inf;
        let threads = self.threads();
        let f = self.factor.as_ref().expect("analysed");
        if self.scatter_index.is_none() {
            self.scatter_index = Some(f.scatter_index(matrix, &self.perm_inv));
        }
        // without a previous factorisation of this pattern, every entry is new
        let incremental = kept.len() == matrix.values.len()
            && self.row_sums.len() == matrix.n
            && self.values.len() == f.len_val();
        self.take_entries(matrix, &mut kept, incremental)?;
        let f = self.factor.as_ref().expect("analysed");
        let index = self.scatter_index.as_ref().expect("built above");
        let norm = inf_norm(&self.row_sums);
        self.stats.matrix_norm_inf = norm;
        if norm == 0.0 && matrix.n > 0 {
            return Err(SolverError::NotPositiveDefinite {
                detail: ": ldlt: the matrix is zero (singular)".into(),
            });
        }
        let rule = PivotRule {
            alpha: self.settings.pivot_threshold,
            tiny: self.settings.tiny_pivot * norm,
            perturb: self.settings.perturbation * norm,
        };
        let mut values = std::mem::take(&mut self.values);
        // Partial refactorisation: the pivots of an unchanged panel are the
        // same under the new constants when no pivot was perturbed and the
        // smallest one is far above the new perturbation threshold.
        let same_rule = previous_rule.is_some_and(|r| {
            r == rule
                || (self.stats.perturbed_pivots == 0
                    && self.stats.min_pivot_ratio * previous_norm > 4.0 * rule.tiny)
        });
        let partial = self.settings.partial_refactor && same_rule && incremental;
        let dirty = if partial {
            // parents are numbered after their children: one pass upwards
            for s in 0..f.n_panels() {
                let p = f.parent[s];
                if self.dirty[s] && p != u32::MAX {
                    self.dirty[p as usize] = true;
                }
            }
            self.dirty_list.clear();
            self.dirty_list.extend(
                (0..f.n_panels())
                    .filter(|&s| self.dirty[s])
                    .map(|s| s as u32),
            );
            Some(&self.dirty[..])
        } else {
            None
        };
        let list = dirty.map(|_| &self.dirty_list[..]);
        f.scatter_with(&mut values, matrix, index, list);
        self.pivots.resize(matrix.n);
        let ptr = SharedPtr(values.as_mut_ptr());
        let piv = PivotPtrs {
            diag: SharedPtr(self.pivots.diag.as_mut_ptr()),
            sub: SharedPtr(self.pivots.sub.as_mut_ptr()),
            kind: SharedPtr(self.pivots.kind.as_mut_ptr()),
            lperm: SharedPtr(self.pivots.lperm.as_mut_ptr()),
        };
        let done: Result<(), std::convert::Infallible> =
            f.traverse(threads, |s, scratch: &mut Scratch| {
                if dirty.is_none_or(|d| d[s]) {
                    factor_panel(f, s, ptr, piv, threads, rule, scratch);
                }
                Ok(())
            });
        let Ok(()) = done;
        if let Some(d) = dirty {
            let redone: f64 = (0..d.len()).filter(|&s| d[s]).map(|s| f.work[s]).sum();
            self.report.partial_factorizations += 1;
            self.report.refactored_work += redone / self.total_work.max(1.0);
        }
        self.report.factorizations += 1;
        self.values = values;
        self.stats.factor_count += 1;
        self.report.factor_seconds += t0.elapsed().as_secs_f64();
        self.check_factor(matrix.n, dirty.is_some(), rule)?;
        self.report.negative_pivots = Some(self.stats.negative_pivots);
        self.factored = true;
        self.factored_matrix = kept;
        self.factored_id = Some(storage_id(matrix));
        self.factored_rule = Some(rule);
        Ok(())
    }

    fn solve_in_place(&mut self, matrix: &SymmetricCsc, b: &mut [f64]) -> Result<(), SolverError> {
        self.solve_many_in_place(matrix, b)
    }

    fn solve_many_in_place(
        &mut self,
        matrix: &SymmetricCsc,
        b: &mut [f64],
    ) -> Result<(), SolverError> {
        let t0 = Instant::now();
        if !self.factored {
            return Err(SolverError::Usage(
                "ldlt: solve called without a successful factorize".into(),
            ));
        }
        let n = self.perm.len();
        if n == 0 && b.is_empty() {
            return Ok(());
        }
        if n == 0 || b.len() % n != 0 || b.is_empty() {
            return Err(SolverError::Usage(format!(
                "ldlt: right-hand side(s) of {} entries, the matrix {n} equations",
                b.len()
            )));
        }
        // the matrix of the factorisation (same storage) was checked then
        if self.factored_id != Some(storage_id(matrix)) {
            if let Some(pattern) = &self.pattern {
                pattern.check(matrix, "ldlt solve")?;
            }
        }
        if let Some(i) = b.iter().position(|v| !v.is_finite()) {
            return Err(SolverError::NonFinite {
                method: format!(
                    "ldlt: the right-hand side holds {} at equation {}",
                    b[i],
                    i % n
                ),
            });
        }
        self.stats.solve_count += b.len() / n;
        self.stats.solve_tasks = self.parallel_plan().map_or(0, |p| p.tasks.len());
        let rhs = b.to_vec();
        let (mut work, mut tmp) = (Vec::with_capacity(b.len()), Vec::new());
        self.apply_inverse(b, &mut work, &mut tmp);
        if self.caller_checks
            && self.settings.residual_check == ResidualCheck::Auto
            && !self.doubtful()
        {
            self.stats.refinement_steps = 0;
            self.report.refinement_steps = 0;
            self.report.unchecked_solves += b.len() / n;
            self.report.solve_seconds += t0.elapsed().as_secs_f64();
            if b.iter().any(|v| !v.is_finite()) {
                b.copy_from_slice(&rhs);
                return Err(SolverError::NonFinite {
                    method: "ldlt solve".into(),
                });
            }
            return Ok(());
        }
        // the residuals of all right-hand sides in one pass over the matrix
        let mut residuals = vec![0.0; b.len()];
        matrix.mul_many(b, &mut residuals);
        for (ri, bi) in residuals.iter_mut().zip(&rhs) {
            *ri = bi - *ri;
        }
        let mut result = Ok(());
        for ((x, rhs), r0) in b.chunks_mut(n).zip(rhs.chunks(n)).zip(residuals.chunks(n)) {
            let r = self.refine(matrix, x, rhs, r0.to_vec(), &mut work, &mut tmp);
            if r.is_err() && result.is_ok() {
                result = r;
            }
        }
        self.report.solve_seconds += t0.elapsed().as_secs_f64();
        result
    }

    fn set_caller_checks_residual(&mut self, checks: bool) {
        self.caller_checks = checks;
    }

    fn report(&self) -> SolveReport {
        self.report.clone()
    }
}

inventory::submit! {
    SolverEntry {
        key: "ldlt",
        description: "sparse supernodal LDL^T for symmetric indefinite matrices (softening tangents): Bunch-Kaufman 1x1/2x2 pivoting within each panel, the ordering and symbolic analysis of cholesky, inertia (negative pivots) in the report, iterative refinement",
        params: LDLT_PARAMS,
        build: |table| Ok(Box::new(LdltSolver::from_table(table)?)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `Q^T L D L^T Q` from a dense Bunch-Kaufman factor (`w x w`).
    fn reconstruct(
        a: &[f64],
        w: usize,
        diag: &[f64],
        sub: &[f64],
        kind: &[u8],
        q: &[u32],
    ) -> Vec<f64> {
        let mut l = vec![0.0; w * w];
        let mut d = vec![0.0; w * w];
        for j in 0..w {
            l[j + j * w] = 1.0;
            for i in j + 1..w {
                l[i + j * w] = a[i + j * w];
            }
            d[j + j * w] = diag[j];
            if kind[j] == FIRST {
                d[j + 1 + j * w] = sub[j];
                d[j + (j + 1) * w] = sub[j];
            }
        }
        let mut out = vec![0.0; w * w];
        for i in 0..w {
            for j in 0..w {
                let mut s = 0.0;
                for p in 0..w {
                    for r in 0..w {
                        s += l[i + p * w] * d[p + r * w] * l[j + r * w];
                    }
                }
                // position i of the pivoted order is original q[i]
                out[q[i] as usize + q[j] as usize * w] = s;
            }
        }
        out
    }

    #[test]
    fn dense_bunch_kaufman_reconstructs() {
        for case in 0..2 {
            let w = 12;
            let mut a = vec![0.0; w * w];
            let mut orig = vec![0.0; w * w];
            for j in 0..w {
                for i in j..w {
                    let v = if i < 4 && j < 4 {
                        0.0
                    } else if case == 0 || j < 4 {
                        ((3 * i + 7 * j + 1) as f64).sin()
                    } else if i == j {
                        10.0
                    } else {
                        0.3 / (1.0 + (i - j) as f64)
                    };
                    a[i + j * w] = v;
                    orig[i + j * w] = v;
                    orig[j + i * w] = v;
                }
            }
            let (mut diag, mut sub, mut kind, mut q) =
                (vec![0.0; w], vec![0.0; w], vec![0u8; w], vec![0u32; w]);
            let rule = PivotRule {
                alpha: BUNCH_KAUFMAN_ALPHA,
                tiny: 1e-300,
                perturb: 1e-8,
            };
            bunch_kaufman(&mut a, w, w, rule, &mut diag, &mut sub, &mut kind, &mut q);
            let r = reconstruct(&a, w, &diag, &sub, &kind, &q);
            let err = r
                .iter()
                .zip(&orig)
                .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
            assert!(
                err < 1e-12,
                "case {case} err {err} kinds {kind:?} q {q:?} diag {diag:?}"
            );
        }
    }
}
