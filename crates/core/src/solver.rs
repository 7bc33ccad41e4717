//! The [`LinearSolver`] trait: direct and iterative back ends behind one
//! interface. `analyze` once per sparsity pattern (symbolic work), then
//! `factorize` per matrix and `solve` per right-hand side.

use crate::sparse::SymmetricCsc;
use thiserror::Error;

/// A failed or unreliable solve, with its numbers.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum SolverError {
    /// The matrix is not positive definite (singular or unconstrained model).
    #[error("matrix is not positive definite: factorisation failed{detail} (is the model constrained against rigid-body motion?)")]
    NotPositiveDefinite {
        /// Where and why it failed (the pivot or diagonal entry and its
        /// equation), starting with `": "` to follow the message; may be
        /// empty.
        detail: String,
    },
    /// An iterative method did not reach its tolerance.
    #[error("{method} did not converge: relative residual {residual:.3e} after {iterations} iterations (tolerance {tolerance:.1e})")]
    NotConverged {
        /// The method and its set-up (e.g. `"cg (Jacobi preconditioner)"`).
        method: String,
        /// Iterations done.
        iterations: usize,
        /// Relative residual `||b - A x|| / ||b||` reached.
        residual: f64,
        /// Relative residual that was asked for.
        tolerance: f64,
    },
    /// The solution contains NaN or infinity.
    #[error("solution is not finite (NaN or infinity) after {method}")]
    NonFinite {
        /// The back end and stage that met it (e.g. `"cg"`, `"ldlt solve"`),
        /// with the offending entry or equation when known.
        method: String,
    },
    /// The factor (or another large buffer) does not fit in the memory
    /// available; the detail gives the bytes needed and available.
    #[error("not enough memory: {detail}")]
    OutOfMemory {
        /// What could not be allocated (back end and buffer), with the
        /// bytes needed and available when known.
        detail: String,
    },
    /// A factorisation whose predicted fill (from the symbolic analysis)
    /// exceeds the back end's bound: it was refused before it started, with
    /// the entries predicted, the bound and what to change.
    #[error("factorisation refused: {detail}")]
    FillLimit {
        /// Back end, predicted entries and bytes, the bound, the remedy.
        detail: String,
    },
    /// `factorize`/`solve` called before `analyze`, or with a different pattern.
    #[error("solver misuse: {0}")]
    Usage(String),
    /// An external solver library (PETSc and what it calls) reported a
    /// failure of its own: the call, its error code and text.
    #[error("{0}")]
    Library(String),
}

/// What a solve did.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SolveReport {
    /// Back-end name.
    pub solver: String,
    /// Iterations (iterative back ends; 0 for direct).
    pub iterations: usize,
    /// Final relative residual ||b - A x|| / ||b||.
    pub residual: f64,
    /// Seconds spent in symbolic analysis (cumulative).
    pub analyze_seconds: f64,
    /// Seconds spent factorising (cumulative).
    pub factor_seconds: f64,
    /// Seconds spent solving (cumulative).
    pub solve_seconds: f64,
    /// Non-zeros of the factor (direct back ends).
    pub factor_nonzeros: usize,
    /// Fill-reducing ordering the direct back end used (e.g.
    /// `"nested_dissection"`, `"amd"`); empty for iterative back ends.
    pub ordering: String,
    /// Every ordering the direct back end computed in its last analysis
    /// (several when it chose among candidates) with the factor non-zeros
    /// it predicted for it; `ordering` is the one used.
    pub ordering_candidates: Vec<(String, usize)>,
    /// Working precision of the factor (direct back ends): `"double"`, or
    /// `"mixed"` for a single-precision factor whose solutions are refined
    /// to double-precision residuals. Empty for iterative back ends.
    pub precision: String,
    /// Iterative-refinement steps of the last solve (direct back ends).
    pub refinement_steps: usize,
    /// Solves whose residual check was skipped (cumulative): the caller
    /// checks its own residual and the factor gave no reason for doubt
    /// ([`LinearSolver::set_caller_checks_residual`]). `residual` is that
    /// of the last checked solve.
    pub unchecked_solves: usize,
    /// Numeric factorisations so far (cumulative).
    pub factorizations: usize,
    /// Of those, partial refactorisations: only the part of the factor
    /// that depends on the matrix entries changed since the previous
    /// factorisation was recomputed (a softening interface changes a few
    /// columns; the elastic solids around it keep theirs).
    pub partial_factorizations: usize,
    /// Share of the full factorisation's floating-point work that the
    /// partial refactorisations did, summed over them (divide by
    /// `partial_factorizations` for the mean).
    pub refactored_work: f64,
    /// Warnings the caller should show (e.g. loss of digits).
    pub warnings: Vec<String>,
    /// Information on what the back end decided on its own (e.g. that it
    /// gave up single precision and refactorised in double).
    pub notes: Vec<String>,
    /// Inertia of the last factorised matrix: the number of negative
    /// eigenvalues (negative pivots of an LDL^T factor, counting one per
    /// 2x2 block with a negative determinant and the negative 1x1 pivots).
    /// `None` when the back end does not know it (iterative back ends);
    /// `Some(0)` from a successful Cholesky factor.
    pub negative_pivots: Option<usize>,
}

