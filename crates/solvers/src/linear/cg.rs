//! Preconditioned conjugate gradients (PCG) for SPD systems (registry key
//! `cg`) and restarted GMRES for symmetric indefinite ones (key `gmres`,
//! [`gmres`]), with a Jacobi, block-Jacobi or smoothed-aggregation AMG
//! ([`crate::amg`]) preconditioner.
//!
//! # Algorithm
//!
//! With `M ≈ A` SPD, `x_0 = 0`, `r_0 = b`, `z_0 = M^-1 r_0`, `p_0 = z_0`:
//!
//! ```text
//! q_k     = A p_k
//! alpha_k = (r_k · z_k) / (p_k · q_k)
//! x_k+1   = x_k + alpha_k p_k
//! r_k+1   = r_k - alpha_k q_k
//! z_k+1   = M^-1 r_k+1
//! beta_k  = (r_k+1 · z_k+1) / (r_k · z_k)
//! p_k+1   = z_k+1 + beta_k p_k
//! ```
//!
//! `x_k` minimises the `A`-norm of the error over the Krylov space
//! `span{M^-1 b, (M^-1 A) M^-1 b, ...}`; the error contracts at least like
//! `2 ((sqrt(κ) - 1) / (sqrt(κ) + 1))^k` with `κ = cond(M^-1 A)`.
//!
//! Stopping: the recurrence residual `||r_k|| / ||b|| <= tol`, confirmed by
//! the true residual `||b - A x_k|| / ||b||` (rounding makes the two drift
//! apart when `κ` is large); if the true one is above `tol`, CG restarts
//! from `x_k` with `r = b - A x_k` (at most [`MAX_RESTARTS`] times).
//!
//! Failures, always with numbers, never a silent wrong `x`:
//! * `p·Ap <= 0`: `A` is not positive definite along `p` (breakdown) ->
//!   [`SolverError::NotPositiveDefinite`];
//! * `max_iterations` reached, or no decrease of the best residual by a
//!   factor 2 within `stagnation_window` iterations ->
//!   [`SolverError::NotConverged`];
//! * NaN/inf -> [`SolverError::NonFinite`].
//!
//! On error `b` is left holding the right-hand side.
//!
//! # Preconditioners
//!
//! * `jacobi`: `M = diag(A)`.
//! * `block_jacobi`: `M` = the 3×3 diagonal blocks of the nodes. The node
//!   blocks are found in `analyze`: runs of consecutive equations with equal
//!   coordinates (or, without coordinates, with identical couplings, see
//!   [`crate::ordering::equation_groups`]); a run of length `3m` gives `m`
//!   3×3 blocks (coincident interface nodes numbered together form runs of
//!   6), any other run (a node with a constrained, eliminated dof) falls
//!   back to scalar Jacobi for its equations. Each block is inverted once
//!   per `factorize` through its Cholesky factor, which also checks that it
//!   is SPD. Block-Jacobi removes the intra-node coupling (Poisson
//!   effect, rotated orthotropic materials) that scalar Jacobi cannot see.
//!
//! * `amg`: one V-cycle of [`crate::amg::Amg`]. The hierarchy's level-0
//!   matrix is the only full copy of `A` (the Krylov vectors then live in
//!   its equation order, [`crate::amg::Amg::perm`]). With `amg_reuse` a new
//!   matrix of the same pattern updates level 0 only; the hierarchy is
//!   built anew when a solve needs more than 1.5x + 3 the iterations of the
//!   first solve after the last set-up (at the next `factorize`), or at
//!   once, the solve repeated, when a kept hierarchy fails or needs more
//!   than 2x + 10.
//!
//! The product `A p` uses both triangles in CSR built once in `analyze`
//! (rows in parallel, no scatter; on the calling thread below
//! 50,000 equations, where waking the thread pool costs more than the
//! arithmetic).

use crate::amg::{layout_from_coords, Amg, AmgSettings};
use crate::common::{
    dot, norm2, residual_floor, symmetric_only, update, update_sum, validate, FullCsr, Pattern,
};
use crate::ordering;
use junta_core::registry::{parse_params, ParamDoc, SolverEntry};
use junta_core::{LinearSolver, MatrixKind, SolveReport, SolverError, SymmetricCsc};
use nalgebra::Matrix3;
use serde::Deserialize;
use std::time::Instant;

/// Restarts from the true residual before giving up.
pub const MAX_RESTARTS: usize = 5;

