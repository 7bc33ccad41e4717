//! Restarted GMRES (Saad and Schultz 1986) with right preconditioning, the
//! Krylov method of the `gmres` back end: [`super::CgSolver`] with
//! `method = Gmres`, sharing its preconditioners, AMG hierarchy and reuse.
//!
//! # Algorithm
//!
//! With `M^-1` the preconditioner (one AMG V-cycle, or block Jacobi), GMRES
//! solves `A M^-1 y = b`, `x = M^-1 y`: Arnoldi with modified Gram-Schmidt
//! (re-orthogonalised once) builds `A M^-1 V_m = V_{m+1} H_m`; the
//! least-squares problem `min ||β e_1 - H_m y||` is updated by one Givens
//! rotation per step, so `|g_{k+1}|` is the residual norm `||b - A x_k||`
//! without forming it (right preconditioning minimises the true residual,
//! not a preconditioned one). After `m = restart` steps, or at the
//! tolerance, `x += M^-1 V_m y`; the true residual is computed and the
//! method restarts from it until `||b - A x|| / ||b|| <= tol`.
//!
//! Unlike CG, nothing needs `A` or `M^-1` to be positive definite: a
//! softening tangent (symmetric, a few negative eigenvalues) and an AMG
//! hierarchy built on it (its block inverses and coarsest factor taken
//! with pivoting, see [`crate::amg::AmgSettings::indefinite`]) are both
//! fine. The price is `m` stored vectors and a growing orthogonalisation
//! cost per step.
//!
//! Failures: [`SolverError::NotConverged`] (iteration limit, or the
//! residual not halved over a whole restart cycle: stagnation, with the
//! numbers) and [`SolverError::NonFinite`].

use super::CgSolver;
use crate::common::{dot, norm2, update};
use junta_core::SolverError;
use std::time::Instant;

impl CgSolver {
    /// Right-preconditioned GMRES(`restart`) from `x = 0` (vectors in the
    /// preconditioner's order); returns `x`, the iterations and the true
    /// relative residual.
    pub(super) fn gmres_iterate(
        &mut self,
        b: &[f64],
        bnorm: f64,
        max_it: usize,
        tol: f64,
        t0: Instant,
    ) -> Result<(Vec<f64>, usize, f64), SolverError> {
        let n = b.len();
        let m = self.settings.restart.clamp(1, max_it.max(1));
        let mut x = vec![0.0; n];
        let mut r = b.to_vec();
        let mut w = vec![0.0; n];
        let mut z = vec![0.0; n];
        // Krylov basis: vectors allocated once and reused by every restart
        let mut basis: Vec<Vec<f64>> = Vec::with_capacity(m + 1);
        let mut used;
        let mut h = vec![vec![0.0; m]; m + 1];
        let (mut cs, mut sn, mut g) = (vec![0.0; m], vec![0.0; m], vec![0.0; m + 1]);
        let mut it = 0usize;
        let mut rel = 1.0;
        let mut cycle_start_rel = rel;
        loop {
            let beta = norm2(&r);
            rel = beta / bnorm;
            if rel <= tol {
                break;
            }
            if it >= max_it {
                let e = SolverError::NotConverged {
                    method: format!(
                        "gmres({m}, {:?} preconditioner)",
                        self.settings.preconditioner
                    ),
                    iterations: it,
                    residual: rel,
                    tolerance: tol,
                };
                return Err(self.fail(t0, it, rel, e));
            }
            if it > 0 && rel > 0.5 * cycle_start_rel {
                let e = SolverError::NotConverged {
                    method: format!(
                        "gmres({m}, {:?} preconditioner; stagnated: a whole restart cycle reduced the residual only from {cycle_start_rel:.3e} to {rel:.3e}; a longer `restart` or a better preconditioner may help)",
                        self.settings.preconditioner
                    ),
                    iterations: it,
                    residual: rel,
                    tolerance: tol,
                };
                return Err(self.fail(t0, it, rel, e));
            }
            cycle_start_rel = rel;
            if basis.is_empty() {
                basis.push(vec![0.0; n]);
            }
            update(&mut basis[0], |i, _| r[i] / beta);
            used = 1;
            g.fill(0.0);
            g[0] = beta;
            let mut k_done = 0;
            for k in 0..m {
                if it >= max_it {
                    break;
                }
                it += 1;
                // w = A M^-1 v_k
                self.precondition(&basis[k], &mut z);
                self.matvec(&z, &mut w);
                for _ in 0..2 {
                    for (j, vj) in basis[..used].iter().enumerate() {
                        let hj = dot(&w, vj);
                        h[j][k] += hj;
                        update(&mut w, |i, wi| wi - hj * vj[i]);
                    }
                }
                let hk1 = norm2(&w);
                if !hk1.is_finite() {
                    let e = SolverError::NonFinite {
                        method: format!("gmres at iteration {it} (||A M^-1 v|| = {hk1:e})"),
                    };
                    return Err(self.fail(t0, it, rel, e));
                }
                h[k + 1][k] = hk1;
                // previous rotations, then a new one zeroing h[k+1][k]
                for j in 0..k {
                    let t = cs[j] * h[j][k] + sn[j] * h[j + 1][k];
                    h[j + 1][k] = -sn[j] * h[j][k] + cs[j] * h[j + 1][k];
                    h[j][k] = t;
                }
                let d = h[k][k].hypot(hk1);
                let (c, s) = if d == 0.0 {
                    (1.0, 0.0)
                } else {
                    (h[k][k] / d, hk1 / d)
                };
                cs[k] = c;
                sn[k] = s;
                h[k][k] = d;
                h[k + 1][k] = 0.0;
                g[k + 1] = -s * g[k];
                g[k] *= c;
                k_done = k + 1;
                let estimate = g[k + 1].abs() / bnorm;
                if estimate <= tol || hk1 == 0.0 || k + 1 == m {
                    break;
                }
                if basis.len() == used {
                    basis.push(vec![0.0; n]);
                }
                update(&mut basis[used], |i, _| w[i] / hk1);
                used += 1;
            }
            // y = H^-1 g (upper triangular), x += M^-1 V y
            let mut y = vec![0.0; k_done];
            for i in (0..k_done).rev() {
                let mut acc = g[i];
                for (j, yj) in y.iter().enumerate().skip(i + 1) {
                    acc -= h[i][j] * yj;
                }
                y[i] = if h[i][i] != 0.0 { acc / h[i][i] } else { 0.0 };
            }
            w.fill(0.0);
            for (vj, yj) in basis[..used].iter().zip(&y) {
                update(&mut w, |i, wi| wi + yj * vj[i]);
            }
            self.precondition(&w, &mut z);
            update(&mut x, |i, xi| xi + z[i]);
            for row in h.iter_mut() {
                row.fill(0.0);
            }
            // true residual
            self.matvec(&x, &mut w);
            update(&mut r, |i, _| b[i] - w[i]);
        }
        Ok((x, it, rel))
    }
}
