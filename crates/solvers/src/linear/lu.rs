//! Sparse direct solver for general (nonsymmetric) matrices: supernodal
//! `LU` (registry key `"lu"`), for the tangents of friction,
//! non-associated plasticity and the exact mixed-mode cohesive tangent.
//!
//! # Method
//!
//! `P_r P A P^T = L U` with `L` unit lower triangular, `U` upper
//! triangular, `P` the fill-reducing ordering and `P_r` row interchanges.
//!
//! - **Ordering.** `P` is the ordering of the shared analysis of the
//!   symmetric back ends (`supernodal::analyze`: nested dissection
//!   or AMD on the pattern of `A + A^T`, by predicted flops). The assembled
//!   pattern is structurally symmetric; this is SuperLU's `MMD_AT_PLUS_A`
//!   choice, which suits matrices with a nearly symmetric structure better
//!   than a column ordering of `A^T A` (COLAMD, faer's default).
//! - **Restricted pivoting (default, [`LuPivoting::Auto`]).** The factor
//!   keeps the structure of the symmetric (Cholesky) factor and takes its
//!   row interchanges within each panel's diagonal block
//!   (the private module `panel_lu`, maths there): left-looking over the panels of
//!   the shared analysis, two BLAS-3 updates per descendant (`L` and `U`
//!   sides), a dense partial-pivoting `LU` of the diagonal block and two
//!   triangular solves. Stored entries: `|J|^2 + 2 |J| |R|` per panel, about
//!   twice `L D L^T`'s. Measured on the 12,420-equation mixed-mode bending
//!   model (`examples/delamination/mmb80_short.toml`, `tangent = "exact"`):
//!   1.7M entries and 23 ms per factorisation, against 127M entries and 8 s
//!   for unrestricted partial pivoting.
//! - **Fallback.** A pivot column with no entry above `tiny_pivot
//!   ||A||_inf` within its panel (a zero diagonal eliminated before the rows
//!   that could replace it) makes `auto` refactorise the matrix with faer's
//!   supernodal numeric LU with unrestricted partial pivoting, for the rest
//!   of the run, with a note; `restricted` perturbs such pivots (static
//!   pivoting, PARDISO's approach) and leaves the rest to refinement;
//!   `partial` uses faer's from the start. Before falling back, `auto`
//!   tells a singular matrix from one that only needs a row from below
//!   the panel: a pivot whose whole Schur-complement column is below
//!   `tiny_pivot ||A||_inf` (rows below the panel included) can be helped
//!   by no interchange, and the factorisation stops at once with
//!   [`SolverError::NotPositiveDefinite`] naming its step and equation
//!   (maths in `panel_lu`). The fallback's factor is predicted by its
//!   symbolic analysis before any numeric work, and refused
//!   ([`SolverError::FillLimit`]) when it exceeds `max_fallback_fill`
//!   times the restricted factor's entries or the memory available: a
//!   singular tangent once sent `auto` into minutes of dense products on a
//!   factor 75 times larger, every iteration, without a word. faer's symbolic analysis with
//!   `P`: the column elimination tree of `A P^T` (the elimination tree of
//!   `P A^T A P^T`), its postorder, the column counts of the Cholesky factor
//!   of `P A^T A P^T` (an upper bound of the structure of `L` and `U` for
//!   every row pivoting: George and Ng) and the supernodes. The values of
//!   `A` (and of `A^T`, which faer also reads) are scattered from
//!   [`SymmetricCsc::values`] / `lower` through maps built in the analysis.
//! - **Solve.** `x = P^T U^{-1} L^{-1} P_r P b`, then iterative refinement
//!   (`r = b - A x`, `x += (LU)^{-1} r`) while the relative residual is
//!   above `refine_tol`, at most `max_refinements` times. A non-finite
//!   solution (a singular matrix: zero pivot) is an error with its numbers.
//!
//! The report's `factor_nonzeros` counts the stored entries of `L + U`
//! (restricted pivoting) or the bound `2 nnz(L_c) - n` of faer's analysis
//! (`L_c` the Cholesky factor of `P A^T A P^T`), not the count of the
//! factor computed.
//!
//! A symmetric matrix ([`SymmetricCsc::is_general`] false) is accepted too
//! (mirrored), so `lu` solves every [`MatrixKind`].

