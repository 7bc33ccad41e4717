//! Plane solid elements: plane strain, plane stress and axisymmetric
//! quadrilaterals (4, 8, 9 nodes) and triangles (3, 6 nodes), registered
//! under the Abaqus names (`cpe4`, `cps8r`, `cax6`, ...), and the 4-node
//! quadrilateral with incompatible modes (`cpe4i`, `cps4i`, `cax4i`: [`incompatible`]).
//!
//! ## Kinematics
//!
//! The cell lies in the x-y plane (axisymmetric: x is the radius `r`, y
//! the axis). Geometry and displacement share the shape functions `N_a`
//! of the quadrilateral or triangle of the same order
//! ([`crate::shape::surface_shape`]); `∂N_a/∂x = J^-T ∂N_a/∂xi` with the
//! 2 x 2 Jacobian `J = ∂(x, y)/∂(xi, eta)`. Every node keeps the three
//! displacement components of the model, but the element uses only `u_x`
//! and `u_y` ([`Element::active_components`]): the model gives the `u_z`
//! of a node that only plane cells hold no equation, so a plane model
//! solves two equations per node.
//!
//! The strain is the 3D Voigt vector `[xx, yy, zz, xy, yz, zx]` with
//!
//! ```text
//! plane strain    eps = [u_x,x, u_y,y, 0,     u_x,y + u_y,x, 0, 0]
//! axisymmetric    eps = [u_r,r, u_z,z, u_r/r, u_r,z + u_z,r, 0, 0]   (zz is the hoop strain)
//! plane stress    eps_p = [u_x,x, u_y,y, u_x,y + u_y,x], and eps_zz, eps_yz, eps_zx
//!                 such that sigma_zz = sigma_yz = sigma_zx = 0
//! ```
//!
//! so, per node `a` with `g_a = ∂N_a/∂x`, the rows of `B_a` (over `u_x`,
//! `u_y`) for `[xx, yy, zz, xy]` are `[g_x, 0]`, `[0, g_y]`, `[N_a / r,
//! 0]` (axisymmetric; zero otherwise) and `[g_y, g_x]`.
//!
//! ## Constitutive relation
//!
//! With the material's 3D `C` (6 x 6, at the point's position for a
//! material that varies in space) and the thermal strain `eps_th`:
//!
//! * plane strain and axisymmetric: `sigma = C (eps - eps_th)` with the
//!   strain above (the out-of-plane stress `sigma_zz` and, for an
//!   anisotropic material, `sigma_yz`, `sigma_zx` follow from it);
//! * plane stress: with `p = {xx, yy, xy}` and `q = {zz, yz, zx}`, the
//!   condensed `C_s = C_pp - C_pq C_qq^-1 C_qp` gives `sigma_p = C_s (eps_p
//!   - eps_th,p)`, `sigma_q = 0`, and the out-of-plane strains `eps_q =
//!   eps_th,q - C_qq^-1 C_qp (eps_p - eps_th,p)` are outputs.
//!
//! ## Integrals
//!
//! `f_a = ∫ B_a^T sigma dV`, `K_ab = ∫ B_a^T D B_b dV` (`D` the `C` or
//! `C_s` above over `[xx, yy, zz, xy]`), with `dV = s(x) det J dxi deta`:
//! `s = t`, the thickness, in plane strain and plane stress (option
//! `thickness`, default 1: forces and energies per thickness `t`); `s =
//! 2 pi r` axisymmetric, so forces, reactions and energies are those of
//! the full ring, as Abaqus and CalculiX give them.
//!
//! Rules: PlaneQuad4 2 x 2 Gauss (full only: one point would leave two
//! hourglass modes); PlaneQuad8 / PlaneQuad9 3 x 3 (full) or 2 x 2
//! (reduced, the `...8r` keys); PlaneTri3 one point (constant strain, as
//! Abaqus) in plane strain and plane stress, the 3-point rule when
//! axisymmetric (one point would leave a spurious zero-energy mode beside
//! the axial translation: the hoop strain `N_a / r` is not constant);
//! PlaneTri6 the 3-point rule (degree 2).
//!
//! ## Large deformation (`nlgeom`)
//!
//! Built with [`Kinematics::Finite`], the element is total-Lagrangian in
//! the plane (St. Venant-Kirchhoff, `S = D E` with the same `D`). With
//! `F` the in-plane deformation gradient `I + sum_a u_a g_a^T` (2 x 2) and,
//! axisymmetric, the hoop stretch `F_tt = 1 + u_r / R` (`R` the reference
//! radius; 1 otherwise), the Green strain over `[xx, yy, zz, xy]` is
//!
//! ```text
//! E_xx = (F_xx^2 + F_yx^2 - 1) / 2        E_yy = (F_xy^2 + F_yy^2 - 1) / 2
//! E_zz = (F_tt^2 - 1) / 2  (axisymmetric; 0 otherwise)
//! 2 E_xy = F_xx F_xy + F_yx F_yy
//! ```
//!
//! and its variation per node `a` over `(u_x, u_y)` has the rows
//! `[F_xx g_x, F_yx g_x]`, `[F_xy g_y, F_yy g_y]`, `[F_tt N_a / R, 0]`,
//! `[F_xx g_y + F_xy g_x, F_yx g_y + F_yy g_x]` (`B_a`). Then `f_a = ∫ B_a^T
//! S dV0` and
//!
//! ```text
//! K_ab = ∫ B_a^T D B_b dV0 + ∫ (g_a^T S_2 g_b) I_2 dV0 + ∫ S_zz N_a N_b / R^2 (r-r entry) dV0
//! ```
//!
//! with `S_2 = [[S_xx, S_xy], [S_xy, S_yy]]` (the last term axisymmetric
//! only). Plane stress condenses `D` as in small strain (exact for St.
//! Venant-Kirchhoff, whose `S` is linear in `E`). The outputs give the
//! Cauchy stress `F S F^T / det F` (with `F_zz` the hoop stretch, or for
//! plane stress the thickness stretch `sqrt(1 + 2 E_zz)`), the Green strain
//! as `strain` and `pk2_stress`.
//!
//! ## Geometry check
//!
//! `det J > 0` at every integration point and corner node (a clockwise
//! cell fails it: list the nodes counter-clockwise), and for axisymmetric
//! cells a radius `r > 0` at every integration point: the reported
//! determinant is then `r det J`.
//!
//! ## Outputs
//!
//! Per integration point: `stress` and `strain` (the 3D Voigt vectors
//! above: `sigma_zz` is the out-of-plane stress in plane strain and the
//! hoop stress axisymmetric), `mises`, `volume` (`w s det J`),
//! `material_stress` for a material with axes, and `thermal_strain` under
//! a temperature change.

