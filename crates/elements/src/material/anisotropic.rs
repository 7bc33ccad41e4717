//! Fully anisotropic linear elasticity: the 21 independent entries of a
//! symmetric 6x6 stiffness, in the material axes, as Abaqus and CalculiX
//! write them (`*ELASTIC, TYPE=ANISO`), with engineering shear strains:
//!
//! ```text
//! D1111, D1122, D2222, D1133, D2233, D3333, D1112, D2212, D3312, D1212,
//! D1113, D2213, D3313, D1213, D1313, D1123, D2223, D3323, D1223, D1323, D2323
//! ```
//!
//! i.e. the upper triangle column by column in the component order
//! `(11, 22, 33, 12, 13, 23)` (Abaqus Analysis User's Guide, "Linear elastic
//! behavior", anisotropic elasticity). Junta's Voigt order is `[11, 22, 33,
//! 12, 23, 31]`, so components 13 and 23 swap places: `C_l[p(i)][p(j)] =
//! D(i, j)` with `p = [0, 1, 2, 3, 5, 4]`. The stiffness must be positive
//! definite. An optional orientation `a`, `b` [, `system`] (as for
//! `orthotropic`, rectangular or cylindrical) gives `C_g = T C_l T^T` (see
//! [`super`]), for a cylindrical system at each integration point.
//!
//! Thermal expansion: `alpha = [a11, a22, a33, a12, a13, a23]` (optional,
//! default 0), the tensor components of the expansion per unit temperature
//! in the material axes in the order of Abaqus / CalculiX `*EXPANSION,
//! TYPE=ANISO`, rotated like a strain tensor ([`crate::thermal`]).

use super::orthotropic::{orientation_of, Axes, Orientation, System};
use super::rotate_symmetric;
use junta_core::registry::{parse_params, MaterialEntry, ParamDoc};
use junta_core::{CoreError, Material, Voigt6};
use serde::Deserialize;
use std::sync::Arc;

/// Junta Voigt index of the Abaqus component order `(11, 22, 33, 12, 13, 23)`.
const ABAQUS_TO_VOIGT: [usize; 6] = [0, 1, 2, 3, 5, 4];

/// Anisotropic linear elastic material.
#[derive(Debug, Clone, PartialEq)]
pub struct Anisotropic {
    axes: Axes,
    c_local: Voigt6,
    c_global: Voigt6,
    reference: f64,
    /// Expansion tensor in the material axes.
    alpha: nalgebra::Matrix3<f64>,
    /// Global Voigt expansion in the reference axes.
    alpha_global: [f64; 6],
}

/// Parameter table of `anisotropic`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AnisotropicParams {
    /// The 21 constants in the Abaqus order (module docs).
    #[serde(rename = "D")]
    pub d: Vec<f64>,
    /// Material axis 1, or a point of the cylinder axis (optional, with `b`;
    /// default: the global axes).
    pub a: Option<[f64; 3]>,
    /// A vector in the material 1-2 plane, or a second point of the
    /// cylinder axis (optional, with `a`).
    pub b: Option<[f64; 3]>,
    /// `"rectangular"` (default) or `"cylindrical"` (`a`, `b` points of the axis).
    pub system: Option<System>,
    /// Thermal expansion `[a11, a22, a33, a12, a13, a23]` (tensor
    /// components, material axes; optional, default 0).
    pub alpha: Option<[f64; 6]>,
}

fn invalid(message: String) -> CoreError {
    CoreError::InvalidParameters {
        kind: "material",
        key: "anisotropic".into(),
        message,
    }
}

/// The stiffness in the material axes, Junta's Voigt order, from the 21
/// constants in the Abaqus order.
pub fn stiffness_from_abaqus(d: &[f64; 21]) -> Voigt6 {
    let mut c = Voigt6::zeros();
    let mut k = 0;
    for j in 0..6 {
        for i in 0..=j {
            let (p, q) = (ABAQUS_TO_VOIGT[i], ABAQUS_TO_VOIGT[j]);
            c[(p, q)] = d[k];
            c[(q, p)] = d[k];
            k += 1;
        }
    }
    c
}

impl Anisotropic {
    /// A material from the 21 constants (Abaqus order) and an optional
    /// orientation. Errors: a non-finite constant, a stiffness that is not
    /// positive definite, degenerate orientation vectors.
    pub fn new(d: &[f64; 21], orientation: Option<Orientation>) -> Result<Self, CoreError> {
        if let Some(k) = d.iter().position(|v| !v.is_finite()) {
            return Err(invalid(format!("D[{k}] = {} must be finite", d[k])));
        }
        let c_local = stiffness_from_abaqus(d);
        if c_local.cholesky().is_none() {
            return Err(invalid(
                "the stiffness D is not positive definite (no strain may cost zero or negative energy)"
                    .into(),
            ));
        }
        let axes = match orientation {
            Some(o) => o.axes().map_err(|e| match e {
                CoreError::InvalidParameters { message, .. } => invalid(message),
                e => e,
            })?,
            None => Axes::Fixed(nalgebra::Matrix3::identity()),
        };
        let c_global = rotate_symmetric(&c_local, &axes.reference());
        let reference = (0..3).map(|i| c_local[(i, i)]).fold(0.0, f64::max);
        Ok(Anisotropic {
            axes,
            c_local,
            c_global,
            reference,
            alpha: nalgebra::Matrix3::zeros(),
            alpha_global: [0.0; 6],
        })
    }

