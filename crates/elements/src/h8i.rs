//! The 8-node hexahedron with incompatible modes, `h8i` (Wilson, Taylor,
//! Doherty and Ghaboussi 1973; Taylor, Beresford and Wilson 1976; the
//! element Abaqus and CalculiX call C3D8I).
//!
//! A trilinear H8 cannot bend: the shear strain that a bilinear field
//! carries with any curvature stiffens it ("shear locking"; a 10 x 1 x 1
//! H8 cantilever is 36 % too stiff). Adding the quadratic bubble modes that
//! bending needs, condensed out element by element, removes that locking at
//! the cost of one 9 x 9 factorisation per element.
//!
//! ## Displacement field
//!
//! With the trilinear shape functions `N_a` of [`crate::shape::hex_shape`]
//! and the three incompatible modes `P_1 = 1 - xi^2`, `P_2 = 1 - eta^2`,
//! `P_3 = 1 - zeta^2` (zero at the corners, not continuous across elements):
//!
//! ```text
//! u(xi) = Σ_a N_a(xi) u_a + Σ_k P_k(xi) alpha_k,    a = 1..8, k = 1..3
//! ```
//!
//! with 9 internal parameters `alpha = (alpha_k)_i` (mode `k`, component
//! `i`, stored at `3 k + i`). The strain is `eps = B_u u + B_a alpha`, `B_u`
//! the H8 matrix of [`crate::solid`] and `B_a` built the same way from the
//! incompatible-mode gradients.
//!
//! ## Taylor's modification (patch test on distorted meshes)
//!
//! The gradients of `P_k` use the Jacobian `J0` at the element centre and
//! are scaled by `det J0 / det J`:
//!
//! ```text
//! ∂P_k/∂x = (det J0 / det J(xi)) J0^-T ∂P_k/∂xi,   ∂P_k/∂xi_j = -2 xi_k δ_kj
//! ```
//!
//! so that `∫ ∂P_k/∂x dV = det J0 J0^-T ∫ ∂P_k/∂xi dxi = 0`, hence
//! `∫ B_a dV = 0`, exactly (also under the 2x2x2 Gauss rule, which
//! integrates the odd `xi_k` exactly). A constant strain `eps0` therefore does no work on the
//! incompatible modes (`K_au u = (∫ B_a dV)^T C eps0 = 0`), they stay at
//! zero and the element passes the patch test for any trilinear geometry.
//! On a parallelepiped (`J = J0`) the modification changes nothing.
//!
//! ## Static condensation
//!
//! With `sigma = C eps` (`C` from the [`Material`]), 2x2x2 Gauss,
//! `dV = w det J`:
//!
//! ```text
//! | K_uu K_ua | | u     |   | f_u |      K_uu = ∫ B_u^T C B_u dV,  K_ua = ∫ B_u^T C B_a dV,
//! | K_au K_aa | | alpha | = | 0   |      K_aa = ∫ B_a^T C B_a dV
//! ```
//!
//! The internal parameters carry no load, so `alpha = -K_aa^-1 K_au u` and
//!
//! ```text
//! K = K_uu - K_ua K_aa^-1 K_au,    f_int = ∫ B_u^T C (B_u u + B_a alpha) dV = K u.
//! ```
//!
//! The materials are linear elastic, so this condensation (with the
//! material's `C`) is exact and `alpha` need not be stored: it is recomputed
//! from `u` in every call. `K_aa` is factorised by Cholesky (it is
//! positive definite whenever `C` is and `det J > 0`). Everything lives in
//! fixed-size `nalgebra` matrices on the stack; `compute` never allocates.
//!
//! ## Properties (measured in `tests/solids.rs`)
//!
//! * exactly 6 zero-energy modes (the rigid-body motions) for one free
//!   element, distorted or not;
//! * patch test on distorted meshes: linear displacement fields and
//!   constant stresses reproduced to round-off;
//! * a rectangular element under pure bending gives the exact solution
//!   (`u_x = -κ x z`, `w = κ (x^2 + ν (z^2 - y^2)) / 2`: the quadratic
//!   terms are exactly the incompatible modes);
//! * the cantilever example (10 x 1 x 1, `crates/cli/tests/cli.rs`): tip
//!   deflection 1.892e-4 m, 1.5 % below Timoshenko's 1.920e-4 m, where H8
//!   gives 1.234e-4 m (-36 %).
//!
//! ## Against CalculiX 2.20 (C3D8I)
//!
//! On parallelepipeds the two agree to the 7 digits ccx prints (the
//! cantilever deck `crates/cli/tests/data/cantilever_c3d8i.inp`). On
//! distorted elements they differ: ccx's C3D8I uses `J0` without the
//! `det J0 / det J` factor (h8i with the factor removed reproduces ccx's
//! numbers to 7 digits) and so does not pass the patch test: on
//! `crates/cli/tests/data/patch_c3d8i.inp` its interior node is up to 3.4 %
//! off the exact linear field, which h8i reproduces. A two-element skewed
//! cantilever differs by 0.36 % (tip |u| 1.99897e-5 m here, 1.99176e-5 m ccx).
//!
//! ## Large deformation (`nlgeom`)
//!
//! Built with [`Kinematics::Finite`], the incompatible modes enhance the
//! displacement gradient of the total-Lagrangian element
//! ([`crate::total_lagrangian`]):
//!
//! ```text
//! F = I + Σ_a u_a ⊗ g_a + Σ_k alpha_k ⊗ G_k,    E = (F^T F - I) / 2,   S = C E
//! ```
//!
//! with `G_k` the (Taylor-modified) gradients of `P_k` above, as if the
//! modes were three extra nodes. The internal parameters are no longer a
//! linear function of `u`: for each `u` the element solves its own
//! equations `r_alpha(u, alpha) = Σ_q w_q det J_q P G_k = 0` (`P = F S`) by
//! Newton from the last converged `alpha` (stored as the element's state,
//! 9 values), to `|Δalpha| <= 1e-12` of the element's size (at most 25
//! iterations, then an error that cuts the increment back). With the full
//! 33 x 33 tangent `[[K_uu, K_ua], [K_au, K_aa]]` of the total-Lagrangian
//! element at the solution, the condensed tangent
//! `K = K_uu - K_ua K_aa^-1 K_au` is exact (implicit function theorem) and
//! symmetric. CalculiX's C3D8I under NLGEOM treats the modes as extra
//! nodes of the same kind, which gives the same equations.
//!
//! ## Outputs
//!
//! Per integration point, as the other solids: `stress` and `strain` (both
//! including the incompatible-mode strain `B_a alpha`) and `mises`; under
//! `nlgeom` the Cauchy stress, the Green strain and `pk2_stress`.
//!
//! ## Thermal strain
//!
//! With a thermal strain `eps_th` ([`crate::thermal`]) the stress is
//! `C (B_u u + B_a alpha - eps_th)` and the modes' balance gains the
//! thermal force `f_a = ∫ B_a^T C eps_th dV`: `alpha = -K_aa^-1 (K_au u -
//! f_a)` (zero extra for a uniform `eps_th` and `C`, since `∫ B_a dV = 0`).
//! The tangent does not change.
//!
//! ## Geometry check
//!
//! [`Element::check_geometry`] asks `det J > 0` at the 8 Gauss points
//! (reported as 0..7), the 8 corners (8..15) and the centre (16).

