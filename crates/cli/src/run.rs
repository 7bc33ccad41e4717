//! The commands: `run`, `check`, `list`.

use crate::{deck, output, scene};
use anyhow::{anyhow, bail, Context, Result};
use indicatif::{ProgressBar, ProgressStyle};
use junta_core::registry::{
    self, CriterionEntry, ElementEntry, Entry, LawEntry, MaterialEntry, SolverEntry,
};
use junta_core::{LinearSolver, MatrixKind, Model};
use junta_solvers::linear_static::solve_linear_static;
use serde_json::json;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// A model ready to run, from a scene or a deck.
pub struct Prepared {
    pub model: Model,
    pub solver: Box<dyn LinearSolver>,
    pub title: String,
    pub units: Option<String>,
    pub output_dir: Option<PathBuf>,
    pub vtu: bool,
    pub probes: Vec<String>,
    pub fractions: Vec<f64>,
    pub reference: Option<(scene::ReferenceSpec, usize)>,
    pub analysis: scene::AnalysisSpec,
    pub curve: Option<scene::CurveSpec>,
    pub every: usize,
    pub thickness: std::collections::BTreeMap<String, f64>,
    pub notes: Vec<String>,
    /// The `--solver KEY=VALUE` overrides applied (kept for restarts).
    pub solver_overrides: Vec<String>,
    /// Registry key and parameters of the solver (to build another one).
    pub solver_key: String,
    pub solver_table: toml::Table,
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
    pub prints: crate::deck_print::PrintTables,
}

fn build_solver(key: &str, table: &toml::Table, where_: &str) -> Result<Box<dyn LinearSolver>> {
    let entry = registry::find::<SolverEntry>(key)
        .map_err(|e| anyhow!("{where_}: key `solver.type`: {e}"))?;
    (entry.build)(table).map_err(|e| anyhow!("{where_}: key `solver`: {e}"))
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
    if key == "auto" && kind != MatrixKind::General {
        if let Some(reason) =
            crate::auto::prefer_amg(model, kind == MatrixKind::SymmetricPositiveDefinite)
        {
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
    let solver = build_solver(key, table, where_)?;
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
        if k != "type" {
            table.insert(k.to_string(), value);
        }
    }
    Ok(())
}

/// Read a scene (`.toml`) or a deck (`.inp`) and build the model;
/// `solver_overrides` are `--solver KEY=VALUE` options.
pub fn prepare(input: &Path, solver_overrides: &[String]) -> Result<Prepared> {
    let p = prepare_unchecked(input, solver_overrides)?;
    crate::validate::prepared(&input.display().to_string(), &p)?;
    Ok(p)
}

fn prepare_unchecked(input: &Path, solver_overrides: &[String]) -> Result<Prepared> {
    let ext = input
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    match ext.as_deref() {
        Some("toml") => {
            let sf = scene::SceneFile::read(input)?;
            check_path_following(input, &sf.scene.analysis)?;
            let model = scene::build_model(&sf)?;
            let (mut key, mut table) = scene::solver_table(&sf);
            apply_solver_overrides(&mut key, &mut table, solver_overrides)?;
            let mut notes = Vec::new();
            let solver = resolve_solver(
                &mut key,
                &table,
                &model,
                &sf.path.display().to_string(),
                &mut notes,
            )?;
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
                analysis: sf.scene.analysis.clone(),
                curve: sf.scene.output.curve.clone(),
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
            })
        }
        Some("inp") => {
            let d = deck::build_model(input)?;
            let mut notes = d.notes;
            let mut key = d.solver.clone().unwrap_or_else(|| "auto".to_string());
            let mut table = toml::Table::new();
            apply_solver_overrides(&mut key, &mut table, solver_overrides)?;
            let solver = resolve_solver(
                &mut key,
                &table,
                &d.model,
                &input.display().to_string(),
                &mut notes,
            )?;
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
            })
        }
        _ => bail!(
            "{}: unknown input type; give a TOML scene (.toml) or an Abaqus/CalculiX deck (.inp)",
            input.display()
        ),
    }
}

fn spinner(enabled: bool, msg: String) -> ProgressBar {
    if !enabled {
        return ProgressBar::hidden();
    }
    let pb = ProgressBar::new_spinner();
    pb.set_style(ProgressStyle::with_template("{spinner} [{elapsed_precise}] {msg}").unwrap());
    pb.set_message(msg);
    pb.enable_steady_tick(Duration::from_millis(200));
    pb
}

