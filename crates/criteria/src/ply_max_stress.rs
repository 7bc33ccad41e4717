//! `ply_max_stress`: the maximum-stress criterion of a ply.
//!
//! ```text
//! index = max( s11/Xt or -s11/Xc,  s22/Yt or -s22/Yc,  s33/Zt or -s33/Zc,
//!              |t12|/S12,  |t23|/S23,  |t31|/S13 ),       failed when index >= 1
//! ```
//!
//! each normal stress over the strength of its sign (tension when `>= 0`).
//! The stress is `[s11, s22, s33, t12, t23, t31]` in the ply axes (1 fibre,
//! 2 transverse, 3 through the thickness). The index is positively
//! homogeneous of degree 1, so `strength_ratio = 1 / index`.
//!
//! Mode: that of the largest ratio (the first on a tie, in the order
//! above): `s11` fibre tension/compression; `s22`, `s33` matrix
//! tension/compression; a shear matrix tension when `s22 + s33 >= 0`,
//! matrix compression otherwise; `Interaction` for a zero stress.
//!
//! The oldest ply criterion; see e.g. Jones, *Mechanics of Composite
//! Materials*, 2nd ed. (1999), sec. 2.9.2.
//!
//! Parameters (stress units, positive, finite): `Xt`, `Xc`, `Yt`, `Yc`,
//! `S12`, `S23`; optional `Zt`, `Zc` (default `Yt`, `Yc`: transverse
//! isotropy) and `S13` (default `S12`).

use crate::ply_common::{governing, PlyStrengths, KIND};
use junta_core::ply_criterion::has_nan;
use junta_core::registry::{parse_params, ParamDoc, PlyCriterionEntry};
use junta_core::{CoreError, PlyCriterion, PlyFailure};
use serde::Deserialize;
use std::sync::Arc;

const KEY: &str = "ply_max_stress";

/// Maximum-stress ply criterion.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlyMaxStress {
    /// The ply strengths.
    pub strengths: PlyStrengths,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct Params {
    #[serde(rename = "Xt")]
    xt: f64,
    #[serde(rename = "Xc")]
    xc: f64,
    #[serde(rename = "Yt")]
    yt: f64,
    #[serde(rename = "Yc")]
    yc: f64,
    #[serde(rename = "Zt")]
    zt: Option<f64>,
    #[serde(rename = "Zc")]
    zc: Option<f64>,
    #[serde(rename = "S12")]
    s12: f64,
    #[serde(rename = "S23")]
    s23: f64,
    #[serde(rename = "S13")]
    s13: Option<f64>,
}

impl PlyMaxStress {
    /// A criterion with these strengths (each positive and finite).
    pub fn new(strengths: PlyStrengths) -> Result<Self, CoreError> {
        Ok(PlyMaxStress {
            strengths: strengths.checked(KEY)?,
        })
    }

    /// From a TOML table (see the module documentation).
    pub fn from_table(t: &toml::Table) -> Result<Self, CoreError> {
        let p: Params = parse_params(KIND, KEY, t)?;
        Self::new(PlyStrengths {
            xt: p.xt,
            xc: p.xc,
            yt: p.yt,
            yc: p.yc,
            zt: p.zt.unwrap_or(p.yt),
            zc: p.zc.unwrap_or(p.yc),
            s12: p.s12,
            s23: p.s23,
            s13: p.s13.unwrap_or(p.s12),
        })
    }
}

impl PlyCriterion for PlyMaxStress {
    fn key(&self) -> &'static str {
        KEY
    }

    fn evaluate(&self, stress: [f64; 6]) -> PlyFailure {
        if has_nan(&stress) {
            return PlyFailure::NAN;
        }
        let (index, mode) = governing(&self.strengths.component_ratios(&stress));
        PlyFailure::homogeneous(index, mode)
    }
}

/// Parameter documentation of `ply_max_stress` and `tsai_wu` (their
/// strengths).
pub(crate) const STRENGTH_PARAMS: [ParamDoc; 9] = [
    ParamDoc {
        name: "Xt",
        doc: "tensile strength along the fibres (axis 1), > 0 [stress]",
    },
    ParamDoc {
        name: "Xc",
        doc: "compressive strength along the fibres, a positive number [stress]",
    },
    ParamDoc {
        name: "Yt",
        doc: "transverse tensile strength (axis 2), > 0 [stress]",
    },
    ParamDoc {
        name: "Yc",
        doc: "transverse compressive strength, a positive number [stress]",
    },
    ParamDoc {
        name: "Zt",
        doc: "optional through-thickness tensile strength (axis 3; default Yt) [stress]",
    },
    ParamDoc {
        name: "Zc",
        doc: "optional through-thickness compressive strength (default Yc) [stress]",
    },
    ParamDoc {
        name: "S12",
        doc: "in-plane shear strength, > 0 [stress]",
    },
    ParamDoc {
        name: "S23",
        doc: "transverse shear strength (2-3), > 0 [stress]",
    },
    ParamDoc {
        name: "S13",
        doc: "optional shear strength 1-3 (default S12) [stress]",
    },
];

inventory::submit! {
    PlyCriterionEntry {
        key: KEY,
        description: "ply maximum stress: each stress component over the strength of its sign, index = the largest",
        params: &STRENGTH_PARAMS,
        build: |t| Ok(Arc::new(PlyMaxStress::from_table(t)?)),
    }
}