/// Preconditioner of [`CgSolver`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Preconditioner {
    /// Diagonal scaling.
    Jacobi,
    /// 3×3 nodal blocks, scalar where a node has fewer than 3 dofs.
    #[default]
    BlockJacobi,
    /// Smoothed-aggregation algebraic multigrid ([`crate::amg`]), one
    /// V-cycle per iteration, rigid-body modes per body as near-null space.
    Amg,
}

/// Krylov method of [`CgSolver`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum KrylovMethod {
    /// Conjugate gradients: symmetric positive-definite matrices (registry
    /// key `cg`).
    #[default]
    Cg,
    /// Restarted GMRES with right preconditioning ([`gmres`]): symmetric
    /// indefinite matrices such as softening tangents (registry key
    /// `gmres`).
    Gmres,
}

pub mod gmres;

/// Settings of [`CgSolver`] (TOML parameters of the `cg` and `gmres` keys).
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct CgSettings {
    /// `"jacobi"` or `"block_jacobi"` (default).
    pub preconditioner: Preconditioner,
    /// Krylov method: CG (SPD matrices) or GMRES (any non-singular
    /// symmetric matrix; the `gmres` back end).
    #[serde(skip)]
    pub method: KrylovMethod,
    /// GMRES: restart length (default 50).
    pub restart: usize,
    /// Relative residual `||b - A x|| / ||b||` to reach (1e-10).
    pub tol: f64,
    /// Iteration limit; `None`: `min(10 n, 20000)` (at least 100).
    pub max_iterations: Option<usize>,
    /// Give up when the best residual has not halved over this many
    /// iterations (default 2000).
    pub stagnation_window: usize,
    /// AMG strength-of-connection threshold `θ` (default 0).
    pub amg_theta: f64,
    /// AMG: coarsen until at most this many equations (default 1500).
    pub amg_max_coarse: usize,
    /// AMG: Chebyshev smoother degree (default 2).
    pub amg_degree: usize,
    /// AMG: aggregation per body (default true): aggregates cross an
    /// interface only where its bond is strong (`amg_interface_theta`);
    /// `false` treats the model as one body.
    pub amg_per_body: bool,
    /// AMG: strength threshold across interfaces (default 0.25).
    pub amg_interface_theta: f64,
    /// AMG: nodes at one point tied by a strong interface bond are one
    /// node of the hierarchy (block-smoothed, aggregated together); default
    /// true. `false` smooths them node by node, whose iteration count
    /// grows with the penalty.
    pub amg_bonded_clusters: bool,
    /// AMG: for a new matrix of the same pattern (the next Newton
    /// iteration) keep the hierarchy and update level 0 only, until the
    /// iteration count exceeds 1.5 times (plus 3) the count of the first
    /// solve after its set-up, or a solve fails; then build it anew
    /// (default true). `false` recomputes every level for every matrix.
    pub amg_reuse: bool,
}

impl Default for CgSettings {
    fn default() -> Self {
        CgSettings {
            preconditioner: Preconditioner::BlockJacobi,
            method: KrylovMethod::Cg,
            restart: 50,
            tol: 1e-10,
            max_iterations: None,
            stagnation_window: 2000,
            amg_theta: 0.0,
            amg_max_coarse: 1500,
            amg_degree: 2,
            amg_per_body: true,
            amg_interface_theta: 0.25,
            amg_bonded_clusters: true,
            amg_reuse: true,
        }
    }
}

/// Parameter documentation of the `cg` registry entry.
pub const CG_PARAMS: &[ParamDoc] = &[
    ParamDoc {
        name: "preconditioner",
        doc: "\"block_jacobi\" (3x3 nodal blocks, default), \"jacobi\" or \"amg\" (smoothed-aggregation multigrid, rigid-body modes per body)",
    },
    ParamDoc {
        name: "tol",
        doc: "relative residual ||b - A x||/||b|| to reach (default 1e-10)",
    },
    ParamDoc {
        name: "max_iterations",
        doc: "iteration limit (default min(10 n, 20000))",
    },
    ParamDoc {
        name: "stagnation_window",
        doc: "stop when the best residual has not halved over this many iterations (default 2000)",
    },
    ParamDoc {
        name: "amg_theta",
        doc: "amg: strength-of-connection threshold on 3x3 nodal blocks (default 0: all non-zero blocks)",
    },
    ParamDoc {
        name: "amg_max_coarse",
        doc: "amg: coarsen until at most this many equations, solved densely (default 1500)",
    },
    ParamDoc {
        name: "amg_degree",
        doc: "amg: degree of the Chebyshev smoother (default 2)",
    },
    ParamDoc {
        name: "amg_per_body",
        doc: "amg: aggregates per body: an interface is aggregated across only where its bond is strong (default true)",
    },
    ParamDoc {
        name: "amg_interface_theta",
        doc: "amg: strength threshold on 3x3 blocks across interfaces; weaker (soft, damaged) bonds separate the bodies (default 0.25)",
    },
    ParamDoc {
        name: "amg_bonded_clusters",
        doc: "amg: nodes at one point tied by a strong interface bond form one block of the smoother and one aggregate, so that stiff penalties do not slow it (default true)",
    },
    ParamDoc {
        name: "restart",
        doc: "gmres: restart length, vectors kept (default 50)",
    },
    ParamDoc {
        name: "amg_reuse",
        doc: "amg: keep the hierarchy for the next matrices (level 0 updated) until the iteration count grows by half or a solve fails, then rebuild (default true)",
    },
];

