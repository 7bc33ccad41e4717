//! `junta`: run TOML scenes or Abaqus/CalculiX decks, check them, list plugins.
//!
//! The whole command line lives in this library; the `junta` binary is
//! `fn main() -> ExitCode { junta_cli::main() }`. A researcher's own crate can
//! register laws, criteria or elements with `inventory::submit!` and build its
//! own `junta` the same way (see `examples/plugin_law/`).
//!
//! ```text
//! junta run <scene.toml | deck.inp> [-o DIR]   solve and write DIR/summary.json, DIR/results.vtu
//! junta check <scene.toml | deck.inp>          validate and print a model summary, no solve
//! junta list                                   every registered plugin with its parameters
//! ```

// Keep every plugin crate linked so that its `inventory` registrations exist.
use junta_criteria as _;
use junta_elements as _;
use junta_interface as _;
use junta_solvers as _;

mod auto;
mod deck;
mod deck_print;
mod export;
mod limits;
mod nonlinear;
mod output;
mod plot;
mod restart_guard;
mod run;
mod scene;
mod sweep;
mod sweep_control;
mod validate;

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
    /// Validate a scene or deck and print a model summary without solving.
    Check {
        /// Scene or deck file.
        input: PathBuf,
    },
    /// List every registered element, material, law, criterion and solver.
    List,
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

/// Parse the command line, run it, and map the outcome to an exit code.
pub fn main() -> ExitCode {
    let cli = Cli::parse();
    let level = match cli.verbose {
        0 => "warn",
        1 => "info",
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
            (_, Some(dir)) => run::restart(&dir, !cli.quiet, max_increments, allow_edited),
            (Some(input), None) => export_matrix
                .map_or(Ok(()), |dir| {
                    export::export_matrix(&run::prepare(&input, &solver)?.model, &dir)
                })
                .and_then(|()| {
                    run::run(
                        &input,
                        output.as_deref(),
                        !cli.quiet,
                        max_increments,
                        &solver,
                    )
                }),
            (None, None) => Err(anyhow::anyhow!("give a scene or --restart DIR")),
        },
        Command::Check { input } => run::check(&input),
        Command::List => {
            run::list();
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
            let out = output.unwrap_or_else(|| run::default_dir(&input, "-sweep"));
            sweep::sweep_penalty(&input, from, to, per_decade, &out).map(|rows| {
                sweep::report(&rows);
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
            let out = output.unwrap_or_else(|| run::default_dir(&input, "-control"));
            sweep_control::sweep_control(&input, &out).map(|runs| {
                sweep_control::report(&runs);
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
            let out = output.unwrap_or_else(|| run::default_dir(&input, "-integration"));
            match ["x", "y", "z"].iter().position(|a| *a == axis) {
                None => Err(anyhow::anyhow!("--axis {axis}: use x, y or z")),
                Some(ax) => sweep::sweep_integration(&input, &d, ax, &out).map(|profiles| {
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
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}
