//! Sparse direct solver: supernodal Cholesky `P A P^T = L L^T` with a
//! nested-dissection (default) or AMD ordering `P`.
//!
//! # Phases
//!
//! * [`LinearSolver::analyze`]: the fill-reducing ordering `P`
//!   ([`crate::ordering`]), then faer's symbolic factorisation with
//!   `SymmetricOrdering::Custom(P)`: elimination tree, column counts,
//!   supernodes, and the row structure of `L`. Supernodes wider than
//!   [`PANEL`] columns are split into panels (see [`PanelFactor`]). Done once
//!   per pattern.
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
//!   pattern. A pivot
//!   `d_k = a_kk - sum_j l_kj^2 <= 0` stops the factorisation: the matrix is
//!   not positive definite ([`SolverError::NotPositiveDefinite`], with the
//!   pivot's position in the original numbering).
//! * [`LinearSolver::solve_in_place`]: `x = P^T L^-T L^-1 P b`, then the
//!   relative residual `rho = ||b - A x|| / ||b||`. If `rho > refine_tol`,
//!   up to `max_refinements` steps of iterative refinement
//!   `x <- x + (L L^T)^-1 (b - A x)` (each costs one product and two
//!   triangular solves; it recovers the digits lost to rounding in the
//!   factor whenever `cond(A) eps < 1`). If `rho` stays above `warn_tol`, the
//!   report carries a warning with the numbers.
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

use crate::common::{norm2, residual, validate, Pattern};
use crate::ordering::{self, OrderingKind};
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::{LltError as DenseLltError, LltRegularization};
use faer::reborrow::{Reborrow, ReborrowMut};
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, SymbolicCholeskyRaw, SymmetricOrdering,
};
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::SymbolicSparseColMatRef;
use faer::{Accum, MatMut, MatRef, Par, Side};
use junta_core::registry::{parse_params, ParamDoc, SolverEntry};
use junta_core::{LinearSolver, SolveReport, SolverError, SymmetricCsc};
use rayon::prelude::*;
use serde::Deserialize;
use std::time::Instant;

/// Settings of [`CholeskySolver`] (TOML parameters of the `cholesky` key).
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct CholeskySettings {
    /// Fill-reducing ordering: `"nested_dissection"` (default), `"amd"` or
    /// `"natural"`.
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
    /// Threads for the numeric factorisation (0: rayon's pool); the
    /// triangular solves are sequential.
    pub threads: usize,
}

impl Default for CholeskySettings {
    fn default() -> Self {
        CholeskySettings {
            ordering: OrderingKind::NestedDissection,
            refine_tol: 1e-8,
            max_refinements: 3,
            warn_tol: 1e-6,
            pivot_warn: 1e-12,
            pivot_fail: 1e-14,
            threads: 0,
        }
    }
}

/// Parameter documentation of the `cholesky` registry entry.
pub const CHOLESKY_PARAMS: &[ParamDoc] = &[
    ParamDoc {
        name: "ordering",
        doc: "fill-reducing ordering: \"nested_dissection\" (default; geometric with node coordinates), \"amd\", \"natural\"",
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
];

/// Numbers describing the last analysis and factorisation.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct CholeskyStats {
    /// Ordering used.
    pub ordering: &'static str,
    /// Number of symbolic analyses so far.
    pub analyze_count: usize,
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
    /// Smallest and largest diagonal entry of the last matrix.
    pub matrix_diag_min: f64,
    pub matrix_diag_max: f64,
    /// Smallest pivot ratio `l_kk^2 / a_kk` and the original equation where
    /// it occurs.
    pub min_pivot_ratio: f64,
    pub min_pivot_equation: usize,
    /// Refinement steps of the last solve.
    pub refinement_steps: usize,
}

