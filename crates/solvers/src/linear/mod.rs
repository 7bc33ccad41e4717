//! Linear back ends: everything behind [`junta_core::LinearSolver`].
//!
//! | file | what |
//! |---|---|
//! | `cholesky.rs` | supernodal Cholesky (SPD), key `cholesky` |
//! | `ldlt.rs` | supernodal `L D L^T` with Bunch-Kaufman pivoting (symmetric indefinite), key `ldlt` |
//! | `lu.rs` | supernodal LU with partial pivoting (general), key `lu` |
//! | `panel_lu.rs` | the LU's dense panel kernel |
//! | `supernodal.rs` | the symbolic analysis and panel storage the three factors share |
//! | `symbolic.rs` | the supernodal symbolic factorisation on the quotient graph of equation groups |
//! | `ordering.rs` | fill-reducing orderings (nested dissection, AMD) and fill estimates |
//! | `cg.rs`, `cg/gmres.rs` | preconditioned CG and GMRES, key `cg` |
//! | `amg.rs` | smoothed-aggregation AMG preconditioner |
//! | `minres.rs` | MINRES, key `minres` |
//! | `gallery.rs` | test matrices (grid Laplacians and elasticity stencils) |
//! | `common.rs` | shared CSR helpers, norms, validation |
//!
//! Nothing here knows the nonlinear drivers.

pub mod amg;
pub mod cg;
pub mod cholesky;
pub(crate) mod common;
pub mod gallery;
pub mod ldlt;
pub mod lu;
pub mod minres;
pub mod ordering;
pub(crate) mod panel_lu;
pub(crate) mod supernodal;
pub(crate) mod symbolic;
