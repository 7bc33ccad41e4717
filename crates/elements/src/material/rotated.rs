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
//!
//! ## A ply on a curved part
//!
//! [`Rotated::in_cylinder`]: the ply's frame turns with the point. With
//! `c` a point of the cylinder's axis and `a` its unit direction, at `x`
//!
//! ```text
//! e3 = radial unit vector of x - c (normal to a),   e2 = a,   e1 = e2 x e3,
//! Q(x) = [e1 e2 e3] R_3(theta)
//! ```
//!
//! (`R_3(theta)` the ply angle about `e3`): on a bend of a laminate whose
//! plies stack radially, `e1` is the tangent of the bend (the 0-degree
//! fibre), `e2` the axis and `e3` the stacking direction. `C(x) = T(Q(x))
//! C_i T(Q(x))^T` with `C_i` the inner material's (uniform) elasticity.
//!
//! ## A ply on any surface
//!
//! [`Rotated::on_surface`]: `e3 = n(x)`, the stacking direction at the
//! point from a [`StackingNormal`] field (the lay-up builder's extrusion
//! of a Gmsh surface), and the in-plane axes from a fixed reference
//! direction `r` projected onto the plane normal to `e3`
//! ([`InPlaneReference`]):
//!
//! ```text
//! Fibre(r):       e1 = (r - (r.e3) e3) / |.|,   e2 = e3 x e1,
//! Transverse(r):  e2 = (r - (r.e3) e3) / |.|,   e1 = e2 x e3,
//! Q(x) = [e1 e2 e3] R_3(theta)
//! ```
//!
//! (Abaqus' composite lay-up projects a reference axis 1 the same way).
//! On a cylinder about `a`, `Transverse(a)` is the frame of
//! [`Rotated::in_cylinder`]; on a plane `z = const` facing `+z`,
//! `Fibre(e_x)` is `R_3(theta)`.

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
    /// `C` when the inner material is the same everywhere and the frame fixed.
    c: Voigt6,
    /// The frame of a curved ply, when it turns with the point.
    frame: Option<Frame>,
}

/// The stacking direction of a curved ply at a point (module docs).
pub trait StackingNormal: Send + Sync + std::fmt::Debug {
    /// The unit normal `e3` at `x`.
    fn normal_at(&self, x: [f64; 3]) -> [f64; 3];
}

/// How the in-plane axes of a ply on a surface are fixed (module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum InPlaneReference {
    /// The 0-degree fibre `e1` is this direction projected on the surface.
    Fibre([f64; 3]),
    /// The in-plane transverse axis `e2` is this direction projected on
    /// the surface (a cylinder's axis).
    Transverse([f64; 3]),
}

impl InPlaneReference {
    /// `[e1 e2 e3]` about the unit normal `e3`; `None` when the reference
    /// is (nearly) along `e3`: its projection shorter than `min_length`.
    pub fn frame(&self, e3: Vector3<f64>, min_length: f64) -> Option<Matrix3<f64>> {
        let (r, fibre) = match *self {
            InPlaneReference::Fibre(r) => (Vector3::from(r), true),
            InPlaneReference::Transverse(r) => (Vector3::from(r), false),
        };
        let r = r.try_normalize(f64::MIN_POSITIVE)?;
        let p = (r - r.dot(&e3) * e3).try_normalize(min_length)?;
        let (e1, e2) = if fibre {
            (p, e3.cross(&p))
        } else {
            (p.cross(&e3), p)
        };
        Some(Matrix3::from_columns(&[e1, e2, e3]))
    }
}

/// A frame that turns with the point.
#[derive(Debug, Clone)]
enum Frame {
    Cylinder(Cylinder),
    Surface {
        normals: Arc<dyn StackingNormal>,
        reference: InPlaneReference,
        turn: Matrix3<f64>,
    },
}

impl Frame {
    fn q_at(&self, x: [f64; 3]) -> Matrix3<f64> {
        match self {
            Frame::Cylinder(c) => c.q_at(x),
            Frame::Surface {
                normals,
                reference,
                turn,
            } => {
                let e3 = Vector3::from(normals.normal_at(x));
                // a reference along the normal: any frame about it
                let q = reference
                    .frame(e3, 1e-9)
                    .or_else(|| InPlaneReference::Fibre([1.0, 0.0, 0.0]).frame(e3, 1e-3))
                    .or_else(|| InPlaneReference::Fibre([0.0, 1.0, 0.0]).frame(e3, 1e-3))
                    .unwrap_or_else(Matrix3::identity);
                q * turn
            }
        }
    }
}

