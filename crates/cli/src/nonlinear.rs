//! Incremental-iterative runs (`[analysis] type = "static"`): the Newton
//! driver of `junta_solvers::newton`, with everything a user needs on disk
//! after every converged increment, whatever stops the run:
//!
//! - `frames/results_NNNN.vtu`, `frames/interfaces_NNNN.vtu`,
//!   `frames/interface_points_NNNN.vtu` and `results.pvd` (ParaView plays
//!   the crack growing), every `[output] every` increments, at separation,
//!   and for the last converged increment when the run ends or stops;
//! - `curve.csv`: increment, step, load factor, reaction, displacement,
//!   failed points, Newton iterations, cut-backs, wall time, dissipated
//!   energy, damaged area, negative pivots of the tangent, sign of the
//!   load-factor increment, the constraint of the increment (`load`, `arc`,
//!   `dissipation`) and the displacement conjugate to the applied forces;
//! - `checkpoint.json`: the restart point (`junta run --restart DIR`);
//! - at the end (also after a failure or Ctrl-C): `summary.json` and
//!   `curve.svg` (load-displacement).

use crate::run::Prepared;
use crate::{output, plot, scene};
use anyhow::{anyhow, bail, Context, Result};
use indicatif::ProgressBar;
use junta_solvers::arc_length::{solve_arc_length, PathEnd};
use junta_solvers::newton::{solve_nonlinear, Checkpoint, Control, NonlinearError};
use serde::{Deserialize, Serialize};
use serde_json::json;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

/// What `checkpoint.json` holds.
#[derive(Debug, Serialize, Deserialize)]
pub struct RestartFile {
    /// The scene that was run.
    pub input: PathBuf,
    /// The driver's restart point.
    pub checkpoint: Checkpoint,
    /// First failure so far, if any.
    pub first_failure: Option<FirstFailure>,
    /// Frames written so far `(load factor, file)`.
    pub frames: Vec<(f64, String)>,
    /// The run's `--solver KEY=VALUE` overrides (applied again on restart).
    #[serde(default)]
    pub solver_overrides: Vec<String>,
    /// Hashes of the scene and every file it reads (a restart refuses
    /// edited inputs).
    #[serde(default)]
    pub inputs: Vec<crate::restart_guard::InputHash>,
    /// The scene's text, to name the keys an edit changed.
    #[serde(default)]
    pub scene_text: Option<String>,
    /// The status of a run that ended for good (end of the program, or
    /// every interface point failed): a restart has nothing to do.
    #[serde(default)]
    pub finished: Option<String>,
}

/// When the first interface point failed.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct FirstFailure {
    pub increment: usize,
    pub load_factor: f64,
    pub reaction: Option<f64>,
    pub displacement: Option<f64>,
}

/// One row of `curve.csv`.
#[derive(Debug, Clone)]
struct Row {
    increment: usize,
    step: usize,
    lambda: f64,
    reaction: Option<f64>,
    displacement: Option<f64>,
    failed: usize,
    points: usize,
    iterations: usize,
    cutbacks: usize,
    seconds: f64,
    small: bool,
    /// Fracture energy dissipated in all interfaces so far.
    dissipated: f64,
    /// Damaged area (damage >= 0.99) of all interfaces.
    damaged_area: f64,
    /// Negative pivots of the last factorised tangent (inertia), when the
    /// back end knows it.
    negative_pivots: Option<usize>,
    /// Sign of the load-factor increment: 1, -1 or 0.
    load_sign: i8,
    /// What constrained the increment (`load`, `arc`, `dissipation`).
    control: String,
    /// `f_ext . u`: the displacement work-conjugate to the load factor of
    /// the applied forces (with forces of a unit total load, the load
    /// point's displacement, e.g. the lever's in a mixed-mode bending test).
    conjugate: f64,
    /// Energy dissipated by friction / interface plasticity so far.
    frictional: f64,
}

const CURVE_HEADER: &str =
    "increment,step,load_factor,reaction,displacement,failed_points,interface_points,newton_iterations,cutbacks,seconds,small_increment,dissipated_energy,damaged_area,negative_pivots,load_increment_sign,control,conjugate_displacement,frictional_dissipation\n";

fn opt(v: Option<f64>) -> String {
    v.map(|x| format!("{x:e}")).unwrap_or_default()
}

