//! Rust errors as Python `ValueError`s whose message starts with the Python argument's name.

use std::fmt::Display;

use pyo3::PyErr;
use pyo3::exceptions::PyValueError;

/// A `ValueError` for `argument`: "`argument`: what is wrong".
pub(crate) fn value_error(argument: &str, error: impl Display) -> PyErr {
    PyValueError::new_err(format!("{argument}: {error}"))
}
