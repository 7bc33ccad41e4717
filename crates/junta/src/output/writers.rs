//! The files of an incremental run, each written by a
//! [`Writer`](crate::run::observer::Writer) (an observer that keeps the run's log):
//!
//! - [`CurveCsv`]: `curve.csv`, one row per converged increment (increment,
//!   step, load factor, reaction, displacement, failed points, Newton
//!   iterations, cut-backs, wall time, dissipated energy, damaged area,
//!   negative pivots of the tangent, sign of the load-factor increment, the
//!   constraint of the increment and the displacement conjugate to the
//!   applied forces, frictional dissipation);
//! - [`PlyFailureCsv`]: `ply_failure.csv`, the `[[ply_failure]]` criteria's
//!   largest index and smallest strength ratio per converged increment;
//! - [`VtuFrames`]: `frames/results_NNNN.vtu`, `frames/interfaces_NNNN.vtu`,
//!   `frames/interface_points_NNNN.vtu` and `results.pvd` (ParaView plays
//!   the crack growing), every `[output] every` increments, at separation,
//!   and for the last converged increment whatever ends the run;
//! - [`Checkpoints`]: `checkpoint.json`, the restart point after every
//!   increment (`junta run --restart DIR`), marked finished at the end of
//!   the program;
//! - [`PrintTables`]: a deck's `node_print.csv` / `el_print.csv`, rows at
//!   the end of each deck step;
//! - [`SummaryJson`]: `summary.json` and `curve.svg` at the end (also after
//!   a failure or an interrupt).
//!
//! [`standard`] gives them in the order they depend on each other (frames
//! before the checkpoint, which lists them).

use crate::error::{Context, Result};
use crate::input::scene::CurveSpec;
use crate::output::deck_print;
use crate::post::curve::{read_reference_curve, CurveRow};
use crate::post::curve_columns::curve_header;
use crate::post::fields::InterfaceResults;
use crate::post::ply_failure::{PlyCriterionUse, PlyFailureResult};
use crate::prepare::Prepared;
use crate::run::checkpoint::{read_restart, write_atomic, InputHash, RestartFile};
use crate::run::observer::{Flow, Increment, RunEnd, RunInfo, RunLog, Writer};
use junta_core::element::StepInfo;
use junta_core::state::StateStore;
use junta_core::Model;
use junta_solvers::newton::Checkpoint;
use std::io::Write;
use std::path::{Path, PathBuf};

/// `curve.csv`.
pub struct CurveCsv {
    path: PathBuf,
    file: Option<std::fs::File>,
}

impl CurveCsv {
    /// Write `dir/curve.csv`.
    pub fn new(dir: &Path) -> Self {
        CurveCsv {
            path: dir.join("curve.csv"),
            file: None,
        }
    }
}

impl Writer for CurveCsv {
    fn on_start(&mut self, _run: &RunInfo<'_>, log: &RunLog) -> Result<()> {
        // a restart keeps the rows up to its checkpoint
        let mut text = curve_header();
        for r in &log.rows {
            text += &r.csv();
        }
        let path = &self.path;
        std::fs::write(path, text).with_context(|| format!("cannot write {}", path.display()))?;
        let file = std::fs::OpenOptions::new()
            .append(true)
            .open(path)
            .with_context(|| format!("cannot open {}", path.display()))?;
        self.file = Some(file);
        Ok(())
    }
    fn on_increment(&mut self, inc: &Increment<'_>, _log: &mut RunLog) -> Result<Flow> {
        if let Some(f) = &mut self.file {
            f.write_all(inc.row.csv().as_bytes())?;
            f.flush()?;
        }
        Ok(Flow::Continue)
    }
}

/// `ply_failure.csv`: per converged increment, each `[[ply_failure]]`
/// criterion's largest index and smallest strength ratio (no file without
/// criteria).
pub struct PlyFailureCsv {
    path: PathBuf,
    names: Vec<String>,
    file: Option<std::fs::File>,
}