mod incompatible;

use crate::quadrature::{gauss_legendre_2d, triangle_rule, Rule};
use crate::shape::surface_shape;
use crate::solid::{material_stress, von_mises};
use crate::thermal::point_thermal_strain;
use junta_core::element::{Element, ElementContext, ElementError, PlaneWidth, PointOutput};
use junta_core::registry::{parse_params, ElementBuild, ElementEntry, ParamDoc};
use junta_core::topology::{CellShape, QUAD9_NODES, TRI6_NODES};
use junta_core::{CoreError, Kinematics, Material, Voigt6};
use nalgebra::{Matrix3, Matrix4, Vector6};
use serde::Deserialize;
use std::f64::consts::PI;
use std::sync::Arc;

/// Largest node count of a plane cell (PlaneQuad9).
const MAX_NODES: usize = 9;

/// The plane assumption of an element.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Section {
    /// Plane strain (`eps_zz = 0`) of a slice of thickness `t`.
    PlaneStrain {
        /// Out-of-plane thickness `t` (forces are per this thickness).
        thickness: f64,
    },
    /// Plane stress (`sigma_zz = 0`) of a plate of thickness `t`.
    PlaneStress {
        /// Plate thickness `t`.
        thickness: f64,
    },
    /// Axisymmetric about the y axis (x = r >= 0): the full ring.
    Axisymmetric,
}

/// Options table of the plane elements.
#[derive(Debug, Clone, Copy, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlaneOptions {
    /// Out-of-plane thickness (plane strain and plane stress; default 1).
    pub thickness: Option<f64>,
    /// `"full"` or `"reduced"` (quadratic quadrilaterals); default: as
    /// the key says.
    pub integration: Option<crate::solid::Integration>,
}

/// Shape data at one point of the reference cell.
#[derive(Debug, Clone)]
struct PlanePoint {
    w: f64,
    n: [f64; MAX_NODES],
    dn: [[f64; 2]; MAX_NODES],
}

impl PlanePoint {
    fn new(shape: CellShape, xi: [f64; 2], w: f64) -> Self {
        let mut n = [0.0; MAX_NODES];
        let mut dn = [[0.0; 2]; MAX_NODES];
        let nn = shape.num_nodes();
        surface_shape(shape, xi, &mut n[..nn], &mut dn[..nn]);
        PlanePoint { w, n, dn }
    }
}

/// A plane strain, plane stress or axisymmetric solid element.
#[derive(Debug, Clone)]
pub struct PlaneElement {
    key: &'static str,
    shape: CellShape,
    section: Section,
    kinematics: Kinematics,
    material: Arc<dyn Material>,
    /// `D` over `[xx, yy, zz, xy]` of a material uniform in space.
    d: Matrix4<f64>,
    points: Vec<PlanePoint>,
    /// Natural coordinates of the points.
    xi: Vec<[f64; 2]>,
    corners: Vec<PlanePoint>,
    /// The centre of the cell (the incompatible modes' `J0`).
    centre: PlanePoint,
    /// With the incompatible modes of [`incompatible`] (`cpe4i`, `cps4i`, `cax4i`).
    incompatible: bool,
}

/// The strains, stresses and `D` at one point.
struct PointState {
    /// Total strain (3D Voigt; plane stress: with its out-of-plane part).
    strain: Vector6<f64>,
    stress: [f64; 6],
    thermal: Vector6<f64>,
}

/// The in-plane deformation gradient `f` and the hoop stretch `ftt` (1
/// unless axisymmetric) at a point.
struct Stretch {
    f: [[f64; 2]; 2],
    ftt: f64,
}