/// Sparse Cholesky back end (registry key `"cholesky"`).
pub struct CholeskySolver {
    settings: CholeskySettings,
    pattern: Option<Pattern>,
    /// `perm[new] = old`, and its inverse.
    perm: Vec<usize>,
    perm_inv: Vec<usize>,
    factor: Option<PanelFactor>,
    factored: bool,
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
            factored: false,
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
        let n = matrix.n;
        self.factored = false;
        let perm = ordering::compute(self.settings.ordering, matrix, coords);
        debug_assert!(ordering::is_permutation(&perm, n));
        let ordering_seconds = t0.elapsed().as_secs_f64();
        let perm_inv = ordering::inverse(&perm);
        let a = SymbolicSparseColMatRef::new_checked(n, n, &matrix.col_ptr, None, &matrix.row_idx);
        let perm_ref = faer::perm::PermRef::new_checked(&perm, &perm_inv, n);
        let symbolic = factorize_symbolic_cholesky(
            a,
            Side::Upper,
            SymmetricOrdering::Custom(perm_ref),
            CholeskySymbolicParams {
                supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SUPERNODAL,
                ..Default::default()
            },
        )
        .map_err(|e| SolverError::Usage(format!("symbolic Cholesky failed: {e:?}")))?;
        let SymbolicCholeskyRaw::Supernodal(sn) = symbolic.raw() else {
            return Err(SolverError::Usage(
                "symbolic Cholesky: supernodal structure expected".into(),
            ));
        };
        let factor = PanelFactor::new(sn);
        drop(symbolic);
        self.stats.supernodal = true;
        self.stats.factor_nonzeros = factor.nonzeros();
        self.factor = Some(factor);
        self.stats.ordering = self.settings.ordering.name();
        self.stats.ordering_seconds = ordering_seconds;
        self.stats.analyze_count += 1;
        self.perm = perm;
        self.perm_inv = perm_inv;
        self.pattern = Some(Pattern::of(matrix));
        let secs = t0.elapsed().as_secs_f64();
        self.report.analyze_seconds += secs;
        self.report.factor_nonzeros = self.stats.factor_nonzeros;
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

    fn factorize(&mut self, matrix: &SymmetricCsc) -> Result<(), SolverError> {
        let t0 = Instant::now();
        let Some(pattern) = &self.pattern else {
            return Err(SolverError::Usage(
                "cholesky: factorize called before analyze".into(),
            ));
        };
        pattern.check(matrix, "cholesky factorize")?;
        self.factored = false;
        // Warnings describe the current factor: start afresh.
        self.report.warnings.clear();
        self.factor_warnings.clear();
        let n = matrix.n;
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
                        ": diagonal entry of equation {i} is {d:e} (an equation with no stiffness, or a missing constraint)"
                    ),
                });
            }
            dmin = dmin.min(d);
            dmax = dmax.max(d);
        }
        self.stats.matrix_diag_min = dmin;
        self.stats.matrix_diag_max = dmax;

        let par = self.par();
        let factor = self.factor.as_mut().expect("analysed");
        if let Err(k) = factor.factorize(matrix, &self.perm_inv, par) {
            // k: the failing column of the permuted matrix; name the
            // original equation.
            let k = k.min(n.saturating_sub(1));
            let eq = self.perm[k];
            self.stats.factor_count += 1;
            self.report.factor_seconds += t0.elapsed().as_secs_f64();
            return Err(SolverError::NotPositiveDefinite {
                detail: format!(
                    ": non-positive pivot at elimination step {k} of {n} (about equation {eq}, diagonal {:.3e}); matrix diagonal in [{dmin:.3e}, {dmax:.3e}]",
                    diag[eq]
                ),
            });
        }
        self.stats.factor_count += 1;

        // Pivot ratios l_kk^2 / a_kk.
        let ldiag = self.factor.as_ref().expect("analysed").diagonal();
        let (mut rmin, mut kmin) = (f64::INFINITY, 0usize);
        for (k, &l) in ldiag.iter().enumerate() {
            let r = l * l / diag[self.perm[k]];
            if r.is_nan() || r < rmin {
                rmin = r;
                kmin = k;
            }
        }
        let eq = self.perm.get(kmin).copied().unwrap_or(0);
        self.stats.min_pivot_ratio = rmin;
        self.stats.min_pivot_equation = eq;
        let spread = dmax / dmin;
        self.report.factor_seconds += t0.elapsed().as_secs_f64();
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
        self.factored = true;
        Ok(())
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
        let rhs = b.to_vec();
        let bnorm = norm2(&rhs);
        self.stats.solve_count += 1;
        self.stats.refinement_steps = 0;
        if bnorm == 0.0 {
            b.fill(0.0);
            self.report.residual = 0.0;
            self.report.solve_seconds += t0.elapsed().as_secs_f64();
            return Ok(());
        }
        let factor = self.factor.as_ref().expect("analysed");
        let (perm, perm_inv) = (&self.perm, &self.perm_inv);
        let mut work = vec![0.0; n];
        let mut apply = |v: &mut [f64]| {
            for (k, w) in work.iter_mut().enumerate() {
                *w = v[perm[k]];
            }
            factor.solve_permuted(&mut work);
            for (i, x) in v.iter_mut().enumerate() {
                *x = work[perm_inv[i]];
            }
        };
        apply(b);
        let mut r = vec![0.0; n];
        let mut rel = residual(matrix, b, &rhs, &mut r) / bnorm;
        let mut steps = 0;
        while rel.is_finite()
            && rel > self.settings.refine_tol
            && steps < self.settings.max_refinements
        {
            apply(&mut r);
            let mut trial = b.to_vec();
            for (t, d) in trial.iter_mut().zip(&r) {
                *t += d;
            }
            let mut r2 = vec![0.0; n];
            let rel2 = residual(matrix, &trial, &rhs, &mut r2) / bnorm;
            steps += 1;
            if rel2.is_nan() || rel2 >= rel {
                break; // refinement no longer helps
            }
            b.copy_from_slice(&trial);
            r = r2;
            rel = rel2;
        }
        self.stats.refinement_steps = steps;
        self.report.residual = rel;
        self.report.solve_seconds += t0.elapsed().as_secs_f64();
        if !rel.is_finite() || b.iter().any(|v| !v.is_finite()) {
            b.copy_from_slice(&rhs);
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

    fn report(&self) -> SolveReport {
        self.report.clone()
    }
}

