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
//!
//! In an incremental run (a deck with a softening law) the rows of a step
//! are those of its last increment, at the step's end load (CalculiX's
//! `.dat` prints every increment; its last block of a step is the one
//! compared). The tables are saved at the end of every step; a run that
//! stops inside a step prints that step at its last converged increment
//! and says so, and a restart keeps the rows of the steps already done.
//!
//! `*EL PRINT, ELSET=` requests go to `el_print.csv`:
//! `step,set,variable,element,point,1,...,6`, elements in ascending label,
//! integration points in the element's rule order (for hexahedra `xi`
//! fastest, `zeta` slowest, as CalculiX numbers them), components in
//! CalculiX's order: `S` the stresses `xx, yy, zz, xy, xz, yz`, `E` the
//! strains with tensor shear components (`e_xy = gamma_xy / 2`); for an
//! element with an `*ORIENTATION` (rectangular or cylindrical) in its
//! material axes at the point (`Q^T sigma Q`), as CalculiX prints them,
//! unless the request says `GLOBAL=YES`. `ME` (mechanical strains) is
//! `E` less the thermal strain (the same without a temperature change),
//! `ENER` the energy density `sigma : eps_mech / 2` at each point, `COORD` the points' global
//! coordinates, and per element (empty `point`) `ELSE` the strain energy
//! `sum_q sigma : eps / 2 dV_q` and `EVOL` the volume `sum_q dV_q` (`dV_q`
//! = weight x det J, the elements' `volume` output); unused columns are
//! empty. Other variables (`PEEQ`: CalculiX prints none for an elastic
//! material), and interface elements in the set, are noted and not
//! written. The same step rules as `*NODE PRINT` apply.

use crate::error::{err, Context, Result};
use crate::input::inp::{InpElPrint, InpNodePrint};
use junta_core::state::StateStore;
use junta_core::Model;
use junta_elements::material::Axes;
use nalgebra::Matrix3;
use std::fmt::Write as _;
use std::path::Path;

/// The print requests of a deck and the tables they fill, step by step.
#[derive(Debug, Default)]
pub struct PrintTables {
    nodes: Vec<InpNodePrint>,
    elements: Vec<InpElPrint>,
    node_csv: String,
    el_csv: String,
    notes: Vec<String>,
    /// Material axes of each block with an orientation (by block index).
    axes: Vec<Option<Axes>>,
}

impl PrintTables {
    /// Empty tables for the requests of a deck.
    pub fn new(nodes: Vec<InpNodePrint>, elements: Vec<InpElPrint>) -> Self {
        PrintTables {
            nodes,
            elements,
            node_csv: HEADER.to_string(),
            el_csv: EL_HEADER.to_string(),
            notes: Vec::new(),
            axes: Vec::new(),
        }
    }

    /// The material axes of each mesh block (`None`: no orientation):
    /// `*EL PRINT` rows of oriented elements are in those axes.
    pub fn with_axes(mut self, axes: Vec<Option<Axes>>) -> Self {
        self.axes = axes;
        self
    }

    /// Whether the deck asked for nothing.
    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty() && self.elements.is_empty()
    }

    /// Add the rows of step `step` (0-based): solution `u`, residual
    /// `f_int - f_ext` with the step's `f_ext`, element state `state`.
    pub fn add_step(
        &mut self,
        model: &Model,
        step: usize,
        u: &[f64],
        residual: &[f64],
        f_ext: &[f64],
        state: &StateStore,
    ) -> Result<()> {
        let f_int = if self.nodes.is_empty() {
            Vec::new()
        } else {
            internal_force(residual, f_ext)
        };
        self.add_step_with_internal_force(model, step, u, &f_int, state)
    }

    /// [`PrintTables::add_step`] given the elements' internal force
    /// `f_int` itself (what `RF` prints; unused without `*NODE PRINT`).
    pub fn add_step_with_internal_force(
        &mut self,
        model: &Model,
        step: usize,
        u: &[f64],
        f_int: &[f64],
        state: &StateStore,
    ) -> Result<()> {
        if !self.nodes.is_empty() {
            rows(
                model,
                &self.nodes,
                step,
                u,
                f_int,
                &mut self.node_csv,
                &mut self.notes,
            )?;
        }
        if !self.elements.is_empty() {
            el_rows(
                model,
                (&self.elements, &self.axes),
                step,
                u,
                state,
                &mut self.el_csv,
                &mut self.notes,
            )?;
        }
        Ok(())
    }

    /// Write `node_print.csv` / `el_print.csv` (those requested) to `dir`;
    /// returns the notes (what was not written, once each).
    pub fn write(mut self, dir: &Path) -> Result<Vec<String>> {
        self.save(dir)?;
        let mut seen = std::collections::HashSet::new();
        self.notes.retain(|n| seen.insert(n.clone()));
        Ok(self.notes)
    }

    /// Write the tables as they stand (an incremental run saves them at
    /// the end of every step, so that a stopped run keeps its rows).
    pub fn save(&self, dir: &Path) -> Result<()> {
        for (reqs, name, text) in [
            (!self.nodes.is_empty(), "node_print.csv", &self.node_csv),
            (!self.elements.is_empty(), "el_print.csv", &self.el_csv),
        ] {
            if reqs {
                std::fs::write(dir.join(name), text)
                    .with_context(|| format!("writing {}", dir.join(name).display()))?;
            }
        }
        Ok(())
    }

    /// Add a note (printed once, with the others, by [`PrintTables::write`]).
    pub fn note(&mut self, note: String) {
        self.notes.push(note);
    }

    /// Keep the rows of steps before `step` (0-based) from the tables a
    /// stopped run wrote to `dir` (a restart continues them).
    pub fn resume_from(&mut self, dir: &Path, step: usize) {
        for (name, csv) in [
            ("node_print.csv", &mut self.node_csv),
            ("el_print.csv", &mut self.el_csv),
        ] {
            let Ok(text) = std::fs::read_to_string(dir.join(name)) else {
                continue;
            };
            for line in text.lines().skip(1) {
                let s = line.split(',').next().and_then(|s| s.parse::<usize>().ok());
                if s.is_some_and(|s| s >= 1 && s <= step) {
                    csv.push_str(line);
                    csv.push('\n');
                }
            }
        }
    }
}

