//! Ply failure indices of a converged state: each `[[ply_failure]]`
//! criterion of a scene ([`junta_core::PlyCriterion`], docs/ply_criteria.md)
//! evaluated on the stress in the material axes (`material_stress`) at
//! every integration point of its blocks.
//!
//! Per criterion the result holds the largest index of each cell (NaN in
//! cells it does not cover) and the point with the smallest strength ratio
//! `R`: the state scaled by `R` fails there first. In a linear analysis
//! the load is proportional to its factor, so `R` is the first-ply-failure
//! load factor (a temperature change scales with the load, as the linear
//! solve applies it).

use crate::error::{bail, err, Result};
use crate::input::scene::SceneFile;
use junta_core::element::StepInfo;
use junta_core::registry::{self, PlyCriterionEntry};
use junta_core::state::StateStore;
use junta_core::{Model, PlyCriterion, PlyFailureMode};
use std::sync::Arc;

/// One `[[ply_failure]]` of a scene: the criterion and the solid blocks it
/// is evaluated in.
#[derive(Debug, Clone)]
pub struct PlyCriterionUse {
    /// Output name (`name`, default the criterion's key): cell data
    /// `NAME_index`, `summary.json` `ply_failure.NAME`.
    pub name: String,
    /// The criterion.
    pub criterion: Arc<dyn PlyCriterion>,
    /// Blocks (indices into the mesh's blocks) it is evaluated in.
    pub blocks: Vec<usize>,
}

/// The `[[ply_failure]]` tables of a scene: `type` (a registered ply
/// criterion), optional `name` and `blocks` (element set names; default
/// every solid block whose material has axes of its own), and the
/// criterion's parameters.
pub fn from_scene(sf: &SceneFile, model: &Model) -> Result<Vec<PlyCriterionUse>> {
    let file = sf.path.display();
    let mut out: Vec<PlyCriterionUse> = Vec::new();
    for (i, table) in sf.scene.ply_failure.iter().enumerate() {
        let key = format!("ply_failure[{i}]");
        let mut t = table.clone();
        let Some(toml::Value::String(kind)) = t.remove("type") else {
            let valid: Vec<_> = registry::entries::<PlyCriterionEntry>()
                .iter()
                .map(|e| e.key)
                .collect();
            bail!(
                "{file}: key `{key}.type` is missing or not a string; valid types: {}",
                valid.join(", ")
            )
        };
        let name = match t.remove("name") {
            Some(toml::Value::String(s)) => s,
            None => kind.clone(),
            Some(v) => bail!("{file}: key `{key}.name`: {v} is not a string"),
        };
        if out.iter().any(|u| u.name == name) {
            bail!("{file}: key `{key}.name`: `{name}` is used twice; give each criterion its own `name`");
        }
        let blocks = criterion_blocks(sf, model, &key, t.remove("blocks"))?;
        let entry = registry::find::<PlyCriterionEntry>(&kind)
            .map_err(|e| err!("{file}: key `{key}.type`: {e}"))?;
        let criterion = (entry.build)(&t).map_err(|e| err!("{file}: key `{key}`: {e}"))?;
        out.push(PlyCriterionUse {
            name,
            criterion,
            blocks,
        });
    }
    Ok(out)
}

/// The solid blocks of `blocks = [element sets]`, or of every solid block
/// whose material has axes of its own.
fn criterion_blocks(
    sf: &SceneFile,
    model: &Model,
    key: &str,
    blocks: Option<toml::Value>,
) -> Result<Vec<usize>> {
    let file = sf.path.display();
    let mesh = &model.mesh;
    let solid = |b: usize| mesh.blocks[b].shape.is_solid();
    let list: Vec<usize> = match blocks {
        None => (0..mesh.blocks.len())
            .filter(|&b| solid(b) && has_axes(model, b))
            .collect(),
        Some(toml::Value::Array(names)) => {
            let mut v = Vec::new();
            for n in names {
                let toml::Value::String(n) = n else {
                    bail!("{file}: key `{key}.blocks`: {n} is not an element set name");
                };
                let set = mesh
                    .element_set(&n)
                    .map_err(|e| err!("{file}: key `{key}.blocks`: {e}"))?;
                v.extend(set.iter().map(|r| r.block).filter(|&b| solid(b)));
            }
            v.sort_unstable();
            v.dedup();
            v
        }
        Some(v) => bail!("{file}: key `{key}.blocks`: {v} is not a list of element set names"),
    };
    if list.is_empty() {
        bail!(
            "{file}: key `{key}`: no solid block to evaluate it in (a ply criterion needs material axes: an orthotropic or anisotropic material, or a [laminate] ply; or list `blocks`)"
        );
    }
    Ok(list)
}

fn has_axes(model: &Model, block: usize) -> bool {
    let b = &model.mesh.blocks[block];
    b.len() > 0 && {
        let x = model.mesh.nodes[b.element(0)[0]];
        model.elements[block]
            .material()
            .and_then(|m| m.axes_at(x))
            .is_some()
    }
}

