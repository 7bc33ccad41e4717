//! The penalty advisor: the paper's choice of the penalty from an error
//! analysis (eqs. 41-55), computed on the assembled model.
//!
//! Two errors compete when a constraint is enforced by a penalty eps:
//!
//! ```text
//! constraint error   e_c(eps) ~ k_min / eps                (eq. 51, c = 1)
//! round-off error    e_r(eps) ~ n e_c eps / k_min          (eq. 52)
//! their sum is least at  eps_op = k_min / sqrt(n e_c)      (eq. 55)
//! where it is about      2 sqrt(n e_c)
//! ```
//!
//! - `k_min`: the smallest diagonal stiffness term that the penalty
//!   modifies: the diagonal of the *solids'* stiffness, assembled over the
//!   solid elements that touch the interface, at the free dofs of the
//!   interface nodes (both sides);
//! - `n`: the number of those free dofs;
//! - `e_c`: machine epsilon of f64 (2.22e-16).
//!
//! Conversion to the law's stiffness d (force / length^3): a node pair of
//! the interface carries on average the area `a_pair = A / pairs` (A the
//! interface area, `pairs` the number of node pairs), so a penalty d acts
//! on the pair like a spring `eps = d a_pair`, and `d_op = eps_op / a_pair`.
//! (The paper's "d is about ten times eps" is this conversion for its
//! meshes.) Turon's rule `K = 50 E / t` is given as well when the physical
//! thickness t of the bonded layer is known (E: the largest reference
//! modulus of the solids beside the interface).
//!
//! # Constraint penalties and cohesive laws
//!
//! The analysis above is for a penalty that *enforces a constraint*
//! (ideally infinite): the paper's `linear_penalty` and `paper_debond`,
//! `contact`, `coulomb_friction`, `mohr_coulomb`. The penalty of a
//! cohesive (fracture) law (`bilinear`, `exponential`, `trilinear`,
//! `bilinear_friction`) is part of the model instead: its compliance adds
//! to the solids' and, with the strength, it sets the opening at damage
//! onset; making it as stiff as round-off allows buys nothing and invites
//! spurious traction oscillations ahead of the crack and ill-conditioned
//! tangents. Each law says which it is
//! ([`junta_core::InterfaceLaw::penalty_role`]); for a
//! [`PenaltyRole::Cohesive`] law the advisor reports ([`CohesivePenalty`])
//!
//! ```text
//! compliance ratio  r = (1 / K) / (t / E_33) = E_33 / (K t)
//! Turon's bound     K >= K_T = 50 E_33 / t          (r <= 2 %)
//! stiff limit       K_max = min(1e3 K_T, d_op)
//! ```
//!
//! (Turon, Davila, Camanho & Costa, Eng. Fract. Mech. 74 (2007)
//! 1665-1682: `K = alpha E_33 / t`; the sub-laminate of thickness t in
//! series with the interface has the effective modulus
//! `E_33 / (1 + 1/alpha)`, which for alpha >= 50 loses less than 2 %.) `E_33` is the modulus of the solids across the
//! interface and `t` the thickness of the thinner body beside it (the arm
//! of a DCB), both read as in [`crate::cohesive_zone`]; `K` is the law's
//! normal penalty. Verdict: below `K_T` too compliant (raise K to `K_T`);
//! above `K_max` too stiff (no accuracy to gain, oscillations and
//! ill-conditioning to lose); otherwise good. The paper's `d_op` enters
//! only as the upper limit, never as a recommendation.

use crate::cohesive_zone::{adjacent_solids, AdjacentSolids};
use junta_core::element::{ElementContext, StepInfo};
use junta_core::{CoreError, Model, PenaltyRole};

/// Turon et al. (2007)'s factor: `K >= TURON_ALPHA E_33 / t`.
pub const TURON_ALPHA: f64 = 50.0;

/// A cohesive penalty above this multiple of Turon's bound is too stiff.
pub const STIFF_FACTOR: f64 = 1e3;

/// Where a cohesive law's penalty stands against the solids beside it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CohesiveVerdict {
    /// Below Turon's bound: the interface adds more than 2 % compliance.
    TooCompliant,
    /// Between Turon's bound and the stiff limit.
    Good,
    /// Above the stiff limit: traction oscillations, ill-conditioning.
    TooStiff,
}

impl CohesiveVerdict {
    /// Name for summaries.
    pub fn name(self) -> &'static str {
        match self {
            CohesiveVerdict::TooCompliant => "too compliant",
            CohesiveVerdict::Good => "good",
            CohesiveVerdict::TooStiff => "too stiff",
        }
    }
}

