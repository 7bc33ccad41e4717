//! The 4-node plane quadrilateral with incompatible modes, `cpe4i` and
//! `cps4i`, and axisymmetric `cax4i` (Wilson, Taylor, Doherty and Ghaboussi 1973 with Taylor,
//! Beresford and Wilson's 1976 modification: QM6, the element Abaqus calls
//! CPE4I / CPS4I), the plane counterpart of [`crate::h8i`].
//!
//! A bilinear quadrilateral cannot bend: the shear strain it carries with
//! any curvature locks it. The two bubble modes `P_1 = 1 - xi^2`, `P_2 = 1
//! - eta^2` per displacement component, condensed out element by element,
//! give it the quadratic displacement that bending needs:
//!
//! ```text
//! u(xi) = sum_a N_a(xi) u_a + sum_k P_k(xi) alpha_k,    k = 1, 2
//! ```
//!
//! with 4 internal parameters `alpha` (mode `k`, component `i` at `2 k +
//! i`). Taylor's modification takes the mode gradients with the Jacobian
//! `J0` at the centre, scaled by `det J0 / det J`, `dP_k/dx = (det J0 / det
//! J) J0^-T dP_k/dxi`, so that `int B_a dA = 0` and a constant strain does
//! no work on the modes (the patch test passes on any quadrilateral).
//!
//! With the section's `D` ([`super`]: plane strain or plane stress),
//! `sigma_0 = sigma(u, alpha = 0)` at each point and
//!
//! ```text
//! K_uu = int B_u^T D B_u dV,  K_ua = int B_u^T D B_a dV,  K_aa = int B_a^T D B_a dV,
//! r_a  = int B_a^T sigma_0 dV,          alpha = -K_aa^-1 r_a,
//! f    = int B_u^T sigma_0 dV + K_ua alpha,   K = K_uu - K_ua K_aa^-1 K_au,
//! ```
//!
//! exact for the linear elastic materials (a thermal strain is carried by
//! `sigma_0`). Small strain only. Outputs are those of the plane elements,
//! with the modes' strain added.
//!
//! **Axisymmetric (`cax4i`).** The ring's volume is `dV = 2 pi r dA`, so
//! Taylor's gradients, whose area integral vanishes, no longer integrate
//! to zero over the volume, and a constant stress would work on the modes.
//! As Simo and Rifai (1990) do for their enhanced strains, the gradients
//! are scaled by `r0 / r` (`r0` the centre's radius), `dP_k/dx <- (r0 / r)
//! (det J0 / det J) J0^-T dP_k/dxi`, so that `int B_a dV = 2 pi r0 int
//! J0^-T dP_k/dxi det J0 dxi = 0`; the modes take no hoop strain (a `P_k /
//! r` term would break the patch test too). The patch test passes; pure
//! bending of a plate is no longer exact (the scaled gradients are not
//! those of a quadratic), but converges at second order without locking
//! (`crates/cli/tests/lame_cylinder.rs`).

use super::{PlaneElement, PlanePoint, MAX_NODES};
use junta_core::element::{ElementContext, ElementError, PointOutput};
use nalgebra::{Matrix4, SMatrix};

type Kua = SMatrix<f64, 8, 4>;

/// `B_a` over `(alpha_{k,x}, alpha_{k,y})` of mode gradient `h`: the
/// rows `[xx, yy, zz, xy]` of the 2 columns of mode `k`.
fn mode_rows(h: [f64; 2]) -> [[f64; 2]; 4] {
    [[h[0], 0.0], [0.0, h[1]], [0.0, 0.0], [h[1], h[0]]]
}

/// `B_u` rows of node `a` with gradient `g` and `h = N_a / r`
/// (axisymmetric: the hoop strain `u_r / r`) or 0.
fn node_rows(g: [f64; 2], h: f64) -> [[f64; 2]; 4] {
    [[g[0], 0.0], [0.0, g[1]], [h, 0.0], [g[1], g[0]]]
}

/// The mode gradients of the four points.
type ModeGradients = [[[f64; 2]; 2]; 4];

