//! # junta-criteria
//!
//! Failure (damage-initiation) criteria behind [`junta_core::FailureCriterion`],
//! one file each, registered with `inventory`:
//!
//! - [`quadratic`]: the paper's quadratic (Hill-type) stress criterion (eq. 40);
//! - [`max_stress`]: the maximum-stress criterion;
//! - [`bk`]: Turon's energy-consistent BK onset criterion (needs the law's
//!   penalties, so it is meant for softening laws).
//!
//! Softening laws evaluate a criterion on the undamaged traction of the
//! jump through [`junta_core::FailureCriterion::onset_index`] (a dual number:
//! index and gradient), which all three implement.
//!
//! Both act on the local traction `[tau_13, tau_23, sigma_33]` and share the
//! [`CompressionRule`] option: `positive_part` (default) uses
//! `<sigma_33> = max(sigma_33, 0)`, so that compression never breaks the bond
//! by itself (Camanho-Davila practice); `as_written` uses `sigma_33` whatever
//! its sign (the paper's literal eq. 40).
//!
//! Mode reported by both ([`FailureMode`]): `Tension` if `sigma_33 > 0`,
//! `Compression` if `sigma_33 < 0`, `Shear` if `sigma_33 == 0` (see
//! [`mode_of`]). The mode depends on the sign of the normal traction only,
//! not on which term dominates the index.
//!
//! Ply failure criteria behind [`junta_core::PlyCriterion`], outputs
//! evaluated on the stress of a ply in its material axes
//! `[s11, s22, s33, t12, t23, t31]` (not progressive damage), each giving a
//! failure index, the strength ratio (the factor on the stress state that
//! fails it exactly) and a [`junta_core::PlyFailureMode`]; one file each,
//! registered as [`junta_core::registry::PlyCriterionEntry`]
//! (see `docs/ply_criteria.md`):
//!
//! - [`ply_max_stress`]: maximum stress, each component over its strength;
//! - [`hashin`]: Hashin (1980) 3D, fibre and matrix tension/compression;
//! - [`tsai_wu`]: Tsai-Wu (1971) 3D quadratic polynomial;
//! - [`puck`]: Puck & Schürmann (1998/2002), fibre fracture by maximum
//!   stress and inter-fibre fracture on the action plane (fracture-angle
//!   search).
//!
//! An embedder that builds criteria by name must reference this crate
//! (`use junta_criteria as _;`) so that the linker keeps the registrations.

#![warn(missing_docs)]

use junta_core::{CoreError, FailureMode};
use serde::Deserialize;

pub mod bk;
pub mod hashin;
pub mod max_stress;
mod ply_common;
pub mod ply_max_stress;
pub mod puck;
pub mod quadratic;
pub mod tsai_wu;

pub use bk::Bk;
pub use hashin::Hashin;
pub use max_stress::MaxStress;
pub use ply_common::PlyStrengths;
pub use ply_max_stress::PlyMaxStress;
pub use puck::{ActionPlane, Puck};
pub use quadratic::Quadratic;
pub use tsai_wu::TsaiWu;

/// How a criterion treats a compressive normal traction.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum CompressionRule {
    /// Use `<sigma_33> = max(sigma_33, 0)`: compression alone never fails
    /// the bond (default).
    #[default]
    PositivePart,
    /// Use `sigma_33` whatever its sign (the paper's eq. 40 as written).
    AsWritten,
}

impl CompressionRule {
    /// The normal traction the criterion uses.
    #[inline]
    pub fn normal(self, s33: f64) -> f64 {
        match self {
            CompressionRule::PositivePart => s33.max(0.0),
            CompressionRule::AsWritten => s33,
        }
    }
}

/// Mode from the sign of the normal traction: `Tension` if `s33 > 0`,
/// `Compression` if `s33 < 0`, `Shear` if `s33 == 0`.
#[inline]
pub fn mode_of(s33: f64) -> FailureMode {
    if s33 > 0.0 {
        FailureMode::Tension
    } else if s33 < 0.0 {
        FailureMode::Compression
    } else {
        FailureMode::Shear
    }
}

/// Parameters shared by the stress criteria (TOML).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct StressParams {
    pub sigma_lim: Option<f64>,
    pub tau_lim: Option<f64>,
    pub compression: Option<CompressionRule>,
}

/// Check that a strength is positive and finite; the error names the key.
pub(crate) fn check_limit(criterion: &str, name: &str, v: f64) -> Result<f64, CoreError> {
    if v > 0.0 && v.is_finite() {
        Ok(v)
    } else {
        Err(CoreError::InvalidParameters {
            kind: "criterion",
            key: criterion.into(),
            message: format!(
                "`{name}` = {v} must be positive and finite (a strength in stress units)"
            ),
        })
    }
}

/// Read `sigma_lim`, `tau_lim` and `compression` from a table.
pub(crate) fn read_stress_params(
    criterion: &str,
    t: &toml::Table,
) -> Result<(f64, f64, CompressionRule), CoreError> {
    let p: StressParams = junta_core::registry::parse_params("criterion", criterion, t)?;
    let need = |v: Option<f64>, name: &str, what: &str| {
        v.ok_or_else(|| CoreError::InvalidParameters {
            kind: "criterion",
            key: criterion.into(),
            message: format!("missing `{name}` ({what}, > 0)"),
        })
    };
    Ok((
        need(p.sigma_lim, "sigma_lim", "normal (tensile) strength")?,
        need(p.tau_lim, "tau_lim", "shear strength")?,
        p.compression.unwrap_or_default(),
    ))
}

/// Parameter documentation shared by the stress criteria.
pub(crate) const STRESS_PARAMS: &[junta_core::registry::ParamDoc] = &[
    junta_core::registry::ParamDoc {
        name: "sigma_lim",
        doc: "normal (tensile) strength, > 0 [stress]",
    },
    junta_core::registry::ParamDoc {
        name: "tau_lim",
        doc: "shear strength, > 0 [stress]",
    },
    junta_core::registry::ParamDoc {
        name: "compression",
        doc: "\"positive_part\" (default: <sigma_33>, compression never fails the bond) or \"as_written\" (sigma_33 squared whatever its sign, the paper's eq. 40)",
    },
];
