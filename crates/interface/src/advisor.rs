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

use junta_core::element::{ElementContext, StepInfo};
use junta_core::{CoreError, Model};

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
    /// Verdict on the scene's d3.
    pub verdict: PenaltyVerdict,
    /// Turon's K = 50 E / t, when a thickness is given.
    pub turon: Option<f64>,
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
    let mesh = &model.mesh;
    let ib = mesh
        .blocks
        .get(block)
        .filter(|b| b.shape.is_interface())
        .ok_or_else(|| CoreError::Invalid(format!("block {block} is not an interface block")))?;
    let iel = &model.elements[block];
    let mut on_interface = vec![false; mesh.nodes.len()];
    let mut pairs = std::collections::BTreeSet::new();
    let m = ib.nodes_per_element() / 2;
    let mut area = 0.0;
    for e in 0..ib.len() {
        let nodes = ib.element(e);
        for a in 0..m {
            on_interface[nodes[a]] = true;
            on_interface[nodes[m + a]] = true;
            pairs.insert((nodes[a], nodes[m + a]));
        }
        let coords: Vec<[f64; 3]> = nodes.iter().map(|&n| mesh.nodes[n]).collect();
        let disp = vec![0.0; 3 * nodes.len()];
        let mut state = vec![0.0; iel.state_len()];
        iel.init_state(&mut state);
        let pts = iel
            .point_outputs(&ElementContext {
                coords: &coords,
                disp: &disp,
                state_committed: &state,
                step: StepInfo::default(),
                law_responses: None,
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
    // diagonal of the solids touching the interface
    let mut diag = vec![0.0; 3 * mesh.nodes.len()];
    let mut modulus: f64 = 0.0;
    for (bi, b) in mesh.blocks.iter().enumerate() {
        if !b.shape.is_solid() {
            continue;
        }
        let el = &model.elements[bi];
        let nd = 3 * b.nodes_per_element();
        let mut k = vec![0.0; nd * nd];
        let mut f = vec![0.0; nd];
        let disp = vec![0.0; nd];
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
                    state_committed: &[],
                    step: StepInfo::default(),
                    law_responses: None,
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
                modulus = modulus.max(r);
            }
        }
    }
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
    if n == 0 || !k_min.is_finite() {
        return Err(CoreError::Invalid(format!(
            "interface `{}` has no free dof on a solid: nothing for the penalty to act on",
            ib.name
        )));
    }
    let e_c = f64::EPSILON;
    let eps_op = k_min / (n as f64 * e_c).sqrt();
    let area_per_pair = area / pairs.len() as f64;
    let d_scene = iel_law_stiffness(model, block);
    let mut advice = PenaltyAdvice {
        block: ib.name.clone(),
        k_min,
        n,
        e_c,
        eps_op,
        area,
        pairs: pairs.len(),
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
    Ok(advice)
}

fn material_modulus(model: &Model, block: usize) -> Option<f64> {
    model.elements[block].reference_modulus()
}

fn iel_law_stiffness(model: &Model, block: usize) -> [f64; 3] {
    model.elements[block]
        .interface_stiffness()
        .unwrap_or([0.0; 3])
}