/// Widest block of columns stored as one dense panel. faer's supernodal
/// layout stores the whole square diagonal block of every supernode (the
/// root separator of a 100k-equation cube is a 5459-column supernode: 120 MB
/// of zeros above its diagonal); splitting wide supernodes into panels of at
/// most this width bounds that waste by `PANEL / 2` entries per column.
const PANEL: usize = 256;

/// Branching depth of the elimination tree down to which subtrees become
/// separate rayon tasks (2^depth subtrees is plenty for a few threads).
const MAX_TASK_DEPTH: usize = 12;

/// Supernodal Cholesky factor `P A P^T = L L^T` in panel storage, factorised
/// left-looking with subtree parallelism (independent subtrees of the
/// supernodal elimination tree run as rayon tasks; the dense kernels of
/// large panels run in parallel too). The supernode partition and row
/// structure come from faer's symbolic analysis; wide supernodes are split
/// into panels (a panel of a supernode is itself a valid supernode whose
/// structure is the rest of its supernode plus the supernode's rows).
///
/// Panel `s` covers the permuted columns `begin[s]..begin[s + 1]` (width
/// `w`), with below-diagonal rows `pat[pat_ptr[s]..pat_ptr[s + 1]]` (`r`
/// rows); its values are the column-major `(w + r) x w` block at
/// `values[val_ptr[s]..]` (the upper triangle of the `w x w` diagonal block
/// is unused).
#[derive(Debug, Default)]
struct PanelFactor {
    n: usize,
    begin: Vec<usize>,
    pat_ptr: Vec<usize>,
    pat: Vec<u32>,
    val_ptr: Vec<usize>,
    /// Panel of each permuted column.
    panel_of: Vec<u32>,
    /// Children in the panel elimination tree (CSR) and the roots.
    child_ptr: Vec<usize>,
    child: Vec<u32>,
    roots: Vec<u32>,
    /// Descendants updating each panel (CSR).
    desc_ptr: Vec<usize>,
    desc: Vec<u32>,
    values: Vec<f64>,
}

