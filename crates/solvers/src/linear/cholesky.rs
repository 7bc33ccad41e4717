//! Sparse direct solver: supernodal Cholesky `P A P^T = L L^T` with a
//! nested-dissection or AMD ordering `P` (by default the one predicted to
//! cost fewer flops, [`OrderingKind::Auto`]).
//!
//! # Phases
//!
//! * [`LinearSolver::analyze`] (`crate::supernodal::analyze`, shared with
//!   the `ldlt` back end [`crate::LdltSolver`]): the fill-reducing ordering `P`
//!   ([`crate::ordering::choose`]; the report's notes give the predicted
//!   factor non-zeros of every candidate and the one kept), then the
//!   supernodal symbolic factorisation on the quotient graph of equation
//!   groups (`crate::symbolic`): elimination tree, column counts,
//!   supernodes, and the row structure of `L`. Supernodes wider than
//!   `PANEL` (256) columns are split into panels (`crate::supernodal`,
//!   which holds the numeric kernels). Done once per pattern.
//! * [`LinearSolver::factorize`]: numeric `L L^T`, left-looking over the
//!   panels, with faer's dense kernels (GEMM, dense Cholesky, triangular
//!   solve) per panel. Independent subtrees of the elimination tree run as
//!   parallel rayon tasks, and large panels also use parallel dense kernels.
//!   The entries of `A` are scattered straight into the factor (no permuted
//!   copy of `A`), and only the lower trapezoid of each panel is stored,
//!   apart from the upper half of its at most `PANEL x PANEL` diagonal block
//!   (faer's own numeric factor stores every supernode's full square
//!   diagonal block and copies `P A P^T`: 25% more memory on 3D meshes).
//!   The value buffer is allocated once (its length is fixed by the
//!   symbolic structure) and reused for every later matrix with the same
//!   pattern. Before it is allocated its size is checked against the
//!   memory available (`MemAvailable` of `/proc/meminfo` on Linux), and
//!   the allocation is a fallible reservation: a factor that does not fit
//!   is a [`SolverError::OutOfMemory`] naming both sizes, never an abort. A pivot
//!   `d_k = a_kk - sum_j l_kj^2 <= 0` stops the factorisation: the matrix is
//!   not positive definite, indefinite or singular
//!   ([`SolverError::NotPositiveDefinite`], with the pivot's position in the
//!   original numbering and a pointer to the `ldlt` back end, which factors
//!   the indefinite tangents of softening laws). A successful factor reports
//!   `negative_pivots = Some(0)`.
//!   The factor is in double precision, or in single precision for the
//!   mixed mode ([`Precision`]: `auto` picks it for large, well-scaled
//!   matrices; it halves the factor's time and memory).
//! * [`LinearSolver::solve_in_place`]: `x = P^T L^-T L^-1 P b` (per panel
//!   one dense triangular solve and one dense matrix-vector product), then
//!   the relative residual `rho = ||b - A x|| / ||b||`. Double factor: if
//!   `rho > refine_tol`, up to `max_refinements` steps of iterative
//!   refinement `x <- x + (L L^T)^-1 (b - A x)` (each costs one product and
//!   two triangular solves; it recovers the digits lost to rounding in the
//!   factor whenever `cond(A) eps < 1`). If `rho` stays above `warn_tol`,
//!   the report carries a warning with the numbers. Single factor: the same
//!   refinement, with residuals in double precision, until `rho <=
//!   mixed_tol`; if it stalls, the matrix is refactorised in double
//!   precision (see [`Precision`]).
//!
//! # Condition indicators (cheap, no extra solve)
//!
//! * the spread of the matrix diagonal `max a_ii / min a_ii` (a penalty of
//!   `1e20` against stiffnesses of `1e9` shows up here);
//! * the pivot ratio `min_k l_kk^2 / a_kk` (in the permuted numbering):
//!   `l_kk^2` is the Schur-complement diagonal, i.e. what is left of `a_kk`
//!   once the coupling to earlier equations has been eliminated. A ratio
//!   near machine precision means the equation is (numerically) a linear
//!   combination of earlier ones: a near-singular matrix. Below
//!   `pivot_warn` (default `1e-12`) the report warns; at or below
//!   `pivot_fail` (default `1e-14`, about 50 ulp) the factorisation is
//!   refused as not positive definite, because the solution would hold
//!   no correct digit (a floating-point factorisation of a singular matrix
//!   rarely meets an exactly non-positive pivot).

use crate::common::{
    inf_norm, norm2, residual, symmetric_norm_inf, symmetric_only, validate, Pattern,
};
use crate::ordering::OrderingKind;
use crate::supernodal::{threads_of, FactorScalar, PanelFactor, SolvePlan, PARALLEL_SOLVE_ENTRIES};
use faer::Par;
use junta_core::registry::{parse_params, ParamDoc, SolverEntry};
use junta_core::{LinearSolver, PrecomputedDissection, SolveReport, SolverError, SymmetricCsc};
use serde::Deserialize;
use std::time::Instant;

/// Settings of [`CholeskySolver`] (TOML parameters of the `cholesky` key).
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct CholeskySettings {
    /// Fill-reducing ordering: `"auto"` (default: nested dissection or
    /// AMD, whichever predicts fewer factor flops), `"nested_dissection"`,
    /// `"amd"` or `"natural"`.
    pub ordering: OrderingKind,
    /// Relative residual above which iterative refinement runs (1e-8).
    pub refine_tol: f64,
    /// Maximum refinement steps per solve (3).
    pub max_refinements: usize,
    /// Relative residual above which the report warns after refinement (1e-6).
    pub warn_tol: f64,
    /// Pivot ratio `min l_kk^2 / a_kk` below which the report warns (1e-12).
    pub pivot_warn: f64,
    /// Pivot ratio at or below which the matrix is refused as singular (1e-14).
    pub pivot_fail: f64,
    /// Threads for the numeric factorisation and the triangular solves
    /// (0: rayon's pool).
    pub threads: usize,
    /// Stored factor entries from which the triangular solves run the
    /// factor's independent subtrees in parallel (2^20; a solve is
    /// memory-bound, and below this the threads' hand-over costs more than
    /// it saves).
    pub parallel_solve_entries: usize,
    /// Working precision of the factor (see [`Precision`]; default `auto`).
    pub precision: Precision,
    /// `auto` uses the mixed mode only when the matrix diagonal spans at
    /// most this ratio `max a_ii / min a_ii` (1e6): penalty and
    /// interface models with stiff penalties go straight to double.
    pub mixed_max_spread: f64,
    /// ... and only from this many equations on (20,000): below it the
    /// double factor takes a fraction of a second, and the mixed mode's
    /// extra solves and possible fallback are not worth it.
    pub mixed_min_equations: usize,
    /// Relative residual the mixed mode refines to (1e-14, about what a
    /// double-precision factor gives on a well-conditioned matrix).
    /// Refinement that stalls within 100x of it counts as converged.
    pub mixed_tol: f64,
    /// Refinement steps the mixed mode may take per solve before it gives
    /// up and refactorises in double precision (12).
    pub max_mixed_refinements: usize,
}