/// The requests in force in step `step`: those given outside any step,
/// and those of `step` or, when it has none, of the nearest earlier step
/// with some (requests stay active, as in CalculiX).
fn active<T>(
    prints: &[T],
    step_of: impl Fn(&T) -> Option<usize>,
    step: usize,
) -> impl Iterator<Item = &T> {
    let owner = prints
        .iter()
        .filter_map(&step_of)
        .filter(|&s| s <= step)
        .max();
    prints.iter().filter(move |p| {
        let s = step_of(p);
        s.is_none() || s == owner
    })
}

/// The set called `name` (case-insensitive, as decks name sets).
fn named<'a, V>(
    sets: &'a std::collections::BTreeMap<String, V>,
    name: &str,
) -> Option<(&'a String, &'a V)> {
    sets.iter().find(|(k, _)| k.eq_ignore_ascii_case(name))
}

/// Header of `el_print.csv`.
pub const EL_HEADER: &str = "step,set,variable,element,point,1,2,3,4,5,6\n";

/// Append the `*EL PRINT` rows of step `step` (module docs): the requests
/// come paired with the material axes of each block (`None`: no
/// orientation).
fn el_rows(
    model: &Model,
    (prints, axes): (&[InpElPrint], &[Option<Axes>]),
    step: usize,
    u: &[f64],
    state: &StateStore,
    out: &mut String,
    notes: &mut Vec<String>,
) -> Result<()> {
    for p in active(prints, |p| p.step, step) {
        let Some((name, members)) = named(&model.mesh.element_sets, &p.elset) else {
            return Err(err!(
                "line {}: *EL PRINT, ELSET={}: no such element set",
                p.line,
                p.elset
            ));
        };
        let mut members = members.clone();
        members.sort_by_key(|r| model.mesh.element_label(r.block, r.element));
        members.dedup();
        for v in &p.variables {
            let Some(kind) = ElVariable::of(v) else {
                notes.push(format!(
                    "line {}: *EL PRINT variable {v} is not written (Junta prints S, E, ME, ENER, ELSE, EVOL, COORD; PEEQ only with plasticity, which Junta's solids do not have, as CalculiX prints no PEEQ for an elastic material)",
                    p.line
                ));
                continue;
            };
            for r in &members {
                if !model.mesh.blocks[r.block].shape.is_solid() {
                    notes.push(format!(
                        "line {}: *EL PRINT, ELSET={}: interface elements have no {v}; not written",
                        p.line, p.elset
                    ));
                    continue;
                }
                let label = model.mesh.element_label(r.block, r.element);
                let pts = crate::post::fields::element_points(
                    model,
                    u,
                    state,
                    r.block,
                    r.element,
                    junta_core::element::StepInfo::default(),
                )?;
                let at = |pt: &junta_core::PointOutput, key: &str| -> Result<Vec<f64>> {
                    if key == "mechanical_strain" {
                        // the total strain less the thermal strain, if any
                        let mut e = pt.get("strain").map(<[f64]>::to_vec).ok_or_else(|| {
                            err!("element {label} reports no strain at its integration points")
                        })?;
                        if let Some(th) = pt.get("thermal_strain") {
                            e.iter_mut().zip(th).for_each(|(e, t)| *e -= t);
                        }
                        return Ok(e);
                    }
                    pt.get(key).map(<[f64]>::to_vec).ok_or_else(|| {
                        err!("element {label} reports no {key} at its integration points")
                    })
                };
                // per element: the integral over its volume
                if matches!(kind, ElVariable::Energy | ElVariable::Volume) {
                    let mut sum = 0.0;
                    for pt in &pts {
                        let dv = at(pt, "volume")?[0];
                        sum += match kind {
                            ElVariable::Energy => {
                                energy_density(&at(pt, "stress")?, &at(pt, "mechanical_strain")?)
                                    * dv
                            }
                            _ => dv,
                        };
                    }
                    let _ = writeln!(out, "{},{name},{v},{label},,{sum:e},,,,,", step + 1);
                    continue;
                }
                for (q, pt) in pts.iter().enumerate() {
                    let vals: Vec<f64> = match kind {
                        ElVariable::Stress | ElVariable::Strain | ElVariable::MechanicalStrain => {
                            let (x, shear) = match kind {
                                ElVariable::Stress => (at(pt, "stress")?, 1.0),
                                ElVariable::Strain => (at(pt, "strain")?, 0.5),
                                _ => (at(pt, "mechanical_strain")?, 0.5),
                            };
                            // ours: xx, yy, zz, xy, yz, zx (engineering shear
                            // for strains); CalculiX: xx, yy, zz, xy, xz, yz
                            let mut c =
                                [x[0], x[1], x[2], shear * x[3], shear * x[5], shear * x[4]];
                            if let (false, Some(Some(a))) = (p.global, axes.get(r.block)) {
                                c = to_local(&c, &a.at(pt.position));
                            }
                            c.to_vec()
                        }
                        ElVariable::EnergyDensity => {
                            vec![energy_density(
                                &at(pt, "stress")?,
                                &at(pt, "mechanical_strain")?,
                            )]
                        }
                        ElVariable::Coordinates => pt.position.to_vec(),
                        ElVariable::Energy | ElVariable::Volume => {
                            unreachable!("per element above")
                        }
                    };
                    let _ = write!(out, "{},{name},{v},{label},{}", step + 1, q + 1);
                    for c in 0..6 {
                        match vals.get(c) {
                            Some(x) => {
                                let _ = write!(out, ",{x:e}");
                            }
                            None => out.push(','),
                        }
                    }
                    out.push('\n');
                }
            }
        }
    }
    Ok(())
}