/// The advisor's numbers for the penalty of a cohesive law (see the module
/// documentation).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CohesivePenalty {
    /// Modulus of the solids across the interface, `E_33`.
    pub modulus_normal: f64,
    /// Thickness `t` of the thinner body beside the interface.
    pub arm_thickness: f64,
    /// The law's normal penalty `K` (the scene's `d3`).
    pub penalty: f64,
    /// `(1 / K) / (t / E_33)`: the compliance the interface adds, relative
    /// to the arm's through-thickness compliance.
    pub compliance_ratio: f64,
    /// Turon's bound `50 E_33 / t`.
    pub turon_bound: f64,
    /// `min(1e3 x Turon's bound, d_op)`.
    pub stiff_limit: f64,
    /// Verdict on `K`.
    pub verdict: CohesiveVerdict,
}

impl CohesivePenalty {
    /// The numbers for penalty `k` between solids of modulus `e_33` and
    /// thickness `t` (both positive and finite), with the error analysis's
    /// round-off balance `d_op` as a ceiling.
    pub fn new(k: f64, e_33: f64, t: f64, d_op: f64) -> CohesivePenalty {
        let turon_bound = TURON_ALPHA * e_33 / t;
        let stiff_limit = (STIFF_FACTOR * turon_bound).min(d_op);
        let verdict = if k < turon_bound {
            CohesiveVerdict::TooCompliant
        } else if k > stiff_limit {
            CohesiveVerdict::TooStiff
        } else {
            CohesiveVerdict::Good
        };
        CohesivePenalty {
            modulus_normal: e_33,
            arm_thickness: t,
            penalty: k,
            compliance_ratio: e_33 / (k * t),
            turon_bound,
            stiff_limit,
            verdict,
        }
    }
}

/// Where a penalty stands against the error analysis.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PenaltyVerdict {
    /// Constraint error dominates (more than 10x): the faces interpenetrate / slide.
    TooLow,
    /// Within a factor 10 of balance.
    Good,
    /// Round-off dominates (more than 10x): the solve loses digits.
    TooHigh,
}

/// The advisor's numbers for one interface block.
#[derive(Debug, Clone, PartialEq)]
pub struct PenaltyAdvice {
    /// Block name.
    pub block: String,
    /// Smallest diagonal stiffness of the solids at the interface dofs [force/length].
    pub k_min: f64,
    /// Free dofs of the interface nodes.
    pub n: usize,
    /// Machine epsilon.
    pub e_c: f64,
    /// Optimal nodal penalty eps_op = k_min / sqrt(n e_c) [force/length].
    pub eps_op: f64,
    /// Interface area.
    pub area: f64,
    /// Node pairs.
    pub pairs: usize,
    /// Mean area per node pair.
    pub area_per_pair: f64,
    /// Recommended law stiffness d_op = eps_op / a_pair [force/length^3].
    pub d_op: f64,
    /// The law's stiffness `[d1, d2, d3]` in the scene.
    pub d_scene: [f64; 3],
    /// Estimated constraint error at the scene's d3.
    pub constraint_error: f64,
    /// Estimated round-off error at the scene's d3.
    pub roundoff_error: f64,
    /// Best attainable relative error, 2 sqrt(n e_c).
    pub best_error: f64,
    /// Verdict of the error analysis on the scene's d3: the advice for a
    /// constraint penalty; for a cohesive law see [`PenaltyAdvice::cohesive`].
    pub verdict: PenaltyVerdict,
    /// Turon's K = 50 E / t, when a thickness is given.
    pub turon: Option<f64>,
    /// What the law's penalty is (the law's
    /// [`junta_core::InterfaceLaw::penalty_role`]).
    pub role: PenaltyRole,
    /// For a cohesive law: its penalty against the solids beside it (`None`
    /// for a constraint penalty, or when no solid beside the interface has
    /// a finite thickness and a modulus across it).
    pub cohesive: Option<CohesivePenalty>,
}

impl PenaltyAdvice {
    /// Error estimate of eq. 53 at law stiffness `d`: (constraint, round-off).
    pub fn errors_at(&self, d: f64) -> (f64, f64) {
        let eps = d * self.area_per_pair;
        (
            self.k_min / eps,
            self.n as f64 * self.e_c * eps / self.k_min,
        )
    }
}