/// `sum_r x[r][i] D[r][s] y[s][j]` for 4-row blocks.
fn btdb(x: &[[f64; 2]; 4], d: &Matrix4<f64>, y: &[[f64; 2]; 4]) -> [[f64; 2]; 2] {
    let mut out = [[0.0; 2]; 2];
    for (i, o) in out.iter_mut().enumerate() {
        for (j, v) in o.iter_mut().enumerate() {
            for r in 0..4 {
                for s in 0..4 {
                    *v += x[r][i] * d[(r, s)] * y[s][j];
                }
            }
        }
    }
    out
}

/// The 2 x 2 Jacobian and its determinant at point data `p`.
fn jacobian(p: &PlanePoint, coords: &[[f64; 3]]) -> ([[f64; 2]; 2], f64) {
    let mut j = [[0.0; 2]; 2];
    for a in 0..4 {
        for r in 0..2 {
            for c in 0..2 {
                j[r][c] += coords[a][r] * p.dn[a][c];
            }
        }
    }
    (j, j[0][0] * j[1][1] - j[0][1] * j[1][0])
}

/// The condensed element: per point the node gradients, `B_a` rows, `dV`
/// and `sigma_0`, and the blocks.
struct Condensed {
    k_ua: Kua,
    k_aa_inv: Matrix4<f64>,
    alpha: [f64; 4],
}

impl PlaneElement {
    /// The mode gradients of every point (Taylor's, [`Self::mode_gradients`]);
    /// axisymmetric, scaled by `r0 / r` (module docs).
    fn all_mode_gradients(&self, coords: &[[f64; 3]]) -> ModeGradients {
        let mut h: ModeGradients =
            std::array::from_fn(|q| self.mode_gradients(coords, q, self.xi[q]));
        if self.section == super::Section::Axisymmetric {
            let radius = |p: &PlanePoint| (0..4).map(|a| p.n[a] * coords[a][0]).sum::<f64>();
            let r0 = radius(&self.centre);
            for (hq, p) in h.iter_mut().zip(&self.points) {
                let s = r0 / radius(p);
                for hm in hq.iter_mut() {
                    hm[0] *= s;
                    hm[1] *= s;
                }
            }
        }
        h
    }

    /// Mode gradients (Taylor's) at the points, with the centre's `J0`.
    fn mode_gradients(&self, coords: &[[f64; 3]], q: usize, xi: [f64; 2]) -> [[f64; 2]; 2] {
        let (j0, det0) = jacobian(&self.centre, coords);
        let (_, det) = jacobian(&self.points[q], coords);
        let s = det0 / det;
        // J0^-T dP/dxi, dP_1/dxi = (-2 xi, 0), dP_2/dxi = (0, -2 eta)
        let inv_t = |d: [f64; 2]| {
            [
                (j0[1][1] * d[0] - j0[1][0] * d[1]) / det0 * s,
                (-j0[0][1] * d[0] + j0[0][0] * d[1]) / det0 * s,
            ]
        };
        [inv_t([-2.0 * xi[0], 0.0]), inv_t([0.0, -2.0 * xi[1]])]
    }

