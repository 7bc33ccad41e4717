//! `junta`: run TOML scenes or Abaqus/CalculiX decks, check them, list plugins.
//!
//! A thin consumer of the run API (the `junta` crate): arguments, the
//! progress bar, messages. The `junta` binary is
//! `fn main() -> ExitCode { junta_cli::main() }`. A researcher's own crate can
//! register laws, criteria or elements with `inventory::submit!` and build its
//! own `junta` the same way (see `examples/plugin_law/`).
//!
//! ```text
//! junta run <scene.toml | deck.inp> [-o DIR]   solve and write DIR/summary.json, DIR/results.vtu
//! junta check <scene.toml | deck.inp> [-v]     validate and print a model summary, no solve
//! junta list                                   every registered plugin with its parameters
//! ```

// Keep every plugin crate linked so that its `inventory` registrations exist.
use junta_criteria as _;
use junta_elements as _;
use junta_interface as _;
use junta_solvers as _;

mod progress;
mod report;

use anyhow::Result;
use junta::output::export;
use junta::study::{sweep, sweep_control};
use junta::{Options, RunResults, RunSettings, Simulation};
use std::path::Path;

use clap::{Parser, Subcommand};
use std::path::PathBuf;
use std::process::ExitCode;

/// Junta: solids joined by interfaces.
#[derive(Parser)]
#[command(name = "junta", version, about, long_about = None)]
struct Cli {
    /// More log output (-v info, -vv debug).
    #[arg(short, long, action = clap::ArgAction::Count, global = true)]
    verbose: u8,
    /// No progress bar.
    #[arg(short, long, global = true)]
    quiet: bool,
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Solve a scene (.toml) or an Abaqus/CalculiX deck (.inp).
    Run {
        /// Scene or deck file (not with --restart).
        #[arg(required_unless_present = "restart")]
        input: Option<PathBuf>,
        /// Output directory (default: the scene's [output] directory, else out/NAME (the input file stem)).
        #[arg(short, long)]
        output: Option<PathBuf>,
        /// Continue the incremental run whose output directory is DIR from its
        /// last converged increment.
        #[arg(long, value_name = "DIR", conflicts_with = "input")]
        restart: Option<PathBuf>,
        /// With --restart: continue although the scene or a file it reads
        /// changed since the run stopped (the changes are listed).
        #[arg(long, requires = "restart")]
        allow_edited: bool,
        /// Incremental runs: stop after this many increments (a restart point is kept).
        #[arg(long)]
        max_increments: Option<usize>,
        /// Override a solver parameter of the scene or deck (repeatable), e.g.
        /// `--solver precision=double`, `--solver type=cg` (see `junta list`).
        /// A restart reuses the overrides of the run it continues.
        #[arg(long = "solver", value_name = "KEY=VALUE", conflicts_with = "restart")]
        solver: Vec<String>,
        /// Also write the assembled stiffness (free dofs), load vector and
        /// near-null space (rigid-body modes) in Matrix Market format into DIR.
        #[arg(long, value_name = "DIR", conflicts_with = "restart")]
        export_matrix: Option<PathBuf>,
    },
    /// Validate a scene or deck and print a model summary without solving
    /// (the named sets summarised; with --verbose all of them).
    Check {
        /// Scene or deck file.
        input: PathBuf,
    },
    /// List every registered element, material, law, criterion and solver.
    List {
        /// Print the catalogue as Markdown (docs/parameters.md).
        #[arg(long)]
        markdown: bool,
    },
    /// Run a scene over a range of a parameter and chart accuracy and speed.
    Sweep {
        #[command(subcommand)]
        what: SweepKind,
    },
}

#[derive(Subcommand)]
enum SweepKind {
    /// Penalty stiffness d of every `linear_penalty` law, log-spaced; direct
    /// and CG back ends; writes sweep.csv and sweep.svg.
    Penalty {
        /// Scene file (.toml) with at least one interface.
        input: PathBuf,
        /// Smallest d.
        #[arg(long, default_value_t = 1e12)]
        from: f64,
        /// Largest d.
        #[arg(long, default_value_t = 1e30)]
        to: f64,
        /// Values per decade.
        #[arg(long, default_value_t = 1)]
        per_decade: usize,
        /// Output directory (default out/NAME-sweep).
        #[arg(short, long)]
        output: Option<PathBuf>,
    },
    /// One incremental scene under arc length, displacement control and
    /// load control: where each method stops and why (control.csv,
    /// control_summary.csv, control.svg).
    Control {
        /// Scene file (.toml), `[analysis] type = "static"` with an
        /// `[output] curve`.
        input: PathBuf,
        /// Output directory (default out/NAME-control).
        #[arg(short, long)]
        output: Option<PathBuf>,
    },
    /// Gauss against Lobatto (nodal) integration of every interface: the
    /// normal traction along an axis (traction.csv, traction.svg).
    Integration {
        /// Scene file (.toml) with at least one interface.
        input: PathBuf,
        /// Penalty values to run (comma separated); default: the scene's.
        #[arg(long, value_delimiter = ',')]
        d: Vec<f64>,
        /// Axis along which to plot: x, y or z.
        #[arg(long, default_value = "y")]
        axis: String,
        /// Output directory (default out/NAME-integration).
        #[arg(short, long)]
        output: Option<PathBuf>,
    },
}

