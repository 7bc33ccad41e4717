//! Drivers: the linear static solve and the incremental nonlinear drivers
//! (load/displacement control, arc length, the switch between them). They
//! reach the linear back ends only through [`junta_core::LinearSolver`].
//!
//! | file | what |
//! |---|---|
//! | `linear_static.rs` | one assembly and one solve per load case |
//! | `newton.rs` | the shared vocabulary, the Newton engine and load/displacement control |
//! | `arc_length.rs` | path following through limit points and snap-backs |
//! | `path_switch.rs` | switching between load control and arc length |

pub mod arc_length;
pub mod linear_static;
pub mod newton;
pub mod path_switch;