/// Preconditioned conjugate-gradient back end (registry key `"cg"`).
pub struct CgSolver {
    settings: CgSettings,
    pattern: Option<Pattern>,
    full: FullCsr,
    /// Node groups (`group_ptr[g]..group_ptr[g+1]`) from `analyze`.
    group_ptr: Vec<usize>,
    /// Per equation: first equation of its block, block size (1 or 3), and
    /// its row of the block inverse.
    block_start: Vec<usize>,
    block_size: Vec<u8>,
    inv_row: Vec<[f64; 3]>,
    ready: bool,
    /// Coordinates per equation and layout (AMG).
    coords: Vec<[f64; 3]>,
    layout: Option<junta_core::EquationLayout>,
    amg: Option<Amg>,
    /// The hierarchy was built (or refreshed) for the current matrix.
    amg_fresh: bool,
    /// Rebuild at the next factorisation (the iteration count grew).
    amg_stale: bool,
    /// Iterations of the first solve after the last set-up.
    amg_base_iterations: Option<usize>,
    /// Set-ups, reuses, rebuilds after growth, rebuilds after a failure.
    amg_counts: [usize; 4],
    /// Iteration cap of a solve with a kept hierarchy (`2 base + 10`): a
    /// hierarchy that far off is rebuilt at once rather than iterated on.
    iteration_cap: Option<usize>,
    report: SolveReport,
    analyze_count: usize,
    blocks3: usize,
}

impl std::fmt::Debug for CgSolver {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("CgSolver")
            .field("settings", &self.settings)
            .field("n", &self.block_size.len())
            .field("blocks3", &self.blocks3)
            .field("ready", &self.ready)
            .finish_non_exhaustive()
    }
}

impl Default for CgSolver {
    fn default() -> Self {
        Self::new(CgSettings::default())
    }
}

impl CgSolver {
    /// A solver with the given settings.
    pub fn new(settings: CgSettings) -> Self {
        CgSolver {
            settings,
            pattern: None,
            full: FullCsr::default(),
            group_ptr: Vec::new(),
            block_start: Vec::new(),
            block_size: Vec::new(),
            inv_row: Vec::new(),
            ready: false,
            coords: Vec::new(),
            layout: None,
            amg: None,
            amg_fresh: false,
            amg_stale: false,
            amg_base_iterations: None,
            amg_counts: [0; 4],
            iteration_cap: None,
            report: SolveReport {
                solver: "cg".into(),
                ..Default::default()
            },
            analyze_count: 0,
            blocks3: 0,
        }
    }

    /// From a TOML parameter table (unknown keys are an error).
    pub fn from_table(table: &toml::Table) -> Result<Self, junta_core::CoreError> {
        Self::from_table_with(table, KrylovMethod::Cg)
    }

    /// From a TOML parameter table for `method` (key `cg` or `gmres`; the
    /// `gmres` key defaults to the AMG preconditioner).
    pub fn from_table_with(
        table: &toml::Table,
        method: KrylovMethod,
    ) -> Result<Self, junta_core::CoreError> {
        let key = match method {
            KrylovMethod::Cg => "cg",
            KrylovMethod::Gmres => "gmres",
        };
        let mut s: CgSettings = parse_params("solver", key, table)?;
        s.method = method;
        if method == KrylovMethod::Gmres && !table.contains_key("preconditioner") {
            s.preconditioner = Preconditioner::Amg;
        }
        let bad = |message: String| junta_core::CoreError::InvalidParameters {
            kind: "solver",
            key: key.into(),
            message,
        };
        if s.restart == 0 || s.restart > 1000 {
            return Err(bad(format!(
                "`restart` = {} must lie in 1..=1000 (GMRES stores that many vectors)",
                s.restart
            )));
        }
        if !(s.tol.is_finite() && s.tol > 0.0 && s.tol < 1.0) {
            return Err(bad(format!("`tol` = {} must lie in (0, 1)", s.tol)));
        }
        if s.max_iterations == Some(0) {
            return Err(bad("`max_iterations` = 0 must be >= 1".into()));
        }
        if s.stagnation_window == 0 {
            return Err(bad("`stagnation_window` = 0 must be >= 1".into()));
        }
        let mut solver = Self::new(s);
        solver.report.solver = key.into();
        Ok(solver)
    }