/// Advice for interface block `block` of `model`; `thickness` enables
/// Turon's rule.
pub fn penalty_advice(
    model: &Model,
    block: usize,
    thickness: Option<f64>,
) -> Result<PenaltyAdvice, CoreError> {
    let mut on_interface = vec![false; model.mesh.nodes.len()];
    if let Some(b) = model.mesh.blocks.get(block) {
        for &n in &b.connectivity {
            on_interface[n] = true;
        }
    }
    let solids = SolidDiagonal::near(model, &on_interface)?;
    penalty_advice_with(model, block, thickness, &solids)
}

/// The diagonal stiffness of the solids at the nodes of some interfaces,
/// computed once for all of them: at a node of an interface every element
/// holding the node touches that interface, so the diagonal there is the
/// same whichever interfaces were asked for (a laminate's 31 interfaces
/// compute each ply's elements once, not once per neighbouring interface).
#[derive(Debug, Clone)]
pub struct SolidDiagonal {
    /// Sum of the solid elements' diagonal stiffness per dof (0 off the nodes asked for).
    diag: Vec<f64>,
    /// Largest reference modulus of the solids holding each node.
    node_modulus: Vec<f64>,
}

impl SolidDiagonal {
    /// The solids' diagonal at the nodes of every interface block.
    pub fn of_interfaces(model: &Model) -> Result<Self, CoreError> {
        let mut on = vec![false; model.mesh.nodes.len()];
        for b in model.mesh.blocks.iter().filter(|b| b.shape.is_interface()) {
            for &n in &b.connectivity {
                on[n] = true;
            }
        }
        Self::near(model, &on)
    }

    /// The solids' diagonal at the nodes where `on` is true.
    pub fn near(model: &Model, on: &[bool]) -> Result<Self, CoreError> {
        let (diag, node_modulus) = solid_diagonal(model, on)?;
        Ok(SolidDiagonal { diag, node_modulus })
    }

    /// The largest modulus of the solids holding a node where `on` is true.
    fn modulus(&self, on: &[bool]) -> f64 {
        on.iter()
            .zip(&self.node_modulus)
            .filter(|(o, _)| **o)
            .fold(0.0, |m, (_, e)| m.max(*e))
    }
}

/// [`penalty_advice`] with the solids' diagonal already computed (it must
/// cover this interface's nodes).
pub fn penalty_advice_with(
    model: &Model,
    block: usize,
    thickness: Option<f64>,
    solids: &SolidDiagonal,
) -> Result<PenaltyAdvice, CoreError> {
    let mesh = &model.mesh;
    let ib = mesh
        .blocks
        .get(block)
        .filter(|b| b.shape.is_interface())
        .ok_or_else(|| CoreError::Invalid(format!("block {block} is not an interface block")))?;
    let (on_interface, pairs, area) = interface_area(model, block)?;
    let modulus = solids.modulus(&on_interface);
    let (k_min, n) = smallest_free_stiffness(model, &on_interface, &solids.diag);
    if n == 0 || !k_min.is_finite() {
        return Err(CoreError::Invalid(format!(
            "interface `{}` has no free dof on a solid: nothing for the penalty to act on",
            ib.name
        )));
    }
    let e_c = f64::EPSILON;
    let eps_op = k_min / (n as f64 * e_c).sqrt();
    let area_per_pair = area / pairs as f64;
    let d_scene = iel_law_stiffness(model, block);
    let mut advice = PenaltyAdvice {
        block: ib.name.clone(),
        k_min,
        n,
        e_c,
        eps_op,
        area,
        pairs,
        area_per_pair,
        d_op: eps_op / area_per_pair,
        d_scene,
        constraint_error: 0.0,
        roundoff_error: 0.0,
        best_error: 2.0 * (n as f64 * e_c).sqrt(),
        verdict: PenaltyVerdict::Good,
        turon: thickness
            .filter(|t| *t > 0.0 && modulus > 0.0)
            .map(|t| 50.0 * modulus / t),
        role: model.elements[block]
            .penalty_role()
            .unwrap_or(PenaltyRole::Constraint),
        cohesive: None,
    };
    let (ce, re) = advice.errors_at(d_scene[2]);
    advice.constraint_error = ce;
    advice.roundoff_error = re;
    advice.verdict = if ce > 10.0 * re {
        PenaltyVerdict::TooLow
    } else if re > 10.0 * ce {
        PenaltyVerdict::TooHigh
    } else {
        PenaltyVerdict::Good
    };
    if advice.role == PenaltyRole::Cohesive {
        advice.cohesive = match adjacent_solids(model, block)? {
            Some(AdjacentSolids {
                modulus_normal: e,
                arm_thickness: t,
                ..
            }) if e > 0.0 && e.is_finite() && t > 0.0 && t.is_finite() && d_scene[2] > 0.0 => {
                Some(CohesivePenalty::new(d_scene[2], e, t, advice.d_op))
            }
            _ => None,
        };
    }
    Ok(advice)
}