use crate::common::{norm2, residual, symmetric_norm_inf, validate, Pattern};
use crate::ordering::OrderingKind;
use crate::panel_lu::{PanelLu, PanelLuStats};
use crate::supernodal::PanelFactor;
use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::lu::partial_pivoting::factor::PartialPivLuParams;
use faer::sparse::linalg::lu::supernodal::{
    factorize_supernodal_numeric_lu, factorize_supernodal_numeric_lu_scratch,
    factorize_supernodal_symbolic_lu, factorize_supernodal_symbolic_lu_scratch,
    solve_in_place_scratch, SupernodalLu, SymbolicSupernodalLu,
};
use faer::sparse::linalg::qr::{
    col_etree, col_etree_scratch, column_counts_aat_scratch, column_counts_ata, postorder,
    postorder_scratch,
};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par, Spec};
use junta_core::registry::{parse_params, ParamDoc, SolverEntry};
use junta_core::{LinearSolver, MatrixKind, SolveReport, SolverError, SymmetricCsc};
use serde::Deserialize;
use std::time::Instant;

/// Settings of [`LuSolver`] (TOML parameters of the `lu` key).
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct LuSettings {
    /// Fill-reducing ordering: `"auto"` (default), `"nested_dissection"`,
    /// `"amd"` or `"natural"` (the analysis shared with `cholesky`).
    pub ordering: OrderingKind,
    /// Relative residual above which iterative refinement runs (1e-12).
    pub refine_tol: f64,
    /// Maximum refinement steps per solve (3).
    pub max_refinements: usize,
    /// Relative residual after refinement above which the report warns (1e-6).
    pub warn_tol: f64,
    /// Threads for the numeric factorisation (0: rayon's pool).
    pub threads: usize,
    /// Row pivoting ([`LuPivoting`]; default `auto`).
    pub pivoting: LuPivoting,
    /// Restricted pivoting: pivot columns whose entries in the panel are at
    /// most `tiny_pivot ||A||_inf` are perturbed (default `f64::EPSILON`).
    pub tiny_pivot: f64,
    /// Size of a perturbed pivot relative to `||A||_inf` (default
    /// `sqrt(f64::EPSILON)`).
    pub perturbation: f64,
    /// `auto`: the largest factor of unrestricted partial pivoting, as a
    /// multiple of the restricted factor's stored entries, that the
    /// fallback may take (default 100; the 12,420-equation mixed-mode
    /// bending model's is 75). Above it, or above the memory available,
    /// the fallback is refused before it starts
    /// ([`SolverError::FillLimit`]).
    pub max_fallback_fill: f64,
}

/// How [`LuSolver`] pivots.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum LuPivoting {
    /// Restricted pivoting on the symmetric structure
    /// (module `panel_lu`); when a pivot has to be perturbed, the matrix
    /// is refactorised with unrestricted partial pivoting, and the run stays
    /// with it (a note says so).
    #[default]
    Auto,
    /// Restricted pivoting on the symmetric structure only: perturbed
    /// pivots are left to iterative refinement.
    Restricted,
    /// faer's supernodal LU with unrestricted partial pivoting on the
    /// structure of `A^T A`.
    Partial,
}

impl Default for LuSettings {
    fn default() -> Self {
        LuSettings {
            ordering: OrderingKind::default(),
            refine_tol: 1e-12,
            max_refinements: 3,
            warn_tol: 1e-6,
            threads: 0,
            pivoting: LuPivoting::Auto,
            tiny_pivot: f64::EPSILON,
            perturbation: f64::EPSILON.sqrt(),
            max_fallback_fill: 100.0,
        }
    }
}