/// Working precision of the numeric factor.
///
/// The mixed mode factorises `P A P^T = L L^T` in `f32` (half the memory
/// and, with twice as many lanes per SIMD instruction, about half the time
/// of the `f64` factor), then refines every solve in `f64`:
/// `x_{k+1} = x_k + (L L^T)^-1 (b - A x_k)` with the residual computed in
/// double precision. The error contracts by about `cond(A) eps_32` per step
/// (`eps_32 = 6e-8`), so a matrix with `cond(A) <~ 1e5` reaches a
/// double-precision residual in 3 or 4 steps. When it does not (single
/// pivot lost, pivot ratio below 1e-4, or refinement not reaching
/// `mixed_tol` within `max_mixed_refinements` steps), the solver refactorises
/// in `f64` and stays in double precision until the next analysis; the
/// solve report says which precision it used, and its notes why it fell
/// back. A failed attempt costs the single factor (about half a double
/// one) on top: on a 76k-equation H20 plate of span/thickness 100, whose
/// refinement stalls at 7e-7 (single pivot ratio 4e-4), `auto` takes 1.33 s
/// against 0.90 s for `double`; on the 107k-equation H20 cube (pivot ratio
/// 0.17) it takes 4.8 s against 7.9 s. Set `precision = "double"` for
/// thin-walled or slender models.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Precision {
    /// `f64` factor; refinement only when the residual asks for it.
    Double,
    /// `f32` factor refined in `f64`, with the fallback to double above.
    Mixed,
    /// `mixed` for large, well-scaled matrices (at least
    /// `mixed_min_equations` equations, diagonal spread at most
    /// `mixed_max_spread`), `double` otherwise.
    #[default]
    Auto,
}

impl Precision {
    /// The TOML name.
    pub fn name(self) -> &'static str {
        match self {
            Precision::Double => "double",
            Precision::Mixed => "mixed",
            Precision::Auto => "auto",
        }
    }
}

/// How to solve the systems Cholesky refuses (in its error messages).
pub const LDLT_HINT: &str = "if the tangent is meant to be indefinite (softening cohesive laws), use [solver] type = \"ldlt\" for softening/indefinite tangents";

/// Pivot ratio below which a single-precision factor is not trusted (it
/// would have lost four of its seven digits).
const SINGLE_PIVOT_MIN: f64 = 1e-4;

impl Default for CholeskySettings {
    fn default() -> Self {
        CholeskySettings {
            ordering: OrderingKind::Auto,
            refine_tol: 1e-8,
            max_refinements: 3,
            warn_tol: 1e-6,
            pivot_warn: 1e-12,
            pivot_fail: 1e-14,
            threads: 0,
            parallel_solve_entries: PARALLEL_SOLVE_ENTRIES,
            precision: Precision::Auto,
            mixed_max_spread: 1e6,
            mixed_min_equations: 20_000,
            mixed_tol: 1e-14,
            max_mixed_refinements: 12,
        }
    }
}

/// Parameter documentation of the `cholesky` registry entry.
pub const CHOLESKY_PARAMS: &[ParamDoc] = &[
    ParamDoc {
        name: "ordering",
        doc: "fill-reducing ordering: \"auto\" (default: computes nested dissection and AMD, predicts the fill of each from the symbolic column counts and keeps the one with fewer factor flops; the summary notes both predictions), \"nested_dissection\" (geometric with node coordinates: median cuts across the axis with the smallest separator), \"amd\", \"natural\"",
    },
    ParamDoc {
        name: "refine_tol",
        doc: "relative residual above which iterative refinement runs (default 1e-8)",
    },
    ParamDoc {
        name: "max_refinements",
        doc: "maximum iterative-refinement steps per solve (default 3)",
    },
    ParamDoc {
        name: "warn_tol",
        doc: "relative residual after refinement above which a warning is reported (default 1e-6)",
    },
    ParamDoc {
        name: "pivot_warn",
        doc: "pivot ratio min l_kk^2/a_kk below which a near-singular warning is reported (default 1e-12)",
    },
    ParamDoc {
        name: "pivot_fail",
        doc: "pivot ratio at or below which the matrix is refused as singular (default 1e-14)",
    },
    ParamDoc {
        name: "threads",
        doc: "threads for factorisation and solves, 0 = all of rayon's pool (default 0)",
    },
    ParamDoc {
        name: "parallel_solve_entries",
        doc: "stored factor entries from which the triangular solves run independent subtrees in parallel (default 1048576)",
    },
    ParamDoc {
        name: "precision",
        doc: "\"double\" (f64 factor), \"mixed\" (f32 factor, solutions refined to f64 residuals, falls back to double when refinement fails) or \"auto\" (default: mixed from mixed_min_equations equations on when the matrix diagonal spans at most mixed_max_spread); thin-walled or slender models refine poorly in single precision: use double",
    },
    ParamDoc {
        name: "mixed_max_spread",
        doc: "largest max/min matrix diagonal ratio for which auto picks the mixed mode (default 1e6)",
    },
    ParamDoc {
        name: "mixed_min_equations",
        doc: "fewest equations for which auto picks the mixed mode (default 20000)",
    },
    ParamDoc {
        name: "mixed_tol",
        doc: "relative residual the mixed mode refines to (default 1e-14; stalling within 100x of it counts as converged)",
    },
    ParamDoc {
        name: "max_mixed_refinements",
        doc: "refinement steps per solve before the mixed mode falls back to double (default 12)",
    },
];