impl Row {
    fn csv(&self) -> String {
        format!(
            "{},{},{:e},{},{},{},{},{},{},{:e},{},{:e},{:e},{},{},{},{:e},{:e}\n",
            self.increment,
            self.step,
            self.lambda,
            opt(self.reaction),
            opt(self.displacement),
            self.failed,
            self.points,
            self.iterations,
            self.cutbacks,
            self.seconds,
            self.small as u8,
            self.dissipated,
            self.damaged_area,
            self.negative_pivots
                .map(|n| n.to_string())
                .unwrap_or_default(),
            self.load_sign,
            self.control,
            self.conjugate,
            self.frictional
        )
    }
    fn parse(line: &str) -> Option<Row> {
        let f: Vec<&str> = line.split(',').collect();
        // 14 columns: a run written before the path-following and
        // frictional columns
        if ![14, 16, 17, 18].contains(&f.len()) {
            return None;
        }
        Some(Row {
            increment: f[0].parse().ok()?,
            step: f[1].parse().ok()?,
            lambda: f[2].parse().ok()?,
            reaction: f[3].parse().ok(),
            displacement: f[4].parse().ok(),
            failed: f[5].parse().ok()?,
            points: f[6].parse().ok()?,
            iterations: f[7].parse().ok()?,
            cutbacks: f[8].parse().ok()?,
            seconds: f[9].parse().ok()?,
            small: f[10].trim() == "1",
            dissipated: f[11].parse().ok()?,
            damaged_area: f[12].parse().ok()?,
            negative_pivots: f[13].trim().parse().ok(),
            load_sign: f.get(14).and_then(|v| v.trim().parse().ok()).unwrap_or(0),
            control: f.get(15).map_or("load", |v| v.trim()).to_string(),
            conjugate: f.get(16).and_then(|v| v.trim().parse().ok()).unwrap_or(0.0),
            frictional: f.get(17).and_then(|v| v.trim().parse().ok()).unwrap_or(0.0),
        })
    }
}

/// When a run of a softening model stops at or after a limit point, say so
/// with the numbers: the reaction passed a maximum (a snap-back, an unstable
/// drop of the load, e.g. an element separating, that load or displacement
/// control cannot follow at any increment size), or, under load control,
/// the curve flattened to a horizontal tangent (a load maximum).
fn past_peak_hint(rows: &[Row], kind: junta_core::MatrixKind) -> String {
    if kind == junta_core::MatrixKind::SymmetricPositiveDefinite {
        return String::new();
    }
    const REMEDY: &str = "use path following (`[analysis] control = \"arc_length\"`, which follows snap-backs through the dissipated energy), or add a small `viscosity` to the softening law (its energy is reported apart)";
    let unstable = rows
        .iter()
        .filter(|r| r.negative_pivots.unwrap_or(0) > 0)
        .count();
    let Some((peak_row, peak)) = rows
        .iter()
        .filter_map(|r| Some((r, r.reaction?.abs())))
        .max_by(|a, b| a.1.total_cmp(&b.1))
    else {
        return String::new();
    };
    let last = rows.last().and_then(|r| r.reaction).map_or(peak, f64::abs);
    if last < peak * (1.0 - 1e-4) {
        return format!(
            ". Limit point: the reaction peaked at {peak:.6e} (increment {}, load factor {:.6e}) and the run stopped after that maximum, at {:.6e} ({} increments with a negative pivot so far): most likely a snap-back. To trace it, {REMEDY}",
            peak_row.increment, peak_row.lambda, last, unstable
        );
    }
    // stalled at the largest load so far: the increments shrank in each of
    // the last increments (typically an element separating: a local
    // snap-back that starts at this load)
    let n = rows.len();
    if n >= 3 && rows[n - 3..].iter().all(|r| r.cutbacks > 0) && last >= peak * (1.0 - 1e-3) {
        return format!(
            ". Limit point: the increments were cut back in each of the last three while the reaction peaked at {peak:.6e} (increment {}, load factor {:.6e}), its largest value so far: most likely a snap-back starting there (e.g. an element separating). To trace it, {REMEDY}",
            peak_row.increment, peak_row.lambda
        );
    }
    // load control: the slope of the curve at the end against the start
    let slope = |a: &Row, b: &Row| -> Option<f64> {
        let dp = b.reaction? - a.reaction?;
        let du = b.displacement? - a.displacement?;
        (du != 0.0).then(|| dp / du)
    };
    if n >= 3 {
        if let (Some(k0), Some(k1)) = (slope(&rows[0], &rows[1]), slope(&rows[n - 2], &rows[n - 1]))
        {
            if k0 != 0.0 && (k1 / k0) < 0.05 {
                return format!(
                    ". Limit point: the load-displacement slope fell to {:.2} % of its initial value at reaction {last:.6e} (load factor {:.6e}): a load maximum, past which load control has no solution. To go past it, {REMEDY}",
                    100.0 * k1 / k0,
                    rows[n - 1].lambda
                );
            }
        }
    }
    if rows.last().and_then(|r| r.negative_pivots).unwrap_or(0) > 0 {
        return format!(
            ". The tangent of the last converged increment is indefinite ({} negative pivots): the structure is past a limit point or a bifurcation. {REMEDY}",
            rows.last().and_then(|r| r.negative_pivots).unwrap_or(0)
        );
    }
    String::new()
}

