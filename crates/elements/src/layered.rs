//! Layered (composite) integration of a hexahedral solid: several plies in
//! one element, integrated ply by ply through the thickness, each with its
//! own material (as Abaqus's `*SOLID SECTION, COMPOSITE`).
//!
//! ## The rule
//!
//! Let `s` (0, 1 or 2) be the stack direction among the natural
//! coordinates `(xi_1, xi_2, xi_3)` of the hexahedron and `(p, q)` the two
//! others. The plies `k = 1..m`, bottom (`xi_s = -1`) to top
//! (`xi_s = +1`), have relative thicknesses `t_k > 0`, normalised to the
//! element: ply `k` occupies the parent interval `[z_{k-1}, z_k]` of
//! `xi_s` with
//!
//! ```text
//! z_0 = -1,     z_k = z_{k-1} + 2 t_k / Σ_j t_j,
//! c_k = (z_{k-1} + z_k) / 2,     h_k = (z_k - z_{k-1}) / 2.
//! ```
//!
//! The in-plane rule is the element's full tensor Gauss rule in `(p, q)`:
//! `(a_i, b_j, w_i w_j)` with 2x2 points for H8, 3x3 for H20 / H27 and
//! 2x2 for the reduced H20r / H27r. Through ply `k`, `n_k` Gauss-Legendre
//! points `(g_l, v_l)` on `[-1, 1]` (1 to 5) are mapped into the ply's
//! interval. The points and weights of the element are
//!
//! ```text
//! xi_p = a_i,  xi_q = b_j,  xi_s = c_k + h_k g_l,     W = w_i w_j h_k v_l,
//! ```
//!
//! `Σ_k n_k` layers of in-plane points, and each point carries its ply's
//! material (already turned into the ply's axes): `C` at the point is that
//! material's (`elasticity_at` at the point's reference position when it
//! varies in space), so is the thermal expansion, and everything else is
//! the [`SolidElement`]'s: `K = Σ_Q W_Q det J_Q B_Q^T C_Q B_Q`, `f = Σ_Q W_Q
//! det J_Q B_Q^T sigma_Q`.
//!
//! A ply's `n_k`-point rule integrates polynomials in `xi_s` of degree
//! `2 n_k - 1` exactly on its interval, so for a uniform material the
//! layered rule integrates exactly what the plain rule does whenever the
//! integrand's degree in `xi_s` is within both rules' reach (e.g. the
//! stiffness of an undistorted H20 with 3 points per ply); with one ply of
//! the plain rule's count it *is* the plain rule. Abaqus uses Simpson's
//! rule through each ply (default 3 points); Junta uses Gauss-Legendre with
//! the count given (3 Gauss points integrate a cubic exactly, as do 3
//! Simpson points, and degree 5 besides).
//!
//! ## Outputs
//!
//! Those of [`SolidElement`] at every point, with `material_stress` in the
//! point's own ply axes ([`junta_core::Material::axes_at`] of its
//! material), and `ply`: the ply number, 1-based, bottom to top.

use crate::quadrature::gauss_legendre;
use crate::solid::{Integration, PointData, PointMaterial, SolidElement};
use junta_core::topology::CellShape;
use junta_core::{CoreError, Material};
use std::sync::Arc;

/// One ply of a layered element.
#[derive(Debug, Clone)]
pub struct Ply {
    /// Its material, already in the ply's axes.
    pub material: Arc<dyn Material>,
    /// Relative thickness (> 0; normalised over the plies).
    pub thickness: f64,
    /// Gauss points through the ply (1 to 5).
    pub points: usize,
}

fn invalid(shape: CellShape, message: String) -> CoreError {
    CoreError::InvalidParameters {
        kind: "element",
        key: shape.name().into(),
        message,
    }
}