impl PlyFailureCsv {
    /// Write `dir/ply_failure.csv` for the criteria `criteria`.
    pub fn new(dir: &Path, criteria: &[PlyCriterionUse]) -> Self {
        PlyFailureCsv {
            path: dir.join("ply_failure.csv"),
            names: criteria.iter().map(|c| c.name.clone()).collect(),
            file: None,
        }
    }

    /// The lines of an earlier run's file up to `increment` (a restart
    /// keeps the rows up to its checkpoint).
    fn kept_lines(&self, increment: usize) -> String {
        let old = std::fs::read_to_string(&self.path).unwrap_or_default();
        old.lines()
            .skip(1)
            .filter(|l| {
                l.split(',')
                    .next()
                    .and_then(|i| i.parse::<usize>().ok())
                    .is_some_and(|i| i <= increment)
            })
            .map(|l| format!("{l}\n"))
            .collect()
    }
}

impl Writer for PlyFailureCsv {
    fn on_start(&mut self, _run: &RunInfo<'_>, log: &RunLog) -> Result<()> {
        if self.names.is_empty() {
            return Ok(());
        }
        let mut text = crate::post::ply_failure_history::csv_header(&self.names);
        if !log.rows.is_empty() {
            text += &self.kept_lines(log.start_increment);
        }
        let path = &self.path;
        std::fs::write(path, text).with_context(|| format!("cannot write {}", path.display()))?;
        let file = std::fs::OpenOptions::new()
            .append(true)
            .open(path)
            .with_context(|| format!("cannot open {}", path.display()))?;
        self.file = Some(file);
        Ok(())
    }
    fn on_increment(&mut self, inc: &Increment<'_>, _log: &mut RunLog) -> Result<Flow> {
        if let Some(f) = &mut self.file {
            let line = crate::post::ply_failure_history::csv_line(inc.row, inc.ply_failure);
            f.write_all(line.as_bytes())?;
            f.flush()?;
        }
        Ok(Flow::Continue)
    }
}

/// `frames/results_NNNN.vtu` of increment `increment`.
fn frame_name(increment: usize) -> String {
    format!("frames/results_{increment:04}.vtu")
}

/// The VTU frames and `results.pvd` (none with `[output] vtu = false`).
pub struct VtuFrames {
    dir: PathBuf,
    every: usize,
    enabled: bool,
    /// The `[[ply_failure]]` criteria (their `NAME_index` cell data).
    ply_criteria: Vec<PlyCriterionUse>,
}

impl VtuFrames {
    /// Frames of every `every`-th increment into `dir/frames`.
    pub fn new(dir: &Path, every: usize) -> Self {
        VtuFrames {
            dir: dir.to_path_buf(),
            every: every.max(1),
            enabled: true,
            ply_criteria: Vec::new(),
        }
    }

    /// With the ply failure indices of `criteria` as cell data.
    pub fn with_ply_criteria(mut self, criteria: &[PlyCriterionUse]) -> Self {
        self.ply_criteria = criteria.to_vec();
        self
    }

    /// No frame at all (`[output] vtu = false`).
    pub fn disabled(dir: &Path) -> Self {
        VtuFrames {
            enabled: false,
            ..Self::new(dir, 1)
        }
    }

    /// Write the frame of increment `step.increment` (solid and interface
    /// VTU files) and list it in `results.pvd`.
    fn write(
        &self,
        model: &Model,
        step: StepInfo,
        frames: &mut Vec<(f64, String)>,
        u: &[f64],
        state: &StateStore,
        ifs: &[InterfaceResults],
        ply: &[PlyFailureResult],
    ) -> Result<()> {
        let name = frame_name(step.increment);
        let mut cells = crate::post::fields::cell_results_at(model, u, state, step)?;
        crate::post::ply_failure::add_cell_data(ply, &mut cells);
        crate::output::vtu::write_vtu(&self.dir.join(&name), model, u, &cells)?;
        let tag = format!("_{:04}", step.increment);
        crate::output::vtu::write_interface_vtu_named(
            &self.dir.join("frames"),
            &tag,
            model,
            u,
            ifs,
        )?;
        frames.push((step.load_factor, name));
        crate::output::vtu::write_pvd(&self.dir.join("results.pvd"), frames)
    }
}

