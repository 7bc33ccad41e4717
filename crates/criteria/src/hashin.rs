//! `hashin`: Hashin's 3D ply failure criterion, four modes.
//!
//! Z. Hashin, "Failure criteria for unidirectional fiber composites",
//! J. Appl. Mech. 47 (1980) 329-334, eqs. (16)-(19) (fibre modes) and
//! (23)-(24) (matrix modes). Stress `[s11, s22, s33, t12, t23, t31]` in the
//! ply axes, `S_L = S12` (axial shear), `S_T = S23` (transverse shear):
//!
//! ```text
//! fibre tension      (s11 >= 0):  F_ft = (s11/Xt)^2 + (t12^2 + t31^2)/S12^2
//! fibre compression  (s11 <  0):  F_fc = (s11/Xc)^2
//! matrix tension     (I >= 0):    F_mt = (I/Yt)^2 + (t23^2 - s22 s33)/S23^2 + (t12^2 + t31^2)/S12^2
//! matrix compression (I <  0):    F_mc = [(Yc/(2 S23))^2 - 1] I/Yc + (I/(2 S23))^2
//!                                        + (t23^2 - s22 s33)/S23^2 + (t12^2 + t31^2)/S12^2
//! with I = s22 + s33;   index = max(F_fibre, F_matrix),   failed when index >= 1
//! ```
//!
//! Hashin writes the fibre-compression mode as `-s11 = Xc`; it is squared
//! here so that both fibre modes are of degree 2 (the same surface). The
//! fibre-tension, fibre-compression and matrix-tension functions are
//! quadratic forms (`R = 1/sqrt(F)`); the matrix-compression one is
//! `a + b` with `a` linear and `b = (s22 - s33)^2/(4 S23^2) + ... >= 0`
//! quadratic, so `R` is the positive root of `a R + b R^2 = 1`
//! ([`quadratic_strength_ratio`]). Scaling the stress by `R > 0` keeps the
//! signs of `s11` and `I`, hence the active modes: `strength_ratio` is the
//! smaller of the fibre and matrix ratios.
//!
//! Mode reported: the mode that fails first when the stress is scaled,
//! the one of the smaller strength ratio (matrix on a tie: pure shear
//! `t12 = S12` reaches both at once); `Interaction` when neither fails (a
//! zero stress). That is the mode of the larger index whenever both modes
//! are quadratic forms; with matrix compression's linear term (`S23 !=
//! Yc/2`) the index of matrix compression can be negative below failure
//! (e.g. `F_mc = -1/98` at `s22 = -Yc/2`, `S23 = 0.35 Yc`), and then the
//! index is the fibre value (0 with `s11 = 0`) while the mode is matrix
//! compression.
//!
//! Parameters (stress units, positive, finite): `Xt`, `Xc`, `Yt`, `Yc`,
//! `S12`; `S23` optional, default `Yc/2`. Hashin notes that `S_T` is hard to
//! measure; `Yc/2` is the transverse shear strength of a fracture plane at
//! 45 degrees without friction (Mohr-Coulomb with zero friction, which is
//! also LaRC04's `S_T = Yc cos a0 (sin a0 + cos a0 / tan 2a0)` at
//! `a0 = 45` degrees), and it is the value at which Hashin's compression
//! mode has no linear term. Transverse isotropy is assumed (`Zt = Yt`,
//! `Zc = Yc`, `S13 = S12`), as in Hashin's paper.

use crate::ply_common::{check_strength, KIND};
use junta_core::ply_criterion::{has_nan, quadratic_strength_ratio};
use junta_core::registry::{parse_params, ParamDoc, PlyCriterionEntry};
use junta_core::{CoreError, PlyCriterion, PlyFailure, PlyFailureMode};
use serde::Deserialize;
use std::sync::Arc;

const KEY: &str = "hashin";

/// Hashin's 3D criterion.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hashin {
    /// Tensile strength along the fibres.
    pub xt: f64,
    /// Compressive strength along the fibres (positive).
    pub xc: f64,
    /// Transverse tensile strength.
    pub yt: f64,
    /// Transverse compressive strength (positive).
    pub yc: f64,
    /// Axial shear strength `S_L`.
    pub s12: f64,
    /// Transverse shear strength `S_T`.
    pub s23: f64,
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
    #[serde(rename = "S12")]
    s12: f64,
    #[serde(rename = "S23")]
    s23: Option<f64>,
}

/// A failure function split into its linear and quadratic parts.
#[derive(Debug, Clone, Copy)]
struct ModeFunction {
    linear: f64,
    quadratic: f64,
    mode: PlyFailureMode,
}