impl SolidElement {
    /// A hexahedron (Hex8, Hex20, Hex27) integrated ply by ply along the
    /// natural direction `stack` (0, 1, 2 for `xi_1, xi_2, xi_3`), plies
    /// bottom to top (module docs). `integration`: the in-plane rule (full,
    /// or reduced for Hex20 / Hex27). Errors for other shapes, no ply, a
    /// thickness that is not positive and finite, or a point count outside
    /// 1..=5.
    pub fn layered(
        shape: CellShape,
        integration: Integration,
        stack: usize,
        plies: &[Ply],
    ) -> Result<Self, CoreError> {
        let n1 = match (shape, integration) {
            (CellShape::Hex8, Integration::Full) => 2,
            (CellShape::Hex20 | CellShape::Hex27, Integration::Full) => 3,
            (CellShape::Hex20 | CellShape::Hex27, Integration::Reduced) => 2,
            (CellShape::Hex8, Integration::Reduced) => {
                return Err(invalid(shape, "a layered hex8 has no reduced rule".into()))
            }
            (s, _) => {
                return Err(invalid(
                    s,
                    format!(
                    "layered (composite) integration is for hexahedra (hex8, hex20, hex27), not {}",
                    s.name()
                ),
                ))
            }
        };
        if stack > 2 {
            return Err(invalid(
                shape,
                format!("stack direction {} is not 1, 2 or 3", stack + 1),
            ));
        }
        let first = plies
            .first()
            .ok_or_else(|| invalid(shape, "a layered element needs at least one ply".into()))?;
        let mut total = 0.0;
        for (k, p) in plies.iter().enumerate() {
            if !(p.thickness.is_finite() && p.thickness > 0.0) {
                return Err(invalid(
                    shape,
                    format!("ply {}: thickness {} must be positive", k + 1, p.thickness),
                ));
            }
            total += p.thickness;
        }
        let plane = gauss_legendre(n1).expect("2 and 3 point rules exist");
        let mut el = SolidElement::new(shape, integration, first.material.clone())?;
        let (ip, iq) = match stack {
            0 => (1, 2),
            1 => (0, 2),
            _ => (0, 1),
        };
        let mut points = Vec::new();
        let mut z0 = -1.0;
        for (k, ply) in plies.iter().enumerate() {
            let through = gauss_legendre(ply.points)
                .map_err(|e| invalid(shape, format!("ply {}: {e}", k + 1)))?;
            let z1 = if k + 1 == plies.len() {
                1.0
            } else {
                z0 + 2.0 * ply.thickness / total
            };
            let (c, h) = (0.5 * (z0 + z1), 0.5 * (z1 - z0));
            for (&g, &v) in through.points.iter().zip(through.weights) {
                for (&a, &wa) in plane.points.iter().zip(plane.weights) {
                    for (&b, &wb) in plane.points.iter().zip(plane.weights) {
                        let mut xi = [0.0; 3];
                        xi[ip] = a;
                        xi[iq] = b;
                        xi[stack] = c + h * g;
                        let mut p = PointData::new(shape, xi, wa * wb * h * v);
                        p.ply = k;
                        points.push(p);
                    }
                }
            }
            z0 = z1;
        }
        el.points = points;
        el.plies = plies
            .iter()
            .map(|p| PointMaterial::new(p.material.clone()))
            .collect();
        el.layered = true;
        Ok(el)
    }

    /// The ply (0-based) of each integration point, in point order; all 0
    /// for an ordinary element.
    pub fn point_plies(&self) -> impl Iterator<Item = usize> + '_ {
        self.points.iter().map(|p| p.ply)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::{EngineeringConstants, Orthotropic, Rotated};
    use junta_core::element::{Element, ElementContext};
    use junta_core::topology::HEX27_NODES;
    use junta_core::StepInfo;
    use nalgebra::{DMatrix, Matrix3, Rotation3, Vector3};

    fn ply_material(angle_deg: f64) -> Arc<dyn Material> {
        let c = EngineeringConstants {
            e1: 181e3,
            e2: 10.3e3,
            e3: 10.3e3,
            nu12: 0.28,
            nu13: 0.28,
            nu23: 0.4,
            g12: 7.17e3,
            g13: 7.17e3,
            g23: 3.68e3,
        };
        let inner: Arc<dyn Material> = Arc::new(Orthotropic::new(c, None).unwrap());
        let q = Rotation3::from_axis_angle(&Vector3::z_axis(), angle_deg.to_radians()).into_inner();
        Arc::new(Rotated::new(inner, q))
    }