/// `dst (+)= alpha lhs rhs^T` where the top `mid x mid` block of the
/// product (`mid` = rows of `rhs`) is symmetric: only its lower triangle is
/// computed (the rest of `dst`'s top block is left alone), then the
/// rectangle below it with a plain product.
fn sym_update(
    dst: MatMut<'_, f64>,
    lhs: MatRef<'_, f64>,
    rhs: MatRef<'_, f64>,
    beta: Accum,
    alpha: f64,
    par: Par,
) {
    use faer::linalg::matmul::triangular::{self, BlockStructure};
    let mid = rhs.nrows();
    let (dst_top, dst_bot) = dst.split_at_row_mut(mid);
    let (lhs_top, lhs_bot) = lhs.split_at_row(mid);
    triangular::matmul(
        dst_top,
        BlockStructure::TriangularLower,
        beta,
        lhs_top,
        BlockStructure::Rectangular,
        rhs.transpose(),
        BlockStructure::Rectangular,
        alpha,
        par,
    );
    if dst_bot.nrows() > 0 {
        faer::linalg::matmul::matmul(dst_bot, beta, lhs_bot, rhs.transpose(), alpha, par);
    }
}

/// Pointer wrapper for writes to disjoint parts of the factor from rayon tasks.
#[derive(Clone, Copy)]
struct SharedPtr(*mut f64);
unsafe impl Send for SharedPtr {}
unsafe impl Sync for SharedPtr {}
impl SharedPtr {
    /// The pointer (a method, so closures capture the `Sync` wrapper).
    #[inline]
    fn get(self) -> *mut f64 {
        self.0
    }
}

impl PanelFactor {
    fn n_panels(&self) -> usize {
        self.begin.len() - 1
    }

    fn pattern(&self, s: usize) -> &[u32] {
        &self.pat[self.pat_ptr[s]..self.pat_ptr[s + 1]]
    }

    /// Stored entries (lower trapezoids only).
    fn nonzeros(&self) -> usize {
        (0..self.n_panels())
            .map(|s| {
                let w = self.begin[s + 1] - self.begin[s];
                w * (w + 1) / 2 + w * (self.pat_ptr[s + 1] - self.pat_ptr[s])
            })
            .sum()
    }

    /// Panels from faer's supernodal symbolic structure.
    fn new(
        sym: &faer::sparse::linalg::cholesky::supernodal::SymbolicSupernodalCholesky<usize>,
    ) -> Self {
        let n = sym.nrows();
        let ns = sym.n_supernodes();
        let sb = sym.supernode_begin();
        let se = sym.supernode_end();
        let cpr = sym.col_ptr_for_row_idx();
        let nps = sym.nnz_per_super();
        let rows = sym.row_idx();
        let mut begin = vec![0usize];
        let mut pat_ptr = vec![0usize];
        let mut pat: Vec<u32> = Vec::new();
        let mut val_ptr = vec![0usize];
        let pw = PANEL;
        for k in 0..ns {
            let (b, e) = (sb[k], se[k]);
            let below = &rows[cpr[k]..cpr[k] + nps[k]];
            let mut c0 = b;
            while c0 < e {
                let c1 = (c0 + pw).min(e);
                pat.extend((c1..e).map(|i| i as u32));
                pat.extend(below.iter().map(|&i| i as u32));
                let r = (e - c1) + below.len();
                let w = c1 - c0;
                begin.push(c1);
                pat_ptr.push(pat.len());
                val_ptr.push(val_ptr.last().unwrap() + (w + r) * w);
                c0 = c1;
            }
        }
        let np = begin.len() - 1;
        let mut panel_of = vec![0u32; n];
        for s in 0..np {
            panel_of[begin[s]..begin[s + 1]].fill(s as u32);
        }
        // elimination tree of panels: parent = panel of the first row below
        let mut parent = vec![u32::MAX; np];
        let mut nchild = vec![0usize; np + 1];
        let mut roots = Vec::new();
        for s in 0..np {
            match pat[pat_ptr[s]..pat_ptr[s + 1]].first() {
                Some(&r) => {
                    let p = panel_of[r as usize];
                    parent[s] = p;
                    nchild[p as usize + 1] += 1;
                }
                None => roots.push(s as u32),
            }
        }
        for s in 0..np {
            nchild[s + 1] += nchild[s];
        }
        let child_ptr = nchild.clone();
        let mut next = nchild;
        let mut child = vec![0u32; np.saturating_sub(roots.len())];
        for s in 0..np {
            if parent[s] != u32::MAX {
                let p = parent[s] as usize;
                child[next[p]] = s as u32;
                next[p] += 1;
            }
        }
        // descendants updating each panel: panels hit by d's rows
        let mut count = vec![0usize; np + 1];
        for d in 0..np {
            let mut last = u32::MAX;
            for &r in &pat[pat_ptr[d]..pat_ptr[d + 1]] {
                let s = panel_of[r as usize];
                if s != last {
                    count[s as usize + 1] += 1;
                    last = s;
                }
            }
        }
        for s in 0..np {
            count[s + 1] += count[s];
        }
        let desc_ptr = count.clone();
        let mut next = count;
        let mut desc = vec![0u32; desc_ptr[np]];
        for d in 0..np {
            let mut last = u32::MAX;
            for &r in &pat[pat_ptr[d]..pat_ptr[d + 1]] {
                let s = panel_of[r as usize];
                if s != last {
                    desc[next[s as usize]] = d as u32;
                    next[s as usize] += 1;
                    last = s;
                }
            }
        }
        PanelFactor {
            n,
            begin,
            pat_ptr,
            pat,
            val_ptr,
            panel_of,
            child_ptr,
            child,
            roots,
            desc_ptr,
            desc,
            values: Vec::new(),
        }
    }