/// Parameters of the `lu` registry entry.
pub const LU_PARAMS: &[ParamDoc] = &[
    ParamDoc {
        name: "ordering",
        doc: "fill-reducing column ordering: \"auto\" (default: nested dissection or AMD on A + A^T, whichever is predicted cheaper), \"nested_dissection\", \"amd\", \"natural\"",
    },
    ParamDoc {
        name: "refine_tol",
        doc: "relative residual above which iterative refinement runs (default 1e-12)",
    },
    ParamDoc {
        name: "max_refinements",
        doc: "maximum refinement steps per solve (default 3)",
    },
    ParamDoc {
        name: "warn_tol",
        doc: "relative residual after refinement above which the report warns (default 1e-6)",
    },
    ParamDoc {
        name: "threads",
        doc: "threads of the numeric factorisation (default 0: all)",
    },
    ParamDoc {
        name: "pivoting",
        doc: "\"auto\" (default: row interchanges within each panel of the symmetric factor's structure, the cost of about two Cholesky factors; a matrix that needs a pivot from outside a panel is refactorised with unrestricted partial pivoting for the rest of the run, with a note), \"restricted\" (never falls back: perturbed pivots, then iterative refinement), \"partial\" (faer's supernodal LU with unrestricted partial pivoting on the structure of A^T A: robust, much denser)",
    },
    ParamDoc {
        name: "tiny_pivot",
        doc: "restricted pivoting: a pivot column whose entries within its panel are at most tiny_pivot * ||A||_inf is perturbed (default 2.2e-16)",
    },
    ParamDoc {
        name: "perturbation",
        doc: "restricted pivoting: size of a perturbed pivot relative to ||A||_inf (default 1.5e-8)",
    },
    ParamDoc {
        name: "max_fallback_fill",
        doc: "auto: the largest factor unrestricted partial pivoting may store, as a multiple of the restricted factor's entries (default 100); a larger one, or one above the memory available, is refused before it starts",
    },
];

/// faer's workspace of the numeric factorisation and solve (allocated
/// once per analysis).
struct Workspace(MemBuffer);

impl std::fmt::Debug for Workspace {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("Workspace")
    }
}

/// Sparse supernodal LU for general matrices (registry key `"lu"`):
/// restricted pivoting on the symmetric structure (module `panel_lu`) with
/// a fallback to faer's unrestricted partial pivoting ([`LuPivoting`]).
#[derive(Debug)]
pub struct LuSolver {
    settings: LuSettings,
    pattern: Option<Pattern>,
    /// Full pattern of `A` (CSC, both triangles); the pattern of `A^T` is
    /// the same (structurally symmetric).
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    /// For each full entry `q`: `2 p + 1` when `A[q]` is `lower[p]`, `2 p`
    /// when it is `values[p]` (of the [`SymmetricCsc`]).
    src: Vec<usize>,
    a_values: Vec<f64>,
    at_values: Vec<f64>,
    col_perm: Vec<usize>,
    col_perm_inv: Vec<usize>,
    row_perm: Vec<usize>,
    row_perm_inv: Vec<usize>,
    symbolic: Option<SymbolicSupernodalLu<usize>>,
    numeric: SupernodalLu<usize, f64>,
    mem: Option<Workspace>,
    /// Restricted pivoting: the symmetric structure and the factor on it.
    panels: Option<(PanelFactor, PanelLu)>,
    /// The last factorisation used unrestricted partial pivoting.
    partial_active: bool,
    /// Statistics and `||A||_inf` of the last restricted-pivoting
    /// factorisation.
    panel_stats: PanelLuStats,
    norm: f64,
    /// The caller checks its own residual
    /// ([`LinearSolver::set_caller_checks_residual`]).
    caller_checks: bool,
    /// Solve scratch of the restricted path.
    work: Vec<f64>,
    tmp: Vec<f64>,
    factored: bool,
    /// Refinement scratch: residual and correction.
    r: Vec<f64>,
    dx: Vec<f64>,
    b0: Vec<f64>,
    report: SolveReport,
}