impl Writer for VtuFrames {
    fn on_start(&mut self, _run: &RunInfo<'_>, _log: &RunLog) -> Result<()> {
        if !self.enabled {
            return Ok(());
        }
        let frames_dir = self.dir.join("frames");
        std::fs::create_dir_all(&frames_dir)
            .with_context(|| format!("cannot create {}", frames_dir.display()))
    }
    fn on_increment(&mut self, inc: &Increment<'_>, log: &mut RunLog) -> Result<Flow> {
        if !self.enabled {
            return Ok(Flow::Continue);
        }
        if inc.step.increment.is_multiple_of(self.every) || log.separated {
            self.write(
                inc.model,
                inc.step,
                &mut log.frames,
                inc.u,
                inc.state,
                inc.interfaces,
                inc.ply_failure,
            )?;
        }
        Ok(Flow::Continue)
    }
    /// The last converged increment is always a frame, whatever stopped
    /// the run (end of the program, Ctrl-C, a stop, an increment below
    /// min_increment), so that nothing computed is lost.
    fn on_end(&mut self, end: &RunEnd<'_>, log: &mut RunLog) -> Result<()> {
        let last = end.step.increment;
        if !self.enabled {
            return Ok(());
        }
        let (Some(u), Some(state)) = (end.u, end.state) else {
            return Ok(());
        };
        if !end.converged_here || log.frames.last().map(|f| &f.1) == Some(&frame_name(last)) {
            return Ok(());
        }
        let ply =
            crate::post::ply_failure::evaluate(end.model, u, state, end.step, &self.ply_criteria)?;
        self.write(
            end.model,
            end.step,
            &mut log.frames,
            u,
            state,
            end.interfaces,
            &ply,
        )
    }
}

/// `checkpoint.json` after every increment.
pub struct Checkpoints {
    dir: PathBuf,
    input: PathBuf,
    solver_overrides: Vec<String>,
    inputs: Vec<InputHash>,
    scene_text: Option<String>,
}

impl Checkpoints {
    /// Restart points of the run of `input` (prepared with
    /// `solver_overrides`) into `dir/checkpoint.json`.
    pub fn new(dir: &Path, input: &Path, solver_overrides: &[String]) -> Self {
        let scene_text = input
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("toml"))
            .then(|| std::fs::read_to_string(input).ok())
            .flatten();
        Checkpoints {
            dir: dir.to_path_buf(),
            input: std::fs::canonicalize(input).unwrap_or_else(|_| input.to_path_buf()),
            solver_overrides: solver_overrides.to_vec(),
            inputs: crate::run::checkpoint::hash_inputs(input),
            scene_text,
        }
    }
}

impl Writer for Checkpoints {
    fn on_increment(&mut self, inc: &Increment<'_>, log: &mut RunLog) -> Result<Flow> {
        let restart = RestartFile {
            input: self.input.clone(),
            checkpoint: inc.checkpoint(),
            first_failure: log.first_failure.clone(),
            path_switches: log.path_switches.clone(),
            frames: log.frames.clone(),
            solver_overrides: self.solver_overrides.clone(),
            inputs: self.inputs.clone(),
            scene_text: self.scene_text.clone(),
            finished: None,
            external_force: log.external_force.clone(),
            ply_failure: log.ply_failure.clone(),
        };
        write_atomic(
            &self.dir.join("checkpoint.json"),
            &serde_json::to_vec(&restart)?,
        )?;
        Ok(Flow::Continue)
    }
    /// Keep the frame list in step with the final frame, and mark a run
    /// that ended for good: a restart then has nothing to do.
    fn on_end(&mut self, end: &RunEnd<'_>, log: &mut RunLog) -> Result<()> {
        let path = self.dir.join("checkpoint.json");
        if !path.exists() {
            return Ok(());
        }
        let mut restart = read_restart(&self.dir)?;
        let ended = end.reason.is_final();
        let frames_changed = restart.frames != log.frames;
        if !ended && !frames_changed {
            return Ok(());
        }
        restart.frames = log.frames.clone();
        if ended {
            restart.finished = Some(end.status.to_string());
        }
        write_atomic(&path, &serde_json::to_vec(&restart)?)
    }
}

