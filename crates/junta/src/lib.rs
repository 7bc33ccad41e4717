//! Junta's run API: read a simulation from a file (a TOML scene, an
//! Abaqus/CalculiX deck, a scene with a Gmsh mesh) or build it in code,
//! check it, and run it with observers; results come back as typed values.
//!
//! ```no_run
//! use junta::{RunSettings, Simulation};
//! let sim = Simulation::from_file("examples/delamination/dcb.toml")?;
//! print!("{}", sim.check()?);
//! let results = sim.run(&RunSettings::into_dir("out/dcb"), &mut [])?;
//! let peak = results.curve().get("reaction").unwrap().iter().cloned().fold(0.0, f64::max);
//! println!("{}: peak {peak:.2} N", results.status_line);
//! # Ok::<(), junta::Error>(())
//! ```
//!
//! The stages of a run, each a folder:
//!
//! | stage | folder | what it holds |
//! |---|---|---|
//! | input | [`input`] | the TOML scene ([`input::scene`], its validation), the Abaqus/CalculiX deck ([`input::inp`]) and the model built from it ([`input::deck`]), Gmsh meshes ([`input::gmsh`]) |
//! | prepare | [`prepare`] | the model and its run settings ([`prepare::Prepared`]), the solver choice ([`prepare::auto`]), memory limits, the check ([`CheckReport`]), the bending advisor ([`prepare::bending`]) |
//! | run | [`run`] | the linear and incremental drivers, observers ([`Observer`], [`Flow`], [`FrameCollector`]), checkpoints and restart ([`run::simulation::restart`]), the [`Simulation`] and its [`RunResults`] |
//! | post | [`post`] | quantities of a converged state: the fields ([`post::fields`]), the curve row ([`Curve`]), the frame ([`Frame`]), the crack front ([`post::crack`]), the largest rotation ([`post::rotation`]) |
//! | output | [`output`] | file formats: VTU/PVD ([`output::vtu`]), `summary.json`'s sections, curve/frame/checkpoint writers, a deck's print tables, plots, the matrix export ([`output::export`]) |
//! | study | [`study`] | sweeps over solvers ([`study::sweep`]) and over controls ([`study::sweep_control`]) |
//!
//! Beside them: the registry as data ([`catalog`]) and the error type
//! ([`Error`]). `docs/contributing.md` maps where new code goes.
//!
//! Nothing here prints: messages are values ([`RunResults::notes`],
//! [`CheckReport`]) and progress goes to observers and `tracing`.

#![warn(missing_docs)]

// Keep every plugin crate linked so that its `inventory` registrations exist.
use junta_criteria as _;
use junta_elements as _;
use junta_interface as _;
use junta_solvers as _;

mod error;
pub use error::{Context, Error, Result};

pub mod catalog;
pub mod input;
pub mod output;
pub mod post;
pub mod prepare;
pub mod run;
pub mod study;

pub use input::scene::AnalysisKind;
pub use post::curve::{Curve, CurveRow};
pub use post::curve_columns::{curve_header, Cell, CurveColumn, CURVE_COLUMNS};
pub use post::frame::{Frame, SolidPoints};
pub use prepare::check::{BlockReport, CheckReport, StepReport};
pub use run::checkpoint::FirstFailure;
pub use run::observer::{
    Flow, FnObserver, FrameCollector, Increment, Observer, Phase, RunEnd, RunInfo, RunLog,
};
pub use run::results::{
    CrackSummary, DriverSummary, EnergySummary, IterationSummary, Summary, SummaryAnalysis, Timings,
};
pub use run::simulation::{EndReason, Options, RunResults, RunSettings, Simulation, Status};

/// The crates underneath, for code that builds models by hand.
pub use junta_core as core;
pub use junta_elements as elements;
pub use junta_interface as interface;
pub use junta_solvers as solvers;
