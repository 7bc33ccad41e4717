//! # junta-solvers
//!
//! Linear solver back ends of Junta behind [`junta_core::LinearSolver`]
//! (`analyze` once per sparsity pattern, `factorize` per matrix,
//! `solve_in_place` per right-hand side), registered in the plugin registry:
//!
//! | key | type | what |
//! |---|---|---|
//! | `cholesky` | [`CholeskySolver`] | supernodal Cholesky (symbolic analysis on the graph of nodes, faer's dense kernels), nested-dissection or AMD ordering ([`ordering`]; by default the one with fewer predicted flops), double or mixed precision ([`Precision`]), iterative refinement, conditioning warnings |
//! | `ldlt` | [`LdltSolver`] | supernodal `L D L^T` for symmetric indefinite (softening) tangents: Bunch-Kaufman 1x1/2x2 pivoting within each panel on the same ordering and symbolic analysis as `cholesky`, inertia (`negative_pivots`) in the report, static perturbation of tiny pivots with iterative refinement |
//! | `lu` | [`LuSolver`] | supernodal `LU` with partial pivoting for general (nonsymmetric) tangents (friction, non-associated plasticity): faer's numeric LU on the ordering of the shared analysis, symbolic analysis reused, iterative refinement |
//! | `cg` | [`CgSolver`] | preconditioned conjugate gradients, Jacobi, 3×3 nodal block-Jacobi or smoothed-aggregation AMG ([`amg`]) with rigid-body modes per body |
//! | `minres` | [`MinresSolver`] | MINRES for symmetric indefinite tangents, `|diag(A)|` preconditioner |
//!
//! Nonlinear drivers: [`newton`] (incremental Newton-Raphson under load or
//! displacement control), [`arc_length`] (path following through limit
//! points and snap-backs: cylindrical arc length, then a dissipation
//! constraint once the laws dissipate) and [`path_switch`] (load control
//! that hands over to path following at limit points and back), plus
//! [`linear_static`].
//!
//! The two halves are two folders: [`linear`] (the back ends above and
//! their kernels; nothing there knows the drivers) and [`nonlinear`] (the
//! drivers). The nonlinear half reaches the linear one only through
//! [`junta_core::LinearSolver`]: the caller's back end, and for the exact
//! (nonsymmetric) tangent the registry's `lu` entry.
//!
//! | file | what it holds |
//! |---|---|
//! | `linear/cholesky.rs`, `ldlt.rs`, `lu.rs` | the direct back ends (keys `cholesky`, `ldlt`, `lu`) |
//! | `linear/supernodal.rs`, `panel_lu.rs` | the panel kernels of the factors |
//! | `linear/ordering.rs` | fill-reducing orderings |
//! | `linear/cg.rs`, `cg/gmres.rs`, `amg.rs`, `minres.rs` | the iterative back ends and the AMG preconditioner |
//! | `linear/common.rs`, `gallery.rs` | shared helpers, test matrices |
//! | `nonlinear/vocabulary.rs` | what the drivers share: settings, observer protocol, reports, checkpoints, path state, errors |
//! | `nonlinear/engine.rs` | the Newton engine (`Work`): residual, one Newton attempt, line search, exact tangent |
//! | `nonlinear/newton.rs` | load/displacement control |
//! | `nonlinear/arc_length.rs` | path following |
//! | `nonlinear/arc_length_settings.rs` | path following's settings (`junta_solvers::arc_length::ArcLengthSettings`) |
//! | `nonlinear/balance.rs` | the energy balances of the dissipation constraint (global; the interfaces' under large deformation) |
//! | `nonlinear/path_switch.rs` | load control with path following at limit points |
//! | `nonlinear/linear_static.rs` | the linear static solve |
//!
//! The drivers import `vocabulary` and `engine`, never each other (only
//! `path_switch` calls both). The old flat paths (`junta_solvers::lu`,
//! `junta_solvers::newton`, ...) are re-exported, and each driver
//! re-exports the shared types it used to define
//! (`junta_solvers::newton::Checkpoint`,
//! `junta_solvers::arc_length::PathState`, ...).
//!
//! Embedders can skip the registry:
//!
//! ```
//! use junta_core::LinearSolver;
//! use junta_solvers::{gallery, CholeskySolver};
//!
//! let (a, coords) = gallery::grid_3d(4, 4, 4, 3, gallery::Stencil::Point27);
//! let mut solver = CholeskySolver::new(Default::default());
//! solver.analyze(&a, Some(&coords))?;
//! solver.factorize(&a)?;
//! let mut x = vec![1.0; a.n];
//! solver.solve_in_place(&a, &mut x)?;
//! assert!(solver.report().residual < 1e-12);
//! # Ok::<(), junta_core::SolverError>(())
//! ```
//!
//! Failures are [`junta_core::SolverError`]s with their numbers (pivot,
//! iterations, residuals), never a silent NaN. A binary that looks solvers up
//! by key must reference this crate (`use junta_solvers as _;`) so that the
//! linker keeps the registrations.

#![warn(missing_docs)]

pub mod linear;
pub mod nonlinear;

// The crate's paths before the split (`junta_solvers::lu`, `junta_solvers::newton`, ...).
pub use linear::{amg, cg, cholesky, gallery, ldlt, lu, minres, ordering};
pub(crate) use linear::{common, panel_lu, supernodal, symbolic};
pub use nonlinear::{arc_length, linear_static, newton, path_switch, vocabulary};

pub use cg::{CgSettings, CgSolver, KrylovMethod, Preconditioner};
pub use cholesky::{CholeskySettings, CholeskySolver, CholeskyStats, Precision};
pub use ldlt::{LdltSettings, LdltSolver, LdltStats, ResidualCheck, UNCHECKED_GROWTH_LIMIT};
pub use lu::{LuPivoting, LuSettings, LuSolver};
pub use minres::{MinresSettings, MinresSolver};
pub use ordering::OrderingKind;