impl Stretch {
    /// Green strain over `[xx, yy, zz, xy]` (engineering shear).
    fn green(&self) -> [f64; 4] {
        let f = &self.f;
        [
            0.5 * (f[0][0] * f[0][0] + f[1][0] * f[1][0] - 1.0),
            0.5 * (f[0][1] * f[0][1] + f[1][1] * f[1][1] - 1.0),
            0.5 * (self.ftt * self.ftt - 1.0),
            f[0][0] * f[0][1] + f[1][0] * f[1][1],
        ]
    }

    /// Rows of `B_a` (the Green strain's variation over `(u_x, u_y)` of
    /// node `a`) for gradient `g` and `h = N_a / R` (axisymmetric) or 0.
    fn variation(&self, g: [f64; 2], h: f64) -> [[f64; 2]; 4] {
        let f = &self.f;
        [
            [f[0][0] * g[0], f[1][0] * g[0]],
            [f[0][1] * g[1], f[1][1] * g[1]],
            [self.ftt * h, 0.0],
            [
                f[0][0] * g[1] + f[0][1] * g[0],
                f[1][0] * g[1] + f[1][1] * g[0],
            ],
        ]
    }

    /// The 3D deformation gradient, `F_zz` the hoop stretch or (plane
    /// stress) the thickness stretch of the Green strain `e_zz`.
    fn full(&self, e_zz: f64) -> nalgebra::Matrix3<f64> {
        let f = &self.f;
        let fzz = if self.ftt != 1.0 {
            self.ftt
        } else {
            (1.0 + 2.0 * e_zz).max(0.0).sqrt()
        };
        nalgebra::Matrix3::new(f[0][0], f[0][1], 0.0, f[1][0], f[1][1], 0.0, 0.0, 0.0, fzz)
    }
}

/// Voigt indices of the in-plane components `[xx, yy, zz, xy]`.
const ACTIVE: [usize; 4] = [0, 1, 2, 3];

/// `D` over `[xx, yy, zz, xy]` for a section and the 3D `C`: the rows and
/// columns of `C` (plane strain, axisymmetric), or the plane-stress
/// condensation `C_pp - C_pq C_qq^-1 C_qp` with zero `zz` row and column.
fn section_stiffness(section: Section, c: &Voigt6) -> Matrix4<f64> {
    let mut d = Matrix4::zeros();
    match section {
        Section::PlaneStress { .. } => {
            let s = plane_stress_condensation(c);
            let p = [0usize, 1, 3];
            for (i, &pi) in p.iter().enumerate() {
                for (j, &pj) in p.iter().enumerate() {
                    d[(pi, pj)] = s.0[(i, j)];
                }
            }
        }
        _ => {
            for (i, &a) in ACTIVE.iter().enumerate() {
                for (j, &b) in ACTIVE.iter().enumerate() {
                    d[(i, j)] = c[(a, b)];
                }
            }
        }
    }
    d
}

/// Plane stress: `C_s = C_pp - C_pq C_qq^-1 C_qp` over `p = [xx, yy, xy]`
/// and `E = -C_qq^-1 C_qp` (the out-of-plane strains per in-plane strain),
/// `q = [zz, yz, zx]`.
fn plane_stress_condensation(c: &Voigt6) -> (Matrix3<f64>, Matrix3<f64>) {
    const P: [usize; 3] = [0, 1, 3];
    const Q: [usize; 3] = [2, 4, 5];
    let pick = |r: [usize; 3], s: [usize; 3]| Matrix3::from_fn(|i, j| c[(r[i], s[j])]);
    let (cpp, cpq, cqp, cqq) = (pick(P, P), pick(P, Q), pick(Q, P), pick(Q, Q));
    // C_qq of an elastic material is positive definite
    let inv = cqq.try_inverse().unwrap_or_else(Matrix3::zeros);
    let e = -(inv * cqp);
    (cpp + cpq * e, e)
}

