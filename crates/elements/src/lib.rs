//! junta-elements (see crate docs)
