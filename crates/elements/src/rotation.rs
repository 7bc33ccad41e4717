//! The rigid rotation of a solid element: the rotation factor of the polar
//! decomposition of the deformation gradient at the element's centre.
//! What `summary.json`'s `largest_rotation` reports, and what the
//! small-strain warning of the run API compares with its threshold.
//!
//! ## Maths
//!
//! At the element's centre (`xi = 0` for a hexahedron, `(1/3, 1/3, 0)` for
//! a wedge) the shape functions' natural derivatives `dN_a/dxi` give the
//! Jacobian `J = Σ_a x_a ⊗ dN_a/dxi` of the reference configuration, the
//! reference gradients `g_a = J^-T dN_a/dxi`, and the deformation gradient
//!
//! ```text
//! F = I + Σ_a u_a ⊗ g_a
//! ```
//!
//! (the nodal displacements only: `h8i`'s incompatible modes are left
//! out; they carry no rigid rotation). The polar decomposition
//! `F = R U` (`R` a rotation, `U` symmetric positive definite) exists for
//! `det F > 0`; `R` is the limit of Higham's Newton iteration (Higham
//! 1986, "Computing the polar decomposition with applications", SIAM J.
//! Sci. Stat. Comput. 7, eq. 3.1)
//!
//! ```text
//! X_0 = F,   X_{k+1} = (X_k + X_k^-T) / 2
//! ```
//!
//! which converges quadratically (a rigid rotation `F = R` is its fixed
//! point: `R^-T = R`). The angle of `R` about its axis, in `[0, pi]`, is
//!
//! ```text
//! theta = atan2(|w|, (tr R - 1) / 2),   w = (R_32 - R_23, R_13 - R_31, R_21 - R_12) / 2
//! ```
//!
//! (`|w| = sin theta`, `(tr R - 1) / 2 = cos theta`; the two together keep
//! every digit at small and at large angles).
//!
//! A small-strain displacement field is not a rotation: a rigid turn by
//! `phi` read linearly is `F = I + phi [n]x`, whose rotation factor turns
//! by `atan(phi)`. The measure is the same function of the displacements
//! under both kinematics, so a threshold measured on it (the run API's
//! `junta::rotation`) means the same thing in both.
//!
//! Everything is on the stack: no allocation per element.

use crate::shape::solid_shape;
use junta_core::topology::CellShape;
use nalgebra::{Matrix3, Vector3};

/// Most nodes of a solid element (H27).
const MAX_NODES: usize = 27;

/// The rotation factor `R` of the polar decomposition `F = R U`, or `None`
/// when `det F <= 0` (an inverted element) or `F` is not finite.
pub fn polar_rotation(f: &Matrix3<f64>) -> Option<Matrix3<f64>> {
    let det = f.determinant();
    if !det.is_finite() || det <= 0.0 {
        return None;
    }
    let mut x = *f;
    for _ in 0..100 {
        let inv_t = x.try_inverse()?.transpose();
        let next = 0.5 * (x + inv_t);
        let change = (next - x).norm();
        x = next;
        if change <= 4.0 * f64::EPSILON {
            break;
        }
    }
    Some(x)
}

/// The angle in `[0, pi]` of the rotation `r` about its axis (see the
/// module's maths).
pub fn rotation_angle(r: &Matrix3<f64>) -> f64 {
    let w = Vector3::new(
        r[(2, 1)] - r[(1, 2)],
        r[(0, 2)] - r[(2, 0)],
        r[(1, 0)] - r[(0, 1)],
    ) * 0.5;
    let cos = 0.5 * (r.trace() - 1.0);
    w.norm().atan2(cos)
}

/// The angle of the rotation factor of `F`, or `None` as
/// [`polar_rotation`].
pub fn deformation_rotation(f: &Matrix3<f64>) -> Option<f64> {
    polar_rotation(f).map(|r| rotation_angle(&r))
}