/// Limit points and changes of stability along the converged increments:
/// load maxima and minima (of the reaction, else of the load factor),
/// displacement turning points (a snap-back starts at a displacement
/// maximum), and increments where the number of negative pivots of the
/// tangent changed (a limit point or a bifurcation was crossed).
fn limit_points(rows: &[Row]) -> serde_json::Value {
    const MAX_LISTED: usize = 50;
    let load = |r: &Row| r.reaction.unwrap_or(r.lambda);
    let mut points = Vec::new();
    let mut counts = [0usize; 5];
    let kinds = [
        "load_maximum",
        "load_minimum",
        "displacement_maximum",
        "displacement_minimum",
        "stability_change",
    ];
    let mut push = |k: usize, r: &Row, extra: Option<String>| {
        counts[k] += 1;
        if points.len() < MAX_LISTED {
            let mut v = json!({
                "kind": kinds[k],
                "increment": r.increment,
                "load_factor": r.lambda,
                "load": load(r),
                "displacement": r.displacement,
            });
            if let Some(e) = extra {
                v["negative_pivots"] = json!(e);
            }
            points.push(v);
        }
    };
    for w in rows.windows(3) {
        let (a, b, c) = (&w[0], &w[1], &w[2]);
        let (la, lb, lc) = (load(a), load(b), load(c));
        if lb > la && lb > lc {
            push(0, b, None);
        } else if lb < la && lb < lc {
            push(1, b, None);
        }
        if let (Some(da), Some(db), Some(dc)) = (a.displacement, b.displacement, c.displacement) {
            if db > da && db > dc {
                push(2, b, None);
            } else if db < da && db < dc {
                push(3, b, None);
            }
        }
    }
    for w in rows.windows(2) {
        if let (Some(x), Some(y)) = (w[0].negative_pivots, w[1].negative_pivots) {
            if x != y {
                push(4, &w[1], Some(format!("{x} -> {y}")));
            }
        }
    }
    let mut count = serde_json::Map::new();
    for (k, n) in kinds.iter().zip(counts) {
        count.insert((*k).into(), json!(n));
    }
    json!({ "counts": count, "first": points })
}

/// Points `(x, y)` of a reference curve file: CSV, two numeric columns,
/// `#` comments and a header line allowed; the path is relative to the
/// scene's folder.
fn read_reference_curve(input: &Path, file: &str) -> Result<Vec<(f64, f64)>> {
    read_reference_points(&input.parent().unwrap_or(Path::new(".")).join(file))
        .with_context(|| format!("{}: key `output.curve.reference.file`", input.display()))
}

/// Points `(x, y)` of the reference curve file `path` (see
/// [`read_reference_curve`]).
pub(crate) fn read_reference_points(path: &Path) -> Result<Vec<(f64, f64)>> {
    let path = path.to_path_buf();
    let text = std::fs::read_to_string(&path)
        .with_context(|| format!("cannot read {}", path.display()))?;
    let mut pts = Vec::new();
    for line in text.lines().map(str::trim) {
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let f: Vec<&str> = line.split(',').map(str::trim).collect();
        match (
            f.first().and_then(|v| v.parse().ok()),
            f.get(1).and_then(|v| v.parse().ok()),
        ) {
            (Some(x), Some(y)) => pts.push((x, y)),
            _ if pts.is_empty() => {} // header
            _ => bail!("{}: `{line}` is not two numbers x, y", path.display()),
        }
    }
    Ok(pts)
}

/// Write `path` atomically (temporary file, then rename).
fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    let tmp = path.with_extension("tmp");
    std::fs::write(&tmp, bytes).with_context(|| format!("cannot write {}", tmp.display()))?;
    std::fs::rename(&tmp, path).with_context(|| format!("cannot write {}", path.display()))
}

static INTERRUPTED: AtomicBool = AtomicBool::new(false);

