//! From an input file to a model ready to run: read the scene (`.toml`) or
//! the deck (`.inp`), build the model, apply the solver overrides, choose the
//! linear back end, and check what can only be checked on the built model.

pub mod auto;
pub mod bending;
pub(crate) mod check;
pub(crate) mod limits;

use crate::error::{bail, err, Context, Result};
use crate::post::crack;
use crate::{input::deck, input::scene};
use junta_core::registry::{self, SolverEntry};
use junta_core::{LinearSolver, MatrixKind, Model};
use std::path::{Path, PathBuf};

/// A model ready to run, from a scene or a deck.
pub struct Prepared {
    /// The built model: mesh, elements, dofs with their constraints, loads.
    pub model: Model,
    /// The linear back end, built and chosen for the model's matrix kind
    /// ([`resolve_solver`]).
    pub solver: Box<dyn LinearSolver>,
    /// The scene's `[model] title` or the first line of the deck's
    /// `*HEADING`; empty if none.
    pub title: String,
    /// The scene's `[model] units`, free text for the reports (e.g.
    /// `"N, mm, MPa"`; `None` for decks).
    pub units: Option<String>,
    /// The scene's `[output] directory` (`None`: the caller chooses, e.g.
    /// [`default_dir`]).
    pub output_dir: Option<PathBuf>,
    /// Write VTU results (`[output] vtu`, default true).
    pub vtu: bool,
    /// Node sets whose mean displacement is reported in `summary.json`
    /// (`[output] probes`).
    pub probes: Vec<String>,
    /// Fractions of the load at which a linear run also writes its
    /// solution scaled (`[output] fractions`).
    pub fractions: Vec<f64>,
    /// The scene's reference reaction and its component index (0 = x,
    /// 1 = y, 2 = z).
    pub reference: Option<(scene::ReferenceSpec, usize)>,
    /// Analysis type, load program and increment control.
    pub analysis: scene::AnalysisSpec,
    /// The load-displacement curve to record (`[output.curve]`, or a
    /// deck's), if any.
    pub curve: Option<scene::CurveSpec>,
    /// How the crack front is measured (`[output] crack`); `None`: the
    /// default of [`crate::post::crack`].
    pub crack: Option<scene::CrackFrontSpec>,
    /// Incremental runs: a VTU frame every this many increments (>= 1).
    pub every: usize,
    /// Physical thickness of the adhesive layer by interface block name
    /// (`interface[].thickness`), for the penalty advisor.
    pub thickness: std::collections::BTreeMap<String, f64>,
    /// Notes from reading the input and choosing the solver (ignored
    /// keywords, the back end chosen and why).
    pub notes: Vec<String>,
    /// The `--solver KEY=VALUE` overrides applied (kept for restarts).
    pub solver_overrides: Vec<String>,
    /// Registry key of the solver (resolved: never `auto`), to build
    /// another one.
    pub solver_key: String,
    /// Parameters of the solver (its `[solver]` table without `type`, with
    /// the `--solver` overrides applied).
    pub solver_table: toml::Table,
    /// What `summary.json` `temperature` reports of the model's
    /// temperature change (stress-free and final temperatures, how it is
    /// applied); `None` without one.
    pub temperature: Option<serde_json::Value>,
    /// The load cases of a linear deck with several `*STEP`s (empty
    /// otherwise).
    pub deck_steps: Vec<deck::DeckStep>,
    /// Per step of the load program: the deck's `*STEP, INC=n` and the
    /// line of that `*STEP` (empty for scenes).
    pub increment_limits: Vec<Option<(usize, usize)>>,
    /// Per step of the load program: the deck step it belongs to (empty
    /// for scenes).
    pub program_deck_steps: Vec<usize>,
    /// A deck's print requests (empty for a scene).
    pub prints: crate::output::deck_print::PrintTables,
    /// Seconds spent reading the input and building the model.
    pub read_seconds: f64,
    /// Seconds spent choosing the linear solver (`auto`'s analysis,
    /// [`crate::prepare::auto::decide`]); not part of `read_seconds`.
    pub choose_solver_seconds: f64,
    /// A scene's model build (mesh, lay-up, interfaces, elements): its
    /// seconds and the process's peak memory after it (`summary.json`
    /// `timings.build`, `timings.build_peak_bytes`); `None` for decks and
    /// models built in code.
    pub build: Option<BuildCost>,
    /// A scene's `[[ply_failure]]` criteria (empty otherwise).
    pub ply_criteria: Vec<crate::post::ply_failure::PlyCriterionUse>,
}