/// The axis of a curved ply's frame and the ply angle about its radius.
#[derive(Debug, Clone, Copy)]
struct Cylinder {
    centre: Vector3<f64>,
    axis: Vector3<f64>,
    /// `R_3(theta)`.
    turn: Matrix3<f64>,
}

impl Cylinder {
    /// `Q(x) = [e1 e2 e3] R_3(theta)` (module docs); on the axis the
    /// radial direction is undefined and the frame at the centre's
    /// perpendicular is used.
    fn q_at(&self, x: [f64; 3]) -> Matrix3<f64> {
        let d = Vector3::from(x) - self.centre;
        let r = d - d.dot(&self.axis) * self.axis;
        let e3 = if r.norm() > 1e-12 * d.norm().max(f64::MIN_POSITIVE) {
            r.normalize()
        } else {
            self.axis
                .cross(&Vector3::x())
                .try_normalize(1e-12)
                .unwrap_or(Vector3::z())
        };
        let e1 = self.axis.cross(&e3);
        Matrix3::from_columns(&[e1, self.axis, e3]) * self.turn
    }
}

impl Rotated {
    /// `inner` rotated by the orthogonal matrix `q` (columns: the new axes
    /// in global components).
    pub fn new(inner: Arc<dyn Material>, q: Matrix3<f64>) -> Self {
        let t = stress_rotation(&q);
        let c = symmetric(t * inner.elasticity() * t.transpose());
        Rotated {
            inner,
            q,
            t,
            c,
            frame: None,
        }
    }

    /// `inner` as a ply of angle `angle_deg` on a cylinder of axis through
    /// `centre` along `axis` (module docs: the frame turns with the point;
    /// the inner material's own axes, if any, are taken as uniform).
    pub fn in_cylinder(
        inner: Arc<dyn Material>,
        centre: [f64; 3],
        axis: [f64; 3],
        angle_deg: f64,
    ) -> Self {
        let turn = nalgebra::Rotation3::from_axis_angle(&Vector3::z_axis(), angle_deg.to_radians())
            .into_inner();
        let cylinder = Cylinder {
            centre: Vector3::from(centre),
            axis: Vector3::from(axis).normalize(),
            turn,
        };
        let mut r = Rotated::new(
            inner,
            cylinder.q_at([centre[0] + 1.0, centre[1], centre[2]]),
        );
        r.frame = Some(Frame::Cylinder(cylinder));
        r
    }