    fn len_val(&self) -> usize {
        *self.val_ptr.last().unwrap()
    }

    /// Numeric factorisation of `P A P^T` (`A` upper CSC, `perm_inv[old] =
    /// new`). `Err(k)`: non-positive pivot at permuted column `k`.
    fn factorize(&mut self, a: &SymmetricCsc, perm_inv: &[usize], par: Par) -> Result<(), usize> {
        if self.values.len() != self.len_val() {
            self.values = Vec::new();
            self.values = vec![0.0; self.len_val()];
        } else {
            self.values.par_iter_mut().for_each(|v| *v = 0.0);
        }
        let ptr = SharedPtr(self.values.as_mut_ptr());
        let this = &*self;
        // scatter A: entry (i, j) of P A P^T with i >= j goes to the panel of j
        (0..a.n).into_par_iter().with_min_len(256).for_each(|c| {
            let jc = perm_inv[c];
            for p in a.col_ptr[c]..a.col_ptr[c + 1] {
                let ir = perm_inv[a.row_idx[p]];
                let (i, j) = if ir >= jc { (ir, jc) } else { (jc, ir) };
                let s = this.panel_of[j] as usize;
                let (b, e) = (this.begin[s], this.begin[s + 1]);
                let w = e - b;
                let pat = this.pattern(s);
                let m = w + pat.len();
                let lr = if i < e {
                    i - b
                } else {
                    w + pat.binary_search(&(i as u32)).expect("structure covers A")
                };
                // SAFETY: every entry of A maps to its own position.
                unsafe { *ptr.get().add(this.val_ptr[s] + (j - b) * m + lr) = a.values[p] };
            }
        });
        let threads = match par {
            Par::Seq => 1,
            Par::Rayon(t) => t.get(),
        };
        if threads > 1 {
            this.roots
                .par_iter()
                .try_for_each(|&s| this.run_subtree(s as usize, ptr, threads, 0))
        } else {
            // panels are numbered in elimination order: descendants first
            let mut tmp = Vec::new();
            for s in 0..this.n_panels() {
                this.factor_panel(s, ptr, 1, &mut tmp)?;
            }
            Ok(())
        }
    }

    /// Factor the subtree rooted at `s`: children subtrees in parallel, then
    /// the chain of single-child ancestors up to `s` in order. Below
    /// [`MAX_TASK_DEPTH`] branchings (where there are far more subtrees than
    /// threads) a subtree is factorised sequentially, without recursion.
    fn run_subtree(
        &self,
        s: usize,
        ptr: SharedPtr,
        threads: usize,
        depth: usize,
    ) -> Result<(), usize> {
        let children = |x: usize| &self.child[self.child_ptr[x]..self.child_ptr[x + 1]];
        let mut tmp = Vec::new();
        if depth >= MAX_TASK_DEPTH {
            let mut nodes = Vec::new();
            let mut stack = vec![s as u32];
            while let Some(x) = stack.pop() {
                nodes.push(x);
                stack.extend_from_slice(children(x as usize));
            }
            // descendants have smaller numbers than their ancestors
            nodes.sort_unstable();
            for &x in &nodes {
                self.factor_panel(x as usize, ptr, threads, &mut tmp)?;
            }
            return Ok(());
        }
        let mut chain = vec![s];
        let mut cur = s;
        while let [only] = children(cur) {
            cur = *only as usize;
            chain.push(cur);
        }
        children(cur)
            .par_iter()
            .try_for_each(|&c| self.run_subtree(c as usize, ptr, threads, depth + 1))?;
        for &x in chain.iter().rev() {
            self.factor_panel(x, ptr, threads, &mut tmp)?;
        }
        Ok(())
    }

