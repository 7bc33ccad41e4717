//! A material turned into a ply's axes: any [`Material`] rotated by a
//! fixed rotation `Q` (the lay-up builder's plies).
//!
//! ## Maths
//!
//! Let `C_i(x)` be the inner material's elasticity in the global frame
//! (its own orientation, if any, already applied) and `Q` the rotation
//! whose columns are the rotated frame's axes in global components. The
//! rotated material is the inner one carried along by `Q`:
//!
//! ```text
//! C(x) = T(Q) C_i(Q^T x) T(Q)^T,       alpha(x) = Q alpha_i(Q^T x) Q^T,
//! ```
//!
//! with `T` the Voigt stress transformation of [`super::stress_rotation`]
//! and `alpha` the thermal expansion as a symmetric tensor. For a ply of
//! angle `theta` about the stacking direction `e_3` (positive from `x`
//! towards `y` when `e_3 = z`)
//!
//! ```text
//!     | cos theta  -sin theta  0 |
//! Q = | sin theta   cos theta  0 |
//!     | 0           0          1 |
//! ```
//!
//! so an orthotropic material without its own orientation gets its fibre
//! axis 1 along `(cos theta, sin theta, 0)`. The inner material's point
//! `Q^T x` matters only for materials whose axes vary in space (a
//! cylindrical system); the lay-up builder rotates about an axis through
//! the origin, so such a material should be given in the ply's own frame.

use super::stress_rotation;
use junta_core::{Material, Voigt6};
use nalgebra::{Matrix3, Vector3};
use std::sync::Arc;

/// `inner` rotated by `q` (see the module docs).
#[derive(Debug, Clone)]
pub struct Rotated {
    inner: Arc<dyn Material>,
    /// Columns: the rotated frame's axes in global components.
    q: Matrix3<f64>,
    /// `T(q)`.
    t: Voigt6,
    /// `C` when the inner material is the same everywhere.
    c: Voigt6,
}

impl Rotated {
    /// `inner` rotated by the orthogonal matrix `q` (columns: the new axes
    /// in global components).
    pub fn new(inner: Arc<dyn Material>, q: Matrix3<f64>) -> Self {
        let t = stress_rotation(&q);
        let c = symmetric(t * inner.elasticity() * t.transpose());
        Rotated { inner, q, t, c }
    }

    /// `inner` turned by `angle_deg` degrees about the unit axis `axis`
    /// (right-hand rule): a ply's angle about its stacking direction.
    pub fn about_axis(inner: Arc<dyn Material>, axis: [f64; 3], angle_deg: f64) -> Self {
        let axis = nalgebra::Unit::new_normalize(Vector3::from(axis));
        let q = nalgebra::Rotation3::from_axis_angle(&axis, angle_deg.to_radians()).into_inner();
        Rotated::new(inner, q)
    }

    /// The rotation: columns are the rotated frame's axes in global
    /// components (for a ply: fibre direction, in-plane transverse,
    /// stacking direction, when the inner material has no orientation).
    pub fn rotation(&self) -> &Matrix3<f64> {
        &self.q
    }

    /// The material before the rotation.
    pub fn inner(&self) -> &Arc<dyn Material> {
        &self.inner
    }

    fn inner_point(&self, x: [f64; 3]) -> [f64; 3] {
        (self.q.transpose() * Vector3::from(x)).into()
    }
}

fn symmetric(c: Voigt6) -> Voigt6 {
    0.5 * (c + c.transpose())
}