/// What building a scene's model cost.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BuildCost {
    /// Wall-clock seconds of the build.
    pub seconds: f64,
    /// Peak resident memory of the process after the build (`VmHWM` of
    /// `/proc/self/status`), bytes; `None` where unknown.
    pub peak_bytes: Option<u64>,
}

/// Build the linear back end registered as `key` from its parameter
/// table; errors name `where_` (the input) and the `solver` key at fault.
pub fn build_solver(key: &str, table: &toml::Table, where_: &str) -> Result<Box<dyn LinearSolver>> {
    let entry =
        registry::find::<SolverEntry>(key).map_err(|e| err!("{where_}: key `solver.type`: {e}"))?;
    (entry.build)(table).map_err(|e| err!("{where_}: key `solver`: {e}"))
}

/// Resolve the solver `type = "auto"` (the default) from the model's
/// matrix kind: `cholesky` for symmetric positive-definite tangents, `ldlt`
/// when a law can soften (symmetric indefinite), `lu` when a law's tangent
/// is nonsymmetric (general). The choice, or a back end
/// the user forced that does not accept the model's kind, is a note.
pub fn resolve_solver(
    key: &mut String,
    table: &toml::Table,
    model: &Model,
    where_: &str,
    notes: &mut Vec<String>,
) -> Result<Box<dyn LinearSolver>> {
    let kind = model.matrix_kind();
    if let Some(c) = junta_core::distributed::collective() {
        return distributed_solver(key, table, c.size(), where_, notes);
    }
    let mut dissection = None;
    if key == "auto" && kind != MatrixKind::General {
        let decision =
            crate::prepare::auto::decide(model, kind == MatrixKind::SymmetricPositiveDefinite);
        dissection = decision.dissection;
        if let Some(reason) = decision.amg_reason {
            let method = if kind == MatrixKind::SymmetricPositiveDefinite {
                "cg"
            } else {
                "gmres"
            };
            notes.push(format!(
                "{reason}: using {method} with the smoothed-aggregation AMG preconditioner{}",
                if method == "gmres" {
                    " (GMRES: the tangent can be indefinite, a softening law)"
                } else {
                    ""
                }
            ));
            *key = method.to_string();
            let mut t = toml::Table::new();
            t.insert("preconditioner".into(), "amg".into());
            return build_solver(key, &t, where_);
        }
    }
    if key == "auto" {
        *key = match kind {
            MatrixKind::SymmetricPositiveDefinite => "cholesky",
            MatrixKind::SymmetricIndefinite => "ldlt",
            MatrixKind::General => "lu",
        }
        .to_string();
        if kind == MatrixKind::General {
            notes.push(format!(
                "solver auto: the tangent is {} (friction or non-associated plasticity), so the direct back end is `lu` (supernodal LU, row interchanges within panels)",
                kind.name()
            ));
        } else if kind != MatrixKind::SymmetricPositiveDefinite {
            notes.push(format!(
                "solver auto: the tangent can be {} (a softening interface law), so the direct back end is `{key}` (LDL^T with Bunch-Kaufman pivots, reports the negative pivots)",
                kind.name()
            ));
        }
    }
    let mut solver = build_solver(key, table, where_)?;
    if let Some(d) = dissection {
        solver.offer_dissection(d);
    }
    if kind == MatrixKind::General && !solver.accepts(kind) {
        notes.push(format!(
            "solver `{key}` solves symmetric matrices only, but the tangent is {}: the symmetric part of the tangent is assembled instead, so Newton loses its quadratic convergence (see the iterations per increment in curve.csv and summary.json); use [solver] type = \"auto\" or \"lu\" for the consistent tangent",
            kind.name()
        ));
    } else if !solver.accepts(kind) {
        notes.push(format!(
            "solver `{key}` accepts symmetric positive-definite matrices only, but the tangent can be {}: it will stop where the tangent stops being positive definite; use [solver] type = \"auto\" or \"ldlt\"",
            kind.name()
        ));
    }
    Ok(solver)
}

/// The solver of a run over MPI ranks: PETSc's (`petsc`, registered by
/// the MPI build). A scene's own `petsc` table is kept; any other back end
/// is replaced, the iterative ones (`cg`, `gmres`, `minres`) by GAMG and
/// the direct ones (and `auto`) by MUMPS, with a note.
fn distributed_solver(
    key: &mut String,
    table: &toml::Table,
    ranks: usize,
    where_: &str,
    notes: &mut Vec<String>,
) -> Result<Box<dyn LinearSolver>> {
    if key == "petsc" {
        return build_solver(key, table, where_);
    }
    let method = if matches!(key.as_str(), "cg" | "gmres" | "minres") {
        "gamg"
    } else {
        "mumps"
    };
    if key != "auto" {
        notes.push(format!(
            "solver `{key}` runs in one process; over {ranks} MPI ranks the solver is `petsc` with method = \"{method}\" (set [solver] type = \"petsc\" to choose)"
        ));
    }
    *key = "petsc".to_string();
    let mut t = toml::Table::new();
    t.insert("method".into(), method.into());
    build_solver(key, &t, where_)
}

