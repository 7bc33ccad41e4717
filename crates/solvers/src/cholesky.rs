//! Sparse direct solver: faer's supernodal Cholesky `P A P^T = L L^T` with a
//! nested-dissection (default) or AMD ordering `P`.
//!
//! # Phases
//!
//! * [`LinearSolver::analyze`]: the fill-reducing ordering `P`
//!   ([`crate::ordering`]), then faer's symbolic factorisation with
//!   `SymmetricOrdering::Custom(P)`: elimination tree, column counts,
//!   supernodes, and the row structure of `L`. Done once per pattern.
//! * [`LinearSolver::factorize`]: numeric `L L^T` into a value buffer that is
//!   allocated once (its length is fixed by the symbolic structure) and
//!   reused for every later matrix with the same pattern. A pivot
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
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, supernodal::SupernodalLltRef, CholeskySymbolicParams, LltRef,
    SymbolicCholesky, SymbolicCholeskyRaw, SymmetricOrdering,
};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par, Side};
use junta_core::registry::{parse_params, ParamDoc, SolverEntry};
use junta_core::{LinearSolver, SolveReport, SolverError, SymmetricCsc};
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
    /// Threads for the numeric factorisation and solves (0: rayon's pool).
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
    symbolic: Option<SymbolicCholesky<usize>>,
    l_values: Vec<f64>,
    factored: bool,
    factor_mem: Option<MemBuffer>,
    solve_mem: Option<MemBuffer>,
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
            symbolic: None,
            l_values: Vec::new(),
            factored: false,
            factor_mem: None,
            solve_mem: None,
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

    /// Diagonal of `L` in the permuted numbering.
    fn factor_diagonal(&self) -> Vec<f64> {
        let symbolic = self.symbolic.as_ref().expect("analysed");
        let n = symbolic.nrows();
        let mut diag = vec![0.0; n];
        match symbolic.raw() {
            SymbolicCholeskyRaw::Supernodal(s) => {
                let l = SupernodalLltRef::new(s, &self.l_values);
                for k in 0..s.n_supernodes() {
                    let node = l.supernode(k);
                    let start = node.start();
                    let val = node.val();
                    let width = val.ncols();
                    for c in 0..width {
                        diag[start + c] = val[(c, c)];
                    }
                }
            }
            SymbolicCholeskyRaw::Simplicial(s) => {
                // the diagonal is the first entry of each column of L
                let col_ptr = s.col_ptr();
                for (k, d) in diag.iter_mut().enumerate() {
                    *d = self.l_values[col_ptr[k]];
                }
            }
        }
        diag
    }

    fn stored_factor_nonzeros(symbolic: &SymbolicCholesky<usize>) -> usize {
        match symbolic.raw() {
            SymbolicCholeskyRaw::Supernodal(s) => {
                let begin = s.supernode_begin();
                let end = s.supernode_end();
                let col_ptr_row = s.col_ptr_for_row_idx();
                (0..s.n_supernodes())
                    .map(|k| {
                        let w = end[k] - begin[k];
                        let below = col_ptr_row[k + 1] - col_ptr_row[k];
                        w * (w + 1) / 2 + w * below
                    })
                    .sum()
            }
            SymbolicCholeskyRaw::Simplicial(s) => s.len_val(),
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
            CholeskySymbolicParams::default(),
        )
        .map_err(|e| SolverError::Usage(format!("symbolic Cholesky failed: {e:?}")))?;
        self.l_values = vec![0.0; symbolic.len_val()];
        let par = self.par();
        self.factor_mem = Some(MemBuffer::new(
            symbolic.factorize_numeric_llt_scratch::<f64>(par, Default::default()),
        ));
        self.solve_mem = Some(MemBuffer::new(
            symbolic.solve_in_place_scratch::<f64>(1, par),
        ));
        self.stats.supernodal = matches!(symbolic.raw(), SymbolicCholeskyRaw::Supernodal(_));
        self.stats.factor_nonzeros = Self::stored_factor_nonzeros(&symbolic);
        self.stats.ordering = self.settings.ordering.name();
        self.stats.ordering_seconds = ordering_seconds;
        self.stats.analyze_count += 1;
        self.symbolic = Some(symbolic);
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
        let symbolic = self.symbolic.as_ref().expect("analysed");
        let a = SparseColMatRef::new(
            SymbolicSparseColMatRef::new_checked(n, n, &matrix.col_ptr, None, &matrix.row_idx),
            &matrix.values,
        );
        let mem = self.factor_mem.as_mut().expect("analysed");
        let result = symbolic.factorize_numeric_llt(
            &mut self.l_values,
            a,
            Side::Upper,
            LltRegularization::default(),
            par,
            MemStack::new(mem),
            Default::default(),
        );
        match result {
            Ok(_) => {}
            Err(DenseLltError::NonPositivePivot { index }) => {
                // faer reports the failing column of the permuted matrix
                // (1-based in the simplicial kernel, 0-based in the
                // supernodal one); name the original equation.
                let k = if self.stats.supernodal {
                    index
                } else {
                    index.saturating_sub(1)
                };
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
        }
        self.stats.factor_count += 1;

        // Pivot ratios l_kk^2 / a_kk.
        let ldiag = self.factor_diagonal();
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
        let par = self.par();
        let symbolic = self.symbolic.as_ref().expect("analysed");
        let llt = LltRef::new(symbolic, &self.l_values);
        let mem = self.solve_mem.as_mut().expect("analysed");
        let mut apply = |v: &mut [f64]| {
            llt.solve_in_place_with_conj(
                Conj::No,
                MatMut::from_column_major_slice_mut(v, n, 1),
                par,
                MemStack::new(mem),
            );
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
    fn params_reject_unknown_keys() {
        let t: toml::Table = toml::from_str("ordering = \"amd\"\nrefine_tol = 1e-9").unwrap();
        let s = CholeskySolver::from_table(&t).unwrap();
        assert_eq!(s.settings().ordering, OrderingKind::Amd);
        assert_eq!(s.settings().refine_tol, 1e-9);
        let bad: toml::Table = toml::from_str("orderin = \"amd\"").unwrap();
        assert!(CholeskySolver::from_table(&bad).is_err());
    }
}
