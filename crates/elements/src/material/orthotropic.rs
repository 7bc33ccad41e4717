//! Orthotropic linear elasticity with a material orientation (key `orthotropic`).
//!
//! ## Engineering constants
//!
//! In the material axes (1, 2, 3), Voigt order `[11, 22, 33, 12, 23, 31]`
//! with engineering shear strains, the compliance `eps = S sigma` is
//!
//! ```text
//!     |  1/E1     -nu21/E2  -nu31/E3   0      0      0     |
//!     | -nu12/E1   1/E2     -nu32/E3   0      0      0     |
//! S = | -nu13/E1  -nu23/E2   1/E3      0      0      0     |
//!     |  0         0         0        1/G12   0      0     |
//!     |  0         0         0         0     1/G23   0     |
//!     |  0         0         0         0      0     1/G13  |
//! ```
//!
//! with the symmetry `nu_ji / E_j = nu_ij / E_i`, so only `nu12, nu13, nu23`
//! are given (Abaqus `*ELASTIC, TYPE=ENGINEERING CONSTANTS` convention:
//! `nu_ij` is the contraction along `j` under stress along `i`). The
//! stiffness in the material axes is `C_l = S^-1`. `S` (hence `C`) must be
//! positive definite: `E_i > 0`, `G_ij > 0`, `|nu_ij| < sqrt(E_i / E_j)` and
//! `1 - nu12 nu21 - nu23 nu32 - nu13 nu31 - 2 nu21 nu32 nu13 > 0`; this is
//! checked with a Cholesky factorisation of `S`.
//!
//! ## Orientation
//!
//! As Abaqus `*ORIENTATION, SYSTEM=RECTANGULAR` (`system = "rectangular"`,
//! the default): vector `a` gives material axis 1, vector `b` lies in the
//! 1-2 plane. Then
//!
//! ```text
//! e1 = a / |a|,   e3 = (a x b) / |a x b|,   e2 = e3 x e1,
//! ```
//!
//! `Q = [e1 e2 e3]` (columns) and `C = T C_l T^T` with the Voigt stress
//! transformation `T` of [`super::stress_rotation`]. Without `a`, `b` the
//! material axes are the global axes.
//!
//! `SYSTEM=CYLINDRICAL` (`system = "cylindrical"`): `a` and `b` are two
//! points of the cylinder axis and the axes depend on the point `x`
//! (CalculiX's `transformatrix`): axis 3 along the cylinder axis, axis 1
//! radial, axis 2 circumferential (r, theta, z),
//!
//! ```text
//! e3 = (b - a) / |b - a|,   r = (x - a) - ((x - a) . e3) e3,
//! e1 = r / |r|,             e2 = e3 x e1,
//! ```
//!
//! and `C(x) = T(x) C_l T(x)^T`, which the elements evaluate at each
//! integration point ([`junta_core::Material::elasticity_at`], as CalculiX
//! does at each Gauss point). On the axis (`|r| <= 1e-10 |x - a|`) `e1` is
//! CalculiX's fixed perpendicular to `e3`; [`Material::elasticity`] of a
//! cylindrical material is `C` in those on-axis axes.
//!
//! ## Thermal expansion
//!
//! `alpha1, alpha2, alpha3` (optional, default 0): expansion per unit
//! temperature along the material axes, rotated to the global frame as a
//! strain tensor at each integration point like the stiffness
//! ([`crate::thermal::rotate_expansion`]).
//!
//! TOML: `E1 = 135e9, E2 = 9e9, E3 = 9e9, nu12 = 0.3, nu13 = 0.3, nu23 = 0.45,
//! G12 = 5e9, G13 = 5e9, G23 = 3.1e9, a = [1, 1, 0], b = [-1, 1, 0]`
//! (add `system = "cylindrical"` for a cylindrical system).

use super::rotate_symmetric;
use junta_core::registry::{parse_params, MaterialEntry, ParamDoc};
use junta_core::{CoreError, Material, Voigt6};
use nalgebra::{Matrix3, Vector3};
use serde::Deserialize;
use std::sync::Arc;