/// Run an incremental analysis into `dir`, from the start or from `restart`.
pub fn run_static(
    input: &Path,
    p: &mut Prepared,
    dir: &Path,
    pb: &ProgressBar,
    restart: Option<RestartFile>,
    max_increments: Option<usize>,
) -> Result<()> {
    let t0 = Instant::now();
    let frames_dir = dir.join("frames");
    std::fs::create_dir_all(&frames_dir)
        .with_context(|| format!("cannot create {}", frames_dir.display()))?;
    let _ = ctrlc::set_handler(|| INTERRUPTED.store(true, Ordering::SeqCst));
    let model = &p.model;
    let analysis = p.analysis.clone();
    let file = input.display().to_string();
    // curve definition
    let curve = match &p.curve {
        Some(c) => {
            let rc = scene::component(&c.reaction_component).ok_or_else(|| {
                anyhow!("{file}: key `output.curve.reaction_component`: use x, y or z")
            })?;
            let pc = scene::component(&c.point_component).ok_or_else(|| {
                anyhow!("{file}: key `output.curve.point_component`: use x, y or z")
            })?;
            model
                .mesh
                .node_set(&c.reaction_set)
                .map_err(|e| anyhow!("{file}: key `output.curve.reaction_set`: {e}"))?;
            let pts = model
                .mesh
                .node_set(&c.point_set)
                .map_err(|e| anyhow!("{file}: key `output.curve.point_set`: {e}"))?
                .to_vec();
            let rel = match &c.relative_to {
                Some(set) => model
                    .mesh
                    .node_set(set)
                    .map_err(|e| anyhow!("{file}: key `output.curve.relative_to`: {e}"))?
                    .to_vec(),
                None => Vec::new(),
            };
            let sign = if c.negate { -1.0 } else { 1.0 };
            Some((c.reaction_set.clone(), rc, pts, pc, rel, sign, c.conjugate))
        }
        None => None,
    };
    // previous rows (restart) and the curve file
    let curve_path = dir.join("curve.csv");
    let (mut rows, checkpoint, mut first_failure, mut frames) = match restart {
        Some(r) => {
            let text = std::fs::read_to_string(&curve_path).unwrap_or_default();
            let rows: Vec<Row> = text
                .lines()
                .skip(1)
                .filter_map(Row::parse)
                .filter(|row| row.increment <= r.checkpoint.increment_index)
                .collect();
            (rows, Some(r.checkpoint), r.first_failure, r.frames)
        }
        None => (Vec::new(), None, None, Vec::new()),
    };
    {
        let mut text = String::from(CURVE_HEADER);
        for r in &rows {
            text += &r.csv();
        }
        std::fs::write(&curve_path, text)
            .with_context(|| format!("cannot write {}", curve_path.display()))?;
    }
    let mut curve_file = std::fs::OpenOptions::new()
        .append(true)
        .open(&curve_path)
        .with_context(|| format!("cannot open {}", curve_path.display()))?;
    let mut io_error: Option<anyhow::Error> = None;
    let mut last_increment = checkpoint.as_ref().map_or(0, |c| c.increment_index);
    let start_increment = last_increment;
    let mut separated = false;
    let every = p.every.max(1);
    let solver_overrides = p.solver_overrides.clone();
    let inputs = crate::restart_guard::hash_inputs(input);
    let scene_text = input
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("toml"))
        .then(|| std::fs::read_to_string(input).ok())
        .flatten();
    let increment_limits = p.increment_limits.clone();
    // a deck's *NODE PRINT / *EL PRINT tables: rows at the end of each deck
    // step (a deck step with an amplitude spans several program steps)
    let mut prints = std::mem::take(&mut p.prints);
    let deck_step_of = p.program_deck_steps.clone();
    let deck_step_ends = |step: usize, fraction: f64| -> Option<usize> {
        let ds = *deck_step_of.get(step)?;
        (fraction >= 1.0 - 1e-12 && deck_step_of.get(step + 1) != Some(&ds)).then_some(ds)
    };
    // deck steps whose rows are in the tables
    let mut printed_steps = 0;
    if let Some(c) = checkpoint.as_ref().filter(|_| !prints.is_empty()) {
        printed_steps = match deck_step_ends(c.step, c.step_fraction) {
            Some(ds) => ds + 1,
            None => deck_step_of.get(c.step).copied().unwrap_or(0),
        };
        prints.resume_from(dir, printed_steps);
    }
    // (step, INC, line of its *STEP) when a deck's INC stopped the run
    let mut inc_reached: Option<(usize, usize, usize)> = None;
    let result = {
        let mut observer = |v: &junta_solvers::newton::IncrementView<'_>| -> Control {
            let r = v.report;
            let step_out = (|| -> Result<()> {
                let step = junta_core::element::StepInfo {
                    increment: r.increment_index,
                    load_factor: r.lambda,
                    delta_load_factor: r.delta_lambda,
                    secant: false,
                };
                let ifs = output::interface_results_at(model, v.u, v.state, step)?;
                let points: usize = ifs.iter().map(|i| i.points.len()).sum();
                let failed: usize = ifs
                    .iter()
                    .flat_map(|i| i.points.iter())
                    .filter(|pt| pt.get("failed").is_some_and(|f| f[0] > 0.5))
                    .count();
                let conjugate: f64 = model.f_ext.iter().zip(v.u).map(|(f, u)| f * u).sum();
                let (reaction, displacement) = match &curve {
                    Some((_, _, _, _, _, sign, true)) => {
                        (Some(sign * r.lambda), Some(sign * conjugate))
                    }
                    Some((set, rc, pts, pc, rel, sign, false)) => {
                        let mean = |nodes: &[usize]| {
                            nodes.iter().map(|&n| v.u[3 * n + pc]).sum::<f64>()
                                / nodes.len().max(1) as f64
                        };
                        let base = if rel.is_empty() { 0.0 } else { mean(rel) };
                        (
                            // internal force on the set = reaction on
                            // supports, applied load on a loaded free set
                            Some(
                                sign * (model.set_total(set, v.residual)?[*rc]
                                    + r.lambda * model.set_total(set, &model.f_ext)?[*rc]),
                            ),
                            Some(sign * (mean(pts) - base)),
                        )
                    }
                    None => (None, None),
                };
                if failed > 0 && first_failure.is_none() {
                    first_failure = Some(FirstFailure {
                        increment: r.increment_index,
                        load_factor: r.lambda,
                        reaction,
                        displacement,
                    });
                }
                // split: every point failed and none is still being released
                separated = points > 0
                    && failed == points
                    && !model.mesh.blocks.iter().enumerate().any(|(b, block)| {
                        block.shape.is_interface()
                            && (0..block.len()).any(|e| {
                                model.elements[b]
                                    .wants_small_increments(&v.state.committed[v.state.range(b, e)])
                            })
                    });
                let energy = ifs.iter().map(output::interface_energy).fold(
                    output::InterfaceEnergy::default(),
                    |a, e| output::InterfaceEnergy {
                        dissipated_energy: a.dissipated_energy + e.dissipated_energy,
                        viscous_energy: a.viscous_energy + e.viscous_energy,
                        damaged_area: a.damaged_area + e.damaged_area,
                        process_zone_area: a.process_zone_area + e.process_zone_area,
                        has_damage: a.has_damage || e.has_damage,
                        frictional_dissipation: a.frictional_dissipation + e.frictional_dissipation,
                        has_friction: a.has_friction || e.has_friction,
                    },
                );
                let row = Row {
                    increment: r.increment_index,
                    step: r.step,
                    lambda: r.lambda,
                    reaction,
                    displacement,
                    failed,
                    points,
                    iterations: r.iterations,
                    cutbacks: r.cutbacks,
                    seconds: r.seconds.total,
                    small: r.small_increment_mode,
                    dissipated: energy.dissipated_energy,
                    damaged_area: energy.damaged_area,
                    negative_pivots: r.negative_pivots,
                    load_sign: if r.delta_lambda > 0.0 {
                        1
                    } else if r.delta_lambda < 0.0 {
                        -1
                    } else {
                        0
                    },
                    control: r.control.name().to_string(),
                    conjugate,
                    frictional: energy.frictional_dissipation,
                };
                curve_file.write_all(row.csv().as_bytes())?;
                curve_file.flush()?;
                rows.push(row);
                if let Some(ds) = deck_step_ends(r.step, r.step_fraction) {
                    if !prints.is_empty() {
                        let f_int = internal_force_of(model, v.residual, r.lambda);
                        prints.add_step_with_internal_force(model, ds, v.u, &f_int, v.state)?;
                        prints.save(dir)?;
                    }
                    printed_steps = ds + 1;
                }
                if r.increment_index.is_multiple_of(every) || separated {
                    let ctx = FrameContext {
                        model,
                        dir,
                        frames_dir: &frames_dir,
                        step,
                        start_increment,
                    };
                    write_frame(&ctx, &mut frames, v.u, v.state, &ifs)?;
                }
                let restart = RestartFile {
                    input: std::fs::canonicalize(input).unwrap_or_else(|_| input.to_path_buf()),
                    checkpoint: v.checkpoint(),
                    first_failure: first_failure.clone(),
                    frames: frames.clone(),
                    solver_overrides: solver_overrides.clone(),
                    inputs: inputs.clone(),
                    scene_text: scene_text.clone(),
                    finished: None,
                };
                write_atomic(&dir.join("checkpoint.json"), &serde_json::to_vec(&restart)?)?;
                pb.set_message(format!(
                    "increment {} lambda = {:.5} ({} iterations{}), {failed}/{points} interface points failed",
                    r.increment_index,
                    r.lambda,
                    r.iterations,
                    if r.small_increment_mode { ", small increments" } else { "" }
                ));
                Ok(())
            })();
            last_increment = r.increment_index;
            if let Err(e) = step_out {
                io_error = Some(e);
                return Control::Stop;
            }
            // a deck's `*STEP, INC=n`: at most n increments in that step
            if let Some(&Some((n, line))) = increment_limits.get(r.step) {
                // the deck step's program steps (one per amplitude segment)
                // share its limit, identified by its line
                let same = |k: usize| increment_limits.get(k) == Some(&Some((n, line)));
                let in_step = rows.iter().filter(|row| same(row.step)).count();
                let last_segment = !same(r.step + 1);
                if in_step >= n && !(last_segment && r.step_fraction >= 1.0 - 1e-12) {
                    inc_reached = Some((r.step, n, line));
                    return Control::Stop;
                }
            }
            if INTERRUPTED.load(Ordering::SeqCst)
                || (analysis.stop_when_separated && separated)
                || max_increments.is_some_and(|m| r.increment_index - start_increment >= m)
            {
                return Control::Stop;
            }
            Control::Continue
        };
        match analysis.control {
            scene::Control::Load => solve_nonlinear(
                model,
                p.solver.as_mut(),
                &analysis.steps,
                &analysis.newton,
                checkpoint.as_ref(),
                &mut observer,
            )
            .map(|r| (r, None)),
            scene::Control::ArcLength => solve_arc_length(
                model,
                p.solver.as_mut(),
                &analysis.steps,
                &analysis.newton,
                &analysis.arc_length,
                checkpoint.as_ref(),
                &mut observer,
            )
            .map(|(r, end)| (r, Some(end))),
        }
    };
    if let Some(e) = io_error {
        return Err(e.context("writing the results of an increment"));
    }
    let (status, run, failure) = match result {
        Ok((run, path_end)) => {
            let status = if INTERRUPTED.load(Ordering::SeqCst) {
                "interrupted (Ctrl-C)".to_string()
            } else if let Some((_, n, line)) = inc_reached {
                format!(
                    "stopped: the *STEP at line {line} reached its maximum number of increments INC={n} before its end; raise INC"
                )
            } else if run.summary.stopped_by_observer && separated {
                "stopped: every interface point has failed".to_string()
            } else if run.summary.stopped_by_observer {
                "stopped after the requested number of increments".to_string()
            } else if path_end == Some(PathEnd::Unloaded) {
                "completed: the load factor fell back to zero after its maximum (the structure carries no load any more)".to_string()
            } else if path_end == Some(PathEnd::IncrementLimit) {
                format!(
                    "stopped: [analysis.arc_length] max_increments = {} reached before the end load factor",
                    analysis.arc_length.max_increments
                )
            } else {
                "completed".to_string()
            };
            (status, Some(run), None)
        }
        Err(e @ NonlinearError::IncrementTooSmall { .. }) => {
            (format!("failed: {e}"), None, Some(e))
        }
        Err(e) => return Err(anyhow!(e).context(format!("solving {file}"))),
    };
    // final summary, from the rows on disk (they include a restarted run's past)
    let total_iterations: usize = rows.iter().map(|r| r.iterations).sum();
    let max_iterations = rows.iter().map(|r| r.iterations).max().unwrap_or(0);
    let mut summary = json!({
        "input": file,
        "title": p.title,
        "units": p.units,
        "analysis": "static",
        "status": status,
        "nodes": model.mesh.nodes.len(),
        "dofs": model.dofs.num_dofs(),
        "equations": model.dofs.num_free,
        "elements": output::element_counts(model),
        "increments": last_increment,
        "newton_iterations": {
            "total": total_iterations,
            "max_per_increment": max_iterations,
            "mean_per_increment": total_iterations as f64 / rows.len().max(1) as f64,
            "per_increment": rows.iter().map(|r| r.iterations).collect::<Vec<_>>(),
        },
        "load_factor": rows.last().map(|r| r.lambda),
        "first_failure": first_failure,
        "restarted_from_increment": if start_increment > 0 { Some(start_increment) } else { None },
        "control": analysis.control,
        "limit_points": limit_points(&rows),
    });
    let step = junta_core::element::StepInfo {
        increment: last_increment,
        load_factor: rows.last().map_or(0.0, |r| r.lambda),
        delta_load_factor: 0.0,
        secant: false,
    };
    // the last converged increment is always a frame, whatever stopped the
    // run (end of the program, Ctrl-C, --max-increments, an increment
    // below min_increment), so that nothing computed is lost
    let frame_ctx = FrameContext {
        model,
        dir,
        frames_dir: &frames_dir,
        step,
        start_increment,
    };
    if let Some(run) = &run {
        let ifs = output::interface_results_at(model, &run.u, &run.state, step)?;
        write_final_frame(&frame_ctx, &mut frames, &run.u, &run.state, &ifs)?;
        summary["interfaces"] = output::interface_summary(model, &ifs);
        summary["reactions"] = output::reactions(model, &run.residual)?;
        summary["displacement_max"] = json!(output::displacement_max(&run.u));
        let t = run.summary.timings;
        summary["timings"] = json!({
            "assemble": t.assemble, "analyze": t.analyze, "factor": t.factor, "solve": t.solve,
            "driver_total": t.total, "total": t0.elapsed().as_secs_f64(),
        });
        summary["symbolic_analyses"] = json!(run.summary.analyze_count);
        summary["cutbacks"] = json!(run.summary.cutbacks);
        // of this call (a restarted run counts from its restart)
        summary["driver"] = json!({
            "newton_iterations_with_failed_attempts": run.summary.newton_iterations_total,
            "linear_solves": run.summary.linear_solves,
            "secant_attempts": run.summary.secant_attempts,
        });
    } else if let Some(last) = rows.last() {
        // failed run: the state of the last converged increment is in the
        // checkpoint
        summary["failed_points_at_last_increment"] = json!(last.failed);
        if last_increment > start_increment {
            let r = read_restart(dir)?;
            let mut state = model.initial_state();
            state
                .committed
                .copy_from_slice(&r.checkpoint.state_committed);
            state.restore();
            let ifs = output::interface_results_at(model, &r.checkpoint.u, &state, step)?;
            write_final_frame(&frame_ctx, &mut frames, &r.checkpoint.u, &state, &ifs)?;
            summary["interfaces"] = output::interface_summary(model, &ifs);
        }
    }
    // a deck step the run did not finish: its print rows at the last
    // converged increment, with a note
    if let Some(last) = rows.last().filter(|_| !prints.is_empty()) {
        let ds = deck_step_of.get(last.step).copied().unwrap_or(0);
        if ds >= printed_steps && last_increment > start_increment {
            match &run {
                Some(run) => {
                    let f_int = internal_force_of(model, &run.residual, last.lambda);
                    prints.add_step_with_internal_force(model, ds, &run.u, &f_int, &run.state)?;
                }
                None => {
                    let r = read_restart(dir)?;
                    let mut state = model.initial_state();
                    state
                        .committed
                        .copy_from_slice(&r.checkpoint.state_committed);
                    state.restore();
                    let u = r.checkpoint.u;
                    let f_int = internal_force_at(model, &u, &state, step)?;
                    prints.add_step_with_internal_force(model, ds, &u, &f_int, &state)?;
                }
            }
            prints.note(format!(
                "step {} did not finish: its *NODE PRINT / *EL PRINT rows are at the last converged increment ({}, load factor {:.6e})",
                ds + 1,
                last.increment,
                last.lambda
            ));
        }
    }
    if !prints.is_empty() {
        for n in prints.write(dir)? {
            pb.suspend(|| eprintln!("note: {n}"));
        }
    }
    let (zone, zone_lines, law_warnings) = output::cohesive_zone_advice(model)?;
    if !zone_lines.is_empty() {
        summary["mesh_advice"] = zone;
    }
    if !law_warnings.is_empty() {
        summary["warnings"] = json!(law_warnings);
    }
    let report = p.solver.report();
    let mut notes = p.notes.clone();
    notes.extend(report.notes.iter().cloned());
    let frictional = rows.last().map_or(0.0, |r| r.frictional);
    if model.matrix_kind() == junta_core::MatrixKind::General {
        summary["frictional_dissipation"] = json!(frictional);
    }
    summary["solver"] = json!({
        "name": report.solver,
        "ordering": report.ordering,
        "predicted_factor_nonzeros": output::ordering_candidates(&report),
        "precision": report.precision,
        "factor_nonzeros": report.factor_nonzeros,
        "factorizations": report.factorizations,
        "partial_factorizations": report.partial_factorizations,
        // mean share of a complete factorisation's work a partial one redid
        "partial_work_mean": if report.partial_factorizations > 0 {
            json!(report.refactored_work / report.partial_factorizations as f64)
        } else {
            json!(null)
        },
        "negative_pivots_max": rows.iter().filter_map(|r| r.negative_pivots).max(),
        // solves whose residual ||b - A x|| the back end left to the
        // driver's own force check (factor above doubt; `ldlt`
        // `residual_check`)
        "unchecked_solves": report.unchecked_solves,
        "matrix_kind": model.matrix_kind().name(),
        // a general tangent is assembled in full only for a back end that
        // solves general matrices; otherwise its symmetric part is used
        "tangent": if model.matrix_kind() != junta_core::MatrixKind::General {
            "symmetric"
        } else if p.solver.accepts(junta_core::MatrixKind::General) {
            "consistent (nonsymmetric, full storage)"
        } else {
            "symmetric part of the nonsymmetric tangent (Newton converges linearly)"
        },
        "warnings": report.warnings,
        "notes": notes,
    });
    output::write_json(&dir.join("summary.json"), &summary)?;
    if curve.is_some() && rows.len() >= 2 {
        let pts: Vec<(f64, f64)> = rows
            .iter()
            .filter_map(|r| Some((r.displacement?, r.reaction?)))
            .collect();
        let c = p.curve.as_ref().unwrap();
        let mut series = vec![plot::Series {
            name: "Junta: converged increments".into(),
            points: pts,
            color: 0,
            markers_only: false,
        }];
        if let Some(r) = &c.reference {
            series.push(plot::Series {
                name: r.label.clone(),
                points: read_reference_curve(input, &r.file)?,
                color: 1,
                markers_only: false,
            });
        }
        plot::write_svg(
            &dir.join("curve.svg"),
            &[plot::Panel {
                title: format!("{}: load-displacement", p.title),
                x_label: format!("displacement of {} ({})", c.point_set, c.point_component),
                y_label: format!("reaction on {} ({})", c.reaction_set, c.reaction_component),
                log_x: false,
                log_y: false,
                series,
                vlines: vec![],
            }],
        )?;
    }
    let ended = status == "completed" || status.starts_with("stopped: every interface point");
    if ended && dir.join("checkpoint.json").exists() {
        let mut restart = read_restart(dir)?;
        restart.finished = Some(status.clone());
        write_atomic(&dir.join("checkpoint.json"), &serde_json::to_vec(&restart)?)?;
    }
    pb.finish_and_clear();
    println!(
        "{file}: {status}; {} increments, {} Newton iterations, load factor {:.6} -> {}",
        last_increment,
        total_iterations,
        rows.last().map_or(0.0, |r| r.lambda),
        dir.display()
    );
    match failure {
        Some(e) => Err(anyhow!(e).context(format!(
            "{file}: the run stopped; the {} converged increments are in {} (restart with `junta run --restart {}` after changing [analysis.newton]){}",
            last_increment,
            dir.display(),
            dir.display(),
            past_peak_hint(&rows, model.matrix_kind())
        ))),
        None if INTERRUPTED.load(Ordering::SeqCst) => {
            bail!("interrupted; the converged increments are in {}", dir.display())
        }
        None => Ok(()),
    }
}