/// Apply `--solver KEY=VALUE` overrides to the solver key and table. A
/// value is read as a TOML value (`1e-10`, `true`, `"amd"`), or else as a
/// bare string (`precision=double`); `type=...` changes the back end.
fn apply_solver_overrides(
    key: &mut String,
    table: &mut toml::Table,
    overrides: &[String],
) -> Result<()> {
    let mut parsed = Vec::with_capacity(overrides.len());
    for o in overrides {
        let Some((k, v)) = o.split_once('=') else {
            bail!("--solver {o}: expected KEY=VALUE, e.g. --solver precision=double");
        };
        let (k, v) = (k.trim(), v.trim());
        let value = toml::from_str::<toml::Table>(&format!("v = {v}"))
            .ok()
            .and_then(|mut t| t.remove("v"))
            .unwrap_or_else(|| toml::Value::String(v.to_string()));
        parsed.push((o, k, value));
    }
    // `type` first, wherever it is given: the other keys are parameters of
    // the back end it selects
    for (o, k, value) in &parsed {
        if *k == "type" {
            let toml::Value::String(name) = value else {
                bail!("--solver {o}: the solver type is a name such as cholesky or cg");
            };
            if name != key {
                // parameters of the scene's back end do not apply to another
                table.clear();
                *key = name.clone();
            }
        }
    }
    for (_, k, value) in parsed {
        // `control` belongs to the nonlinear driver ([`control_override`])
        if k != "type" && k != "control" {
            table.insert(k.to_string(), value);
        }
    }
    Ok(())
}

/// Read a scene (`.toml`) or a deck (`.inp`) and build the model;
/// `solver_overrides` are `--solver KEY=VALUE` options.
pub fn prepare(input: &Path, solver_overrides: &[String]) -> Result<Prepared> {
    prepare_with(
        input,
        &crate::Options {
            solver: solver_overrides.to_vec(),
            overrides: Vec::new(),
        },
    )
}

/// [`prepare`] with scene overrides (`laws.cz.G_Ic = 0.5`).
pub fn prepare_with(input: &Path, options: &crate::Options) -> Result<Prepared> {
    let t0 = std::time::Instant::now();
    let mut p = prepare_unchecked(input, options)?;
    control_override(input, &mut p)?;
    p.read_seconds = t0.elapsed().as_secs_f64() - p.choose_solver_seconds;
    check_prepared(&input.display().to_string(), &p)?;
    Ok(p)
}

/// A scene given as text (named `input` in messages).
pub fn prepare_scene_text(
    input: &Path,
    text: String,
    solver_overrides: &[String],
) -> Result<Prepared> {
    let sf = scene::SceneFile::parse(input, text)?;
    crate::input::validate::scene(&sf)?;
    let mut p = prepare_scene(input, &sf, solver_overrides)?;
    control_override(input, &mut p)?;
    check_prepared(&input.display().to_string(), &p)?;
    Ok(p)
}

/// A model built in code, run as `analysis` with the solver `key`.
pub fn prepare_model(model: Model, analysis: scene::AnalysisSpec, key: &str) -> Result<Prepared> {
    let where_ = "(model built in code)";
    crate::input::validate::analysis(where_, &analysis)?;
    check_supported(where_, &model)?;
    let mut key = key.to_string();
    let table = toml::Table::new();
    let mut notes = Vec::new();
    let t_choice = std::time::Instant::now();
    let solver = resolve_solver(&mut key, &table, &model, where_, &mut notes)?;
    let choose_solver_seconds = t_choice.elapsed().as_secs_f64();
    let temperature = temperature_summary(&model, None, "as the model's temperature_steps say");
    Ok(Prepared {
        model,
        solver,
        title: String::new(),
        units: None,
        output_dir: None,
        vtu: true,
        probes: Vec::new(),
        fractions: Vec::new(),
        reference: None,
        analysis,
        curve: None,
        crack: None,
        every: 1,
        thickness: Default::default(),
        notes,
        solver_overrides: Vec::new(),
        solver_key: key,
        solver_table: table,
        deck_steps: Vec::new(),
        increment_limits: Vec::new(),
        program_deck_steps: Vec::new(),
        prints: Default::default(),
        read_seconds: 0.0,
        choose_solver_seconds,
        temperature,
        build: None,
        ply_criteria: Vec::new(),
    })
}