impl ModeFunction {
    fn value(&self) -> f64 {
        self.linear + self.quadratic
    }
    fn ratio(&self) -> f64 {
        quadratic_strength_ratio(self.linear, self.quadratic)
    }
}

impl Hashin {
    /// A criterion with these strengths (each positive and finite).
    pub fn new(xt: f64, xc: f64, yt: f64, yc: f64, s12: f64, s23: f64) -> Result<Self, CoreError> {
        Ok(Hashin {
            xt: check_strength(KEY, "Xt", xt)?,
            xc: check_strength(KEY, "Xc", xc)?,
            yt: check_strength(KEY, "Yt", yt)?,
            yc: check_strength(KEY, "Yc", yc)?,
            s12: check_strength(KEY, "S12", s12)?,
            s23: check_strength(KEY, "S23", s23)?,
        })
    }

    /// From a TOML table (see the module documentation).
    pub fn from_table(t: &toml::Table) -> Result<Self, CoreError> {
        let p: Params = parse_params(KIND, KEY, t)?;
        Self::new(p.xt, p.xc, p.yt, p.yc, p.s12, p.s23.unwrap_or(0.5 * p.yc))
    }

    fn fibre(&self, s: &[f64; 6]) -> ModeFunction {
        if s[0] >= 0.0 {
            let axial_shear = (s[3] * s[3] + s[5] * s[5]) / (self.s12 * self.s12);
            ModeFunction {
                linear: 0.0,
                quadratic: (s[0] / self.xt).powi(2) + axial_shear,
                mode: PlyFailureMode::FibreTension,
            }
        } else {
            ModeFunction {
                linear: 0.0,
                quadratic: (s[0] / self.xc).powi(2),
                mode: PlyFailureMode::FibreCompression,
            }
        }
    }

    fn matrix(&self, s: &[f64; 6]) -> ModeFunction {
        let i2 = s[1] + s[2];
        let axial_shear = (s[3] * s[3] + s[5] * s[5]) / (self.s12 * self.s12);
        let transverse_shear = (s[4] * s[4] - s[1] * s[2]) / (self.s23 * self.s23);
        if i2 >= 0.0 {
            ModeFunction {
                linear: 0.0,
                quadratic: (i2 / self.yt).powi(2) + transverse_shear + axial_shear,
                mode: PlyFailureMode::MatrixTension,
            }
        } else {
            let k = self.yc / (2.0 * self.s23);
            ModeFunction {
                linear: (k * k - 1.0) * i2 / self.yc,
                quadratic: (i2 / (2.0 * self.s23)).powi(2) + transverse_shear + axial_shear,
                mode: PlyFailureMode::MatrixCompression,
            }
        }
    }
}

impl PlyCriterion for Hashin {
    fn key(&self) -> &'static str {
        KEY
    }

    fn evaluate(&self, stress: [f64; 6]) -> PlyFailure {
        if has_nan(&stress) {
            return PlyFailure::NAN;
        }
        let fibre = self.fibre(&stress);
        let matrix = self.matrix(&stress);
        let (fibre_ratio, matrix_ratio) = (fibre.ratio(), matrix.ratio());
        let first = if fibre_ratio < matrix_ratio {
            fibre
        } else {
            matrix
        };
        let strength_ratio = fibre_ratio.min(matrix_ratio);
        PlyFailure {
            index: fibre.value().max(matrix.value()),
            strength_ratio,
            mode: if strength_ratio.is_finite() {
                first.mode
            } else {
                PlyFailureMode::Interaction
            },
        }
    }
}

inventory::submit! {
    PlyCriterionEntry {
        key: KEY,
        description: "Hashin (1980) 3D: fibre tension/compression, matrix tension/compression (quadratic stress modes)",
        params: &[
            ParamDoc { name: "Xt", doc: "tensile strength along the fibres, > 0 [stress]" },
            ParamDoc { name: "Xc", doc: "compressive strength along the fibres, a positive number [stress]" },
            ParamDoc { name: "Yt", doc: "transverse tensile strength, > 0 [stress]" },
            ParamDoc { name: "Yc", doc: "transverse compressive strength, a positive number [stress]" },
            ParamDoc { name: "S12", doc: "axial (in-plane) shear strength S_L, > 0 [stress]" },
            ParamDoc { name: "S23", doc: "optional transverse shear strength S_T (default Yc/2: a 45-degree fracture plane without friction) [stress]" },
        ],
        build: |t| Ok(Arc::new(Hashin::from_table(t)?)),
    }
}