    /// The settings.
    pub fn settings(&self) -> &CgSettings {
        &self.settings
    }

    /// Number of symbolic analyses so far.
    pub fn analyze_count(&self) -> usize {
        self.analyze_count
    }

    /// Number of 3×3 blocks of the block-Jacobi preconditioner (0 for Jacobi).
    pub fn block_count(&self) -> usize {
        self.blocks3
    }

    fn max_iterations(&self, n: usize) -> usize {
        self.settings
            .max_iterations
            .unwrap_or_else(|| (10 * n).clamp(100, 20_000))
    }

    /// Equation runs of length 3m -> 3x3 blocks, others scalar.
    fn layout_blocks(&mut self, n: usize) {
        self.block_start = (0..n).collect();
        self.block_size = vec![1; n];
        self.blocks3 = 0;
        if self.settings.preconditioner == Preconditioner::Jacobi {
            return;
        }
        for g in 0..self.group_ptr.len().saturating_sub(1) {
            let (s, e) = (self.group_ptr[g], self.group_ptr[g + 1]);
            if (e - s) % 3 == 0 {
                for b in (s..e).step_by(3) {
                    for i in b..b + 3 {
                        self.block_start[i] = b;
                        self.block_size[i] = 3;
                    }
                    self.blocks3 += 1;
                }
            }
        }
    }

    /// The AMG hierarchy (after `factorize` with `preconditioner = "amg"`).
    pub fn amg(&self) -> Option<&Amg> {
        self.amg.as_ref()
    }

    /// z = M^-1 r, and returns r · z.
    /// `y = A x`: with AMG the hierarchy's level-0 matrix (vectors in its
    /// order, [`Amg::perm`]), so the matrix is stored once; otherwise the
    /// solver's own full copy.
    fn matvec(&self, x: &[f64], y: &mut [f64]) {
        match &self.amg {
            Some(amg) => amg.levels[0].a.mul(x, y),
            None => self.full.mul(x, y),
        }
    }

    /// `eps |||A| |x|||` (see [`crate::common::residual_floor`]).
    fn residual_floor(&self, x: &[f64]) -> f64 {
        match &self.amg {
            Some(amg) => {
                let a = &amg.levels[0].a;
                residual_floor(&a.row_ptr, &a.col, &a.val, x)
            }
            None => self.full.residual_floor(x),
        }
    }

    /// `z = M^-1 r`, returns `r . z` (with AMG in level-0 order).
    fn precondition(&mut self, r: &[f64], z: &mut [f64]) -> f64 {
        if let Some(amg) = &mut self.amg {
            amg.apply_in_level_order(r, z);
            return dot(r, z);
        }
        let (start, size, inv_row) = (&self.block_start, &self.block_size, &self.inv_row);
        update_sum(z, |i, _| {
            let s = start[i];
            let row = &inv_row[i];
            let v = match size[i] {
                3 => row[0] * r[s] + row[1] * r[s + 1] + row[2] * r[s + 2],
                _ => row[0] * r[i],
            };
            (v, v * r[i])
        })
    }

    fn factorize_amg(&mut self, matrix: &SymmetricCsc, t0: Instant) -> Result<(), SolverError> {
        match &mut self.amg {
            Some(amg) if !self.amg_stale && self.settings.amg_reuse => {
                amg.update_finest(matrix)?;
                self.amg_fresh = false;
                self.amg_counts[1] += 1;
            }
            Some(amg) if !self.settings.amg_reuse => {
                amg.refresh(matrix)?;
                self.amg_fresh = true;
            }
            _ => {
                if self.amg_stale {
                    self.amg_counts[2] += 1;
                }
                self.setup_amg(matrix)?;
            }
        }
        self.update_reuse_note();
        self.ready = true;
        self.report.factor_seconds += t0.elapsed().as_secs_f64();
        Ok(())
    }

