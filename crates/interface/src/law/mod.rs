//! Traction-separation laws, one file each. A law sees only the jump in
//! the local frame `[delta_1, delta_2, delta_3]` (two slips, opening) and
//! its own committed state; it returns the traction `[tau_13, tau_23,
//! sigma_33]` and the consistent tangent. Adding a law is one file here plus
//! its `inventory::submit!`.
//!
//! A law also declares the kind of its tangent
//! ([`junta_core::InterfaceLaw::tangent_kind`]: softening laws are
//! symmetric indefinite, which makes the driver pick `ldlt`), names its
//! per-point outputs (`damage`, `dissipated_energy`, ...) and may give
//! fracture properties (for the mesh advice) and parameter warnings. The
//! fracture-energy laws compute in dual numbers ([`junta_core::Dual3`]), so
//! their tangents need no hand derivation.
//!
//! Plastic and frictional laws (`coulomb_friction`, `mohr_coulomb`,
//! `bilinear_friction`) keep a plastic jump in their state, return to their
//! yield surface in closed form and declare a general (nonsymmetric)
//! tangent, which makes the driver pick `lu`; they report the plastic slip,
//! the stick/slip/open state and the frictional dissipation.

pub mod bilinear;
pub mod bilinear_friction;
pub mod cohesive;
pub mod contact;
pub mod coulomb_friction;
pub mod exponential;
pub mod fatigue_cf20;
pub mod fatigue_paris;
pub mod linear_penalty;
pub mod mohr_coulomb;
pub mod paper_debond;
pub mod superposed;

use junta_core::CoreError;

/// The penalty stiffness `[d1, d2, d3]` of a law's parameter table: `d` for
/// all three directions, each of `d1`, `d2`, `d3` overriding it; every value
/// positive and finite. Errors name the law `key`.
pub fn penalty_stiffness(
    key: &str,
    d: Option<f64>,
    d123: [Option<f64>; 3],
) -> Result<[f64; 3], CoreError> {
    let invalid = |message: String| CoreError::InvalidParameters {
        kind: "law",
        key: key.into(),
        message,
    };
    let mut out = [0.0; 3];
    for (i, v) in d123.iter().enumerate() {
        let v = v
            .or(d)
            .ok_or_else(|| invalid(format!("give `d` (all directions) or `d{}`", i + 1)))?;
        if !(v > 0.0 && v.is_finite()) {
            return Err(invalid(format!(
                "d{} = {v} must be positive and finite (a penalty stiffness in force/length^3)",
                i + 1
            )));
        }
        out[i] = v;
    }
    Ok(out)
}
