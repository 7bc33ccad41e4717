//! The run API: a [`Simulation`] read from a file (a TOML scene or an
//! Abaqus/CalculiX deck) or built in code, checked, and run with observers.
//!
//! ```no_run
//! use junta::{Flow, FnObserver, RunSettings, Simulation};
//! let sim = Simulation::from_file("examples/delamination/dcb.toml")?;
//! let report = sim.check()?;
//! println!("{} equations", report.equations);
//! // stop once the crack has failed 100 interface points
//! let mut watch = FnObserver(|inc: &junta::Increment<'_>| {
//!     if inc.row.failed >= 100 { Flow::Stop("100 points failed".into()) } else { Flow::Continue }
//! });
//! let results = sim.run(&RunSettings::in_memory(), &mut [&mut watch])?;
//! let peak = results.curve().get("reaction").unwrap().iter().cloned().fold(0.0, f64::max);
//! println!("{}: peak {peak}", results.status_line);
//! # Ok::<(), junta::Error>(())
//! ```
//!
//! A run writes the files of the command line (`curve.csv`, frames,
//! `checkpoint.json`, `summary.json`) when [`RunSettings::output`] names a
//! directory, and only reports to the observers otherwise. A run that ends
//! early (a stop, an increment below the smallest size, an interrupt)
//! returns `Ok` with its [`Status`]; [`RunResults::failure`] holds the
//! error the command line exits with.

use crate::error::{bail, err, Context, Error, Result};
use crate::input::scene::AnalysisKind;
use crate::output::writers;
use crate::post::curve::{past_peak_hint, Curve};
use crate::prepare::check::CheckReport;
use crate::prepare::{prepare_with, Prepared};
use crate::run::checkpoint::{check_fields, check_inputs, read_restart, RestartFile};
use crate::run::incremental::{run_incremental, Limits};
use crate::run::observer::{Observer, ReadOnly, RunLog, Writer};
pub use crate::run::results::{EndReason, RunResults, Status};
use std::path::{Path, PathBuf};

/// Options of reading an input.
#[derive(Debug, Clone, Default)]
pub struct Options {
    /// `KEY=VALUE` overrides of the linear solver (`type=cg`,
    /// `precision=double`), as `junta run --solver`.
    pub solver: Vec<String>,
    /// Overrides of scene keys by dotted path (`laws.cz.G_Ic`,
    /// `analysis.arc_length.max_increments`, `boundary.1.value`) with their
    /// new value; TOML scenes only. A path whose parent is not in the scene
    /// is an error naming it.
    pub overrides: Vec<(String, toml::Value)>,
}

/// Where and how long a run goes.
#[derive(Debug, Clone, Default)]
pub struct RunSettings {
    /// Output directory for the standard files; `None`: observers only.
    pub output: Option<PathBuf>,
    /// Incremental runs: stop after this many increments of this call (a
    /// restart point is kept).
    pub max_increments: Option<usize>,
    /// Linear runs: leave [`RunResults::frame`] empty. The end fields at
    /// every integration point cost about 200 bytes per point (340 MB on a
    /// 216,000-element H8 cube); a caller that only writes the files (the
    /// command line) does without them.
    pub without_end_frame: bool,
    /// Run the drivers on the calling thread rather than on a thread of
    /// rayon's pool (see [`Simulation::run`]). For a caller that must see
    /// its own thread's state during the run (a signal handler, a
    /// thread-local). The Python package, whose Ctrl-C is only seen on
    /// Python's main thread, runs on the pool and has that thread answer
    /// its signal checks instead.
    pub on_calling_thread: bool,
}

impl RunSettings {
    /// Write the standard files into `dir`.
    pub fn into_dir(dir: impl Into<PathBuf>) -> Self {
        RunSettings {
            output: Some(dir.into()),
            ..Self::default()
        }
    }
    /// Write no file: results and observers only.
    pub fn in_memory() -> Self {
        Self::default()
    }
}

/// A model ready to run.
pub struct Simulation {
    input: PathBuf,
    prepared: Prepared,
    options: Options,
}

impl std::fmt::Debug for Simulation {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Simulation")
            .field("input", &self.input)
            .field("equations", &self.prepared.model.dofs.num_free)
            .finish()
    }
}

impl Simulation {
    /// Read a scene (`.toml`) or a deck (`.inp`) and build its model.
    pub fn from_file(path: impl AsRef<Path>) -> Result<Simulation> {
        Self::from_file_with(path, Options::default())
    }

    /// [`Simulation::from_file`] with solver and scene overrides.
    pub fn from_file_with(path: impl AsRef<Path>, options: Options) -> Result<Simulation> {
        let input = path.as_ref().to_path_buf();
        let prepared = prepare_with(&input, &options)?;
        Ok(Simulation {
            input,
            prepared,
            options,
        })
    }

    /// A scene given as TOML text; `path` names it in messages and
    /// relative file names (mesh, reference curve) are read next to it.
    pub fn from_scene_text(text: &str, path: impl AsRef<Path>) -> Result<Simulation> {
        let input = path.as_ref().to_path_buf();
        let prepared = crate::prepare::prepare_scene_text(&input, text.to_string(), &[])?;
        Ok(Simulation {
            input,
            prepared,
            options: Options::default(),
        })
    }