/// Numbers describing the last analysis and factorisation.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct CholeskyStats {
    /// Ordering used (never `"auto"`: the kind `auto` kept).
    pub ordering: &'static str,
    /// Every ordering computed by the last analysis (two for `auto`) with
    /// its predicted factor non-zeros and flops.
    pub ordering_candidates: Vec<(&'static str, crate::ordering::FillEstimate)>,
    /// Bytes of the numeric factor's values (last factorisation).
    pub factor_bytes: usize,
    /// Number of symbolic analyses so far.
    pub analyze_count: usize,
    /// Of those, analyses that took the caller's nested dissection
    /// ([`LinearSolver::offer_dissection`]) instead of computing it.
    pub dissections_reused: usize,
    /// Independent subtrees the triangular solves of the current factor
    /// run in parallel (0: the solves run in panel order on one thread).
    pub solve_tasks: usize,
    /// Number of numeric factorisations so far.
    pub factor_count: usize,
    /// Number of solves so far.
    pub solve_count: usize,
    /// Seconds of the last ordering computation (part of `analyze_seconds`).
    pub ordering_seconds: f64,
    /// Whether faer chose the supernodal (rather than simplicial) factor.
    pub supernodal: bool,
    /// Non-zeros of `L` as stored (supernodal blocks count their full
    /// lower trapezoid).
    pub factor_nonzeros: usize,
    /// Smallest diagonal entry of the last matrix.
    pub matrix_diag_min: f64,
    /// Largest diagonal entry of the last matrix.
    pub matrix_diag_max: f64,
    /// Smallest pivot ratio `l_kk^2 / a_kk` of the last factor (near 0:
    /// digits lost to cancellation, the matrix is nearly singular).
    pub min_pivot_ratio: f64,
    /// Original (unpermuted) equation where `min_pivot_ratio` occurs.
    pub min_pivot_equation: usize,
    /// Refinement steps of the last solve.
    pub refinement_steps: usize,
    /// Precision of the current factor (`"double"` or `"mixed"`).
    pub precision: &'static str,
    /// Times the mixed mode gave up and refactorised in double precision.
    pub mixed_fallbacks: usize,
    /// Why it gave up the last time (empty if it never did).
    pub mixed_fallback_reason: String,
}

/// Sparse Cholesky back end (registry key `"cholesky"`).
pub struct CholeskySolver {
    settings: CholeskySettings,
    pattern: Option<Pattern>,
    /// `perm[new] = old`, and its inverse.
    perm: Vec<usize>,
    perm_inv: Vec<usize>,
    factor: Option<PanelFactor>,
    /// The independent parts of the triangular solves, balanced for the
    /// threads ([`SolvePlan`]), from the last analysis.
    plan: Option<SolvePlan>,
    /// Values of the double- or single-precision factor (only one is
    /// non-empty at a time).
    values64: Vec<f64>,
    values32: Vec<f32>,
    /// Whether the current factor is the single-precision one.
    single: bool,
    /// A mixed-precision attempt failed: double from now on.
    single_failed: bool,
    /// `||A||_inf` of the matrix of the single-precision factor.
    a_norm_inf: f64,
    factored: bool,
    /// A nested dissection offered by the caller, taken by the next
    /// analysis.
    dissection: Option<PrecomputedDissection>,
    stats: CholeskyStats,
    report: SolveReport,
    /// Warnings of the last factorisation (kept while solving with it).
    factor_warnings: Vec<String>,
}

impl std::fmt::Debug for CholeskySolver {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("CholeskySolver")
            .field("settings", &self.settings)
            .field("n", &self.perm.len())
            .field("factored", &self.factored)
            .field("stats", &self.stats)
            .finish_non_exhaustive()
    }
}

impl Default for CholeskySolver {
    fn default() -> Self {
        Self::new(CholeskySettings::default())
    }
}

impl CholeskySolver {
    /// A solver with the given settings (`CholeskySolver::new(Default::default())`).
    pub fn new(settings: CholeskySettings) -> Self {
        CholeskySolver {
            settings,
            pattern: None,
            perm: Vec::new(),
            perm_inv: Vec::new(),
            factor: None,
            plan: None,
            values64: Vec::new(),
            values32: Vec::new(),
            single: false,
            single_failed: false,
            a_norm_inf: 0.0,
            factored: false,
            dissection: None,
            stats: CholeskyStats::default(),
            report: SolveReport {
                solver: "cholesky".into(),
                ..Default::default()
            },
            factor_warnings: Vec::new(),
        }
    }

    /// From a TOML parameter table (unknown keys are an error).
    pub fn from_table(table: &toml::Table) -> Result<Self, junta_core::CoreError> {
        Ok(Self::new(parse_params("solver", "cholesky", table)?))
    }

    /// The settings.
    pub fn settings(&self) -> &CholeskySettings {
        &self.settings
    }

    /// Statistics of the analysis, last factorisation and last solve.
    pub fn stats(&self) -> &CholeskyStats {
        &self.stats
    }

    /// The ordering of the last analysis (`perm[new] = old`).
    pub fn permutation(&self) -> &[usize] {
        &self.perm
    }

    fn par(&self) -> Par {
        let threads = if self.settings.threads == 0 {
            rayon::current_num_threads()
        } else {
            self.settings.threads
        };
        if threads <= 1 {
            Par::Seq
        } else {
            Par::rayon(threads)
        }
    }

    /// The plan of parallel triangular solves, for a factor of `entries`
    /// stored values of at least [`CholeskySettings::parallel_solve_entries`]
    /// with more than one group of subtrees.
    fn parallel_plan(&self, entries: usize) -> Option<&SolvePlan> {
        self.plan
            .as_ref()
            .filter(|p| p.groups.len() > 1 && entries >= self.settings.parallel_solve_entries)
    }