impl LuSolver {
    /// A solver with these settings.
    pub fn new(settings: LuSettings) -> Self {
        LuSolver {
            settings,
            pattern: None,
            col_ptr: Vec::new(),
            row_idx: Vec::new(),
            src: Vec::new(),
            a_values: Vec::new(),
            at_values: Vec::new(),
            col_perm: Vec::new(),
            col_perm_inv: Vec::new(),
            row_perm: Vec::new(),
            row_perm_inv: Vec::new(),
            symbolic: None,
            numeric: SupernodalLu::new(),
            mem: None,
            panels: None,
            partial_active: false,
            panel_stats: PanelLuStats::default(),
            norm: 0.0,
            caller_checks: false,
            work: Vec::new(),
            tmp: Vec::new(),
            factored: false,
            r: Vec::new(),
            dx: Vec::new(),
            b0: Vec::new(),
            report: SolveReport {
                solver: "lu".into(),
                precision: "double".into(),
                ..Default::default()
            },
        }
    }

    /// From the TOML table of the `lu` key.
    pub fn from_table(table: &toml::Table) -> Result<Self, junta_core::CoreError> {
        let settings: LuSettings = parse_params("solver", "lu", table)?;
        if !(settings.refine_tol > 0.0 && settings.warn_tol > 0.0) {
            return Err(junta_core::CoreError::InvalidParameters {
                kind: "solver",
                key: "lu".into(),
                message: "refine_tol and warn_tol must be positive".into(),
            });
        }
        Ok(Self::new(settings))
    }

    /// The settings.
    pub fn settings(&self) -> &LuSettings {
        &self.settings
    }

    /// The column ordering of the last analysis (`perm[new] = old`).
    pub fn permutation(&self) -> &[usize] {
        &self.col_perm
    }

    fn threads(&self) -> usize {
        if self.settings.threads == 0 {
            rayon::current_num_threads()
        } else {
            self.settings.threads
        }
    }

    fn par(&self) -> Par {
        let t = self.threads();
        if t <= 1 {
            Par::Seq
        } else {
            Par::rayon(t)
        }
    }

    /// faer's symbolic analysis for unrestricted partial pivoting on the
    /// ordering of [`LinearSolver::analyze`] (at the analysis with
    /// `pivoting = "partial"`, or at the first fallback).
    fn analyze_partial(&mut self, matrix: &SymmetricCsc) -> Result<(), SolverError> {
        let n = matrix.n;
        // full pattern of A and the source of every entry
        let (col_ptr, row_idx, _) = matrix.to_full_csc();
        let mut src = vec![0usize; row_idx.len()];
        let mut next = col_ptr.clone();
        for j in 0..n {
            for p in matrix.col_ptr[j]..matrix.col_ptr[j + 1] {
                src[next[j]] = 2 * p;
                next[j] += 1;
            }
        }
        for j in 0..n {
            for p in matrix.col_ptr[j]..matrix.col_ptr[j + 1] {
                let i = matrix.row_idx[p];
                if i != j {
                    src[next[i]] = 2 * p + 1;
                    next[i] += 1;
                }
            }
        }
        let perm = self.col_perm.clone();
        let perm_inv = self.col_perm_inv.clone();
        let nnz = row_idx.len();
        let req = StackReq::any_of(&[
            col_etree_scratch::<usize>(n, n),
            postorder_scratch::<usize>(n),
            column_counts_aat_scratch::<usize>(n, n),
            factorize_supernodal_symbolic_lu_scratch::<usize>(n, n).and(StackReq::new::<usize>(n)),
        ]);
        let mut mem = MemBuffer::try_new(req).map_err(|_| SolverError::OutOfMemory {
            detail: format!("lu: symbolic analysis workspace for n = {n}"),
        })?;
        let stack = MemStack::new(&mut mem);
        let a = SymbolicSparseColMatRef::new_checked(n, n, &col_ptr, None, &row_idx);
        let perm_ref = faer::perm::PermRef::new_checked(&perm, &perm_inv, n);
        let mut etree = vec![0usize; n];
        let mut post = vec![0usize; n];
        let mut col_counts = vec![0usize; n];
        let mut min_col = vec![0usize; n];
        let et = col_etree(a, Some(perm_ref), &mut etree, stack);
        postorder(&mut post, et, stack);
        // A is structurally symmetric: A^T has the pattern of A
        column_counts_ata(
            &mut col_counts,
            &mut min_col,
            a,
            Some(perm_ref),
            et,
            &post,
            stack,
        );
        let symbolic = factorize_supernodal_symbolic_lu(
            a,
            Some(perm_ref),
            &min_col,
            et,
            &col_counts,
            stack,
            Default::default(),
        )
        .map_err(|e| SolverError::OutOfMemory {
            detail: format!("lu: symbolic analysis: {e:?}"),
        })?;
        // the structure of L + U is bounded by the Cholesky factor of
        // Q^T A^T A Q (George and Ng) whatever the row pivoting
        let chol_nnz: usize = col_counts.iter().sum();
        self.report.factor_nonzeros = (2 * chol_nnz).saturating_sub(n);
        let par = self.par();
        let params: Spec<PartialPivLuParams, f64> = Default::default();
        let numeric_req = StackReq::all_of(&[
            factorize_supernodal_numeric_lu_scratch::<usize, f64>(&symbolic, params),
            StackReq::new::<usize>(n + 1),
            StackReq::new::<usize>(nnz),
        ])
        .or(solve_in_place_scratch::<usize, f64>(n, 1, par));
        self.mem = Some(Workspace(MemBuffer::try_new(numeric_req).map_err(
            |_| SolverError::OutOfMemory {
                detail: format!("lu: factorisation workspace for n = {n}"),
            },
        )?));
        self.symbolic = Some(symbolic);
        self.numeric = SupernodalLu::new();
        self.col_ptr = col_ptr;
        self.row_idx = row_idx;
        self.src = src;
        self.a_values = vec![0.0; nnz];
        self.at_values = vec![0.0; nnz];
        self.col_perm = perm;
        self.col_perm_inv = perm_inv;
        self.row_perm = vec![0; n];
        self.row_perm_inv = vec![0; n];
        Ok(())
    }

