//! `summary.json`'s sections: element counts, reactions, probes, the
//! ranges of the solids' and interfaces' fields, the penalty and
//! cohesive-zone advice, the solver's orderings and the distributed
//! partition.

use crate::error::{Context, Result};
use crate::post::fields::{component_range, interface_energy, CellResults, InterfaceResults};
use junta_core::{Model, PenaltyRole};
use junta_interface::advisor::STIFF_FACTOR;
use junta_interface::{CohesiveVerdict, PenaltyVerdict};
use serde_json::{json, Value};
use std::collections::BTreeMap;
use std::path::Path;

/// Elements counted per element type key.
pub fn element_counts(model: &Model) -> BTreeMap<String, usize> {
    let mut m = BTreeMap::new();
    for b in &model.mesh.blocks {
        *m.entry(b.element_type.clone()).or_insert(0) += b.len();
    }
    m
}

/// The orderings a direct solver computed, name -> predicted factor
/// non-zeros (`{}` for iterative solvers), for `summary.json`.
pub fn ordering_candidates(report: &junta_core::SolveReport) -> serde_json::Value {
    serde_json::Value::Object(
        report
            .ordering_candidates
            .iter()
            .map(|(k, n)| (k.clone(), serde_json::json!(n)))
            .collect(),
    )
}

/// Largest nodal displacement magnitude.
pub fn displacement_max(u: &[f64]) -> f64 {
    u.chunks(3)
        .map(|c| (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]).sqrt())
        .fold(0.0, f64::max)
}

/// Write a JSON value to a file, pretty.
pub fn write_json(path: &Path, v: &Value) -> Result<()> {
    let s = serde_json::to_string_pretty(v)?;
    std::fs::write(path, s + "\n").with_context(|| format!("cannot write {}", path.display()))
}

/// Reactions on every set that carries a boundary condition.
pub fn reactions(model: &Model, residual: &[f64]) -> Result<Value> {
    let mut m = serde_json::Map::new();
    for s in &model.reaction_sets {
        m.insert(s.clone(), json!(model.set_total(s, residual)?));
    }
    Ok(Value::Object(m))
}

/// Mean displacement of each probe node set.
pub fn probes(model: &Model, sets: &[String], u: &[f64]) -> Result<Value> {
    let mut m = serde_json::Map::new();
    for s in sets {
        let nodes = model.mesh.node_set(s)?;
        let mut mean = [0.0; 3];
        for &n in nodes {
            for c in 0..3 {
                mean[c] += u[3 * n + c] / nodes.len() as f64;
            }
        }
        m.insert(s.clone(), json!(mean));
    }
    Ok(Value::Object(m))
}

/// `summary.json` entry `interfaces`: per block, ranges of the local
/// tractions `[t1, t2, tn]` and jumps over all integration points.
pub fn interface_summary(model: &Model, res: &[InterfaceResults]) -> Value {
    let mut m = serde_json::Map::new();
    for r in res {
        let (tmin, tmax) = component_range(&r.points, "traction");
        let (jmin, jmax) = component_range(&r.points, "jump");
        let area: f64 = r
            .points
            .iter()
            .filter_map(|p| p.get("area"))
            .map(|a| a[0])
            .sum();
        let failed = r
            .points
            .iter()
            .filter(|p| p.get("failed").is_some_and(|f| f[0] > 0.5))
            .count();
        let b = &model.mesh.blocks[r.block];
        let energy = interface_energy(r);
        let mut entry = json!({
                "element": b.element_type,
                "elements": b.len(),
                "points": r.points.len(),
                "area": area,
                "traction_min": tmin,
                "traction_max": tmax,
                "jump_min": jmin,
                "jump_max": jmax,
                "failed_points": failed,
                "failed_fraction": failed as f64 / r.points.len().max(1) as f64,
        });
        if energy.has_damage {
            let o = entry.as_object_mut().expect("json object");
            o.insert("dissipated_energy".into(), json!(energy.dissipated_energy));
            o.insert("viscous_energy".into(), json!(energy.viscous_energy));
            o.insert("damaged_area".into(), json!(energy.damaged_area));
            o.insert("process_zone_area".into(), json!(energy.process_zone_area));
        }
        if energy.has_friction {
            let o = entry.as_object_mut().expect("json object");
            o.insert(
                "frictional_dissipation".into(),
                json!(energy.frictional_dissipation),
            );
            // points per contact state (stick / slip / open)
            let mut counts = [0usize; 3];
            for p in &r.points {
                if let Some(s) = p.get(junta_core::law::output::SLIP_STATE) {
                    counts[(s[0].round() as usize).min(2)] += 1;
                }
            }
            o.insert(
                "slip_state_points".into(),
                json!({ "stick": counts[0], "slip": counts[1], "open": counts[2] }),
            );
        }
        m.insert(b.name.clone(), entry);
    }
    Value::Object(m)
}

