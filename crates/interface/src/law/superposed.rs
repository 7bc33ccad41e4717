//! `superposed`: two or more laws acting in parallel at every point, e.g.
//! an initiation law and a bridging law of low strength and long reach
//! (fibre bridging in a DCB), whose sum is a trilinear law and gives a
//! rising R-curve (Davila, Rose & Camanho 2009, "A procedure for
//! superposing linear cohesive laws to represent multiple damage
//! mechanisms in the fracture of composites", Int. J. Fract. 158, 211-223).
//!
//! Every law sees the same jump `delta` and keeps its own state; the point
//! carries the sum:
//!
//! ```text
//! t(delta) = sum_i t_i(delta),     dt/ddelta = sum_i dt_i/ddelta
//! ```
//!
//! so that the energy dissipated to full separation is the sum of the
//! laws' toughnesses, and the R-curve of a specimen rises from the first
//! law's toughness (the crack tip, where it has failed) to the sum (the
//! bridging zone behind the tip fully developed).
//!
//! State: the laws' states one after the other. Outputs: each law's
//! outputs as `law<i>.<name>` (`law1.damage`, `law2.dissipated_energy`,
//! ...), and the shared names summed over the laws that report them
//! (`dissipated_energy`, `viscous_energy`, `frictional_dissipation`); the
//! point's `damage` is the first law's. A point has failed
//! ([`junta_core::PointStage::Failed`]) when every law has, having
//! dissipated the sum of the toughnesses: the crack front is where the
//! bridging law is exhausted too, and the process zone spans the
//! initiation law's softening and the bridging zone. The tangent kind is the
//! widest of the laws'; the fracture properties (for the mesh advice) are
//! those of the sum: strengths, toughnesses and penalties added.
//!
//! ```toml
//! [laws.r_curve]
//! type = "superposed"
//! [[laws.r_curve.laws]]        # the initiation law
//! type = "bilinear"
//! K = 1.0e6
//! N = 60.0
//! ...
//! [[laws.r_curve.laws]]        # the bridging law
//! type = "bilinear"
//! ...
//! ```

use junta_core::law::{output, FractureProperties, LawContext, LawError, LawResponse};
use junta_core::registry::{build_law, LawEntry, ParamDoc};
use junta_core::solver::MatrixKind;
use junta_core::{CoreError, InterfaceLaw};
use std::sync::Arc;

/// Outputs summed over the laws.
const SUMMED: [&str; 3] = [
    output::DISSIPATED_ENERGY,
    output::VISCOUS_ENERGY,
    output::FRICTIONAL_DISSIPATION,
];

/// The most laws one point may carry (bounds the output buffer on the
/// stack).
pub const MAX_LAWS: usize = 8;

/// Largest number of outputs one law may report here.
const MAX_LAW_OUTPUTS: usize = 32;

/// Laws in parallel.
#[derive(Debug)]
pub struct Superposed {
    laws: Vec<Arc<dyn InterfaceLaw>>,
    /// Start of each law's state in the point's state.
    offsets: Vec<usize>,
    state_len: usize,
    /// `damage`, the summed names, then `law<i>.<name>` per law.
    names: &'static [&'static str],
}

impl Superposed {
    /// From already built laws (at least two, at most [`MAX_LAWS`]).
    pub fn new(laws: Vec<Arc<dyn InterfaceLaw>>) -> Result<Self, CoreError> {
        let invalid = |message: String| CoreError::InvalidParameters {
            kind: "law",
            key: "superposed".into(),
            message,
        };
        if laws.len() < 2 || laws.len() > MAX_LAWS {
            return Err(invalid(format!(
                "`laws` has {} entries: give 2 to {MAX_LAWS} laws, each a table with its `type`",
                laws.len()
            )));
        }
        if let Some(l) = laws.iter().find(|l| l.is_batched()) {
            return Err(invalid(format!(
                "law `{}` is evaluated in batches (a run-time law) and cannot be superposed",
                l.key()
            )));
        }
        if let Some(l) = laws
            .iter()
            .find(|l| l.output_names().len() > MAX_LAW_OUTPUTS)
        {
            return Err(invalid(format!(
                "law `{}` reports more than {MAX_LAW_OUTPUTS} outputs",
                l.key()
            )));
        }
        let mut offsets = Vec::with_capacity(laws.len());
        let mut state_len = 0;
        for l in &laws {
            offsets.push(state_len);
            state_len += l.state_len();
        }
        let mut names: Vec<&'static str> = vec![output::DAMAGE];
        names.extend(SUMMED);
        for (i, l) in laws.iter().enumerate() {
            for n in l.output_names() {
                // one string per output of a law built once per scene: a
                // bounded leak that gives the trait its `'static` names
                names.push(Box::leak(format!("law{}.{n}", i + 1).into_boxed_str()));
            }
        }
        Ok(Superposed {
            laws,
            offsets,
            state_len,
            names: Box::leak(names.into_boxed_slice()),
        })
    }