impl PlaneElement {
    /// A plane element of `shape` (a plane cell) with the section, the
    /// integration (`reduced` for PlaneQuad8 / PlaneQuad9 only) and the
    /// material; `key` is its registry key. Errors: a shape that is not a
    /// plane cell, a reduced rule on a linear cell or a triangle, and a
    /// thickness that is not positive and finite.
    pub fn new(
        key: &'static str,
        shape: CellShape,
        section: Section,
        reduced: bool,
        material: Arc<dyn Material>,
    ) -> Result<Self, CoreError> {
        let bad = |message: String| CoreError::InvalidParameters {
            kind: "element",
            key: key.into(),
            message,
        };
        if let Section::PlaneStrain { thickness } | Section::PlaneStress { thickness } = section {
            if !(thickness.is_finite() && thickness > 0.0) {
                return Err(bad(format!(
                    "thickness = {thickness}: the out-of-plane thickness must be positive"
                )));
            }
        }
        let (rule, corners): (Rule<2>, &[[f64; 2]]) = match (shape, reduced) {
            (CellShape::PlaneQuad4, false) => {
                (gauss_legendre_2d(2).expect("rule"), &QUAD9_NODES[..4])
            }
            (CellShape::PlaneQuad8 | CellShape::PlaneQuad9, r) => (
                gauss_legendre_2d(if r { 2 } else { 3 }).expect("rule"),
                &QUAD9_NODES[..4],
            ),
            (CellShape::PlaneTri3, false) => {
                let n = if section == Section::Axisymmetric {
                    3
                } else {
                    1
                };
                (triangle_rule(n).expect("rule"), &TRI6_NODES[..3])
            }
            (CellShape::PlaneTri6, false) => (triangle_rule(3).expect("rule"), &TRI6_NODES[..3]),
            (s, true) if s.is_plane() => {
                return Err(bad(format!(
                    "{} has no reduced integration here (one point leaves hourglass modes); use \
                     integration = \"full\"",
                    s.name()
                )))
            }
            (s, _) => {
                return Err(bad(format!(
                    "plane elements are plane_quad4/8/9 or plane_tri3/6 cells, not {}",
                    s.name()
                )))
            }
        };
        let points = rule
            .points
            .iter()
            .zip(&rule.weights)
            .map(|(&xi, &w)| PlanePoint::new(shape, xi, w))
            .collect();
        let centre = match shape {
            CellShape::PlaneTri3 | CellShape::PlaneTri6 => [1.0 / 3.0, 1.0 / 3.0],
            _ => [0.0, 0.0],
        };
        let corners = corners
            .iter()
            .map(|&xi| PlanePoint::new(shape, xi, 0.0))
            .collect();
        Ok(PlaneElement {
            key,
            shape,
            section,
            kinematics: Kinematics::Small,
            d: section_stiffness(section, &material.elasticity()),
            material,
            points,
            xi: rule.points.clone(),
            corners,
            centre: PlanePoint::new(shape, centre, 0.0),
            incompatible: false,
        })
    }

    /// The same 4-node quadrilateral with incompatible modes (plane strain,
    /// plane stress or axisymmetric; see [`incompatible`]). Errors for
    /// other cells.
    pub fn with_incompatible_modes(mut self) -> Result<Self, CoreError> {
        if self.shape != CellShape::PlaneQuad4 {
            return Err(CoreError::InvalidParameters {
                kind: "element",
                key: self.key.into(),
                message:
                    "incompatible modes are for the 4-node quadrilateral (cpe4i, cps4i, cax4i)"
                        .into(),
            });
        }
        self.incompatible = true;
        Ok(self)
    }

    /// The section (plane strain, plane stress or axisymmetric).
    pub fn section(&self) -> Section {
        self.section
    }

    /// The same element with the given kinematics.
    pub fn with_kinematics(mut self, kinematics: Kinematics) -> Self {
        self.kinematics = kinematics;
        self
    }

    /// Build registry key `key` with its shape, section kind and default
    /// rule from the options (`thickness`, `integration`).
    fn from_build(
        key: &'static str,
        shape: CellShape,
        kind: SectionKind,
        reduced: bool,
        build: &ElementBuild<'_>,
    ) -> Result<Self, CoreError> {
        let incompatible = key.ends_with('i');
        let bad = |message: String| CoreError::InvalidParameters {
            kind: "element",
            key: key.into(),
            message,
        };
        let opts: PlaneOptions = parse_params("element", key, build.options)?;
        let reduced = match opts.integration {
            Some(crate::solid::Integration::Reduced) => true,
            Some(crate::solid::Integration::Full) if reduced => {
                return Err(bad(format!(
                    "{key} is the reduced-integration element; for full integration use `{}`",
                    key.trim_end_matches('r')
                )))
            }
            _ => reduced,
        };
        let section =
            match (kind, opts.thickness) {
                (SectionKind::Strain, t) => Section::PlaneStrain {
                    thickness: t.unwrap_or(1.0),
                },
                (SectionKind::Stress, t) => Section::PlaneStress {
                    thickness: t.unwrap_or(1.0),
                },
                (SectionKind::Axisymmetric, None) => Section::Axisymmetric,
                (SectionKind::Axisymmetric, Some(_)) => return Err(bad(
                    "an axisymmetric element takes no thickness: it models the full ring (forces \
                     and reactions per 2 pi radians)"
                        .into(),
                )),
            };
        let material = build.material.clone().ok_or_else(|| {
            bad(format!(
                "plane element {key} requires a material (an `isotropic`, `orthotropic` or \
                 `anisotropic` material named by the block); none was given"
            ))
        })?;
        let el =
            Self::new(key, shape, section, reduced, material)?.with_kinematics(build.kinematics);
        if incompatible {
            el.with_incompatible_modes()
        } else {
            Ok(el)
        }
    }