/// `summary.json` `temperature` of a model with a temperature change: the
/// range of the nodal changes, with `stress_free` (a scene's) the final
/// temperatures, and how the change is `applied`.
pub(crate) fn temperature_summary(
    model: &Model,
    stress_free: Option<f64>,
    applied: &str,
) -> Option<serde_json::Value> {
    let d = model.temperature.as_ref()?;
    let lo = d.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = d.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let mut v = serde_json::json!({
        "change_min": lo,
        "change_max": hi,
        "applied": applied,
    });
    if let Some(t0) = stress_free {
        v["stress_free"] = serde_json::json!(t0);
        v["final_min"] = serde_json::json!(t0 + lo);
        v["final_max"] = serde_json::json!(t0 + hi);
    }
    Some(v)
}

/// Set `path` (dotted; an array index is a number, `boundary.1.value`) of
/// a scene table to `value`. The parent must exist; the leaf may be new
/// (the scene's own checks then say whether it is a valid key).
pub fn apply_override(table: &mut toml::Table, path: &str, value: toml::Value) -> Result<()> {
    let keys: Vec<&str> = path.split('.').collect();
    let mut root = toml::Value::Table(std::mem::take(table));
    let r = set_path(&mut root, &keys, value, path, 0);
    if let toml::Value::Table(t) = root {
        *table = t;
    }
    r
}

/// [`apply_override`] below `node`, which is `keys[..depth]` of `path`.
fn set_path(
    node: &mut toml::Value,
    keys: &[&str],
    value: toml::Value,
    path: &str,
    depth: usize,
) -> Result<()> {
    let at = || keys[..depth + 1].join(".");
    let Some((k, rest)) = keys[depth..].split_first() else {
        bail!("override `{path}`: empty key");
    };
    let _ = rest;
    let last = depth + 1 == keys.len();
    match node {
        toml::Value::Table(t) if last => {
            t.insert(k.to_string(), value);
            Ok(())
        }
        toml::Value::Table(t) => match t.get_mut(*k) {
            Some(child) => set_path(child, keys, value, path, depth + 1),
            None => bail!("override `{path}`: the scene has no `{}`", at()),
        },
        toml::Value::Array(a) => match k.parse::<usize>().ok().and_then(|i| a.get_mut(i)) {
            Some(slot) if last => {
                *slot = value;
                Ok(())
            }
            Some(child) => set_path(child, keys, value, path, depth + 1),
            None => bail!(
                "override `{path}`: the scene has no `{}` (`{}` has {} entries, indexed from 0)",
                at(),
                keys[..depth].join("."),
                a.len()
            ),
        },
        _ => bail!(
            "override `{path}`: `{}` is a value, not a table",
            keys[..depth].join(".")
        ),
    }
}

/// The text of a scene with `overrides` applied.
fn overridden_scene(
    input: &Path,
    text: String,
    overrides: &[(String, toml::Value)],
) -> Result<String> {
    if overrides.is_empty() {
        return Ok(text);
    }
    let mut table: toml::Table = toml::from_str(&text)
        .map_err(|e| err!("{}: {}", input.display(), e.to_string().trim_end()))?;
    for (path, value) in overrides {
        apply_override(&mut table, path, value.clone())
            .map_err(|e| err!("{}: {e}", input.display()))?;
    }
    toml::to_string(&table).map_err(|e| err!("{}: {e}", input.display()))
}