/// `frames/results_NNNN.vtu` of increment `increment`.
fn frame_name(increment: usize) -> String {
    format!("frames/results_{increment:04}.vtu")
}

/// Write the frame of increment `ctx.step.increment` (solid and interface
/// VTU files) and list it in `results.pvd`.
fn write_frame(
    ctx: &FrameContext<'_>,
    frames: &mut Vec<(f64, String)>,
    u: &[f64],
    state: &junta_core::state::StateStore,
    ifs: &[output::InterfaceResults],
) -> Result<()> {
    let name = frame_name(ctx.step.increment);
    let cells = output::cell_results_at(ctx.model, u, state, ctx.step)?;
    output::write_vtu(&ctx.dir.join(&name), ctx.model, u, &cells)?;
    let tag = format!("_{:04}", ctx.step.increment);
    output::write_interface_vtu_named(ctx.frames_dir, &tag, ctx.model, u, ifs)?;
    frames.push((ctx.step.load_factor, name));
    output::write_pvd(&ctx.dir.join("results.pvd"), frames)
}

/// What [`write_frame`] and [`write_final_frame`] need besides the state.
struct FrameContext<'a> {
    model: &'a junta_core::Model,
    dir: &'a Path,
    frames_dir: &'a Path,
    step: junta_core::element::StepInfo,
    start_increment: usize,
}

