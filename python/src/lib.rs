//! `junta._junta`: the native part of the `junta` Python package, over the
//! run API crate `junta` (see `pysrc/junta/__init__.py` for the Python
//! layer users import).
//!
//! | concern | module |
//! |---|---|
//! | read, check and run a simulation; results as numpy | [`simulation`] |
//! | `junta::Error` -> Python exceptions, panics | [`errors`] |
//! | traction laws written in Python | [`law`] |
//! | the registry as data (`junta.catalog()`) | [`catalog`] |
//! | Python <-> TOML / JSON / numpy | [`convert`] |

use pyo3::prelude::*;

mod catalog;
mod convert;
mod errors;
mod law;
mod simulation;

/// The native module.
#[pymodule]
fn _junta(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<simulation::PySimulation>()?;
    m.add_function(wrap_pyfunction!(catalog::list_plugins, m)?)?;
    m.add_function(wrap_pyfunction!(catalog::list_text, m)?)?;
    m.add_function(wrap_pyfunction!(law::register_law, m)?)?;
    m.add_function(wrap_pyfunction!(law::unregister_law, m)?)?;
    m.add_function(wrap_pyfunction!(law::evaluate_law, m)?)?;
    m.add_function(wrap_pyfunction!(law::evaluate_registered, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    // a dev-profile build (the benchmarks say so)
    m.add("debug_build", cfg!(debug_assertions))?;
    Ok(())
}