/// The nodes of interface block `block` (a flag per node of the mesh),
/// its node pairs and its area (the sum of its points' `area` outputs).
fn interface_area(model: &Model, block: usize) -> Result<(Vec<bool>, usize, f64), CoreError> {
    let mesh = &model.mesh;
    let ib = &mesh.blocks[block];
    let iel = &model.elements[block];
    let mut on_interface = vec![false; mesh.nodes.len()];
    let mut pairs = std::collections::BTreeSet::new();
    let m = ib.nodes_per_element() / 2;
    let mut area = 0.0;
    let (states, responses) = initial_block_states(model, block)?;
    let per = iel.state_len();
    let np = iel.num_points();
    for e in 0..ib.len() {
        let nodes = ib.element(e);
        for a in 0..m {
            on_interface[nodes[a]] = true;
            on_interface[nodes[m + a]] = true;
            pairs.insert((nodes[a], nodes[m + a]));
        }
        let coords: Vec<[f64; 3]> = nodes.iter().map(|&n| mesh.nodes[n]).collect();
        let disp = vec![0.0; 3 * nodes.len()];
        let pts = iel
            .point_outputs(&ElementContext {
                coords: &coords,
                disp: &disp,
                state_committed: &states[e * per..(e + 1) * per],
                step: StepInfo::default(),
                law_responses: (!responses.is_empty()).then(|| &responses[e * np..(e + 1) * np]),
                temperature: None,
            })
            .map_err(|source| CoreError::Element {
                block: ib.name.clone(),
                element: e,
                source,
            })?;
        area += pts
            .iter()
            .filter_map(|p| p.get("area"))
            .map(|a| a[0])
            .sum::<f64>();
    }
    Ok((on_interface, pairs.len(), area))
}

/// The initial states of interface block `block`, element-major, and,
/// when its law is batched (a law written in Python), its responses at
/// zero jump from one call for the whole block, with the outputs of those
/// states prefetched ([`junta_core::InterfaceLaw::prefetch_outputs`]): the area pass
/// then asks the law nothing per point.
fn initial_block_states(
    model: &Model,
    block: usize,
) -> Result<(Vec<f64>, Vec<junta_core::LawResponse>), CoreError> {
    let iel = &model.elements[block];
    let per = iel.state_len();
    let n = model.mesh.blocks[block].len();
    let mut states = vec![0.0; per * n];
    if per > 0 {
        for chunk in states.chunks_mut(per) {
            iel.init_state(chunk);
        }
    }
    let Some(law) = iel.batch_law() else {
        return Ok((states, Vec::new()));
    };
    law.prefetch_outputs(&states);
    let u = vec![0.0; 3 * model.mesh.nodes.len()];
    let mut trial = states.clone();
    let responses = junta_core::assembly::block_law_responses(
        &model.mesh,
        iel.as_ref(),
        block,
        &u,
        &states,
        &mut trial,
        StepInfo::default(),
    )?;
    Ok((states, responses))
}

/// The stiffness diagonal of the solid elements touching the interface
/// nodes (`on_interface`), in the reference state, and the largest
/// reference modulus of their materials.
/// The diagonal of the solids touching the nodes where `on_interface` is
/// true, per dof, and the largest modulus of the solids holding each node.
fn solid_diagonal(model: &Model, on_interface: &[bool]) -> Result<(Vec<f64>, Vec<f64>), CoreError> {
    let mesh = &model.mesh;
    // diagonal of the solids touching the interface
    let mut diag = vec![0.0; 3 * mesh.nodes.len()];
    let mut node_modulus = vec![0.0f64; mesh.nodes.len()];
    for (bi, b) in mesh.blocks.iter().enumerate() {
        if !b.shape.is_solid() {
            continue;
        }
        let el = &model.elements[bi];
        let nd = 3 * b.nodes_per_element();
        let mut k = vec![0.0; nd * nd];
        let mut f = vec![0.0; nd];
        let disp = vec![0.0; nd];
        // the reference state: zero displacement and zero committed state
        // (an element with state, e.g. H8I under nlgeom, reads it)
        let committed = vec![0.0; el.state_len()];
        let mut state = vec![0.0; el.state_len()];
        for e in 0..b.len() {
            let nodes = b.element(e);
            if !nodes.iter().any(|&n| on_interface[n]) {
                continue;
            }
            let coords: Vec<[f64; 3]> = nodes.iter().map(|&n| mesh.nodes[n]).collect();
            el.compute(
                &ElementContext {
                    coords: &coords,
                    disp: &disp,
                    state_committed: &committed,
                    step: StepInfo::default(),
                    law_responses: None,
                    temperature: None,
                },
                &mut state,
                &mut f,
                Some(&mut k),
            )
            .map_err(|source| CoreError::Element {
                block: b.name.clone(),
                element: e,
                source,
            })?;
            for (a, &n) in nodes.iter().enumerate() {
                for c in 0..3 {
                    diag[3 * n + c] += k[(3 * a + c) * nd + 3 * a + c];
                }
            }
            if let Some(r) = material_modulus(model, bi) {
                for &n in nodes {
                    node_modulus[n] = node_modulus[n].max(r);
                }
            }
        }
    }
    Ok((diag, node_modulus))
}