    /// The error of a numerically singular matrix: pivots with no entry
    /// above `tiny_pivot ||A||_inf` in their whole Schur-complement column
    /// (module `panel_lu`), the first by its step and equation.
    fn singular_error(&self, st: &PanelLuStats, n: usize) -> SolverError {
        let k = st.first_singular.min(n.saturating_sub(1));
        SolverError::NotPositiveDefinite {
            detail: format!(
                ": lu: the matrix is numerically singular: {} pivot(s) have no entry above {:.1e} * ||A||_inf (||A||_inf = {:.3e}) anywhere in their column of the Schur complement, so no row interchange can help; the first at elimination step {k} of {n}, equation {}",
                st.singular,
                self.settings.tiny_pivot,
                self.norm,
                self.col_perm.get(k).copied().unwrap_or(k)
            ),
        }
    }

    /// Refuse the fallback to unrestricted partial pivoting when its
    /// predicted factor (`report.factor_nonzeros` after
    /// [`Self::analyze_partial`]) exceeds `max_fallback_fill` times the
    /// `restricted` factor's entries, or the memory available. The
    /// analysis is dropped so that a later call analyses again.
    fn check_fallback_fill(
        &mut self,
        restricted: usize,
        perturbed: usize,
    ) -> Result<(), SolverError> {
        let predicted = self.report.factor_nonzeros;
        let ratio = predicted as f64 / restricted.max(1) as f64;
        let bytes = predicted as u64 * 8;
        let available = crate::common::available_memory();
        let too_big = ratio > self.settings.max_fallback_fill;
        let no_room = available.is_some_and(|a| bytes > a);
        self.report.factor_nonzeros = restricted;
        if !(too_big || no_room) {
            self.report.factor_nonzeros = predicted;
            return Ok(());
        }
        self.symbolic = None;
        self.mem = None;
        let room = match available {
            Some(a) => format!("{:.2} GB available", a as f64 / 1e9),
            None => "memory available unknown".into(),
        };
        Err(SolverError::FillLimit {
            detail: format!(
                "lu: {perturbed} pivot(s) need a row from outside their panel, but unrestricted partial pivoting would store {predicted} entries ({:.2} GB, {room}), {ratio:.0} times the restricted factor's {restricted} (max_fallback_fill = {}); use pivoting = \"restricted\" (perturbed pivots and iterative refinement), or raise max_fallback_fill",
                bytes as f64 / 1e9,
                self.settings.max_fallback_fill
            ),
        })
    }

