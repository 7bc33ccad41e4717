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
    /// `[xx, yy, zz, xy, yz, zx]`, engineering shear strains).
    fn elasticity(&self) -> Voigt6;
    /// A representative Young's modulus (for diagnostics such as the penalty advisor).
    fn reference_modulus(&self) -> f64;
}