    /// A new hierarchy for `matrix` (aggregates included: damage may have
    /// changed which interfaces are strong).
    fn setup_amg(&mut self, matrix: &SymmetricCsc) -> Result<(), SolverError> {
        let mut layout = match &self.layout {
            Some(l) if l.node.len() == matrix.n => l.clone(),
            _ => layout_from_coords(&self.coords),
        };
        if !self.settings.amg_per_body {
            layout.body.iter_mut().for_each(|b| *b = 0);
        }
        let settings = AmgSettings {
            theta: self.settings.amg_theta,
            theta_interface: self.settings.amg_interface_theta,
            max_coarse: self.settings.amg_max_coarse.max(1),
            degree: self.settings.amg_degree.max(1),
            bonded_clusters: self.settings.amg_bonded_clusters,
            indefinite: self.settings.method == KrylovMethod::Gmres,
            ..Default::default()
        };
        self.amg = None;
        let amg = Amg::setup(matrix, &self.coords, &layout, settings)?;
        let bodies = layout.body.iter().copied().max().map_or(0, |b| b + 1);
        let note = format!(
            "amg: {} levels {:?}, operator complexity {:.2}, {} bod{}, {} bonded node clusters",
            amg.num_levels(),
            amg.sizes(),
            amg.operator_complexity(),
            bodies,
            if bodies == 1 { "y" } else { "ies" },
            amg.bonded_clusters()
        );
        tracing::info!("{note}");
        self.report.notes.retain(|n| !n.starts_with("amg:"));
        self.report.notes.push(note);
        self.amg = Some(amg);
        self.amg_fresh = true;
        self.amg_stale = false;
        self.amg_base_iterations = None;
        self.amg_counts[0] += 1;
        Ok(())
    }

    fn update_reuse_note(&mut self) {
        if !self.settings.amg_reuse || self.amg_counts[1] == 0 {
            return;
        }
        let [setups, reuses, growth, failed] = self.amg_counts;
        let note = format!(
            "amg reuse: {setups} set-up{} for {} matrices ({reuses} solved with a kept hierarchy; rebuilt {growth} time{} when the iterations grew by half, {failed} time{} when a kept hierarchy failed or needed over twice the iterations)",
            if setups == 1 { "" } else { "s" },
            setups + reuses,
            if growth == 1 { "" } else { "s" },
            if failed == 1 { "" } else { "s" },
        );
        self.report.notes.retain(|n| !n.starts_with("amg reuse:"));
        self.report.notes.push(note);
    }

    fn fail(
        &mut self,
        t0: Instant,
        iterations: usize,
        residual: f64,
        e: SolverError,
    ) -> SolverError {
        self.report.iterations = iterations;
        self.report.residual = residual;
        self.report.solve_seconds += t0.elapsed().as_secs_f64();
        tracing::warn!("{e}");
        e
    }
}