    /// Blocks, the modes' parameters and (if asked) `K_uu` accumulated
    /// into `k` (in-plane entries of the 12 x 12 row-major matrix), with the
    /// force of `sigma_0` into `f`.
    fn condense(
        &self,
        ctx: &ElementContext<'_>,
        f: &mut [f64],
        mut k: Option<&mut [f64]>,
    ) -> Result<Condensed, ElementError> {
        let mut g = [[0.0; 2]; MAX_NODES];
        let (mut k_ua, mut k_aa, mut r_a) = (Kua::zeros(), Matrix4::zeros(), [0.0; 4]);
        let modes = self.all_mode_gradients(ctx.coords);
        let axi = self.section == super::Section::Axisymmetric;
        for (q, p) in self.points.iter().enumerate() {
            let (x, vol) = self.gradients(p, ctx.coords, q, &mut g)?;
            let dv = p.w * vol;
            let d = self.stiffness_at(x);
            let s = self
                .point_state(p, self.active_strain(p, &g, x, ctx.disp), x, ctx)
                .stress;
            let s4 = [s[0], s[1], s[2], s[3]];
            let h = modes[q];
            let ba = [mode_rows(h[0]), mode_rows(h[1])];
            let bu: [[[f64; 2]; 4]; 4] =
                std::array::from_fn(|a| node_rows(g[a], if axi { p.n[a] / x[0] } else { 0.0 }));
            for a in 0..4 {
                for i in 0..2 {
                    f[3 * a + i] += dv * (0..4).map(|r| bu[a][r][i] * s4[r]).sum::<f64>();
                }
            }
            for (m, bm) in ba.iter().enumerate() {
                for i in 0..2 {
                    r_a[2 * m + i] += dv * (0..4).map(|r| bm[r][i] * s4[r]).sum::<f64>();
                }
                for (n, bn) in ba.iter().enumerate() {
                    let blk = btdb(bm, &d, bn);
                    for i in 0..2 {
                        for j in 0..2 {
                            k_aa[(2 * m + i, 2 * n + j)] += dv * blk[i][j];
                        }
                    }
                }
                for (a, bua) in bu.iter().enumerate() {
                    let blk = btdb(bua, &d, bm);
                    for i in 0..2 {
                        for j in 0..2 {
                            k_ua[(2 * a + i, 2 * m + j)] += dv * blk[i][j];
                        }
                    }
                }
            }
            if let Some(k) = k.as_deref_mut() {
                for a in 0..4 {
                    for b in 0..4 {
                        let blk = btdb(&bu[a], &d, &bu[b]);
                        for i in 0..2 {
                            for j in 0..2 {
                                k[(3 * a + i) * 12 + 3 * b + j] += dv * blk[i][j];
                            }
                        }
                    }
                }
            }
        }
        let k_aa_inv = k_aa
            .try_inverse()
            .ok_or(ElementError::NegativeJacobian { point: 0, det: 0.0 })?;
        let alpha: [f64; 4] = (-(k_aa_inv * nalgebra::Vector4::from(r_a))).into();
        Ok(Condensed {
            k_ua,
            k_aa_inv,
            alpha,
        })
    }

    /// `f = int B_u^T sigma_0 dV + K_ua alpha` and `K = K_uu - K_ua K_aa^-1
    /// K_au` (module docs).
    pub(super) fn compute_incompatible(
        &self,
        ctx: &ElementContext<'_>,
        f_int: &mut [f64],
        mut k: Option<&mut [f64]>,
    ) -> Result<(), ElementError> {
        let c = self.condense(ctx, f_int, k.as_deref_mut())?;
        let fa = c.k_ua * nalgebra::Vector4::from(c.alpha);
        for a in 0..4 {
            for i in 0..2 {
                f_int[3 * a + i] += fa[2 * a + i];
            }
        }
        if let Some(k) = k {
            let corr = c.k_ua * c.k_aa_inv * c.k_ua.transpose();
            for a in 0..4 {
                for b in 0..4 {
                    for i in 0..2 {
                        for j in 0..2 {
                            k[(3 * a + i) * 12 + 3 * b + j] -= corr[(2 * a + i, 2 * b + j)];
                        }
                    }
                }
            }
        }
        Ok(())
    }

    /// Point outputs with the modes' strain: the plane outputs of the
    /// strain `B_u u + B_a alpha`.
    pub(super) fn point_outputs_incompatible(
        &self,
        ctx: &ElementContext<'_>,
    ) -> Result<Vec<PointOutput>, ElementError> {
        let mut scratch = [0.0; 12];
        let c = self.condense(ctx, &mut scratch, None)?;
        let mut g = [[0.0; 2]; MAX_NODES];
        let mut out = Vec::with_capacity(4);
        let modes = self.all_mode_gradients(ctx.coords);
        for (q, p) in self.points.iter().enumerate() {
            let (x, vol) = self.gradients(p, ctx.coords, q, &mut g)?;
            let mut e = self.active_strain(p, &g, x, ctx.disp);
            let h = modes[q];
            for (m, hm) in h.iter().enumerate() {
                let rows = mode_rows(*hm);
                for (r, row) in rows.iter().enumerate() {
                    e[r] += row[0] * c.alpha[2 * m] + row[1] * c.alpha[2 * m + 1];
                }
            }
            out.push(self.point_output(p, e, x, vol, ctx));
        }
        Ok(out)
    }
}
