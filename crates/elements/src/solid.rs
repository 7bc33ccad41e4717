//! Isoparametric hexahedral and wedge solid elements (H8, H20, H27, wedges)
//! for linear elasticity: small strain, or total-Lagrangian large
//! deformation under `nlgeom` ([`crate::total_lagrangian`]).
//!
//! ## Kinematics
//!
//! Geometry and displacement share the shape functions `N_a` of
//! [`crate::shape::hex_shape`]: `x(xi) = Σ_a N_a(xi) x_a`,
//! `u(xi) = Σ_a N_a(xi) u_a`. The Jacobian `J_ij = ∂x_i/∂xi_j = Σ_a x_ai
//! ∂N_a/∂xi_j` maps natural to physical derivatives,
//! `∂N_a/∂x_i = Σ_j (J^-1)_ji ∂N_a/∂xi_j`, and `dV = det J dxi`.
//!
//! The strain in Voigt order `[xx, yy, zz, xy, yz, zx]` (engineering shear)
//! is `eps = Σ_a B_a u_a` with, writing `N_a,i = ∂N_a/∂x_i`,
//!
//! ```text
//!       | N,x   0    0  |
//!       |  0   N,y   0  |
//! B_a = |  0    0   N,z |
//!       | N,y  N,x   0  |
//!       |  0   N,z  N,y |
//!       | N,z   0   N,x |
//! ```
//!
//! ## Integrals
//!
//! With `sigma = C eps` (`C` from the [`Material`]; for a material whose
//! axes vary in space, a cylindrical orientation, `C` is taken at each
//! integration point's reference position `x_q = Σ_a N_a(xi_q) x_a`, as
//! CalculiX does) and a tensor Gauss rule `(xi_q, w_q)`:
//!
//! ```text
//! f_a  = ∫ B_a^T sigma dV   ≈ Σ_q w_q det J_q B_a^T(xi_q) sigma(xi_q)
//! K_ab = ∫ B_a^T C B_b dV   ≈ Σ_q w_q det J_q B_a^T C B_b
//! ```
//!
//! so that `f_int = K u` (linear). Rules: H8 2x2x2, H20 / H27 3x3x3 (full),
//! H20r / H27r 2x2x2 (reduced).
//!
//! ## Wedges (C3D6, C3D15)
//!
//! The same kinematics and integrals with the wedge shape functions of
//! [`crate::shape::wedge_shape`] (natural coordinates `(r, s, zeta)`,
//! triangle `r, s >= 0, r + s <= 1` times `zeta` in `[-1, 1]`, node order of
//! [`junta_core::topology::WEDGE15_NODES`], which is Abaqus / CalculiX's).
//! Rules ([`crate::quadrature::wedge_rule`]): Wedge6 3-point triangle x
//! 2-point Gauss (6 points: exact for the stiffness of an undistorted
//! prism, whose `B` is linear in (r, s) and in zeta; `wedge6r`: centroid x
//! 2-point Gauss, CalculiX's C3D6 rule, used for C3D6 in decks so that
//! results match CalculiX; a single free element then has one spurious
//! zero mode besides the 6 rigid ones); Wedge15 3-point
//! triangle x 3-point Gauss (9 points, CalculiX's C3D15 rule). `wedge6`
//! and `wedge15` have exactly the 6 rigid-body zero modes. The geometry check uses the 6
//! corners.
//!
//! ## Zero-energy modes (single element, free)
//!
//! Full integration: exactly the 6 rigid-body modes. Reduced 2x2x2
//! integration (8 points x 6 strains = rank <= 48): H20r has 12 zero
//! eigenvalues (6 rigid + 6 spurious, which do not propagate through a mesh
//! of more than one element: an assembled 2x2x2 H20r block has only the 6
//! rigid modes); H27r has 33 (6 rigid + 27 spurious), and the spurious ones
//! do propagate (an assembled free 2x2x2 block of H27r has 45 zero modes),
//! so prefer `h27` or `h20r`. The tests in `tests/solids.rs` measure these counts.
//!
//! ## Geometry check
//!
//! [`Element::check_geometry`] asks `det J > 0` at every integration point
//! and at the 8 corner nodes (which catches quadratic elements with a
//! mid-side node past the quarter point, whose Gauss points may still be
//! fine). Corner `c` is reported as point `num_points + c`. Collapsed
//! (degenerate) hexahedra therefore fail the check.
//!
//! ## Large deformation (`nlgeom`)
//!
//! Built with [`Kinematics::Finite`], the element is total-Lagrangian: the
//! same shape functions, rules and `C` (at the reference position), with
//! the Green strain, the second Piola-Kirchhoff stress `S = C E` (St.
//! Venant-Kirchhoff) and the tangent with its geometric stiffness of
//! [`crate::total_lagrangian`]. The element is then no longer linear
//! (`is_linear` is false) and its tangent may be indefinite.
//!
//! ## Outputs
//!
//! Under a temperature change the stress is `C (eps - eps_th)` (small
//! strain) or `S = C (E - eps_th)` (`nlgeom`) with the thermal strain of
//! [`crate::thermal`] (`thermal_strain` is then an output too); the
//! tangent does not change.
//!
//! Per integration point: `stress` (6; under `nlgeom` the Cauchy stress
//! on the current configuration, with the second Piola-Kirchhoff stress
//! as `pk2_stress`), `strain` (6, engineering shear; under `nlgeom` the
//! Green-Lagrange strain) and `mises` (1, of `stress`): `sqrt(((sxx-syy)^2 + (syy-szz)^2 + (szz-sxx)^2)/2 +
//! 3 (sxy^2 + syz^2 + szx^2))`.