fn prepare_unchecked(input: &Path, options: &crate::Options) -> Result<Prepared> {
    let solver_overrides = &options.solver;
    let ext = input
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    if ext.as_deref() != Some("toml") && !options.overrides.is_empty() {
        bail!(
            "{}: overrides apply to TOML scenes; edit the deck instead",
            input.display()
        );
    }
    match ext.as_deref() {
        Some("toml") => {
            let text = std::fs::read_to_string(input)
                .with_context(|| format!("cannot read scene file {}", input.display()))?;
            let text = overridden_scene(input, text, &options.overrides)?;
            let sf = scene::SceneFile::parse(input, text)?;
            crate::input::validate::scene(&sf)?;
            prepare_scene(input, &sf, solver_overrides)
        }
        Some("inp") => {
            let d = deck::build_model(input)?;
            let mut notes = d.notes;
            let mut key = d.solver.clone().unwrap_or_else(|| "auto".to_string());
            let mut table = toml::Table::new();
            apply_solver_overrides(&mut key, &mut table, solver_overrides)?;
            let t_choice = std::time::Instant::now();
            let solver = resolve_solver(
                &mut key,
                &table,
                &d.model,
                &input.display().to_string(),
                &mut notes,
            )?;
            let choose_solver_seconds = t_choice.elapsed().as_secs_f64();
            let deck_temperature = temperature_summary(
                &d.model,
                None,
                if d.incremental.is_some() {
                    "ramped over the first step (*TEMPERATURE), from *INITIAL CONDITIONS"
                } else {
                    "with each step's loads (*TEMPERATURE), from *INITIAL CONDITIONS"
                },
            );
            let (analysis, (increment_limits, program_deck_steps), deck_steps) = match d.incremental
            {
                // the load program holds the steps
                Some(inc) => (
                    inc.analysis,
                    (inc.increment_limits, inc.deck_steps),
                    Vec::new(),
                ),
                None => (
                    Default::default(),
                    (Vec::new(), Vec::new()),
                    if d.steps.len() > 1 {
                        d.steps
                    } else {
                        Vec::new()
                    },
                ),
            };
            Ok(Prepared {
                model: d.model,
                solver,
                title: d.title,
                units: None,
                output_dir: None,
                vtu: true,
                probes: Vec::new(),
                fractions: Vec::new(),
                analysis,
                curve: d.curve,
                crack: None,
                every: d.every.unwrap_or(1),
                reference: None,
                thickness: Default::default(),
                notes,
                solver_overrides: solver_overrides.to_vec(),
                solver_key: key,
                solver_table: table,
                deck_steps,
                increment_limits,
                program_deck_steps,
                prints: d.prints,
                temperature: deck_temperature,
                read_seconds: 0.0,
                choose_solver_seconds,
                build: None,
                ply_criteria: Vec::new(),
            })
        }
        _ => bail!(
            "{}: unknown input type; give a TOML scene (.toml) or an Abaqus/CalculiX deck (.inp)",
            input.display()
        ),
    }
}

/// The model, solver and output options of a parsed, checked scene.
fn prepare_scene(
    input: &Path,
    sf: &scene::SceneFile,
    solver_overrides: &[String],
) -> Result<Prepared> {
    check_path_following(input, &sf.scene.analysis)?;
    let mut notes = Vec::new();
    let mut analysis = sf.scene.analysis.clone();
    if analysis.nlgeom && analysis.kind == scene::AnalysisKind::Linear {
        analysis.kind = scene::AnalysisKind::Static;
        notes.push(
            "nlgeom = true: the analysis runs incrementally (type = \"static\"), as a large-deformation run must"
                .into(),
        );
    }
    let t_build = std::time::Instant::now();
    let mut model = scene::build_model_with_notes(sf, &mut notes)?;
    let build = BuildCost {
        seconds: t_build.elapsed().as_secs_f64(),
        peak_bytes: limits::peak_resident_bytes(),
    };
    let ply_criteria = crate::post::ply_failure::from_scene(sf, &model)?;
    let temperature = thermal_program(input, sf, &mut analysis, &mut model, &mut notes)?;
    fatigue_program(input, sf, &mut analysis, &mut model, &mut notes)?;
    let (mut key, mut table) = scene::solver_table(sf);
    apply_solver_overrides(&mut key, &mut table, solver_overrides)?;
    if analysis.kind.is_incremental() && !sf.scene.output.fractions.is_empty() {
        bail!(
            "{}: key `output.fractions`: only a linear run scales its one solution to fractions of the load; an incremental run writes a frame every `output.every` increments (frames/, results.pvd): remove `fractions`",
            sf.path.display()
        );
    }
    let t_choice = std::time::Instant::now();
    let solver = resolve_solver(
        &mut key,
        &table,
        &model,
        &sf.path.display().to_string(),
        &mut notes,
    )?;
    let choose_solver_seconds = t_choice.elapsed().as_secs_f64();
    let (solver_key, solver_table) = (key, table);
    Ok(Prepared {
        model,
        solver,
        title: sf.scene.model.title.clone().unwrap_or_default(),
        units: sf.scene.model.units.clone(),
        output_dir: sf.scene.output.directory.clone(),
        vtu: sf.scene.output.vtu,
        probes: sf.scene.output.probes.clone(),
        fractions: sf.scene.output.fractions.clone(),
        analysis,
        curve: sf.scene.output.curve.clone(),
        crack: sf.scene.output.crack.clone(),
        every: sf.scene.output.every,
        reference: match &sf.scene.reference {
            Some(r) => Some((r.clone(), r.component_index(&sf.path)?)),
            None => None,
        },
        thickness: sf
            .scene
            .interface
            .iter()
            .filter_map(|f| f.thickness.map(|t| (f.name.clone(), t)))
            .collect(),
        notes,
        solver_overrides: solver_overrides.to_vec(),
        solver_key,
        solver_table,
        deck_steps: Vec::new(),
        increment_limits: Vec::new(),
        program_deck_steps: Vec::new(),
        prints: Default::default(),
        read_seconds: 0.0,
        choose_solver_seconds,
        temperature,
        build: Some(build),
        ply_criteria,
    })
}