/// Where a criterion's smallest strength ratio lies.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct WeakestPoint {
    /// Block name.
    pub block: String,
    /// Element label (the input's own number).
    pub element: usize,
    /// Reference position of the integration point.
    pub position: [f64; 3],
    /// Stress there in the material axes, Voigt `[11, 22, 33, 12, 23, 31]`.
    pub stress: [f64; 6],
    /// Failure mode there.
    pub mode: &'static str,
}

/// One criterion's result over its blocks.
#[derive(Debug, Clone)]
pub struct PlyFailureResult {
    /// Output name.
    pub name: String,
    /// Largest index per solid cell (cells in block order, as
    /// [`crate::post::fields::CellResults`]); NaN outside its blocks.
    pub cell_index: Vec<f64>,
    /// Largest index over its points.
    pub max_index: f64,
    /// Smallest strength ratio over its points.
    pub strength_ratio: f64,
    /// The point of the smallest strength ratio.
    pub weakest: Option<WeakestPoint>,
}

impl PlyFailureResult {
    /// `summary.json` `ply_failure.NAME`.
    pub fn to_json(&self, linear: bool) -> serde_json::Value {
        let mut v = serde_json::json!({
            "max_index": self.max_index,
            "strength_ratio": self.strength_ratio,
            "weakest": self.weakest,
        });
        if linear {
            v["first_ply_failure_load_factor"] = serde_json::json!(self.strength_ratio);
        }
        v
    }
}

/// Each result's largest index per cell as the cell data `NAME_index`.
pub fn add_cell_data(results: &[PlyFailureResult], cells: &mut crate::post::fields::CellResults) {
    for r in results {
        cells
            .extra
            .push((format!("{}_index", r.name), r.cell_index.clone()));
    }
}

/// `summary.json` `ply_failure`: each criterion by name (`linear`: with
/// its first-ply-failure load factor).
pub fn summary(results: &[PlyFailureResult], linear: bool) -> serde_json::Value {
    let m: serde_json::Map<String, serde_json::Value> = results
        .iter()
        .map(|r| (r.name.clone(), r.to_json(linear)))
        .collect();
    serde_json::Value::Object(m)
}

fn mode_name(m: PlyFailureMode) -> &'static str {
    match m {
        PlyFailureMode::FibreTension => "fibre_tension",
        PlyFailureMode::FibreCompression => "fibre_compression",
        PlyFailureMode::MatrixTension => "matrix_tension",
        PlyFailureMode::MatrixCompression => "matrix_compression",
        PlyFailureMode::Interaction => "interaction",
    }
}

/// Every criterion of `uses` at the state `u`, `state` of `step` (none
/// when `uses` is empty).
pub fn evaluate(
    model: &Model,
    u: &[f64],
    state: &StateStore,
    step: StepInfo,
    uses: &[PlyCriterionUse],
) -> Result<Vec<PlyFailureResult>> {
    if uses.is_empty() {
        return Ok(Vec::new());
    }
    let mut out: Vec<PlyFailureResult> = uses
        .iter()
        .map(|c| PlyFailureResult {
            name: c.name.clone(),
            cell_index: Vec::new(),
            max_index: f64::NAN,
            strength_ratio: f64::INFINITY,
            weakest: None,
        })
        .collect();
    for (bi, b) in model.mesh.blocks.iter().enumerate() {
        if !b.shape.is_solid() {
            continue;
        }
        let here: Vec<usize> = (0..uses.len())
            .filter(|&c| uses[c].blocks.contains(&bi))
            .collect();
        for e in 0..b.len() {
            if here.is_empty() {
                out.iter_mut().for_each(|r| r.cell_index.push(f64::NAN));
                continue;
            }
            let pts = crate::post::fields::element_points(model, u, state, bi, e, step)?;
            let mut cell = vec![f64::NAN; uses.len()];
            for p in &pts {
                let Some(s) = p.get("material_stress") else {
                    continue;
                };
                let s: [f64; 6] = [s[0], s[1], s[2], s[3], s[4], s[5]];
                for &c in &here {
                    let f = uses[c].criterion.evaluate(s);
                    let r = &mut out[c];
                    cell[c] = cell[c].max(f.index);
                    r.max_index = r.max_index.max(f.index);
                    if f.strength_ratio < r.strength_ratio {
                        r.strength_ratio = f.strength_ratio;
                        r.weakest = Some(WeakestPoint {
                            block: b.name.clone(),
                            element: model.mesh.element_label(bi, e),
                            position: p.position,
                            stress: s,
                            mode: mode_name(f.mode),
                        });
                    }
                }
            }
            for (r, v) in out.iter_mut().zip(cell) {
                r.cell_index.push(v);
            }
        }
    }
    Ok(out)
}