    /// From the scene table: `laws`, an array of tables, each with the
    /// `type` of a registered law and its parameters.
    pub fn from_table(t: &toml::Table) -> Result<Self, CoreError> {
        let invalid = |message: String| CoreError::InvalidParameters {
            kind: "law",
            key: "superposed".into(),
            message,
        };
        if let Some(k) = t.keys().find(|k| *k != "laws") {
            return Err(invalid(format!("unknown key `{k}`; valid: laws")));
        }
        let Some(toml::Value::Array(list)) = t.get("laws") else {
            return Err(invalid(
                "give `laws`, an array of tables ([[laws.NAME.laws]]), each with its `type`".into(),
            ));
        };
        let mut laws = Vec::with_capacity(list.len());
        for (i, v) in list.iter().enumerate() {
            let Some(table) = v.as_table() else {
                return Err(invalid(format!("`laws[{i}]` is not a table")));
            };
            let mut table = table.clone();
            let Some(toml::Value::String(key)) = table.remove("type") else {
                return Err(invalid(format!(
                    "`laws[{i}].type` is missing or not a string"
                )));
            };
            if key == "superposed" {
                return Err(invalid(format!(
                    "`laws[{i}]`: a superposed law cannot nest another"
                )));
            }
            let law = build_law(&key, &table)
                .map_err(|e| invalid(format!("`laws[{i}]` (`{key}`): {e}")))?;
            laws.push(law);
        }
        Self::new(laws)
    }

    /// The laws, in order.
    pub fn laws(&self) -> &[Arc<dyn InterfaceLaw>] {
        &self.laws
    }

    fn state_of<'s>(&self, i: usize, state: &'s [f64]) -> &'s [f64] {
        &state[self.offsets[i]..self.offsets[i] + self.laws[i].state_len()]
    }
}

