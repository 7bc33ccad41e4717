//! The [`FailureCriterion`] trait: traction -> failure index and mode, and
//! (for softening laws) the differentiable onset index of a jump.

use crate::dual::Dual3;

/// Mode of failure at a point.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FailureMode {
    /// Normal traction is tensile (opening).
    Tension,
    /// Normal traction is compressive (shear failure under contact).
    Compression,
    /// Pure shear (zero normal traction).
    Shear,
}

/// Result of evaluating a criterion.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FailureResult {
    /// Failure index; `>= 1` means failed.
    pub index: f64,
    /// Mode of failure.
    pub mode: FailureMode,
}

/// What a softening law hands a criterion to locate damage onset: the
/// undamaged traction `t0 = K delta` of the point and its jump, as dual
/// numbers seeded on the jump (so that the index comes with its gradient),
/// and the law's undamaged penalties `[K_1, K_2, K_n]`. The law passes the
/// opening part only (`<delta_3>`, `K_n <delta_3>`): closing never damages.
#[derive(Debug, Clone, Copy)]
pub struct OnsetInput {
    /// Undamaged traction `[tau_13, tau_23, sigma_33]`.
    pub traction: [Dual3; 3],
    /// Jump `[delta_1, delta_2, delta_3]`.
    pub jump: [Dual3; 3],
    /// Undamaged penalty stiffnesses `[K_1, K_2, K_n]`.
    pub penalty: [f64; 3],
}

/// A failure (damage-initiation) criterion.
pub trait FailureCriterion: Send + Sync + std::fmt::Debug {
    /// Registry key.
    fn key(&self) -> &'static str;
    /// Failure index from the local traction `[tau_13, tau_23, sigma_33]`.
    fn evaluate(&self, traction: [f64; 3]) -> FailureResult;
    /// Failure index of an undamaged point as a differentiable function of
    /// its jump (see [`OnsetInput`]), for softening laws that locate damage
    /// onset along the current jump direction. The index must be
    /// positively homogeneous of degree [`FailureCriterion::degree`] in the
    /// jump (`index(s delta) = s^p index(delta)` for `s > 0`), so that the
    /// onset jump along `delta` is `|delta| index^(-1/p)`. `None`: this
    /// criterion cannot drive a softening law (the law reports an error).
    fn onset_index(&self, _input: &OnsetInput) -> Option<Dual3> {
        None
    }
    /// Degree `p` of homogeneity of [`FailureCriterion::onset_index`].
    fn degree(&self) -> f64 {
        2.0
    }
}