impl LinearSolver for CgSolver {
    fn key(&self) -> &'static str {
        match self.settings.method {
            KrylovMethod::Cg => "cg",
            KrylovMethod::Gmres => "gmres",
        }
    }

    fn accepts(&self, kind: MatrixKind) -> bool {
        match self.settings.method {
            KrylovMethod::Cg => kind == MatrixKind::SymmetricPositiveDefinite,
            KrylovMethod::Gmres => kind != MatrixKind::General,
        }
    }

    fn analyze(
        &mut self,
        matrix: &SymmetricCsc,
        coords: Option<&[[f64; 3]]>,
    ) -> Result<(), SolverError> {
        let t0 = Instant::now();
        validate(matrix)?;
        symmetric_only(matrix, "cg")?;
        if matrix.n > u32::MAX as usize {
            return Err(SolverError::Usage("cg: more than 2^32 equations".into()));
        }
        self.ready = false;
        // with AMG the hierarchy holds the (only) full copy of the matrix
        self.full = if self.settings.preconditioner == Preconditioner::Amg {
            FullCsr::default()
        } else {
            FullCsr::new(matrix)
        };
        let coords = coords.filter(|c| c.len() == matrix.n);
        self.group_ptr = ordering::equation_groups(matrix, coords);
        self.layout_blocks(matrix.n);
        self.inv_row = vec![[0.0; 3]; matrix.n];
        self.amg = None;
        self.coords = coords.map_or_else(|| vec![[0.0; 3]; matrix.n], |c| c.to_vec());
        self.pattern = Some(Pattern::of(matrix));
        self.analyze_count += 1;
        self.report.analyze_seconds += t0.elapsed().as_secs_f64();
        Ok(())
    }

    fn factorize(&mut self, matrix: &SymmetricCsc) -> Result<(), SolverError> {
        symmetric_only(matrix, "cg")?;
        let t0 = Instant::now();
        let Some(pattern) = &self.pattern else {
            return Err(SolverError::Usage(
                "cg: factorize called before analyze".into(),
            ));
        };
        pattern.check(matrix, "cg factorize")?;
        self.ready = false;
        self.report.warnings.clear();
        if let Some(p) = matrix.values.iter().position(|v| !v.is_finite()) {
            return Err(SolverError::NonFinite {
                method: format!(
                    "cg set-up: the matrix holds {} at stored entry {p}",
                    matrix.values[p]
                ),
            });
        }
        let n = matrix.n;
        if self.settings.preconditioner == Preconditioner::Amg {
            return self.factorize_amg(matrix, t0);
        }
        self.full.fill(matrix);
        let diag = matrix.diagonal();
        let mut i = 0;
        while i < n {
            if self.block_size[i] == 3 {
                let mut m = Matrix3::zeros();
                for a in 0..3 {
                    for b in a..3 {
                        let v = matrix
                            .position(i + a, i + b)
                            .map_or(0.0, |p| matrix.values[p]);
                        m[(a, b)] = v;
                        m[(b, a)] = v;
                    }
                }
                let inv = m.cholesky().map(|c| c.inverse()).ok_or_else(|| {
                    SolverError::NotPositiveDefinite {
                        detail: format!(
                            ": the 3x3 diagonal block of equations {}..{} is not positive definite (diagonal {:.3e}, {:.3e}, {:.3e})",
                            i,
                            i + 2,
                            m[(0, 0)],
                            m[(1, 1)],
                            m[(2, 2)]
                        ),
                    }
                })?;
                for a in 0..3 {
                    self.inv_row[i + a] = [inv[(a, 0)], inv[(a, 1)], inv[(a, 2)]];
                }
                i += 3;
            } else {
                let d = diag[i];
                if d.is_nan() || d <= 0.0 {
                    return Err(SolverError::NotPositiveDefinite {
                        detail: format!(": diagonal entry of equation {i} is {d:e}"),
                    });
                }
                self.inv_row[i] = [1.0 / d, 0.0, 0.0];
                i += 1;
            }
        }
        let (dmin, dmax) = diag.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), &d| {
            (lo.min(d), hi.max(d))
        });
        if n > 0 && dmax / dmin > 1e12 {
            let w = format!(
                "cg: the matrix diagonal spans {dmin:.3e} .. {dmax:.3e} (ratio {:.1e}); expect slow convergence (penalty too high?)",
                dmax / dmin
            );
            tracing::warn!("{w}");
            self.report.warnings.push(w);
        }
        self.ready = true;
        self.report.factor_seconds += t0.elapsed().as_secs_f64();
        Ok(())
    }

    fn solve_in_place(&mut self, matrix: &SymmetricCsc, b: &mut [f64]) -> Result<(), SolverError> {
        let kept = self.amg.is_some() && !self.amg_fresh;
        let rhs = if kept { b.to_vec() } else { Vec::new() };
        self.iteration_cap = match self.amg_base_iterations {
            Some(base) if kept => Some(2 * base + 10),
            _ => None,
        };
        let first = self.solve_once(matrix, b);
        self.iteration_cap = None;
        match first {
            Err(
                e @ (SolverError::NotConverged { .. } | SolverError::NotPositiveDefinite { .. }),
            ) if kept => {
                let w = format!(
                    "cg: the kept AMG hierarchy failed on this matrix ({e}); rebuilt for it"
                );
                tracing::info!("{w}");
                b.copy_from_slice(&rhs);
                self.amg_counts[3] += 1;
                // this matrix ends up solved with a new hierarchy
                self.amg_counts[1] -= 1;
                let t0 = Instant::now();
                self.setup_amg(matrix)?;
                self.update_reuse_note();
                self.report.factor_seconds += t0.elapsed().as_secs_f64();
                self.solve_once(matrix, b)?;
            }
            r => r?,
        }
        if self.amg.is_some() {
            let it = self.report.iterations;
            match self.amg_base_iterations {
                None if self.amg_fresh => self.amg_base_iterations = Some(it),
                Some(base) if it as f64 > 1.5 * base as f64 + 3.0 => self.amg_stale = true,
                _ => {}
            }
        }
        Ok(())
    }

    fn set_layout(&mut self, layout: &junta_core::EquationLayout) {
        self.layout = Some(layout.clone());
        self.amg = None;
    }

    fn report(&self) -> SolveReport {
        self.report.clone()
    }
}