/// The nine engineering constants of an orthotropic material (material axes).
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
pub struct EngineeringConstants {
    /// Young's modulus along material axis 1 (stress units, > 0).
    pub e1: f64,
    /// Young's modulus along material axis 2 (stress units, > 0).
    pub e2: f64,
    /// Young's modulus along material axis 3 (stress units, > 0).
    pub e3: f64,
    /// Poisson's ratio: contraction along 2 under stress along 1
    /// (`|nu12| < sqrt(E1 / E2)`).
    pub nu12: f64,
    /// Poisson's ratio: contraction along 3 under stress along 1
    /// (`|nu13| < sqrt(E1 / E3)`).
    pub nu13: f64,
    /// Poisson's ratio: contraction along 3 under stress along 2
    /// (`|nu23| < sqrt(E2 / E3)`).
    pub nu23: f64,
    /// Shear modulus in the 1-2 plane (stress units, > 0).
    pub g12: f64,
    /// Shear modulus in the 1-3 plane (stress units, > 0).
    pub g13: f64,
    /// Shear modulus in the 2-3 plane (stress units, > 0).
    pub g23: f64,
}

impl EngineeringConstants {
    /// The constants of an isotropic material (`G = E / (2 (1 + nu))`).
    pub fn isotropic(e: f64, nu: f64) -> Self {
        let g = e / (2.0 * (1.0 + nu));
        EngineeringConstants {
            e1: e,
            e2: e,
            e3: e,
            nu12: nu,
            nu13: nu,
            nu23: nu,
            g12: g,
            g13: g,
            g23: g,
        }
    }

    /// Compliance matrix `S` in the material axes (see the module docs).
    pub fn compliance(&self) -> Voigt6 {
        let mut s = Voigt6::zeros();
        s[(0, 0)] = 1.0 / self.e1;
        s[(1, 1)] = 1.0 / self.e2;
        s[(2, 2)] = 1.0 / self.e3;
        s[(0, 1)] = -self.nu12 / self.e1;
        s[(1, 0)] = s[(0, 1)];
        s[(0, 2)] = -self.nu13 / self.e1;
        s[(2, 0)] = s[(0, 2)];
        s[(1, 2)] = -self.nu23 / self.e2;
        s[(2, 1)] = s[(1, 2)];
        s[(3, 3)] = 1.0 / self.g12;
        s[(4, 4)] = 1.0 / self.g23;
        s[(5, 5)] = 1.0 / self.g13;
        s
    }
}

/// Coordinate system of an [`Orientation`] (`system` in the tables).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum System {
    /// Fixed axes: `a` along material axis 1, `b` in the 1-2 plane.
    #[default]
    Rectangular,
    /// Axes (r, theta, z) about the axis through the points `a` and `b`.
    Cylindrical,
}

/// A material orientation, as `*ORIENTATION`: for [`System::Rectangular`]
/// `a` along material axis 1 and `b` in the 1-2 plane; for
/// [`System::Cylindrical`] two points `a`, `b` of the cylinder axis (module
/// docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Orientation {
    /// Rectangular: a vector along material axis 1. Cylindrical: a point
    /// of the cylinder axis.
    pub a: [f64; 3],
    /// Rectangular: a vector in the material 1-2 plane (not parallel to
    /// `a`). Cylindrical: a second point of the axis (`b - a` gives axis 3).
    pub b: [f64; 3],
    /// How `a` and `b` are read.
    pub system: System,
}

impl Orientation {
    /// A rectangular system: `a` along material axis 1, `b` in the 1-2 plane.
    pub fn rectangular(a: [f64; 3], b: [f64; 3]) -> Self {
        Orientation {
            a,
            b,
            system: System::Rectangular,
        }
    }

    /// A cylindrical system about the axis through the points `a` and `b`.
    pub fn cylindrical(a: [f64; 3], b: [f64; 3]) -> Self {
        Orientation {
            a,
            b,
            system: System::Cylindrical,
        }
    }