    /// `inner` as a ply of angle `angle_deg` on a surface whose stacking
    /// direction at a point is `normals`' (module docs: the frame turns
    /// with the point; the inner material's own axes, if any, are taken as
    /// uniform). `at` is a point of the ply, where [`Material::elasticity`]
    /// is evaluated.
    pub fn on_surface(
        inner: Arc<dyn Material>,
        normals: Arc<dyn StackingNormal>,
        reference: InPlaneReference,
        angle_deg: f64,
        at: [f64; 3],
    ) -> Self {
        let turn = nalgebra::Rotation3::from_axis_angle(&Vector3::z_axis(), angle_deg.to_radians())
            .into_inner();
        let frame = Frame::Surface {
            normals,
            reference,
            turn,
        };
        let mut r = Rotated::new(inner, frame.q_at(at));
        r.frame = Some(frame);
        r
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
        self.frame.is_some() || self.inner.varies_in_space()
    }
    fn elasticity_at(&self, x: [f64; 3]) -> Voigt6 {
        if let Some(cyl) = &self.frame {
            let t = stress_rotation(&cyl.q_at(x));
            return symmetric(t * self.inner.elasticity() * t.transpose());
        }
        if !self.inner.varies_in_space() {
            return self.c;
        }
        let ci = self.inner.elasticity_at(self.inner_point(x));
        symmetric(self.t * ci * self.t.transpose())
    }
    /// `Q Q_i(Q^T x)`: the inner material's axes carried along (the
    /// rotation itself for an inner material without axes).
    fn axes_at(&self, x: [f64; 3]) -> Option<Matrix3<f64>> {
        if let Some(cyl) = &self.frame {
            let inner = self.inner.axes_at(x);
            let q = cyl.q_at(x);
            return Some(inner.map_or(q, |qi| q * qi));
        }
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
        let (q, at) = match &self.frame {
            Some(cyl) => (cyl.q_at(x), x),
            None => (self.q, self.inner_point(x)),
        };
        let a = self.inner.thermal_expansion_at(at);
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
        crate::thermal::rotate_expansion(&g, &q)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::{EngineeringConstants, Orientation, Orthotropic};

    fn ply(a: Option<[f64; 3]>) -> Orthotropic {
        ply_axes(a.map(|a| (a, [-a[1], a[0], 0.0])))
    }

    /// The test ply with the orientation `a`, `b` (none: global axes).
    fn ply_axes(ab: Option<([f64; 3], [f64; 3])>) -> Orthotropic {
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
        Orthotropic::new(k, ab.map(|(a, b)| Orientation::rectangular(a, b))).unwrap()
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

    /// A 0-degree ply on a cylinder about z has its fibre along the hoop:
    /// at the point (0, 2, 0) the hoop is -x, so it is the ply turned by
    /// 180 degrees (the same fibre direction) about z, i.e. an orthotropic
    /// material with axis 1 along x in the x-y plane... and axis 3 along y.
    #[test]
    fn curved_ply_frame_turns_with_the_point() {
        let m: Arc<dyn Material> = Arc::new(ply(None));
        let r = Rotated::in_cylinder(m.clone(), [0.0; 3], [0.0, 0.0, 1.0], 0.0);
        assert!(r.varies_in_space());
        for (x, e1, e3) in [
            ([3.0, 0.0, 1.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0]),
            ([0.0, 2.0, -4.0], [-1.0, 0.0, 0.0], [0.0, 1.0, 0.0]),
        ] {
            let q = r.axes_at(x).unwrap();
            for k in 0..3 {
                assert!(
                    (q[(k, 0)] - e1[k]).abs() < 1e-14 && (q[(k, 2)] - e3[k]).abs() < 1e-14,
                    "{q}"
                );
            }
            // the same C as the rectangular orientation a = e1, b = e2 (= z)
            let o = ply_axes(Some((e1, [0.0, 0.0, 1.0])));
            let d = (r.elasticity_at(x) - o.elasticity()).abs().max();
            assert!(d < 1e-9 * 140e3, "{d}");
        }
    }

    /// The radius of a cylinder about z, as a stacking-normal field.
    #[derive(Debug)]
    struct Radial;
    impl StackingNormal for Radial {
        fn normal_at(&self, x: [f64; 3]) -> [f64; 3] {
            let r = x[0].hypot(x[1]);
            [x[0] / r, x[1] / r, 0.0]
        }
    }

    /// On the radial field of a cylinder, `Transverse(axis)` is the
    /// cylinder's own frame (`in_cylinder`), at every angle; `Fibre(e_x)`
    /// on a plane facing `+z` is the ply turned about `z`.
    #[test]
    fn surface_frame_is_the_cylinders_and_the_planes() {
        let m: Arc<dyn Material> = Arc::new(ply(None));
        for theta in [0.0, 30.0, -45.0, 90.0] {
            let cyl = Rotated::in_cylinder(m.clone(), [0.0; 3], [0.0, 0.0, 1.0], theta);
            let surf = Rotated::on_surface(
                m.clone(),
                Arc::new(Radial),
                InPlaneReference::Transverse([0.0, 0.0, 2.0]),
                theta,
                [1.0, 0.0, 0.0],
            );
            assert!(surf.varies_in_space());
            for x in [[3.0, 0.0, 1.0], [0.0, 2.0, -4.0], [-1.0, -2.5, 0.3]] {
                let d = (cyl.axes_at(x).unwrap() - surf.axes_at(x).unwrap())
                    .abs()
                    .max();
                assert!(d < 1e-14, "theta {theta} at {x:?}: {d}");
            }
        }
        #[derive(Debug)]
        struct Up;
        impl StackingNormal for Up {
            fn normal_at(&self, _: [f64; 3]) -> [f64; 3] {
                [0.0, 0.0, 1.0]
            }
        }
        let plane = Rotated::on_surface(
            m.clone(),
            Arc::new(Up),
            InPlaneReference::Fibre([1.0, 0.0, 0.0]),
            30.0,
            [0.0; 3],
        );
        let turned = Rotated::about_axis(m, [0.0, 0.0, 1.0], 30.0);
        let d = (plane.elasticity_at([5.0, 1.0, 2.0]) - turned.elasticity())
            .abs()
            .max();
        assert!(d < 1e-9 * 140e3, "{d}");
        // a reference along the normal has no projection
        assert!(InPlaneReference::Fibre([0.0, 0.0, 1.0])
            .frame(nalgebra::Vector3::z(), 1e-3)
            .is_none());
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
