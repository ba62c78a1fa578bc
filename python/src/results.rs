//! `viscoslide.Result`'s native half: a library `Solution` with the
//! analysis its problem asks for; fields as `(nx, ny)` arrays (the axis
//! convention of the `.npy` outputs), documents as JSON for Python to parse.

use std::path::PathBuf;

use numpy::{IntoPyArray, PyArray2, PyArrayMethods};
use pyo3::prelude::*;
use viscoslide::problem::AnalysisReport;
use viscoslide::problem::Solution;

use crate::errors::to_py;

/// The result of one solve.
#[pyclass(name = "Result", module = "viscoslide._native", frozen)]
pub struct NativeResult {
    pub solution: Solution,
    /// The configured analysis (`None` when `[analysis]` disables it).
    pub analysis: Option<AnalysisReport>,
    /// Which executor ran it, and why.
    pub backend_line: String,
}

impl NativeResult {
    fn field<'py>(&self, py: Python<'py>, values: &[f64]) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let (nx, ny) = self.solution.grid();
        values.to_vec().into_pyarray(py).reshape([nx, ny])
    }
}

#[pymethods]
impl NativeResult {
    /// Friction coefficient from the work of the pressure (paper Eq. 9).
    #[getter]
    fn friction_coefficient(&self) -> f64 {
        self.solution.friction_coefficient
    }

    /// Friction coefficient from the dissipated power (Appendix A3-A4).
    #[getter]
    fn friction_coefficient_dissipation(&self) -> f64 {
        self.solution.friction_coefficient_dissipation
    }

    /// Real contact area over the nominal area.
    #[getter]
    fn contact_area_fraction(&self) -> f64 {
        self.solution.stats.contact_area_fraction
    }

    /// Rigid approach \[m\].
    #[getter]
    fn approach(&self) -> f64 {
        self.solution.fields.approach
    }

    /// Contact pressure \[Pa\], shape `(nx, ny)`.
    #[getter]
    fn pressure<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        self.field(py, &self.solution.fields.pressure)
    }

    /// Gap \[m\], shape `(nx, ny)`.
    #[getter]
    fn gap<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        self.field(py, &self.solution.fields.gap)
    }

    /// Surface displacement \[m\], shape `(nx, ny)`.
    #[getter]
    fn displacement<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        self.field(py, &self.solution.fields.displacement)
    }

    /// 1 in contact, 0 elsewhere, shape `(nx, ny)`.
    #[getter]
    fn contact<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        self.field(py, &self.solution.fields.contact)
    }

    /// `(nx, ny)`.
    #[getter]
    fn grid(&self) -> (usize, usize) {
        self.solution.grid()
    }

    /// Which executor ran the solve, and why.
    #[getter]
    fn backend_line(&self) -> String {
        self.backend_line.clone()
    }

    /// The `summary.json` document, as JSON.
    fn summary_json(&self) -> String {
        serde_json::to_string(&self.solution.summary_with(self.analysis.as_ref()))
            .unwrap_or_default()
    }

    /// The convergence report, as JSON.
    fn convergence_json(&self) -> String {
        serde_json::to_string(&self.solution.info).unwrap_or_default()
    }

    /// The full analysis (`analysis.json`), as JSON; `None` when disabled.
    fn analysis_json(&self) -> Option<String> {
        self.analysis
            .as_ref()
            .map(|r| serde_json::to_string(r).unwrap_or_default())
    }

    /// Write every output of the solve into `directory` (as `viscoslide
    /// solve --out`): all files or none. Returns the written paths.
    fn write(&self, py: Python<'_>, directory: PathBuf) -> PyResult<Vec<PathBuf>> {
        let solution = &self.solution;
        py.detach(|| solution.write(&directory))
            .map_err(|e| Python::attach(|py| to_py(py, e)))
    }
}
