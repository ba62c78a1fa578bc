//! Magnification studies for Python (`viscoslide::magnification`): a
//! configuration file, its levels and speeds, solved with the GIL released
//! and interruptible, optionally stored in a study directory (resumable,
//! shardable) as `viscoslide magnification` does.

use std::path::PathBuf;

use pyo3::prelude::*;
use viscoslide::config;
use viscoslide::magnification::{run, MagnificationParams, Study, StudyObserver};
use viscoslide::problem::Observer;
use viscoslide::problem::{Executor, Problem};
use viscoslide::sweep::Shard;
use viscoslide::Error;

use crate::errors::{to_py, value_error};
use crate::observer::PyObserver;
use crate::problem;
use crate::solve::backend_choice;

struct Progress(PyObserver);

impl StudyObserver for Progress {
    fn solver(&mut self) -> &mut dyn Observer {
        &mut self.0
    }
}

/// The study of the configuration at `path` (with `overrides`) over the
/// levels `q1` \[1/m\] or `scales`; `speeds` \[m/s\] (`None`: the
/// configuration's). With `out`, points are stored there and the files
/// written as by the command line. Returns the `magnification.json`
/// document, or `None` when points of other shards are still missing.
#[pyfunction]
#[pyo3(signature = (path, overrides, q1, scales, cells_per_wavelength, speeds, backend, shard, out))]
#[allow(clippy::too_many_arguments)]
pub fn magnification(
    py: Python<'_>,
    path: PathBuf,
    overrides: Vec<String>,
    q1: Option<Vec<f64>>,
    scales: Option<Vec<f64>>,
    cells_per_wavelength: f64,
    speeds: Option<Vec<f64>>,
    backend: Option<&str>,
    shard: Option<&str>,
    out: Option<PathBuf>,
) -> PyResult<Option<String>> {
    let choice = backend_choice(backend)?;
    let shard: Shard = match shard {
        Some(s) => s.parse().map_err(value_error)?,
        None => Shard::ALL,
    };
    let cfg = config::load(&path, &overrides).map_err(|e| value_error(problem::load_message(e)))?;
    let params = MagnificationParams::from_options(q1, scales, cells_per_wavelength, speeds)
        .map_err(|e| to_py(py, e))?;
    let mut observer = Progress(PyObserver::new(None));
    let outcome = py.detach(|| -> Result<Option<String>, Error> {
        let study = Study::new(&cfg, params)?;
        let coarse = Problem::from_config(&study.point_config(&study.points[0])?)?;
        let (executor, _) = Executor::select(choice, &coarse)?;
        let done = run(&study, &executor, out.as_deref(), shard, &mut observer)?;
        Ok(done.report.map(|r| r.to_json().to_string()))
    });
    outcome.map_err(|e| observer.0.exception(py, e, "study"))
}
