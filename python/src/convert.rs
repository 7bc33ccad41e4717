//! Conversions between Python objects and the values the run API reads
//! (TOML values of overrides and law parameters), and the arrays and dicts
//! it hands back (numpy arrays moved from Rust vectors without a copy,
//! JSON values as Python objects).

use numpy::{PyArray1, PyArrayMethods};
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};

/// A Python value as a TOML value: bool, int, float, str, list/tuple (an
/// array), dict with str keys (a table).
pub fn py_to_toml(v: &Bound<'_, PyAny>, what: &str) -> PyResult<toml::Value> {
    if v.is_instance_of::<PyBool>() {
        return Ok(toml::Value::Boolean(v.extract::<bool>()?));
    }
    if v.is_instance_of::<PyInt>() {
        return Ok(toml::Value::Integer(v.extract::<i64>()?));
    }
    if v.is_instance_of::<PyFloat>() {
        return Ok(toml::Value::Float(v.extract::<f64>()?));
    }
    if v.is_instance_of::<PyString>() {
        return Ok(toml::Value::String(v.extract::<String>()?));
    }
    if v.is_instance_of::<PyList>() || v.is_instance_of::<PyTuple>() {
        let mut out = Vec::new();
        for x in v.try_iter()? {
            out.push(py_to_toml(&x?, what)?);
        }
        return Ok(toml::Value::Array(out));
    }
    if let Ok(d) = v.cast::<PyDict>() {
        let mut t = toml::Table::new();
        for (k, x) in d.iter() {
            let key: String = k.extract().map_err(|_| {
                PyTypeError::new_err(format!("{what}: table keys must be str, not {k}"))
            })?;
            t.insert(key, py_to_toml(&x, what)?);
        }
        return Ok(toml::Value::Table(t));
    }
    // numpy scalars and other numbers
    if let Ok(f) = v.call_method0("__float__") {
        if v.hasattr("dtype")? {
            let kind: String = v.getattr("dtype")?.getattr("kind")?.extract()?;
            if kind == "i" || kind == "u" {
                return Ok(toml::Value::Integer(v.call_method0("__int__")?.extract()?));
            }
            if kind == "b" {
                return Ok(toml::Value::Boolean(v.is_truthy()?));
            }
        }
        return Ok(toml::Value::Float(f.extract()?));
    }
    Err(PyTypeError::new_err(format!(
        "{what}: {} cannot be a scene value (use bool, int, float, str, list or dict)",
        v.get_type().qualname()?
    )))
}

/// A TOML value as a Python object.
pub fn toml_to_py<'py>(py: Python<'py>, v: &toml::Value) -> PyResult<Bound<'py, PyAny>> {
    Ok(match v {
        toml::Value::String(s) => PyString::new(py, s).into_any(),
        toml::Value::Integer(i) => i.into_pyobject(py)?.into_any(),
        toml::Value::Float(f) => PyFloat::new(py, *f).into_any(),
        toml::Value::Boolean(b) => PyBool::new(py, *b).to_owned().into_any(),
        toml::Value::Datetime(d) => PyString::new(py, &d.to_string()).into_any(),
        toml::Value::Array(a) => {
            let l = PyList::empty(py);
            for x in a {
                l.append(toml_to_py(py, x)?)?;
            }
            l.into_any()
        }
        toml::Value::Table(t) => toml_table_to_py(py, t)?.into_any(),
    })
}

/// A TOML table as a Python dict.
pub fn toml_table_to_py<'py>(py: Python<'py>, t: &toml::Table) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    for (k, x) in t {
        d.set_item(k, toml_to_py(py, x)?)?;
    }
    Ok(d)
}

/// A JSON value as a Python object (`json.loads` of its text, which keeps
/// every float to the last bit: serde_json writes the shortest
/// round-tripping representation).
pub fn json_to_py<'py>(py: Python<'py>, v: &serde_json::Value) -> PyResult<Bound<'py, PyAny>> {
    let text = serde_json::to_string(v)
        .map_err(|e| PyTypeError::new_err(format!("cannot write JSON: {e}")))?;
    py.import("json")?.call_method1("loads", (text,))
}

/// Any serializable value as a Python object, through JSON.
pub fn to_py<'py, T: serde::Serialize>(py: Python<'py>, v: &T) -> PyResult<Bound<'py, PyAny>> {
    let value = serde_json::to_value(v)
        .map_err(|e| PyTypeError::new_err(format!("cannot write JSON: {e}")))?;
    json_to_py(py, &value)
}

/// A numpy float64 array of shape `[len / cols, cols]` (or `[len]` when
/// `cols` is 0) that takes over `v` without copying it.
pub fn array<'py>(py: Python<'py>, v: Vec<f64>, cols: usize) -> PyResult<Bound<'py, PyAny>> {
    let a = PyArray1::from_vec(py, v);
    if cols == 0 {
        return Ok(a.into_any());
    }
    let rows = a.len()? / cols;
    Ok(a.reshape([rows, cols])?.into_any())
}

/// A numpy int64 array of shape `[len / cols, cols]` (or `[len]` when
/// `cols` is 0).
pub fn int_array<'py>(py: Python<'py>, v: Vec<i64>, cols: usize) -> PyResult<Bound<'py, PyAny>> {
    let a = PyArray1::from_vec(py, v);
    if cols == 0 {
        return Ok(a.into_any());
    }
    let rows = a.len()? / cols;
    Ok(a.reshape([rows, cols])?.into_any())
}
