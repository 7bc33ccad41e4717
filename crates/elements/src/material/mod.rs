//! Linear elastic solid materials implementing [`junta_core::Material`].
//!
//! * [`isotropic`]: key `isotropic`, parameters `E`, `nu`.
//! * [`orthotropic`]: key `orthotropic`, engineering constants
//!   `E1, E2, E3, nu12, nu13, nu23, G12, G13, G23` and an optional material
//!   orientation given by two vectors `a`, `b` (as Abaqus `*ORIENTATION`),
//!   rectangular or (`system = "cylindrical"`) cylindrical, whose axes
//!   vary with the point ([`Axes`]).
//! * [`anisotropic`]: key `anisotropic`, the 21 stiffness constants `D` in
//!   the Abaqus `TYPE=ANISO` order and the same optional orientation.
//! * [`rotated`]: any of them turned into a ply's axes by a fixed rotation
//!   (built by the lay-up builder, not registered).
//!
//! Voigt order everywhere: `[xx, yy, zz, xy, yz, zx]`, engineering shear
//! strains `gamma_ij = 2 eps_ij`, so that `sigma = C eps` and the strain
//! energy density is `sigma . eps / 2`.
//!
//! ## Rotating a Voigt elasticity matrix
//!
//! Let `Q` be the orthogonal matrix whose columns are the material axes
//! `e_1, e_2, e_3` in global components, so that a tensor transforms as
//! `sigma_g = Q sigma_l Q^T`. In Voigt form `sigma_g = T sigma_l` with, for
//! the Voigt index pairs `p = (i, j)` and `q = (k, l)`,
//!
//! ```text
//! T[p][q] = Q_ik Q_jl                 if k == l
//! T[p][q] = Q_ik Q_jl + Q_il Q_jk     if k != l   (sigma_kl = sigma_lk)
//! ```
//!
//! Work conjugacy (`sigma_g . eps_g = sigma_l . eps_l` for engineering
//! strains) gives `eps_l = T^T eps_g`, hence
//!
//! ```text
//! C_g = T C_l T^T.
//! ```
//!
//! The engineering-shear factors of 2 are carried by `T^T` acting on
//! engineering strains; no separate Reuter matrix is needed.

pub mod anisotropic;
pub mod isotropic;
pub mod orthotropic;
pub mod rotated;

pub use anisotropic::Anisotropic;
pub use isotropic::Isotropic;
pub use orthotropic::{Axes, EngineeringConstants, Orientation, Orthotropic, System};
pub use rotated::{InPlaneReference, Rotated, StackingNormal};

use junta_core::Voigt6;
use nalgebra::Matrix3;

/// Voigt index pairs in Junta's order `[xx, yy, zz, xy, yz, zx]`.
pub const VOIGT_PAIRS: [(usize, usize); 6] = [(0, 0), (1, 1), (2, 2), (0, 1), (1, 2), (2, 0)];

/// The 6x6 stress transformation `T` of a rotation `Q` (columns = local
/// axes in global components): `sigma_g = T sigma_l`, `eps_l = T^T eps_g`,
/// `C_g = T C_l T^T` (see the module docs).
pub fn stress_rotation(q: &Matrix3<f64>) -> Voigt6 {
    let mut t = Voigt6::zeros();
    for (p, &(i, j)) in VOIGT_PAIRS.iter().enumerate() {
        for (c, &(k, l)) in VOIGT_PAIRS.iter().enumerate() {
            t[(p, c)] = if k == l {
                q[(i, k)] * q[(j, l)]
            } else {
                q[(i, k)] * q[(j, l)] + q[(i, l)] * q[(j, k)]
            };
        }
    }
    t
}

/// `C_g = T C_l T^T` for the rotation `q` (columns = local axes).
pub fn rotate_elasticity(c_local: &Voigt6, q: &Matrix3<f64>) -> Voigt6 {
    let t = stress_rotation(q);
    t * c_local * t.transpose()
}

/// [`rotate_elasticity`] with the round-off asymmetry removed: `C_g` is
/// symmetric to the last bit.
#[inline]
pub fn rotate_symmetric(c_local: &Voigt6, q: &Matrix3<f64>) -> Voigt6 {
    let c = rotate_elasticity(c_local, q);
    0.5 * (c + c.transpose())
}

/// Moduli accepted by the materials: wide enough for any unit system (Pa to
/// GPa, psi to Msi, soft gels to diamond), narrow enough that the element
/// stiffness (modulus x length, squared in the factorisation) stays far
/// from overflow and underflow.
pub const MODULUS_RANGE: (f64, f64) = (1e-20, 1e20);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stress_rotation_matches_tensor_rotation() {
        let q = nalgebra::Rotation3::from_euler_angles(0.3, -0.7, 1.1).into_inner();
        let sl = Matrix3::new(1.0, 0.4, -0.2, 0.4, -2.0, 0.7, -0.2, 0.7, 0.5);
        let sg = q * sl * q.transpose();
        let v = |m: &Matrix3<f64>| {
            nalgebra::Vector6::from_iterator(VOIGT_PAIRS.iter().map(|&(i, j)| m[(i, j)]))
        };
        let t = stress_rotation(&q);
        assert!((t * v(&sl) - v(&sg)).norm() < 1e-14);
        // strains with engineering shear: eps_l = T^T eps_g
        let e = |m: &Matrix3<f64>| {
            nalgebra::Vector6::from_iterator(VOIGT_PAIRS.iter().map(|&(i, j)| {
                if i == j {
                    m[(i, j)]
                } else {
                    2.0 * m[(i, j)]
                }
            }))
        };
        assert!((t.transpose() * e(&sg) - e(&sl)).norm() < 1e-14);
    }
}