    /// The same material with the thermal expansion `[a11, a22, a33, a12,
    /// a13, a23]` (tensor components in the material axes, per unit
    /// temperature); an error unless finite.
    pub fn with_expansion(mut self, alpha: [f64; 6]) -> Result<Self, CoreError> {
        crate::thermal::check_coefficients(&["a11", "a22", "a33", "a12", "a13", "a23"], &alpha)
            .map_err(invalid)?;
        self.alpha = crate::thermal::expansion_tensor(&alpha);
        self.alpha_global = crate::thermal::rotate_expansion(&self.alpha, &self.axes.reference());
        Ok(self)
    }

    /// Build from a parameter table (unknown keys rejected).
    pub fn from_table(table: &toml::Table) -> Result<Self, CoreError> {
        let p: AnisotropicParams = parse_params("material", "anisotropic", table)?;
        let d: [f64; 21] = p.d.as_slice().try_into().map_err(|_| {
            invalid(format!(
                "`D` needs the 21 constants D1111, D1122, D2222, ..., D2323 (Abaqus order), not {}",
                p.d.len()
            ))
        })?;
        let orientation = orientation_of(p.a, p.b, p.system).map_err(invalid)?;
        Self::new(&d, orientation)?.with_expansion(p.alpha.unwrap_or([0.0; 6]))
    }
}

impl Material for Anisotropic {
    fn key(&self) -> &'static str {
        "anisotropic"
    }
    /// For a cylindrical orientation: `C` in the axes on the cylinder axis.
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
    /// The largest normal stiffness `D1111, D2222, D3333`.
    fn axes_at(&self, x: [f64; 3]) -> Option<nalgebra::Matrix3<f64>> {
        Some(self.axes.at(x))
    }
    fn reference_modulus(&self) -> f64 {
        self.reference
    }
    fn has_thermal_expansion(&self) -> bool {
        self.alpha != nalgebra::Matrix3::zeros()
    }
    fn thermal_expansion_at(&self, x: [f64; 3]) -> [f64; 6] {
        match self.axes {
            Axes::Fixed(_) => self.alpha_global,
            _ => crate::thermal::rotate_expansion(&self.alpha, &self.axes.at(x)),
        }
    }
}

inventory::submit! {
    MaterialEntry {
        key: "anisotropic",
        description: "anisotropic linear elasticity from the 21 stiffness constants (Abaqus/CalculiX TYPE=ANISO order), optional orientation (a, b; rectangular or cylindrical)",
        params: &[
            ParamDoc { name: "D", doc: "21 constants D1111, D1122, D2222, D1133, D2233, D3333, D1112, D2212, D3312, D1212, D1113, D2213, D3313, D1213, D1313, D1123, D2223, D3323, D1223, D1323, D2323 (engineering shear strains); positive definite" },
            ParamDoc { name: "a", doc: "optional [x, y, z]: material axis 1 (with b; default global x)" },
            ParamDoc { name: "b", doc: "optional [x, y, z]: a vector in the material 1-2 plane (with a)" },
            ParamDoc { name: "system", doc: "optional \"rectangular\" (default) or \"cylindrical\": a, b two points of the axis, material axes r, theta, z at each integration point" },
            ParamDoc { name: "alpha", doc: "optional [a11, a22, a33, a12, a13, a23]: thermal expansion per unit temperature, tensor components in the material axes (*EXPANSION, TYPE=ANISO order; default 0)" },
        ],
        build: |t| Ok(Arc::new(Anisotropic::from_table(t)?)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::{EngineeringConstants, Orthotropic};

    /// An orthotropic stiffness written as ANISO (zero couplings) gives the
    /// orthotropic material's matrix, in every orientation.
    #[test]
    fn orthotropic_as_aniso_equals_orthotropic() {
        let k = EngineeringConstants {
            e1: 135e3,
            e2: 9e3,
            e3: 8e3,
            nu12: 0.3,
            nu13: 0.28,
            nu23: 0.4,
            g12: 5e3,
            g13: 4.5e3,
            g23: 3e3,
        };
        let o = Orientation::rectangular([1.0, 1.0, 0.2], [-0.3, 1.0, 0.5]);
        let ortho = Orthotropic::new(k, Some(o)).unwrap();
        let c = ortho.local_elasticity();
        // Abaqus order (11,22,33,12,13,23) from Junta's Voigt indices
        let v = [0usize, 1, 2, 3, 5, 4];
        let mut d = [0.0; 21];
        let mut n = 0;
        for j in 0..6 {
            for i in 0..=j {
                d[n] = c[(v[i], v[j])];
                n += 1;
            }
        }
        let aniso = Anisotropic::new(&d, Some(o)).unwrap();
        let diff = (aniso.elasticity() - ortho.elasticity()).abs().max();
        assert!(diff < 1e-9 * 135e3, "{diff}");
        // a coupling term lands where Junta keeps 13 (index 5) and 23 (4)
        let mut d2 = d;
        d2[14] += 0.0; // D1313
        d2[10] = 100.0; // D1113
        let c2 = Anisotropic::new(&d2, None).unwrap().elasticity();
        assert_eq!(c2[(0, 5)], 100.0);
        assert_eq!(c2[(5, 0)], 100.0);
        // not positive definite
        let mut bad = d;
        bad[0] = -1.0;
        assert!(Anisotropic::new(&bad, None).is_err());
    }
}
