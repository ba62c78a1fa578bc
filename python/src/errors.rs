//! Library errors as Python exceptions: bad input (configuration, material,
//! surface, kernel, invalid values) is a `ValueError`, file trouble an
//! `OSError`, a solve that did not converge a
//! `viscoslide.ConvergenceError` (a `RuntimeError`) carrying its history,
//! anything else a `RuntimeError`. The message is the library's, one line
//! that says what to fix.

use pyo3::exceptions::{PyKeyboardInterrupt, PyOSError, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use viscoslide::problem::SolverError;
use viscoslide::Error;

/// A `ValueError` with the message of `e` (numbers written out in full
/// shown in scientific notation, [`Error::compact_numbers`]).
pub fn value_error(e: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(Error::compact_numbers(&e.to_string()))
}

/// The Python exception for a library error.
pub fn to_py(py: Python<'_>, e: Error) -> PyErr {
    let message = e.message();
    match e {
        Error::Solver(SolverError::NoConvergence {
            iterations,
            matvecs,
            residual,
            history,
            ..
        }) => convergence_error(py, message, history, iterations, matvecs, residual),
        Error::Solver(SolverError::Cancelled) => PyKeyboardInterrupt::new_err(message),
        Error::Io { .. } | Error::Output(_) => PyOSError::new_err(message),
        Error::Gpu(_) | Error::Plot(_) => PyRuntimeError::new_err(message),
        Error::Config(_)
        | Error::Material(_)
        | Error::Surface(_)
        | Error::Kernel(_)
        | Error::Response(_)
        | Error::Npy(_)
        | Error::Solver(_)
        | Error::Analysis(_)
        | Error::Persson(_)
        | Error::Heat(_)
        | Error::Invalid(_) => PyValueError::new_err(message),
    }
}

/// `viscoslide.ConvergenceError(message, history, iterations, matvecs,
/// residual)`, defined in Python (`viscoslide/errors.py`).
fn convergence_error(
    py: Python<'_>,
    message: String,
    history: Vec<f64>,
    iterations: usize,
    matvecs: usize,
    residual: f64,
) -> PyErr {
    let made = py
        .import("viscoslide.errors")
        .and_then(|m| m.getattr("ConvergenceError"))
        .and_then(|cls| cls.call1((message.clone(), history, iterations, matvecs, residual)));
    match made {
        Ok(instance) => PyErr::from_value(instance),
        Err(_) => PyRuntimeError::new_err(message),
    }
}