/// Write the frame of the last converged increment (`step.increment`)
/// unless this run wrote none or it is already the last frame, list it in
/// `results.pvd`, and keep the checkpoint's frame list in step.
fn write_final_frame(
    ctx: &FrameContext<'_>,
    frames: &mut Vec<(f64, String)>,
    u: &[f64],
    state: &junta_core::state::StateStore,
    ifs: &[output::InterfaceResults],
) -> Result<()> {
    let last = ctx.step.increment;
    if last <= ctx.start_increment || frames.last().map(|f| &f.1) == Some(&frame_name(last)) {
        return Ok(());
    }
    write_frame(ctx, frames, u, state, ifs)?;
    let mut restart = read_restart(ctx.dir)?;
    restart.frames = frames.clone();
    write_atomic(
        &ctx.dir.join("checkpoint.json"),
        &serde_json::to_vec(&restart)?,
    )
}

/// Read `DIR/checkpoint.json`.
pub fn read_restart(dir: &Path) -> Result<RestartFile> {
    let path = dir.join("checkpoint.json");
    let text = std::fs::read_to_string(&path).with_context(|| {
        format!(
            "cannot read {} (is {} the output directory of an incremental run?)",
            path.display(),
            dir.display()
        )
    })?;
    serde_json::from_str(&text)
        .with_context(|| format!("{}: not a Junta checkpoint", path.display()))
}

/// The elements' internal force `f_int = r + lambda f_ext` from a run's
/// residual `r = f_int - lambda f_ext`.
fn internal_force_of(model: &junta_core::Model, residual: &[f64], lambda: f64) -> Vec<f64> {
    residual
        .iter()
        .zip(&model.f_ext)
        .map(|(r, f)| r + lambda * f)
        .collect()
}

/// The elements' internal force `f_int(u)` at a converged state (trial
/// state from `state`'s committed values): the `RF` of a print table.
fn internal_force_at(
    model: &junta_core::Model,
    u: &[f64],
    state: &junta_core::state::StateStore,
    step: junta_core::element::StepInfo,
) -> Result<Vec<f64>> {
    let asm = model.assembler();
    let mut f_int = vec![0.0; model.dofs.num_dofs()];
    let mut state = state.clone();
    asm.assemble(
        &model.mesh,
        &model.elements,
        &model.dofs,
        u,
        &mut state,
        step,
        None,
        &mut f_int,
    )
    .context("internal force of the last converged increment")?;
    Ok(f_int)
}