use crate::quadrature::gauss_legendre_3d;
use crate::shape::hex_shape;
use crate::solid::{material_stress, von_mises};
use crate::total_lagrangian as tl;
use junta_core::element::{Element, ElementContext, ElementError, PointOutput};
use junta_core::registry::{parse_params, ElementBuild, ElementEntry, ParamDoc};
use junta_core::topology::{CellShape, HEX27_NODES};
use junta_core::{CoreError, Kinematics, Material, Voigt6};
use nalgebra::{Matrix3, SMatrix, SVector, Vector6};
use serde::Deserialize;
use std::sync::Arc;

/// Nodal dofs.
const NU: usize = 24;
/// Internal (incompatible-mode) parameters.
const NA: usize = 9;

type Bu = SMatrix<f64, 6, NU>;
type Ba = SMatrix<f64, 6, NA>;
type Kua = SMatrix<f64, NU, NA>;
type Kaa = SMatrix<f64, NA, NA>;
type Kuu = SMatrix<f64, NU, NU>;

/// Options table of `h8i` (none so far; unknown keys are errors).
#[derive(Debug, Clone, Copy, Default, Deserialize)]
#[serde(deny_unknown_fields)]
struct H8iOptions {}

/// Trilinear shape-function data at one point of the reference cell.
#[derive(Debug, Clone, Copy)]
struct PointData {
    xi: [f64; 3],
    w: f64,
    n: [f64; 8],
    dn: [[f64; 3]; 8],
}