/// How a scene's `[temperature]` enters the run: a linear run applies it
/// with the loads; a `static` run with `ramp = "before"` gets a thermal
/// step ahead of its program (load factor held at 0, temperature factor 0
/// -> 1: `steps` gains a leading 0), with `"with_first"` the temperature
/// ramps with the first step. Returns the summary's `temperature`.
fn thermal_program(
    input: &Path,
    sf: &scene::SceneFile,
    analysis: &mut scene::AnalysisSpec,
    model: &mut Model,
    notes: &mut Vec<String>,
) -> Result<Option<serde_json::Value>> {
    let Some(t) = &sf.scene.temperature else {
        return Ok(None);
    };
    let applied = if !analysis.kind.is_incremental() {
        "with the loads (linear analysis)"
    } else {
        model.temperature_steps = vec![1.0];
        if analysis.control == scene::Control::ArcLength {
            bail!(
                "{}: key `temperature`: the temperature changes under load control (a thermal step, or with the first step), and `analysis.control = \"arc_length\"` follows the path throughout; use control = \"auto\" (the default: path following takes over at a limit point of the mechanical steps) or \"load\"",
                input.display()
            );
        }
        match t.ramp {
            scene::Ramp::Before => {
                analysis.steps.insert(0, 0.0);
                notes.push(format!(
                    "{}: [temperature]: a thermal step (step 0 of curve.csv, load factor 0, temperature factor 0 -> 1) runs before the load program",
                    input.display()
                ));
                "thermal step before the load program"
            }
            scene::Ramp::WithFirst => "ramped with the first step of the load program",
        }
    };
    Ok(temperature_summary(model, Some(t.stress_free), applied))
}

/// A scene's `[fatigue]`: a fatigue step after the load program of a
/// `static` run (the program's last load factor held, the cycles going 0
/// -> `cycles`; [`junta_core::FatigueProgram`]).
fn fatigue_program(
    input: &Path,
    sf: &scene::SceneFile,
    analysis: &mut scene::AnalysisSpec,
    model: &mut Model,
    notes: &mut Vec<String>,
) -> Result<()> {
    let Some(f) = &sf.scene.fatigue else {
        return Ok(());
    };
    let at = input.display();
    if !analysis.kind.is_incremental() {
        bail!("{at}: key `fatigue`: a fatigue step follows an incremental load program: set `[analysis] type = \"static\"` and its `steps`");
    }
    if analysis.control == scene::Control::ArcLength {
        bail!("{at}: key `fatigue`: the fatigue step holds the load while the cycles run, which path following throughout (`analysis.control = \"arc_length\"`) cannot drive; use control = \"auto\" (the default) or \"load\"");
    }
    if !(f.max_damage_increment > 0.0 && f.max_damage_increment <= 1.0) {
        bail!("{at}: key `fatigue.max_damage_increment` = {}: the damage growth allowed per increment must be in (0, 1]", f.max_damage_increment);
    }
    let Some(&held) = analysis.steps.last() else {
        bail!("{at}: key `fatigue`: the load program (`analysis.steps`) is empty: it must load the model to the cycle's maximum first");
    };
    let blocks = fatigue_blocks(&at.to_string(), f, held)?;
    // the static steps: no cycles, the first block's load ratio
    let mut cycle_steps = vec![0.0; analysis.steps.len()];
    let mut load_ratios = vec![blocks[0].2; analysis.steps.len()];
    let (mut n, mut current) = (0.0, held);
    for &(load, cycles, r) in &blocks {
        if load != current {
            // to the block's maximum, the cycles held
            analysis.steps.push(load);
            cycle_steps.push(n);
            load_ratios.push(r);
            current = load;
        }
        n += cycles;
        analysis.steps.push(load);
        cycle_steps.push(n);
        load_ratios.push(r);
    }
    let front_direction = match f.energy_release_rate.as_str() {
        "local" => None,
        "crack_front" => Some(fatigue_direction(&at.to_string(), f, sf, model)?),
        other => bail!("{at}: key `fatigue.energy_release_rate` = \"{other}\": valid values are \"crack_front\" (the J integral of the cohesive tractions, measured on the interface) and \"local\" (each point's own estimate)"),
    };
    let first_step = analysis.steps.len() - cycle_steps.iter().filter(|&&c| c > 0.0).count();
    model.fatigue = Some(junta_core::FatigueProgram {
        cycle_steps,
        load_ratios,
        max_damage_increment: f.max_damage_increment,
        front_direction,
    });
    notes.push(format!(
        "{at}: [fatigue]: {} block(s) of cycles from step {first_step} of curve.csv, {n} cycles in all (at most {} damage growth per increment)",
        blocks.len(),
        f.max_damage_increment
    ));
    Ok(())
}

