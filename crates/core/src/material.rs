//! The [`Material`] trait: linear elastic solid constitutive laws.
//!
//! Voigt order used everywhere in Junta: `[xx, yy, zz, xy, yz, zx]`, with
//! engineering shear strains `gamma_ij = 2 eps_ij`.

use nalgebra::SMatrix;

/// 6x6 matrix in Voigt notation.
pub type Voigt6 = SMatrix<f64, 6, 6>;

/// A solid material: gives the elasticity matrix in the global frame.
pub trait Material: Send + Sync + std::fmt::Debug {
    /// Registry key (`"isotropic"`, `"orthotropic"`).
    fn key(&self) -> &'static str;
    /// Elasticity matrix C in the global frame, sigma = C eps (Voigt order
    /// `[xx, yy, zz, xy, yz, zx]`, engineering shear strains). For a
    /// material whose axes vary in space ([`Material::varies_in_space`]) a
    /// representative value (the material documents which).
    fn elasticity(&self) -> Voigt6;
    /// Whether C depends on the position (material axes of a cylindrical
    /// system): elements then ask [`Material::elasticity_at`] at each
    /// integration point. Default `false`.
    fn varies_in_space(&self) -> bool {
        false
    }
    /// Elasticity matrix C in the global frame at the point `x` (reference
    /// coordinates). Default: [`Material::elasticity`]. Called once per
    /// integration point in element loops: must not allocate.
    fn elasticity_at(&self, x: [f64; 3]) -> Voigt6 {
        let _ = x;
        self.elasticity()
    }
    /// The material axes at the point `x` (reference coordinates): the
    /// columns of `Q` are the axes 1, 2, 3 in global components, so that
    /// the stress in the material axes is `Q^T sigma Q` (a ply: 1 along
    /// the fibre, 3 through the thickness). `None` (the default) for a
    /// material without axes of its own (isotropic). Called once per
    /// output point: must not allocate.
    fn axes_at(&self, x: [f64; 3]) -> Option<nalgebra::Matrix3<f64>> {
        let _ = x;
        None
    }
    /// A representative Young's modulus (for diagnostics such as the penalty advisor).
    fn reference_modulus(&self) -> f64;
    /// Whether the material has a non-zero thermal expansion: elements then
    /// ask [`Material::thermal_expansion_at`] at each integration point
    /// when the model carries a temperature change. Default `false`.
    fn has_thermal_expansion(&self) -> bool {
        false
    }
    /// Thermal strain per unit temperature change in the global frame at
    /// the point `x` (reference coordinates), Voigt order
    /// `[xx, yy, zz, xy, yz, zx]` with engineering shear strains
    /// (`gamma_xy = 2 alpha_xy`): the thermal strain of a temperature
    /// change `dT` is `dT` times this vector, and the stress is
    /// `sigma = C (eps - eps_th)`. The material's coefficients are rotated
    /// from its axes at `x` like its stiffness. Default: zero. Called once
    /// per integration point in element loops: must not allocate.
    fn thermal_expansion_at(&self, x: [f64; 3]) -> [f64; 6] {
        let _ = x;
        [0.0; 6]
    }
    /// Young's modulus along the unit direction `n`: the ratio of stress
    /// to strain in a uniaxial stress state along `n`,
    /// `1 / E(n) = v^T S v` with `S = C^-1` and `v` the Voigt form of
    /// `n (x) n` (`[n1^2, n2^2, n3^2, n1 n2, n2 n3, n3 n1]`, engineering
    /// shear strains). `None` if `C` is singular.
    fn directional_modulus(&self, n: [f64; 3]) -> Option<f64> {
        let s = self.elasticity().try_inverse()?;
        let v = nalgebra::SVector::<f64, 6>::from([
            n[0] * n[0],
            n[1] * n[1],
            n[2] * n[2],
            n[0] * n[1],
            n[1] * n[2],
            n[2] * n[0],
        ]);
        let c = (v.transpose() * s * v)[(0, 0)];
        (c > 0.0).then(|| 1.0 / c)
    }
}