use crate::quadrature::{gauss_legendre_3d, wedge_rule, Rule};
use crate::shape::solid_shape;
use crate::thermal::point_thermal_strain;
use crate::total_lagrangian as tl;
use junta_core::element::{Element, ElementContext, ElementError, PointOutput};
use junta_core::registry::{parse_params, ElementBuild, ElementEntry, ParamDoc};
use junta_core::topology::{CellShape, HEX27_NODES, WEDGE15_NODES};
use junta_core::{CoreError, Kinematics, Material, Voigt6};
use nalgebra::{Matrix3, Vector6};
use serde::Deserialize;
use std::sync::Arc;

/// Largest node count of a solid element (H27).
pub const MAX_NODES: usize = 27;

/// Integration rule choice of a solid element.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Integration {
    /// H8: 2x2x2, H20 / H27: 3x3x3 Gauss.
    Full,
    /// H20 / H27: 2x2x2 Gauss (not available for H8).
    Reduced,
}

/// Options table of the solid elements.
#[derive(Debug, Clone, Copy, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SolidOptions {
    /// `"full"` or `"reduced"`; default: as the key says.
    pub integration: Option<Integration>,
}

/// Shape-function data at one point of the reference cell, computed once.
#[derive(Clone)]
pub(crate) struct PointData {
    pub(crate) xi: [f64; 3],
    pub(crate) w: f64,
    n: [f64; MAX_NODES],
    dn: [[f64; 3]; MAX_NODES],
    /// Index of the point's material in [`SolidElement::plies`] (0 for an
    /// ordinary element, which has one).
    pub(crate) ply: usize,
}

impl PointData {
    pub(crate) fn new(shape: CellShape, xi: [f64; 3], w: f64) -> Self {
        let mut n = [0.0; MAX_NODES];
        let mut dn = [[0.0; 3]; MAX_NODES];
        solid_shape(shape, xi, &mut n, &mut dn);
        PointData {
            xi,
            w,
            n,
            dn,
            ply: 0,
        }
    }
}

/// A material of the element's points, with what is precomputed of it.
#[derive(Clone)]
pub(crate) struct PointMaterial {
    pub(crate) material: Arc<dyn Material>,
    /// `C` of a material uniform in space.
    c: Voigt6,
    /// The material's `C` varies in space: [`Material::elasticity_at`] per point.
    varies: bool,
}

impl PointMaterial {
    pub(crate) fn new(material: Arc<dyn Material>) -> Self {
        PointMaterial {
            c: material.elasticity(),
            varies: material.varies_in_space(),
            material,
        }
    }
}

