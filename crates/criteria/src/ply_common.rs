//! What the ply criteria share: strength checks and errors, the ply
//! strengths, and the per-component maximum-stress ratios that label modes.

use junta_core::{CoreError, PlyFailureMode};

/// Kind name of the ply criteria in errors.
pub(crate) const KIND: &str = "ply criterion";

/// An error about the parameters of the ply criterion `key`.
pub(crate) fn invalid(key: &str, message: String) -> CoreError {
    CoreError::InvalidParameters {
        kind: KIND,
        key: key.into(),
        message,
    }
}

/// Check that a strength is positive and finite; the error names it.
pub(crate) fn check_strength(key: &str, name: &str, v: f64) -> Result<f64, CoreError> {
    if v > 0.0 && v.is_finite() {
        Ok(v)
    } else {
        Err(invalid(
            key,
            format!("`{name}` = {v} must be positive and finite (a strength in stress units)"),
        ))
    }
}

/// Check a dimensionless parameter lies in `[lo, hi)`; the error names it.
pub(crate) fn check_range(
    key: &str,
    name: &str,
    v: f64,
    lo: f64,
    hi: f64,
) -> Result<f64, CoreError> {
    if v >= lo && v < hi {
        Ok(v)
    } else {
        Err(invalid(
            key,
            format!("`{name}` = {v} must lie in [{lo}, {hi})"),
        ))
    }
}

/// The nine strengths of an orthotropic ply (stress units).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlyStrengths {
    /// Tensile strength along the fibres.
    pub xt: f64,
    /// Compressive strength along the fibres (a positive number).
    pub xc: f64,
    /// Transverse tensile strength (axis 2).
    pub yt: f64,
    /// Transverse compressive strength (axis 2, positive).
    pub yc: f64,
    /// Through-thickness tensile strength (axis 3).
    pub zt: f64,
    /// Through-thickness compressive strength (axis 3, positive).
    pub zc: f64,
    /// In-plane shear strength (1-2).
    pub s12: f64,
    /// Transverse shear strength (2-3).
    pub s23: f64,
    /// Shear strength 1-3.
    pub s13: f64,
}

impl PlyStrengths {
    /// Check that every strength is positive and finite.
    pub(crate) fn checked(self, key: &str) -> Result<Self, CoreError> {
        let named = [
            ("Xt", self.xt),
            ("Xc", self.xc),
            ("Yt", self.yt),
            ("Yc", self.yc),
            ("Zt", self.zt),
            ("Zc", self.zc),
            ("S12", self.s12),
            ("S23", self.s23),
            ("S13", self.s13),
        ];
        for (name, v) in named {
            check_strength(key, name, v)?;
        }
        Ok(self)
    }

    /// Each component divided by the strength of its sign, with its mode:
    /// `s11` fibre tension/compression, `s22` and `s33` matrix
    /// tension/compression, the shears matrix tension if `s22 + s33 >= 0`
    /// and matrix compression otherwise.
    pub fn component_ratios(&self, s: &[f64; 6]) -> [(f64, PlyFailureMode); 6] {
        use PlyFailureMode::*;
        let signed =
            |v: f64, t: f64, c: f64, mt, mc| if v >= 0.0 { (v / t, mt) } else { (-v / c, mc) };
        let shear_mode = if s[1] + s[2] >= 0.0 {
            MatrixTension
        } else {
            MatrixCompression
        };
        [
            signed(s[0], self.xt, self.xc, FibreTension, FibreCompression),
            signed(s[1], self.yt, self.yc, MatrixTension, MatrixCompression),
            signed(s[2], self.zt, self.zc, MatrixTension, MatrixCompression),
            (s[3].abs() / self.s12, shear_mode),
            (s[4].abs() / self.s23, shear_mode),
            (s[5].abs() / self.s13, shear_mode),
        ]
    }
}

/// The largest value of `candidates` and its mode (the first one on a tie);
/// `Interaction` when no value is positive.
pub(crate) fn governing(candidates: &[(f64, PlyFailureMode)]) -> (f64, PlyFailureMode) {
    let mut best = (0.0, PlyFailureMode::Interaction);
    for &(v, mode) in candidates {
        if v > best.0 {
            best = (v, mode);
        }
    }
    best
}