    /// A model built in code, run as `analysis` (linear when
    /// `analysis.kind` is [`AnalysisKind::Linear`]) with the linear solver `solver`
    /// (`"auto"` chooses from the model).
    pub fn from_model(
        model: junta_core::Model,
        analysis: crate::input::scene::AnalysisSpec,
        solver: &str,
    ) -> Result<Simulation> {
        let prepared = crate::prepare::prepare_model(model, analysis, solver)?;
        Ok(Simulation {
            input: PathBuf::from("(model built in code)"),
            prepared,
            options: Options::default(),
        })
    }

    /// The input file.
    pub fn input(&self) -> &Path {
        &self.input
    }

    /// The prepared model, solver and output options.
    pub fn prepared(&self) -> &Prepared {
        &self.prepared
    }

    /// The model.
    pub fn model(&self) -> &junta_core::Model {
        &self.prepared.model
    }

    /// Notes from reading the input (solver choice, ignored keywords).
    pub fn notes(&self) -> &[String] {
        &self.prepared.notes
    }

    /// True for an incremental run (`[analysis] type = "static"`, a deck
    /// with a softening law or amplitudes).
    pub fn is_incremental(&self) -> bool {
        self.prepared.analysis.kind.is_incremental()
    }

    /// What `junta check` prints, as data.
    pub fn check(&self) -> Result<CheckReport> {
        CheckReport::of(&self.input, &self.prepared)
    }

    /// The default output directory: the scene's `[output] directory`,
    /// else `out/<file stem>`.
    pub fn default_output(&self) -> PathBuf {
        self.prepared
            .output_dir
            .clone()
            .unwrap_or_else(|| crate::prepare::default_dir(&self.input, ""))
    }

    /// Run, reporting to `observers` (after the standard writers when
    /// `settings.output` names a directory). The drivers run on a thread of
    /// rayon's global pool (the calling thread waits), unless
    /// `settings.on_calling_thread` or under MPI: a caller that wants a
    /// larger stack for them than rayon's 2 MiB builds the global pool
    /// first, as the command line does.
    pub fn run(
        self,
        settings: &RunSettings,
        observers: &mut [&mut dyn Observer],
    ) -> Result<RunResults> {
        on_pool(settings, || self.run_here(settings, observers))
    }

    /// [`Simulation::run`] on the calling thread.
    fn run_here(
        mut self,
        settings: &RunSettings,
        observers: &mut [&mut dyn Observer],
    ) -> Result<RunResults> {
        let dir = create_output(settings.output.as_deref())?;
        match self.prepared.analysis.kind {
            AnalysisKind::Linear => crate::run::linear::run_linear(
                &self.input,
                &mut self.prepared,
                dir.as_deref(),
                observers,
                !settings.without_end_frame,
            ),
            AnalysisKind::Static => run_static(
                &self.input,
                &mut self.prepared,
                dir,
                None,
                settings,
                observers,
            ),
        }
    }

    /// The `--solver` overrides the simulation was read with.
    pub fn options(&self) -> &Options {
        &self.options
    }
}

/// Run `work` on a thread of rayon's global pool, unless `settings` ask
/// for the calling thread or this process is one rank of an MPI run (MPI
/// is called from the thread that started it).
///
/// Why: a parallel loop started from a thread outside the pool queues its
/// work for the pool and sleeps until a pool thread has done it (rayon's
/// "cold" path: a lock, a wake-up and a context switch each way). The
/// drivers start several per Newton iteration (assembly, residual, norms),
/// about 1,900 in the 2D DCB example's 0.8 s. Started from a pool thread,
/// the loop begins on that thread at once and the other threads steal from
/// it. The answers are the same to the last bit (every reduction's order is
/// fixed by its chunks, not by the threads); the 2D DCB runs in 0.63 s
/// instead of 0.85 s (docs/performance.md).
fn on_pool<R: Send>(settings: &RunSettings, work: impl FnOnce() -> R + Send) -> R {
    if settings.on_calling_thread || junta_core::distributed::collective().is_some() {
        return work();
    }
    rayon::scope(|_| work())
}

/// Create the output directory, if any.
fn create_output(dir: Option<&Path>) -> Result<Option<PathBuf>> {
    let Some(dir) = dir else { return Ok(None) };
    std::fs::create_dir_all(dir)
        .with_context(|| format!("cannot create output directory {}", dir.display()))?;
    Ok(Some(dir.to_path_buf()))
}

/// A restart read from an output directory, checked against its inputs.
pub struct Restart {
    /// The checkpoint file.
    pub file: RestartFile,
    /// Edits of the inputs accepted with `allow_edited` (for the user).
    pub edits: Vec<String>,
}