/// A nested-dissection ordering computed by the caller, with the factor
/// size predicted for it ([`LinearSolver::offer_dissection`]).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PrecomputedDissection {
    /// `perm[new] = old`: the equation eliminated `new`-th.
    pub perm: Vec<usize>,
    /// Predicted non-zeros of the Cholesky factor (diagonal included).
    pub nonzeros: usize,
    /// Predicted floating-point operations of the factorisation.
    pub flops: f64,
}

/// Kind of a tangent matrix, from the laws and materials of a model.
/// Ordered: a model's kind is the largest of its elements' kinds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Default)]
pub enum MatrixKind {
    /// Symmetric positive definite once constrained (elastic solids,
    /// penalty interfaces that do not soften).
    #[default]
    SymmetricPositiveDefinite,
    /// Symmetric, possibly indefinite (softening laws: negative stiffness
    /// on the descending branch).
    SymmetricIndefinite,
    /// Nonsymmetric (non-associated plasticity, friction).
    General,
}

impl MatrixKind {
    /// Short name for messages and summaries.
    pub fn name(self) -> &'static str {
        match self {
            MatrixKind::SymmetricPositiveDefinite => "symmetric positive definite",
            MatrixKind::SymmetricIndefinite => "symmetric indefinite",
            MatrixKind::General => "general (nonsymmetric)",
        }
    }
}

/// What algebraic multigrid needs to know of each equation (free dof):
/// its mesh node, its displacement component (0, 1, 2) and the body it
/// belongs to (solids connected through solid elements; interface
/// elements do not connect bodies). Built by
/// [`crate::dof::DofMap::equation_layout`].
#[derive(Debug, Clone, Default, PartialEq)]
pub struct EquationLayout {
    /// Node of each equation (equations of a node are consecutive).
    pub node: Vec<usize>,
    /// Component (0 = x, 1 = y, 2 = z) of each equation.
    pub component: Vec<u8>,
    /// Body of each equation.
    pub body: Vec<u32>,
}

/// A linear solver for symmetric positive-definite systems stored as the
/// upper triangle in [`SymmetricCsc`].
pub trait LinearSolver: Send + std::fmt::Debug {
    /// Registry key (`"cholesky"`, `"cg"`).
    fn key(&self) -> &'static str;
    /// Symbolic analysis of the pattern (ordering, elimination tree). Done
    /// once; later matrices must share the pattern. `coords`, when given,
    /// holds one point per equation for geometric orderings.
    fn analyze(
        &mut self,
        matrix: &SymmetricCsc,
        coords: Option<&[[f64; 3]]>,
    ) -> Result<(), SolverError>;
    /// Numeric factorisation (direct) or preconditioner set-up (iterative).
    fn factorize(&mut self, matrix: &SymmetricCsc) -> Result<(), SolverError>;
    /// Solve `A x = b` for the last factorised `A` (passed again: iterative
    /// back ends multiply by it), overwriting `b` with `x`.
    fn solve_in_place(&mut self, matrix: &SymmetricCsc, b: &mut [f64]) -> Result<(), SolverError>;
    /// Solve for several right-hand sides stored one after another in `b`
    /// (`b.len()` a multiple of `matrix.n`), overwriting each with its
    /// solution. A direct back end reads its factor once for all of them;
    /// the default solves them one by one.
    fn solve_many_in_place(
        &mut self,
        matrix: &SymmetricCsc,
        b: &mut [f64],
    ) -> Result<(), SolverError> {
        let n = matrix.n.max(1);
        if b.len() % n != 0 {
            return Err(SolverError::Usage(format!(
                "solve_many_in_place: {} right-hand-side entries are not a multiple of the {} equations",
                b.len(),
                matrix.n
            )));
        }
        for col in b.chunks_mut(n) {
            self.solve_in_place(matrix, col)?;
        }
        Ok(())
    }
    /// Node, component and body of each equation, given by the driver
    /// before `analyze` (used by AMG for the rigid-body modes; ignored by
    /// default).
    fn set_layout(&mut self, _layout: &EquationLayout) {}
    /// Told by a caller that verifies every solution through a residual of
    /// its own (a Newton driver computes the out-of-balance forces after
    /// each update), so that a back end may skip its check of
    /// `||b - A x||` when its factor gives no reason for doubt (no
    /// perturbed pivot, no tiny pivot, little growth): that check reads
    /// the whole matrix once more per solve. Ignored by default.
    fn set_caller_checks_residual(&mut self, _checks: bool) {}
    /// A nested-dissection ordering of the pattern the next
    /// [`LinearSolver::analyze`] will see, computed before this back end
    /// was built (the solver choice `auto` orders the model to predict the
    /// direct factor's size). A direct back end that would compute nested
    /// dissection takes this one instead; others ignore it.
    fn offer_dissection(&mut self, _dissection: PrecomputedDissection) {}
    /// Cumulative report of what the solver did.
    fn report(&self) -> SolveReport;
    /// The matrix kinds this back end can solve (default: SPD only).
    fn accepts(&self, kind: MatrixKind) -> bool {
        kind == MatrixKind::SymmetricPositiveDefinite
    }
}