impl CgSolver {
    /// Preconditioned CG iterations from `x = 0` (vectors in level order);
    /// returns `x`, the iterations and the true relative residual.
    fn cg_iterate(
        &mut self,
        b: &[f64],
        bnorm: f64,
        max_it: usize,
        tol: f64,
        t0: Instant,
    ) -> Result<(Vec<f64>, usize, f64), SolverError> {
        let n = b.len();
        let mut x = vec![0.0; n];
        let mut r = b.to_vec();
        let mut z = vec![0.0; n];
        let mut q = vec![0.0; n];
        let mut rz = self.precondition(&r, &mut z);
        let mut p = z.clone();
        let mut rel = 1.0;
        let mut best = rel;
        let mut best_it = 0usize;
        let mut restarts = 0;
        let mut it = 0usize;
        loop {
            if it >= max_it {
                let e = SolverError::NotConverged {
                    method: format!("cg ({:?} preconditioner)", self.settings.preconditioner),
                    iterations: it,
                    residual: rel,
                    tolerance: tol,
                };
                return Err(self.fail(t0, it, rel, e));
            }
            it += 1;
            self.matvec(&p, &mut q);
            let pq = dot(&p, &q);
            if !pq.is_finite() || !rz.is_finite() {
                let e = SolverError::NonFinite {
                    method: format!("cg at iteration {it} (p'Ap = {pq:e}, r'z = {rz:e})"),
                };
                return Err(self.fail(t0, it, rel, e));
            }
            if pq <= 0.0 {
                let e = SolverError::NotPositiveDefinite {
                    detail: format!(
                        ": cg breakdown at iteration {it}, p'Ap = {pq:.3e} <= 0 with ||p|| = {:.3e} (relative residual {rel:.3e})",
                        norm2(&p)
                    ),
                };
                return Err(self.fail(t0, it, rel, e));
            }
            let alpha = rz / pq;
            update(&mut x, |i, xi| xi + alpha * p[i]);
            let rr = update_sum(&mut r, |i, ri| {
                let new = ri - alpha * q[i];
                (new, new * new)
            });
            rel = rr.sqrt() / bnorm;
            if rel < 0.5 * best {
                best = rel;
                best_it = it;
            } else if it - best_it > self.settings.stagnation_window {
                let e = SolverError::NotConverged {
                    method: format!(
                        "cg ({:?} preconditioner; stagnated: best residual {best:.3e} at iteration {best_it})",
                        self.settings.preconditioner
                    ),
                    iterations: it,
                    residual: rel,
                    tolerance: tol,
                };
                return Err(self.fail(t0, it, rel, e));
            }
            if rel <= tol {
                // Confirm with the true residual.
                self.matvec(&x, &mut q);
                update(&mut r, |i, _| b[i] - q[i]);
                rel = norm2(&r) / bnorm;
                if rel <= tol {
                    break;
                }
                restarts += 1;
                if restarts > MAX_RESTARTS {
                    let floor = self.residual_floor(&x) / bnorm;
                    let e = SolverError::NotConverged {
                        method: format!(
                            "cg ({:?} preconditioner; true residual stays above the recurrence one after {MAX_RESTARTS} restarts; its round-off floor eps |||A| |x||| / ||b|| is {floor:.1e}{})",
                            self.settings.preconditioner,
                            if floor > 0.1 * tol {
                                format!(", so `tol` = {tol:e} is too close to what double precision resolves on this matrix: raise it")
                            } else {
                                String::new()
                            }
                        ),
                        iterations: it,
                        residual: rel,
                        tolerance: tol,
                    };
                    return Err(self.fail(t0, it, rel, e));
                }
                rz = self.precondition(&r, &mut z);
                p.copy_from_slice(&z);
                continue;
            }
            let rz_new = self.precondition(&r, &mut z);
            let beta = rz_new / rz;
            rz = rz_new;
            update(&mut p, |i, pi| z[i] + beta * pi);
        }
        Ok((x, it, rel))
    }