/// `out/<file stem><suffix>`.
pub fn default_dir(input: &Path, suffix: &str) -> PathBuf {
    let stem = input.file_stem().and_then(|s| s.to_str()).unwrap_or("run");
    PathBuf::from("out").join(format!("{stem}{suffix}"))
}

/// The output directory (`-o`, else the scene's `[output] directory`, else
/// `out/<file stem>`), created.
fn output_dir(input: &Path, out: Option<&Path>, p: &Prepared) -> Result<PathBuf> {
    let dir = match (out, &p.output_dir) {
        (Some(o), _) => o.to_path_buf(),
        (None, Some(d)) => d.clone(),
        (None, None) => default_dir(input, ""),
    };
    std::fs::create_dir_all(&dir)
        .with_context(|| format!("cannot create output directory {}", dir.display()))?;
    Ok(dir)
}

/// `junta run`.
pub fn run(
    input: &Path,
    out: Option<&Path>,
    progress: bool,
    max_increments: Option<usize>,
    solver_overrides: &[String],
) -> Result<()> {
    let t0 = Instant::now();
    let pb = spinner(progress, format!("reading {}", input.display()));
    let mut p = prepare(input, solver_overrides)?;
    match p.analysis.kind.as_str() {
        "linear" => {}
        "static" => {
            let dir = output_dir(input, out, &p)?;
            return crate::nonlinear::run_static(input, &mut p, &dir, &pb, None, max_increments);
        }
        other => bail!(
            "{}: key `analysis.type`: `{other}` is not valid; use \"linear\" or \"static\"",
            input.display()
        ),
    }
    for n in &p.notes {
        pb.suspend(|| eprintln!("note: {n}"));
    }
    let read_seconds = t0.elapsed().as_secs_f64();
    let dir = output_dir(input, out, &p)?;
    pb.set_message(format!(
        "solving {} equations ({} elements) with {}",
        p.model.dofs.num_free,
        p.model.mesh.num_elements(),
        p.solver.key()
    ));
    let mut prints = std::mem::take(&mut p.prints);
    let (res, steps_summary) = if p.deck_steps.len() > 1 {
        let (res, steps) = solve_deck_steps(&mut p, &dir, &pb, input, &mut prints)?;
        (res, Some(steps))
    } else {
        let res = solve_linear_static(&p.model, p.solver.as_mut())
            .with_context(|| format!("solving {}", input.display()))?;
        if !prints.is_empty() {
            prints.add_step(
                &p.model,
                0,
                &res.u,
                &res.residual,
                &p.model.f_ext,
                &res.state,
            )?;
        }
        (res, None)
    };
    for w in &res.report.warnings {
        pb.suspend(|| eprintln!("warning: {w}"));
    }
    for n in &res.report.notes {
        pb.suspend(|| eprintln!("note: {n}"));
    }
    if res.free_residual > 1e-6 {
        pb.suspend(|| {
            eprintln!(
                "warning: equilibrium residual after the solve is {:.3e} (relative); the result has lost digits",
                res.free_residual
            )
        });
    }
    pb.set_message("writing results");
    let t_out = Instant::now();
    let interfaces = output::interface_results(&p.model, &res.u, &res.state)?;
    let cells = output::cell_results(&p.model, &res.u, &res.state)?;
    if p.vtu {
        output::write_vtu(&dir.join("results.vtu"), &p.model, &res.u, &cells)?;
        output::write_interface_vtu(&dir, &p.model, &res.u, &interfaces)?;
        if !p.fractions.is_empty() {
            output::write_fractions(&dir, &p.model, &res.u, &res.state, &p.fractions)?;
        }
    }
    for n in prints.write(&dir)? {
        pb.suspend(|| eprintln!("note: {n}"));
    }
    let (advice, advice_lines) =
        output::penalty_advice(&p.model, &|b| p.thickness.get(b).copied())?;
    for l in advice_lines.iter().filter(|l| !l.contains(": good:")) {
        pb.suspend(|| eprintln!("warning: {l}"));
    }
    let reference = match &p.reference {
        Some((r, c)) => {
            let computed = p
                .model
                .set_total(&r.set, &res.residual)
                .context("key `reference.set`")?[*c];
            json!({
                "set": r.set, "component": r.component, "value": r.value, "source": r.source,
                "computed": computed, "relative_error": (computed - r.value).abs() / r.value.abs(),
            })
        }
        None => serde_json::Value::Null,
    };
    let output_seconds = t_out.elapsed().as_secs_f64();
    let reactions = output::reactions(&p.model, &res.residual)?;
    let probes = output::probes(&p.model, &p.probes, &res.u).context("[output] probes")?;
    let summary = json!({
        "input": input.display().to_string(),
        "title": p.title,
        "units": p.units,
        "analysis": "linear_static",
        "nodes": p.model.mesh.nodes.len(),
        "dofs": p.model.dofs.num_dofs(),
        "equations": p.model.dofs.num_free,
        "elements": output::element_counts(&p.model),
        "reactions": reactions,
        "displacement_max": output::displacement_max(&res.u),
        "probes": probes,
        "solids": output::solid_summary(&cells),
        "interfaces": output::interface_summary(&p.model, &interfaces),
        "penalty_advice": advice,
        "reference": reference,
        "equilibrium_residual": res.free_residual,
        "timings": {
            "read": read_seconds,
            "pattern": res.timings.pattern,
            "assemble": res.timings.assemble,
            "analyze": res.timings.analyze,
            "factor": res.timings.factor,
            "solve": res.timings.solve,
            "output": output_seconds,
            "total": t0.elapsed().as_secs_f64(),
        },
        "solver": {
            "name": res.report.solver,
            "iterations": res.report.iterations,
            "residual": res.report.residual,
            "factor_nonzeros": res.report.factor_nonzeros,
            "ordering": res.report.ordering,
            "predicted_factor_nonzeros": output::ordering_candidates(&res.report),
            "precision": res.report.precision,
            "refinement_steps": res.report.refinement_steps,
            "warnings": res.report.warnings,
            "notes": res.report.notes,
        },
        "notes": p.notes,
    });
    let mut summary = summary;
    if let Some(steps) = steps_summary {
        summary["steps"] = json!(steps);
    }
    output::write_json(&dir.join("summary.json"), &summary)?;
    pb.finish_and_clear();
    println!(
        "{}: {} equations, max |u| = {:.6e}, total {:.2} s -> {}",
        input.display(),
        p.model.dofs.num_free,
        output::displacement_max(&res.u),
        t0.elapsed().as_secs_f64(),
        dir.display()
    );
    if let Some(obj) = summary["reactions"].as_object() {
        for (k, v) in obj {
            println!("  reaction on {k}: {v}");
        }
    }
    Ok(())
}