/// The log level (`-v` counts; a rank that does not write logs errors
/// only) and rayon's global pool. The drivers run on that pool
/// (`Simulation::run`): its threads get a main thread's stack (8 MiB), not
/// rayon's 2 MiB. Called after the MPI session starts, which sets each
/// rank's thread count.
fn set_up_process(verbose: u8, writer: bool) {
    let level = match (verbose, writer) {
        (_, false) => "error",
        (0, _) => "warn",
        (1, _) => "info",
        _ => "debug",
    };
    tracing_subscriber::fmt()
        .with_env_filter(
            tracing_subscriber::EnvFilter::try_from_default_env().unwrap_or_else(|_| {
                tracing_subscriber::EnvFilter::new(format!("{level},junta_solvers=error"))
            }),
        )
        .with_writer(std::io::stderr)
        .init();
    rayon::ThreadPoolBuilder::new()
        .stack_size(8 << 20)
        .build_global()
        .ok();
}

/// Parse the command line, run it, and map the outcome to an exit code.
pub fn main() -> ExitCode {
    let cli = Cli::parse();
    #[cfg(feature = "mpi")]
    let session = match junta_mpi::Session::start_if_launched() {
        Ok(s) => s,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::FAILURE;
        }
    };
    #[cfg(feature = "mpi")]
    let writer = session.as_ref().is_none_or(junta_mpi::Session::is_root);
    #[cfg(not(feature = "mpi"))]
    let writer = true;
    set_up_process(cli.verbose, writer);
    #[cfg(feature = "mpi")]
    if session.is_some() && !matches!(cli.command, Command::Run { .. }) {
        junta_mpi::abort_all(
            "under mpirun only `junta run` is distributed; run the other commands in one process",
        );
    }
    let progress = !cli.quiet && writer;
    let result = match cli.command {
        Command::Run {
            input,
            output,
            restart,
            max_increments,
            solver,
            allow_edited,
            export_matrix,
        } => match (input, restart) {
            (_, Some(dir)) => restart_run(&dir, progress, writer, max_increments, allow_edited),
            (Some(input), None) => run(
                &input,
                output.as_deref(),
                (progress, writer),
                max_increments,
                solver,
                export_matrix.as_deref(),
            ),
            (None, None) => Err(anyhow::anyhow!("give a scene or --restart DIR")),
        },
        Command::Check { input } => Simulation::from_file(&input)
            .and_then(|sim| sim.check())
            .map(|report| {
                if cli.verbose > 0 {
                    print!("{}", report.verbose());
                } else {
                    print!("{report}");
                }
            })
            .map_err(anyhow::Error::from),
        Command::List { markdown } => {
            if markdown {
                print!("{}", junta::catalog::markdown());
            } else {
                print!("{}", junta::catalog::text());
            }
            Ok(())
        }
        Command::Sweep {
            what:
                SweepKind::Penalty {
                    input,
                    from,
                    to,
                    per_decade,
                    output,
                },
        } => {
            let out = output.unwrap_or_else(|| junta::prepare::default_dir(&input, "-sweep"));
            sweep::sweep_penalty(&input, from, to, per_decade, &out)
                .map_err(anyhow::Error::from)
                .map(|rows| {
                    report::sweep(&rows);
                    println!(
                        "wrote {}/sweep.csv and {}/sweep.svg",
                        out.display(),
                        out.display()
                    );
                })
        }
        Command::Sweep {
            what: SweepKind::Control { input, output },
        } => {
            let out = output.unwrap_or_else(|| junta::prepare::default_dir(&input, "-control"));
            sweep_control::sweep_control(&input, &out)
                .map_err(anyhow::Error::from)
                .map(|runs| {
                    report::control(&runs);
                    println!(
                        "wrote {}/control.csv, control_summary.csv and control.svg",
                        out.display()
                    );
                })
        }
        Command::Sweep {
            what:
                SweepKind::Integration {
                    input,
                    d,
                    axis,
                    output,
                },
        } => {
            let out = output.unwrap_or_else(|| junta::prepare::default_dir(&input, "-integration"));
            match ["x", "y", "z"].iter().position(|a| *a == axis) {
                None => Err(anyhow::anyhow!("--axis {axis}: use x, y or z")),
                Some(ax) => sweep::sweep_integration(&input, &d, ax, &out).map_err(anyhow::Error::from).map(|profiles| {
                    for p in &profiles {
                        println!(
                            "d = {:>9} {:>8}: {} points, roughness {:.3}, {} local extrema, t_n in [{:.4e}, {:.4e}]",
                            p.d.map(|v| format!("{v:.1e}")).unwrap_or("scene".into()),
                            p.rule,
                            p.points.len(),
                            p.roughness,
                            p.extrema,
                            p.points.iter().map(|q| q.1).fold(f64::INFINITY, f64::min),
                            p.points.iter().map(|q| q.1).fold(f64::NEG_INFINITY, f64::max)
                        );
                    }
                    println!("wrote {}/traction.csv and {}/traction.svg", out.display(), out.display());
                }),
            }
        }
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        #[cfg(feature = "mpi")]
        Err(e) if session.is_some() => end_all_ranks(writer, &format!("{e:#}")),
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}

