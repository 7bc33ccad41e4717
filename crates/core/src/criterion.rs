//! The [`FailureCriterion`] trait: traction -> failure index and mode.

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

/// A failure (damage-initiation) criterion.
pub trait FailureCriterion: Send + Sync + std::fmt::Debug {
    /// Registry key.
    fn key(&self) -> &'static str;
    /// Failure index from the local traction `[tau_13, tau_23, sigma_33]`.
    fn evaluate(&self, traction: [f64; 3]) -> FailureResult;
}