    /// The material axes, or an error if the system is degenerate
    /// (rectangular: `a` zero or `b` parallel to `a`; cylindrical: `a == b`).
    pub fn axes(&self) -> Result<Axes, CoreError> {
        let a = Vector3::from(self.a);
        let b = Vector3::from(self.b);
        if !a.iter().chain(b.iter()).all(|x| x.is_finite()) {
            return Err(invalid(format!(
                "orientation vectors a = {:?}, b = {:?} must be finite",
                self.a, self.b
            )));
        }
        if self.system == System::Cylindrical {
            let d = b - a;
            if d.norm() <= 1e-12 * a.norm().max(b.norm()) || d.norm() == 0.0 {
                return Err(invalid(format!(
                    "cylindrical orientation: the axis points a = {:?} and b = {:?} must differ",
                    self.a, self.b
                )));
            }
            return Ok(Axes::Cylindrical {
                point: a,
                axis: d.normalize(),
            });
        }
        if a.norm() == 0.0 {
            return Err(invalid(format!(
                "orientation vector a = {:?} must be non-zero (it gives material axis 1)",
                self.a
            )));
        }
        let n = a.cross(&b);
        if n.norm() <= 1e-10 * a.norm() * b.norm() {
            return Err(invalid(format!(
                "orientation vector b = {:?} must not be parallel to a = {:?} \
                 (b lies in the material 1-2 plane)",
                self.b, self.a
            )));
        }
        let e1 = a.normalize();
        let e3 = n.normalize();
        let e2 = e3.cross(&e1);
        Ok(Axes::Fixed(Matrix3::from_columns(&[e1, e2, e3])))
    }
}

/// Material axes resolved from an [`Orientation`]: fixed, or a function of
/// the point (cylindrical).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Axes {
    /// `Q = [e1 e2 e3]` (columns: material axes in global components).
    Fixed(Matrix3<f64>),
    /// Cylindrical: a point of the axis and the unit axis direction `e3`.
    Cylindrical {
        /// A point of the cylinder axis (the orientation's `a`).
        point: Vector3<f64>,
        /// Unit direction of the axis, material axis 3.
        axis: Vector3<f64>,
    },
}

impl Axes {
    /// `Q = [e1 e2 e3]` at the point `x` (module docs; no allocation).
    #[inline]
    pub fn at(&self, x: [f64; 3]) -> Matrix3<f64> {
        match *self {
            Axes::Fixed(q) => q,
            Axes::Cylindrical { point, axis } => {
                let d = Vector3::from(x) - point;
                let r = d - d.dot(&axis) * axis;
                let e1 = if r.norm() <= 1e-10 * d.norm().max(f64::MIN_POSITIVE) {
                    Self::perpendicular(&axis)
                } else {
                    r.normalize()
                };
                Matrix3::from_columns(&[e1, axis.cross(&e1), axis])
            }
        }
    }

    /// The axes where [`Material::elasticity`] is taken: the fixed ones, or
    /// for a cylindrical system those on its axis.
    pub fn reference(&self) -> Matrix3<f64> {
        match *self {
            Axes::Fixed(q) => q,
            Axes::Cylindrical { axis, .. } => {
                let e1 = Self::perpendicular(&axis);
                Matrix3::from_columns(&[e1, axis.cross(&e1), axis])
            }
        }
    }

    /// Whether the axes depend on the point.
    pub fn varies(&self) -> bool {
        matches!(self, Axes::Cylindrical { .. })
    }

    /// CalculiX's unit vector perpendicular to `e3` for points on the axis.
    fn perpendicular(e3: &Vector3<f64>) -> Vector3<f64> {
        let v = if e3[0].abs() > 1e-10 {
            Vector3::new(-e3[1] / e3[0], 1.0, 0.0)
        } else if e3[1].abs() > 1e-10 {
            Vector3::new(0.0, -e3[2] / e3[1], 1.0)
        } else {
            Vector3::new(1.0, 0.0, -e3[0] / e3[2])
        };
        v.normalize()
    }
}

/// `System` and the vectors `a`, `b` of a material table as an orientation
/// (both vectors or neither; `system` only with them).
pub(super) fn orientation_of(
    a: Option<[f64; 3]>,
    b: Option<[f64; 3]>,
    system: Option<System>,
) -> Result<Option<Orientation>, String> {
    match (a, b) {
        (Some(a), Some(b)) => Ok(Some(Orientation {
            a,
            b,
            system: system.unwrap_or_default(),
        })),
        (None, None) if system.is_none() => Ok(None),
        (None, None) => Err("`system` needs the orientation points `a` and `b`".into()),
        _ => Err(
            "give both orientation vectors `a` (material axis 1, or a point of the cylinder axis) \
             and `b` (in the 1-2 plane, or a second point of the axis), or neither"
                .into(),
        ),
    }
}