impl PointData {
    fn new(xi: [f64; 3], w: f64) -> Self {
        let mut n = [0.0; 8];
        let mut dn = [[0.0; 3]; 8];
        hex_shape(CellShape::Hex8, xi, &mut n, &mut dn);
        PointData { xi, w, n, dn }
    }
}

/// Strain-displacement matrices, volume weight and elasticity at one
/// Gauss point.
#[derive(Clone, Copy)]
struct PointB {
    bu: Bu,
    ba: Ba,
    dv: f64,
    /// `C` at the point (the material's per point if it varies in space).
    c: Voigt6,
}

/// Reference gradients (8 nodes, then 3 modes), volume weight and
/// elasticity at one Gauss point.
#[derive(Clone, Copy)]
struct PointGrad {
    g: [[f64; 3]; 11],
    dv: f64,
    c: Voigt6,
}

/// The 8-node hexahedron with 9 condensed incompatible modes (see the
/// module docs).
#[derive(Clone)]
pub struct IncompatibleHex8 {
    material: Arc<dyn Material>,
    /// `C` of a material uniform in space.
    c: Voigt6,
    /// The material's `C` varies in space: [`Material::elasticity_at`] per point.
    varies: bool,
    points: [PointData; 8],
    corners: [PointData; 8],
    centre: PointData,
    kinematics: Kinematics,
}

impl std::fmt::Debug for IncompatibleHex8 {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("IncompatibleHex8")
            .field("key", &"h8i")
            .field("material", &self.material)
            .finish()
    }
}

/// Jacobian `J_ij = Σ_a x_ai ∂N_a/∂xi_j`, its determinant and inverse;
/// error (reported at `point`) if `det J <= 0`.
fn jacobian(
    p: &PointData,
    coords: &[[f64; 3]],
    point: usize,
) -> Result<(f64, Matrix3<f64>), ElementError> {
    let mut j = Matrix3::<f64>::zeros();
    for (x, d) in coords[..8].iter().zip(&p.dn) {
        for r in 0..3 {
            for c in 0..3 {
                j[(r, c)] += x[r] * d[c];
            }
        }
    }
    let det = j.determinant();
    if det.is_nan() || det <= 0.0 {
        return Err(ElementError::NegativeJacobian { point, det });
    }
    let jinv = j
        .try_inverse()
        .ok_or(ElementError::NegativeJacobian { point, det })?;
    Ok((det, jinv))
}

/// Reference position `Σ_a N_a x_a` of point data `p`.
#[inline]
fn position(p: &PointData, coords: &[[f64; 3]]) -> [f64; 3] {
    let mut x = [0.0; 3];
    for (n, c) in p.n.iter().zip(coords) {
        for i in 0..3 {
            x[i] += n * c[i];
        }
    }
    x
}

/// Write the 6 x 3 block `B(g)` of a gradient `g` into columns
/// `col..col + 3` of `b`.
#[inline(always)]
fn put_b<const N: usize>(b: &mut SMatrix<f64, 6, N>, col: usize, g: [f64; 3]) {
    b[(0, col)] = g[0];
    b[(1, col + 1)] = g[1];
    b[(2, col + 2)] = g[2];
    b[(3, col)] = g[1];
    b[(3, col + 1)] = g[0];
    b[(4, col + 1)] = g[2];
    b[(4, col + 2)] = g[1];
    b[(5, col)] = g[2];
    b[(5, col + 2)] = g[0];
}