/// The steps of a deck as linear load cases: steps that constrain the same
/// dofs share one factorisation; a step that changes the constrained dofs
/// starts a new model. Writes `results_stepN.vtu` per step and
/// `results.pvd`; returns the last step's result (with the timings of all
/// steps) and one summary object per step. On return `p.model` is the model
/// of the last step.
#[allow(clippy::too_many_arguments)]
fn solve_deck_steps(
    p: &mut Prepared,
    dir: &Path,
    pb: &ProgressBar,
    input: &Path,
    prints: &mut crate::deck_print::PrintTables,
) -> Result<(
    junta_solvers::linear_static::LinearStaticResult,
    Vec<serde_json::Value>,
)> {
    use junta_solvers::linear_static::{solve_linear_static_cases, LoadCase, Timings};
    let file = input.display().to_string();
    let steps = std::mem::take(&mut p.deck_steps);
    let dofs_of = |s: &deck::DeckStep| s.constraints.iter().map(|c| c.0).collect::<Vec<_>>();
    let mut summaries = Vec::with_capacity(steps.len());
    let mut frames = Vec::new();
    let mut total = Timings::default();
    let mut last = None;
    let mut k = 0;
    while k < steps.len() {
        let mut end = k + 1;
        while end < steps.len() && dofs_of(&steps[end]) == dofs_of(&steps[k]) {
            end += 1;
        }
        if k > 0 {
            // other constrained dofs: another dof map, pattern and factor
            let m = &p.model;
            p.model = Model::new(
                m.mesh.clone(),
                m.elements.clone(),
                &steps[k].constraints,
                steps[k].f_ext.clone(),
                m.reaction_sets.clone(),
            )
            .and_then(|mut new| {
                new.add_equations(&m.equations)?;
                Ok(new)
            })
            .map_err(|e| anyhow!("{file}: {} (line {}): {e}", steps[k].name, steps[k].line))?;
            p.solver = build_solver(&p.solver_key, &p.solver_table, &file)?;
        }
        let ndof = p.model.dofs.num_dofs();
        let prescribed: Vec<Vec<f64>> = steps[k..end]
            .iter()
            .map(|s| {
                let mut v = vec![0.0; ndof];
                for &(d, x) in &s.constraints {
                    v[d] = x;
                }
                v
            })
            .collect();
        let cases: Vec<LoadCase<'_>> = steps[k..end]
            .iter()
            .zip(&prescribed)
            .map(|(s, pr)| LoadCase {
                prescribed: pr,
                f_ext: &s.f_ext,
            })
            .collect();
        pb.set_message(format!(
            "solving steps {}..{} of {} ({} equations, one factorisation)",
            k + 1,
            end,
            steps.len(),
            p.model.dofs.num_free
        ));
        let results =
            solve_linear_static_cases(&p.model, p.solver.as_mut(), &cases).with_context(|| {
                format!("solving {file}, {} (line {})", steps[k].name, steps[k].line)
            })?;
        for (i, mut res) in results.into_iter().enumerate() {
            let s = &steps[k + i];
            let t = res.timings;
            total.pattern += t.pattern;
            total.assemble += t.assemble;
            total.analyze += t.analyze;
            total.factor += t.factor;
            total.solve += t.solve;
            total.total += t.total;
            // the step's own load vector, for its reactions
            p.model.f_ext.clone_from(&s.f_ext);
            if !prints.is_empty() {
                prints.add_step(&p.model, k + i, &res.u, &res.residual, &s.f_ext, &res.state)?;
            }
            if p.vtu {
                let name = format!("results_step{}.vtu", k + i + 1);
                let cells = output::cell_results(&p.model, &res.u, &res.state)?;
                output::write_vtu(&dir.join(&name), &p.model, &res.u, &cells)?;
                frames.push(((k + i + 1) as f64, name));
            }
            summaries.push(json!({
                "name": s.name,
                "line": s.line,
                "reactions": output::reactions(&p.model, &res.residual)?,
                "displacement_max": output::displacement_max(&res.u),
                "equilibrium_residual": res.free_residual,
                "shares_factorisation_with_previous": i > 0,
                "timings": {
                    "assemble": t.assemble, "analyze": t.analyze, "factor": t.factor,
                    "solve": t.solve, "total": t.total,
                },
                "solver": {
                    "residual": res.report.residual,
                    "precision": res.report.precision,
                    "refinement_steps": res.report.refinement_steps,
                },
            }));
            res.timings = total;
            last = Some(res);
        }
        k = end;
    }
    if p.vtu {
        output::write_pvd(&dir.join("results.pvd"), &frames)?;
    }
    Ok((last.expect("at least one step"), summaries))
}

