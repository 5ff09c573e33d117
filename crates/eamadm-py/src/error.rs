//! Rust errors and panics as Python exceptions: `ValueError`s and `TypeError`s whose message
//! starts with the Python argument's name, `FileNotFoundError`s naming the path, and a
//! `RuntimeError` for a panic (a bug), so that no panic reaches Python as pyo3's
//! `PanicException` (a `BaseException` that `except Exception` does not catch).

use std::any::Any;
use std::fmt::Display;
use std::panic::{AssertUnwindSafe, catch_unwind};

use pyo3::PyErr;
use pyo3::PyResult;
use pyo3::exceptions::{PyFileNotFoundError, PyRuntimeError, PyTypeError, PyValueError};

/// A `ValueError` for `argument`: "`argument`: what is wrong".
pub(crate) fn value_error(argument: &str, error: impl Display) -> PyErr {
    PyValueError::new_err(format!("{argument}: {error}"))
}

/// A `TypeError` for `argument`: "`argument`: what was expected".
pub(crate) fn type_error(argument: &str, error: impl Display) -> PyErr {
    PyTypeError::new_err(format!("{argument}: {error}"))
}

/// A `FileNotFoundError` for `argument`: "`argument`: what is missing".
pub(crate) fn not_found(argument: &str, error: impl Display) -> PyErr {
    PyFileNotFoundError::new_err(format!("{argument}: {error}"))
}

/// The text of a panic's payload.
pub(crate) fn panic_message(payload: &(dyn Any + Send)) -> String {
    payload
        .downcast_ref::<&str>()
        .map(|text| (*text).to_owned())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "(no message)".to_owned())
}

/// The `RuntimeError` of a panic in `what`.
pub(crate) fn internal_error(what: &str, payload: &(dyn Any + Send)) -> PyErr {
    PyRuntimeError::new_err(format!(
        "{what}: internal error (a bug of eamadm, please report it): {}",
        panic_message(payload)
    ))
}

/// Runs `body`, turning a panic into a `RuntimeError` naming `what` (every entry point of the
/// module goes through this).
pub(crate) fn guard<T>(what: &str, body: impl FnOnce() -> PyResult<T>) -> PyResult<T> {
    catch_unwind(AssertUnwindSafe(body))
        .unwrap_or_else(|payload| Err(internal_error(what, &*payload)))
}