impl IncompatibleHex8 {
    /// An `h8i` element of the given material.
    pub fn new(material: Arc<dyn Material>) -> Self {
        let rule = gauss_legendre_3d(2).expect("the 2-point rule exists");
        let mut points = [PointData::new([0.0; 3], 0.0); 8];
        for (p, (&xi, w)) in points.iter_mut().zip(rule.iter()) {
            *p = PointData::new(xi, w);
        }
        let mut corners = points;
        for (p, &xi) in corners.iter_mut().zip(&HEX27_NODES[..8]) {
            *p = PointData::new(xi, 0.0);
        }
        let c = material.elasticity();
        let varies = material.varies_in_space();
        IncompatibleHex8 {
            material,
            c,
            varies,
            points,
            corners,
            centre: PointData::new([0.0; 3], 0.0),
            kinematics: Kinematics::Small,
        }
    }

    /// The same element with the given kinematics.
    pub fn with_kinematics(mut self, kinematics: Kinematics) -> Self {
        self.kinematics = kinematics;
        self
    }

    /// Build from a registry table (no options; a material is required).
    pub fn from_build(build: &ElementBuild<'_>) -> Result<Self, CoreError> {
        let _: H8iOptions = parse_params("element", "h8i", build.options)?;
        let material = build
            .material
            .clone()
            .ok_or_else(|| CoreError::InvalidParameters {
                kind: "element",
                key: "h8i".into(),
                message: "solid element h8i requires a material (e.g. an `isotropic` or \
                          `orthotropic` material named by the block); none was given"
                    .into(),
            })?;
        Ok(Self::new(material).with_kinematics(build.kinematics))
    }

    /// The material.
    pub fn material(&self) -> &Arc<dyn Material> {
        &self.material
    }

    /// The reference gradients at the 8 Gauss points: the 8 nodes' `g_a`,
    /// then the 3 modes' Taylor-modified `G_k`; with `w det J` and `C`
    /// (at the trilinear position `Σ_a N_a x_a` when the material varies
    /// in space).
    fn point_gradients(&self, coords: &[[f64; 3]]) -> Result<[PointGrad; 8], ElementError> {
        let (det0, j0inv) = jacobian(&self.centre, coords, 16)?;
        let mut out = [PointGrad {
            g: [[0.0; 3]; 11],
            dv: 0.0,
            c: self.c,
        }; 8];
        for (q, (p, o)) in self.points.iter().zip(out.iter_mut()).enumerate() {
            let (det, jinv) = jacobian(p, coords, q)?;
            for (ga, d) in o.g.iter_mut().zip(&p.dn) {
                // ∂N/∂x_i = Σ_j (J^-1)_ji ∂N/∂xi_j
                *ga = [0, 1, 2]
                    .map(|i| jinv[(0, i)] * d[0] + jinv[(1, i)] * d[1] + jinv[(2, i)] * d[2]);
            }
            let scale = det0 / det;
            for k in 0..3 {
                // (det J0 / det J) J0^-T (-2 xi_k e_k)
                let s = -2.0 * p.xi[k] * scale;
                o.g[8 + k] = [0, 1, 2].map(|i| s * j0inv[(k, i)]);
            }
            o.dv = p.w * det;
            if self.varies {
                o.c = self.material.elasticity_at(position(p, coords));
            }
        }
        Ok(out)
    }

