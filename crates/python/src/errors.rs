//! How navkf's errors reach Python: every Rust error becomes a `navkf.NavkfError` (a
//! `ValueError`, so `except ValueError` also catches bad settings) carrying the same located
//! message the command line prints (file, line and column, or the setting's key). A stop on
//! Ctrl-C is a `KeyboardInterrupt`.

use pyo3::exceptions::{PyKeyboardInterrupt, PyValueError};
use pyo3::prelude::*;

pyo3::create_exception!(
    _navkf,
    NavkfError,
    PyValueError,
    "An error of navkf's: bad input, a setting it refuses, a file it cannot read or write. \
     The message names the file, line and column (or the setting) and what was expected."
);

/// `e` as a `navkf.NavkfError`.
pub fn to_py<E: std::fmt::Display + ?Sized>(e: &E) -> PyErr {
    NavkfError::new_err(e.to_string())
}

/// The error of a call stopped by Ctrl-C, with what it had done.
pub fn interrupted(message: String) -> PyErr {
    PyKeyboardInterrupt::new_err(message)
}

/// `Result<T, E>` into `PyResult<T>` with [`to_py`].
pub trait OrNavkfError<T> {
    fn or_py(self) -> PyResult<T>;
}

impl<T, E: std::fmt::Display> OrNavkfError<T> for Result<T, E> {
    fn or_py(self) -> PyResult<T> {
        self.map_err(|e| to_py(&e))
    }
}
