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
//! `sigma_0`). Outputs are those of the plane elements, with the modes'
//! strain added.
//!
//! **Large deformation (`nlgeom`).** As [`crate::h8i`] does in 3D, the
//! modes enhance the deformation gradient of the total-Lagrangian plane
//! element ([`super`], "Large deformation") as two more nodes with the
//! gradients `G_k` above and no hoop stretch:
//!
//! ```text
//! F = I + sum_a u_a ⊗ g_a + sum_k alpha_k ⊗ G_k,   E = (F^T F - I) / 2,   S = D E
//! ```
//!
//! For each `u` the element solves its own equations `r_alpha(u, alpha) =
//! 0` by Newton from the last converged `alpha` (the element's state, 4
//! values) to `|Δalpha| <= 1e-12` of its size (at most 25 iterations,
//! then an error that cuts the increment back), and condenses the full 12
//! x 12 tangent there: `K = K_uu - K_ua K_aa^-1 K_au` is exact (implicit
//! function theorem). A plane-stress cantilever of 50 CPS4I follows the
//! elastica within 0.06 % to an 82-degree tip rotation
//! (`crates/cli/tests/large_deformation.rs`); the tangent matches central
//! differences (`crates/elements/tests/plane.rs`).
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
use nalgebra::{Matrix4, SMatrix, SVector};

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

/// Dofs of the finite system: 4 nodes and 2 modes, 2 components each.
const NT: usize = 12;

/// Most Newton iterations of the modes' own equations under `nlgeom`.
const MODE_ITERATIONS: usize = 25;

/// Force (8 nodal + 4 modal) and full tangent of the total-Lagrangian
/// element with its modes, at one `(u, alpha)`.
struct FiniteModes {
    f: SVector<f64, NT>,
    k: SMatrix<f64, NT, NT>,
}

impl PlaneElement {
    /// The Taylor-modified mode gradients added to the deformation gradient
    /// of point `p`: `F += sum_k alpha_k ⊗ G_k` (module docs, "Large
    /// deformation"); the modes take no hoop stretch.
    fn stretch_with_modes(
        &self,
        p: &PlanePoint,
        g: &[[f64; 2]; MAX_NODES],
        x: [f64; 3],
        ctx: &ElementContext<'_>,
        modes: &[[f64; 2]; 2],
        alpha: &[f64; 4],
    ) -> super::Stretch {
        let mut st = self.stretch(p, g, x, ctx.disp);
        for (k, gk) in modes.iter().enumerate() {
            for (i, fi) in st.f.iter_mut().enumerate() {
                fi[0] += alpha[2 * k + i] * gk[0];
                fi[1] += alpha[2 * k + i] * gk[1];
            }
        }
        st
    }

    /// The total-Lagrangian force and (if `with_k`) tangent of the 4 nodes
    /// and the 2 modes taken as two more nodes with gradients `G_k` and no
    /// hoop term, at the displacements of `ctx` and the modes `alpha`.
    fn finite_modes_system(
        &self,
        ctx: &ElementContext<'_>,
        modes: &ModeGradients,
        alpha: &[f64; 4],
        with_k: bool,
    ) -> Result<FiniteModes, ElementError> {
        let axi = self.section == super::Section::Axisymmetric;
        let mut out = FiniteModes {
            f: SVector::zeros(),
            k: SMatrix::zeros(),
        };
        let mut g = [[0.0; 2]; MAX_NODES];
        for (q, p) in self.points.iter().enumerate() {
            let (x, vol) = self.gradients(p, ctx.coords, q, &mut g)?;
            let dv = p.w * vol;
            let st = self.stretch_with_modes(p, &g, x, ctx, &modes[q], alpha);
            let s = self.point_state(p, st.green(), x, ctx).stress;
            let s4 = [s[0], s[1], s[2], s[3]];
            // gradient and hoop factor of each of the 6 "nodes"
            let grad = |n: usize| if n < 4 { g[n] } else { modes[q][n - 4] };
            let hoop = |n: usize| if axi && n < 4 { p.n[n] / x[0] } else { 0.0 };
            let b: [[[f64; 2]; 4]; 6] = std::array::from_fn(|n| st.variation(grad(n), hoop(n)));
            for (n, bn) in b.iter().enumerate() {
                for i in 0..2 {
                    out.f[2 * n + i] += dv * (0..4).map(|r| bn[r][i] * s4[r]).sum::<f64>();
                }
            }
            if !with_k {
                continue;
            }
            let d = self.stiffness_at(x);
            for m in 0..6 {
                for n in 0..6 {
                    let blk = btdb(&b[m], &d, &b[n]);
                    let (gm, gn) = (grad(m), grad(n));
                    let geo = gm[0] * (s4[0] * gn[0] + s4[3] * gn[1])
                        + gm[1] * (s4[3] * gn[0] + s4[1] * gn[1]);
                    for i in 0..2 {
                        for j in 0..2 {
                            let mut v = blk[i][j];
                            if i == j {
                                v += geo;
                                if i == 0 {
                                    v += s4[2] * hoop(m) * hoop(n);
                                }
                            }
                            out.k[(2 * m + i, 2 * n + j)] += dv * v;
                        }
                    }
                }
            }
        }
        Ok(out)
    }

