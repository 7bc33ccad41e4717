//! The [`PlyCriterion`] trait: ply failure criteria evaluated as outputs on
//! the stress of a ply in its material axes (not progressive damage).
//!
//! The stress is in Junta's Voigt order `[s11, s22, s33, t12, t23, t31]`,
//! axis 1 along the fibres, 2 transverse in the ply plane, 3 through the
//! thickness. A criterion returns a [`PlyFailure`]: its own failure function
//! value (`index`, `>= 1` means failed), the factor `strength_ratio` by which
//! the whole stress state must be scaled to reach failure exactly, and the
//! failure mode. A linear analysis gets its first-ply-failure load as the
//! smallest `strength_ratio` over its plies times its load.
//!
//! A stress with a NaN component gives [`PlyFailure::NAN`] (index and ratio
//! NaN, mode `Interaction`): no criterion panics on it.
//!
//! Criteria are plugins, registered with `inventory::submit!` as a
//! [`PlyCriterionEntry`] and found with
//! `registry::find::<PlyCriterionEntry>("hashin")`.

use crate::error::CoreError;
use crate::registry::ParamDoc;
use std::sync::Arc;

/// Failure mode of a ply.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PlyFailureMode {
    /// Fibre fracture under tension along axis 1.
    FibreTension,
    /// Fibre fracture (kinking, crushing) under compression along axis 1.
    FibreCompression,
    /// Inter-fibre (matrix) fracture under tensile normal stress.
    MatrixTension,
    /// Inter-fibre (matrix) fracture under compressive normal stress.
    MatrixCompression,
    /// No single mode: a single-expression criterion with no dominant
    /// component, a zero stress, or a NaN stress (see each criterion).
    Interaction,
}

/// What a ply criterion says about one stress state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlyFailure {
    /// The criterion's own failure function value; `>= 1` means failed.
    /// For criteria with several modes, the largest mode's value.
    pub index: f64,
    /// Factor `R > 0` by which the whole stress state must be scaled for
    /// the criterion to reach failure exactly (`index(R stress) = 1`);
    /// `f64::INFINITY` when no positive factor fails it.
    pub strength_ratio: f64,
    /// Mode of the governing failure function.
    pub mode: PlyFailureMode,
}

impl PlyFailure {
    /// The answer to a stress with a NaN component.
    pub const NAN: PlyFailure = PlyFailure {
        index: f64::NAN,
        strength_ratio: f64::NAN,
        mode: PlyFailureMode::Interaction,
    };

    /// The answer of a criterion positively homogeneous of degree 1
    /// (`index(s stress) = s index(stress)`): `strength_ratio = 1 / index`,
    /// infinite when the index is not positive.
    pub fn homogeneous(index: f64, mode: PlyFailureMode) -> PlyFailure {
        let strength_ratio = if index > 0.0 {
            1.0 / index
        } else if index.is_nan() {
            f64::NAN
        } else {
            f64::INFINITY
        };
        PlyFailure {
            index,
            strength_ratio,
            mode,
        }
    }
}

/// True when a stress has a NaN component.
#[inline]
pub fn has_nan(stress: &[f64; 6]) -> bool {
    stress.iter().any(|v| v.is_nan())
}

/// The smallest positive root `R` of `linear R + quadratic R^2 = 1`, the
/// strength ratio of a failure function `F = L + Q` with `L` of degree 1
/// and `Q >= 0` of degree 2 in the stress (`F(0) = 0`); `f64::INFINITY`
/// when there is none. Computed as `2 / (L + sqrt(L^2 + 4 Q))`, which has
/// no cancellation.
#[inline]
pub fn quadratic_strength_ratio(linear: f64, quadratic: f64) -> f64 {
    let denominator = linear + (linear * linear + 4.0 * quadratic.max(0.0)).sqrt();
    if denominator > 0.0 {
        2.0 / denominator
    } else if denominator.is_nan() {
        f64::NAN
    } else {
        f64::INFINITY
    }
}

/// A ply failure criterion.
pub trait PlyCriterion: Send + Sync + std::fmt::Debug {
    /// Registry key.
    fn key(&self) -> &'static str;
    /// Failure index, strength ratio and mode of the ply stress
    /// `[s11, s22, s33, t12, t23, t31]` in the ply material axes.
    fn evaluate(&self, stress: [f64; 6]) -> PlyFailure;
}

/// Registry entry of a ply failure criterion.
pub struct PlyCriterionEntry {
    /// Registry key, by which scenes name it (e.g. `hashin`).
    pub key: &'static str,
    /// One-line description, for listings (`junta list`).
    pub description: &'static str,
    /// Documentation of each key of its parameter table.
    pub params: &'static [ParamDoc],
    /// Builds the criterion from its parameter table.
    pub build: fn(&toml::Table) -> Result<Arc<dyn PlyCriterion>, CoreError>,
}