/// The `*EL PRINT` variables Junta writes (CalculiX's names).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum ElVariable {
    /// `S`: stresses at the integration points.
    Stress,
    /// `E`: total strains with tensor shear components.
    Strain,
    /// `ME`: mechanical strains, `E` less the thermal strain.
    MechanicalStrain,
    /// `ENER`: strain energy density `sigma : eps / 2` at the points.
    EnergyDensity,
    /// `ELSE`: strain energy of the element, `int sigma : eps / 2 dV`.
    Energy,
    /// `EVOL`: volume of the element.
    Volume,
    /// `COORD`: global coordinates of the integration points.
    Coordinates,
}

impl ElVariable {
    fn of(name: &str) -> Option<Self> {
        Some(match name {
            "S" => ElVariable::Stress,
            "E" => ElVariable::Strain,
            "ME" => ElVariable::MechanicalStrain,
            "ENER" => ElVariable::EnergyDensity,
            "ELSE" => ElVariable::Energy,
            "EVOL" => ElVariable::Volume,
            "COORD" => ElVariable::Coordinates,
            _ => return None,
        })
    }
}

/// `sigma : eps / 2` from Voigt stresses and strains with engineering
/// shear components (the same order).
fn energy_density(s: &[f64], e: &[f64]) -> f64 {
    0.5 * s.iter().zip(e).map(|(a, b)| a * b).sum::<f64>()
}

/// A symmetric tensor in CalculiX's order `xx, yy, zz, xy, xz, yz` in the
/// axes `q` (columns: the local axes in global components): `Q^T T Q`, in
/// the same order.
fn to_local(c: &[f64; 6], q: &Matrix3<f64>) -> [f64; 6] {
    let t = Matrix3::new(c[0], c[3], c[4], c[3], c[1], c[5], c[4], c[5], c[2]);
    let l = q.transpose() * t * q;
    [
        l[(0, 0)],
        l[(1, 1)],
        l[(2, 2)],
        l[(0, 1)],
        l[(0, 2)],
        l[(1, 2)],
    ]
}

/// Append the rows of the requests of step `step` (0-based) for the
/// solution `u` and the residual `r` (both `3 * node + component`) to
/// `out`; `notes` gets what was skipped.
fn rows(
    model: &Model,
    prints: &[InpNodePrint],
    step: usize,
    u: &[f64],
    r: &[f64],
    out: &mut String,
    notes: &mut Vec<String>,
) -> Result<()> {
    for p in active(prints, |p| p.step, step) {
        let Some((name, nodes)) = named(&model.mesh.node_sets, &p.nset) else {
            return Err(err!(
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
fn internal_force(residual: &[f64], f_ext: &[f64]) -> Vec<f64> {
    residual.iter().zip(f_ext).map(|(r, f)| r + f).collect()
}

/// Header of `node_print.csv`.
pub const HEADER: &str = "step,set,variable,node,1,2,3\n";