    /// `B_u`, `B_a`, `w det J` and `C` at the 8 Gauss points.
    fn b_matrices(&self, coords: &[[f64; 3]]) -> Result<[PointB; 8], ElementError> {
        let grads = self.point_gradients(coords)?;
        let mut out = [PointB {
            bu: Bu::zeros(),
            ba: Ba::zeros(),
            dv: 0.0,
            c: self.c,
        }; 8];
        for (o, pg) in out.iter_mut().zip(&grads) {
            for (a, &g) in pg.g[..8].iter().enumerate() {
                put_b(&mut o.bu, 3 * a, g);
            }
            for (k, &g) in pg.g[8..].iter().enumerate() {
                // mode k, component i: column 3 k + i
                put_b(&mut o.ba, 3 * k, g);
            }
            o.dv = pg.dv;
            o.c = pg.c;
        }
        Ok(out)
    }

    /// `K_ua`, `K_aa`, and `K_uu` if `with_kuu`.
    fn blocks(&self, b: &[PointB; 8], with_kuu: bool) -> (Kua, Kaa, Kuu) {
        let mut kua = Kua::zeros();
        let mut kaa = Kaa::zeros();
        let mut kuu = Kuu::zeros();
        for p in b {
            let cba = p.c * p.ba * p.dv;
            kua += p.bu.transpose() * cba;
            kaa += p.ba.transpose() * cba;
            if with_kuu {
                kuu += p.bu.transpose() * (p.c * p.bu * p.dv);
            }
        }
        (kua, kaa, kuu)
    }

    /// The incompatible-mode parameters `alpha = -K_aa^-1 K_au u` and the
    /// Cholesky factor of `K_aa`.
    fn condense(
        kua: &Kua,
        kaa: Kaa,
        u: &SVector<f64, NU>,
    ) -> Result<
        (
            SVector<f64, NA>,
            nalgebra::Cholesky<f64, nalgebra::Const<NA>>,
        ),
        ElementError,
    > {
        let chol = kaa.cholesky().ok_or_else(|| ElementError::Law {
            point: 0,
            message: "h8i: the incompatible-mode stiffness K_aa is not positive definite \
                      (degenerate element or material)"
                .into(),
        })?;
        let alpha = -chol.solve(&(kua.transpose() * u));
        Ok((alpha, chol))
    }
}

/// Dofs of the total-Lagrangian element before condensation (24 + 9).
const NT: usize = NU + NA;

/// An element's state under `nlgeom` at given displacements
/// ([`IncompatibleHex8::finite_solution`]).
struct FiniteSolution {
    grads: [PointGrad; 8],
    thermal: [Vector6<f64>; 8],
    /// Displacements and solved modes, stacked (24 + 9).
    d: [f64; NT],
    state: FiniteState,
}

/// Internal force and full tangent of the uncondensed total-Lagrangian
/// element at one `(u, alpha)`.
struct FiniteState {
    f: [f64; NT],
    k: [f64; NT * NT],
}

impl IncompatibleHex8 {
    /// Internal force (24 + 9) and, if `with_k`, the full 33 x 33 tangent
    /// of the total-Lagrangian element at the displacements and modes `d`.
    fn finite_state(
        &self,
        grads: &[PointGrad; 8],
        thermal: &[Vector6<f64>; 8],
        d: &[f64; NT],
        with_k: bool,
        out: &mut FiniteState,
    ) {
        out.f.fill(0.0);
        if with_k {
            out.k.fill(0.0);
        }
        for (pg, th) in grads.iter().zip(thermal) {
            let f = tl::deformation_gradient(&pg.g, d);
            let s = pg.c * (tl::green_strain(&f) - th);
            tl::add_internal_force(&pg.g, &f, &s, pg.dv, &mut out.f);
            if with_k {
                tl::add_tangent(&pg.g, &f, &s, &pg.c, pg.dv, &mut out.k, NT);
            }
        }
    }