/// `summary.json` entry `solids`: per solid block, the range of each stress
/// component (Voigt `[xx, yy, zz, xy, yz, zx]`) over its integration points.
pub fn solid_summary(cells: &CellResults) -> Value {
    let mut m = serde_json::Map::new();
    for (name, lo, hi) in &cells.ranges {
        m.insert(name.clone(), json!({ "stress_min": lo, "stress_max": hi }));
    }
    Value::Object(m)
}

/// The penalty advisor of every interface block, as JSON and as text
/// lines, and the lines that are warnings (a verdict other than good).
///
/// A constraint penalty gets the paper's error analysis (eqs. 41-55) and
/// its recommended `d_op`; a cohesive law's penalty gets the compliance it
/// adds to the solids and Turon's bound instead (see
/// [`junta_interface::advisor`]).
pub fn penalty_advice(
    model: &Model,
    thickness: &dyn Fn(&str) -> Option<f64>,
) -> Result<(Value, Vec<String>, Vec<String>)> {
    let mut m = serde_json::Map::new();
    let mut lines = Vec::new();
    let mut warnings = Vec::new();
    let solids = junta_interface::advisor::SolidDiagonal::of_interfaces(model)?;
    for (bi, b) in model.mesh.blocks.iter().enumerate() {
        if !b.shape.is_interface() {
            continue;
        }
        let a = junta_interface::penalty_advice_with(model, bi, thickness(&b.name), &solids)?;
        let turon_t = a
            .turon
            .map(|k| format!("; Turon K = 50 E/t = {k:.3e}"))
            .unwrap_or_default();
        let (line, good, entry) = if a.role == PenaltyRole::Cohesive {
            cohesive_penalty_line(&a, &turon_t)
        } else {
            let verdict = match a.verdict {
                PenaltyVerdict::TooLow => {
                    "too low: the constraint error dominates (interpenetration / slip)"
                }
                PenaltyVerdict::Good => "good: within 10x of the error balance",
                PenaltyVerdict::TooHigh => "too high: round-off dominates (the solve loses digits)",
            };
            let line = format!(
                "interface `{}`: k_min = {:.3e}, n = {}, eps_op = k_min/sqrt(n e_c) = {:.3e} (force/length); \
                 area per node pair {:.3e} -> recommended d_op = {:.3e}; scene d3 = {:.3e}: {verdict} \
                 (estimated constraint error {:.1e}, round-off {:.1e}; best attainable {:.1e}){turon_t}",
                a.block,
                a.k_min,
                a.n,
                a.eps_op,
                a.area_per_pair,
                a.d_op,
                a.d_scene[2],
                a.constraint_error,
                a.roundoff_error,
                a.best_error,
            );
            let entry = json!({
                "role": a.role.name(),
                "k_min": a.k_min, "n": a.n, "e_c": a.e_c, "eps_op": a.eps_op,
                "area": a.area, "pairs": a.pairs, "area_per_pair": a.area_per_pair,
                "d_op": a.d_op, "d_scene": a.d_scene,
                "constraint_error": a.constraint_error, "roundoff_error": a.roundoff_error,
                "best_error": a.best_error, "verdict": format!("{:?}", a.verdict), "turon": a.turon,
            });
            (line, a.verdict == PenaltyVerdict::Good, entry)
        };
        if !good {
            warnings.push(line.clone());
        }
        lines.push(line);
        m.insert(a.block.clone(), entry);
    }
    Ok((Value::Object(m), lines, warnings))
}

