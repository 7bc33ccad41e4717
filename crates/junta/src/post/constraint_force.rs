//! Reactions under `*EQUATION`s: the generalized reaction of each
//! reaction set, `summary.json` `generalized_reactions`.
//!
//! A prescribed dof that is the independent dof of linear equations (a
//! master node that a face or a periodic partner follows) carries two
//! forces: its own elements' share `r_p` (what `reactions`, the curve's
//! `reaction` and a deck's `*NODE PRINT` `RF` report, as CalculiX prints
//! it), and the constraint forces of the dependents tied to it. Their sum
//! with the equation coefficients, `R_p = r_p + sum_d c_dp r_d`, is the
//! reaction of the reduced system: the force conjugate to the prescribed
//! motion, whose work is the `external_work` (derivation at
//! [`junta_core::dof::DofMap::generalized_reactions_into`]). For a face
//! tied to a master node by `u_d - u_master = 0` it is the total force on
//! the face.

use crate::error::Result;
use junta_core::Model;
use serde_json::{json, Value};

/// The total generalized reaction `T^T r` on every reaction set (the sets
/// of `reactions`), or `None` when the model has no equations (then it
/// equals `reactions`). `residual` is the full `f_int - lambda f_ext`.
pub(crate) fn generalized_reactions(model: &Model, residual: &[f64]) -> Result<Option<Value>> {
    if !model.dofs.has_equations() {
        return Ok(None);
    }
    let g = model.dofs.generalized_reactions(residual);
    let mut m = serde_json::Map::new();
    for s in &model.reaction_sets {
        m.insert(s.clone(), json!(model.set_total(s, &g)?));
    }
    Ok(Some(Value::Object(m)))
}

/// Add `generalized_reactions` to a summary object when the model has
/// equations (a summary of a model without equations is left unchanged).
pub(crate) fn add_generalized_reactions(
    summary: &mut Value,
    model: &Model,
    residual: &[f64],
) -> Result<()> {
    if let Some(g) = generalized_reactions(model, residual)? {
        summary["generalized_reactions"] = g;
    }
    Ok(())
}