/// A small-strain linear elastic hexahedron (H8, H20, H27; full or reduced).
///
/// Shape functions are evaluated once at construction; `compute` works on
/// stack arrays and the caller's buffers and never allocates.
#[derive(Clone)]
pub struct SolidElement {
    key: &'static str,
    shape: CellShape,
    integration: Integration,
    /// The materials of the points: one for an ordinary element, one per
    /// ply for a layered one ([`crate::layered`]); each point names its own.
    pub(crate) plies: Vec<PointMaterial>,
    /// Integrated ply by ply ([`crate::layered`]): outputs carry `ply`.
    pub(crate) layered: bool,
    pub(crate) points: Vec<PointData>,
    corners: Vec<PointData>,
    kinematics: Kinematics,
}

impl std::fmt::Debug for SolidElement {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SolidElement")
            .field("key", &self.key)
            .field("shape", &self.shape)
            .field("integration", &self.integration)
            .field("num_points", &self.points.len())
            .field("plies", &self.plies.len())
            .field("material", &self.plies[0].material)
            .finish()
    }
}

/// Registry key of a shape / integration pair, or an error if there is none.
fn key_of(shape: CellShape, integration: Integration) -> Result<&'static str, String> {
    match (shape, integration) {
        (CellShape::Hex8, Integration::Full) => Ok("h8"),
        (CellShape::Hex8, Integration::Reduced) => Err(
            "h8 has no reduced integration (a 1-point H8 has 12 hourglass modes and Junta has no \
             hourglass control); use integration = \"full\", or h20r"
                .into(),
        ),
        (CellShape::Hex20, Integration::Full) => Ok("h20"),
        (CellShape::Hex20, Integration::Reduced) => Ok("h20r"),
        (CellShape::Hex27, Integration::Full) => Ok("h27"),
        (CellShape::Hex27, Integration::Reduced) => Ok("h27r"),
        (CellShape::Wedge6, Integration::Full) => Ok("wedge6"),
        (CellShape::Wedge6, Integration::Reduced) => Ok("wedge6r"),
        (CellShape::Wedge15, Integration::Full) => Ok("wedge15"),
        (CellShape::Wedge15, Integration::Reduced) => {
            Err("wedge15 has no reduced integration; use integration = \"full\"".into())
        }
        (s, _) => Err(format!(
            "solid elements are hexahedra (hex8, hex20, hex27) or wedges (wedge6, wedge15), not {}",
            s.name()
        )),
    }
}

impl SolidElement {
    /// A solid element of `shape` (Hex8 / Hex20 / Hex27) with the given
    /// integration and material. Errors for non-hexahedral shapes and for
    /// reduced H8.
    pub fn new(
        shape: CellShape,
        integration: Integration,
        material: Arc<dyn Material>,
    ) -> Result<Self, CoreError> {
        let key = key_of(shape, integration).map_err(|message| CoreError::InvalidParameters {
            kind: "element",
            key: shape.name().into(),
            message,
        })?;
        let n1 = match (shape, integration) {
            (CellShape::Wedge6, Integration::Full) => 3,
            (CellShape::Hex8, _) | (_, Integration::Reduced) => 2,
            _ => 3,
        };
        let (rule, corner_nodes): (Rule<3>, &[[f64; 3]]) = match shape {
            CellShape::Wedge6 => (
                wedge_rule(if n1 == 2 { 1 } else { 3 }, 2).expect("rule exists"),
                &WEDGE15_NODES[..6],
            ),
            CellShape::Wedge15 => (wedge_rule(3, 3).expect("rule exists"), &WEDGE15_NODES[..6]),
            _ => (
                gauss_legendre_3d(n1).expect("2 and 3 point rules exist"),
                &HEX27_NODES[..8],
            ),
        };
        let points = rule
            .iter()
            .map(|(&xi, w)| PointData::new(shape, xi, w))
            .collect();
        let corners = corner_nodes
            .iter()
            .map(|&xi| PointData::new(shape, xi, 0.0))
            .collect();
        Ok(SolidElement {
            key,
            shape,
            integration,
            plies: vec![PointMaterial::new(material)],
            layered: false,
            points,
            corners,
            kinematics: Kinematics::Small,
        })
    }

    /// The same element with the given kinematics.
    pub fn with_kinematics(mut self, kinematics: Kinematics) -> Self {
        self.kinematics = kinematics;
        self
    }