    /// One preconditioned CG solve of `matrix x = b` (`b` overwritten by
    /// `x`).
    fn solve_once(&mut self, matrix: &SymmetricCsc, b: &mut [f64]) -> Result<(), SolverError> {
        let t0 = Instant::now();
        if !self.ready {
            return Err(SolverError::Usage(
                "cg: solve called without a successful factorize".into(),
            ));
        }
        let n = self.block_size.len();
        if b.len() != n {
            return Err(SolverError::Usage(format!(
                "cg: right-hand side has {} entries, the matrix {n} equations",
                b.len()
            )));
        }
        if let Some(p) = &self.pattern {
            p.check(matrix, "cg solve")?;
        }
        if let Some(i) = b.iter().position(|v| !v.is_finite()) {
            return Err(SolverError::NonFinite {
                method: format!("cg: the right-hand side holds {} at equation {i}", b[i]),
            });
        }
        let tol = self.settings.tol;
        let max_it = self
            .iteration_cap
            .map_or(self.max_iterations(n), |c| c.min(self.max_iterations(n)));
        let bnorm = norm2(b);
        if bnorm == 0.0 {
            b.fill(0.0);
            self.report.iterations = 0;
            self.report.residual = 0.0;
            self.report.solve_seconds += t0.elapsed().as_secs_f64();
            return Ok(());
        }
        // with AMG, CG runs in the hierarchy's level-0 order
        let perm: Option<Vec<usize>> = self
            .amg
            .as_ref()
            .filter(|a| !a.perm.is_empty())
            .map(|a| a.perm.clone());
        let original = perm.as_ref().map(|_| b.to_vec());
        if let (Some(perm), Some(orig)) = (&perm, &original) {
            update(b, |k, _| orig[perm[k]]);
        }
        let result = match self.settings.method {
            KrylovMethod::Cg => self.cg_iterate(b, bnorm, max_it, tol, t0),
            KrylovMethod::Gmres => self.gmres_iterate(b, bnorm, max_it, tol, t0),
        };
        let (x, it, rel) = match result {
            Ok(r) => r,
            Err(e) => {
                // b holds the right-hand side again, in the caller's order
                if let Some(orig) = &original {
                    b.copy_from_slice(orig);
                }
                return Err(e);
            }
        };
        if x.iter().any(|v| !v.is_finite()) {
            let e = SolverError::NonFinite {
                method: "cg".into(),
            };
            return Err(self.fail(t0, it, rel, e));
        }
        match &perm {
            Some(perm) => {
                for (&i, &v) in perm.iter().zip(&x) {
                    b[i] = v;
                }
            }
            None => b.copy_from_slice(&x),
        }
        self.report.iterations = it;
        self.report.residual = rel;
        self.report.solve_seconds += t0.elapsed().as_secs_f64();
        tracing::debug!(iterations = it, residual = rel, "cg converged");
        Ok(())
    }
}

inventory::submit! {
    SolverEntry {
        key: "cg",
        description: "preconditioned conjugate gradients with Jacobi, 3x3 nodal block-Jacobi or smoothed-aggregation AMG preconditioning",
        params: CG_PARAMS,
        build: |table| Ok(Box::new(CgSolver::from_table(table)?)),
    }
}

inventory::submit! {
    SolverEntry {
        key: "gmres",
        description: "restarted GMRES for symmetric indefinite (softening) tangents, AMG (default), block-Jacobi or Jacobi preconditioning; the same parameters as `cg` plus `restart`",
        params: CG_PARAMS,
        build: |table| Ok(Box::new(CgSolver::from_table_with(table, KrylovMethod::Gmres)?)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gallery::{grid_3d, Stencil};

    #[test]
    fn block_layout_follows_coordinates() {
        let (a, mut coords) = grid_3d(2, 2, 1, 3, Stencil::Point7);
        // pretend node 1 lost a dof: give equation 5 other coordinates
        coords[5] = [9.0, 9.0, 9.0];
        let mut s = CgSolver::default();
        s.analyze(&a, Some(&coords)).unwrap();
        assert_eq!(s.block_count(), 3);
        assert_eq!(s.block_size[3], 1);
        assert_eq!(s.block_size[6], 3);
        let mut j = CgSolver::new(CgSettings {
            preconditioner: Preconditioner::Jacobi,
            ..Default::default()
        });
        j.analyze(&a, Some(&coords)).unwrap();
        assert_eq!(j.block_count(), 0);
    }

    #[test]
    fn indefinite_matrix_breaks_down_with_numbers() {
        // [[1,2],[2,1]], b along the negative eigenvector (1,-1)
        let mut a = SymmetricCsc::from_columns(vec![vec![0], vec![0, 1]]);
        a.values = vec![1.0, 2.0, 1.0];
        let mut s = CgSolver::new(CgSettings {
            preconditioner: Preconditioner::Jacobi,
            ..Default::default()
        });
        s.analyze(&a, None).unwrap();
        s.factorize(&a).unwrap();
        let mut b = vec![1.0, -1.0];
        let e = s.solve_in_place(&a, &mut b).unwrap_err();
        assert!(matches!(e, SolverError::NotPositiveDefinite { .. }), "{e}");
        assert_eq!(b, vec![1.0, -1.0]);
    }
}
