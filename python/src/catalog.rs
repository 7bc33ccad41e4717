//! `junta.catalog()`: the registry as data (what `junta list` prints), with
//! the laws registered at run time (from Python) in the interface-law
//! section.

use crate::convert::to_py;
use junta::catalog::catalog;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

/// Every registered plugin by section: `[{title, plugins: [{key,
/// description, params: [{name, doc}]}]}]`; laws registered from Python
/// carry `"runtime": True`.
#[pyfunction(name = "catalog")]
pub fn list_plugins(py: Python<'_>) -> PyResult<Bound<'_, PyAny>> {
    crate::errors::guarded(py, || sections(py))
}

fn sections(py: Python<'_>) -> PyResult<Bound<'_, PyAny>> {
    let sections = to_py(py, &catalog())?;
    let runtime = junta_core::registry::runtime_laws();
    let params = crate::law::law_params();
    let list = sections.cast::<PyList>()?;
    for sec in list.iter() {
        let sec = sec.cast::<PyDict>()?.clone();
        let title: String = sec
            .get_item("title")?
            .map(|t| t.extract())
            .transpose()?
            .unwrap_or_default();
        let plugins = sec.get_item("plugins")?;
        for p in plugins.iter() {
            p.cast::<PyList>()?
                .iter()
                .try_for_each(|q| q.cast::<PyDict>()?.set_item("runtime", false))?;
        }
        if title != "interface laws" {
            continue;
        }
        let Some(plugins) = plugins else { continue };
        let plugins = plugins.cast::<PyList>()?;
        for law in &runtime {
            let d = PyDict::new(py);
            d.set_item("key", &law.key)?;
            d.set_item("description", &law.description)?;
            let ps = PyList::empty(py);
            for (name, doc) in params.get(&law.key).cloned().unwrap_or_default() {
                let q = PyDict::new(py);
                q.set_item("name", name)?;
                q.set_item("doc", doc)?;
                ps.append(q)?;
            }
            d.set_item("params", ps)?;
            d.set_item("runtime", true)?;
            plugins.append(d)?;
        }
    }
    Ok(sections)
}

/// What `junta list` prints (compiled plugins only).
#[pyfunction]
pub fn list_text() -> String {
    junta::catalog::text()
}
