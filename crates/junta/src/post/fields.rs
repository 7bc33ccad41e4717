//! The fields of a converged state, as the post-processing and the
//! writers read them: cell-averaged solid output ([`CellResults`]), the
//! integration-point output of every interface block
//! ([`InterfaceResults`]) and the energies it integrates to
//! ([`InterfaceEnergy`]).

use crate::error::{Context, Result};
use junta_core::element::{ElementContext, StepInfo};
use junta_core::state::StateStore;
use junta_core::Model;
use junta_core::PointStage;
use rayon::prelude::*;

/// Cell-averaged output of every solid element, in block order, and the
/// range of each stress component over the integration points per block.
/// `Default`: no cell (what a rank of an MPI run that writes nothing keeps).
#[derive(Default)]
pub struct CellResults {
    /// Per solid block: (name, stress_min, stress_max) over all points.
    pub ranges: Vec<(String, [f64; 6], [f64; 6])>,
    /// Average stress per cell (Voigt `[xx, yy, zz, xy, yz, zx]`).
    pub stress: Vec<[f64; 6]>,
    /// Average von Mises stress per cell.
    pub mises: Vec<f64>,
    /// Average second Piola-Kirchhoff stress per cell, when an element
    /// reports it (large deformation: `stress` is then the Cauchy stress).
    pub pk2_stress: Option<Vec<[f64; 6]>>,
    /// Average stress per cell in its material's own axes (a ply: 11 along
    /// the fibre, 33 through the thickness; Voigt `[11, 22, 33, 12, 23,
    /// 31]`), when some block's material has axes; NaN in the cells of the
    /// others.
    pub material_stress: Option<Vec<[f64; 6]>>,
    /// Further scalars per cell by name (the ply failure indices,
    /// `NAME_index`), written as cell data beside the stress.
    pub extra: Vec<(String, Vec<f64>)>,
}

/// Average integration-point outputs over each solid cell (a linear
/// analysis: the model's whole temperature change, if it has one).
pub fn cell_results(model: &Model, u: &[f64], state: &StateStore) -> Result<CellResults> {
    cell_results_at(model, u, state, StepInfo::default())
}

/// [`cell_results`] for the state of increment `step` (laws whose answer
/// depends on the increment, such as a release schedule, need it).
pub fn cell_results_at(
    model: &Model,
    u: &[f64],
    state: &StateStore,
    step: StepInfo,
) -> Result<CellResults> {
    let mut stress = Vec::with_capacity(model.mesh.num_elements());
    let mut mises = Vec::with_capacity(model.mesh.num_elements());
    let mut pk2 = Vec::with_capacity(model.mesh.num_elements());
    let mut any_pk2 = false;
    let mut in_axes = Vec::with_capacity(model.mesh.num_elements());
    let mut any_axes = false;
    let mut ranges = Vec::new();
    for (bi, b) in model.mesh.blocks.iter().enumerate() {
        if !b.shape.is_solid() {
            continue;
        }
        let mut lo = [f64::INFINITY; 6];
        let mut hi = [f64::NEG_INFINITY; 6];
        for e in 0..b.len() {
            let pts = element_points(model, u, state, bi, e, step)?;
            for p in &pts {
                if let Some(v) = p.get("stress") {
                    for k in 0..6 {
                        lo[k] = lo[k].min(v[k]);
                        hi[k] = hi[k].max(v[k]);
                    }
                }
            }
            let mut s = [0.0; 6];
            let mut s2 = [0.0; 6];
            let mut sl = [0.0; 6];
            let mut has_axes = false;
            let mut m = 0.0;
            let np = pts.len().max(1) as f64;
            for p in &pts {
                if let Some(v) = p.get("stress") {
                    for k in 0..6 {
                        s[k] += v[k] / np;
                    }
                }
                if let Some(v) = p.get("pk2_stress") {
                    any_pk2 = true;
                    for k in 0..6 {
                        s2[k] += v[k] / np;
                    }
                }
                if let Some(v) = p.get("mises") {
                    m += v[0] / np;
                }
                if let Some(v) = p.get("material_stress") {
                    has_axes = true;
                    for k in 0..6 {
                        sl[k] += v[k] / np;
                    }
                }
            }
            stress.push(s);
            pk2.push(s2);
            any_axes |= has_axes;
            in_axes.push(if has_axes { sl } else { [f64::NAN; 6] });
            mises.push(m);
        }
        ranges.push((b.name.clone(), lo, hi));
    }
    Ok(CellResults {
        ranges,
        stress,
        mises,
        pk2_stress: any_pk2.then_some(pk2),
        material_stress: any_axes.then_some(in_axes),
        extra: Vec::new(),
    })
}

