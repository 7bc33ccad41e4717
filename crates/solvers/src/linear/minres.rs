//! MINRES (Paige and Saunders 1975) for symmetric, possibly indefinite
//! systems (softening tangents), with a symmetric positive-definite
//! diagonal preconditioner `M = |diag(A)|`.
//!
//! # Algorithm
//!
//! Preconditioned Lanczos builds `M`-orthonormal vectors `v_k` with
//! `A V_k = V_{k+1} T_k` (`T_k` tridiagonal, `(k+1) × k`); MINRES takes
//! `x_k = V_k y_k` minimising `||β_1 e_1 - T_k y||`, i.e. the residual
//! `||b - A x||_{M^-1}` over the Krylov space. The least-squares problem is
//! updated by one Givens rotation per step (`c_k, s_k`), so `x_k` follows
//! from a three-term recurrence of search directions `w_k` and the residual
//! norm estimate is `φ̄_k = φ̄_{k-1} s_k` without forming `r_k`. Unlike CG,
//! nothing requires `A` to be definite: MINRES converges for every
//! symmetric non-singular `A` (at a rate set by the eigenvalues on both
//! sides of zero). `M` must be SPD, hence `|diag(A)|` rather than
//! `diag(A)`.
//!
//! Stopping: `φ̄_k / φ̄_0 <= tol`, confirmed by the true residual
//! `||b - A x|| / ||b|| <= tol`; otherwise MINRES restarts from `x` (at most
//! 5 times). Failures are [`SolverError::NotConverged`] (iteration limit or
//! stagnation, with the numbers) or [`SolverError::NonFinite`].

use crate::common::{dot, norm2, validate, FullCsr, Pattern};
use junta_core::registry::{parse_params, ParamDoc, SolverEntry};
use junta_core::{LinearSolver, MatrixKind, SolveReport, SolverError, SymmetricCsc};
use serde::Deserialize;
use std::time::Instant;

/// Settings of [`MinresSolver`] (TOML parameters of the `minres` key).
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct MinresSettings {
    /// Relative residual `||b - A x|| / ||b||` to reach (1e-10).
    pub tol: f64,
    /// Iteration limit; `None`: `min(10 n, 50000)` (at least 100).
    pub max_iterations: Option<usize>,
}

impl Default for MinresSettings {
    fn default() -> Self {
        MinresSettings {
            tol: 1e-10,
            max_iterations: None,
        }
    }
}

/// Parameter documentation of the `minres` registry entry.
pub const MINRES_PARAMS: &[ParamDoc] = &[
    ParamDoc {
        name: "tol",
        doc: "relative residual ||b - A x||/||b|| to reach (default 1e-10)",
    },
    ParamDoc {
        name: "max_iterations",
        doc: "iteration limit (default min(10 n, 50000))",
    },
];

/// MINRES back end (registry key `"minres"`), symmetric indefinite.
#[derive(Debug)]
pub struct MinresSolver {
    settings: MinresSettings,
    pattern: Option<Pattern>,
    full: FullCsr,
    inv_m: Vec<f64>,
    ready: bool,
    report: SolveReport,
}

impl Default for MinresSolver {
    fn default() -> Self {
        Self::new(MinresSettings::default())
    }
}

impl MinresSolver {
    /// A solver with the given settings.
    pub fn new(settings: MinresSettings) -> Self {
        MinresSolver {
            settings,
            pattern: None,
            full: FullCsr::default(),
            inv_m: Vec::new(),
            ready: false,
            report: SolveReport {
                solver: "minres".into(),
                ..Default::default()
            },
        }
    }

    /// From a TOML parameter table (unknown keys are an error).
    pub fn from_table(table: &toml::Table) -> Result<Self, junta_core::CoreError> {
        Ok(Self::new(parse_params("solver", "minres", table)?))
    }

    /// One MINRES run from `x` on `A x = b`; returns the iterations used.
    fn run(&self, b: &[f64], x: &mut [f64], max_it: usize, tol_abs: f64) -> usize {
        let n = b.len();
        let mut q = vec![0.0; n];
        self.full.mul(x, &mut q);
        let mut r1: Vec<f64> = b.iter().zip(&q).map(|(b, q)| b - q).collect();
        let mut y: Vec<f64> = r1.iter().zip(&self.inv_m).map(|(r, m)| r * m).collect();
        let beta1 = dot(&r1, &y).sqrt();
        if beta1 == 0.0 {
            return 0;
        }
        let mut r2 = r1.clone();
        let (mut oldb, mut beta) = (0.0, beta1);
        let (mut dbar, mut epsln, mut phibar) = (0.0f64, 0.0f64, beta1);
        let (mut cs, mut sn) = (-1.0f64, 0.0f64);
        let mut w = vec![0.0; n];
        let mut w1 = vec![0.0; n];
        let mut w2 = vec![0.0; n];
        let mut v = vec![0.0; n];
        for it in 1..=max_it {
            let s = 1.0 / beta;
            for (vi, yi) in v.iter_mut().zip(&y) {
                *vi = s * yi;
            }
            self.full.mul(&v, &mut y);
            if it >= 2 {
                let f = beta / oldb;
                for (yi, ri) in y.iter_mut().zip(&r1) {
                    *yi -= f * ri;
                }
            }
            let alfa = dot(&v, &y);
            let f = alfa / beta;
            for (yi, ri) in y.iter_mut().zip(&r2) {
                *yi -= f * ri;
            }
            std::mem::swap(&mut r1, &mut r2);
            r2.copy_from_slice(&y);
            for (yi, (ri, mi)) in y.iter_mut().zip(r2.iter().zip(&self.inv_m)) {
                *yi = ri * mi;
            }
            oldb = beta;
            beta = dot(&r2, &y).max(0.0).sqrt();
            let oldeps = epsln;
            let delta = cs * dbar + sn * alfa;
            let gbar = sn * dbar - cs * alfa;
            epsln = sn * beta;
            dbar = -cs * beta;
            let gamma = gbar.hypot(beta).max(f64::EPSILON);
            cs = gbar / gamma;
            sn = beta / gamma;
            let phi = cs * phibar;
            phibar *= sn;
            let denom = 1.0 / gamma;
            std::mem::swap(&mut w1, &mut w2);
            std::mem::swap(&mut w2, &mut w);
            for i in 0..n {
                w[i] = (v[i] - oldeps * w1[i] - delta * w2[i]) * denom;
                x[i] += phi * w[i];
            }
            if phibar <= tol_abs || beta == 0.0 || !phibar.is_finite() {
                return it;
            }
        }
        max_it
    }
}

