//! # junta-interface
//!
//! Zero-thickness interface elements between 3D solids and the traction
//! laws they use.
//!
//! - [`element`]: INTER8 / INTER16 / INTER18 (4+4, 8+8, 9+9 nodes; they match
//!   H8 / H20 / H27 faces and wedges' quadrilateral sides) and INTER6 /
//!   INTER12 (3+3, 6+6 nodes; the triangles of wedge6 / wedge15), one
//!   generic kernel over the face shape, with Gauss or Lobatto (nodal)
//!   integration. The paper's element is INTER18.
//! - [`law`]: traction-separation laws behind [`junta_core::InterfaceLaw`],
//!   one file each, registered with `inventory`: `linear_penalty` and
//!   `paper_debond` (the paper's), the fracture-energy laws `bilinear` and
//!   `exponential` (mixed mode, shared maths in [`law::cohesive`]) and
//!   `contact` (frictionless, for precracks).
//! - [`cohesive_zone`]: mesh advice for softening interfaces (cohesive-zone
//!   length, elements spanning it, Turon's strength reduction).
//! - [`advisor`]: the penalty advice on an assembled model: the paper's
//!   choice from its error analysis (eqs. 41-55) for constraint penalties,
//!   Turon's bound `K >= 50 E_33 / t` and a stiff limit for cohesive laws
//!   (each law says which it is: [`junta_core::InterfaceLaw::penalty_role`]).

#![warn(missing_docs)]

pub mod advisor;
pub mod cohesive_zone;
pub mod element;
pub mod law;

pub use advisor::{
    penalty_advice, penalty_advice_with, CohesivePenalty, CohesiveVerdict, PenaltyAdvice,
    PenaltyVerdict,
};
pub use cohesive_zone::{cohesive_zone_advice, CohesiveZoneAdvice, MeshVerdict};
pub use element::{InterfaceElement, InterfaceRule};
pub use law::linear_penalty::LinearPenalty;
