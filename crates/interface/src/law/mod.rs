//! Traction-separation laws, one file each. A law sees only the jump in
//! the local frame `[delta_1, delta_2, delta_3]` (two slips, opening) and
//! its own committed state; it returns the traction `[tau_13, tau_23,
//! sigma_33]` and the consistent tangent. Adding a law is one file here plus
//! its `inventory::submit!`.

pub mod linear_penalty;
pub mod paper_debond;