    /// Left-looking update and dense factorisation of panel `s`.
    fn factor_panel(
        &self,
        s: usize,
        ptr: SharedPtr,
        threads: usize,
        tmp: &mut Vec<f64>,
    ) -> Result<(), usize> {
        let (b, e) = (self.begin[s], self.begin[s + 1]);
        let w = e - b;
        let pat_s = self.pattern(s);
        let m = w + pat_s.len();
        // SAFETY: panel s is written only here; its descendants are complete
        // and only read.
        let ls_slice =
            unsafe { std::slice::from_raw_parts_mut(ptr.get().add(self.val_ptr[s]), m * w) };
        let mut ls = MatMut::from_column_major_slice_mut(ls_slice, m, w);
        let big = threads > 1 && m * w >= 128 * 128;
        let par = if big { Par::rayon(threads) } else { Par::Seq };
        let mut loc: Vec<u32> = Vec::new();
        for &d in &self.desc[self.desc_ptr[s]..self.desc_ptr[s + 1]] {
            let d = d as usize;
            let wd = self.begin[d + 1] - self.begin[d];
            let pd = self.pattern(d);
            let md = wd + pd.len();
            let k0 = pd.partition_point(|&x| (x as usize) < b);
            let k1 = k0 + pd[k0..].partition_point(|&x| (x as usize) < e);
            let (len, mid) = (pd.len() - k0, k1 - k0);
            let ld = unsafe {
                std::slice::from_raw_parts(ptr.get().add(self.val_ptr[d]) as *const f64, md * wd)
            };
            let ld = MatRef::from_column_major_slice(ld, md, wd);
            let lhs = ld.subrows(wd + k0, len);
            let rhs = ld.subrows(wd + k0, mid);
            let p = if threads > 1 && len * mid * wd >= 1 << 21 {
                Par::rayon(threads)
            } else {
                Par::Seq
            };
            // local rows in panel s
            loc.clear();
            let mut q = 0usize;
            for &g in &pd[k0..] {
                let g = g as usize;
                if g < e {
                    loc.push((g - b) as u32);
                } else {
                    while pat_s[q] as usize != g {
                        q += 1;
                    }
                    loc.push((w + q) as u32);
                }
            }
            let (l0, ln) = (loc[0] as usize, loc[len - 1] as usize);
            if ln - l0 == len - 1 {
                // contiguous rows (e.g. an earlier panel of the same
                // supernode): update in place, no scatter
                let dst = ls.rb_mut().submatrix_mut(l0, l0, len, mid);
                sym_update(dst, lhs, rhs, Accum::Add, -1.0, p);
                continue;
            }
            tmp.clear();
            tmp.resize(len * mid, 0.0);
            let t = MatMut::from_column_major_slice_mut(&mut tmp[..], len, mid);
            sym_update(t, lhs, rhs, Accum::Replace, 1.0, p);
            for jj in 0..mid {
                let lc = loc[jj] as usize;
                let col = ls
                    .rb_mut()
                    .col_mut(lc)
                    .try_as_col_major_mut()
                    .unwrap()
                    .as_slice_mut();
                let tc = &tmp[jj * len..(jj + 1) * len];
                for ii in jj..len {
                    col[loc[ii] as usize] -= tc[ii];
                }
            }
        }
        let (mut top, bot) = ls.rb_mut().split_at_row_mut(w);
        let mut mem = MemBuffer::new(
            faer::linalg::cholesky::llt::factor::cholesky_in_place_scratch::<f64>(
                w,
                par,
                Default::default(),
            ),
        );
        match faer::linalg::cholesky::llt::factor::cholesky_in_place(
            top.rb_mut(),
            LltRegularization::default(),
            par,
            MemStack::new(&mut mem),
            Default::default(),
        ) {
            Ok(_) => {}
            Err(DenseLltError::NonPositivePivot { index }) => return Err(b + index),
        }
        if bot.nrows() > 0 {
            faer::linalg::triangular_solve::solve_lower_triangular_in_place(
                top.rb().conjugate(),
                bot.transpose_mut(),
                par,
            );
        }
        Ok(())
    }