/// The blocks of a `[fatigue]` as `(load factor, cycles, load ratio)`:
/// `blocks`, or one block of `cycles` at the program's last load factor
/// `held`. Checks each value and says which key is wrong.
fn fatigue_blocks(at: &str, f: &scene::FatigueSpec, held: f64) -> Result<Vec<(f64, f64, f64)>> {
    let ratio = |r: f64, key: &str| -> Result<f64> {
        if (0.0..1.0).contains(&r) {
            Ok(r)
        } else {
            bail!("{at}: key `{key}` = {r}: R = min / max of the load cycle must be in [0, 1)")
        }
    };
    let count = |c: f64, key: &str| -> Result<f64> {
        if c > 0.0 && c.is_finite() {
            Ok(c)
        } else {
            bail!("{at}: key `{key}` = {c}: give the cycles, positive and finite")
        }
    };
    let r0 = ratio(f.load_ratio, "fatigue.load_ratio")?;
    match (f.cycles, f.blocks.is_empty()) {
        (Some(c), true) => Ok(vec![(held, count(c, "fatigue.cycles")?, r0)]),
        (None, false) => f
            .blocks
            .iter()
            .enumerate()
            .map(|(k, b)| {
                if !b.load.is_finite() {
                    bail!("{at}: key `fatigue.blocks[{k}].load` = {}: give the load factor at the cycle's maximum", b.load);
                }
                let r = match b.load_ratio {
                    Some(r) => ratio(r, &format!("fatigue.blocks[{k}].load_ratio"))?,
                    None => r0,
                };
                Ok((b.load, count(b.cycles, &format!("fatigue.blocks[{k}].cycles"))?, r))
            })
            .collect(),
        (Some(_), false) => bail!("{at}: key `fatigue`: give either `cycles` (one block at the program's last load factor) or `blocks`, not both"),
        (None, true) => bail!("{at}: key `fatigue.cycles`: missing; give the cycles of the fatigue step, e.g. cycles = 1.0e6 (or `blocks = [{{ load = .., cycles = .. }}, ..]`)"),
    }
}

/// The unit direction of crack growth of a `crack_front` fatigue step:
/// `[fatigue] direction`, else `[output] crack`'s, else the axis along
/// which the interfaces' nodes spread the most.
fn fatigue_direction(
    at: &str,
    f: &scene::FatigueSpec,
    sf: &scene::SceneFile,
    model: &Model,
) -> Result<[f64; 3]> {
    let (d, key) = match (f.direction, &sf.scene.output.crack) {
        (Some(d), _) => (d, "fatigue.direction"),
        (None, Some(c)) => (c.direction, "output.crack.direction"),
        (None, None) => {
            let nodes = crack::block_nodes(model, &crack::interface_blocks(model));
            if nodes.is_empty() {
                bail!("{at}: key `fatigue`: the model has no interface, so there is no crack to grow; add an [[interface]] with a fatigue law");
            }
            return Ok(crack::default_direction(&nodes));
        }
    };
    crack::unit_direction(d, at, key)
}

/// `--solver control=load|displacement|auto|arc_length`: the control of an
/// incremental run, for decks (which have no `control` key) and scenes
/// alike; the last one given counts.
fn control_override(input: &Path, p: &mut Prepared) -> Result<()> {
    let Some(value) = p
        .solver_overrides
        .iter()
        .filter_map(|o| o.split_once('='))
        .filter(|(k, _)| k.trim() == "control")
        .map(|(_, v)| v.trim().trim_matches('"').to_string())
        .last()
    else {
        return Ok(());
    };
    p.analysis.control = match value.as_str() {
        "auto" => scene::Control::Auto,
        "load" | "displacement" => scene::Control::Load,
        "arc_length" => scene::Control::ArcLength,
        other => bail!(
            "--solver control={other}: use auto (load control, path following at limit points), load or displacement (load control only: stop at a limit point), or arc_length"
        ),
    };
    check_path_following(input, &p.analysis)
}

/// `out/<file stem><suffix>`.
pub fn default_dir(input: &Path, suffix: &str) -> PathBuf {
    let stem = input.file_stem().and_then(|s| s.to_str()).unwrap_or("run");
    PathBuf::from("out").join(format!("{stem}{suffix}"))
}