    /// Solve the modes' equations `r_alpha(u, alpha) = 0` by Newton from
    /// `alpha0`; returns `(u, alpha)` stacked, with the force and full
    /// tangent there in `out`.
    fn solve_modes(
        &self,
        grads: &[PointGrad; 8],
        thermal: &[Vector6<f64>; 8],
        coords: &[[f64; 3]],
        disp: &[f64],
        alpha0: &[f64],
        out: &mut FiniteState,
    ) -> Result<[f64; NT], ElementError> {
        let mut d = [0.0; NT];
        d[..NU].copy_from_slice(&disp[..NU]);
        d[NU..].copy_from_slice(&alpha0[..NA]);
        let size = element_size(coords);
        for _ in 0..MODE_ITERATIONS {
            self.finite_state(grads, thermal, &d, true, out);
            let kaa = Kaa::from_fn(|r, c| out.k[(NU + r) * NT + NU + c]);
            let ra = SVector::<f64, NA>::from_column_slice(&out.f[NU..]);
            let step = kaa.lu().solve(&ra).ok_or_else(singular_modes)?;
            for (x, dx) in d[NU..].iter_mut().zip(step.iter()) {
                *x -= dx;
            }
            if !step.norm().is_finite() {
                break;
            }
            if step.norm() <= 1e-12 * size {
                self.finite_state(grads, thermal, &d, true, out);
                return Ok(d);
            }
        }
        Err(ElementError::Law {
            point: 0,
            message: format!(
                "h8i: the incompatible modes did not converge in {MODE_ITERATIONS} Newton iterations (the element is too distorted for this increment)"
            ),
        })
    }

    /// The gradients, thermal strains, modes (solved from the committed
    /// ones) and the uncondensed force and tangent at `ctx`'s displacements.
    fn finite_solution(&self, ctx: &ElementContext<'_>) -> Result<FiniteSolution, ElementError> {
        let grads = self.point_gradients(ctx.coords)?;
        let thermal = self.thermal_strains(ctx);
        let mut state = FiniteState {
            f: [0.0; NT],
            k: [0.0; NT * NT],
        };
        let d = self.solve_modes(
            &grads,
            &thermal,
            ctx.coords,
            ctx.disp,
            ctx.state_committed,
            &mut state,
        )?;
        Ok(FiniteSolution {
            grads,
            thermal,
            d,
            state,
        })
    }

    /// Total-Lagrangian force and condensed tangent
    /// `K_uu - K_ua K_aa^-1 K_au` (module docs), the modes into `state_trial`.
    fn compute_finite(
        &self,
        ctx: &ElementContext<'_>,
        state_trial: &mut [f64],
        f_int: &mut [f64],
        k: Option<&mut [f64]>,
    ) -> Result<(), ElementError> {
        let FiniteSolution { d, state: st, .. } = self.finite_solution(ctx)?;
        state_trial[..NA].copy_from_slice(&d[NU..]);
        f_int[..NU].copy_from_slice(&st.f[..NU]);
        if let Some(k) = k {
            let kaa = Kaa::from_fn(|r, c| st.k[(NU + r) * NT + NU + c]);
            let kua = Kua::from_fn(|r, c| st.k[r * NT + NU + c]);
            let x = kaa
                .lu()
                .solve(&kua.transpose())
                .ok_or_else(singular_modes)?;
            let kc = Kuu::from_fn(|r, c| st.k[r * NT + c]) - kua * x;
            for r in 0..NU {
                for c in 0..NU {
                    k[r * NU + c] = 0.5 * (kc[(r, c)] + kc[(c, r)]);
                }
            }
        }
        Ok(())
    }
    /// Point outputs under `nlgeom`: Cauchy `stress`, Green `strain`,
    /// `pk2_stress`, with the modes solved from the committed ones.
    fn point_outputs_finite(
        &self,
        ctx: &ElementContext<'_>,
    ) -> Result<Vec<PointOutput>, ElementError> {
        let FiniteSolution {
            grads,
            thermal: th,
            d,
            ..
        } = self.finite_solution(ctx)?;
        let mut out = Vec::with_capacity(8);
        for ((p, pg), th) in self.points.iter().zip(&grads).zip(&th) {
            let f = tl::deformation_gradient(&pg.g, &d);
            let e = tl::green_strain(&f);
            let s = pg.c * (e - th);
            let sigma = tl::cauchy_stress(&f, &s);
            let position = position(p, ctx.coords);
            let pk2: [f64; 6] = s.into();
            let mut values = vec![
                ("stress", sigma.to_vec()),
                ("strain", e.iter().copied().collect()),
                ("mises", vec![von_mises(&sigma)]),
                ("volume", vec![pg.dv]),
                ("pk2_stress", pk2.to_vec()),
            ];
            if let Some(m) = material_stress(self.material.as_ref(), position, &pk2) {
                values.push(("material_stress", m.to_vec()));
            }
            out.push(PointOutput { position, values });
            if ctx.temperature.is_some() {
                let v = &mut out.last_mut().expect("pushed").values;
                v.push(("thermal_strain", th.iter().copied().collect()));
            }
        }
        Ok(out)
    }
}

