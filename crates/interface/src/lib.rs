//! junta-interface (see crate docs)
