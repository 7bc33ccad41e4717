//! The [`InterfaceLaw`] trait: traction-separation laws in the local frame
//! `[s1, s2, n]` (two slips, then the opening; positive opening separates).
//! Laws never see geometry.

use crate::element::StepInfo;
use thiserror::Error;

/// Errors raised by a law.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum LawError {
    /// The law cannot evaluate this jump.
    #[error("{0}")]
    Failed(String),
}

/// What a law reads at one integration point.
#[derive(Debug, Clone, Copy)]
pub struct LawContext<'a> {
    /// Displacement jump in the local frame `[delta_1, delta_2, delta_3]`.
    pub jump: [f64; 3],
    /// Committed state of this point (len = `state_len`).
    pub state_committed: &'a [f64],
    /// Increment information.
    pub step: StepInfo,
}

/// What a law returns at one integration point.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct LawResponse {
    /// Traction `[tau_13, tau_23, sigma_33]`.
    pub traction: [f64; 3],
    /// Consistent tangent `d traction / d jump` (row-major 3x3).
    pub tangent: [[f64; 3]; 3],
}

/// A traction-separation law.
pub trait InterfaceLaw: Send + Sync + std::fmt::Debug {
    /// Registry key (`"linear_penalty"`, ...).
    fn key(&self) -> &'static str;
    /// Number of state values per integration point.
    fn state_len(&self) -> usize {
        0
    }
    /// Initial state of one point.
    fn init_state(&self, _state: &mut [f64]) {}
    /// Traction and tangent for the given jump; trial state into `state_trial`.
    fn evaluate(
        &self,
        ctx: &LawContext<'_>,
        state_trial: &mut [f64],
    ) -> Result<LawResponse, LawError>;
    /// Initial (undamaged) stiffness `[d1, d2, d3]`, for diagnostics.
    fn initial_stiffness(&self) -> [f64; 3];
    /// True when the committed state asks for small increments.
    fn wants_small_increments(&self, _state_committed: &[f64]) -> bool {
        false
    }
    /// True when the point has failed (for output: failed fractions,
    /// crack fronts). Laws without failure return false.
    fn is_failed(&self, _state: &[f64]) -> bool {
        false
    }
    /// The last failure index stored in the state, if the law keeps one.
    fn failure_index(&self, _state: &[f64]) -> Option<f64> {
        None
    }
    /// Kind of the tangent this law can produce: SPD for laws that never
    /// soften, symmetric indefinite for softening laws, general for
    /// nonsymmetric tangents. The model's matrix kind is the largest over
    /// its elements; the driver picks the linear back end from it.
    fn tangent_kind(&self) -> crate::solver::MatrixKind {
        crate::solver::MatrixKind::SymmetricPositiveDefinite
    }
}