/// A deck's `*NODE PRINT` / `*EL PRINT` tables.
pub struct PrintTables {
    dir: PathBuf,
    tables: deck_print::PrintTables,
    /// Per program step: the deck step it belongs to.
    deck_step_of: Vec<usize>,
    /// Deck steps whose rows are in the tables.
    printed_steps: usize,
    /// Notes of the tables (the command line shows them).
    pub notes: Vec<String>,
}

impl PrintTables {
    /// The print requests of `p` (taken out of it), resumed after
    /// `checkpoint` on a restart.
    pub fn new(dir: &Path, p: &mut Prepared, checkpoint: Option<&Checkpoint>) -> Self {
        let mut w = PrintTables {
            dir: dir.to_path_buf(),
            tables: std::mem::take(&mut p.prints),
            deck_step_of: p.program_deck_steps.clone(),
            printed_steps: 0,
            notes: Vec::new(),
        };
        if let Some(c) = checkpoint.filter(|_| !w.tables.is_empty()) {
            w.printed_steps = match w.deck_step_ends(c.step, c.step_fraction) {
                Some(ds) => ds + 1,
                None => w.deck_step_of.get(c.step).copied().unwrap_or(0),
            };
            w.tables.resume_from(dir, w.printed_steps);
        }
        w
    }

    /// The deck step that ends with program step `step` at `fraction`
    /// (a deck step with an amplitude spans several program steps).
    fn deck_step_ends(&self, step: usize, fraction: f64) -> Option<usize> {
        let ds = *self.deck_step_of.get(step)?;
        (fraction >= 1.0 - 1e-12 && self.deck_step_of.get(step + 1) != Some(&ds)).then_some(ds)
    }
}

impl Writer for PrintTables {
    fn on_increment(&mut self, inc: &Increment<'_>, _log: &mut RunLog) -> Result<Flow> {
        let r = inc.report;
        if let Some(ds) = self.deck_step_ends(r.step, r.step_fraction) {
            if !self.tables.is_empty() {
                let f_int = internal_force_of(inc.model, inc.residual, r.lambda);
                self.tables
                    .add_step_with_internal_force(inc.model, ds, inc.u, &f_int, inc.state)?;
                self.tables.save(&self.dir)?;
            }
            self.printed_steps = ds + 1;
        }
        Ok(Flow::Continue)
    }
    /// A deck step the run did not finish: its rows at the last converged
    /// increment, with a note.
    fn on_end(&mut self, end: &RunEnd<'_>, log: &mut RunLog) -> Result<()> {
        if self.tables.is_empty() {
            return Ok(());
        }
        if let (Some(last), Some(u), Some(state)) = (log.rows.last(), end.u, end.state) {
            let ds = self.deck_step_of.get(last.step).copied().unwrap_or(0);
            if ds >= self.printed_steps && end.converged_here {
                let f_int = match end.residual {
                    Some(r) => internal_force_of(end.model, r, last.lambda),
                    None => internal_force_at(end.model, u, state, end.step)?,
                };
                self.tables
                    .add_step_with_internal_force(end.model, ds, u, &f_int, state)?;
                self.tables.note(format!(
                    "step {} did not finish: its *NODE PRINT / *EL PRINT rows are at the last converged increment ({}, load factor {:.6e})",
                    ds + 1,
                    last.increment,
                    last.lambda
                ));
            }
        }
        let tables = std::mem::take(&mut self.tables);
        self.notes.extend(tables.write(&self.dir)?);
        Ok(())
    }
}

