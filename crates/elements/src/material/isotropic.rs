//! Isotropic linear elasticity (key `isotropic`).
//!
//! Parameters: Young's modulus `E > 0` and Poisson's ratio `-1 < nu < 1/2`.
//! With the Lamé constants
//!
//! ```text
//! lambda = E nu / ((1 + nu)(1 - 2 nu)),     mu = G = E / (2 (1 + nu)),
//! ```
//!
//! the elasticity matrix in Voigt order `[xx, yy, zz, xy, yz, zx]` with
//! engineering shear strains is
//!
//! ```text
//!     | lambda+2mu  lambda      lambda      0   0   0  |
//!     | lambda      lambda+2mu  lambda      0   0   0  |
//! C = | lambda      lambda      lambda+2mu  0   0   0  |
//!     | 0           0           0           mu  0   0  |
//!     | 0           0           0           0   mu  0  |
//!     | 0           0           0           0   0   mu |
//! ```
//!
//! Thermal expansion: `alpha` (optional, default 0) per unit temperature,
//! the same in every direction: thermal strain `alpha dT [1, 1, 1, 0, 0, 0]`
//! ([`crate::thermal`]).
//!
//! TOML: `{ type = "isotropic", E = 210e9, nu = 0.3 }` (the `type` key is
//! the scene's, not ours: the table handed to the constructor holds `E`,
//! `nu` and the optional `alpha`).

use junta_core::registry::{parse_params, MaterialEntry, ParamDoc};
use junta_core::{CoreError, Material, Voigt6};
use serde::Deserialize;
use std::sync::Arc;

/// Isotropic linear elastic material.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Isotropic {
    e: f64,
    nu: f64,
    c: Voigt6,
    /// Thermal expansion per unit temperature.
    alpha: f64,
}

/// Parameter table of `isotropic`.
#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct IsotropicParams {
    /// Young's modulus.
    #[serde(rename = "E")]
    pub e: f64,
    /// Poisson's ratio.
    pub nu: f64,
    /// Thermal expansion coefficient (optional, default 0).
    pub alpha: Option<f64>,
}

fn invalid(message: String) -> CoreError {
    CoreError::InvalidParameters {
        kind: "material",
        key: "isotropic".into(),
        message,
    }
}

impl Isotropic {
    /// A material with Young's modulus `e` and Poisson's ratio `nu`.
    ///
    /// Errors unless `e > 0` (finite) and `-1 < nu < 0.5`.
    pub fn new(e: f64, nu: f64) -> Result<Self, CoreError> {
        if !(e > 0.0 && e.is_finite()) {
            return Err(invalid(format!(
                "Young's modulus E = {e} is invalid; E must be positive and finite"
            )));
        }
        if !(super::MODULUS_RANGE.0..=super::MODULUS_RANGE.1).contains(&e) {
            return Err(invalid(format!(
                "Young's modulus E = {e:e} is out of range [{:e}, {:e}] in any unit system; \
                 stiffness products would overflow or underflow",
                super::MODULUS_RANGE.0,
                super::MODULUS_RANGE.1
            )));
        }
        if !(nu > -1.0 && nu < 0.5) {
            return Err(invalid(format!(
                "Poisson's ratio nu = {nu} is invalid; it must satisfy -1 < nu < 0.5 \
                 (0.5 is the incompressible limit, which displacement elements cannot represent)"
            )));
        }
        let lambda = e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
        let mu = e / (2.0 * (1.0 + nu));
        let mut c = Voigt6::zeros();
        for i in 0..3 {
            for j in 0..3 {
                c[(i, j)] = lambda;
            }
            c[(i, i)] = lambda + 2.0 * mu;
            c[(i + 3, i + 3)] = mu;
        }
        Ok(Isotropic {
            e,
            nu,
            c,
            alpha: 0.0,
        })
    }

    /// The same material with the thermal expansion coefficient `alpha`
    /// (per unit temperature); an error unless finite.
    pub fn with_expansion(mut self, alpha: f64) -> Result<Self, CoreError> {
        crate::thermal::check_coefficients(&["alpha"], &[alpha]).map_err(invalid)?;
        self.alpha = alpha;
        Ok(self)
    }

    /// Thermal expansion coefficient.
    pub fn expansion(&self) -> f64 {
        self.alpha
    }

    /// Build from a parameter table (`E`, `nu`; unknown keys rejected).
    pub fn from_table(table: &toml::Table) -> Result<Self, CoreError> {
        let p: IsotropicParams = parse_params("material", "isotropic", table)?;
        Self::new(p.e, p.nu)?.with_expansion(p.alpha.unwrap_or(0.0))
    }

