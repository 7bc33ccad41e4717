//! Junta's run API: read a simulation from a file (a TOML scene, an
//! Abaqus/CalculiX deck, a scene with a Gmsh mesh) or build it in code,
//! check it, and run it with observers; results come back as typed values.
//!
//! ```no_run
//! use junta::{RunSettings, Simulation};
//! let sim = Simulation::from_file("examples/delamination/dcb.toml")?;
//! print!("{}", sim.check()?);
//! let results = sim.run(&RunSettings::into_dir("out/dcb"), &mut [])?;
//! let peak = results.curve.get("reaction").unwrap().iter().cloned().fold(0.0, f64::max);
//! println!("{}: peak {peak:.2} N", results.status_line);
//! # Ok::<(), junta::Error>(())
//! ```
//!
//! The stages of a run, each a module:
//!
//! | stage | module |
//! |---|---|
//! | read a scene / a deck / its print requests | [`scene`], [`validate`], [`deck`], [`deck_print`] |
//! | build the model, choose the solver | [`prepare`], [`auto`], [`limits`] |
//! | check it | [`check`] |
//! | diagnose a converged state (largest element rotation) | [`rotation`] |
//! | run it: linear, incremental | `linear`, [`incremental`] |
//! | report increments | [`observer`] ([`Observer`], [`Flow`], [`FrameCollector`]) |
//! | write files | [`writers`] (curve, frames, checkpoint, prints, summary), [`output`], [`plot`] |
//! | restart | [`checkpoint`], [`simulation::restart`] |
//! | results | [`curve`] ([`Curve`]), [`frame`] ([`Frame`]), [`RunResults`] |
//! | studies | [`sweep`], [`sweep_control`] |
//! | the registry as data | [`catalog`] |
//!
//! Nothing here prints: messages are values ([`RunResults::notes`],
//! [`CheckReport`]) and progress goes to observers and `tracing`.

#![warn(missing_docs)]

// Keep every plugin crate linked so that its `inventory` registrations exist.
use junta_criteria as _;
use junta_elements as _;
use junta_interface as _;
use junta_solvers as _;

pub mod error;
pub use error::{Context, Error, Result};

pub mod auto;
pub mod bending;
pub mod catalog;
pub mod check;
pub mod checkpoint;
pub mod crack;
pub mod curve;
pub mod deck;
pub mod deck_print;
pub mod export;
pub mod frame;
pub mod incremental;
pub mod limits;
mod linear;
pub mod observer;
pub mod output;
pub mod plot;
pub mod prepare;
pub mod readers;
pub mod results;
pub mod rotation;
pub mod scene;
pub mod simulation;
pub mod sweep;
pub mod sweep_control;
pub mod validate;
pub mod writers;

pub use check::CheckReport;
pub use curve::{Curve, CurveRow};
pub use frame::Frame;
pub use observer::{Flow, FnObserver, FrameCollector, Increment, Observer, RunEnd, RunLog};
pub use simulation::{Options, RunResults, RunSettings, Simulation, Status};

/// The crates underneath, for code that builds models by hand.
pub use junta_core as core;
pub use junta_elements as elements;
pub use junta_interface as interface;
pub use junta_solvers as solvers;
