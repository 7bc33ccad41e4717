//! Run: the [`simulation::Simulation`] a front end drives, the linear and
//! incremental drivers, the observers that see each converged increment,
//! checkpoints and restart, and what a run returns ([`results`]).

pub mod checkpoint;
pub(crate) mod incremental;
pub(crate) mod linear;
pub(crate) mod observer;
pub(crate) mod results;
pub mod simulation;