    /// Build for registry key `key` (its shape and default integration),
    /// honouring the `integration` option.
    pub fn from_build(
        key: &'static str,
        shape: CellShape,
        default: Integration,
        build: &ElementBuild<'_>,
    ) -> Result<Self, CoreError> {
        let opts: SolidOptions = parse_params("element", key, build.options)?;
        let integration = opts.integration.unwrap_or(default);
        if default == Integration::Reduced && integration == Integration::Full {
            return Err(CoreError::InvalidParameters {
                kind: "element",
                key: key.into(),
                message: format!(
                    "{key} is the reduced-integration element; for full integration use `{}`",
                    key.trim_end_matches('r')
                ),
            });
        }
        let material = build
            .material
            .clone()
            .ok_or_else(|| CoreError::InvalidParameters {
                kind: "element",
                key: key.into(),
                message: format!(
                "solid element {key} requires a material (e.g. an `isotropic` or `orthotropic` \
                 material named by the block); none was given"
            ),
            })?;
        let el = Self::new(shape, integration, material).map_err(|e| match e {
            CoreError::InvalidParameters { message, .. } => CoreError::InvalidParameters {
                kind: "element",
                key: key.into(),
                message,
            },
            e => e,
        })?;
        Ok(el.with_kinematics(build.kinematics))
    }

    /// The integration rule in use.
    pub fn integration(&self) -> Integration {
        self.integration
    }

    /// The material (of the first ply for a layered element).
    pub fn material(&self) -> &Arc<dyn Material> {
        &self.plies[0].material
    }

    /// The material of point data `p`.
    #[inline]
    fn material_of(&self, p: &PointData) -> &dyn Material {
        &*self.plies[p.ply].material
    }

    /// Natural coordinates and weights of the integration points.
    pub fn points(&self) -> impl Iterator<Item = ([f64; 3], f64)> + '_ {
        self.points.iter().map(|p| (p.xi, p.w))
    }

    /// Physical shape-function gradients `g[a] = ∂N_a/∂x` at point data `p`
    /// and det J; error if det J <= 0 (`point` is the reported index).
    #[inline]
    fn gradients(
        &self,
        p: &PointData,
        coords: &[[f64; 3]],
        point: usize,
        g: &mut [[f64; 3]; MAX_NODES],
    ) -> Result<f64, ElementError> {
        let nn = self.shape.num_nodes();
        let mut j = Matrix3::<f64>::zeros();
        for (x, d) in coords[..nn].iter().zip(&p.dn[..nn]) {
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
        // ∂N/∂x_i = Σ_j (J^-1)_ji ∂N/∂xi_j, i.e. g = J^-T dN
        let jinv = j
            .try_inverse()
            .ok_or(ElementError::NegativeJacobian { point, det })?;
        for (ga, d) in g[..nn].iter_mut().zip(&p.dn[..nn]) {
            for (i, gi) in ga.iter_mut().enumerate() {
                *gi = jinv[(0, i)] * d[0] + jinv[(1, i)] * d[1] + jinv[(2, i)] * d[2];
            }
        }
        Ok(det)
    }

    /// Reference position `x = Σ_a N_a x_a` of point data `p`.
    #[inline]
    fn position(&self, p: &PointData, coords: &[[f64; 3]]) -> [f64; 3] {
        let mut x = [0.0; 3];
        for (n, c) in p.n[..self.shape.num_nodes()].iter().zip(coords) {
            for i in 0..3 {
                x[i] += n * c[i];
            }
        }
        x
    }

    /// `C` at point data `p`: the material's at the point's reference
    /// position if it varies in space (a cylindrical orientation, evaluated
    /// at each integration point as CalculiX does), else the stored one.
    #[inline]
    fn elasticity(&self, p: &PointData, coords: &[[f64; 3]]) -> Voigt6 {
        let m = &self.plies[p.ply];
        if m.varies {
            m.material.elasticity_at(self.position(p, coords))
        } else {
            m.c
        }
    }

    /// Strain (Voigt, engineering shear) from gradients and displacements.
    #[inline]
    fn strain(&self, g: &[[f64; 3]; MAX_NODES], disp: &[f64]) -> Vector6<f64> {
        let mut e = Vector6::zeros();
        for (a, d) in g.iter().take(self.shape.num_nodes()).enumerate() {
            let (ux, uy, uz) = (disp[3 * a], disp[3 * a + 1], disp[3 * a + 2]);
            e[0] += d[0] * ux;
            e[1] += d[1] * uy;
            e[2] += d[2] * uz;
            e[3] += d[1] * ux + d[0] * uy;
            e[4] += d[2] * uy + d[1] * uz;
            e[5] += d[2] * ux + d[0] * uz;
        }
        e
    }
}

