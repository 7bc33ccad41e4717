//! Drivers: the linear static solve and the incremental nonlinear drivers
//! (load/displacement control, arc length, the switch between them). They
//! reach the linear back ends only through [`junta_core::LinearSolver`].
//!
//! | file | what |
//! |---|---|
//! | `linear_static.rs` | one assembly and one solve per load case |
//! | `vocabulary.rs` | the drivers' shared vocabulary: settings, observer protocol, reports, checkpoints and path state, errors |
//! | `engine.rs` | the Newton engine (`Work`): buffers, residual, one Newton attempt, line search, exact tangent |
//! | `newton.rs` | load/displacement control |
//! | `arc_length.rs` | path following through limit points and snap-backs |
//! | `arc_length_settings.rs` | path following's settings (`[analysis.arc_length]`): meaning, defaults, ranges |
//! | `balance.rs` | the energy balances of path following's dissipation constraint (global under small kinematics, the interfaces' under any) |
//! | `packed.rs` | a checkpoint's long vectors packed as base64 of their bytes |
//! | `path_switch.rs` | switching between load control and arc length (calls both drivers; neither calls it) |

pub mod arc_length;
mod arc_length_settings;
pub(crate) mod balance;
pub(crate) mod engine;
pub mod linear_static;
pub mod newton;
pub mod packed;
pub mod path_switch;
pub mod vocabulary;