    /// Physical gradients `g[a] = ∂N_a/∂(x, y)`, the position and the
    /// volume factor `s(x) det J` at point `p`; error if it is not positive.
    fn gradients(
        &self,
        p: &PlanePoint,
        coords: &[[f64; 3]],
        point: usize,
        g: &mut [[f64; 2]; MAX_NODES],
    ) -> Result<([f64; 3], f64), ElementError> {
        let nn = self.shape.num_nodes();
        let (mut j, mut x) = ([[0.0; 2]; 2], [0.0; 3]);
        for a in 0..nn {
            for r in 0..2 {
                for c in 0..2 {
                    j[r][c] += coords[a][r] * p.dn[a][c];
                }
            }
            for (xi, ci) in x.iter_mut().zip(&coords[a]) {
                *xi += p.n[a] * ci;
            }
        }
        let det = j[0][0] * j[1][1] - j[0][1] * j[1][0];
        let scale = match self.section {
            Section::PlaneStrain { thickness } | Section::PlaneStress { thickness } => thickness,
            Section::Axisymmetric => 2.0 * PI * x[0],
        };
        let vol = scale * det;
        if vol.is_nan() || det <= 0.0 || vol <= 0.0 {
            return Err(ElementError::NegativeJacobian { point, det: vol });
        }
        // g = J^-T dN
        for a in 0..nn {
            let [dx, dy] = p.dn[a];
            g[a] = [
                (j[1][1] * dx - j[1][0] * dy) / det,
                (-j[0][1] * dx + j[0][0] * dy) / det,
            ];
        }
        Ok((x, vol))
    }

    /// `D` at a point at `x`: the stored one, or the material's at `x`.
    fn stiffness_at(&self, x: [f64; 3]) -> Matrix4<f64> {
        if self.material.varies_in_space() {
            section_stiffness(self.section, &self.material.elasticity_at(x))
        } else {
            self.d
        }
    }

    /// In-plane strain `[xx, yy, zz, xy]` (zz: the hoop strain u_r / r
    /// axisymmetric, 0 otherwise).
    fn active_strain(
        &self,
        p: &PlanePoint,
        g: &[[f64; 2]; MAX_NODES],
        x: [f64; 3],
        u: &[f64],
    ) -> [f64; 4] {
        let mut e = [0.0; 4];
        let axi = self.section == Section::Axisymmetric;
        for (a, ga) in g.iter().enumerate().take(self.shape.num_nodes()) {
            let (ux, uy) = (u[3 * a], u[3 * a + 1]);
            e[0] += ga[0] * ux;
            e[1] += ga[1] * uy;
            if axi {
                e[2] += p.n[a] * ux / x[0];
            }
            e[3] += ga[1] * ux + ga[0] * uy;
        }
        e
    }

    /// Strain (from its in-plane part `e` over `[xx, yy, zz, xy]`),
    /// stress and thermal strain at point `p` (position `x`).
    fn point_state(
        &self,
        p: &PlanePoint,
        e: [f64; 4],
        x: [f64; 3],
        ctx: &ElementContext<'_>,
    ) -> PointState {
        let nn = self.shape.num_nodes();
        let thermal =
            point_thermal_strain(&*self.material, &p.n[..nn], ctx.coords, ctx.temperature);
        let mut strain = Vector6::zeros();
        for (i, &k) in ACTIVE.iter().enumerate() {
            strain[k] = e[i];
        }
        let c = if self.material.varies_in_space() {
            self.material.elasticity_at(x)
        } else {
            self.material.elasticity()
        };
        let plane_stress = matches!(self.section, Section::PlaneStress { .. });
        if plane_stress {
            let (_, ez) = plane_stress_condensation(&c);
            let mech_p =
                nalgebra::Vector3::new(e[0] - thermal[0], e[1] - thermal[1], e[3] - thermal[3]);
            let out = ez * mech_p;
            for (i, k) in [2usize, 4, 5].into_iter().enumerate() {
                strain[k] = thermal[k] + out[i];
            }
        }
        let mut stress: [f64; 6] = (c * (strain - thermal)).into();
        if plane_stress {
            // zero to round-off by construction; exactly zero as stated
            stress[2] = 0.0;
            stress[4] = 0.0;
            stress[5] = 0.0;
        }
        PointState {
            strain,
            stress,
            thermal,
        }
    }

    /// The in-plane deformation gradient and the hoop stretch at point `p`.
    fn stretch(
        &self,
        p: &PlanePoint,
        g: &[[f64; 2]; MAX_NODES],
        x: [f64; 3],
        u: &[f64],
    ) -> Stretch {
        let mut f = [[1.0, 0.0], [0.0, 1.0]];
        let mut ftt = 1.0;
        for (a, ga) in g.iter().enumerate().take(self.shape.num_nodes()) {
            for (i, fi) in f.iter_mut().enumerate() {
                fi[0] += u[3 * a + i] * ga[0];
                fi[1] += u[3 * a + i] * ga[1];
            }
            if self.section == Section::Axisymmetric {
                ftt += p.n[a] * u[3 * a] / x[0];
            }
        }
        Stretch { f, ftt }
    }