    /// `x <- (L L^T)^-1 x` through the permutation, in the factor's
    /// precision (`work`: scratch of length `n`).
    fn apply_inverse<T: FactorScalar>(&self, values: &[T], x: &mut [f64], work: &mut Vec<T>) {
        let factor = self.factor.as_ref().expect("analysed");
        work.clear();
        work.extend(self.perm.iter().map(|&old| T::of_f64(x[old])));
        factor.solve_permuted(values, work, self.parallel_plan(values.len()));
        for (i, xi) in x.iter_mut().enumerate() {
            *xi = work[self.perm_inv[i]].to_f64();
        }
    }

    /// Pivot ratios `l_kk^2 / a_kk` of the current factor: the smallest and
    /// its original equation.
    fn min_pivot_ratio(&self, ldiag: &[f64], diag: &[f64]) -> (f64, usize) {
        let (mut rmin, mut kmin) = (f64::INFINITY, 0usize);
        for (k, &l) in ldiag.iter().enumerate() {
            let r = l * l / diag[self.perm[k]];
            if r.is_nan() || r < rmin {
                rmin = r;
                kmin = k;
            }
        }
        (rmin, self.perm.get(kmin).copied().unwrap_or(0))
    }

    /// Single-precision factor. `Err(reason)` when it cannot be trusted.
    fn factor_single(&mut self, matrix: &SymmetricCsc, diag: &[f64]) -> Result<(), String> {
        self.a_norm_inf = symmetric_norm_inf(matrix);
        let par = self.par();
        self.values64 = Vec::new();
        let factor = self.factor.as_ref().expect("analysed");
        let mut values = std::mem::take(&mut self.values32);
        // allocated by the caller (`allocate_values`)
        debug_assert_eq!(values.len(), factor.len_val());
        let res = factor.factorize(&mut values, matrix, &self.perm_inv, par);
        self.stats.factor_count += 1;
        if let Err(k) = res {
            return Err(format!(
                "single-precision pivot lost at elimination step {k} (about equation {})",
                self.perm[k.min(self.perm.len().saturating_sub(1))]
            ));
        }
        let ldiag = factor.diagonal(&values);
        self.values32 = values;
        let (rmin, eq) = self.min_pivot_ratio(&ldiag, diag);
        self.stats.min_pivot_ratio = rmin;
        self.stats.min_pivot_equation = eq;
        tracing::info!(
            min_pivot_ratio = rmin,
            equation = eq,
            "cholesky: single-precision factor"
        );
        if rmin.is_nan() || rmin < SINGLE_PIVOT_MIN {
            return Err(format!(
                "single-precision pivot ratio {rmin:.3e} at equation {eq} is below {SINGLE_PIVOT_MIN:.0e}"
            ));
        }
        self.single = true;
        self.stats.precision = "mixed";
        self.report.precision = "mixed".into();
        Ok(())
    }

    /// Record why the mixed mode was abandoned; double from now on.
    fn give_up_single(&mut self, reason: String) {
        let note = format!(
            "cholesky: mixed precision abandoned, refactorised in double precision: {reason}"
        );
        tracing::info!("{note}");
        if !self.report.notes.contains(&note) {
            self.report.notes.push(note);
        }
        self.single = false;
        self.single_failed = true;
        self.values32 = Vec::new();
        self.stats.mixed_fallbacks += 1;
        self.stats.mixed_fallback_reason = reason;
    }

    /// Double-precision factor with the conditioning checks.
    fn factor_double(
        &mut self,
        matrix: &SymmetricCsc,
        diag: &[f64],
        dmin: f64,
        dmax: f64,
    ) -> Result<(), SolverError> {
        let n = matrix.n;
        let par = self.par();
        self.single = false;
        self.values32 = Vec::new();
        self.stats.precision = "double";
        self.report.precision = "double".into();
        let factor = self.factor.as_ref().expect("analysed");
        self.stats.factor_bytes = allocate_values(&mut self.values64, factor.len_val(), "double")?;
        self.stats.solve_tasks = self
            .parallel_plan(factor.len_val())
            .map_or(0, |p| p.tasks.len());
        let mut values = std::mem::take(&mut self.values64);
        let res = factor.factorize(&mut values, matrix, &self.perm_inv, par);
        self.stats.factor_count += 1;
        if let Err(k) = res {
            self.values64 = values;
            // k: the failing column of the permuted matrix; name the
            // original equation.
            let k = k.min(n.saturating_sub(1));
            let eq = self.perm[k];
            return Err(SolverError::NotPositiveDefinite {
                detail: format!(
                    ": non-positive pivot at elimination step {k} of {n}: the matrix is not positive definite (indefinite or singular) at about equation {eq} (diagonal {:.3e}; matrix diagonal in [{dmin:.3e}, {dmax:.3e}]); {LDLT_HINT}",
                    diag[eq]
                ),
            });
        }
        let ldiag = factor.diagonal(&values);
        self.values64 = values;
        let (rmin, eq) = self.min_pivot_ratio(&ldiag, diag);
        let kmin = self.perm_inv.get(eq).copied().unwrap_or(0);
        self.stats.min_pivot_ratio = rmin;
        self.stats.min_pivot_equation = eq;
        let spread = dmax / dmin;
        if !rmin.is_finite() || rmin <= self.settings.pivot_fail {
            return Err(SolverError::NotPositiveDefinite {
                detail: format!(
                    ": numerically singular, pivot ratio l_kk^2/a_kk = {rmin:.3e} at equation {eq} (elimination step {kmin} of {n}; threshold {:.1e}); matrix diagonal in [{dmin:.3e}, {dmax:.3e}]",
                    self.settings.pivot_fail
                ),
            });
        }
        if rmin < self.settings.pivot_warn {
            self.factor_warnings.push(format!(
                "cholesky: near-singular matrix: smallest pivot ratio l_kk^2/a_kk = {rmin:.3e} at equation {eq}; expect to lose about {:.0} digits (matrix diagonal spans {dmin:.3e} .. {dmax:.3e})",
                -rmin.log10()
            ));
        }
        if spread > 1e12 {
            self.factor_warnings.push(format!(
                "cholesky: the matrix diagonal spans {dmin:.3e} .. {dmax:.3e} (ratio {spread:.1e}); the matrix is ill-conditioned (penalty too high?)"
            ));
        }
        for w in self.factor_warnings.clone() {
            self.push_warning(w);
        }
        self.report.negative_pivots = Some(0);
        self.factored = true;
        Ok(())
    }