/// The advisor's line, verdict and JSON for a cohesive law's penalty
/// (never the constraint optimum `d_op` as a recommendation: it appears
/// only as the round-off ceiling).
fn cohesive_penalty_line(
    a: &junta_interface::PenaltyAdvice,
    turon_t: &str,
) -> (String, bool, Value) {
    let Some(c) = a.cohesive else {
        let line = format!(
            "interface `{}`: cohesive law, K = {:.3e}: no solid of finite thickness with a modulus \
             across the interface beside it, so the penalty cannot be judged against the solids' \
             compliance (Turon: K >= 50 E_33 / t with t the thickness of the body beside it){turon_t}",
            a.block, a.d_scene[2]
        );
        let entry = json!({
            "role": a.role.name(), "d_scene": a.d_scene, "verdict": "unknown", "turon": a.turon,
        });
        return (line, true, entry);
    };
    let ceiling = if c.stiff_limit < STIFF_FACTOR * c.turon_bound {
        format!(
            "the round-off balance of the constraint analysis (eq. 55) {:.3e}",
            c.stiff_limit
        )
    } else {
        format!("{STIFF_FACTOR:.0e} x Turon's bound = {:.3e}", c.stiff_limit)
    };
    let verdict = match c.verdict {
        CohesiveVerdict::TooCompliant => format!(
            "too compliant: the penalty adds more than 2% compliance to the solids beside the \
             interface: raise K to at least Turon's bound {:.3e}",
            c.turon_bound
        ),
        CohesiveVerdict::Good => format!(
            "good: K is {:.3} x Turon's bound and below the stiff limit ({ceiling})",
            c.penalty / c.turon_bound,
        ),
        CohesiveVerdict::TooStiff => format!(
            "too stiff: above {ceiling}: a stiffer penalty gains no accuracy but invites traction \
             oscillations ahead of the crack and an ill-conditioned tangent; \
             K = {:.3e} .. {:.3e} (1 to 10 x Turon's bound 50 E_33/t) suffices",
            c.turon_bound,
            10.0 * c.turon_bound
        ),
    };
    let line = format!(
        "interface `{}`: cohesive law (its penalty is part of the model, not a constraint): \
         K = {:.3e}, E_33 = {:.4e}, arm thickness t = {:.4e}: the interface compliance 1/K = {:.3e} \
         is {:.2}% of the arm's t/E_33 = {:.3e}; Turon's bound K >= 50 E_33/t = {:.3e}: {verdict}{turon_t}",
        a.block,
        c.penalty,
        c.modulus_normal,
        c.arm_thickness,
        1.0 / c.penalty,
        100.0 * c.compliance_ratio,
        c.arm_thickness / c.modulus_normal,
        c.turon_bound,
    );
    let entry = json!({
        "role": a.role.name(),
        "d_scene": a.d_scene,
        "modulus_normal": c.modulus_normal,
        "arm_thickness": c.arm_thickness,
        "compliance_ratio": c.compliance_ratio,
        "turon_bound": c.turon_bound,
        "stiff_limit": c.stiff_limit,
        "roundoff_limit": a.d_op,
        "k_min": a.k_min, "n": a.n, "area_per_pair": a.area_per_pair,
        "verdict": c.verdict.name(),
        "turon": a.turon,
    });
    (line, c.verdict == CohesiveVerdict::Good, entry)
}

/// Mesh advice of every softening interface (cohesive-zone length,
/// elements spanning it, verdict, Turon's strengths) as JSON and text
/// lines, and the laws' parameter warnings as text lines.
pub fn cohesive_zone_advice(model: &Model) -> Result<(Value, Vec<String>, Vec<String>)> {
    let mut m = serde_json::Map::new();
    let mut lines = Vec::new();
    let mut warnings = Vec::new();
    for (bi, b) in model.mesh.blocks.iter().enumerate() {
        if !b.shape.is_interface() {
            continue;
        }
        for w in model.elements[bi].warnings() {
            warnings.push(format!("interface `{}`: {w}", b.name));
        }
        let Some(a) = junta_interface::cohesive_zone_advice(model, bi)? else {
            continue;
        };
        lines.push(a.message());
        let mode = |z: &junta_interface::cohesive_zone::ZoneLengths| {
            json!({
                "strength": z.strength, "toughness": z.toughness,
                "hillerborg": z.hillerborg, "rice": z.rice, "hui": z.hui,
                "slender": z.slender, "length": z.length,
                "turon_reduced_strength": z.reduced_strength,
            })
        };
        m.insert(
            a.block.clone(),
            json!({
                "modulus_normal": a.modulus_normal,
                "modulus_along": a.modulus_along,
                "arm_thickness": a.arm_thickness,
                "element_length_min": a.element_length_min,
                "element_length_max": a.element_length_max,
                "mode_i": mode(&a.mode_i),
                "mode_ii": mode(&a.mode_ii),
                "cohesive_zone_length": a.length,
                "crack_region": a.crack_region.as_ref().map(|r| json!({
                    "front_edges": r.front_edges, "radius": r.radius, "elements": r.elements,
                    "element_length_min": r.element_length_min,
                    "element_length_max": r.element_length_max,
                })),
                "elements_in_zone": a.elements_in_zone,
                "verdict": a.verdict.name(),
                "law_warnings": model.elements[bi].warnings(),
            }),
        );
    }
    Ok((Value::Object(m), lines, warnings))
}

