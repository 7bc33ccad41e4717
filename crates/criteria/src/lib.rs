//! junta-criteria (see crate docs)