    /// Nodes of a hexahedron: the reference cell mapped by `x = A xi + d`
    /// (affine, an undistorted parallelepiped) plus, if `wobble`, a
    /// non-affine perturbation.
    fn coords(shape: CellShape, wobble: bool) -> Vec<[f64; 3]> {
        let a = Matrix3::new(2.0, 0.3, 0.1, -0.2, 1.5, 0.2, 0.05, 0.1, 0.4);
        HEX27_NODES[..shape.num_nodes()]
            .iter()
            .map(|xi| {
                let v = a * Vector3::from(*xi) + Vector3::new(1.0, -2.0, 0.5);
                let w = if wobble {
                    0.05 * Vector3::new(xi[0] * xi[1], xi[1] * xi[2], xi[0] * xi[2] * xi[1])
                } else {
                    Vector3::zeros()
                };
                (v + w).into()
            })
            .collect()
    }

    fn ctx<'a>(coords: &'a [[f64; 3]], disp: &'a [f64]) -> ElementContext<'a> {
        ElementContext {
            coords,
            disp,
            state_committed: &[],
            step: StepInfo::default(),
            law_responses: None,
            temperature: None,
        }
    }

    fn stiffness(el: &SolidElement, x: &[[f64; 3]]) -> DMatrix<f64> {
        let ndof = 3 * x.len();
        let disp = vec![0.0; ndof];
        let c = ctx(x, &disp);
        let mut f = vec![0.0; ndof];
        let mut k = vec![0.0; ndof * ndof];
        el.compute(&c, &mut [], &mut f, Some(&mut k)).unwrap();
        DMatrix::from_row_slice(ndof, ndof, &k)
    }

    fn rel(a: &DMatrix<f64>, b: &DMatrix<f64>) -> f64 {
        (a - b).norm() / b.norm()
    }

    #[test]
    fn one_ply_is_the_plain_element() {
        let m = ply_material(30.0);
        for (shape, int) in [
            (CellShape::Hex20, Integration::Full),
            (CellShape::Hex20, Integration::Reduced),
            (CellShape::Hex8, Integration::Full),
            (CellShape::Hex27, Integration::Full),
        ] {
            let n = if int == Integration::Full && shape != CellShape::Hex8 {
                3
            } else {
                2
            };
            let plain = SolidElement::new(shape, int, m.clone()).unwrap();
            let ply = Ply {
                material: m.clone(),
                thickness: 0.7,
                points: n,
            };
            let lay = SolidElement::layered(shape, int, 2, &[ply]).unwrap();
            assert_eq!(lay.num_points(), plain.num_points());
            let x = coords(shape, true);
            let e = rel(&stiffness(&lay, &x), &stiffness(&plain, &x));
            assert!(e < 1e-12, "{shape:?} {int:?}: {e}");
        }
    }

    #[test]
    fn two_plies_of_one_material_are_the_plain_element() {
        let m = ply_material(-20.0);
        for stack in 0..3 {
            let plies: Vec<Ply> = [0.3, 0.5]
                .iter()
                .map(|&t| Ply {
                    material: m.clone(),
                    thickness: t,
                    points: 3,
                })
                .collect();
            let lay =
                SolidElement::layered(CellShape::Hex20, Integration::Full, stack, &plies).unwrap();
            assert_eq!(lay.num_points(), 54);
            let plain = SolidElement::new(CellShape::Hex20, Integration::Full, m.clone()).unwrap();
            // undistorted: B^T C B is of degree 4 in each coordinate, which
            // 3 Gauss points integrate exactly on any interval
            let x = coords(CellShape::Hex20, false);
            let e = rel(&stiffness(&lay, &x), &stiffness(&plain, &x));
            assert!(e < 1e-12, "stack {stack}: {e}");
        }
    }

    #[test]
    fn weights_sum_to_the_cell_and_plies_are_in_order() {
        let plies: Vec<Ply> = [(1.0, 2), (2.0, 3), (1.0, 1)]
            .iter()
            .map(|&(t, n)| Ply {
                material: ply_material(0.0),
                thickness: t,
                points: n,
            })
            .collect();
        let el = SolidElement::layered(CellShape::Hex8, Integration::Full, 2, &plies).unwrap();
        assert_eq!(el.num_points(), 4 * 6);
        let w: f64 = el.points().map(|(_, w)| w).sum();
        assert!((w - 8.0).abs() < 1e-14);
        let plies: Vec<usize> = el.point_plies().collect();
        for (q, (xi, _)) in el.points().enumerate() {
            let (lo, hi) = [(-1.0, -0.5), (-0.5, 0.5), (0.5, 1.0)][plies[q]];
            assert!(xi[2] > lo && xi[2] < hi);
        }
    }