    /// Total-Lagrangian: `f_a = ∫ B_a^T S dV0`, `K` with the geometric
    /// stiffness (module docs).
    fn compute_finite(
        &self,
        ctx: &ElementContext<'_>,
        f_int: &mut [f64],
        mut k: Option<&mut [f64]>,
    ) -> Result<(), ElementError> {
        let nn = self.shape.num_nodes();
        let ndof = 3 * nn;
        let axi = self.section == Section::Axisymmetric;
        let mut g = [[0.0; 2]; MAX_NODES];
        let mut b = [[[0.0; 2]; 4]; MAX_NODES];
        for (q, p) in self.points.iter().enumerate() {
            let (x, vol) = self.gradients(p, ctx.coords, q, &mut g)?;
            let dv = p.w * vol;
            let st = self.stretch(p, &g, x, ctx.disp);
            let ps = self.point_state(p, st.green(), x, ctx);
            let s4 = [ps.stress[0], ps.stress[1], ps.stress[2], ps.stress[3]];
            for a in 0..nn {
                let h = if axi { p.n[a] / x[0] } else { 0.0 };
                b[a] = st.variation(g[a], h);
                for i in 0..2 {
                    f_int[3 * a + i] += dv * (0..4).map(|r| b[a][r][i] * s4[r]).sum::<f64>();
                }
            }
            let Some(k) = k.as_deref_mut() else { continue };
            let d = self.stiffness_at(x);
            for bb in 0..nn {
                // D B_b, column by column
                let db: [[f64; 4]; 2] = std::array::from_fn(|j| {
                    std::array::from_fn(|r| (0..4).map(|c| d[(r, c)] * b[bb][c][j]).sum())
                });
                for a in 0..nn {
                    let geo = dv
                        * (g[a][0] * (s4[0] * g[bb][0] + s4[3] * g[bb][1])
                            + g[a][1] * (s4[3] * g[bb][0] + s4[1] * g[bb][1]));
                    let hoop = if axi {
                        dv * s4[2] * p.n[a] * p.n[bb] / (x[0] * x[0])
                    } else {
                        0.0
                    };
                    for i in 0..2 {
                        for j in 0..2 {
                            let mat: f64 = (0..4).map(|r| b[a][r][i] * db[j][r]).sum();
                            let extra = if i == j {
                                geo + if i == 0 { hoop } else { 0.0 }
                            } else {
                                0.0
                            };
                            k[(3 * a + i) * ndof + 3 * bb + j] += dv * mat + extra;
                        }
                    }
                }
            }
        }
        Ok(())
    }
}

/// `B_a^T s` over `(u_x, u_y)` for `s` over `[xx, yy, zz, xy]`: gradient
/// `g`, and `h = N_a / r` (axisymmetric) or 0.
#[inline(always)]
fn bt_times(g: [f64; 2], h: f64, s: &[f64; 4]) -> [f64; 2] {
    [
        g[0] * s[0] + h * s[2] + g[1] * s[3],
        g[1] * s[1] + g[0] * s[3],
    ]
}