impl Material for Rotated {
    fn key(&self) -> &'static str {
        self.inner.key()
    }
    fn elasticity(&self) -> Voigt6 {
        self.c
    }
    fn varies_in_space(&self) -> bool {
        self.inner.varies_in_space()
    }
    fn elasticity_at(&self, x: [f64; 3]) -> Voigt6 {
        if !self.inner.varies_in_space() {
            return self.c;
        }
        let ci = self.inner.elasticity_at(self.inner_point(x));
        symmetric(self.t * ci * self.t.transpose())
    }
    /// `Q Q_i(Q^T x)`: the inner material's axes carried along (the
    /// rotation itself for an inner material without axes).
    fn axes_at(&self, x: [f64; 3]) -> Option<Matrix3<f64>> {
        let inner = self.inner.axes_at(self.inner_point(x));
        Some(inner.map_or(self.q, |qi| self.q * qi))
    }
    fn reference_modulus(&self) -> f64 {
        self.inner.reference_modulus()
    }
    fn has_thermal_expansion(&self) -> bool {
        self.inner.has_thermal_expansion()
    }
    fn thermal_expansion_at(&self, x: [f64; 3]) -> [f64; 6] {
        let a = self.inner.thermal_expansion_at(self.inner_point(x));
        // engineering shear components back to the tensor, then rotated
        let g = Matrix3::new(
            a[0],
            0.5 * a[3],
            0.5 * a[5],
            0.5 * a[3],
            a[1],
            0.5 * a[4],
            0.5 * a[5],
            0.5 * a[4],
            a[2],
        );
        crate::thermal::rotate_expansion(&g, &self.q)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::{EngineeringConstants, Orientation, Orthotropic};

    fn ply(a: Option<[f64; 3]>) -> Orthotropic {
        let k = EngineeringConstants {
            e1: 140e3,
            e2: 10e3,
            e3: 10e3,
            nu12: 0.3,
            nu13: 0.3,
            nu23: 0.45,
            g12: 5e3,
            g13: 5e3,
            g23: 3.4e3,
        };
        match a {
            None => Orthotropic::new(k, None).unwrap(),
            Some(a) => {
                Orthotropic::new(k, Some(Orientation::rectangular(a, [-a[1], a[0], 0.0]))).unwrap()
            }
        }
    }

    /// Turning an unoriented ply by theta about z is the ply whose axis 1
    /// is (cos theta, sin theta, 0): the orthotropic material's own
    /// orientation path, written independently.
    #[test]
    fn angle_about_z_equals_the_oriented_ply() {
        for theta in [0.0f64, 30.0, 45.0, -45.0, 90.0, 137.0] {
            let r = Rotated::about_axis(Arc::new(ply(None)), [0.0, 0.0, 1.0], theta);
            let (s, c) = theta.to_radians().sin_cos();
            let o = ply(Some([c, s, 0.0]));
            let d = (r.elasticity() - o.elasticity()).abs().max();
            assert!(d < 1e-9 * 140e3, "theta {theta}: {d}");
        }
    }

    #[test]
    fn expansion_turns_with_the_ply() {
        let m = Orthotropic::from_table(
            &toml::from_str(
                "E1 = 140e3\nE2 = 10e3\nE3 = 10e3\nnu12 = 0.3\nnu13 = 0.3\nnu23 = 0.45\nG12 = 5e3\nG13 = 5e3\nG23 = 3.4e3\nalpha1 = -1e-6\nalpha2 = 3e-5\nalpha3 = 3e-5",
            )
            .unwrap(),
        )
        .unwrap();
        let r = Rotated::about_axis(Arc::new(m), [0.0, 0.0, 1.0], 90.0);
        let a = r.thermal_expansion_at([0.0; 3]);
        // axis 1 along y: alpha_yy = alpha1, alpha_xx = alpha2
        assert!((a[1] + 1e-6).abs() < 1e-15 && (a[0] - 3e-5).abs() < 1e-15);
        assert!(a[3].abs() < 1e-15);
        let r45 = Rotated::about_axis(r.inner().clone(), [0.0, 0.0, 1.0], 45.0);
        let a = r45.thermal_expansion_at([0.0; 3]);
        // engineering shear 2 alpha_xy = (alpha1 - alpha2) sin(2 theta)
        assert!((a[3] - (-1e-6 - 3e-5)).abs() < 1e-15, "{a:?}");
    }
}
