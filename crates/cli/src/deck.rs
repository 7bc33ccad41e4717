//! Abaqus/CalculiX decks (`.inp`) to a [`Model`]: the reader lives in
//! `junta_core::mesh::inp`; here its materials become registry materials
//! (`*ELASTIC` isotropic -> `isotropic`, ENGINEERING CONSTANTS ->
//! `orthotropic`, TRACTION -> `linear_penalty` law for COH3D8), its
//! `*BOUNDARY` lines constraints and its `*CLOAD` lines nodal forces.
//! Reactions are reported for every `*BOUNDARY` target.
//!
//! Several `*STEP`s are several linear load cases, with CalculiX's rules
//! (checked against `ccx` 2.20 on a 4-step deck):
//! - boundary conditions and loads of earlier steps (and the model data)
//!   stay; a step's value on a dof replaces the earlier one (`OP=MOD`, the
//!   default);
//! - `OP=NEW` on a keyword removes everything of its kind given before it;
//! - several `*CLOAD` values on one dof within a step add up; two different
//!   `*BOUNDARY` values on one dof within a step are an error;
//! - each step is solved from the unloaded state (linear analysis: the
//!   result of a step is the response to its loads, not an increment).

use anyhow::{anyhow, Result};
use junta_core::mesh::inp::{parse_inp, InpDeck, InpMaterialKind};
use junta_core::registry::{self, ElementBuild, ElementEntry, LawEntry, MaterialEntry};
use junta_core::Model;
use std::path::Path;

fn table(pairs: &[(&str, f64)]) -> toml::Table {
    pairs
        .iter()
        .map(|(k, v)| (k.to_string(), toml::Value::Float(*v)))
        .collect()
}

/// Read a deck and build the model (with the boundary conditions and loads
/// of its first step); returns the reader's notes and every step's load
/// case too.
pub fn build_model(path: &Path) -> Result<(Model, Vec<String>, Vec<DeckStep>)> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| anyhow!("cannot read deck {}: {e}", path.display()))?;
    let file = path.display().to_string();
    let mut deck = parse_inp(&text, &file).map_err(|e| anyhow!("{e}"))?;
    let mut elements = Vec::new();
    for b in &deck.mesh.blocks {
        let mat = deck.material(&b.material).ok_or_else(|| {
            anyhow!(
                "{file}: elements of block `{}` have no material: add a *SOLID SECTION (or *COHESIVE SECTION) for their ELSET",
                b.name
            )
        })?;
        let entry =
            registry::find::<ElementEntry>(&b.element_type).map_err(|e| anyhow!("{file}: {e}"))?;
        let mut build = ElementBuild {
            material: None,
            law: None,
            options: &toml::Table::new(),
        };
        let at = format!("{file}:{}: *MATERIAL, NAME={}", mat.line, mat.name);
        match (&mat.kind, b.shape.is_interface()) {
            (InpMaterialKind::Isotropic { e, nu }, false) => {
                let m = registry::find::<MaterialEntry>("isotropic")?;
                build.material = Some((m.build)(&table(&[("E", *e), ("nu", *nu)])).map_err(|e| anyhow!("{at}: {e}"))?);
            }
            (InpMaterialKind::EngineeringConstants(c), false) => {
                let names = ["E1", "E2", "E3", "nu12", "nu13", "nu23", "G12", "G13", "G23"];
                let pairs: Vec<(&str, f64)> = names.iter().copied().zip(c.iter().copied()).collect();
                let m = registry::find::<MaterialEntry>("orthotropic")?;
                build.material = Some((m.build)(&table(&pairs)).map_err(|e| anyhow!("{at}: {e}"))?);
            }
            (InpMaterialKind::Traction([enn, ess, ett]), true) => {
                let l = registry::find::<LawEntry>("linear_penalty")?;
                let t = table(&[("d1", *ess), ("d2", *ett), ("d3", *enn)]);
                build.law = Some((l.build)(&t).map_err(|e| anyhow!("{at}: {e}"))?);
            }
            (_, true) => {
                return Err(anyhow!(
                    "{at}: cohesive elements of block `{}` need *ELASTIC, TYPE=TRACTION",
                    b.name
                ))
            }
            (_, false) => {
                return Err(anyhow!(
                    "{at}: solid elements of block `{}` need *ELASTIC (ISOTROPIC or ENGINEERING CONSTANTS)",
                    b.name
                ))
            }
        }
        elements
            .push((entry.build)(&build).map_err(|e| anyhow!("{file}: block `{}`: {e}", b.name))?);
    }
    let steps = deck_steps(&deck, &file)?;
    let mut reaction_sets: Vec<String> = Vec::new();
    for bc in &deck.boundaries {
        let name = match deck
            .mesh
            .node_sets
            .keys()
            .find(|k| k.eq_ignore_ascii_case(&bc.target))
        {
            Some(k) => k.clone(),
            None => {
                let k = format!("node_{}", bc.target);
                deck.mesh.node_sets.insert(k.clone(), bc.nodes.clone());
                k
            }
        };
        if !reaction_sets.contains(&name) {
            reaction_sets.push(name);
        }
    }
    let notes = deck.notes.clone();
    let first = &steps[0];
    let model = Model::new(
        deck.mesh,
        elements,
        &first.constraints,
        first.f_ext.clone(),
        reaction_sets,
    )
    .map_err(|e| anyhow!("{file}: {e}"))?;
    Ok((model, notes, steps))
}

