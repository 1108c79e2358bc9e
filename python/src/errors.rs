//! `celltissue.ScenarioError`: a `ValueError` carrying the message and the offending key of a
//! [`celltissue::scenario::ScenarioError`].

use pyo3::create_exception;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

create_exception!(
    celltissue,
    ScenarioError,
    PyValueError,
    "A scenario (or an override) that cannot be run as written. `.key` is the dotted key \
     (e.g. `\"model.K\"`, or None when the error names no key) and `.message` the full message \
     with the valid range."
);

/// A Python `ScenarioError` with `.key` and `.message`.
pub fn scenario_error(py: Python<'_>, key: Option<&str>, message: String) -> PyErr {
    let err = ScenarioError::new_err(message.clone());
    let value = err.value(py);
    // setting attributes on a fresh exception instance cannot fail short of memory exhaustion
    let _ = value.setattr("key", key);
    let _ = value.setattr("message", message);
    err
}

/// From the library's error.
pub fn from_scenario(py: Python<'_>, e: &celltissue::scenario::ScenarioError) -> PyErr {
    scenario_error(py, e.key_name(), e.to_string())
}