/// `B_a^T s` for the gradient `d` of node `a` and a Voigt 6-vector `s`.
#[inline(always)]
fn bt_times(d: &[f64; 3], s: &[f64; 6]) -> [f64; 3] {
    [
        d[0] * s[0] + d[1] * s[3] + d[2] * s[5],
        d[1] * s[1] + d[0] * s[3] + d[2] * s[4],
        d[2] * s[2] + d[1] * s[4] + d[0] * s[5],
    ]
}

/// Von Mises equivalent stress of a Voigt stress.
pub fn von_mises(s: &[f64; 6]) -> f64 {
    let [xx, yy, zz, xy, yz, zx] = *s;
    (0.5 * ((xx - yy).powi(2) + (yy - zz).powi(2) + (zz - xx).powi(2))
        + 3.0 * (xy * xy + yz * yz + zx * zx))
        .sqrt()
}

/// The stresses and strains at one point ([`SolidElement::point_stress`]).
struct PointStress {
    stress: [f64; 6],
    strain: Vector6<f64>,
    thermal: Vector6<f64>,
    pk2: Option<[f64; 6]>,
}

impl SolidElement {
    /// Small strain: `f = K u + f_th` with `K = ∫ B^T C B dV`.
    fn compute_small(
        &self,
        ctx: &ElementContext<'_>,
        f_int: &mut [f64],
        mut k: Option<&mut [f64]>,
    ) -> Result<(), ElementError> {
        let nn = self.shape.num_nodes();
        let ndof = 3 * nn;
        debug_assert!(ctx.coords.len() >= nn && ctx.disp.len() >= ndof && f_int.len() >= ndof);
        let f_int = &mut f_int[..ndof];
        f_int.fill(0.0);
        if let Some(k) = k.as_deref_mut() {
            debug_assert!(k.len() >= ndof * ndof);
            k[..ndof * ndof].fill(0.0);
        }
        let mut g = [[0.0; 3]; MAX_NODES];
        // C B_b, column-wise: cb[b][col] is a Voigt 6-vector
        let mut cb = [[[0.0; 6]; 3]; MAX_NODES];
        for (q, p) in self.points.iter().enumerate() {
            let det = self.gradients(p, ctx.coords, q, &mut g)?;
            let dv = p.w * det;
            let c = &self.elasticity(p, ctx.coords);
            let eps_th =
                point_thermal_strain(self.material_of(p), &p.n[..nn], ctx.coords, ctx.temperature);
            let eps = self.strain(&g, ctx.disp) - eps_th;
            let sig = c * eps;
            let s: [f64; 6] = sig.into();
            for a in 0..nn {
                let r = bt_times(&g[a], &s);
                for i in 0..3 {
                    f_int[3 * a + i] += dv * r[i];
                }
            }
            if let Some(k) = k.as_deref_mut() {
                for b in 0..nn {
                    let d = g[b];
                    for r in 0..6 {
                        // columns of B_b: [d0,0,0,d1,0,d2], [0,d1,0,d0,d2,0], [0,0,d2,0,d1,d0]
                        cb[b][0][r] = d[0] * c[(r, 0)] + d[1] * c[(r, 3)] + d[2] * c[(r, 5)];
                        cb[b][1][r] = d[1] * c[(r, 1)] + d[0] * c[(r, 3)] + d[2] * c[(r, 4)];
                        cb[b][2][r] = d[2] * c[(r, 2)] + d[1] * c[(r, 4)] + d[0] * c[(r, 5)];
                    }
                }
                // upper block triangle (b >= a); mirrored below
                for (a, ga) in g[..nn].iter().enumerate() {
                    for (b, cbb) in cb.iter().enumerate().take(nn).skip(a) {
                        for (col, s) in cbb.iter().enumerate() {
                            let r = bt_times(ga, s);
                            let base = (3 * a) * ndof + 3 * b + col;
                            k[base] += dv * r[0];
                            k[base + ndof] += dv * r[1];
                            k[base + 2 * ndof] += dv * r[2];
                        }
                    }
                }
            }
        }
        if let Some(k) = k {
            // mirror: K_ba = K_ab^T for b > a
            for a in 0..nn {
                for b in (a + 1)..nn {
                    for i in 0..3 {
                        for j in 0..3 {
                            k[(3 * b + j) * ndof + 3 * a + i] = k[(3 * a + i) * ndof + 3 * b + j];
                        }
                    }
                }
            }
        }
        Ok(())
    }

