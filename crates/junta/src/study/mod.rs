//! Studies: many runs of one model. Every linear solver on one scene
//! ([`sweep`]) and every incremental control on one scene
//! ([`sweep_control`]).

pub mod sweep;
pub mod sweep_control;
