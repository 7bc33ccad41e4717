//! `quadratic`: the paper's quadratic (Hill-type) stress criterion (eq. 40).
//!
//! ```text
//! index = (s / sigma_lim)^2 + (tau_13^2 + tau_23^2) / tau_lim^2,   failed when index >= 1
//! s     = <sigma_33> = max(sigma_33, 0)   (compression = "positive_part", default)
//! s     = sigma_33                        (compression = "as_written", the paper's form)
//! ```
//!
//! As a damage-onset criterion of a softening law ([`FailureCriterion::onset_index`])
//! the same index of the undamaged traction, degree 2 in the jump: with one
//! penalty K the onset jump along a direction of mixity
//! `beta = delta_shear / delta_n` is Camanho & Davila's (2002)
//! `delta_0m = delta_0n delta_0s sqrt(1 + beta^2) / sqrt(delta_0s^2 + (beta delta_0n)^2)`
//! (Abaqus QUADS).
//!
//! Mode: `Tension` if `sigma_33 > 0`, `Compression` if `sigma_33 < 0`,
//! `Shear` if `sigma_33 == 0`. `sigma_lim`, `tau_lim` must be positive and
//! finite.

use crate::{check_limit, mode_of, read_stress_params, CompressionRule, STRESS_PARAMS};
use junta_core::registry::CriterionEntry;
use junta_core::{CoreError, Dual3, FailureCriterion, FailureResult, OnsetInput};
use std::sync::Arc;

/// Quadratic stress criterion (paper eq. 40).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Quadratic {
    /// Normal (tensile) strength.
    pub sigma_lim: f64,
    /// Shear strength.
    pub tau_lim: f64,
    /// Treatment of a compressive normal traction.
    pub compression: CompressionRule,
}

impl Quadratic {
    /// A criterion with strengths `sigma_lim`, `tau_lim` (positive, finite).
    pub fn new(
        sigma_lim: f64,
        tau_lim: f64,
        compression: CompressionRule,
    ) -> Result<Self, CoreError> {
        Ok(Quadratic {
            sigma_lim: check_limit("quadratic", "sigma_lim", sigma_lim)?,
            tau_lim: check_limit("quadratic", "tau_lim", tau_lim)?,
            compression,
        })
    }

    /// From a TOML table: `sigma_lim`, `tau_lim`, optional `compression`.
    pub fn from_table(t: &toml::Table) -> Result<Self, CoreError> {
        let (s, tau, c) = read_stress_params("quadratic", t)?;
        Self::new(s, tau, c)
    }
}

impl FailureCriterion for Quadratic {
    fn key(&self) -> &'static str {
        "quadratic"
    }

    fn evaluate(&self, t: [f64; 3]) -> FailureResult {
        let s = self.compression.normal(t[2]) / self.sigma_lim;
        let a = t[0] / self.tau_lim;
        let b = t[1] / self.tau_lim;
        FailureResult {
            index: s * s + (a * a + b * b),
            mode: mode_of(t[2]),
        }
    }

    fn onset_index(&self, p: &OnsetInput) -> Option<Dual3> {
        let t = p.traction;
        let s = match self.compression {
            CompressionRule::PositivePart => t[2].pos(),
            CompressionRule::AsWritten => t[2],
        } / self.sigma_lim;
        let a = t[0] / self.tau_lim;
        let b = t[1] / self.tau_lim;
        Some(s * s + a * a + b * b)
    }

    fn degree(&self) -> f64 {
        2.0
    }
}

inventory::submit! {
    CriterionEntry {
        key: "quadratic",
        description: "quadratic stress criterion (s33/sigma_lim)^2 + (t13^2+t23^2)/tau_lim^2 >= 1 (paper eq. 40)",
        params: STRESS_PARAMS,
        build: |t| Ok(Arc::new(Quadratic::from_table(t)?)),
    }
}