/// `summary.json`, `curve.svg` and (fatigue runs) `fatigue.svg` at the
/// end of the run.
pub struct SummaryJson {
    dir: PathBuf,
    input: PathBuf,
    title: String,
    curve: Option<CurveSpec>,
    /// An interface element whose law has a fatigue growth law, and the
    /// program's load ratio (for the law's line on `fatigue.svg`).
    fatigue_law: Option<(std::sync::Arc<dyn junta_core::Element>, f64)>,
}

impl SummaryJson {
    /// The summary of the run of `input` into `dir`.
    pub fn new(dir: &Path, input: &Path, p: &Prepared) -> Self {
        SummaryJson {
            dir: dir.to_path_buf(),
            input: input.to_path_buf(),
            title: p.title.clone(),
            curve: p.curve.clone(),
            fatigue_law: p.model.fatigue.as_ref().and_then(|f| {
                p.model
                    .elements
                    .iter()
                    .find(|e| e.fatigue_growth_rate(1.0, 0.0, 0.0).is_some())
                    .map(|e| (e.clone(), f.load_ratios.last().copied().unwrap_or(0.0)))
            }),
        }
    }
}

impl Writer for SummaryJson {
    fn on_increment(&mut self, _inc: &Increment<'_>, _log: &mut RunLog) -> Result<Flow> {
        Ok(Flow::Continue)
    }
    fn on_end(&mut self, end: &RunEnd<'_>, log: &mut RunLog) -> Result<()> {
        crate::output::summary::write_json(&self.dir.join("summary.json"), &end.summary.to_json())?;
        if let Some((law, r)) = &self.fatigue_law {
            write_fatigue_svg(
                &self.dir.join("fatigue.svg"),
                &self.title,
                law.as_ref(),
                *r,
                &log.rows,
            )?;
        }
        match &self.curve {
            Some(c) if log.rows.len() >= 2 => write_curve_svg(
                &self.dir.join("curve.svg"),
                &self.input,
                &self.title,
                c,
                &log.rows,
            ),
            _ => Ok(()),
        }
    }
}

/// The fatigue chart: the crack growth rate of every row where the crack
/// grew against the energy release rate measured on the interface (over
/// the law's toughness at the measured mode ratio), on log axes, with the
/// law's own growth law (the Paris line) at the mean mode ratio. Nothing
/// when no row has both.
fn write_fatigue_svg(
    path: &Path,
    title: &str,
    law: &dyn junta_core::Element,
    load_ratio: f64,
    rows: &[CurveRow],
) -> Result<()> {
    use crate::output::plot;
    let measured: Vec<(f64, f64, f64)> = rows
        .iter()
        .filter_map(|r| {
            let (g, b, rate) = (
                r.energy_release_rate?,
                r.crack_mode_ratio?,
                r.crack_growth_rate?,
            );
            let (g_c, _) = law.fatigue_growth_rate(g, b, load_ratio)?;
            Some((g / g_c, rate, b))
        })
        .collect();
    if measured.is_empty() {
        return Ok(());
    }
    let b = measured.iter().map(|m| m.2).sum::<f64>() / measured.len() as f64;
    let lo = measured.iter().map(|m| m.0).fold(f64::INFINITY, f64::min) / 1.5;
    let line: Vec<(f64, f64)> = (0..=40)
        .filter_map(|i| {
            let x = lo * (1.0 / lo).powf(i as f64 / 40.0);
            let (g_c, _) = law.fatigue_growth_rate(1.0, b, load_ratio)?;
            Some((x, law.fatigue_growth_rate(x * g_c, b, load_ratio)?.1))
        })
        .collect();
    plot::write_svg(
        path,
        &[plot::Panel {
            title: format!("{title}: crack growth rate (R = {load_ratio})"),
            x_label: "G_max / G_c (J integral of the cohesive tractions)".into(),
            y_label: "da/dN (length per cycle)".into(),
            log_x: true,
            log_y: true,
            series: vec![
                plot::Series {
                    name: "Junta: growth between crack readings".into(),
                    points: measured.iter().map(|m| (m.0, m.1)).collect(),
                    color: 0,
                    markers_only: true,
                },
                plot::Series {
                    name: format!("the law's growth law at mode ratio {b:.2}"),
                    points: line,
                    color: 1,
                    markers_only: false,
                },
            ],
            vlines: vec![],
        }],
    )
}

