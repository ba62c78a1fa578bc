//! The observer of a solve run with the GIL released: it reports each
//! outer iteration (and the heated solve's stage it belongs to) to an
//! optional Python callable and polls Python's signal
//! handlers (Ctrl-C) every [`POLL`], stopping the solve through
//! [`Observer::cancelled`] when a handler raised or the callable failed.
//! The exception is kept and raised once the solve has returned.

use std::time::{Duration, Instant};

use pyo3::exceptions::PyKeyboardInterrupt;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use viscoslide::problem::{Observer, SolverError};
use viscoslide::Error;

use crate::errors::to_py;

/// How often the signal handlers run during a solve.
pub const POLL: Duration = Duration::from_millis(50);

/// Progress to a Python callable, Ctrl-C from Python's signal handlers.
pub struct PyObserver {
    /// Called as `progress({"iteration", "matvecs", "residual",
    /// "contact_cells"})` after every outer iteration, with `"stage"` too
    /// once a heated solve has named the stage they belong to.
    progress: Option<Py<PyAny>>,
    /// The stage the iterations belong to (a heated solve's evaluation).
    stage: Option<String>,
    last_poll: Instant,
    /// The exception that stopped the solve.
    pub error: Option<PyErr>,
}

impl PyObserver {
    pub fn new(progress: Option<Py<PyAny>>) -> Self {
        Self {
            progress,
            stage: None,
            last_poll: Instant::now(),
            error: None,
        }
    }
}

impl PyObserver {
    /// The Python exception for `e`, the failure of the work (`what`) this
    /// observer watched: a cancellation raises the exception that asked for
    /// it (a `KeyboardInterrupt`, or the callable's own).
    pub fn exception(&mut self, py: Python<'_>, e: Error, what: &str) -> PyErr {
        match e {
            Error::Solver(SolverError::Cancelled) => self
                .error
                .take()
                .unwrap_or_else(|| PyKeyboardInterrupt::new_err(format!("{what} cancelled"))),
            e => to_py(py, e),
        }
    }
}

impl Observer for PyObserver {
    fn iteration(&mut self, iteration: usize, matvecs: usize, residual: f64, contact_cells: usize) {
        let Some(progress) = &self.progress else {
            return;
        };
        if self.error.is_some() {
            return;
        }
        let outcome = Python::attach(|py| -> PyResult<()> {
            let info = PyDict::new(py);
            info.set_item("iteration", iteration)?;
            info.set_item("matvecs", matvecs)?;
            info.set_item("residual", residual)?;
            info.set_item("contact_cells", contact_cells)?;
            if let Some(stage) = &self.stage {
                info.set_item("stage", stage)?;
            }
            progress.call1(py, (info,))?;
            Ok(())
        });
        if let Err(e) = outcome {
            self.error = Some(e);
        }
    }

    fn stage(&mut self, label: &str) {
        self.stage = Some(label.to_string());
    }

    fn cancelled(&mut self) -> bool {
        if self.error.is_none() && self.last_poll.elapsed() >= POLL {
            self.last_poll = Instant::now();
            if let Err(e) = Python::attach(|py| py.check_signals()) {
                self.error = Some(e);
            }
        }
        self.error.is_some()
    }
}