/// `junta run --restart DIR`: continue an incremental run from its last
/// converged increment.
pub fn restart(
    dir: &Path,
    progress: bool,
    max_increments: Option<usize>,
    allow_edited: bool,
) -> Result<()> {
    let r = crate::nonlinear::read_restart(dir)?;
    let input = r.input.clone();
    if let Some(status) = &r.finished {
        println!(
            "{}: the run already finished ({status}) at increment {}; nothing to restart, {} left unchanged",
            input.display(),
            r.checkpoint.increment_index,
            dir.display()
        );
        return Ok(());
    }
    for change in crate::restart_guard::check_inputs(&r, allow_edited)? {
        eprintln!("note: continuing with an edited input (--allow-edited): {change}");
    }
    let pb = spinner(
        progress,
        format!(
            "restarting {} from increment {}",
            input.display(),
            r.checkpoint.increment_index
        ),
    );
    // the run's own --solver overrides carry over
    let mut p = prepare(&input, &r.solver_overrides)?;
    if p.analysis.kind != "static" {
        bail!(
            "{}: only incremental runs ([analysis] type = \"static\") can be restarted",
            input.display()
        );
    }
    crate::restart_guard::check_fields(
        &r,
        &dir.join("checkpoint.json"),
        p.analysis.steps.len(),
        p.model.dofs.num_dofs(),
    )?;
    crate::nonlinear::run_static(&input, &mut p, dir, &pb, Some(r), max_increments)
}