/// An error on this rank of a run over MPI ends every rank
/// (`MPI_Abort`), so that none is left waiting in a collective. Rank 0
/// reports at once; another rank waits two seconds first, so that an error
/// every rank met (bad input) is reported once, by rank 0, whose abort
/// ends the others.
#[cfg(feature = "mpi")]
fn end_all_ranks(root: bool, message: &str) -> ExitCode {
    if !root {
        std::thread::sleep(std::time::Duration::from_secs(2));
    }
    junta_mpi::abort_all(message)
}

/// `junta run INPUT`.
///
/// `(progress, writer)`: show progress; write the files and the result
/// lines (false on the ranks of a run over MPI other than rank 0, which
/// compute alike and write nothing).
fn run(
    input: &Path,
    output: Option<&Path>,
    (progress, writer): (bool, bool),
    max_increments: Option<usize>,
    solver: Vec<String>,
    export_matrix: Option<&Path>,
) -> Result<()> {
    let mut bar = progress::Progress::new(progress, format!("reading {}", input.display()));
    let options = Options {
        solver,
        overrides: Vec::new(),
    };
    let sim = Simulation::from_file_with(input, options)?;
    if let (Some(dir), true) = (export_matrix, writer) {
        export::export_matrix(sim.model(), dir)?;
    }
    // a linear run's notes come before its solve
    let shown = if sim.is_incremental() || !writer {
        0
    } else {
        for n in sim.notes() {
            bar.suspend(|| eprintln!("note: {n}"));
        }
        sim.notes().len()
    };
    let dir = output.map_or_else(|| sim.default_output(), Path::to_path_buf);
    let settings = RunSettings {
        output: writer.then_some(dir),
        max_increments,
        without_end_frame: true,
        ..RunSettings::default()
    };
    let results = sim.run(&settings, &mut [&mut bar])?;
    bar.finish();
    finish(input, &results, shown, writer)
}

/// `junta run --restart DIR`.
fn restart_run(
    dir: &Path,
    progress: bool,
    writer: bool,
    max_increments: Option<usize>,
    allow_edited: bool,
) -> Result<()> {
    let Some(restart) = junta::run::simulation::read_checkpoint(dir, allow_edited)? else {
        if writer {
            println!("{}", junta::run::simulation::finished_message(dir)?);
        }
        return Ok(());
    };
    for change in restart.edits.iter().filter(|_| writer) {
        eprintln!("note: continuing with an edited input (--allow-edited): {change}");
    }
    let shown = restart.edits.len();
    let input = restart.file.input.clone();
    let mut bar = progress::Progress::new(
        progress,
        format!(
            "restarting {} from increment {}",
            input.display(),
            restart.file.checkpoint.increment_index
        ),
    );
    let settings = RunSettings {
        output: writer.then(|| dir.to_path_buf()),
        max_increments,
        without_end_frame: true,
        ..RunSettings::default()
    };
    let results = junta::run::simulation::restart(dir, restart, &settings, &mut [&mut bar])?;
    bar.finish();
    finish(&input, &results, shown, writer)
}

/// Print a run's notes (past the first `shown`), warnings and result line
/// (when `writer`); the run's failure is the command's error.
fn finish(input: &Path, r: &RunResults, shown: usize, writer: bool) -> Result<()> {
    if !writer {
        return match &r.failure {
            Some(e) => Err(anyhow::anyhow!("{}", e.chain())),
            None => Ok(()),
        };
    }
    for n in r.notes.iter().skip(shown) {
        eprintln!("note: {n}");
    }
    for w in &r.warnings {
        eprintln!("warning: {w}");
    }
    let s = &r.summary;
    let dir = r.output.as_deref().unwrap_or(Path::new("."));
    if r.rows.is_empty() && s.analysis == junta::SummaryAnalysis::LinearStatic {
        println!(
            "{}: {} equations, max |u| = {:.6e}, total {:.2} s -> {}",
            input.display(),
            s.equations,
            s.displacement_max.unwrap_or(0.0),
            s.timings.map_or(0.0, |t| t.total),
            dir.display()
        );
        if let Some(obj) = s["reactions"].as_object() {
            for (k, v) in obj {
                println!("  reaction on {k}: {v}");
            }
        }
    } else {
        println!(
            "{}: {}; {} increments, {} Newton iterations, load factor {:.6} -> {}",
            input.display(),
            r.status_line,
            s.increments.unwrap_or(0),
            s.newton_iterations.as_ref().map_or(0, |n| n.total),
            s["load_factor"].as_f64().unwrap_or(0.0),
            dir.display()
        );
    }
    match &r.failure {
        Some(e) => Err(anyhow::anyhow!("{}", e.chain())),
        None => Ok(()),
    }
}