fn check_path_following(input: &Path, a: &scene::AnalysisSpec) -> Result<()> {
    if a.control != scene::Control::ArcLength {
        return Ok(());
    }
    let file = input.display();
    if !a.kind.is_incremental() {
        bail!("{file}: key `analysis.control`: \"arc_length\" needs `analysis.type = \"static\"`");
    }
    if a.steps.len() != 1 || !a.steps[0].is_finite() || a.steps[0] == 0.0 {
        bail!(
            "{file}: key `analysis.steps`: path following runs one step to a finite, non-zero end load factor (`steps = [lambda_end]`), got {:?}",
            a.steps
        );
    }
    a.arc_length
        .validate()
        .map_err(|e| err!("{file}: key `analysis.arc_length`: {e}"))
}

/// What needs the model: every part held by a support
/// ([`junta_core::connectivity`]), probe, reference and curve sets, curve
/// components.
pub fn check_prepared(file: &str, p: &Prepared) -> Result<()> {
    crate::input::validate::analysis(file, &p.analysis)?;
    check_supported(file, &p.model)?;
    let mesh = &p.model.mesh;
    for s in &p.probes {
        mesh.node_set(s)
            .map_err(|e| crate::error::err!("{file}: key `output.probes`: {e}"))?;
    }
    if let Some((r, _)) = &p.reference {
        mesh.node_set(&r.set)
            .map_err(|e| crate::error::err!("{file}: key `reference.set`: {e}"))?;
    }
    if let Some(c) = &p.curve {
        for (k, v) in [
            ("reaction_component", &c.reaction_component),
            ("point_component", &c.point_component),
        ] {
            if scene::component(v).is_none() {
                bail!("{file}: key `output.curve.{k}`: `{v}` is not valid; use x, y or z");
            }
        }
        for (k, v) in [
            ("reaction_set", Some(&c.reaction_set)),
            ("point_set", Some(&c.point_set)),
            ("relative_to", c.relative_to.as_ref()),
        ] {
            if let Some(v) = v {
                mesh.node_set(v)
                    .map_err(|e| crate::error::err!("{file}: key `output.curve.{k}`: {e}"))?;
            }
        }
    }
    Ok(())
}

/// Refuse a model with a part that no support holds (its free rigid-body
/// modes make every factorisation singular), naming its blocks, elements
/// and free modes, before any solver sees it.
fn check_supported(file: &str, model: &Model) -> Result<()> {
    let parts = junta_core::connectivity::floating_parts(model);
    if parts.is_empty() {
        return Ok(());
    }
    let lines: Vec<String> = parts.iter().map(|p| format!("  - {p}")).collect();
    bail!(
        "{file}: {} part(s) of the model held by no support (the stiffness matrix would be singular):\n{}",
        parts.len(),
        lines.join("\n")
    )
}

#[cfg(test)]
mod tests {
    use super::apply_solver_overrides;

    fn apply(key: &str, table: &str, overrides: &[&str]) -> (String, toml::Table) {
        let mut key = key.to_string();
        let mut table: toml::Table = toml::from_str(table).unwrap();
        let o: Vec<String> = overrides.iter().map(|s| s.to_string()).collect();
        apply_solver_overrides(&mut key, &mut table, &o).unwrap();
        (key, table)
    }

    #[test]
    fn solver_overrides_parse_values_and_apply_type_first() {
        let (key, t) = apply(
            "cholesky",
            "ordering = \"amd\"",
            &[
                "refine_tol=1e-10",
                "precision=double",
                "max_refinements = 5",
            ],
        );
        assert_eq!(key, "cholesky");
        assert_eq!(t["refine_tol"].as_float(), Some(1e-10));
        assert_eq!(t["precision"].as_str(), Some("double"));
        assert_eq!(t["max_refinements"].as_integer(), Some(5));
        assert_eq!(t["ordering"].as_str(), Some("amd"));
        // a new back end drops the scene's parameters but keeps the other
        // overrides, whatever their order
        let (key, t) = apply("cg", "tol = 1e-12", &["precision=double", "type=cholesky"]);
        assert_eq!(key, "cholesky");
        assert_eq!(t.len(), 1);
        assert_eq!(t["precision"].as_str(), Some("double"));
        // the same back end keeps them
        let (_, t) = apply("cg", "tol = 1e-12", &["type=cg"]);
        assert_eq!(t["tol"].as_float(), Some(1e-12));
        let mut key = "cholesky".to_string();
        let mut t = toml::Table::new();
        assert!(apply_solver_overrides(&mut key, &mut t, &["novalue".into()]).is_err());
        assert!(apply_solver_overrides(&mut key, &mut t, &["type=3".into()]).is_err());
    }
}