    /// Solve with the single-precision factor, refined in double precision
    /// until the relative residual is at most `mixed_tol`. `Err(reason)`
    /// when it does not get there (`b` then holds garbage).
    fn solve_mixed(
        &mut self,
        matrix: &SymmetricCsc,
        rhs: &[f64],
        x: &mut [f64],
    ) -> Result<(), String> {
        let n = rhs.len();
        let bnorm = norm2(rhs);
        let values = std::mem::take(&mut self.values32);
        let mut work: Vec<f32> = Vec::with_capacity(n);
        let mut r = rhs.to_vec();
        let mut best = vec![0.0; n];
        let mut best_rel = f64::INFINITY;
        x.fill(0.0);
        let mut prev_rel = f64::INFINITY;
        // refinement steps done; the first pass is the plain solve
        let mut k = 0;
        let tol = self.settings.mixed_tol;
        let outcome = loop {
            // x <- x + s (L L^T)^-1 (r / s), with r scaled to unit size so
            // that its single-precision copy neither underflows nor
            // overflows; then r = b - A x in double precision
            let scale = inf_norm(&r);
            if scale == 0.0 {
                best.copy_from_slice(x);
                best_rel = 0.0;
                break Ok(());
            }
            r.iter_mut().for_each(|v| *v /= scale);
            self.apply_inverse(&values, &mut r, &mut work);
            for (xi, di) in x.iter_mut().zip(&r) {
                *xi += scale * di;
            }
            let rel = residual(matrix, x, rhs, &mut r) / bnorm;
            if !rel.is_finite() {
                break Err(format!("refinement step {k} gave a non-finite residual"));
            }
            if rel < best_rel {
                best_rel = rel;
                best.copy_from_slice(x);
            }
            if rel <= tol {
                break Ok(());
            }
            let stalled = k > 0 && rel > 0.5 * prev_rel;
            if stalled || k >= self.settings.max_mixed_refinements {
                // Converged anyway when the best iterate is at the floor of
                // double precision: a relative residual within 100x of the
                // target, or a normwise backward error
                // ||b - A x||_inf / (||A||_inf ||x||_inf + ||b||_inf) of at
                // most 1000 eps_64 (on an ill-conditioned matrix the
                // residual floor of a double factor is above mixed_tol too).
                x.copy_from_slice(&best);
                let res_inf = {
                    residual(matrix, x, rhs, &mut r);
                    inf_norm(&r)
                };
                let eta = res_inf / (self.a_norm_inf * inf_norm(x) + inf_norm(rhs));
                if best_rel <= 100.0 * tol || eta <= 1e3 * f64::EPSILON {
                    break Ok(());
                }
                break Err(format!(
                    "refinement stalled at relative residual {best_rel:.3e} (backward error {eta:.1e}) after {k} steps (mixed_tol {tol:.1e})"
                ));
            }
            prev_rel = rel;
            k += 1;
        };
        self.values32 = values;
        self.stats.refinement_steps = k;
        self.report.refinement_steps = k;
        if outcome.is_ok() {
            x.copy_from_slice(&best);
            self.report.residual = best_rel;
        }
        outcome
    }

    /// Solve with the double-precision factor, refined while the residual
    /// is above `refine_tol`; warns when it stays above `warn_tol`.
    fn solve_double(
        &mut self,
        matrix: &SymmetricCsc,
        rhs: &[f64],
        b: &mut [f64],
    ) -> Result<(), SolverError> {
        let n = rhs.len();
        let bnorm = norm2(rhs);
        let values = std::mem::take(&mut self.values64);
        let mut work: Vec<f64> = Vec::with_capacity(n);
        self.apply_inverse(&values, b, &mut work);
        let mut r = vec![0.0; n];
        let mut rel = residual(matrix, b, rhs, &mut r) / bnorm;
        let mut steps = 0;
        let mut trial = vec![0.0; n];
        let mut r2 = vec![0.0; n];
        while rel.is_finite()
            && rel > self.settings.refine_tol
            && steps < self.settings.max_refinements
        {
            self.apply_inverse(&values, &mut r, &mut work);
            for ((t, bi), d) in trial.iter_mut().zip(b.iter()).zip(&r) {
                *t = bi + d;
            }
            let rel2 = residual(matrix, &trial, rhs, &mut r2) / bnorm;
            steps += 1;
            if rel2.is_nan() || rel2 >= rel {
                break; // refinement no longer helps
            }
            b.copy_from_slice(&trial);
            std::mem::swap(&mut r, &mut r2);
            rel = rel2;
        }
        self.values64 = values;
        self.stats.refinement_steps = steps;
        self.report.refinement_steps = steps;
        self.report.residual = rel;
        if !rel.is_finite() || b.iter().any(|v| !v.is_finite()) {
            b.copy_from_slice(rhs);
            return Err(SolverError::NonFinite {
                method: "cholesky solve".into(),
            });
        }
        if rel > self.settings.warn_tol {
            let w = format!(
                "direct solve lost digits: residual {rel:.3e} after {steps} refinement steps (warn_tol {:.1e}); the matrix is ill-conditioned (penalty too high?): diagonal spans {:.3e} .. {:.3e}, smallest pivot ratio {:.3e}",
                self.settings.warn_tol,
                self.stats.matrix_diag_min,
                self.stats.matrix_diag_max,
                self.stats.min_pivot_ratio
            );
            self.push_warning(w);
        }
        Ok(())
    }

    fn push_warning(&mut self, w: String) {
        tracing::warn!("{w}");
        if !self.report.warnings.contains(&w) && self.report.warnings.len() < 32 {
            self.report.warnings.push(w);
        }
    }
}

