//! # junta-core
//!
//! The shared vocabulary of Junta: the mesh ([`mesh`]), cell topologies and
//! node orders ([`topology`]), the degree-of-freedom map with Dirichlet
//! conditions by elimination ([`dof`]), the plugin traits ([`Element`],
//! [`Material`], [`InterfaceLaw`], [`FailureCriterion`], [`PlyCriterion`], [`LinearSolver`]),
//! the plugin [`registry`] on `inventory`, integration-point [`state`]
//! storage, parallel [`assembly`] into a fixed sparsity pattern (with a
//! cache of the linear elements for incremental runs), the tangent
//! [`MatrixKind`] that laws declare, and forward-mode [`dual`] numbers for
//! exact law tangents.
//!
//! Dependencies point one way: every other Junta crate depends on this one,
//! and this one on none of them.

#![warn(missing_docs)]

pub use inventory;

pub mod assembly;
pub mod connectivity;
pub mod crack_drive;
pub mod criterion;
pub mod distributed;
pub mod dof;
pub mod dual;
pub mod element;
pub mod error;
pub mod law;
pub mod material;
pub mod mesh;
pub mod model;
pub mod ply_criterion;
pub mod registry;
pub mod solver;
pub mod sparse;
pub mod state;
pub mod step;
pub mod topology;

pub use criterion::{FailureCriterion, FailureMode, FailureResult, OnsetInput};
pub use dual::Dual3;
pub use element::{Element, ElementContext, ElementError, Kinematics, PointOutput};
pub use error::CoreError;
pub use law::{
    FractureProperties, InterfaceLaw, LawContext, LawError, LawResponse, PenaltyRole, PointStage,
};
pub use material::{Material, Voigt6};
pub use model::{FatigueProgram, Model};
pub use ply_criterion::{PlyCriterion, PlyCriterionEntry, PlyFailure, PlyFailureMode};
pub use solver::{
    EquationLayout, LinearSolver, MatrixKind, PrecomputedDissection, SolveReport, SolverError,
};
pub use sparse::SymmetricCsc;
pub use step::{CrackDrive, StepInfo};