    /// Total-Lagrangian: `f_a = ∫ F S g_a dV0`, `K` with the geometric
    /// stiffness ([`crate::total_lagrangian`]).
    fn compute_finite(
        &self,
        ctx: &ElementContext<'_>,
        f_int: &mut [f64],
        mut k: Option<&mut [f64]>,
    ) -> Result<(), ElementError> {
        let nn = self.shape.num_nodes();
        let ndof = 3 * nn;
        let f_int = &mut f_int[..ndof];
        f_int.fill(0.0);
        if let Some(k) = k.as_deref_mut() {
            k[..ndof * ndof].fill(0.0);
        }
        let mut g = [[0.0; 3]; MAX_NODES];
        for (q, p) in self.points.iter().enumerate() {
            let dv = p.w * self.gradients(p, ctx.coords, q, &mut g)?;
            let c = self.elasticity(p, ctx.coords);
            let eps_th =
                point_thermal_strain(self.material_of(p), &p.n[..nn], ctx.coords, ctx.temperature);
            let f = tl::deformation_gradient(&g[..nn], ctx.disp);
            let s = c * (tl::green_strain(&f) - eps_th);
            tl::add_internal_force(&g[..nn], &f, &s, dv, f_int);
            if let Some(k) = k.as_deref_mut() {
                tl::add_tangent(&g[..nn], &f, &s, &c, dv, k, ndof);
            }
        }
        Ok(())
    }

    /// At point data `p` with gradients `g`: the stress (Cauchy under
    /// `nlgeom`), the strain (Green's under `nlgeom`), the thermal strain
    /// and, under `nlgeom`, the second Piola-Kirchhoff stress.
    fn point_stress(
        &self,
        p: &PointData,
        g: &[[f64; 3]; MAX_NODES],
        ctx: &ElementContext<'_>,
    ) -> PointStress {
        let nn = self.shape.num_nodes();
        let c = self.elasticity(p, ctx.coords);
        let thermal =
            point_thermal_strain(self.material_of(p), &p.n[..nn], ctx.coords, ctx.temperature);
        match self.kinematics {
            Kinematics::Small => {
                let strain = self.strain(g, ctx.disp);
                PointStress {
                    stress: (c * (strain - thermal)).into(),
                    strain,
                    thermal,
                    pk2: None,
                }
            }
            Kinematics::Finite => {
                let f = tl::deformation_gradient(&g[..nn], ctx.disp);
                let strain = tl::green_strain(&f);
                let s = c * (strain - thermal);
                PointStress {
                    stress: tl::cauchy_stress(&f, &s),
                    strain,
                    thermal,
                    pk2: Some(s.into()),
                }
            }
        }
    }
}

