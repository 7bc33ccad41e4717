//! Output: file formats. VTU/PVD frames ([`vtu`]), `summary.json`'s
//! sections (`summary`), the writers a run registers as observers (curve,
//! frames, checkpoint, print tables, summary: `writers`), a deck's
//! `*NODE PRINT`/`*EL PRINT` tables (`deck_print`), SVG/PNG plots (`plot`)
//! and the Matrix Market export ([`export`]).

pub(crate) mod deck_print;
pub mod export;
pub(crate) mod plot;
pub(crate) mod summary;
pub mod vtu;
pub(crate) mod writers;