/// Read `DIR/checkpoint.json` and check the inputs it was made from (an
/// edited input is an error unless `allow_edited`). `Ok(None)`: the run
/// already finished, nothing to restart.
pub fn read_checkpoint(dir: &Path, allow_edited: bool) -> Result<Option<Restart>> {
    let r = read_restart(dir)?;
    if r.finished.is_some() {
        return Ok(None);
    }
    let edits = check_inputs(&r, allow_edited)?;
    Ok(Some(Restart { file: r, edits }))
}

/// The status line of a run that already finished (for
/// [`read_checkpoint`] returning `None`).
pub fn finished_message(dir: &Path) -> Result<String> {
    let r = read_restart(dir)?;
    Ok(format!(
        "{}: the run already finished ({}) at increment {}; nothing to restart, {} left unchanged",
        r.input.display(),
        r.finished.as_deref().unwrap_or("finished"),
        r.checkpoint.increment_index,
        dir.display()
    ))
}

/// Continue the incremental run whose output directory is `dir` from its
/// last converged increment, with the run's own solver overrides.
pub fn restart(
    dir: &Path,
    restart: Restart,
    settings: &RunSettings,
    observers: &mut [&mut dyn Observer],
) -> Result<RunResults> {
    on_pool(settings, || restart_here(dir, restart, settings, observers))
}

/// [`restart`] on the calling thread.
fn restart_here(
    dir: &Path,
    restart: Restart,
    settings: &RunSettings,
    observers: &mut [&mut dyn Observer],
) -> Result<RunResults> {
    let r = restart.file;
    let input = r.input.clone();
    let options = Options {
        solver: r.solver_overrides.clone(),
        overrides: Vec::new(),
    };
    let mut p = prepare_with(&input, &options)?;
    if !p.analysis.kind.is_incremental() {
        bail!(
            "{}: only incremental runs ([analysis] type = \"static\") can be restarted",
            input.display()
        );
    }
    check_fields(
        &r,
        &dir.join("checkpoint.json"),
        p.analysis.steps.len(),
        p.model.dofs.num_dofs(),
    )?;
    // the converged rows are read from `dir`; the files are written where
    // `settings` says (a run over MPI ranks writes from rank 0 only)
    let past = Curve::read_rows(dir, r.checkpoint.increment_index);
    let mut results = run_static(
        &input,
        &mut p,
        settings.output.clone(),
        Some((r, past)),
        settings,
        observers,
    )?;
    let mut notes: Vec<String> = restart
        .edits
        .into_iter()
        .map(|c| format!("continuing with an edited input (--allow-edited): {c}"))
        .collect();
    notes.append(&mut results.notes);
    results.notes = notes;
    Ok(results)
}

/// An incremental run with the standard writers (when `dir` is given) in
/// front of the caller's observers.
fn run_static(
    input: &Path,
    p: &mut Prepared,
    dir: Option<PathBuf>,
    restart: Option<(RestartFile, Vec<crate::post::curve::CurveRow>)>,
    settings: &RunSettings,
    observers: &mut [&mut dyn Observer],
) -> Result<RunResults> {
    let mut standard = dir
        .as_deref()
        .map(|d| writers::standard(d, input, p, restart.as_ref().map(|r| &r.0.checkpoint)));
    let mut read_only: Vec<ReadOnly<'_>> =
        observers.iter_mut().map(|o| ReadOnly(&mut **o)).collect();
    let mut all: Vec<&mut dyn Writer> = Vec::new();
    if let Some(s) = &mut standard {
        all.extend(s.writers());
    }
    all.extend(read_only.iter_mut().map(|o| o as &mut dyn Writer));
    let limits = Limits {
        max_increments: settings.max_increments,
        stop_when_separated: p.analysis.stop_when_separated,
        increment_limits: p.increment_limits.clone(),
    };
    let (mut ending, summary, log) = run_incremental(input, p, restart, limits, &mut all)?;
    let notes = standard.map(|s| s.prints.notes).unwrap_or_default();
    let warnings = std::mem::take(&mut ending.warnings);
    let status = ending.reason.status();
    let failure = failure_of(
        input,
        p,
        &log,
        dir.as_deref(),
        ending.failure,
        ending.interrupted,
    );
    Ok(RunResults {
        status,
        reason: ending.reason,
        status_line: ending.status,
        summary,
        rows: log.rows,
        output: dir,
        notes,
        warnings,
        failure,
        frame: None,
    })
}

/// The error a failed or interrupted run ends with.
fn failure_of(
    input: &Path,
    p: &Prepared,
    log: &RunLog,
    dir: Option<&Path>,
    failure: Option<junta_solvers::newton::NonlinearError>,
    interrupted: bool,
) -> Option<Error> {
    let where_ = dir.map_or("memory".to_string(), |d| d.display().to_string());
    if let Some(e) = failure {
        return Some(Error::from(e).context(format!(
            "{}: the run stopped; the {} converged increments are in {where_} (restart with `junta run --restart {where_}` after changing [analysis.newton]){}",
            input.display(),
            log.last_increment,
            past_peak_hint(
                &log.rows,
                p.model.matrix_kind(),
                p.analysis.control,
                p.analysis.nlgeom
            )
        )));
    }
    interrupted.then(|| err!("interrupted; the converged increments are in {where_}"))
}