/// Integration-point outputs of element `e` of block `bi`.
pub fn element_points(
    model: &Model,
    u: &[f64],
    state: &StateStore,
    bi: usize,
    e: usize,
    step: StepInfo,
) -> Result<Vec<junta_core::PointOutput>> {
    element_points_with(model, u, state, bi, e, step, None)
}

/// [`element_points`] with the element's law responses when its block's
/// law was evaluated once for the whole block.
fn element_points_with(
    model: &Model,
    u: &[f64],
    state: &StateStore,
    bi: usize,
    e: usize,
    step: StepInfo,
    law_responses: Option<&[junta_core::LawResponse]>,
) -> Result<Vec<junta_core::PointOutput>> {
    let b = &model.mesh.blocks[bi];
    let nodes = b.element(e);
    let coords: Vec<[f64; 3]> = nodes.iter().map(|&n| model.mesh.nodes[n]).collect();
    let disp: Vec<f64> = nodes
        .iter()
        .flat_map(|&n| u[3 * n..3 * n + 3].iter().copied())
        .collect();
    // solids see the temperature change of the increment (interfaces none)
    let temperature: Option<Vec<f64>> = model
        .temperature
        .as_ref()
        .filter(|_| b.shape.is_solid())
        .map(|t| {
            nodes
                .iter()
                .map(|&n| step.temperature_factor * t[n])
                .collect()
        });
    let ctx = ElementContext {
        coords: &coords,
        disp: &disp,
        state_committed: &state.committed[state.range(bi, e)],
        step,
        law_responses,
        temperature: temperature.as_deref(),
    };
    model.elements[bi]
        .point_outputs(&ctx)
        .with_context(|| format!("output of element {e} of block `{}`", b.name))
}

/// Integration-point output of one interface block.
pub struct InterfaceResults {
    /// Block index.
    pub block: usize,
    /// Points of every element, element-major (`points_per_element` each).
    pub points: Vec<junta_core::PointOutput>,
    /// Points per element.
    pub points_per_element: usize,
}

/// Point outputs of every interface block.
pub fn interface_results(
    model: &Model,
    u: &[f64],
    state: &StateStore,
) -> Result<Vec<InterfaceResults>> {
    interface_results_at(model, u, state, StepInfo::default())
}

/// [`interface_results`] for the state of increment `step`.
pub fn interface_results_at(
    model: &Model,
    u: &[f64],
    state: &StateStore,
    step: StepInfo,
) -> Result<Vec<InterfaceResults>> {
    let mut out = Vec::new();
    for (bi, b) in model.mesh.blocks.iter().enumerate() {
        if !b.shape.is_interface() {
            continue;
        }
        let responses = batched_responses(model, u, state, bi, step)?;
        let np = model.elements[bi].num_points();
        let points = if responses.is_empty() {
            // on rayon's threads (the run's drivers ask every increment),
            // in element order
            let per_element: Vec<Vec<junta_core::PointOutput>> = (0..b.len())
                .into_par_iter()
                .map(|e| element_points_with(model, u, state, bi, e, step, None))
                .collect::<Result<_>>()?;
            per_element.into_iter().flatten().collect()
        } else {
            // a batched (Python) law answers from the block's responses,
            // on this thread
            let mut points = Vec::new();
            for e in 0..b.len() {
                let own = &responses[e * np..(e + 1) * np];
                points.extend(element_points_with(
                    model,
                    u,
                    state,
                    bi,
                    e,
                    step,
                    Some(own),
                )?);
            }
            points
        };
        out.push(InterfaceResults {
            block: bi,
            points_per_element: model.elements[bi].num_points(),
            points,
        });
    }
    Ok(out)
}

/// For a block whose law is batched (a law written in Python): the law
/// evaluated once for all the block's points, and told to prefetch the
/// outputs of their committed states
/// ([`junta_core::InterfaceLaw::prefetch_outputs`]), so that the output
/// pass calls it once per block rather than once per element and point.
/// Empty for the other blocks.
fn batched_responses(
    model: &Model,
    u: &[f64],
    state: &StateStore,
    bi: usize,
    step: StepInfo,
) -> Result<Vec<junta_core::LawResponse>> {
    let el = &model.elements[bi];
    let Some(law) = el.batch_law() else {
        return Ok(Vec::new());
    };
    let span = state.block_offsets[bi]
        ..state.block_offsets[bi] + model.mesh.blocks[bi].len() * state.per_element[bi];
    let committed = &state.committed[span];
    law.prefetch_outputs(committed);
    let mut trial = committed.to_vec();
    Ok(junta_core::assembly::block_law_responses(
        &model.mesh,
        el.as_ref(),
        bi,
        u,
        committed,
        &mut trial,
        step,
    )?)
}