/// `junta check`.
pub fn check(input: &Path) -> Result<()> {
    let p = prepare(input, &[])?;
    let m = &p.model;
    println!("{}: valid", input.display());
    if !p.title.is_empty() {
        println!("  title: {}", p.title);
    }
    if let Some(u) = &p.units {
        println!("  units: {u}");
    }
    println!(
        "  nodes: {}, dofs: {}, equations: {} ({} constrained)",
        m.mesh.nodes.len(),
        m.dofs.num_dofs(),
        m.dofs.num_free,
        m.dofs.num_dofs() - m.dofs.num_free
    );
    for (k, n) in output::element_counts(m) {
        println!("  elements {k}: {n}");
    }
    if p.analysis.kind == "static" {
        let n = &p.analysis.newton;
        println!(
            "  analysis: incremental static, load program {:?}, increments (fractions of a step) initial {}, min {}, max {}",
            p.analysis.steps, n.initial_increment, n.min_increment, n.max_increment
        );
    }
    for (k, st) in p.deck_steps.iter().enumerate() {
        println!(
            "  step {} `{}` (line {}): {} constrained dofs, {} loaded dofs",
            k + 1,
            st.name,
            st.line,
            st.constraints.len(),
            st.f_ext.iter().filter(|f| **f != 0.0).count()
        );
    }
    for (b, el) in m.mesh.blocks.iter().zip(&m.elements) {
        println!(
            "  block `{}`: {} x {} ({} integration points each), material `{}`",
            b.name,
            b.len(),
            el.key(),
            el.num_points(),
            b.material
        );
    }
    let list = |kind: &str, v: Vec<(String, usize)>| {
        if !v.is_empty() {
            let s: Vec<String> = v.into_iter().map(|(k, n)| format!("{k} ({n})")).collect();
            println!("  {kind} sets: {}", s.join(", "));
        }
    };
    list(
        "node",
        m.mesh
            .node_sets
            .iter()
            .map(|(k, v)| (k.clone(), v.len()))
            .collect(),
    );
    list(
        "element",
        m.mesh
            .element_sets
            .iter()
            .map(|(k, v)| (k.clone(), v.len()))
            .collect(),
    );
    list(
        "face",
        m.mesh
            .face_sets
            .iter()
            .map(|(k, v)| (k.clone(), v.len()))
            .collect(),
    );
    let mut total = [0.0; 3];
    for (i, f) in m.f_ext.iter().enumerate() {
        total[i % 3] += f;
    }
    println!("  total applied force: {total:?}");
    println!("  solver: {}", p.solver.key());
    let (_, advice) = output::penalty_advice(m, &|b| p.thickness.get(b).copied())?;
    for l in advice {
        println!("  penalty advisor: {l}");
    }
    let (_, zone, warnings) = output::cohesive_zone_advice(m)?;
    for l in zone {
        println!("  mesh advice: {l}");
    }
    for w in warnings {
        println!("  warning: {w}");
    }
    for n in &p.notes {
        println!("  note: {n}");
    }
    Ok(())
}

fn print_entries<E: Entry>(title: &str)
where
    junta_core::inventory::iter<E>: IntoIterator<Item = &'static E>,
{
    println!("{title}:");
    for e in registry::entries::<E>() {
        println!("  {:<16} {}", e.key(), e.description());
        for p in e.params() {
            println!("      {:<12} {}", p.name, p.doc);
        }
    }
}

/// `[analysis] control = "arc_length"`: one step to a non-zero load factor
/// and valid `[analysis.arc_length]` settings, checked before anything is
/// built (so that `junta check` reports it too).
fn check_path_following(input: &Path, a: &scene::AnalysisSpec) -> Result<()> {
    if a.control != scene::Control::ArcLength {
        return Ok(());
    }
    let file = input.display();
    if a.kind != "static" {
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
        .map_err(|e| anyhow!("{file}: key `analysis.arc_length`: {e}"))
}

/// `junta list`.
pub fn list() {
    print_entries::<ElementEntry>("elements");
    print_entries::<MaterialEntry>("materials");
    print_entries::<LawEntry>("interface laws");
    print_entries::<CriterionEntry>("failure criteria");
    print_entries::<SolverEntry>("linear solvers");
    println!("incremental controls ([analysis] type = \"static\"):");
    println!("  {:<16} the load factor is prescribed: load or displacement control, whatever the scene prescribes; [analysis.newton]", "load");
    println!("  {:<16} path following through limit points and snap-backs: cylindrical arc length, then the dissipated energy once the laws dissipate; one step, [analysis.newton] tolerances, and [analysis.arc_length]:", "arc_length");
    for (name, doc) in junta_solvers::arc_length::PARAMETERS {
        println!("      {name:<20} {doc}");
    }
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