    /// The last restricted-pivoting factor gives no reason to check a
    /// solve whose caller checks its own residual: no perturbed pivot, none
    /// below `1e-12 ||A||_inf`, growth `max(1, max|L|) max|U| / ||A||_inf`
    /// at most [`crate::UNCHECKED_GROWTH_LIMIT`] (as for `ldlt`).
    fn above_doubt(&self) -> bool {
        let st = &self.panel_stats;
        st.perturbed == 0
            && st.min_pivot_ratio >= 1e-12
            && st.growth(self.norm) <= crate::UNCHECKED_GROWTH_LIMIT
    }

    /// Solve with the factors in place (no refinement).
    fn apply_inverse(&mut self, x: &mut [f64]) {
        let n = x.len();
        if !self.partial_active {
            let (f, lu) = self.panels.as_ref().expect("analysed");
            self.work.clear();
            self.work.extend(self.col_perm.iter().map(|&old| x[old]));
            lu.solve_permuted(f, &mut self.work, &mut self.tmp);
            for (new, &old) in self.col_perm.iter().enumerate() {
                x[old] = self.work[new];
            }
            return;
        }
        debug_assert!(self.symbolic.is_some());
        let par = self.par();
        let mem = self.mem.as_mut().expect("analysed");
        let stack = MemStack::new(&mut mem.0);
        let row_perm = faer::perm::PermRef::new_checked(&self.row_perm, &self.row_perm_inv, n);
        let col_perm = faer::perm::PermRef::new_checked(&self.col_perm, &self.col_perm_inv, n);
        let rhs = MatMut::from_column_major_slice_mut(x, n, 1);
        self.numeric
            .solve_in_place_with_conj(row_perm, col_perm, Conj::No, rhs, par, stack);
    }
}

impl Default for LuSolver {
    fn default() -> Self {
        Self::new(LuSettings::default())
    }
}