    #[test]
    fn rigid_body_modes_give_no_force() {
        let plies: Vec<Ply> = [0.0, 45.0, -45.0, 90.0]
            .iter()
            .map(|&a| Ply {
                material: ply_material(a),
                thickness: 1.0,
                points: 3,
            })
            .collect();
        let el = SolidElement::layered(CellShape::Hex20, Integration::Full, 2, &plies).unwrap();
        let x = coords(CellShape::Hex20, true);
        let k = stiffness(&el, &x);
        let scale = k.norm();
        for mode in 0..6 {
            let u: Vec<f64> = x
                .iter()
                .flat_map(|p| {
                    let v = if mode < 3 {
                        let mut t = [0.0; 3];
                        t[mode] = 1.0;
                        Vector3::from(t)
                    } else {
                        let mut a = Vector3::zeros();
                        a[mode - 3] = 1.0;
                        a.cross(&Vector3::from(*p))
                    };
                    [v[0], v[1], v[2]]
                })
                .collect();
            let f = &k * nalgebra::DVector::from_vec(u.clone());
            assert!(f.norm() < 1e-10 * scale, "mode {mode}: {}", f.norm());
            // and through compute's internal force
            let c = ctx(&x, &u);
            let mut fi = vec![0.0; 60];
            el.compute(&c, &mut [], &mut fi, None).unwrap();
            assert!(fi.iter().map(|v| v * v).sum::<f64>().sqrt() < 1e-10 * scale);
        }
    }

    #[test]
    fn outputs_carry_the_ply_and_its_axes() {
        let plies: Vec<Ply> = [0.0, 90.0]
            .iter()
            .map(|&a| Ply {
                material: ply_material(a),
                thickness: 1.0,
                points: 2,
            })
            .collect();
        let el = SolidElement::layered(CellShape::Hex8, Integration::Full, 2, &plies).unwrap();
        let x: Vec<[f64; 3]> = HEX27_NODES[..8].to_vec();
        // uniform strain eps_xx = 1e-3
        let u: Vec<f64> = x.iter().flat_map(|p| [1e-3 * p[0], 0.0, 0.0]).collect();
        let out = el.point_outputs(&ctx(&x, &u)).unwrap();
        assert_eq!(out.len(), 16);
        for p in &out {
            let get = |n: &str| &p.values.iter().find(|(k, _)| *k == n).unwrap().1;
            let ply = get("ply")[0];
            let ms = get("material_stress");
            let s = get("stress");
            if ply == 1.0 {
                assert!((ms[0] - s[0]).abs() < 1e-9 * s[0].abs());
            } else {
                assert_eq!(ply, 2.0);
                // 90 degrees: axis 1 along y
                assert!((ms[1] - s[0]).abs() < 1e-9 * s[0].abs());
            }
        }
    }

    #[test]
    fn refusals() {
        let ply = Ply {
            material: ply_material(0.0),
            thickness: 1.0,
            points: 3,
        };
        let bad = |shape, t: f64, n: usize| {
            SolidElement::layered(
                shape,
                Integration::Full,
                2,
                &[Ply {
                    thickness: t,
                    points: n,
                    ..ply.clone()
                }],
            )
            .is_err()
        };
        assert!(bad(CellShape::Wedge15, 1.0, 3));
        assert!(bad(CellShape::Hex20, 0.0, 3));
        assert!(bad(CellShape::Hex20, -1.0, 3));
        assert!(bad(CellShape::Hex20, 1.0, 0));
        assert!(bad(CellShape::Hex20, 1.0, 6));
        assert!(!bad(CellShape::Hex20, 1.0, 3));
        assert!(SolidElement::layered(CellShape::Hex20, Integration::Full, 2, &[]).is_err());
    }
}
