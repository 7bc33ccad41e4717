//! `tsai_wu`: the Tsai-Wu quadratic polynomial criterion in 3D.
//!
//! S. W. Tsai, E. M. Wu, "A general theory of strength for anisotropic
//! materials", J. Compos. Mater. 5 (1971) 58-80. With the stress
//! `[s11, s22, s33, t12, t23, t31]` in the ply axes:
//!
//! ```text
//! F = F1 s11 + F2 s22 + F3 s33
//!   + F11 s11^2 + F22 s22^2 + F33 s33^2 + 2 F12 s11 s22 + 2 F13 s11 s33 + 2 F23 s22 s33
//!   + F44 t23^2 + F55 t31^2 + F66 t12^2,                  failed when F >= 1
//!
//! F1 = 1/Xt - 1/Xc   F11 = 1/(Xt Xc)   (and likewise F2, F22 with Y, F3, F33 with Z)
//! F66 = 1/S12^2      F55 = 1/S13^2     F44 = 1/S23^2
//! F12 = f12_star / sqrt(Xt Xc Yt Yc)   F13 = f12_star / sqrt(Xt Xc Zt Zc)
//! F23 = sqrt(F22 F33) - F44/2
//! ```
//!
//! Assumptions, those of a transversely isotropic ply (isotropic in the 2-3
//! plane; `Zt = Yt`, `Zc = Yc`, `S13 = S12` by default): the normalised 1-3
//! interaction equals the 1-2 one (`F13` from `f12_star`), and the 2-3
//! terms satisfy the isotropy relation `F44 = 2 (F22 - F23)` (a rotation
//! about axis 1 leaves `F` unchanged), which yields `F23` from `S23`.
//! `S23` defaults to `Yc/2`, as for [`hashin`](crate::hashin) (the
//! transverse shear strength of a 45-degree fracture plane without
//! friction). Giving `F23` the normalised interaction -0.5 too (the
//! "generalised von Mises" choice) would make the quadratic form only
//! semi-definite (no failure under a normalised hydrostatic stress), so it
//! is not offered.
//!
//! `F` is one expression: `index = F` (negative under some compressions),
//! and `strength_ratio` is the positive root of `L R + Q R^2 = 1` with `L`
//! the linear and `Q` the quadratic part. The parameters are refused unless
//! the 3x3 matrix of `F11 .. F33` is positive definite (a closed failure
//! surface, so that `Q > 0` for any nonzero stress and `R` is finite).
//!
//! Mode reported: the mode of the stress component with the largest ratio
//! to the strength of its sign (the maximum-stress mode of
//! [`PlyStrengths::component_ratios`](crate::PlyStrengths::component_ratios):
//! `s11` fibre, `s22`/`s33` matrix tension/compression, shears matrix
//! tension or compression by the sign of `s22 + s33`); `Interaction` for a
//! zero stress.
//!
//! Parameters (stress units, positive, finite): `Xt`, `Xc`, `Yt`, `Yc`,
//! `S12`; optional `Zt`, `Zc` (default `Yt`, `Yc`), `S13` (default `S12`),
//! `S23` (default `Yc/2`) and `f12_star` (dimensionless, in (-1, 1), default
//! -0.5).

use crate::ply_common::{governing, invalid, PlyStrengths, KIND};
use crate::ply_max_stress::STRENGTH_PARAMS;
use junta_core::ply_criterion::{has_nan, quadratic_strength_ratio};
use junta_core::registry::{parse_params, ParamDoc, PlyCriterionEntry};
use junta_core::{CoreError, PlyCriterion, PlyFailure};
use serde::Deserialize;
use std::sync::Arc;

const KEY: &str = "tsai_wu";

/// The Tsai-Wu criterion, with its coefficients.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TsaiWu {
    /// The strengths.
    pub strengths: PlyStrengths,
    /// Normalised interaction `F12 / sqrt(F11 F22)`.
    pub f12_star: f64,
    /// `[F1, F2, F3]`.
    pub linear: [f64; 3],
    /// `[[F11, F12, F13], [F12, F22, F23], [F13, F23, F33]]`.
    pub normal: [[f64; 3]; 3],
    /// `[F66, F44, F55]`, the coefficients of `t12^2, t23^2, t31^2`.
    pub shear: [f64; 3],
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
    s23: Option<f64>,
    #[serde(rename = "S13")]
    s13: Option<f64>,
    f12_star: Option<f64>,
}

/// True when the symmetric 3x3 matrix is positive definite (leading minors).
fn positive_definite(m: &[[f64; 3]; 3]) -> bool {
    let minor2 = m[0][0] * m[1][1] - m[0][1] * m[0][1];
    let det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[1][2])
        - m[0][1] * (m[0][1] * m[2][2] - m[1][2] * m[0][2])
        + m[0][2] * (m[0][1] * m[1][2] - m[1][1] * m[0][2]);
    m[0][0] > 0.0 && minor2 > 0.0 && det > 0.0
}