/// Orthotropic linear elastic material with an optional orientation.
#[derive(Debug, Clone, PartialEq)]
pub struct Orthotropic {
    constants: EngineeringConstants,
    axes: Axes,
    c_local: Voigt6,
    c_global: Voigt6,
    /// Expansion along the material axes.
    alpha: [f64; 3],
    /// Global Voigt expansion in the reference axes.
    alpha_global: [f64; 6],
}

/// Parameter table of `orthotropic`.
#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OrthotropicParams {
    /// `E1`: Young's modulus along material axis 1, > 0.
    #[serde(rename = "E1")]
    pub e1: f64,
    /// `E2`: Young's modulus along material axis 2, > 0.
    #[serde(rename = "E2")]
    pub e2: f64,
    /// `E3`: Young's modulus along material axis 3, > 0.
    #[serde(rename = "E3")]
    pub e3: f64,
    /// Poisson's ratio: contraction along 2 under stress along 1.
    pub nu12: f64,
    /// Poisson's ratio: contraction along 3 under stress along 1.
    pub nu13: f64,
    /// Poisson's ratio: contraction along 3 under stress along 2.
    pub nu23: f64,
    /// `G12`: shear modulus in the 1-2 plane, > 0.
    #[serde(rename = "G12")]
    pub g12: f64,
    /// `G13`: shear modulus in the 1-3 plane, > 0.
    #[serde(rename = "G13")]
    pub g13: f64,
    /// `G23`: shear modulus in the 2-3 plane, > 0.
    #[serde(rename = "G23")]
    pub g23: f64,
    /// Material axis 1 (optional, with `b`).
    pub a: Option<[f64; 3]>,
    /// A vector in the material 1-2 plane (optional, with `a`).
    pub b: Option<[f64; 3]>,
    /// `"rectangular"` (default) or `"cylindrical"` (`a`, `b` points of the axis).
    pub system: Option<System>,
    /// Thermal expansion along material axis 1 (optional, default 0).
    pub alpha1: Option<f64>,
    /// Thermal expansion along material axis 2 (optional, default 0).
    pub alpha2: Option<f64>,
    /// Thermal expansion along material axis 3 (optional, default 0).
    pub alpha3: Option<f64>,
}

fn invalid(message: String) -> CoreError {
    CoreError::InvalidParameters {
        kind: "material",
        key: "orthotropic".into(),
        message,
    }
}

impl Orthotropic {
    /// A material from its engineering constants and an optional orientation
    /// (`None`: material axes = global axes).
    ///
    /// Errors if a modulus is not positive, the compliance is not positive
    /// definite, or the orientation vectors are degenerate.
    pub fn new(
        constants: EngineeringConstants,
        orientation: Option<Orientation>,
    ) -> Result<Self, CoreError> {
        let k = &constants;
        for (name, v) in [
            ("E1", k.e1),
            ("E2", k.e2),
            ("E3", k.e3),
            ("G12", k.g12),
            ("G13", k.g13),
            ("G23", k.g23),
        ] {
            if !(v > 0.0 && v.is_finite()) {
                return Err(invalid(format!(
                    "{name} = {v} is invalid; moduli E1, E2, E3, G12, G13, G23 must be positive and finite"
                )));
            }
            if !(super::MODULUS_RANGE.0..=super::MODULUS_RANGE.1).contains(&v) {
                return Err(invalid(format!(
                    "{name} = {v:e} is out of range [{:e}, {:e}] in any unit system",
                    super::MODULUS_RANGE.0,
                    super::MODULUS_RANGE.1
                )));
            }
        }
        for (name, v) in [("nu12", k.nu12), ("nu13", k.nu13), ("nu23", k.nu23)] {
            if !v.is_finite() {
                return Err(invalid(format!("{name} = {v} must be finite")));
            }
        }
        let s = constants.compliance();
        let Some(chol) = s.cholesky() else {
            return Err(invalid(format!(
                "the compliance is not positive definite for nu12 = {}, nu13 = {}, nu23 = {} \
                 (E1 = {}, E2 = {}, E3 = {}); valid constants satisfy |nu12| < sqrt(E1/E2), \
                 |nu13| < sqrt(E1/E3), |nu23| < sqrt(E2/E3) and \
                 1 - nu12 nu21 - nu23 nu32 - nu13 nu31 - 2 nu21 nu32 nu13 > 0 \
                 with nu21 = nu12 E2/E1, nu31 = nu13 E3/E1, nu32 = nu23 E3/E2",
                k.nu12, k.nu13, k.nu23, k.e1, k.e2, k.e3
            )));
        };
        let mut c_local = chol.inverse();
        // symmetrise the round-off of the inverse
        c_local = 0.5 * (c_local + c_local.transpose());
        let axes = match orientation {
            Some(o) => o.axes()?,
            None => Axes::Fixed(Matrix3::identity()),
        };
        let c_global = rotate_symmetric(&c_local, &axes.reference());
        Ok(Orthotropic {
            constants,
            axes,
            c_local,
            c_global,
            alpha: [0.0; 3],
            alpha_global: [0.0; 6],
        })
    }