impl LinearSolver for CholeskySolver {
    fn key(&self) -> &'static str {
        "cholesky"
    }

    fn analyze(
        &mut self,
        matrix: &SymmetricCsc,
        coords: Option<&[[f64; 3]]>,
    ) -> Result<(), SolverError> {
        let t0 = Instant::now();
        validate(matrix)?;
        symmetric_only(matrix, "cholesky")?;
        let n = matrix.n;
        self.factored = false;
        let crate::supernodal::Analysis {
            perm,
            perm_inv,
            factor,
            ordering_seconds,
            kind,
            candidates,
            ordering_note,
            dissection_reused,
        } = crate::supernodal::analyze(
            self.settings.ordering,
            matrix,
            coords,
            1.0,
            self.dissection.take().as_ref(),
        )?;
        self.stats.dissections_reused += usize::from(dissection_reused);
        self.stats.supernodal = true;
        self.stats.factor_nonzeros = factor.nonzeros();
        self.plan = factor.solve_plan();
        let threads = threads_of(self.par());
        if let Some(plan) = self.plan.as_mut() {
            plan.balance(threads);
        }
        self.factor = Some(factor);
        self.stats.ordering = kind.name();
        self.stats.ordering_candidates = candidates.iter().map(|(k, e)| (k.name(), *e)).collect();
        self.stats.ordering_seconds = ordering_seconds;
        self.stats.analyze_count += 1;
        // a new pattern is a new problem: the mixed mode may be tried again
        self.single_failed = false;
        self.report.notes.clear();
        self.report.notes.push(ordering_note);
        self.report.ordering = kind.name().into();
        self.report.ordering_candidates = candidates
            .iter()
            .map(|(k, e)| (k.name().to_string(), e.nonzeros))
            .collect();
        self.single = false;
        self.values32 = Vec::new();
        self.values64 = Vec::new();
        self.perm = perm;
        self.perm_inv = perm_inv;
        self.pattern = Some(Pattern::of(matrix));
        let secs = t0.elapsed().as_secs_f64();
        self.report.analyze_seconds += secs;
        self.report.factor_nonzeros = self.stats.factor_nonzeros;
        self.report.ordering = self.stats.ordering.into();
        tracing::info!(
            n,
            nnz = matrix.nnz(),
            ordering = self.stats.ordering,
            ordering_seconds,
            analyze_seconds = secs,
            factor_nonzeros = self.stats.factor_nonzeros,
            "cholesky: symbolic analysis"
        );
        Ok(())
    }

    fn offer_dissection(&mut self, dissection: PrecomputedDissection) {
        self.dissection = Some(dissection);
    }

    fn factorize(&mut self, matrix: &SymmetricCsc) -> Result<(), SolverError> {
        symmetric_only(matrix, "cholesky")?;
        let t0 = Instant::now();
        let Some(pattern) = &self.pattern else {
            return Err(SolverError::Usage(
                "cholesky: factorize called before analyze".into(),
            ));
        };
        pattern.check(matrix, "cholesky factorize")?;
        self.factored = false;
        self.report.negative_pivots = None;
        // Warnings describe the current factor: start afresh.
        self.report.warnings.clear();
        self.factor_warnings.clear();
        if let Some(p) = matrix.values.iter().position(|v| !v.is_finite()) {
            let col = matrix.col_ptr.partition_point(|&c| c <= p) - 1;
            return Err(SolverError::NonFinite {
                method: format!(
                    "cholesky factorisation: the matrix holds {} at entry ({}, {})",
                    matrix.values[p], matrix.row_idx[p], col
                ),
            });
        }
        // Matrix diagonal: a non-positive entry already rules out SPD.
        let diag = matrix.diagonal();
        let (mut dmin, mut dmax) = (f64::INFINITY, 0.0f64);
        for (i, &d) in diag.iter().enumerate() {
            if d <= 0.0 {
                return Err(SolverError::NotPositiveDefinite {
                    detail: format!(
                        ": diagonal entry of equation {i} is {d:e}: the matrix is not positive definite (indefinite or singular) at equation {i} (an equation with no stiffness, a missing constraint, or a softening tangent); {LDLT_HINT}"
                    ),
                });
            }
            dmin = dmin.min(d);
            dmax = dmax.max(d);
        }
        self.stats.matrix_diag_min = dmin;
        self.stats.matrix_diag_max = dmax;

        let spread = dmax / dmin;
        let try_single = !self.single_failed
            && match self.settings.precision {
                Precision::Double => false,
                Precision::Mixed => true,
                Precision::Auto => {
                    spread <= self.settings.mixed_max_spread
                        && matrix.n >= self.settings.mixed_min_equations
                }
            };
        if try_single {
            // the single factor needs half the memory of the double one: when
            // it does not fit, neither does the fallback
            let len = self.factor.as_ref().expect("analysed").len_val();
            self.values64 = Vec::new();
            self.stats.factor_bytes = allocate_values(&mut self.values32, len, "single")?;
            self.stats.solve_tasks = self.parallel_plan(len).map_or(0, |p| p.tasks.len());
            match self.factor_single(matrix, &diag) {
                Ok(()) => {
                    self.report.factor_seconds += t0.elapsed().as_secs_f64();
                    self.report.negative_pivots = Some(0);
                    self.factored = true;
                    return Ok(());
                }
                Err(reason) => self.give_up_single(reason),
            }
        }
        let result = self.factor_double(matrix, &diag, dmin, dmax);
        self.report.factor_seconds += t0.elapsed().as_secs_f64();
        result
    }

    fn solve_in_place(&mut self, matrix: &SymmetricCsc, b: &mut [f64]) -> Result<(), SolverError> {
        let t0 = Instant::now();
        if !self.factored {
            return Err(SolverError::Usage(
                "cholesky: solve called without a successful factorize".into(),
            ));
        }
        let n = self.perm.len();
        if b.len() != n {
            return Err(SolverError::Usage(format!(
                "cholesky: right-hand side has {} entries, the matrix {n} equations",
                b.len()
            )));
        }
        if let Some(pattern) = &self.pattern {
            pattern.check(matrix, "cholesky solve")?;
        }
        if let Some(i) = b.iter().position(|v| !v.is_finite()) {
            return Err(SolverError::NonFinite {
                method: format!(
                    "cholesky: the right-hand side holds {} at equation {i}",
                    b[i]
                ),
            });
        }
        self.stats.solve_count += 1;
        self.stats.refinement_steps = 0;
        self.report.refinement_steps = 0;
        if norm2(b) == 0.0 {
            b.fill(0.0);
            self.report.residual = 0.0;
            self.report.solve_seconds += t0.elapsed().as_secs_f64();
            return Ok(());
        }
        let rhs = b.to_vec();
        // seconds of a fallback refactorisation (booked as factor time)
        let mut refactor_seconds = 0.0;
        if self.single {
            match self.solve_mixed(matrix, &rhs, b) {
                Ok(()) => {
                    self.report.solve_seconds += t0.elapsed().as_secs_f64();
                    return Ok(());
                }
                Err(reason) => {
                    // refactorise in double precision and solve afresh
                    self.give_up_single(reason);
                    // no usable factor until the double one succeeds
                    self.factored = false;
                    b.copy_from_slice(&rhs);
                    let tf = Instant::now();
                    let diag = matrix.diagonal();
                    let (dmin, dmax) = (self.stats.matrix_diag_min, self.stats.matrix_diag_max);
                    let fac = self.factor_double(matrix, &diag, dmin, dmax);
                    refactor_seconds = tf.elapsed().as_secs_f64();
                    self.report.factor_seconds += refactor_seconds;
                    if let Err(e) = fac {
                        self.report.solve_seconds += t0.elapsed().as_secs_f64() - refactor_seconds;
                        return Err(e);
                    }
                }
            }
        }
        let result = self.solve_double(matrix, &rhs, b);
        self.report.solve_seconds += t0.elapsed().as_secs_f64() - refactor_seconds;
        result
    }

    fn report(&self) -> SolveReport {
        self.report.clone()
    }
}