impl Element for SolidElement {
    fn key(&self) -> &'static str {
        self.key
    }
    fn shape(&self) -> CellShape {
        self.shape
    }
    fn num_points(&self) -> usize {
        self.points.len()
    }
    /// The largest of the plies' (one material for an ordinary element).
    fn reference_modulus(&self) -> Option<f64> {
        self.plies
            .iter()
            .map(|m| m.material.reference_modulus())
            .reduce(f64::max)
    }
    /// The material of the first ply for a layered element.
    fn material(&self) -> Option<&dyn Material> {
        Some(self.plies[0].material.as_ref())
    }
    /// The largest of the plies' (one material for an ordinary element).
    fn directional_modulus(&self, n: [f64; 3]) -> Option<f64> {
        self.plies
            .iter()
            .filter_map(|m| m.material.directional_modulus(n))
            .reduce(f64::max)
    }
    fn has_thermal_expansion(&self) -> bool {
        self.plies
            .iter()
            .any(|m| m.material.has_thermal_expansion())
    }
    /// Small strains and a linear elastic material: `f = K u`; not so
    /// under `nlgeom`.
    fn is_linear(&self) -> bool {
        self.kinematics == Kinematics::Small
    }
    fn kinematics(&self) -> Kinematics {
        self.kinematics
    }
    /// Symmetric positive definite; under `nlgeom` the geometric stiffness
    /// makes it indefinite under compression (buckling).
    fn tangent_kind(&self) -> junta_core::MatrixKind {
        match self.kinematics {
            Kinematics::Small => junta_core::MatrixKind::SymmetricPositiveDefinite,
            Kinematics::Finite => junta_core::MatrixKind::SymmetricIndefinite,
        }
    }

    fn compute(
        &self,
        ctx: &ElementContext<'_>,
        _state_trial: &mut [f64],
        f_int: &mut [f64],
        k: Option<&mut [f64]>,
    ) -> Result<(), ElementError> {
        match self.kinematics {
            Kinematics::Small => self.compute_small(ctx, f_int, k),
            Kinematics::Finite => self.compute_finite(ctx, f_int, k),
        }
    }

    fn check_geometry(&self, coords: &[[f64; 3]]) -> Result<(), ElementError> {
        let mut g = [[0.0; 3]; MAX_NODES];
        for (q, p) in self.points.iter().enumerate() {
            self.gradients(p, coords, q, &mut g)?;
        }
        let np = self.points.len();
        for (c, p) in self.corners.iter().enumerate() {
            self.gradients(p, coords, np + c, &mut g)?;
        }
        Ok(())
    }

    fn point_outputs(&self, ctx: &ElementContext<'_>) -> Result<Vec<PointOutput>, ElementError> {
        let mut g = [[0.0; 3]; MAX_NODES];
        let mut out = Vec::with_capacity(self.points.len());
        for (q, p) in self.points.iter().enumerate() {
            let det = self.gradients(p, ctx.coords, q, &mut g)?;
            let ps = self.point_stress(p, &g, ctx);
            let mut values = vec![
                ("stress", ps.stress.to_vec()),
                ("strain", ps.strain.iter().copied().collect()),
                ("mises", vec![von_mises(&ps.stress)]),
                ("volume", vec![p.w * det]),
            ];
            if let Some(pk2) = ps.pk2 {
                values.push(("pk2_stress", pk2.to_vec()));
            }
            let position = self.position(p, ctx.coords);
            // under nlgeom: the PK2 stress, whose axes are the reference ones
            let objective = ps.pk2.as_ref().unwrap_or(&ps.stress);
            if let Some(s) = material_stress(self.material_of(p), position, objective) {
                values.push(("material_stress", s.to_vec()));
            }
            if self.layered {
                values.push(("ply", vec![(p.ply + 1) as f64]));
            }
            if ctx.temperature.is_some() {
                values.push(("thermal_strain", ps.thermal.iter().copied().collect()));
            }
            out.push(PointOutput { position, values });
        }
        Ok(out)
    }
}

/// The stress in the material's own axes at `x` (output `material_stress`,
/// Voigt `[11, 22, 33, 12, 23, 31]`): `sigma_l = Q^T sigma Q` with `Q` the
/// axes of [`Material::axes_at`], i.e. `sigma_l = T(Q^T) sigma` in Voigt
/// form ([`crate::material::stress_rotation`]). `None` for a material
/// without axes. Under large deformation the elements pass the second
/// Piola-Kirchhoff stress, whose axes are the reference material axes.
pub fn material_stress(
    material: &dyn Material,
    x: [f64; 3],
    stress: &[f64; 6],
) -> Option<[f64; 6]> {
    let q = material.axes_at(x)?;
    let t = crate::material::stress_rotation(&q.transpose());
    Some((t * Vector6::from(*stress)).into())
}

const SOLID_PARAMS: &[ParamDoc] = &[ParamDoc {
    name: "integration",
    doc: "optional \"full\" or \"reduced\" (default: as the key says; h8 has no reduced rule)",
}];