impl Element for PlaneElement {
    fn key(&self) -> &'static str {
        self.key
    }
    fn shape(&self) -> CellShape {
        self.shape
    }
    fn num_points(&self) -> usize {
        self.points.len()
    }
    fn active_components(&self) -> [bool; 3] {
        [true, true, false]
    }
    fn plane_width(&self) -> Option<PlaneWidth> {
        Some(match self.section {
            Section::PlaneStrain { thickness } | Section::PlaneStress { thickness } => {
                PlaneWidth::Thickness(thickness)
            }
            Section::Axisymmetric => PlaneWidth::Axisymmetric,
        })
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
    /// Small strains: `f = K u` (plus the thermal force); not so under `nlgeom`.
    fn is_linear(&self) -> bool {
        self.kinematics == Kinematics::Small
    }
    fn kinematics(&self) -> Kinematics {
        self.kinematics
    }
    /// Under `nlgeom` the incompatible modes' 4 parameters
    /// ([`incompatible`]); none otherwise.
    fn state_len(&self) -> usize {
        if self.incompatible && self.kinematics == Kinematics::Finite {
            4
        } else {
            0
        }
    }
    /// Symmetric positive definite; under `nlgeom` the geometric stiffness
    /// makes it indefinite under compression.
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
        mut k: Option<&mut [f64]>,
    ) -> Result<(), ElementError> {
        let nn = self.shape.num_nodes();
        let ndof = 3 * nn;
        let f_int = &mut f_int[..ndof];
        f_int.fill(0.0);
        if let Some(k) = k.as_deref_mut() {
            k[..ndof * ndof].fill(0.0);
        }
        match (self.kinematics, self.incompatible) {
            (Kinematics::Finite, true) => {
                return self.compute_finite_incompatible(ctx, state_trial, f_int, k)
            }
            (Kinematics::Finite, false) => return self.compute_finite(ctx, f_int, k),
            (Kinematics::Small, true) => return self.compute_incompatible(ctx, f_int, k),
            (Kinematics::Small, false) => {}
        }
        let axi = self.section == Section::Axisymmetric;
        let mut g = [[0.0; 2]; MAX_NODES];
        for (q, p) in self.points.iter().enumerate() {
            let (x, vol) = self.gradients(p, ctx.coords, q, &mut g)?;
            let dv = p.w * vol;
            let ps = self.point_state(p, self.active_strain(p, &g, x, ctx.disp), x, ctx);
            let s = [ps.stress[0], ps.stress[1], ps.stress[2], ps.stress[3]];
            let h = |a: usize| if axi { p.n[a] / x[0] } else { 0.0 };
            for a in 0..nn {
                let r = bt_times(g[a], h(a), &s);
                f_int[3 * a] += dv * r[0];
                f_int[3 * a + 1] += dv * r[1];
            }
            let Some(k) = k.as_deref_mut() else { continue };
            let d = self.stiffness_at(x);
            for b in 0..nn {
                // D B_b, column by column (u_x, u_y of node b)
                let (gb, hb) = (g[b], h(b));
                let cx: [f64; 4] =
                    std::array::from_fn(|r| d[(r, 0)] * gb[0] + d[(r, 2)] * hb + d[(r, 3)] * gb[1]);
                let cy: [f64; 4] = std::array::from_fn(|r| d[(r, 1)] * gb[1] + d[(r, 3)] * gb[0]);
                for a in 0..nn {
                    let (rx, ry) = (bt_times(g[a], h(a), &cx), bt_times(g[a], h(a), &cy));
                    let row = 3 * a * ndof + 3 * b;
                    k[row] += dv * rx[0];
                    k[row + 1] += dv * ry[0];
                    k[row + ndof] += dv * rx[1];
                    k[row + ndof + 1] += dv * ry[1];
                }
            }
        }
        Ok(())
    }

    fn check_geometry(&self, coords: &[[f64; 3]]) -> Result<(), ElementError> {
        let mut g = [[0.0; 2]; MAX_NODES];
        for (q, p) in self.points.iter().enumerate() {
            self.gradients(p, coords, q, &mut g)?;
        }
        // corners: det J only (an axisymmetric node on the axis has r = 0)
        let np = self.points.len();
        for (c, p) in self.corners.iter().enumerate() {
            let mut j = [[0.0; 2]; 2];
            for a in 0..self.shape.num_nodes() {
                for r in 0..2 {
                    for s in 0..2 {
                        j[r][s] += coords[a][r] * p.dn[a][s];
                    }
                }
            }
            let det = j[0][0] * j[1][1] - j[0][1] * j[1][0];
            if det.is_nan() || det <= 0.0 {
                return Err(ElementError::NegativeJacobian { point: np + c, det });
            }
        }
        Ok(())
    }

    fn point_outputs(&self, ctx: &ElementContext<'_>) -> Result<Vec<PointOutput>, ElementError> {
        match (self.kinematics, self.incompatible) {
            (Kinematics::Finite, true) => return self.point_outputs_finite_incompatible(ctx),
            (Kinematics::Small, true) => return self.point_outputs_incompatible(ctx),
            _ => {}
        }
        let mut g = [[0.0; 2]; MAX_NODES];
        let mut out = Vec::with_capacity(self.points.len());
        for (q, p) in self.points.iter().enumerate() {
            let (x, vol) = self.gradients(p, ctx.coords, q, &mut g)?;
            out.push(match self.kinematics {
                Kinematics::Small => {
                    self.point_output(p, self.active_strain(p, &g, x, ctx.disp), x, vol, ctx)
                }
                Kinematics::Finite => self.point_output_finite(p, &g, x, vol, ctx),
            });
        }
        Ok(out)
    }
}

impl PlaneElement {
    /// The outputs at point `p` (position `x`, volume factor `vol`) of the
    /// small-strain in-plane strain `e`.
    fn point_output(
        &self,
        p: &PlanePoint,
        e: [f64; 4],
        x: [f64; 3],
        vol: f64,
        ctx: &ElementContext<'_>,
    ) -> PointOutput {
        let ps = self.point_state(p, e, x, ctx);
        self.output_values(p, ps, None, x, vol, ctx)
    }

    /// The outputs at point `p` under `nlgeom`: Cauchy `stress`, Green
    /// `strain`, `pk2_stress`.
    fn point_output_finite(
        &self,
        p: &PlanePoint,
        g: &[[f64; 2]; MAX_NODES],
        x: [f64; 3],
        vol: f64,
        ctx: &ElementContext<'_>,
    ) -> PointOutput {
        let st = self.stretch(p, g, x, ctx.disp);
        self.finite_output_of(p, &st, x, vol, ctx)
    }

    /// The outputs at point `p` of the stretch `st` under `nlgeom`.
    fn finite_output_of(
        &self,
        p: &PlanePoint,
        st: &Stretch,
        x: [f64; 3],
        vol: f64,
        ctx: &ElementContext<'_>,
    ) -> PointOutput {
        let mut ps = self.point_state(p, st.green(), x, ctx);
        let pk2 = ps.stress;
        let f = st.full(ps.strain[2]);
        ps.stress = crate::total_lagrangian::cauchy_stress(&f, &Vector6::from(pk2));
        self.output_values(p, ps, Some(pk2), x, vol, ctx)
    }