/// The smallest diagonal stiffness `k_min` of a free dof on the interface
/// and the number `n` of such dofs.
fn smallest_free_stiffness(model: &Model, on_interface: &[bool], diag: &[f64]) -> (f64, usize) {
    let mut k_min = f64::INFINITY;
    let mut n = 0;
    for (node, &on) in on_interface.iter().enumerate() {
        if !on {
            continue;
        }
        for c in 0..3 {
            let d = 3 * node + c;
            if model.dofs.eq[d] != junta_core::dof::CONSTRAINED && diag[d] > 0.0 {
                k_min = k_min.min(diag[d]);
                n += 1;
            }
        }
    }
    (k_min, n)
}

fn material_modulus(model: &Model, block: usize) -> Option<f64> {
    model.elements[block].reference_modulus()
}

fn iel_law_stiffness(model: &Model, block: usize) -> [f64; 3] {
    model.elements[block]
        .interface_stiffness()
        .unwrap_or([0.0; 3])
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The DCB of examples/delamination/dcb.toml: AS4/PEEK arms, E_33 =
    /// E3 = 10100 MPa across the interface, arm thickness t = 1.56 mm,
    /// K = 1e6 N/mm^3. By hand: Turon's bound 50 x 10100 / 1.56 =
    /// 323717.95 N/mm^3; compliance ratio E_33 / (K t) = 10100 / 1.56e6 =
    /// 6.4744e-3 (0.65 %, i.e. alpha = K t / E_33 = 154.5 >= 50).
    #[test]
    fn dcb_penalty_is_above_turons_bound() {
        let c = CohesivePenalty::new(1e6, 10100.0, 1.56, 6.0e10);
        assert!((c.turon_bound - 323_717.948_717_948_7).abs() < 1e-6);
        assert!((c.compliance_ratio - 6.474_358_974_358_974e-3).abs() < 1e-15);
        // the stiff limit is 1e3 x the bound, below the round-off balance
        assert!((c.stiff_limit - 3.237_179_487_179_487e8).abs() < 1e-3);
        assert_eq!(c.verdict, CohesiveVerdict::Good);
    }

    /// Below the bound (K = 1e5 < 3.237e5): more than 2 % compliance
    /// (10100 / (1e5 x 1.56) = 6.47 %); above 1e3 x the bound, or above
    /// d_op when that is lower: too stiff.
    #[test]
    fn cohesive_verdicts_follow_the_bounds() {
        let low = CohesivePenalty::new(1e5, 10100.0, 1.56, 6.0e10);
        assert_eq!(low.verdict, CohesiveVerdict::TooCompliant);
        assert!(low.compliance_ratio > 1.0 / TURON_ALPHA);
        // exactly at the bound: 2 %
        let at = CohesivePenalty::new(50.0 * 10100.0 / 1.56, 10100.0, 1.56, 6.0e10);
        assert!((at.compliance_ratio - 0.02).abs() < 1e-15);
        assert_eq!(at.verdict, CohesiveVerdict::Good);
        let stiff = CohesivePenalty::new(1e9, 10100.0, 1.56, 6.0e10);
        assert_eq!(stiff.verdict, CohesiveVerdict::TooStiff);
        // a round-off balance below 1e3 x the bound caps the limit
        let capped = CohesivePenalty::new(1e7, 10100.0, 1.56, 5e6);
        assert_eq!(capped.stiff_limit, 5e6);
        assert_eq!(capped.verdict, CohesiveVerdict::TooStiff);
    }
}