impl TsaiWu {
    /// A criterion from the strengths (each positive and finite) and the
    /// normalised interaction `f12_star` in (-1, 1).
    pub fn new(strengths: PlyStrengths, f12_star: f64) -> Result<Self, CoreError> {
        let st = strengths.checked(KEY)?;
        if !(f12_star > -1.0 && f12_star < 1.0) {
            return Err(invalid(
                KEY,
                format!("`f12_star` = {f12_star} must lie in (-1, 1)"),
            ));
        }
        let f11 = 1.0 / (st.xt * st.xc);
        let f22 = 1.0 / (st.yt * st.yc);
        let f33 = 1.0 / (st.zt * st.zc);
        let f12 = f12_star * (f11 * f22).sqrt();
        let f13 = f12_star * (f11 * f33).sqrt();
        let f44 = 1.0 / (st.s23 * st.s23);
        let f23 = (f22 * f33).sqrt() - 0.5 * f44;
        let normal = [[f11, f12, f13], [f12, f22, f23], [f13, f23, f33]];
        if !positive_definite(&normal) {
            return Err(invalid(
                KEY,
                format!("the interaction terms (f12_star = {f12_star}, F23 = {f23:e} from S23) open the failure surface: [F11 F12 F13; F12 F22 F23; F13 F23 F33] must be positive definite; with the default Z strengths this needs at least S23 > sqrt(Yt Yc)/2 = {:e}", 0.5 / f22.sqrt()),
            ));
        }
        Ok(TsaiWu {
            strengths: st,
            f12_star,
            linear: [
                1.0 / st.xt - 1.0 / st.xc,
                1.0 / st.yt - 1.0 / st.yc,
                1.0 / st.zt - 1.0 / st.zc,
            ],
            normal,
            shear: [1.0 / (st.s12 * st.s12), f44, 1.0 / (st.s13 * st.s13)],
        })
    }

    /// From a TOML table (see the module documentation).
    pub fn from_table(t: &toml::Table) -> Result<Self, CoreError> {
        let p: Params = parse_params(KIND, KEY, t)?;
        let strengths = PlyStrengths {
            xt: p.xt,
            xc: p.xc,
            yt: p.yt,
            yc: p.yc,
            zt: p.zt.unwrap_or(p.yt),
            zc: p.zc.unwrap_or(p.yc),
            s12: p.s12,
            s23: p.s23.unwrap_or(0.5 * p.yc),
            s13: p.s13.unwrap_or(p.s12),
        };
        Self::new(strengths, p.f12_star.unwrap_or(-0.5))
    }

    /// The linear and quadratic parts `(L, Q)` of `F` at `s`.
    pub fn parts(&self, s: &[f64; 6]) -> (f64, f64) {
        let n = [s[0], s[1], s[2]];
        let mut linear = 0.0;
        let mut quadratic = 0.0;
        for i in 0..3 {
            linear += self.linear[i] * n[i];
            for j in 0..3 {
                quadratic += self.normal[i][j] * n[i] * n[j];
            }
        }
        quadratic +=
            self.shear[0] * s[3] * s[3] + self.shear[1] * s[4] * s[4] + self.shear[2] * s[5] * s[5];
        (linear, quadratic)
    }
}

impl PlyCriterion for TsaiWu {
    fn key(&self) -> &'static str {
        KEY
    }

    fn evaluate(&self, stress: [f64; 6]) -> PlyFailure {
        if has_nan(&stress) {
            return PlyFailure::NAN;
        }
        let (linear, quadratic) = self.parts(&stress);
        let (_, mode) = governing(&self.strengths.component_ratios(&stress));
        PlyFailure {
            index: linear + quadratic,
            strength_ratio: quadratic_strength_ratio(linear, quadratic),
            mode,
        }
    }
}

const PARAMS: [ParamDoc; 10] = [
    STRENGTH_PARAMS[0],
    STRENGTH_PARAMS[1],
    STRENGTH_PARAMS[2],
    STRENGTH_PARAMS[3],
    STRENGTH_PARAMS[4],
    STRENGTH_PARAMS[5],
    STRENGTH_PARAMS[6],
    ParamDoc {
        name: "S23",
        doc: "optional transverse shear strength (2-3), default Yc/2 [stress]; gives F23 = sqrt(F22 F33) - 1/(2 S23^2) (transverse isotropy)",
    },
    STRENGTH_PARAMS[8],
    ParamDoc {
        name: "f12_star",
        doc: "optional normalised interaction F12/sqrt(F11 F22), in (-1, 1) (default -0.5)",
    },
];

inventory::submit! {
    PlyCriterionEntry {
        key: KEY,
        description: "Tsai-Wu (1971) 3D quadratic polynomial, interaction f12_star",
        params: &PARAMS,
        build: |t| Ok(Arc::new(TsaiWu::from_table(t)?)),
    }
}