/// Make `values` a zero-filled buffer of `len` entries (kept as is when it
/// already has that length) and return its bytes; or, before anything is
/// allocated, a [`SolverError::OutOfMemory`] with the numbers when the
/// buffer is larger than the memory available (`/proc/meminfo` on Linux;
/// elsewhere only a failed reservation is caught). Aborting on a failed
/// allocation, or being killed by the kernel once the pages are touched,
/// is what this avoids.
fn allocate_values<T: Default + Copy + Send + Sync>(
    values: &mut Vec<T>,
    len: usize,
    precision: &str,
) -> Result<usize, SolverError> {
    let bytes = len.saturating_mul(std::mem::size_of::<T>());
    if values.len() == len {
        return Ok(bytes);
    }
    *values = Vec::new();
    let gb = |b: u64| b as f64 / 1e9;
    let refuse = |available: String| {
        SolverError::OutOfMemory {
        detail: format!(
            "the {precision}-precision Cholesky factor needs {:.2} GB ({len} non-zeros stored), {available}; use a coarser mesh{}",
            gb(bytes as u64),
            if precision == "double" {
                ", or precision = \"mixed\" (half the memory)"
            } else {
                ""
            }
        ),
    }
    };
    if let Some(avail) = crate::common::available_memory() {
        if bytes as u64 > avail {
            return Err(refuse(format!("{:.2} GB available", gb(avail))));
        }
    }
    values
        .try_reserve_exact(len)
        .map_err(|_| refuse("and the allocation failed".into()))?;
    crate::common::fill_default_in_parallel(values, len);
    Ok(bytes)
}