    /// The same material with the thermal expansion `alpha` along its
    /// material axes 1, 2, 3 (per unit temperature); an error unless finite.
    pub fn with_expansion(mut self, alpha: [f64; 3]) -> Result<Self, CoreError> {
        crate::thermal::check_coefficients(&["alpha1", "alpha2", "alpha3"], &alpha)
            .map_err(invalid)?;
        self.alpha = alpha;
        self.alpha_global = self.expansion_in(&self.axes.reference());
        Ok(self)
    }

    /// Thermal expansion along the material axes 1, 2, 3.
    pub fn expansion(&self) -> [f64; 3] {
        self.alpha
    }

    /// The global Voigt expansion for material axes `q`.
    fn expansion_in(&self, q: &Matrix3<f64>) -> [f64; 6] {
        let a = Matrix3::from_diagonal(&Vector3::from(self.alpha));
        crate::thermal::rotate_expansion(&a, q)
    }

    /// Build from a parameter table (unknown keys rejected).
    pub fn from_table(table: &toml::Table) -> Result<Self, CoreError> {
        let p: OrthotropicParams = parse_params("material", "orthotropic", table)?;
        let orientation = orientation_of(p.a, p.b, p.system).map_err(invalid)?;
        Self::new(
            EngineeringConstants {
                e1: p.e1,
                e2: p.e2,
                e3: p.e3,
                nu12: p.nu12,
                nu13: p.nu13,
                nu23: p.nu23,
                g12: p.g12,
                g13: p.g13,
                g23: p.g23,
            },
            orientation,
        )?
        .with_expansion([
            p.alpha1.unwrap_or(0.0),
            p.alpha2.unwrap_or(0.0),
            p.alpha3.unwrap_or(0.0),
        ])
    }

    /// The engineering constants.
    pub fn constants(&self) -> &EngineeringConstants {
        &self.constants
    }
    /// Material axes as columns of a rotation matrix (global components);
    /// for a cylindrical orientation those on its axis ([`Axes::reference`]).
    pub fn rotation(&self) -> Matrix3<f64> {
        self.axes.reference()
    }
    /// The material axes (fixed or cylindrical).
    pub fn axes(&self) -> &Axes {
        &self.axes
    }
    /// Elasticity matrix in the material axes.
    pub fn local_elasticity(&self) -> Voigt6 {
        self.c_local
    }
}

