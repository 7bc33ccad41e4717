//! `bimodular_penalty`: a linear penalty law with one normal stiffness in
//! opening and another in closure, and its own shear stiffness; written
//! outside Junta's crates and registered with `inventory::submit!`.
//!
//! ```text
//! tau_13 = ks delta_1,   tau_23 = ks delta_2
//! sigma_33 = kt delta_3  if delta_3 >= 0  (opening)
//!          = kc delta_3  if delta_3 <  0  (closure)
//! D = d t / d delta = diag(ks, ks, kt or kc)        [force/length^3]
//! ```
//!
//! No state; `ks`, `kt`, `kc` must be positive and finite. A stiff `kc`
//! with a soft `kt` models a bond that resists interpenetration more than
//! separation.

use junta_core::law::{InterfaceLaw, LawContext, LawError, LawResponse};
use junta_core::registry::{parse_params, LawEntry, ParamDoc};
use junta_core::CoreError;
use serde::Deserialize;
use std::sync::Arc;

/// Bimodular penalty law.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BimodularPenalty {
    /// Shear stiffness.
    pub ks: f64,
    /// Normal stiffness in opening.
    pub kt: f64,
    /// Normal stiffness in closure.
    pub kc: f64,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Params {
    ks: f64,
    kt: f64,
    kc: f64,
}

impl BimodularPenalty {
    /// From a TOML table `{ ks, kt, kc }`, each positive and finite.
    pub fn from_table(t: &toml::Table) -> Result<Self, CoreError> {
        let p: Params = parse_params("law", "bimodular_penalty", t)?;
        for (name, v) in [("ks", p.ks), ("kt", p.kt), ("kc", p.kc)] {
            if !(v.is_finite() && v > 0.0) {
                return Err(CoreError::InvalidParameters {
                    kind: "law",
                    key: "bimodular_penalty".into(),
                    message: format!("`{name}` = {v} must be positive and finite"),
                });
            }
        }
        Ok(BimodularPenalty {
            ks: p.ks,
            kt: p.kt,
            kc: p.kc,
        })
    }
}

impl InterfaceLaw for BimodularPenalty {
    fn key(&self) -> &'static str {
        "bimodular_penalty"
    }

    fn evaluate(&self, ctx: &LawContext<'_>, _state: &mut [f64]) -> Result<LawResponse, LawError> {
        let kn = if ctx.jump[2] >= 0.0 { self.kt } else { self.kc };
        let k = [self.ks, self.ks, kn];
        let mut r = LawResponse::default();
        for (i, ki) in k.into_iter().enumerate() {
            r.traction[i] = ki * ctx.jump[i];
            r.tangent[i][i] = ki;
        }
        Ok(r)
    }

    fn initial_stiffness(&self) -> [f64; 3] {
        [self.ks, self.ks, self.kt.max(self.kc)]
    }
}

inventory::submit! {
    LawEntry {
        key: "bimodular_penalty",
        description: "penalty with normal stiffness kt in opening, kc in closure, ks in shear (plugin example)",
        params: &[
            ParamDoc { name: "ks", doc: "shear stiffness [force/length^3]" },
            ParamDoc { name: "kt", doc: "normal stiffness in opening" },
            ParamDoc { name: "kc", doc: "normal stiffness in closure" },
        ],
        build: |t| Ok(Arc::new(BimodularPenalty::from_table(t)?)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use junta_core::element::StepInfo;

    fn law() -> BimodularPenalty {
        let t: toml::Table = toml::from_str("ks = 2e12\nkt = 1e13\nkc = 5e14").unwrap();
        BimodularPenalty::from_table(&t).unwrap()
    }

    fn eval(law: &BimodularPenalty, j: [f64; 3]) -> LawResponse {
        let ctx = LawContext {
            jump: j,
            state_committed: &[],
            step: StepInfo::default(),
        };
        law.evaluate(&ctx, &mut []).unwrap()
    }

    #[test]
    fn tangent_matches_central_differences_in_opening_and_closure() {
        let law = law();
        for jump in [[1e-6, -2e-6, 3e-7], [4e-7, 1e-6, -2e-7]] {
            let r = eval(&law, jump);
            let h = 1e-10; // well below |delta_3|: no crossing of the kink
            for k in 0..3 {
                let (mut a, mut b) = (jump, jump);
                a[k] += h;
                b[k] -= h;
                let (ta, tb) = (eval(&law, a).traction, eval(&law, b).traction);
                for i in 0..3 {
                    let fd = (ta[i] - tb[i]) / (2.0 * h);
                    assert!(
                        (fd - r.tangent[i][k]).abs() <= 1e-6 * 5e14,
                        "jump {jump:?}: d t{i}/d delta{k} = {fd} vs {}",
                        r.tangent[i][k]
                    );
                }
            }
        }
        assert_eq!(eval(&law, [0.0, 0.0, 1e-6]).traction[2], 1e7);
        assert_eq!(eval(&law, [0.0, 0.0, -1e-6]).traction[2], -5e8);
    }

    #[test]
    fn bad_parameters_are_rejected_with_the_key() {
        for bad in ["ks = 1\nkt = -1\nkc = 1", "ks = 1\nkt = 1\nkc = nan"] {
            let t: toml::Table = toml::from_str(bad).unwrap();
            assert!(BimodularPenalty::from_table(&t).is_err(), "{bad}");
        }
        let t: toml::Table = toml::from_str("ks = 1\nkt = 1\nkc = 1\nkn = 1").unwrap();
        let e = BimodularPenalty::from_table(&t).unwrap_err().to_string();
        assert!(e.contains("kn"), "{e}");
    }
}