    /// Diagonal of `L` (permuted numbering).
    fn diagonal(&self) -> Vec<f64> {
        let mut d = vec![0.0; self.n];
        for s in 0..self.n_panels() {
            let (b, e) = (self.begin[s], self.begin[s + 1]);
            let m = (e - b) + self.pat_ptr[s + 1] - self.pat_ptr[s];
            for c in 0..e - b {
                d[b + c] = self.values[self.val_ptr[s] + c * m + c];
            }
        }
        d
    }

    /// `x <- (L L^T)^-1 x` in the permuted numbering.
    fn solve_permuted(&self, x: &mut [f64]) {
        let np = self.n_panels();
        for s in 0..np {
            let (b, e) = (self.begin[s], self.begin[s + 1]);
            let w = e - b;
            let pat = self.pattern(s);
            let m = w + pat.len();
            let v = &self.values[self.val_ptr[s]..self.val_ptr[s] + m * w];
            for j in 0..w {
                let col = &v[j * m..(j + 1) * m];
                let xj = x[b + j] / col[j];
                x[b + j] = xj;
                for i in j + 1..w {
                    x[b + i] -= col[i] * xj;
                }
                for (k, &g) in pat.iter().enumerate() {
                    x[g as usize] -= col[w + k] * xj;
                }
            }
        }
        for s in (0..np).rev() {
            let (b, e) = (self.begin[s], self.begin[s + 1]);
            let w = e - b;
            let pat = self.pattern(s);
            let m = w + pat.len();
            let v = &self.values[self.val_ptr[s]..self.val_ptr[s] + m * w];
            for j in (0..w).rev() {
                let col = &v[j * m..(j + 1) * m];
                let mut acc = x[b + j];
                for i in j + 1..w {
                    acc -= col[i] * x[b + i];
                }
                for (k, &g) in pat.iter().enumerate() {
                    acc -= col[w + k] * x[g as usize];
                }
                x[b + j] = acc / col[j];
            }
        }
    }
}

inventory::submit! {
    SolverEntry {
        key: "cholesky",
        description: "sparse supernodal Cholesky (faer) with nested-dissection or AMD ordering, iterative refinement and conditioning warnings",
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
        let mut s = CholeskySolver::default();
        let mut b = vec![1.0, 2.0, 3.0];
        assert!(matches!(s.factorize(&a), Err(SolverError::Usage(_))));
        s.analyze(&a, None).unwrap();
        assert!(matches!(
            s.solve_in_place(&a, &mut b),
            Err(SolverError::Usage(_))
        ));
        s.factorize(&a).unwrap();
        s.solve_in_place(&a, &mut b).unwrap();
        let mut y = vec![0.0; 3];
        a.mul_vec(&b, &mut y);
        for (yi, bi) in y.iter().zip([1.0, 2.0, 3.0]) {
            assert!((yi - bi).abs() < 1e-14);
        }
        let r = s.report();
        assert!(r.residual < 1e-15);
        assert!(r.factor_nonzeros >= 5);
        assert!(r.warnings.is_empty());
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
                assert!(detail.contains("equation 1"), "{detail}")
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
            let widest = (0..f.n_panels())
                .map(|p| f.begin[p + 1] - f.begin[p])
                .max()
                .unwrap();
            assert_eq!(widest, PANEL, "a supernode wider than a panel was split");
            // stored entries: exact fill plus the explicit zeros of merged
            // (relaxed) supernodes
            assert!(
                s.stats().factor_nonzeros >= ordering::factor_nonzeros(&a, Some(s.permutation()))
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
    fn params_reject_unknown_keys() {
        let t: toml::Table = toml::from_str("ordering = \"amd\"\nrefine_tol = 1e-9").unwrap();
        let s = CholeskySolver::from_table(&t).unwrap();
        assert_eq!(s.settings().ordering, OrderingKind::Amd);
        assert_eq!(s.settings().refine_tol, 1e-9);
        let bad: toml::Table = toml::from_str("orderin = \"amd\"").unwrap();
        assert!(CholeskySolver::from_table(&bad).is_err());
    }
}