inventory::submit! {
    SolverEntry {
        key: "cholesky",
        description: "sparse supernodal Cholesky (symbolic analysis on the graph of nodes, faer dense kernels) with nested-dissection or AMD ordering (auto: the one with fewer predicted flops), double or mixed (single-precision factor refined in double) precision, iterative refinement and conditioning warnings",
        params: CHOLESKY_PARAMS,
        build: |table| Ok(Box::new(CholeskySolver::from_table(table)?)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spd3() -> SymmetricCsc {
        // [[4,1,0],[1,3,1],[0,1,2]]
        let mut a = SymmetricCsc::from_columns(vec![vec![0], vec![0, 1], vec![1, 2]]);
        a.values = vec![4.0, 1.0, 3.0, 1.0, 2.0];
        a
    }

    #[test]
    fn small_system_and_usage_errors() {
        let a = spd3();
        // x = A^-1 [1, 2, 3] = [2, 1, 13] / 9 (by elimination by hand)
        let exact = [2.0 / 9.0, 1.0 / 9.0, 13.0 / 9.0];
        for precision in [Precision::Double, Precision::Mixed] {
            let mut s = CholeskySolver::new(CholeskySettings {
                precision,
                ..Default::default()
            });
            let mut b = vec![1.0, 2.0, 3.0];
            assert!(matches!(s.factorize(&a), Err(SolverError::Usage(_))));
            s.analyze(&a, None).unwrap();
            assert!(matches!(
                s.solve_in_place(&a, &mut b),
                Err(SolverError::Usage(_))
            ));
            s.factorize(&a).unwrap();
            s.solve_in_place(&a, &mut b).unwrap();
            for (x, e) in b.iter().zip(exact) {
                assert!((x - e).abs() < 1e-14, "{precision:?}: {x} vs {e}");
            }
            let r = s.report();
            assert!(r.residual < 1e-14, "{precision:?}: {}", r.residual);
            assert_eq!(r.precision, precision.name());
            assert!(r.factor_nonzeros >= 5);
            assert!(r.warnings.is_empty());
        }
    }

    #[test]
    fn indefinite_matrix_names_the_pivot() {
        // [[1,2],[2,1]]: eigenvalues 3 and -1
        let mut a = SymmetricCsc::from_columns(vec![vec![0], vec![0, 1]]);
        a.values = vec![1.0, 2.0, 1.0];
        let mut s = CholeskySolver::new(CholeskySettings {
            ordering: OrderingKind::Natural,
            ..Default::default()
        });
        s.analyze(&a, None).unwrap();
        match s.factorize(&a) {
            Err(SolverError::NotPositiveDefinite { detail }) => {
                assert!(detail.contains("equation 1"), "{detail}");
                assert!(detail.contains("indefinite or singular"), "{detail}");
                assert!(detail.contains("type = \"ldlt\""), "{detail}");
            }
            other => panic!("expected NotPositiveDefinite, got {other:?}"),
        }
    }

    #[test]
    fn wide_supernodes_are_split_and_threads_agree() {
        // 12^3 nodes, 3 dofs each: the top separator (432 columns) is wider
        // than a panel, so split panels, in-place and scattered updates and
        // subtree tasks are all exercised.
        let (a, coords) = crate::gallery::grid_3d(12, 12, 12, 3, crate::gallery::Stencil::Point27);
        let b: Vec<f64> = (0..a.n).map(|i| ((i * 7919) % 17) as f64 - 8.0).collect();
        let mut sols = Vec::new();
        for threads in [1, 2] {
            let mut s = CholeskySolver::new(CholeskySettings {
                threads,
                refine_tol: 0.0,
                max_refinements: 0,
                ..Default::default()
            });
            s.analyze(&a, Some(&coords)).unwrap();
            let f = s.factor.as_ref().unwrap();
            let widest = f.widest_panel();
            assert_eq!(
                widest,
                crate::supernodal::PANEL,
                "a supernode wider than a panel was split"
            );
            // stored entries: exact fill plus the explicit zeros of merged
            // (relaxed) supernodes
            assert!(
                s.stats().factor_nonzeros
                    >= crate::ordering::factor_nonzeros(&a, Some(s.permutation()))
            );
            s.factorize(&a).unwrap();
            let mut x = b.clone();
            s.solve_in_place(&a, &mut x).unwrap();
            assert!(
                s.report().residual < 1e-12,
                "residual {}",
                s.report().residual
            );
            sols.push(x);
        }
        for (p, q) in sols[0].iter().zip(&sols[1]) {
            assert!((p - q).abs() <= 1e-10 * p.abs().max(1.0));
        }
        // an indefinite matrix of the same pattern (positive diagonal, one
        // 2x2 principal minor negative) is refused during the factorisation
        let mut bad = a.clone();
        let mid = bad.n / 2;
        let p = bad.col_ptr[mid + 1] - 2; // an off-diagonal entry of column mid
        let (i, j) = (bad.row_idx[p], mid);
        let d = a.diagonal();
        bad.values[p] = 2.0 * (d[i] * d[j]).sqrt();
        let mut s = CholeskySolver::new(CholeskySettings {
            threads: 2,
            ..Default::default()
        });
        s.analyze(&bad, Some(&coords)).unwrap();
        assert!(matches!(
            s.factorize(&bad),
            Err(SolverError::NotPositiveDefinite { .. })
        ));
    }

    #[test]
    fn a_factor_larger_than_memory_is_an_error_not_an_abort() {
        // 2^60 entries (8 EiB): more than /proc/meminfo's MemAvailable on
        // Linux, a failed reservation elsewhere; nothing is allocated
        let mut v: Vec<f64> = vec![1.0; 4];
        match allocate_values(&mut v, 1 << 60, "double") {
            Err(SolverError::OutOfMemory { detail }) => {
                assert!(detail.contains("needs 9223372036.85 GB"), "{detail}");
                assert!(detail.contains("mixed"), "{detail}");
            }
            other => panic!("expected OutOfMemory, got {other:?}"),
        }
        assert!(v.is_empty());
        // a buffer that fits is zero-filled, and kept when its length is right
        assert_eq!(allocate_values(&mut v, 3, "single"), Ok(24));
        assert_eq!(v, vec![0.0; 3]);
        v[0] = 5.0;
        assert_eq!(allocate_values(&mut v, 3, "single"), Ok(24));
        assert_eq!(v[0], 5.0);
    }

    #[test]
    fn report_names_the_ordering_and_its_prediction() {
        let (a, coords) = crate::gallery::grid_3d(6, 6, 6, 3, crate::gallery::Stencil::Point27);
        for kind in [OrderingKind::Auto, OrderingKind::Amd] {
            let mut s = CholeskySolver::new(CholeskySettings {
                ordering: kind,
                ..Default::default()
            });
            s.analyze(&a, Some(&coords)).unwrap();
            let r = s.report();
            let stats = s.stats();
            assert_eq!(r.ordering, stats.ordering);
            assert_ne!(r.ordering, "auto");
            let expected = if kind == OrderingKind::Auto { 2 } else { 1 };
            assert_eq!(r.ordering_candidates.len(), expected);
            assert_eq!(stats.ordering_candidates.len(), expected);
            // the prediction of the kept ordering is the exact fill; faer's
            // stored factor adds the explicit zeros of relaxed supernodes
            let exact = crate::ordering::factor_nonzeros(&a, Some(s.permutation()));
            let kept = r
                .ordering_candidates
                .iter()
                .find(|c| c.0 == r.ordering)
                .unwrap()
                .1;
            assert_eq!(kept, exact);
            assert!(r.factor_nonzeros >= exact);
            assert!(
                r.notes[0].starts_with(&format!("ordering {}", kind.name())),
                "{:?}",
                r.notes
            );
            s.factorize(&a).unwrap();
            assert_eq!(
                s.stats().factor_bytes,
                s.factor.as_ref().unwrap().len_val() * 8
            );
        }
    }

    #[test]
    fn params_reject_unknown_keys() {
        let t: toml::Table = toml::from_str("ordering = \"amd\"\nrefine_tol = 1e-9").unwrap();
        let s = CholeskySolver::from_table(&t).unwrap();
        assert_eq!(s.settings().ordering, OrderingKind::Amd);
        assert_eq!(s.settings().refine_tol, 1e-9);
        let bad: toml::Table = toml::from_str("orderin = \"amd\"").unwrap();
        assert!(CholeskySolver::from_table(&bad).is_err());
    }
}