impl InterfaceLaw for Superposed {
    fn key(&self) -> &'static str {
        "superposed"
    }

    fn state_len(&self) -> usize {
        self.state_len
    }

    fn init_state(&self, state: &mut [f64]) {
        for (i, l) in self.laws.iter().enumerate() {
            l.init_state(&mut state[self.offsets[i]..self.offsets[i] + l.state_len()]);
        }
    }

    fn evaluate(
        &self,
        ctx: &LawContext<'_>,
        state_trial: &mut [f64],
    ) -> Result<LawResponse, LawError> {
        let mut sum = LawResponse::default();
        for (i, l) in self.laws.iter().enumerate() {
            let range = self.offsets[i]..self.offsets[i] + l.state_len();
            let part = LawContext {
                jump: ctx.jump,
                state_committed: &ctx.state_committed[range.clone()],
                step: ctx.step,
            };
            let r = l.evaluate(&part, &mut state_trial[range])?;
            for a in 0..3 {
                sum.traction[a] += r.traction[a];
                for b in 0..3 {
                    sum.tangent[a][b] += r.tangent[a][b];
                }
            }
        }
        Ok(sum)
    }

    fn initial_stiffness(&self) -> [f64; 3] {
        let mut k = [0.0; 3];
        for l in &self.laws {
            let ki = l.initial_stiffness();
            for a in 0..3 {
                k[a] += ki[a];
            }
        }
        k
    }

    fn wants_small_increments(&self, state: &[f64]) -> bool {
        (0..self.laws.len()).any(|i| self.laws[i].wants_small_increments(self.state_of(i, state)))
    }

    /// Failed when every law has failed (the point has dissipated the
    /// sum of the toughnesses); process zone when any law has left
    /// `Intact` short of that.
    fn stage(&self, state: &[f64]) -> junta_core::PointStage {
        use junta_core::PointStage;
        let stages = (0..self.laws.len()).map(|i| self.laws[i].stage(self.state_of(i, state)));
        let (mut all_failed, mut any_started) = (true, false);
        for s in stages {
            all_failed &= s == PointStage::Failed;
            any_started |= s != PointStage::Intact;
        }
        if all_failed {
            PointStage::Failed
        } else if any_started {
            PointStage::ProcessZone
        } else {
            PointStage::Intact
        }
    }

    fn failure_index(&self, state: &[f64]) -> Option<f64> {
        self.laws[0].failure_index(self.state_of(0, state))
    }

    fn tangent_kind(&self) -> MatrixKind {
        let rank = |k: MatrixKind| match k {
            MatrixKind::SymmetricPositiveDefinite => 0,
            MatrixKind::SymmetricIndefinite => 1,
            MatrixKind::General => 2,
        };
        self.laws
            .iter()
            .map(|l| l.tangent_kind())
            .max_by_key(|k| rank(*k))
            .unwrap_or(MatrixKind::SymmetricPositiveDefinite)
    }

    fn tangent_is_symmetrised(&self) -> bool {
        self.laws.iter().any(|l| l.tangent_is_symmetrised())
    }

    fn output_names(&self) -> &'static [&'static str] {
        self.names
    }

    fn outputs(&self, state: &[f64], out: &mut [f64]) {
        out.fill(0.0);
        let mut buf = [0.0; MAX_LAW_OUTPUTS];
        let mut at = 1 + SUMMED.len();
        for (i, l) in self.laws.iter().enumerate() {
            let names = l.output_names();
            let vals = &mut buf[..names.len()];
            l.outputs(self.state_of(i, state), vals);
            for (n, v) in names.iter().zip(vals.iter()) {
                if i == 0 && *n == output::DAMAGE {
                    out[0] = *v;
                }
                if let Some(s) = SUMMED.iter().position(|s| s == n) {
                    out[1 + s] += *v;
                }
            }
            out[at..at + names.len()].copy_from_slice(vals);
            at += names.len();
        }
    }

    fn fracture_properties(&self) -> Option<FractureProperties> {
        let mut sum: Option<FractureProperties> = None;
        for p in self.laws.iter().filter_map(|l| l.fracture_properties()) {
            sum = Some(match sum {
                None => p,
                Some(s) => FractureProperties {
                    strength_normal: s.strength_normal + p.strength_normal,
                    strength_shear: s.strength_shear + p.strength_shear,
                    toughness_mode_i: s.toughness_mode_i + p.toughness_mode_i,
                    toughness_mode_ii: s.toughness_mode_ii + p.toughness_mode_ii,
                    penalty: [
                        s.penalty[0] + p.penalty[0],
                        s.penalty[1] + p.penalty[1],
                        s.penalty[2] + p.penalty[2],
                    ],
                },
            });
        }
        sum
    }

    fn penalty_role(&self) -> junta_core::law::PenaltyRole {
        self.laws[0].penalty_role()
    }

    fn warnings(&self) -> Vec<String> {
        self.laws
            .iter()
            .enumerate()
            .flat_map(|(i, l)| {
                l.warnings()
                    .into_iter()
                    .map(move |w| format!("law{} ({}): {w}", i + 1, l.key()))
            })
            .collect()
    }
}

/// Parameter documentation.
pub const PARAMS: &[ParamDoc] = &[ParamDoc {
    name: "laws",
    doc: "array of tables ([[laws.NAME.laws]]), 2 to 8 laws acting in parallel, each with its `type` and parameters; the first is the initiation law (its damage is the point's)",
}];

inventory::submit! {
    LawEntry {
        key: "superposed",
        description: "laws acting in parallel, tractions and tangents summed (an initiation law and a bridging law: trilinear law, R-curve; Davila, Rose & Camanho 2009)",
        params: PARAMS,
        build: |t| Ok(Arc::new(Superposed::from_table(t)?)),
    }
}