/// The boundary conditions and loads in force in one step of a deck.
#[derive(Debug, Clone)]
pub struct DeckStep {
    /// `*STEP, NAME=` or `step N` (1-based).
    pub name: String,
    /// Line of `*STEP` (0 for a deck without steps).
    pub line: usize,
    /// `(dof, value)`, sorted by dof.
    pub constraints: Vec<(usize, f64)>,
    /// Nodal forces (length = dofs).
    pub f_ext: Vec<f64>,
}

/// The load cases of a deck: one per `*STEP` (one in all for a deck
/// without steps), by the rules of the module docs.
pub fn deck_steps(deck: &InpDeck, file: &str) -> Result<Vec<DeckStep>> {
    use std::collections::BTreeMap;
    let ndof = 3 * deck.mesh.nodes.len();
    let nsteps = deck.steps.len().max(1);
    let mut out = Vec::with_capacity(nsteps);
    for k in 0..nsteps {
        let upto = |s: Option<usize>| s.is_none_or(|s| s <= k);
        // dof -> (value, step it was set in, line)
        let mut bcs: BTreeMap<usize, (f64, Option<usize>, usize)> = BTreeMap::new();
        let mut cleared_at = None;
        for bc in deck.boundaries.iter().filter(|b| upto(b.step)) {
            if bc.op_new && cleared_at != Some(bc.keyword_line) {
                bcs.clear();
                cleared_at = Some(bc.keyword_line);
            }
            for &n in &bc.nodes {
                for dof in bc.first_dof..=bc.last_dof {
                    let d = 3 * n + dof - 1;
                    if let Some(&(v, s, line)) = bcs.get(&d) {
                        if s == bc.step && v != bc.value {
                            return Err(anyhow!(
                                "{file}:{}: *BOUNDARY: node {} dof {dof} is given {} here and {v} at line {line} of the same {}",
                                bc.line,
                                deck.mesh.node_labels.get(n).copied().unwrap_or(n + 1),
                                bc.value,
                                if bc.step.is_some() { "step" } else { "model data" }
                            ));
                        }
                    }
                    bcs.insert(d, (bc.value, bc.step, bc.line));
                }
            }
        }
        // dof -> (value, step it was set in)
        let mut loads: BTreeMap<usize, (f64, Option<usize>)> = BTreeMap::new();
        let mut cleared_at = None;
        for c in deck.cloads.iter().filter(|c| upto(c.step)) {
            if c.op_new && cleared_at != Some(c.keyword_line) {
                loads.clear();
                cleared_at = Some(c.keyword_line);
            }
            for &n in &c.nodes {
                let d = 3 * n + c.dof - 1;
                match loads.get_mut(&d) {
                    // within one step (or the model data) loads add up
                    Some((v, s)) if *s == c.step => *v += c.value,
                    // a later step replaces the value
                    _ => {
                        loads.insert(d, (c.value, c.step));
                    }
                }
            }
        }
        let mut f_ext = vec![0.0; ndof];
        for (d, (v, _)) in loads {
            f_ext[d] = v;
        }
        let step = deck.steps.get(k);
        out.push(DeckStep {
            name: step
                .and_then(|s| s.name.clone())
                .unwrap_or_else(|| format!("step {}", k + 1)),
            line: step.map_or(0, |s| s.line),
            constraints: bcs.into_iter().map(|(d, (v, _, _))| (d, v)).collect(),
            f_ext,
        });
    }
    Ok(out)
}