/// The load-displacement chart, with the scene's reference curve.
fn write_curve_svg(
    path: &Path,
    input: &Path,
    title: &str,
    c: &CurveSpec,
    rows: &[CurveRow],
) -> Result<()> {
    use crate::output::plot;
    let pts: Vec<(f64, f64)> = rows
        .iter()
        .filter_map(|r| Some((r.displacement?, r.reaction?)))
        .collect();
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
        path,
        &[plot::Panel {
            title: format!("{title}: load-displacement"),
            x_label: format!("displacement of {} ({})", c.point_set, c.point_component),
            y_label: format!("reaction on {} ({})", c.reaction_set, c.reaction_component),
            log_x: false,
            log_y: false,
            series,
            vlines: vec![],
        }],
    )
}

/// The writers of a standard run directory, in the order they depend on
/// each other: curve, print tables, frames, checkpoint, summary.
pub struct Standard {
    /// `curve.csv`.
    pub curve: CurveCsv,
    /// `ply_failure.csv`.
    pub ply_failure: PlyFailureCsv,
    /// Print tables (decks).
    pub prints: PrintTables,
    /// VTU frames.
    pub frames: VtuFrames,
    /// `checkpoint.json`.
    pub checkpoints: Checkpoints,
    /// `summary.json`, `curve.svg`.
    pub summary: SummaryJson,
}

/// The standard writers of the run of `input` into `dir`.
pub fn standard(
    dir: &Path,
    input: &Path,
    p: &mut Prepared,
    checkpoint: Option<&Checkpoint>,
) -> Standard {
    Standard {
        curve: CurveCsv::new(dir),
        ply_failure: PlyFailureCsv::new(dir, &p.ply_criteria),
        prints: PrintTables::new(dir, p, checkpoint),
        frames: if p.vtu {
            VtuFrames::new(dir, p.every).with_ply_criteria(&p.ply_criteria)
        } else {
            VtuFrames::disabled(dir)
        },
        checkpoints: Checkpoints::new(dir, input, &p.solver_overrides),
        summary: SummaryJson::new(dir, input, p),
    }
}

impl Standard {
    /// The writers, in order.
    pub(crate) fn writers(&mut self) -> [&mut dyn Writer; 6] {
        [
            &mut self.curve,
            &mut self.ply_failure,
            &mut self.prints,
            &mut self.frames,
            &mut self.checkpoints,
            &mut self.summary,
        ]
    }
}

/// The elements' internal force `f_int = r + lambda f_ext` from a run's
/// residual `r = f_int - lambda f_ext`.
fn internal_force_of(model: &Model, residual: &[f64], lambda: f64) -> Vec<f64> {
    residual
        .iter()
        .zip(&model.f_ext)
        .map(|(r, f)| r + lambda * f)
        .collect()
}

/// The elements' internal force `f_int(u)` at a converged state (trial
/// state from `state`'s committed values): the `RF` of a print table.
fn internal_force_at(
    model: &Model,
    u: &[f64],
    state: &StateStore,
    step: StepInfo,
) -> Result<Vec<f64>> {
    use crate::error::Context;
    let asm = model.whole_assembler();
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