    /// Young's modulus.
    pub fn youngs_modulus(&self) -> f64 {
        self.e
    }
    /// Poisson's ratio.
    pub fn poissons_ratio(&self) -> f64 {
        self.nu
    }
    /// Shear modulus `G = E / (2 (1 + nu))`.
    pub fn shear_modulus(&self) -> f64 {
        self.e / (2.0 * (1.0 + self.nu))
    }
    /// Bulk modulus `K = E / (3 (1 - 2 nu))`.
    pub fn bulk_modulus(&self) -> f64 {
        self.e / (3.0 * (1.0 - 2.0 * self.nu))
    }
}

impl Material for Isotropic {
    fn key(&self) -> &'static str {
        "isotropic"
    }
    fn elasticity(&self) -> Voigt6 {
        self.c
    }
    fn reference_modulus(&self) -> f64 {
        self.e
    }
    fn has_thermal_expansion(&self) -> bool {
        self.alpha != 0.0
    }
    fn thermal_expansion_at(&self, _x: [f64; 3]) -> [f64; 6] {
        let a = self.alpha;
        [a, a, a, 0.0, 0.0, 0.0]
    }
}

inventory::submit! {
    MaterialEntry {
        key: "isotropic",
        description: "isotropic linear elasticity (Young's modulus and Poisson's ratio)",
        params: &[
            ParamDoc { name: "E", doc: "Young's modulus, > 0 (stress units, e.g. Pa)" },
            ParamDoc { name: "nu", doc: "Poisson's ratio, -1 < nu < 0.5" },
            ParamDoc { name: "alpha", doc: "optional thermal expansion coefficient per unit temperature (default 0; see [temperature] in scenes.md)" },
        ],
        build: |t| Ok(Arc::new(Isotropic::from_table(t)?)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn closed_form() {
        let (e, nu) = (200e9, 0.3);
        let m = Isotropic::new(e, nu).unwrap();
        let c = m.elasticity();
        let f = e / ((1.0 + nu) * (1.0 - 2.0 * nu));
        assert!((c[(0, 0)] - f * (1.0 - nu)).abs() < 1e-6 * e);
        assert!((c[(0, 1)] - f * nu).abs() < 1e-6 * e);
        assert!((c[(3, 3)] - f * (1.0 - 2.0 * nu) / 2.0).abs() < 1e-6 * e);
        assert!((c[(5, 5)] - e / (2.0 * (1.0 + nu))).abs() < 1e-6 * e);
        assert_eq!(c[(0, 3)], 0.0);
        assert_eq!(c, c.transpose());
        // uniaxial stress: S = C^-1 has 1/E on the diagonal and -nu/E off it
        let s = c.try_inverse().unwrap();
        assert!((s[(1, 1)] * e - 1.0).abs() < 1e-12);
        assert!((s[(0, 2)] * e + nu).abs() < 1e-12);
        assert!((s[(4, 4)] * m.shear_modulus() - 1.0).abs() < 1e-12);
        assert!(c.cholesky().is_some());
        assert_eq!(m.reference_modulus(), e);
    }

    #[test]
    fn invalid_parameters_say_what_is_valid() {
        let e = Isotropic::new(-1.0, 0.3).unwrap_err().to_string();
        assert!(e.contains("positive"), "{e}");
        let e = Isotropic::new(1.0, 0.5).unwrap_err().to_string();
        assert!(e.contains("-1 < nu < 0.5"), "{e}");
        assert!(Isotropic::new(1.0, -1.0).is_err());
        assert!(Isotropic::new(f64::NAN, 0.2).is_err());
        assert!(Isotropic::new(1.0, f64::NAN).is_err());
    }

    #[test]
    fn from_table_rejects_unknown_keys() {
        let t: toml::Table = toml::from_str("E = 1.0e3\nnu = 0.25").unwrap();
        let m = Isotropic::from_table(&t).unwrap();
        assert_eq!(m.poissons_ratio(), 0.25);
        let t: toml::Table = toml::from_str("E = 1.0e3\nNu = 0.25").unwrap();
        let e = Isotropic::from_table(&t).unwrap_err().to_string();
        assert!(e.contains("Nu") && e.contains("nu"), "{e}");
        let t: toml::Table = toml::from_str("E = 1.0e3").unwrap();
        assert!(Isotropic::from_table(&t).is_err());
    }
}