/// The natural coordinates of a solid's centre.
fn centre(shape: CellShape) -> [f64; 3] {
    match shape {
        CellShape::Wedge6 | CellShape::Wedge15 | CellShape::PlaneTri3 | CellShape::PlaneTri6 => {
            [1.0 / 3.0, 1.0 / 3.0, 0.0]
        }
        _ => [0.0; 3],
    }
}

/// The deformation gradient at the centre of a solid element of shape
/// `shape` with reference nodal coordinates `coords` and nodal
/// displacements `disp` (node-major, 3 per node). `None` when `shape` is
/// not a solid, the buffers do not match its node count, or the reference
/// Jacobian is singular.
pub fn centre_deformation_gradient(
    shape: CellShape,
    coords: &[[f64; 3]],
    disp: &[f64],
) -> Option<Matrix3<f64>> {
    if !shape.is_solid() {
        return None;
    }
    let nn = shape.num_nodes();
    if nn > MAX_NODES || coords.len() != nn || disp.len() != 3 * nn {
        return None;
    }
    let mut n = [0.0; MAX_NODES];
    let mut dn = [[0.0; 3]; MAX_NODES];
    let mut j = Matrix3::zeros();
    if shape.is_plane() {
        // a plane cell: the z column of J is e_z, F_zz = 1 (u_z is 0)
        let mut d2 = [[0.0; 2]; MAX_NODES];
        let c = centre(shape);
        crate::shape::surface_shape(shape, [c[0], c[1]], &mut n[..nn], &mut d2[..nn]);
        for (d, e) in dn.iter_mut().zip(&d2) {
            *d = [e[0], e[1], 0.0];
        }
        j[(2, 2)] = 1.0;
    } else {
        solid_shape(shape, centre(shape), &mut n[..nn], &mut dn[..nn]);
    }
    for (x, d) in coords.iter().zip(&dn[..nn]) {
        for r in 0..3 {
            for c in 0..3 {
                j[(r, c)] += x[r] * d[c];
            }
        }
    }
    let jinv_t = j.try_inverse()?.transpose();
    let mut f = Matrix3::identity();
    for (a, d) in dn[..nn].iter().enumerate() {
        let g = jinv_t * Vector3::from(*d);
        for i in 0..3 {
            let u = disp[3 * a + i];
            for k in 0..3 {
                f[(i, k)] += u * g[k];
            }
        }
    }
    Some(f)
}

/// The rigid rotation (radians, in `[0, pi]`) of a solid element: the
/// angle of the rotation factor of `F` at its centre. `None` for a
/// non-solid shape, mismatched buffers, a singular reference element or
/// an inverted one (`det F <= 0`).
pub fn element_rotation(shape: CellShape, coords: &[[f64; 3]], disp: &[f64]) -> Option<f64> {
    centre_deformation_gradient(shape, coords, disp).and_then(|f| deformation_rotation(&f))
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Rotation3;

    #[test]
    fn polar_factor_of_a_stretched_rotation() {
        let r = Rotation3::from_axis_angle(&Vector3::y_axis(), 1.1).into_inner();
        let u = Matrix3::new(1.3, 0.1, 0.0, 0.1, 0.9, 0.05, 0.0, 0.05, 1.1);
        let got = polar_rotation(&(r * u)).unwrap();
        assert!((got - r).norm() < 1e-13, "{got} {r}");
        assert!((rotation_angle(&got) - 1.1).abs() < 1e-13);
    }

    #[test]
    fn inverted_gradient_has_no_rotation() {
        let f = Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, -0.5));
        assert!(polar_rotation(&f).is_none());
        assert_eq!(deformation_rotation(&Matrix3::identity()), Some(0.0));
    }

    #[test]
    fn angle_near_pi_keeps_its_digits() {
        for t in [1e-9, 0.3, 3.0, std::f64::consts::PI - 1e-6] {
            let r = Rotation3::from_axis_angle(&Vector3::x_axis(), t).into_inner();
            assert!((rotation_angle(&r) - t).abs() < 1e-12, "{t}");
        }
    }
}
