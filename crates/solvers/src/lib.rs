//! junta-solvers (see crate docs)
