//! One mapping from [`junta::Error`] to the Python exceptions of
//! `junta._errors` (pure Python classes, so that they can inherit from two
//! bases: `InputError(JuntaError, ValueError)`, `FileError(JuntaError,
//! OSError)`), and the guard that turns a Rust panic into
//! `JuntaError("internal error: ...")` instead of letting it cross into
//! Python.
//!
//! | `junta::Error` | Python |
//! |---|---|
//! | `is_input()` (a scene key, a deck line, a TOML syntax error) | `InputError` |
//! | an `io::Error` of kind `NotFound` | `FileNotFound` (a `FileError` and a `FileNotFoundError`) |
//! | another `io::Error` | `FileError` |
//! | anything else (a solver, a model that cannot be built) | `JuntaError` |
//!
//! The message is always [`junta::Error::chain`], what the command line
//! prints after `error: `.

use pyo3::prelude::*;
use std::panic::{catch_unwind, AssertUnwindSafe};

/// An instance of the exception class `name` of `junta._errors` with
/// `message` (or the error of importing it).
pub fn new_error(py: Python<'_>, name: &str, message: impl Into<String>) -> PyErr {
    let message = message.into();
    let made = py
        .import("junta._errors")
        .and_then(|m| m.getattr(name))
        .and_then(|cls| cls.call1((message,)));
    match made {
        Ok(v) => PyErr::from_value(v),
        Err(e) => e,
    }
}

/// `JuntaError(message)`.
pub fn junta_error(py: Python<'_>, message: impl Into<String>) -> PyErr {
    new_error(py, "JuntaError", message)
}

/// The kind of the `io::Error` at the bottom of `e`'s context chain, if
/// that is what it is.
fn io_kind(e: &junta::Error) -> Option<std::io::ErrorKind> {
    match e {
        junta::Error::Context { source, .. } => io_kind(source),
        junta::Error::Io(io) => Some(io.kind()),
        _ => None,
    }
}

/// The Python exception of a run-API error.
pub fn to_pyerr(py: Python<'_>, e: &junta::Error) -> PyErr {
    let message = e.chain();
    let class = if e.is_input() {
        "InputError"
    } else {
        match io_kind(e) {
            Some(std::io::ErrorKind::NotFound) => "FileNotFound",
            Some(_) => "FileError",
            None => "JuntaError",
        }
    };
    new_error(py, class, message)
}

/// The text of a panic's payload.
pub fn panic_message(payload: &(dyn std::any::Any + Send)) -> String {
    if let Some(s) = payload.downcast_ref::<&str>() {
        (*s).to_string()
    } else if let Some(s) = payload.downcast_ref::<String>() {
        s.clone()
    } else {
        "a panic without a message".to_string()
    }
}

/// Run `f`; a panic becomes `Err("internal error: ...")` (converted to
/// `JuntaError` by the caller, which holds the GIL).
pub fn guard<T>(f: impl FnOnce() -> T) -> Result<T, String> {
    catch_unwind(AssertUnwindSafe(f)).map_err(|p| {
        format!(
            "internal error (a bug in Junta, please report it with the input): {}",
            panic_message(&*p)
        )
    })
}

/// [`guard`] for code that holds the GIL and returns a `PyResult`.
pub fn guarded<T>(py: Python<'_>, f: impl FnOnce() -> PyResult<T>) -> PyResult<T> {
    match guard(f) {
        Ok(r) => r,
        Err(message) => Err(junta_error(py, message)),
    }
}

/// The type name and message of a Python exception: `ValueError: boom`.
pub fn describe(py: Python<'_>, e: &PyErr) -> String {
    let ty = e
        .get_type(py)
        .qualname()
        .map(|s| s.to_string())
        .unwrap_or_else(|_| "Exception".into());
    let msg = e.value(py).str().map(|s| s.to_string()).unwrap_or_default();
    if msg.is_empty() {
        ty
    } else {
        format!("{ty}: {msg}")
    }
}

/// Re-raise `original` (a Python exception from a law or a callback) with
/// `context` (the run's error, as a `JuntaError`) as its `__cause__`, so
/// that the traceback shows both and `except` sees the original type.
pub fn reraise_with_cause(py: Python<'_>, original: PyErr, context: Option<String>) -> PyErr {
    if let Some(c) = context {
        if original.cause(py).is_none() {
            original.set_cause(py, Some(junta_error(py, c)));
        }
    }
    original
}