/// `summary.json` `plane` of a plane (2D) model, `null` for a 3D one: the
/// section (`plane_strain`, `plane_stress`, `axisymmetric`), the width its
/// forces, reactions and energies are those of (a thickness, or the full
/// ring of 2 pi radians), and a sentence saying so.
pub fn plane_summary(model: &junta_core::Model) -> serde_json::Value {
    use junta_core::element::PlaneWidth;
    if !model.mesh.blocks.iter().all(|b| b.shape.dimension() == 2) {
        return serde_json::Value::Null;
    }
    let solid = |prefix: &str| {
        model
            .mesh
            .blocks
            .iter()
            .any(|b| b.element_type.starts_with(prefix))
    };
    let section = match (solid("cax"), solid("cps"), solid("cpe")) {
        (true, _, _) => "axisymmetric",
        (_, true, true) => "plane_strain_and_plane_stress",
        (_, true, false) => "plane_stress",
        _ => "plane_strain",
    };
    match model.elements.iter().find_map(|e| e.plane_width()) {
        Some(PlaneWidth::Axisymmetric) => serde_json::json!({
            "section": section,
            "width": "full_ring",
            "note": "forces, reactions and energies are those of the full ring (2 pi radians); x is the radius, y the axis",
        }),
        Some(PlaneWidth::Thickness(t)) => serde_json::json!({
            "section": section,
            "width": "thickness",
            "thickness": t,
            "note": format!("forces, reactions and energies are those of the out-of-plane thickness {t}"),
        }),
        None => serde_json::Value::Null,
    }
}

/// `summary.json` `distributed` of a run over MPI ranks (`null` in one
/// process): the ranks, and per rank its elements, the nodes they touch
/// and of those the nodes shared with other ranks (the partition's cut,
/// [`junta_core::distributed::partition_cut`]), with the bytes per Newton
/// iteration each rank exchanges; the equations each rank owns and holds as
/// ghosts, and each rank's peak resident memory so far, also per owned
/// equation. Collective: every rank calls it once.
pub fn distributed_summary(model: &junta_core::Model) -> serde_json::Value {
    use junta_core::distributed::{
        collective, equations_by_rank, partition_cut, partition_elements,
    };
    let Some(c) = collective() else {
        return serde_json::Value::Null;
    };
    let ranks = c.size();
    let parts = partition_elements(&model.mesh, ranks);
    let cut = partition_cut(&model.mesh, &parts, ranks);
    let (owned, ghost) = equations_by_rank(&model.mesh, &parts, ranks, &model.dofs);
    let mut peak = vec![0.0; ranks];
    peak[c.rank()] = crate::prepare::limits::peak_resident_bytes().unwrap_or(0) as f64;
    c.sum_in_place(&mut peak);
    let n = model.dofs.num_free as f64;
    let states: usize = model
        .mesh
        .blocks
        .iter()
        .zip(&model.elements)
        .map(|(b, e)| b.len() * e.state_len())
        .sum();
    serde_json::json!({
        "ranks": ranks,
        "partition": "recursive coordinate bisection of the element centroids, weighted by element matrix size",
        "elements": cut.elements,
        "nodes": cut.nodes,
        "shared_nodes": cut.shared_nodes,
        // PETSc's matrix and vector halo: 3 dofs of each shared node, both ways
        "halo_bytes_per_iteration": cut.shared_nodes.iter().map(|s| 2 * 3 * 8 * s).collect::<Vec<_>>(),
        // replicated vectors: the force sum, the state copy and the solution
        // gathered on every rank, each the whole length
        "replicated_bytes_per_iteration": 8.0 * (2.0 * 3.0 * model.mesh.nodes.len() as f64 + states as f64 + n),
        "owned_equations": owned,
        "ghost_equations": ghost,
        // VmHWM of each rank when the summary is made (the run's end)
        "peak_resident_bytes": peak,
        "peak_bytes_per_owned_equation": peak.iter().zip(&owned).map(|(p, &o)| (p / o.max(1) as f64).round()).collect::<Vec<_>>(),
    })
}
