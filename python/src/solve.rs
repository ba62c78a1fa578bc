//! Solves with the GIL released: `solve` (a surface, a material and config
//! sections) and `solve_config` (a configuration file with `--set`
//! overrides, exactly as `viscoslide solve`), isothermal or, with an
//! enabled `[heating]` section, heated (`viscoslide::heating::solve_heated`,
//! physics.md section 14). The executor is chosen as the command line
//! chooses it; the solve and the configured analysis run detached from the
//! interpreter, the observer polls Ctrl-C and reports progress.

use std::path::PathBuf;

use pyo3::prelude::*;
use viscoslide::config;
use viscoslide::heating::{solve_heated, HeatingParams};
use viscoslide::problem::BackendChoice;
use viscoslide::problem::{Executor, Problem};
use viscoslide::Error;

use crate::errors::{to_py, value_error};
use crate::material::NativeMaterial;
use crate::observer::PyObserver;
use crate::problem;
use crate::problem::Sections;
use crate::results::{NativeResult, Solved};
use crate::surface::NativeSurface;

/// `auto`, `cpu` or `gpu`; `None`: `VISCOSLIDE_BACKEND`, else `auto` (as
/// the command line without `--backend`).
pub(crate) fn backend_choice(name: Option<&str>) -> PyResult<BackendChoice> {
    let flag = match name {
        None => None,
        Some("auto") => Some(BackendChoice::Auto),
        Some("cpu") => Some(BackendChoice::Cpu),
        Some("gpu") => Some(BackendChoice::Gpu),
        Some(other) => {
            return Err(value_error(format!(
                "backend '{other}': expected 'auto', 'cpu' or 'gpu'"
            )))
        }
    };
    BackendChoice::resolve(flag).map_err(value_error)
}

/// Solve `problem` (heated with `heating`, else isothermal) and run its
/// configured analysis with the GIL released.
pub(crate) fn run(
    py: Python<'_>,
    problem: &Problem,
    heating: Option<&HeatingParams>,
    backend: Option<&str>,
    progress: Option<Py<PyAny>>,
) -> PyResult<NativeResult> {
    let choice = backend_choice(backend)?;
    let mut observer = PyObserver::new(progress);
    let outcome = py.detach(|| -> Result<NativeResult, Error> {
        let (executor, backend_line) = Executor::select(choice, problem)?;
        let solved = match heating {
            Some(params) => Solved::Heated(Box::new(solve_heated(
                problem,
                params,
                &executor,
                &mut observer,
            )?)),
            None => Solved::Isothermal(Box::new(problem.solve(&executor, &mut observer)?)),
        };
        let analysis = solved.solution().analyze_configured()?;
        Ok(NativeResult {
            solved,
            problem: problem.clone(),
            analysis,
            backend_line,
        })
    });
    outcome.map_err(|e| observer.exception(py, e, "solve"))
}

/// Solve `surface` under `material` with the `[loading]`, `[solver]` and
/// optional `[layer]` and `[heating]` sections (JSON); every section and
/// the heating's parameters are checked before anything is solved.
#[pyfunction]
#[pyo3(signature = (surface, material, loading_json, solver_json, layer_json, heating_json, backend, progress=None))]
#[allow(clippy::too_many_arguments)]
pub fn solve(
    py: Python<'_>,
    surface: PyRef<'_, NativeSurface>,
    material: PyRef<'_, NativeMaterial>,
    loading_json: &str,
    solver_json: &str,
    layer_json: Option<&str>,
    heating_json: Option<&str>,
    backend: Option<&str>,
    progress: Option<Py<PyAny>>,
) -> PyResult<NativeResult> {
    let sections = Sections {
        loading: loading_json,
        solver: solver_json,
        layer: layer_json,
        heating: heating_json,
    };
    let (problem, heating) = problem::build(&surface, &material, sections)?;
    problem.check_analysis().map_err(value_error)?;
    run(py, &problem, heating.as_ref(), backend, progress)
}

/// Solve the configuration at `path` with `overrides` (`section.key=value`,
/// TOML values), as `viscoslide solve` does (heated with an enabled
/// `[heating]` section).
#[pyfunction]
#[pyo3(signature = (path, overrides, backend, progress=None))]
pub fn solve_config(
    py: Python<'_>,
    path: PathBuf,
    overrides: Vec<String>,
    backend: Option<&str>,
    progress: Option<Py<PyAny>>,
) -> PyResult<NativeResult> {
    let cfg = config::load(&path, &overrides).map_err(|e| value_error(problem::load_message(e)))?;
    let problem = Problem::from_config(&cfg).map_err(|e| to_py(py, e))?;
    problem.check_analysis().map_err(value_error)?;
    let ambient = cfg.config.loading.as_ref().and_then(|l| l.temperature);
    let heating = problem::heating_params(cfg.config.heating.as_ref(), &problem, ambient)?;
    run(py, &problem, heating.as_ref(), backend, progress)
}
