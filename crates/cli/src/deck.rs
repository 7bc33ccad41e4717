//! Abaqus/CalculiX decks (`.inp`) to a [`Model`]: the reader lives in
//! `junta_core::mesh::inp`; here its materials become registry materials
//! (`*ELASTIC` isotropic -> `isotropic`, ENGINEERING CONSTANTS ->
//! `orthotropic`, TRACTION -> `linear_penalty` law for COH3D8), its
//! `*BOUNDARY` lines constraints and its `*CLOAD` lines nodal forces.
//! Reactions are reported for every `*BOUNDARY` target.

use anyhow::{anyhow, Result};
use junta_core::mesh::inp::{parse_inp, InpMaterialKind};
use junta_core::registry::{self, ElementBuild, ElementEntry, LawEntry, MaterialEntry};
use junta_core::Model;
use std::path::Path;

fn table(pairs: &[(&str, f64)]) -> toml::Table {
    pairs
        .iter()
        .map(|(k, v)| (k.to_string(), toml::Value::Float(*v)))
        .collect()
}

/// Read a deck and build the model; returns the reader's notes too.
pub fn build_model(path: &Path) -> Result<(Model, Vec<String>)> {
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
    let mut constraints = Vec::new();
    let mut reaction_sets: Vec<String> = Vec::new();
    for bc in &deck.boundaries {
        for &n in &bc.nodes {
            for dof in bc.first_dof..=bc.last_dof {
                constraints.push((3 * n + dof - 1, bc.value));
            }
        }
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
    let mut f_ext = vec![0.0; 3 * deck.mesh.nodes.len()];
    for c in &deck.cloads {
        for &n in &c.nodes {
            f_ext[3 * n + c.dof - 1] += c.value;
        }
    }
    let notes = deck.notes.clone();
    let model = Model::new(deck.mesh, elements, &constraints, f_ext, reaction_sets)
        .map_err(|e| anyhow!("{file}: {e}"))?;
    Ok((model, notes))
}