/// Most Newton iterations of the modes' own equations under `nlgeom`.
const MODE_ITERATIONS: usize = 25;

fn singular_modes() -> ElementError {
    ElementError::Law {
        point: 0,
        message: "h8i: the incompatible-mode tangent K_aa is singular (degenerate element, or a stress state at which the modes buckle)".into(),
    }
}

/// The diagonal of the reference nodes' bounding box.
fn element_size(coords: &[[f64; 3]]) -> f64 {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for x in &coords[..8] {
        for i in 0..3 {
            lo[i] = lo[i].min(x[i]);
            hi[i] = hi[i].max(x[i]);
        }
    }
    ((hi[0] - lo[0]).powi(2) + (hi[1] - lo[1]).powi(2) + (hi[2] - lo[2]).powi(2)).sqrt()
}

impl Element for IncompatibleHex8 {
    fn key(&self) -> &'static str {
        "h8i"
    }
    fn shape(&self) -> CellShape {
        CellShape::Hex8
    }
    fn num_points(&self) -> usize {
        8
    }
    fn reference_modulus(&self) -> Option<f64> {
        Some(self.material.reference_modulus())
    }
    fn material(&self) -> Option<&dyn Material> {
        Some(self.material.as_ref())
    }
    fn directional_modulus(&self, n: [f64; 3]) -> Option<f64> {
        self.material.directional_modulus(n)
    }
    fn has_thermal_expansion(&self) -> bool {
        self.material.has_thermal_expansion()
    }
    /// Small strains and a linear elastic material: `f = K u`; not so
    /// under `nlgeom`.
    fn is_linear(&self) -> bool {
        self.kinematics == Kinematics::Small
    }
    fn kinematics(&self) -> Kinematics {
        self.kinematics
    }
    /// Under `nlgeom` the 9 incompatible-mode parameters (module docs).
    fn state_len(&self) -> usize {
        match self.kinematics {
            Kinematics::Small => 0,
            Kinematics::Finite => NA,
        }
    }
    fn tangent_kind(&self) -> junta_core::MatrixKind {
        match self.kinematics {
            Kinematics::Small => junta_core::MatrixKind::SymmetricPositiveDefinite,
            Kinematics::Finite => junta_core::MatrixKind::SymmetricIndefinite,
        }
    }

    fn compute(
        &self,
        ctx: &ElementContext<'_>,
        state_trial: &mut [f64],
        f_int: &mut [f64],
        k: Option<&mut [f64]>,
    ) -> Result<(), ElementError> {
        if self.kinematics == Kinematics::Finite {
            return self.compute_finite(ctx, state_trial, f_int, k);
        }
        debug_assert!(ctx.coords.len() >= 8 && ctx.disp.len() >= NU && f_int.len() >= NU);
        let b = self.b_matrices(ctx.coords)?;
        let (kua, kaa, kuu) = self.blocks(&b, k.is_some());
        let u = SVector::<f64, NU>::from_column_slice(&ctx.disp[..NU]);
        let (mut alpha, chol) = Self::condense(&kua, kaa, &u)?;
        let th = self.thermal_strains(ctx);
        alpha += chol.solve(&thermal_mode_force(&b, &th));
        // f_int from the stresses (= K u for this linear element)
        let mut f = SVector::<f64, NU>::zeros();
        for (p, th) in b.iter().zip(&th) {
            let sig = p.c * (p.bu * u + p.ba * alpha - th);
            f += p.bu.transpose() * sig * p.dv;
        }
        f_int[..NU].copy_from_slice(f.as_slice());
        if let Some(k) = k {
            debug_assert!(k.len() >= NU * NU);
            let x = chol.solve(&kua.transpose()); // K_aa^-1 K_au
            let kc = kuu - kua * x;
            for r in 0..NU {
                for c in 0..NU {
                    // symmetric part: removes round-off asymmetry of K_ua X
                    k[r * NU + c] = 0.5 * (kc[(r, c)] + kc[(c, r)]);
                }
            }
        }
        Ok(())
    }

    fn check_geometry(&self, coords: &[[f64; 3]]) -> Result<(), ElementError> {
        for (q, p) in self.points.iter().enumerate() {
            jacobian(p, coords, q)?;
        }
        for (c, p) in self.corners.iter().enumerate() {
            jacobian(p, coords, 8 + c)?;
        }
        jacobian(&self.centre, coords, 16)?;
        Ok(())
    }

    fn point_outputs(&self, ctx: &ElementContext<'_>) -> Result<Vec<PointOutput>, ElementError> {
        if self.kinematics == Kinematics::Finite {
            return self.point_outputs_finite(ctx);
        }
        let b = self.b_matrices(ctx.coords)?;
        let (kua, kaa, _) = self.blocks(&b, false);
        let u = SVector::<f64, NU>::from_column_slice(&ctx.disp[..NU]);
        let (mut alpha, chol) = Self::condense(&kua, kaa, &u)?;
        let th = self.thermal_strains(ctx);
        alpha += chol.solve(&thermal_mode_force(&b, &th));
        let mut out = Vec::with_capacity(8);
        for ((p, pb), th) in self.points.iter().zip(&b).zip(&th) {
            let eps: Vector6<f64> = pb.bu * u + pb.ba * alpha;
            let s: [f64; 6] = (pb.c * (eps - th)).into();
            let position = position(p, ctx.coords);
            let mut values = vec![
                ("stress", s.to_vec()),
                ("strain", eps.iter().copied().collect()),
                ("mises", vec![von_mises(&s)]),
                ("volume", vec![pb.dv]),
            ];
            if let Some(m) = material_stress(self.material.as_ref(), position, &s) {
                values.push(("material_stress", m.to_vec()));
            }
            out.push(PointOutput { position, values });
            if ctx.temperature.is_some() {
                let v = &mut out.last_mut().expect("pushed").values;
                v.push(("thermal_strain", th.iter().copied().collect()));
            }
        }
        Ok(out)
    }
}

