//! Thermal strains of the solid elements.
//!
//! A solid whose material expands ([`Material::has_thermal_expansion`])
//! under a temperature change `dT` from its stress-free temperature carries
//! the thermal strain
//!
//! ```text
//! eps_th = alpha(x) dT,     sigma = C (eps - eps_th)
//! ```
//!
//! with `alpha(x)` the material's expansion per unit temperature in the
//! global frame at the point, Voigt order `[xx, yy, zz, xy, yz, zx]` with
//! engineering shear (`gamma_xy = 2 alpha_xy dT`). The temperature is
//! prescribed: the tangent `B^T C B` does not change, the internal force
//! gains `-∫ B^T C eps_th dV`.
//!
//! The temperature change at an integration point is interpolated from the
//! element's nodal changes ([`junta_core::ElementContext::temperature`])
//! with the element's shape functions, `dT = Σ_a N_a dT_a` (for a
//! uniform change, exactly `dT`).
//!
//! Material axes: coefficients `alpha_l` given in the material axes (a
//! symmetric tensor: diagonal `alpha1, alpha2, alpha3` for an orthotropic
//! material) rotate as a strain tensor, `alpha_g = Q alpha_l Q^T` with `Q`
//! the material axes as columns ([`rotate_expansion`]); a cylindrical or
//! otherwise spatially varying system is evaluated at the integration
//! point, as the stiffness is.
//!
//! One call per integration point does it all ([`point_thermal_strain`]),
//! so that every kinematics takes the same hook: small strain subtracts it
//! from `eps`, the total-Lagrangian form from the Green strain `E`.

use junta_core::Material;
use nalgebra::{Matrix3, Vector6};

/// The global Voigt expansion (engineering shear) of the symmetric
/// expansion tensor `alpha_l` given in the material axes `q` (columns =
/// material axes in global components): `alpha_g = q alpha_l q^T`, then
/// `[g_xx, g_yy, g_zz, 2 g_xy, 2 g_yz, 2 g_zx]`.
pub fn rotate_expansion(alpha_l: &Matrix3<f64>, q: &Matrix3<f64>) -> [f64; 6] {
    let g = q * alpha_l * q.transpose();
    [
        g[(0, 0)],
        g[(1, 1)],
        g[(2, 2)],
        g[(0, 1)] + g[(1, 0)],
        g[(1, 2)] + g[(2, 1)],
        g[(2, 0)] + g[(0, 2)],
    ]
}

/// The expansion tensor of the Abaqus/CalculiX component list
/// `[a11, a22, a33, a12, a13, a23]` (tensor components, material axes).
pub fn expansion_tensor(a: &[f64; 6]) -> Matrix3<f64> {
    Matrix3::new(a[0], a[3], a[4], a[3], a[1], a[5], a[4], a[5], a[2])
}

/// The thermal strain at an integration point: `alpha(x) dT` with
/// `dT = Σ_a n_a dT_a` and `x = Σ_a n_a x_a` (`n`: the element's shape
/// functions at the point, one per node; `coords`: its reference nodal
/// coordinates; `temperature`: its nodal temperature changes). Zero when
/// the model has no temperature field or the material does not expand.
/// No allocation.
#[inline]
pub fn point_thermal_strain(
    material: &dyn Material,
    n: &[f64],
    coords: &[[f64; 3]],
    temperature: Option<&[f64]>,
) -> Vector6<f64> {
    let Some(t) = temperature else {
        return Vector6::zeros();
    };
    if !material.has_thermal_expansion() {
        return Vector6::zeros();
    }
    let dt: f64 = n.iter().zip(t).map(|(n, t)| n * t).sum();
    if dt == 0.0 {
        return Vector6::zeros();
    }
    let mut x = [0.0; 3];
    for (n, c) in n.iter().zip(coords) {
        for i in 0..3 {
            x[i] += n * c[i];
        }
    }
    thermal_strain(material, x, dt)
}

/// The thermal strain `alpha(x) dT` of a temperature change `dT` at the
/// point `x` (Voigt, engineering shear).
#[inline]
pub fn thermal_strain(material: &dyn Material, x: [f64; 3], dt: f64) -> Vector6<f64> {
    Vector6::from(material.thermal_expansion_at(x)) * dt
}

/// Check expansion coefficients: finite (an error message naming `name`
/// otherwise).
pub(crate) fn check_coefficients(names: &[&str], values: &[f64]) -> Result<(), String> {
    for (n, v) in names.iter().zip(values) {
        if !v.is_finite() {
            return Err(format!(
                "thermal expansion coefficient {n} = {v} must be finite (per unit temperature, e.g. 1/K)"
            ));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rotation_about_z_by_90_degrees_swaps_1_and_2() {
        let a = Matrix3::from_diagonal(&nalgebra::Vector3::new(1e-6, 3e-5, 2e-5));
        let q = nalgebra::Rotation3::from_axis_angle(
            &nalgebra::Vector3::z_axis(),
            0.5 * std::f64::consts::PI,
        )
        .into_inner();
        let g = rotate_expansion(&a, &q);
        assert!((g[0] - 3e-5).abs() < 1e-18 && (g[1] - 1e-6).abs() < 1e-18);
        assert!((g[2] - 2e-5).abs() < 1e-18 && g[3].abs() < 1e-18);
    }

    #[test]
    fn rotation_by_45_degrees_gives_the_engineering_shear() {
        // alpha_l = diag(a1, a2, a3) about z by 45 deg: g_xy = (a1 - a2) / 2,
        // engineering 2 g_xy = a1 - a2
        let (a1, a2) = (1e-6, 3e-5);
        let a = Matrix3::from_diagonal(&nalgebra::Vector3::new(a1, a2, 0.0));
        let q = nalgebra::Rotation3::from_axis_angle(
            &nalgebra::Vector3::z_axis(),
            0.25 * std::f64::consts::PI,
        )
        .into_inner();
        let g = rotate_expansion(&a, &q);
        assert!((g[0] - 0.5 * (a1 + a2)).abs() < 1e-18);
        assert!((g[3] - (a1 - a2)).abs() < 1e-18, "{g:?}");
    }
}
