//! Post-processing: quantities of a converged state. The fields the
//! writers and observers read ([`fields`]), the curve row (`curve`) and the table of its columns ([`curve_columns`]), the
//! typed frame (`frame`), the crack front ([`crack`]), the generalized reactions under
//! `*EQUATION`s (`constraint_force`), the largest element
//! rotation ([`rotation`]) the ply failure indices ([`ply_failure`]) and their course through an
//! incremental run ([`ply_failure_history`]).

pub(crate) mod constraint_force;
pub mod crack;
pub(crate) mod curve;
pub mod curve_columns;
pub mod fields;
pub(crate) mod frame;
pub mod ply_failure;
pub mod ply_failure_history;
pub mod rotation;