    /// Solve the modes' equations `r_alpha(u, alpha) = 0` by Newton from
    /// the committed modes (zero when there are none); the modes and the
    /// full system there.
    fn solve_finite_modes(
        &self,
        ctx: &ElementContext<'_>,
        modes: &ModeGradients,
    ) -> Result<([f64; 4], FiniteModes), ElementError> {
        let mut alpha = [0.0; 4];
        if ctx.state_committed.len() >= 4 {
            alpha.copy_from_slice(&ctx.state_committed[..4]);
        }
        let size = element_size(ctx.coords);
        for _ in 0..MODE_ITERATIONS {
            let sys = self.finite_modes_system(ctx, modes, &alpha, true)?;
            let kaa = Matrix4::from_fn(|r, c| sys.k[(8 + r, 8 + c)]);
            let ra = nalgebra::Vector4::from_fn(|r, _| sys.f[8 + r]);
            let step = kaa.lu().solve(&ra).ok_or_else(singular_modes)?;
            for (a, da) in alpha.iter_mut().zip(step.iter()) {
                *a -= da;
            }
            if !step.norm().is_finite() {
                break;
            }
            if step.norm() <= 1e-12 * size {
                let sys = self.finite_modes_system(ctx, modes, &alpha, true)?;
                return Ok((alpha, sys));
            }
        }
        Err(ElementError::Law {
            point: 0,
            message: format!(
                "{}: the incompatible modes did not converge in {MODE_ITERATIONS} Newton iterations (the element is too distorted for this increment)",
                self.key
            ),
        })
    }

    /// Under `nlgeom`: the force of the nodes at the solved modes and the
    /// condensed tangent `K_uu - K_ua K_aa^-1 K_au` (exact by the implicit
    /// function theorem), the modes into `state_trial`.
    pub(super) fn compute_finite_incompatible(
        &self,
        ctx: &ElementContext<'_>,
        state_trial: &mut [f64],
        f_int: &mut [f64],
        k: Option<&mut [f64]>,
    ) -> Result<(), ElementError> {
        let modes = self.all_mode_gradients(ctx.coords);
        let (alpha, sys) = self.solve_finite_modes(ctx, &modes)?;
        state_trial[..4].copy_from_slice(&alpha);
        for a in 0..4 {
            for i in 0..2 {
                f_int[3 * a + i] = sys.f[2 * a + i];
            }
        }
        if let Some(k) = k {
            let kaa = Matrix4::from_fn(|r, c| sys.k[(8 + r, 8 + c)]);
            let kua = Kua::from_fn(|r, c| sys.k[(r, 8 + c)]);
            let x = kaa
                .lu()
                .solve(&kua.transpose())
                .ok_or_else(singular_modes)?;
            let kc = SMatrix::<f64, 8, 8>::from_fn(|r, c| sys.k[(r, c)]) - kua * x;
            for a in 0..4 {
                for b in 0..4 {
                    for i in 0..2 {
                        for j in 0..2 {
                            let (r, c) = (2 * a + i, 2 * b + j);
                            k[(3 * a + i) * 12 + 3 * b + j] = 0.5 * (kc[(r, c)] + kc[(c, r)]);
                        }
                    }
                }
            }
        }
        Ok(())
    }

    /// Point outputs under `nlgeom` with the modes solved from the
    /// committed ones: Cauchy `stress`, Green `strain`, `pk2_stress`.
    pub(super) fn point_outputs_finite_incompatible(
        &self,
        ctx: &ElementContext<'_>,
    ) -> Result<Vec<PointOutput>, ElementError> {
        let modes = self.all_mode_gradients(ctx.coords);
        let (alpha, _) = self.solve_finite_modes(ctx, &modes)?;
        let mut g = [[0.0; 2]; MAX_NODES];
        let mut out = Vec::with_capacity(4);
        for (q, p) in self.points.iter().enumerate() {
            let (x, vol) = self.gradients(p, ctx.coords, q, &mut g)?;
            let st = self.stretch_with_modes(p, &g, x, ctx, &modes[q], &alpha);
            out.push(self.finite_output_of(p, &st, x, vol, ctx));
        }
        Ok(out)
    }
}

fn singular_modes() -> ElementError {
    ElementError::Law {
        point: 0,
        message: "the incompatible-mode tangent K_aa is singular (degenerate element, or a stress state at which the modes buckle)".into(),
    }
}

/// The diagonal of the reference nodes' bounding box (in the plane).
fn element_size(coords: &[[f64; 3]]) -> f64 {
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for x in &coords[..4] {
        for i in 0..2 {
            lo[i] = lo[i].min(x[i]);
            hi[i] = hi[i].max(x[i]);
        }
    }
    ((hi[0] - lo[0]).powi(2) + (hi[1] - lo[1]).powi(2)).sqrt()
}
