//! The registry as data: every element, material, law, criterion, ply
//! criterion and solver with its parameters (what `junta list` prints), as text and as the
//! Markdown page `docs/parameters.md`.

use junta_core::registry::{
    self, CriterionEntry, ElementEntry, Entry, LawEntry, MaterialEntry, PlyCriterionEntry,
    SolverEntry,
};
use serde::Serialize;
use std::fmt::Write;

/// One parameter of a plugin.
#[derive(Debug, Clone, Serialize)]
pub struct Param {
    /// Key in the TOML table.
    pub name: &'static str,
    /// What it means, its unit and default.
    pub doc: &'static str,
}

/// One registered plugin.
#[derive(Debug, Clone, Serialize)]
pub struct Plugin {
    /// Registry key (`bilinear`, `h20`, ...).
    pub key: &'static str,
    /// One-line description.
    pub description: &'static str,
    /// Parameters.
    pub params: Vec<Param>,
}

/// The plugins of one kind.
#[derive(Debug, Clone, Serialize)]
pub struct Section {
    /// Title (`interface laws`).
    pub title: &'static str,
    /// The plugins, in the registry's order.
    pub plugins: Vec<Plugin>,
}

fn section<E: Entry>(title: &'static str) -> Section
where
    junta_core::inventory::iter<E>: IntoIterator<Item = &'static E>,
{
    Section {
        title,
        plugins: registry::entries::<E>()
            .into_iter()
            .map(|e| Plugin {
                key: e.key(),
                description: e.description(),
                params: e
                    .params()
                    .iter()
                    .map(|p| Param {
                        name: p.name,
                        doc: p.doc,
                    })
                    .collect(),
            })
            .collect(),
    }
}

/// Every registered plugin, and the incremental controls.
pub fn catalog() -> Vec<Section> {
    let controls = Section {
        title: "incremental controls ([analysis] type = \"static\")",
        plugins: vec![
            Plugin {
                key: "load",
                description: "the load factor is prescribed: load or displacement control, whatever the scene prescribes; [analysis.newton]",
                params: Vec::new(),
            },
            Plugin {
                key: "arc_length",
                description: "path following through limit points and snap-backs: cylindrical arc length, then the dissipated energy once the laws dissipate; one step, [analysis.newton] tolerances, and [analysis.arc_length]:",
                params: junta_solvers::arc_length::PARAMETERS
                    .iter()
                    .map(|(name, doc)| Param { name, doc })
                    .collect(),
            },
        ],
    };
    vec![
        section::<ElementEntry>("elements"),
        section::<MaterialEntry>("materials"),
        section::<LawEntry>("interface laws"),
        section::<CriterionEntry>("failure criteria"),
        section::<PlyCriterionEntry>("ply failure criteria (outputs on ply stresses)"),
        section::<SolverEntry>("linear solvers"),
        controls,
    ]
}

/// What `junta list` prints.
pub fn text() -> String {
    let mut s = String::new();
    for sec in catalog() {
        let _ = writeln!(s, "{}:", sec.title);
        let controls = sec.title.starts_with("incremental");
        for p in &sec.plugins {
            let _ = writeln!(s, "  {:<16} {}", p.key, p.description);
            for q in &p.params {
                if controls {
                    let _ = writeln!(s, "      {:<20} {}", q.name, q.doc);
                } else {
                    let _ = writeln!(s, "      {:<12} {}", q.name, q.doc);
                }
            }
        }
    }
    s
}

/// `docs/parameters.md`: the same catalogue as Markdown tables.
pub fn markdown() -> String {
    let mut s = String::from(
        "# Parameters\n\nEvery registered element, material, interface law, failure criterion, ply failure criterion, linear solver and incremental control with its parameters. Generated from the registry by `junta list --markdown > docs/parameters.md`; a test fails when this page is stale.\n",
    );
    for sec in catalog() {
        let _ = write!(s, "\n## {}\n", sec.title);
        for p in &sec.plugins {
            let _ = write!(
                s,
                "\n### `{}`\n\n{}\n",
                p.key,
                p.description.replace('\n', " ")
            );
            if !p.params.is_empty() {
                s += "\n| parameter | meaning |\n|---|---|\n";
                for q in &p.params {
                    let _ = writeln!(
                        s,
                        "| `{}` | {} |",
                        q.name,
                        q.doc.replace('|', "\\|").replace('\n', " ")
                    );
                }
            }
        }
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `junta list` prints the ply criteria as their own section, each with
    /// its parameters.
    #[test]
    fn catalog_lists_the_ply_criteria_with_parameters() {
        let sections = catalog();
        let ply = sections
            .iter()
            .find(|s| s.title.starts_with("ply failure criteria"))
            .expect("a ply criteria section");
        let keys: Vec<_> = ply.plugins.iter().map(|p| p.key).collect();
        assert_eq!(keys, ["hashin", "ply_max_stress", "puck", "tsai_wu"]);
        let puck = &ply.plugins[2];
        assert!(puck.params.iter().any(|p| p.name == "p_perp_perp_minus"));
        let listing = text();
        assert!(listing.contains("ply failure criteria (outputs on ply stresses):\n  hashin"));
        assert!(listing.contains("      f12_star"));
    }
}