impl Material for Orthotropic {
    fn key(&self) -> &'static str {
        "orthotropic"
    }
    fn elasticity(&self) -> Voigt6 {
        self.c_global
    }
    fn varies_in_space(&self) -> bool {
        self.axes.varies()
    }
    fn elasticity_at(&self, x: [f64; 3]) -> Voigt6 {
        match self.axes {
            Axes::Fixed(_) => self.c_global,
            _ => rotate_symmetric(&self.c_local, &self.axes.at(x)),
        }
    }
    fn axes_at(&self, x: [f64; 3]) -> Option<Matrix3<f64>> {
        Some(self.axes.at(x))
    }
    /// The largest of `E1, E2, E3`.
    fn reference_modulus(&self) -> f64 {
        self.constants
            .e1
            .max(self.constants.e2)
            .max(self.constants.e3)
    }
    fn has_thermal_expansion(&self) -> bool {
        self.alpha != [0.0; 3]
    }
    fn thermal_expansion_at(&self, x: [f64; 3]) -> [f64; 6] {
        match self.axes {
            Axes::Fixed(_) => self.alpha_global,
            _ => self.expansion_in(&self.axes.at(x)),
        }
    }
}

inventory::submit! {
    MaterialEntry {
        key: "orthotropic",
        description: "orthotropic linear elasticity from engineering constants, optional orientation (a, b; rectangular or cylindrical)",
        params: &[
            ParamDoc { name: "E1", doc: "Young's modulus along material axis 1, > 0" },
            ParamDoc { name: "E2", doc: "Young's modulus along material axis 2, > 0" },
            ParamDoc { name: "E3", doc: "Young's modulus along material axis 3, > 0" },
            ParamDoc { name: "nu12", doc: "Poisson's ratio: contraction along 2 under stress along 1" },
            ParamDoc { name: "nu13", doc: "Poisson's ratio: contraction along 3 under stress along 1" },
            ParamDoc { name: "nu23", doc: "Poisson's ratio: contraction along 3 under stress along 2" },
            ParamDoc { name: "G12", doc: "shear modulus in the 1-2 plane, > 0" },
            ParamDoc { name: "G13", doc: "shear modulus in the 1-3 plane, > 0" },
            ParamDoc { name: "G23", doc: "shear modulus in the 2-3 plane, > 0" },
            ParamDoc { name: "a", doc: "optional [x, y, z]: material axis 1 (with b; default global x)" },
            ParamDoc { name: "b", doc: "optional [x, y, z]: a vector in the material 1-2 plane (with a)" },
            ParamDoc { name: "system", doc: "optional \"rectangular\" (default) or \"cylindrical\": a, b two points of the axis, material axes r, theta, z at each integration point" },
            ParamDoc { name: "alpha1", doc: "optional thermal expansion per unit temperature along material axis 1 (default 0)" },
            ParamDoc { name: "alpha2", doc: "optional thermal expansion per unit temperature along material axis 2 (default 0)" },
            ParamDoc { name: "alpha3", doc: "optional thermal expansion per unit temperature along material axis 3 (default 0)" },
        ],
        build: |t| Ok(Arc::new(Orthotropic::from_table(t)?)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::Isotropic;

    fn composite() -> EngineeringConstants {
        EngineeringConstants {
            e1: 135e9,
            e2: 9e9,
            e3: 8e9,
            nu12: 0.3,
            nu13: 0.28,
            nu23: 0.45,
            g12: 5e9,
            g13: 4.8e9,
            g23: 3.1e9,
        }
    }

    fn rel(a: &Voigt6, b: &Voigt6) -> f64 {
        (a - b).norm() / b.norm()
    }

    #[test]
    fn isotropic_constants_give_isotropic_c() {
        let o = Orthotropic::new(EngineeringConstants::isotropic(70e9, 0.33), None).unwrap();
        let i = Isotropic::new(70e9, 0.33).unwrap();
        assert!(rel(&o.elasticity(), &i.elasticity()) < 1e-13);
        // and any orientation leaves it unchanged
        let r = Orientation::rectangular([1.0, 2.0, -0.5], [0.3, -1.0, 2.0]);
        let o = Orthotropic::new(EngineeringConstants::isotropic(70e9, 0.33), Some(r)).unwrap();
        assert!(rel(&o.elasticity(), &i.elasticity()) < 1e-13);
    }

    #[test]
    fn rotation_by_90_degrees_about_z_swaps_axes_1_and_2() {
        let k = composite();
        let o = Orthotropic::new(
            k,
            Some(Orientation::rectangular([0.0, 1.0, 0.0], [-1.0, 0.0, 0.0])),
        )
        .unwrap();
        let s = o.elasticity().try_inverse().unwrap();
        // global x is material 2, global y is material 1
        assert!((1.0 / s[(0, 0)] - k.e2).abs() < 1e-6 * k.e2);
        assert!((1.0 / s[(1, 1)] - k.e1).abs() < 1e-6 * k.e1);
        assert!((1.0 / s[(2, 2)] - k.e3).abs() < 1e-6 * k.e3);
        // nu_yx (global) = nu12: -S_yx E_y... S[1][0] = -nu12/E1
        assert!((s[(1, 0)] * k.e1 + k.nu12).abs() < 1e-9);
        // shear: xy is still 12, yz is 13 (global y = 1, z = 3), zx is 23
        assert!((1.0 / s[(3, 3)] - k.g12).abs() < 1e-6 * k.g12);
        assert!((1.0 / s[(4, 4)] - k.g13).abs() < 1e-6 * k.g13);
        assert!((1.0 / s[(5, 5)] - k.g23).abs() < 1e-6 * k.g23);
        let c = o.elasticity();
        let cl = o.local_elasticity();
        assert!((c[(0, 0)] - cl[(1, 1)]).abs() < 1e-6 * cl[(0, 0)]);
        assert!((c[(1, 1)] - cl[(0, 0)]).abs() < 1e-6 * cl[(0, 0)]);
        assert!((c[(0, 2)] - cl[(1, 2)]).abs() < 1e-6 * cl[(0, 0)]);
    }

    #[test]
    fn rotation_by_45_degrees_gives_known_modulus() {
        // E_x at 45 degrees: 1/Ex = c^4/E1 + s^4/E2 + c^2 s^2 (1/G12 - 2 nu12/E1)
        let k = composite();
        let o = Orthotropic::new(
            k,
            Some(Orientation::rectangular([1.0, 1.0, 0.0], [-1.0, 1.0, 0.0])),
        )
        .unwrap();
        let s = o.elasticity().try_inverse().unwrap();
        let inv_ex = 0.25 / k.e1 + 0.25 / k.e2 + 0.25 * (1.0 / k.g12 - 2.0 * k.nu12 / k.e1);
        assert!((s[(0, 0)] / inv_ex - 1.0).abs() < 1e-10);
    }

    #[test]
    fn c_is_symmetric_positive_definite() {
        let o = Orthotropic::new(
            composite(),
            Some(Orientation::rectangular([0.2, 1.0, 0.7], [1.0, -0.4, 0.1])),
        )
        .unwrap();
        let c = o.elasticity();
        assert!((c - c.transpose()).norm() < 1e-14 * c.norm());
        let eig = c.symmetric_eigen().eigenvalues;
        assert!(eig.iter().all(|&l| l > 0.0), "{eig:?}");
        // rotation preserves the eigenvalues of the Kelvin-scaled stiffness... and the trace of S's normal block
        let s = c.try_inverse().unwrap();
        let sl = o.local_elasticity().try_inverse().unwrap();
        let tr = |m: &Voigt6| {
            m[(0, 0)] + m[(1, 1)] + m[(2, 2)] + 2.0 * (m[(0, 1)] + m[(1, 2)] + m[(0, 2)])
        };
        assert!((tr(&s) - tr(&sl)).abs() < 1e-10 * tr(&sl).abs());
    }

    #[test]
    fn invalid_constants_are_rejected_with_valid_ranges() {
        let mut k = composite();
        k.nu12 = 4.0; // > sqrt(E1/E2) = 3.87
        let e = Orthotropic::new(k, None).unwrap_err().to_string();
        assert!(
            e.contains("positive definite") && e.contains("sqrt(E1/E2)"),
            "{e}"
        );
        let mut k = composite();
        k.g23 = 0.0;
        let e = Orthotropic::new(k, None).unwrap_err().to_string();
        assert!(e.contains("G23"), "{e}");
        let e = Orthotropic::new(
            composite(),
            Some(Orientation::rectangular([1.0, 0.0, 0.0], [2.0, 0.0, 0.0])),
        )
        .unwrap_err()
        .to_string();
        assert!(e.contains("parallel"), "{e}");
    }

    #[test]
    fn from_table() {
        let base = "E1 = 135e9\nE2 = 9e9\nE3 = 9e9\nnu12 = 0.3\nnu13 = 0.3\nnu23 = 0.45\nG12 = 5e9\nG13 = 5e9\nG23 = 3.1e9\n";
        let t: toml::Table = toml::from_str(base).unwrap();
        let o = Orthotropic::from_table(&t).unwrap();
        assert_eq!(o.reference_modulus(), 135e9);
        let t: toml::Table =
            toml::from_str(&format!("{base}a = [1.0, 1.0, 0.0]\nb = [0.0, 1.0, 0.0]")).unwrap();
        assert!(Orthotropic::from_table(&t).is_ok());
        let t: toml::Table = toml::from_str(&format!("{base}a = [1.0, 1.0, 0.0]")).unwrap();
        assert!(Orthotropic::from_table(&t)
            .unwrap_err()
            .to_string()
            .contains("both"));
        let t: toml::Table = toml::from_str(&format!("{base}E4 = 1.0")).unwrap();
        assert!(Orthotropic::from_table(&t)
            .unwrap_err()
            .to_string()
            .contains("E4"));
    }

    #[test]
    fn cylindrical_axes_follow_the_point() {
        let k = composite();
        // axis along global z through (1, 2, 0)
        let o = Orthotropic::new(
            k,
            Some(Orientation::cylindrical([1.0, 2.0, 0.0], [1.0, 2.0, 5.0])),
        )
        .unwrap();
        assert!(o.varies_in_space());
        let e = |c: Voigt6, n: usize| 1.0 / c.try_inverse().unwrap()[(n, n)];
        // on the +x side of the axis: x radial (E1), y hoop (E2), z axial (E3)
        let c = o.elasticity_at([4.0, 2.0, 7.0]);
        assert!((e(c, 0) / k.e1 - 1.0).abs() < 1e-10);
        assert!((e(c, 1) / k.e2 - 1.0).abs() < 1e-10);
        assert!((e(c, 2) / k.e3 - 1.0).abs() < 1e-10);
        // on the +y side: y radial, x hoop
        let c = o.elasticity_at([1.0, 5.0, -1.0]);
        assert!((e(c, 1) / k.e1 - 1.0).abs() < 1e-10);
        assert!((e(c, 0) / k.e2 - 1.0).abs() < 1e-10);
        // at 45 degrees: the rectangular system with a radial, b hoop
        let q = o.axes().at([2.0, 3.0, 0.5]);
        let r = Orthotropic::new(
            k,
            Some(Orientation::rectangular([1.0, 1.0, 0.0], [-1.0, 1.0, 0.0])),
        )
        .unwrap();
        assert!((q - r.rotation()).norm() < 1e-14);
        assert!(rel(&o.elasticity_at([2.0, 3.0, 0.5]), &r.elasticity()) < 1e-14);
        // on the axis: CalculiX's perpendicular, a valid frame
        let q = o.axes().at([1.0, 2.0, 3.0]);
        assert!((q.transpose() * q - Matrix3::identity()).norm() < 1e-14);
        assert!((q.determinant() - 1.0).abs() < 1e-14);
        // a == b is an error; a table with system = "cylindrical"
        assert!(Orthotropic::new(
            k,
            Some(Orientation::cylindrical([1.0, 2.0, 0.0], [1.0, 2.0, 0.0]))
        )
        .unwrap_err()
        .to_string()
        .contains("must differ"));
        let base = "E1 = 135e9\nE2 = 9e9\nE3 = 9e9\nnu12 = 0.3\nnu13 = 0.3\nnu23 = 0.45\nG12 = 5e9\nG13 = 5e9\nG23 = 3.1e9\n";
        let t: toml::Table = toml::from_str(&format!(
            "{base}a = [0.0, 0.0, 0.0]\nb = [0.0, 0.0, 1.0]\nsystem = \"cylindrical\""
        ))
        .unwrap();
        assert!(Orthotropic::from_table(&t).unwrap().varies_in_space());
        let t: toml::Table = toml::from_str(&format!("{base}system = \"cylindrical\"")).unwrap();
        assert!(Orthotropic::from_table(&t).is_err());
    }
}
