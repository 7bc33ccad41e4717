//! `*NODE PRINT` requests of a deck, honoured as a CSV table
//! (`node_print.csv` in the output directory), so that a deck's printed
//! results compare line by line with CalculiX's `.dat`.
//!
//! One row per node of the named set, in ascending node label as CalculiX
//! prints them: `step,set,variable,node,1,2,3` where `variable` is `U`
//! (displacements) or `RF` (forces as CalculiX's `.dat` prints them: the
//! elements' internal force `f_int` at the node, so a load applied on a
//! constrained node itself, e.g. the share of a gravity load, is not in it;
//! the summary's `reactions` are the equilibrium reactions `f_int - f_ext`).
//! With `TOTALS=YES` a row `node = total` follows the nodes of each set;
//! with `TOTALS=ONLY` it is the only row. Other variables (`NT`, `PU`, ...)
//! have no meaning in a Junta run: noted, not written. Every solved step
//! gets rows: its own requests, or, for a step without any, those of the
//! nearest earlier step that has some (requests stay active, as in
//! CalculiX); a request outside any step applies to every step.

use anyhow::{anyhow, Result};
use junta_core::mesh::inp::{read_inp, InpNodePrint};
use junta_core::Model;
use std::fmt::Write as _;
use std::path::Path;

/// The `*NODE PRINT` requests of the deck `input`, or none for a scene.
pub fn node_prints(input: &Path) -> Result<Vec<InpNodePrint>> {
    if input.extension().and_then(|e| e.to_str()) != Some("inp") {
        return Ok(Vec::new());
    }
    let deck = read_inp(input).map_err(|e| anyhow!("{e}"))?;
    Ok(deck.node_prints)
}

/// Append the rows of the requests of step `step` (0-based) for the
/// solution `u` and the residual `r` (both `3 * node + component`) to
/// `out`; `notes` gets what was skipped.
pub fn rows(
    model: &Model,
    prints: &[InpNodePrint],
    step: usize,
    u: &[f64],
    r: &[f64],
    out: &mut String,
    notes: &mut Vec<String>,
) -> Result<()> {
    // the requests of this step, or of the nearest earlier step with some
    let owner = prints
        .iter()
        .filter_map(|p| p.step)
        .filter(|&s| s <= step)
        .max();
    for p in prints
        .iter()
        .filter(|p| p.step.is_none() || p.step == owner)
    {
        let Some((name, nodes)) = model
            .mesh
            .node_sets
            .iter()
            .find(|(k, _)| k.eq_ignore_ascii_case(&p.nset))
        else {
            return Err(anyhow!(
                "line {}: *NODE PRINT, NSET={}: no such node set",
                p.line,
                p.nset
            ));
        };
        let mut nodes: Vec<usize> = nodes.clone();
        nodes.sort_by_key(|&n| model.mesh.node_label(n));
        nodes.dedup();
        for v in &p.variables {
            let field = match v.as_str() {
                "U" => u,
                "RF" => r,
                other => {
                    notes.push(format!(
                        "line {}: *NODE PRINT variable {other} has no Junta counterpart; not written",
                        p.line
                    ));
                    continue;
                }
            };
            let mut total = [0.0; 3];
            for &n in &nodes {
                let x = [0, 1, 2].map(|c| field[3 * n + c]);
                for c in 0..3 {
                    total[c] += x[c];
                }
                if p.totals != "ONLY" {
                    let _ = writeln!(
                        out,
                        "{},{name},{v},{},{:e},{:e},{:e}",
                        step + 1,
                        model.mesh.node_label(n),
                        x[0],
                        x[1],
                        x[2]
                    );
                }
            }
            if p.totals != "NO" {
                let _ = writeln!(
                    out,
                    "{},{name},{v},total,{:e},{:e},{:e}",
                    step + 1,
                    total[0],
                    total[1],
                    total[2]
                );
            }
        }
    }
    Ok(())
}

/// The internal force `f_int = r + f_ext` from the residual `r = f_int -
/// f_ext` (the `RF` of CalculiX's `.dat`).
pub fn internal_force(residual: &[f64], f_ext: &[f64]) -> Vec<f64> {
    residual.iter().zip(f_ext).map(|(r, f)| r + f).collect()
}

/// Header of `node_print.csv`.
pub const HEADER: &str = "step,set,variable,node,1,2,3\n";
