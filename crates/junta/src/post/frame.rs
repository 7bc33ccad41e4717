//! Typed fields of one state of a run: nodal displacement, solid stress and
//! strain at the integration points, and interface traction, jump, damage
//! and the laws' other outputs at the interface integration points.
//!
//! Arrays are flat and row-major so that they map to numpy without a copy
//! of shape: `displacement` is `[nodes, 3]`, `solid.stress` `[points, 6]`
//! (Voigt `xx, yy, zz, xy, yz, zx`), `interface.traction` `[points, 3]`
//! (local `[s1, s2, n]`).

use crate::error::Result;
use crate::post::fields::element_points;
use crate::post::fields::InterfaceResults;
use junta_core::element::StepInfo;
use junta_core::state::StateStore;
use junta_core::Model;
use serde::Serialize;
use std::collections::BTreeMap;

/// Integration-point values of the solid elements.
#[derive(Debug, Clone, Default, Serialize)]
pub struct SolidPoints {
    /// Block index of each point.
    pub block: Vec<usize>,
    /// Element index (within its block) of each point.
    pub element: Vec<usize>,
    /// Reference position `[points, 3]`.
    pub position: Vec<f64>,
    /// Stress `[points, 6]` (Voigt `xx, yy, zz, xy, yz, zx`).
    pub stress: Vec<f64>,
    /// Strain `[points, 6]` (engineering shear, same order).
    pub strain: Vec<f64>,
    /// Stress in each point's material axes `[points, 6]` (Voigt `11, 22,
    /// 33, 12, 23, 31`; a ply: 1 along the fibre, 3 through the
    /// thickness); NaN at points whose material has no axes (isotropic).
    /// Under large deformation: the second Piola-Kirchhoff stress in the
    /// reference axes.
    pub material_stress: Vec<f64>,
}

/// Integration-point values of the interface elements.
#[derive(Debug, Clone, Default, Serialize)]
pub struct InterfacePoints {
    /// Block index of each point.
    pub block: Vec<usize>,
    /// Element index (within its block) of each point.
    pub element: Vec<usize>,
    /// Reference position `[points, 3]`.
    pub position: Vec<f64>,
    /// Jump in the local frame `[points, 3]` (`[s1, s2, n]`).
    pub jump: Vec<f64>,
    /// Traction in the local frame `[points, 3]`.
    pub traction: Vec<f64>,
    /// Scalar outputs per point by name: `damage`, `dissipated_energy`,
    /// `failed`, `failure_index`, `area` and each law's own outputs (NaN at
    /// points whose law does not report that name).
    pub outputs: BTreeMap<String, Vec<f64>>,
}

/// The fields of one converged state.
#[derive(Debug, Clone, Default, Serialize)]
pub struct Frame {
    /// Converged increment (0 for a linear run).
    pub increment: usize,
    /// Load factor.
    pub load_factor: f64,
    /// Nodal displacement `[nodes, 3]`.
    pub displacement: Vec<f64>,
    /// Solid integration points.
    pub solid: SolidPoints,
    /// Interface integration points.
    pub interface: InterfacePoints,
}

impl Frame {
    /// The fields at displacement `u` and state `state` of increment `step`;
    /// `interfaces` are the interface results of that state (computed once
    /// per increment by the run).
    pub fn at(
        model: &Model,
        u: &[f64],
        state: &StateStore,
        interfaces: &[InterfaceResults],
        step: StepInfo,
    ) -> Result<Frame> {
        Ok(Frame {
            increment: step.increment,
            load_factor: step.load_factor,
            displacement: u.to_vec(),
            solid: solid_points(model, u, state, step)?,
            interface: interface_points(interfaces),
        })
    }

    /// Number of nodes.
    pub fn num_nodes(&self) -> usize {
        self.displacement.len() / 3
    }
}

fn solid_points(
    model: &Model,
    u: &[f64],
    state: &StateStore,
    step: StepInfo,
) -> Result<SolidPoints> {
    let mut s = SolidPoints::default();
    for (bi, b) in model.mesh.blocks.iter().enumerate() {
        if !b.shape.is_solid() {
            continue;
        }
        for e in 0..b.len() {
            for p in element_points(model, u, state, bi, e, step)? {
                s.block.push(bi);
                s.element.push(e);
                s.position.extend_from_slice(&p.position);
                push_n(&mut s.stress, p.get("stress"), 6);
                push_n(&mut s.strain, p.get("strain"), 6);
                push_n(&mut s.material_stress, p.get("material_stress"), 6);
            }
        }
    }
    Ok(s)
}

/// Append exactly `n` values (NaN where missing).
fn push_n(out: &mut Vec<f64>, v: Option<&[f64]>, n: usize) {
    for k in 0..n {
        out.push(v.and_then(|v| v.get(k)).copied().unwrap_or(f64::NAN));
    }
}

fn interface_points(interfaces: &[InterfaceResults]) -> InterfacePoints {
    let mut s = InterfacePoints::default();
    let total: usize = interfaces.iter().map(|r| r.points.len()).sum();
    for r in interfaces {
        for (i, p) in r.points.iter().enumerate() {
            let row = s.block.len();
            s.block.push(r.block);
            s.element.push(i / r.points_per_element.max(1));
            s.position.extend_from_slice(&p.position);
            push_n(&mut s.jump, p.get("jump"), 3);
            push_n(&mut s.traction, p.get("traction"), 3);
            for (name, v) in &p.values {
                if v.len() == 1 {
                    let col = s
                        .outputs
                        .entry(name.to_string())
                        .or_insert_with(|| vec![f64::NAN; total]);
                    col[row] = v[0];
                }
            }
        }
    }
    s
}