macro_rules! register_solid {
    ($key:literal, $shape:expr, $int:expr, $desc:literal) => {
        inventory::submit! {
            ElementEntry {
                key: $key,
                description: $desc,
                params: SOLID_PARAMS,
                shape: $shape,
                build: |b| Ok(Arc::new(SolidElement::from_build($key, $shape, $int, b)?)),
            }
        }
    };
}

register_solid!(
    "h8",
    CellShape::Hex8,
    Integration::Full,
    "8-node trilinear hexahedron, 2x2x2 Gauss, small-strain elasticity"
);
register_solid!(
    "h20",
    CellShape::Hex20,
    Integration::Full,
    "20-node serendipity hexahedron, 3x3x3 Gauss, small-strain elasticity"
);
register_solid!(
    "h27",
    CellShape::Hex27,
    Integration::Full,
    "27-node triquadratic hexahedron, 3x3x3 Gauss, small-strain elasticity"
);
register_solid!(
    "h20r",
    CellShape::Hex20,
    Integration::Reduced,
    "20-node serendipity hexahedron, reduced 2x2x2 Gauss, small-strain elasticity"
);
register_solid!(
    "h27r",
    CellShape::Hex27,
    Integration::Reduced,
    "27-node triquadratic hexahedron, reduced 2x2x2 Gauss (has spurious modes), small-strain elasticity"
);
register_solid!(
    "wedge6",
    CellShape::Wedge6,
    Integration::Full,
    "6-node linear wedge (C3D6), 3-point triangle x 2-point Gauss, small-strain elasticity"
);
register_solid!(
    "wedge6r",
    CellShape::Wedge6,
    Integration::Reduced,
    "6-node linear wedge, centroid x 2-point Gauss as CalculiX's C3D6 (one spurious mode per free element)"
);
register_solid!(
    "wedge15",
    CellShape::Wedge15,
    Integration::Full,
    "15-node serendipity wedge (C3D15), 3-point triangle x 3-point Gauss, small-strain elasticity"
);

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::Isotropic;

    #[test]
    fn von_mises_of_uniaxial_and_shear() {
        assert!((von_mises(&[3.0, 0.0, 0.0, 0.0, 0.0, 0.0]) - 3.0).abs() < 1e-15);
        assert!((von_mises(&[0.0, 0.0, 0.0, 1.0, 0.0, 0.0]) - 3f64.sqrt()).abs() < 1e-15);
        assert!(von_mises(&[2.0, 2.0, 2.0, 0.0, 0.0, 0.0]).abs() < 1e-15);
    }

    #[test]
    fn wedge_rule_sizes() {
        let m: Arc<dyn Material> = Arc::new(Isotropic::new(1.0, 0.3).unwrap());
        let n = |s| {
            SolidElement::new(s, Integration::Full, m.clone())
                .unwrap()
                .num_points()
        };
        assert_eq!(n(CellShape::Wedge6), 6);
        assert_eq!(n(CellShape::Wedge15), 9);
        let r = SolidElement::new(CellShape::Wedge6, Integration::Reduced, m.clone()).unwrap();
        assert_eq!(r.num_points(), 2);
        assert!(SolidElement::new(CellShape::Wedge15, Integration::Reduced, m).is_err());
    }

    #[test]
    fn rule_sizes() {
        let m: Arc<dyn Material> = Arc::new(Isotropic::new(1.0, 0.3).unwrap());
        let n = |s, i| SolidElement::new(s, i, m.clone()).unwrap().num_points();
        assert_eq!(n(CellShape::Hex8, Integration::Full), 8);
        assert_eq!(n(CellShape::Hex20, Integration::Full), 27);
        assert_eq!(n(CellShape::Hex27, Integration::Full), 27);
        assert_eq!(n(CellShape::Hex20, Integration::Reduced), 8);
        assert_eq!(n(CellShape::Hex27, Integration::Reduced), 8);
        assert!(SolidElement::new(CellShape::Hex8, Integration::Reduced, m.clone()).is_err());
        assert!(SolidElement::new(CellShape::Quad4, Integration::Full, m).is_err());
    }
}