impl LinearSolver for LuSolver {
    fn key(&self) -> &'static str {
        "lu"
    }

    fn accepts(&self, _kind: MatrixKind) -> bool {
        true
    }

    fn analyze(
        &mut self,
        matrix: &SymmetricCsc,
        coords: Option<&[[f64; 3]]>,
    ) -> Result<(), SolverError> {
        let t0 = Instant::now();
        validate(matrix)?;
        self.factored = false;
        // ordering and symmetric structure: the shared analysis on the
        // pattern of A + A^T (the assembled pattern is symmetric)
        let a = crate::supernodal::analyze(self.settings.ordering, matrix, coords, 1.0, None)?;
        self.report.notes.retain(|n| !n.starts_with("ordering "));
        self.report.notes.push(a.ordering_note.clone());
        self.report.ordering = a.kind.name().into();
        self.report.ordering_candidates = a
            .candidates
            .iter()
            .map(|(k, e)| (k.name().to_string(), e.nonzeros))
            .collect();
        self.col_perm = a.perm;
        self.col_perm_inv = a.perm_inv;
        self.symbolic = None;
        self.mem = None;
        self.partial_active = self.settings.pivoting == LuPivoting::Partial;
        if self.partial_active {
            self.panels = None;
            self.analyze_partial(matrix)?;
        } else {
            let lu = PanelLu::new(&a.factor, matrix, &self.col_perm_inv);
            self.report.factor_nonzeros = lu.nonzeros(&a.factor);
            self.panels = Some((a.factor, lu));
        }
        self.r = vec![0.0; matrix.n];
        self.dx = vec![0.0; matrix.n];
        self.b0 = vec![0.0; matrix.n];
        self.pattern = Some(Pattern::of(matrix));
        let secs = t0.elapsed().as_secs_f64();
        self.report.analyze_seconds += secs;
        tracing::info!(
            n = matrix.n,
            ordering = self.report.ordering.as_str(),
            pivoting = if self.partial_active {
                "partial"
            } else {
                "restricted"
            },
            analyze_seconds = secs,
            "lu: symbolic analysis"
        );
        Ok(())
    }

    fn factorize(&mut self, matrix: &SymmetricCsc) -> Result<(), SolverError> {
        let t0 = Instant::now();
        let Some(pattern) = &self.pattern else {
            return Err(SolverError::Usage(
                "lu: factorize called before analyze".into(),
            ));
        };
        pattern.check(matrix, "lu factorize")?;
        if !matrix.lower.is_empty() && matrix.lower.len() != matrix.values.len() {
            return Err(SolverError::Usage(format!(
                "lu factorize: {} lower values for {} entries",
                matrix.lower.len(),
                matrix.values.len()
            )));
        }
        self.factored = false;
        self.report.warnings.clear();
        if !self.partial_active {
            let low = if matrix.is_general() {
                &matrix.lower
            } else {
                &matrix.values
            };
            for (p, (&v, &w)) in matrix.values.iter().zip(low).enumerate() {
                if !(v.is_finite() && w.is_finite()) {
                    let col = matrix.col_ptr.partition_point(|&c| c <= p) - 1;
                    return Err(SolverError::NonFinite {
                        method: format!(
                            "lu factorisation: the matrix holds {} at entry ({}, {col})",
                            if v.is_finite() { w } else { v },
                            matrix.row_idx[p]
                        ),
                    });
                }
            }
            let norm = symmetric_norm_inf(matrix);
            let threads = self.threads();
            let (f, lu) = self.panels.as_mut().expect("analysed");
            let st = lu.factorize(
                f,
                matrix,
                norm,
                self.settings.tiny_pivot,
                self.settings.perturbation,
                threads,
            );
            self.panel_stats = st;
            self.norm = norm;
            self.report.factorizations += 1;
            if st.singular > 0 && self.settings.pivoting == LuPivoting::Auto {
                return Err(self.singular_error(&st, matrix.n));
            }
            if !(st.max_multiplier.is_finite() && st.max_upper.is_finite()) {
                return Err(SolverError::NonFinite {
                    method: "lu factorisation: the factor overflowed".into(),
                });
            }
            if st.perturbed == 0 || self.settings.pivoting == LuPivoting::Restricted {
                if st.perturbed > 0 {
                    let w = format!(
                        "lu: {} pivot(s) below {:.1e} * ||A||_inf within their panel (restricted pivoting) were perturbed; the solution relies on iterative refinement",
                        st.perturbed, self.settings.tiny_pivot
                    );
                    tracing::warn!("{w}");
                    self.report.warnings.push(w);
                }
                self.factored = true;
                self.report.factor_seconds += t0.elapsed().as_secs_f64();
                return Ok(());
            }
            // a pivot from outside its panel is needed: unrestricted
            // partial pivoting from now on
            self.report.notes.push(format!(
                "lu: {} pivot(s) had no acceptable row within their panel of the symmetric structure (factorisation {}); refactorised with unrestricted partial pivoting (faer, structure of A^T A) for the rest of the run",
                st.perturbed, self.report.factorizations
            ));
            if self.symbolic.is_none() {
                let restricted = self.report.factor_nonzeros;
                self.analyze_partial(matrix)?;
                self.check_fallback_fill(restricted, st.perturbed)?;
            }
            self.partial_active = true;
        }
        let low = if matrix.is_general() {
            &matrix.lower
        } else {
            &matrix.values
        };
        for (q, &s) in self.src.iter().enumerate() {
            let p = s >> 1;
            // A^T at the same position holds the transposed entry: the other array
            let (a, at) = if s & 1 == 1 {
                (low[p], matrix.values[p])
            } else {
                (matrix.values[p], low[p])
            };
            self.a_values[q] = a;
            self.at_values[q] = at;
        }
        if let Some(q) = self.a_values.iter().position(|v| !v.is_finite()) {
            let col = self.col_ptr.partition_point(|&c| c <= q) - 1;
            return Err(SolverError::NonFinite {
                method: format!(
                    "lu factorisation: the matrix holds {} at entry ({}, {col})",
                    self.a_values[q], self.row_idx[q]
                ),
            });
        }
        let n = matrix.n;
        let par = self.par();
        let symbolic = self.symbolic.as_ref().expect("analysed");
        let mem = self.mem.as_mut().expect("analysed");
        let stack = MemStack::new(&mut mem.0);
        let a = SparseColMatRef::new(
            SymbolicSparseColMatRef::new_checked(n, n, &self.col_ptr, None, &self.row_idx),
            &self.a_values,
        );
        let at = SparseColMatRef::new(
            SymbolicSparseColMatRef::new_checked(n, n, &self.col_ptr, None, &self.row_idx),
            &self.at_values,
        );
        let col_perm = faer::perm::PermRef::new_checked(&self.col_perm, &self.col_perm_inv, n);
        factorize_supernodal_numeric_lu(
            &mut self.row_perm,
            &mut self.row_perm_inv,
            &mut self.numeric,
            a,
            at,
            col_perm,
            symbolic,
            par,
            stack,
            Default::default(),
        )
        .map_err(|e| SolverError::NotPositiveDefinite {
            detail: format!(": lu: the matrix is structurally singular ({e:?})"),
        })?;
        self.factored = true;
        self.report.factorizations += 1;
        self.report.factor_seconds += t0.elapsed().as_secs_f64();
        Ok(())
    }

    fn solve_in_place(&mut self, matrix: &SymmetricCsc, b: &mut [f64]) -> Result<(), SolverError> {
        let t0 = Instant::now();
        if !self.factored {
            return Err(SolverError::Usage(
                "lu: solve called before a successful factorize".into(),
            ));
        }
        if b.len() != matrix.n {
            return Err(SolverError::Usage(format!(
                "lu: right-hand side of length {} for n = {}",
                b.len(),
                matrix.n
            )));
        }
        let bnorm = norm2(b);
        self.b0.copy_from_slice(b);
        self.apply_inverse(b);
        if self.caller_checks && !self.partial_active && self.above_doubt() {
            self.report.unchecked_solves += 1;
            self.report.refinement_steps = 0;
            self.report.solve_seconds += t0.elapsed().as_secs_f64();
            if b.iter().any(|v| !v.is_finite()) {
                return Err(SolverError::NonFinite {
                    method: "lu solve (a zero pivot: the matrix is singular; is the model constrained against rigid-body motion?)".into(),
                });
            }
            return Ok(());
        }
        let mut rel = 0.0;
        let mut steps = 0;
        if bnorm > 0.0 {
            let mut r = std::mem::take(&mut self.r);
            let mut dx = std::mem::take(&mut self.dx);
            loop {
                if b.iter().any(|v| !v.is_finite()) {
                    self.r = r;
                    self.dx = dx;
                    return Err(SolverError::NonFinite {
                        method: "lu solve (a zero pivot: the matrix is singular; is the model constrained against rigid-body motion?)".into(),
                    });
                }
                rel = residual(matrix, b, &self.b0, &mut r) / bnorm;
                if rel <= self.settings.refine_tol || steps >= self.settings.max_refinements {
                    break;
                }
                dx.copy_from_slice(&r);
                self.apply_inverse(&mut dx);
                for (x, d) in b.iter_mut().zip(&dx) {
                    *x += d;
                }
                steps += 1;
            }
            self.r = r;
            self.dx = dx;
        }
        if rel > self.settings.warn_tol {
            let w = format!(
                "lu: direct solve lost digits: residual {rel:.3e} after {steps} refinement steps (warn_tol {:.1e}): the matrix is ill-conditioned or nearly singular",
                self.settings.warn_tol
            );
            tracing::warn!("{w}");
            if !self.report.warnings.contains(&w) {
                self.report.warnings.push(w);
            }
        }
        self.report.residual = rel;
        self.report.refinement_steps = steps;
        self.report.solve_seconds += t0.elapsed().as_secs_f64();
        Ok(())
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
        key: "lu",
        description: "sparse supernodal LU for general (nonsymmetric) matrices (friction, non-associated plasticity, exact mixed-mode cohesive tangents): row interchanges within the panels of the symmetric factor's structure (about the cost of two Cholesky factors), falling back to faer's unrestricted partial pivoting when a pivot is missing; ordering of the shared analysis (nested dissection or AMD on A + A^T), symbolic analysis reused across refactorisations, iterative refinement",
        params: LU_PARAMS,
        build: |table| Ok(Box::new(LuSolver::from_table(table)?)),
    }
}