impl IncompatibleHex8 {
    /// The thermal strain at the 8 Gauss points ([`crate::thermal`]).
    fn thermal_strains(&self, ctx: &ElementContext<'_>) -> [Vector6<f64>; 8] {
        let m = &*self.material;
        self.points
            .map(|p| crate::thermal::point_thermal_strain(m, &p.n, ctx.coords, ctx.temperature))
    }
}

/// The modes' thermal force `∫ B_a^T C eps_th dV` (module docs).
fn thermal_mode_force(b: &[PointB; 8], th: &[Vector6<f64>; 8]) -> SVector<f64, NA> {
    let mut f = SVector::<f64, NA>::zeros();
    for (p, th) in b.iter().zip(th) {
        if *th != Vector6::zeros() {
            f += p.ba.transpose() * (p.c * th) * p.dv;
        }
    }
    f
}

const H8I_PARAMS: &[ParamDoc] = &[];

inventory::submit! {
    ElementEntry {
        key: "h8i",
        description: "8-node hexahedron with 9 condensed incompatible modes (as C3D8I), 2x2x2 Gauss, \
                      small-strain elasticity; bends without shear locking",
        params: H8I_PARAMS,
        shape: CellShape::Hex8,
        build: |b| Ok(Arc::new(IncompatibleHex8::from_build(b)?)),
    }
}
