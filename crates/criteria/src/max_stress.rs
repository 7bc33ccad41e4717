//! `max_stress`: the maximum-stress criterion.
//!
//! ```text
//! index = max( s / sigma_lim,  sqrt(tau_13^2 + tau_23^2) / tau_lim ),   failed when index >= 1
//! s     = <sigma_33> = max(sigma_33, 0)   (compression = "positive_part", default)
//! s     = |sigma_33|                      (compression = "as_written")
//! ```
//!
//! With `as_written` a compressive normal traction counts by its magnitude,
//! the same convention as the quadratic criterion, which squares it.
//! Mode: `Tension` if `sigma_33 > 0`, `Compression` if `sigma_33 < 0`,
//! `Shear` if `sigma_33 == 0`. `sigma_lim`, `tau_lim` must be positive and
//! finite.

use crate::{check_limit, mode_of, read_stress_params, CompressionRule, STRESS_PARAMS};
use junta_core::registry::CriterionEntry;
use junta_core::{CoreError, Dual3, FailureCriterion, FailureResult, OnsetInput};
use std::sync::Arc;

/// Maximum-stress criterion.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MaxStress {
    /// Normal (tensile) strength.
    pub sigma_lim: f64,
    /// Shear strength.
    pub tau_lim: f64,
    /// Treatment of a compressive normal traction.
    pub compression: CompressionRule,
}

impl MaxStress {
    /// A criterion with strengths `sigma_lim`, `tau_lim` (positive, finite).
    pub fn new(
        sigma_lim: f64,
        tau_lim: f64,
        compression: CompressionRule,
    ) -> Result<Self, CoreError> {
        Ok(MaxStress {
            sigma_lim: check_limit("max_stress", "sigma_lim", sigma_lim)?,
            tau_lim: check_limit("max_stress", "tau_lim", tau_lim)?,
            compression,
        })
    }

    /// From a TOML table: `sigma_lim`, `tau_lim`, optional `compression`.
    pub fn from_table(t: &toml::Table) -> Result<Self, CoreError> {
        let (s, tau, c) = read_stress_params("max_stress", t)?;
        Self::new(s, tau, c)
    }
}

impl FailureCriterion for MaxStress {
    fn key(&self) -> &'static str {
        "max_stress"
    }

    fn evaluate(&self, t: [f64; 3]) -> FailureResult {
        let s = self.compression.normal(t[2]).abs() / self.sigma_lim;
        let tau = t[0].hypot(t[1]) / self.tau_lim;
        FailureResult {
            index: s.max(tau),
            mode: mode_of(t[2]),
        }
    }

    fn onset_index(&self, p: &OnsetInput) -> Option<Dual3> {
        let t = p.traction;
        let s = match self.compression {
            CompressionRule::PositivePart => t[2].pos(),
            CompressionRule::AsWritten => t[2].abs(),
        } / self.sigma_lim;
        let tau = (t[0] * t[0] + t[1] * t[1]).sqrt() / self.tau_lim;
        Some(s.max(tau))
    }

    fn degree(&self) -> f64 {
        1.0
    }
}

inventory::submit! {
    CriterionEntry {
        key: "max_stress",
        description: "maximum-stress criterion max(s33/sigma_lim, |tau|/tau_lim) >= 1",
        params: STRESS_PARAMS,
        build: |t| Ok(Arc::new(MaxStress::from_table(t)?)),
    }
}