pub(crate) fn component_range(
    points: &[junta_core::PointOutput],
    name: &str,
) -> ([f64; 3], [f64; 3]) {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in points {
        if let Some(v) = p.get(name) {
            for c in 0..3 {
                lo[c] = lo[c].min(v[c]);
                hi[c] = hi[c].max(v[c]);
            }
        }
    }
    (lo, hi)
}

/// Values every interface point carries whatever its law; the other
/// scalar values of a point are its law's outputs
/// ([`junta_core::InterfaceLaw::output_names`]).
pub const FIXED_POINT_VALUES: &[&str] = &[
    "jump",
    "traction",
    "frame",
    "area",
    "state",
    "failed",
    "stage",
    "failure_index",
];

/// Names of the law outputs present in the interface points, in the order
/// first met.
pub fn law_output_names(res: &[InterfaceResults]) -> Vec<&'static str> {
    let mut names: Vec<&'static str> = Vec::new();
    for r in res {
        if let Some(p) = r.points.first() {
            for (n, v) in &p.values {
                if v.len() == 1 && !FIXED_POINT_VALUES.contains(n) && !names.contains(n) {
                    names.push(n);
                }
            }
        }
    }
    names
}

/// Energies and areas of one interface block, from its law outputs:
/// fracture and viscous energy (integrals of the per-area densities),
/// damaged area (the failed points, [`junta_core::PointStage::Failed`]) and
/// process-zone area (damage started, not failed).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct InterfaceEnergy {
    /// Fracture energy dissipated in the block (integral of the points'
    /// `dissipated_energy` density over their area).
    pub dissipated_energy: f64,
    /// Energy dissipated by viscous regularisation (same integral of
    /// `viscous_energy`).
    pub viscous_energy: f64,
    /// Area of the failed points ([`junta_core::PointStage::Failed`]).
    pub damaged_area: f64,
    /// Area of the process-zone points (damage started, not failed).
    pub process_zone_area: f64,
    /// Whether the law reports damage (else the numbers are zero).
    pub has_damage: bool,
    /// Energy dissipated by friction or interface plasticity (integral of
    /// the law output `frictional_dissipation`).
    pub frictional_dissipation: f64,
    /// Whether a law reports frictional dissipation.
    pub has_friction: bool,
}

/// The [`PointStage`] of an interface point's results (its `stage`, which
/// the interface element writes from [`junta_core::InterfaceLaw::stage`];
/// `Intact` for a point without one).
pub fn point_stage(p: &junta_core::PointOutput) -> PointStage {
    p.get("stage")
        .map_or(PointStage::Intact, |s| PointStage::of_code(s[0]))
}

/// [`InterfaceEnergy`] of one block's points.
pub fn interface_energy(r: &InterfaceResults) -> InterfaceEnergy {
    use junta_core::law::output;
    let mut e = InterfaceEnergy::default();
    for p in &r.points {
        // Under nlgeom a point reports its current `area` and its
        // `reference_area`: energies and crack areas are integrated over
        // the reference one (the crack's extent on the undeformed surface;
        // the current mid-surface of a peeled-off point shrinks as its faces
        // move apart, e.g. by 1/sqrt(2) once the faces stand at 90 degrees,
        // while its dissipated energy stays). The law's densities are per
        // current area while a point softens, so the energy is exact where
        // the mid-surface keeps its area while the point softens (openings
        // small against the element).
        let area = p
            .get("reference_area")
            .or_else(|| p.get("area"))
            .map_or(0.0, |a| a[0]);
        if let Some(d) = p.get(output::DISSIPATED_ENERGY) {
            e.dissipated_energy += d[0] * area;
        }
        if let Some(d) = p.get(output::VISCOUS_ENERGY) {
            e.viscous_energy += d[0] * area;
        }
        if let Some(d) = p.get(output::FRICTIONAL_DISSIPATION) {
            e.has_friction = true;
            e.frictional_dissipation += d[0] * area;
        }
        if p.get(output::DAMAGE).is_some() {
            e.has_damage = true;
            match point_stage(p) {
                PointStage::Failed => e.damaged_area += area,
                PointStage::ProcessZone => e.process_zone_area += area,
                PointStage::Intact => {}
            }
        }
    }
    e
}
