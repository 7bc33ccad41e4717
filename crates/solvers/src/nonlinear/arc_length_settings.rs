//! The settings of path following (`[analysis.arc_length]`): their
//! meaning and defaults, the table `junta list` prints, and their ranges.
//! The driver that reads them: [`crate::arc_length`].

use junta_core::CoreError;
use serde::{Deserialize, Serialize};

/// Settings of the path-following driver (`[analysis.arc_length]`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ArcLengthSettings {
    /// Newton iterations an increment should take; the next path step is
    /// scaled by `sqrt(target_iterations / iterations)`. Default 5.
    pub target_iterations: usize,
    /// Stop after this many increments (bounds every run). Default 5000.
    pub max_increments: usize,
    /// Switch from the cylindrical arc length to the dissipation
    /// constraint after an increment that dissipated more than this
    /// fraction of the stored energy. Default 1e-4.
    pub switch_dissipation: f64,
    /// Smallest path step, as a fraction of the first one, before the run
    /// stops. Default 1e-6.
    pub min_step: f64,
    /// Largest dissipation per increment (energy units); `None`: no limit.
    pub max_dissipation: Option<f64>,
    /// Largest arc length as a multiple of the first one. Default 10.
    pub max_arc: f64,
    /// An arc-length (or the first, load-controlled) increment that
    /// dissipates more than this fraction of the stored energy is redone
    /// with a shorter arc: a long arc can jump from the loading path to
    /// another equilibrium branch (e.g. the fully cracked one) across a
    /// snap-back. Default 1e-2.
    pub max_arc_dissipation: f64,
    /// Start of the iterations of an increment under the dissipation
    /// constraint: `tangent` (default) starts from the converged state;
    /// `secant` extrapolates the last converged increment, scaled by the
    /// ratio of the dissipation steps.
    pub predictor: Predictor,
}

/// Start of an increment's iterations under the dissipation constraint
/// ([`ArcLengthSettings::predictor`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Predictor {
    /// `u = u_n`, `lambda = lambda_n`.
    #[default]
    Tangent,
    /// `u = u_n + (tau / tau_n) Δu_n`, `lambda = lambda_n + (tau / tau_n)
    /// Δlambda_n`: the last converged increment `n`, scaled.
    Secant,
}

impl Default for ArcLengthSettings {
    fn default() -> Self {
        ArcLengthSettings {
            target_iterations: 5,
            max_increments: 5000,
            switch_dissipation: 1e-4,
            min_step: 1e-6,
            max_dissipation: None,
            max_arc: 10.0,
            max_arc_dissipation: 1e-2,
            predictor: Predictor::Tangent,
        }
    }
}

/// `[analysis.arc_length]` keys with their meaning and default (printed by
/// `junta list`).
pub const PARAMETERS: &[(&str, &str)] = &[
    ("target_iterations", "Newton iterations an increment should take; the next path step scales with sqrt(target / iterations) (default 5)"),
    ("max_increments", "stop after this many increments (default 5000)"),
    ("switch_dissipation", "switch from the arc length to the dissipation constraint after an increment dissipating this fraction of the stored energy, when the laws report dissipation (default 1e-4)"),
    ("max_arc_dissipation", "an arc-length increment dissipating more than this fraction of the stored energy is redone shorter: a long arc can jump to another branch (default 1e-2)"),
    ("max_dissipation", "cap on the energy dissipated per increment, energy units (default: none)"),
    ("min_step", "smallest path step as a fraction of the first one before the run stops (default 1e-6)"),
    ("max_arc", "largest arc length as a multiple of the first one (default 10)"),
    ("predictor", "start of an increment under the dissipation constraint: \"tangent\" from the converged state (default), \"secant\" from the last increment extrapolated by the ratio of the dissipation steps (fewer iterations where a crack runs steadily on a fine mesh; it can jump across the saw-tooth of a coarse mesh, so it is not the default; a failed secant start is retried from the converged state before any cut-back)"),
];

impl ArcLengthSettings {
    /// Check the ranges of every setting.
    pub fn validate(&self) -> Result<(), CoreError> {
        let bad = |what: &str| Err(CoreError::Invalid(format!("arc-length settings: {what}")));
        if self.target_iterations == 0 {
            return bad("target_iterations must be >= 1");
        }
        if self.max_increments == 0 {
            return bad("max_increments must be >= 1");
        }
        if !(self.switch_dissipation > 0.0 && self.switch_dissipation.is_finite()) {
            return bad("switch_dissipation must be positive and finite");
        }
        if !(self.min_step > 0.0 && self.min_step < 1.0) {
            return bad("min_step must lie in (0, 1)");
        }
        if !(self.max_arc_dissipation > self.switch_dissipation
            && self.max_arc_dissipation.is_finite())
        {
            return bad("max_arc_dissipation must be finite and exceed switch_dissipation");
        }
        if !(self.max_arc >= 1.0 && self.max_arc.is_finite()) {
            return bad("max_arc must be >= 1 and finite");
        }
        if let Some(m) = self.max_dissipation {
            if !(m > 0.0 && m.is_finite()) {
                return bad("max_dissipation must be positive and finite");
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `junta list` documents every setting (and nothing else).
    #[test]
    fn parameter_docs_cover_every_setting() {
        let v = serde_json::to_value(ArcLengthSettings::default()).unwrap();
        let mut keys: Vec<&str> = v.as_object().unwrap().keys().map(|k| k.as_str()).collect();
        let mut documented: Vec<&str> = PARAMETERS.iter().map(|p| p.0).collect();
        keys.sort_unstable();
        documented.sort_unstable();
        assert_eq!(keys, documented);
    }

    #[test]
    fn settings_out_of_range_are_refused() {
        let ok = ArcLengthSettings::default();
        assert!(ok.validate().is_ok());
        for bad in [
            ArcLengthSettings {
                target_iterations: 0,
                ..ok.clone()
            },
            ArcLengthSettings {
                max_increments: 0,
                ..ok.clone()
            },
            ArcLengthSettings {
                switch_dissipation: f64::NAN,
                ..ok.clone()
            },
            ArcLengthSettings {
                min_step: 1.0,
                ..ok.clone()
            },
            ArcLengthSettings {
                max_arc: 0.5,
                ..ok.clone()
            },
            ArcLengthSettings {
                max_dissipation: Some(-1.0),
                ..ok.clone()
            },
            ArcLengthSettings {
                max_arc_dissipation: 1e-5,
                ..ok.clone()
            },
        ] {
            assert!(bad.validate().is_err(), "{bad:?}");
        }
    }
}