    fn output_values(
        &self,
        p: &PlanePoint,
        ps: PointState,
        pk2: Option<[f64; 6]>,
        x: [f64; 3],
        vol: f64,
        ctx: &ElementContext<'_>,
    ) -> PointOutput {
        let mut values = vec![
            ("stress", ps.stress.to_vec()),
            ("strain", ps.strain.iter().copied().collect()),
            ("mises", vec![von_mises(&ps.stress)]),
            ("volume", vec![p.w * vol]),
        ];
        if let Some(pk2) = pk2 {
            values.push(("pk2_stress", pk2.to_vec()));
        }
        let objective = pk2.as_ref().unwrap_or(&ps.stress);
        if let Some(s) = material_stress(&*self.material, x, objective) {
            values.push(("material_stress", s.to_vec()));
        }
        if ctx.temperature.is_some() {
            values.push(("thermal_strain", ps.thermal.iter().copied().collect()));
        }
        PointOutput {
            position: x,
            values,
        }
    }
}

/// Which section a registry key builds.
#[derive(Debug, Clone, Copy)]
enum SectionKind {
    Strain,
    Stress,
    Axisymmetric,
}

const PLANE_PARAMS: &[ParamDoc] = &[
    ParamDoc {
        name: "thickness",
        doc: "out-of-plane thickness of plane strain and plane stress elements (default 1; forces \
              are per this thickness); axisymmetric elements take none (full ring)",
    },
    ParamDoc {
        name: "integration",
        doc: "optional \"full\" or \"reduced\" (8- and 9-node quadrilaterals only)",
    },
];

macro_rules! register_plane {
    ($key:literal, $shape:expr, $kind:expr, $reduced:expr, $desc:literal) => {
        inventory::submit! {
            ElementEntry {
                key: $key,
                description: $desc,
                params: PLANE_PARAMS,
                shape: $shape,
                build: |b| Ok(Arc::new(PlaneElement::from_build($key, $shape, $kind, $reduced, b)?)),
            }
        }
    };
}

use CellShape::{
    PlaneQuad4 as Q4, PlaneQuad8 as Q8, PlaneQuad9 as Q9, PlaneTri3 as T3, PlaneTri6 as T6,
};
use SectionKind::{Axisymmetric as Ax, Strain as Pe, Stress as Ps};

register_plane!(
    "cpe3",
    T3,
    Pe,
    false,
    "3-node plane strain triangle (CPE3), 1 point"
);
register_plane!(
    "cpe4",
    Q4,
    Pe,
    false,
    "4-node plane strain quadrilateral (CPE4), 2x2 Gauss"
);
register_plane!(
    "cpe6",
    T6,
    Pe,
    false,
    "6-node plane strain triangle (CPE6), 3 points"
);
register_plane!(
    "cpe8",
    Q8,
    Pe,
    false,
    "8-node plane strain quadrilateral (CPE8), 3x3 Gauss"
);
register_plane!(
    "cpe8r",
    Q8,
    Pe,
    true,
    "8-node plane strain quadrilateral, reduced 2x2 (CPE8R)"
);
register_plane!(
    "cpe9",
    Q9,
    Pe,
    false,
    "9-node plane strain quadrilateral, 3x3 Gauss"
);
register_plane!(
    "cps3",
    T3,
    Ps,
    false,
    "3-node plane stress triangle (CPS3), 1 point"
);
register_plane!(
    "cps4",
    Q4,
    Ps,
    false,
    "4-node plane stress quadrilateral (CPS4), 2x2 Gauss"
);
register_plane!(
    "cps6",
    T6,
    Ps,
    false,
    "6-node plane stress triangle (CPS6), 3 points"
);
register_plane!(
    "cps8",
    Q8,
    Ps,
    false,
    "8-node plane stress quadrilateral (CPS8), 3x3 Gauss"
);
register_plane!(
    "cps8r",
    Q8,
    Ps,
    true,
    "8-node plane stress quadrilateral, reduced 2x2 (CPS8R)"
);
register_plane!(
    "cps9",
    Q9,
    Ps,
    false,
    "9-node plane stress quadrilateral, 3x3 Gauss"
);
register_plane!(
    "cax3",
    T3,
    Ax,
    false,
    "3-node axisymmetric triangle (CAX3), 3 points"
);
register_plane!(
    "cax4",
    Q4,
    Ax,
    false,
    "4-node axisymmetric quadrilateral (CAX4), 2x2 Gauss"
);
register_plane!(
    "cax6",
    T6,
    Ax,
    false,
    "6-node axisymmetric triangle (CAX6), 3 points"
);
register_plane!(
    "cax8",
    Q8,
    Ax,
    false,
    "8-node axisymmetric quadrilateral (CAX8), 3x3 Gauss"
);
register_plane!(
    "cax8r",
    Q8,
    Ax,
    true,
    "8-node axisymmetric quadrilateral, reduced 2x2 (CAX8R)"
);
register_plane!(
    "cax9",
    Q9,
    Ax,
    false,
    "9-node axisymmetric quadrilateral, 3x3 Gauss"
);
register_plane!(
    "cpe4i",
    Q4,
    Pe,
    false,
    "4-node plane strain quadrilateral with incompatible modes (CPE4I): bends without shear locking"
);
register_plane!(
    "cax4i",
    Q4,
    Ax,
    false,
    "4-node axisymmetric quadrilateral with incompatible modes (CAX4I): bends in the r-z plane without shear locking"
);
register_plane!(
    "cps4i",
    Q4,
    Ps,
    false,
    "4-node plane stress quadrilateral with incompatible modes (CPS4I): bends without shear locking"
);