impl LinearSolver for MinresSolver {
    fn key(&self) -> &'static str {
        "minres"
    }

    fn analyze(
        &mut self,
        matrix: &SymmetricCsc,
        _c: Option<&[[f64; 3]]>,
    ) -> Result<(), SolverError> {
        let t0 = Instant::now();
        validate(matrix)?;
        self.full = FullCsr::new(matrix);
        self.pattern = Some(Pattern::of(matrix));
        self.ready = false;
        self.report.analyze_seconds += t0.elapsed().as_secs_f64();
        Ok(())
    }

    fn factorize(&mut self, matrix: &SymmetricCsc) -> Result<(), SolverError> {
        let t0 = Instant::now();
        let Some(p) = &self.pattern else {
            return Err(SolverError::Usage(
                "minres: factorize before analyze".into(),
            ));
        };
        p.check(matrix, "minres factorize")?;
        if let Some(p) = matrix.values.iter().position(|v| !v.is_finite()) {
            return Err(SolverError::NonFinite {
                method: format!("minres set-up: stored entry {p} is {}", matrix.values[p]),
            });
        }
        self.full.fill(matrix);
        self.inv_m = matrix
            .diagonal()
            .iter()
            .map(|d| if d.abs() > 0.0 { 1.0 / d.abs() } else { 1.0 })
            .collect();
        self.ready = true;
        self.report.factor_seconds += t0.elapsed().as_secs_f64();
        Ok(())
    }

    fn solve_in_place(&mut self, matrix: &SymmetricCsc, b: &mut [f64]) -> Result<(), SolverError> {
        let t0 = Instant::now();
        if !self.ready {
            return Err(SolverError::Usage("minres: solve without factorize".into()));
        }
        let n = self.inv_m.len();
        if b.len() != n {
            return Err(SolverError::Usage(format!(
                "minres: right-hand side has {} entries, the matrix {n} equations",
                b.len()
            )));
        }
        if let Some(p) = &self.pattern {
            p.check(matrix, "minres solve")?;
        }
        let tol = self.settings.tol;
        let max_it = self
            .settings
            .max_iterations
            .unwrap_or_else(|| (10 * n).clamp(100, 50_000));
        let bnorm = norm2(b);
        let mut x = vec![0.0; n];
        let mut r = vec![0.0; n];
        let mut total = 0;
        let mut rel = if bnorm == 0.0 { 0.0 } else { 1.0 };
        for _restart in 0..=5 {
            if rel <= tol || total >= max_it {
                break;
            }
            // preconditioned residual target, scaled from the true one
            let bm = dot(
                b,
                &b.iter()
                    .zip(&self.inv_m)
                    .map(|(b, m)| b * m)
                    .collect::<Vec<_>>(),
            )
            .sqrt();
            total += self.run(b, &mut x, max_it - total, 0.5 * tol * bm);
            self.full.mul(&x, &mut r);
            let rr: f64 = r.iter().zip(b.iter()).map(|(a, b)| (b - a) * (b - a)).sum();
            rel = rr.sqrt() / bnorm;
            if !rel.is_finite() {
                return Err(SolverError::NonFinite {
                    method: format!("minres after {total} iterations"),
                });
            }
        }
        self.report.iterations = total;
        self.report.residual = rel;
        self.report.solve_seconds += t0.elapsed().as_secs_f64();
        if rel > tol {
            return Err(SolverError::NotConverged {
                method: "minres (|diag| preconditioner)".into(),
                iterations: total,
                residual: rel,
                tolerance: tol,
            });
        }
        b.copy_from_slice(&x);
        Ok(())
    }

    fn report(&self) -> SolveReport {
        self.report.clone()
    }

    fn accepts(&self, kind: MatrixKind) -> bool {
        kind != MatrixKind::General
    }
}

inventory::submit! {
    SolverEntry {
        key: "minres",
        description: "MINRES for symmetric indefinite (softening) tangents, |diag| preconditioner",
        params: MINRES_PARAMS,
        build: |table| Ok(Box::new(MinresSolver::from_table(table)?)),
    }
}
