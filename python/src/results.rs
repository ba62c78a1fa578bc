//! `viscoslide.Result`'s native half: a library `Solution` (or the heated
//! solve's `HeatedSolution`, physics.md section 14) with the analysis its
//! problem asks for; fields as `(nx, ny)` arrays (the axis convention of
//! the `.npy` outputs), documents as JSON for Python to parse.

use std::path::PathBuf;

use numpy::{IntoPyArray, PyArray2, PyArrayMethods};
use pyo3::prelude::*;
use viscoslide::config::Formulation;
use viscoslide::heat::{Conduction, DepthRule, SourceKind};
use viscoslide::heating::HeatedSolution;
use viscoslide::problem::{AnalysisReport, Observer, Problem, Solution};

use crate::errors::{to_py, value_error};
use crate::observer::PyObserver;

/// A solve's answer: isothermal, or heated (the isothermal solve at the
/// effective temperature with its heat).
pub enum Solved {
    Isothermal(Box<Solution>),
    Heated(Box<HeatedSolution>),
}

impl Solved {
    /// The contact solution (the heated one's at `T_eff`).
    pub fn solution(&self) -> &Solution {
        match self {
            Solved::Isothermal(s) => s,
            Solved::Heated(h) => &h.solution,
        }
    }

    /// The heated solve, if it was one.
    pub fn heated(&self) -> Option<&HeatedSolution> {
        match self {
            Solved::Isothermal(_) => None,
            Solved::Heated(h) => Some(h),
        }
    }
}

/// The result of one solve.
#[pyclass(name = "Result", module = "viscoslide._native", frozen)]
pub struct NativeResult {
    pub solved: Solved,
    /// The problem solved (its material at the ambient temperature), for
    /// the heat of the solution.
    pub problem: Problem,
    /// The configured analysis (`None` when `[analysis]` disables it).
    pub analysis: Option<AnalysisReport>,
    /// Which executor ran it, and why.
    pub backend_line: String,
}

impl NativeResult {
    fn solution(&self) -> &Solution {
        self.solved.solution()
    }

    fn field<'py>(&self, py: Python<'py>, values: &[f64]) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let (nx, ny) = self.solution().grid();
        values.to_vec().into_pyarray(py).reshape([nx, ny])
    }

    /// `summary.json` as `viscoslide solve` writes it: with the `heating`
    /// object of a heated solve.
    fn summary(&self) -> serde_json::Value {
        let mut doc = self.solution().summary_with(self.analysis.as_ref());
        if let Some(h) = self.solved.heated() {
            doc["heating"] = h.summary();
        }
        doc
    }
}

#[pymethods]
impl NativeResult {
    /// Friction coefficient from the work of the pressure (paper Eq. 9).
    #[getter]
    fn friction_coefficient(&self) -> f64 {
        self.solution().friction_coefficient
    }

    /// Friction coefficient from the dissipated power (Appendix A3-A4).
    #[getter]
    fn friction_coefficient_dissipation(&self) -> f64 {
        self.solution().friction_coefficient_dissipation
    }

    /// Real contact area over the nominal area.
    #[getter]
    fn contact_area_fraction(&self) -> f64 {
        self.solution().stats.contact_area_fraction
    }

    /// Rigid approach \[m\].
    #[getter]
    fn approach(&self) -> f64 {
        self.solution().fields.approach
    }

    /// Contact pressure \[Pa\], shape `(nx, ny)`.
    #[getter]
    fn pressure<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        self.field(py, &self.solution().fields.pressure)
    }

    /// Gap \[m\], shape `(nx, ny)`.
    #[getter]
    fn gap<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        self.field(py, &self.solution().fields.gap)
    }

    /// Surface displacement \[m\], shape `(nx, ny)`.
    #[getter]
    fn displacement<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        self.field(py, &self.solution().fields.displacement)
    }

    /// 1 in contact, 0 elsewhere, shape `(nx, ny)`.
    #[getter]
    fn contact<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        self.field(py, &self.solution().fields.contact)
    }

    /// `(nx, ny)`.
    #[getter]
    fn grid(&self) -> (usize, usize) {
        self.solution().grid()
    }

    /// Which executor ran the solve, and why.
    #[getter]
    fn backend_line(&self) -> String {
        self.backend_line.clone()
    }

    /// The `summary.json` document (with the `heating` object of a heated
    /// solve), as JSON.
    fn summary_json(&self) -> String {
        serde_json::to_string(&self.summary()).unwrap_or_default()
    }

    /// The heated solve's report (`summary.json`'s `heating` object), as
    /// JSON; `None` for an isothermal solve.
    fn heating_json(&self) -> Option<String> {
        let heating = self.solved.heated()?.summary();
        Some(serde_json::to_string(&heating).unwrap_or_default())
    }

    /// The surface temperature rise `T - T0` \[K\] of a heated solve at
    /// the cell centres, shape `(nx, ny)` (`temperature.npy`); `None` for
    /// an isothermal solve.
    #[getter]
    fn temperature_rise<'py>(
        &self,
        py: Python<'py>,
    ) -> PyResult<Option<Bound<'py, PyArray2<f64>>>> {
        self.solved
            .heated()
            .map(|h| self.field(py, &h.surface_rise))
            .transpose()
    }

    /// The heated solve's rise against depth (`temperature_depth.csv`):
    /// rows of depth \[m\], mean and highest rise \[K\] and mean volume
    /// source \[W/m^3\]; `None` for an isothermal solve or a pad.
    #[getter]
    fn temperature_depth(&self) -> Option<Vec<(f64, f64, f64, f64)>> {
        let rows = self.solved.heated()?.depth_profile.as_ref()?;
        Some(
            rows.iter()
                .map(|r| (r.depth, r.mean_rise, r.max_rise, r.mean_source))
                .collect(),
        )
    }

    /// The heat of this solution in a rubber of `conductivity` \[W/(m K)\]
    /// and `diffusivity` \[m^2/s\] (`viscoslide heat --from-run`,
    /// `viscoslide::problem::ContactHeating`, physics.md section 14): the
    /// creep elements' dissipation on depth layers (`source` `"volume"`,
    /// periodic cells on a half-space; default there) or the surface work
    /// of the pressure (`"surface"`, default on a pad or a layer),
    /// `refined_layers` for depth
    /// integrals to about 5e-9; `block_length` \[m\] gives a periodic
    /// cell its background heating. A heated solve's solution is at its
    /// effective temperature, and so is its heat. Returns the `heat.json`
    /// numbers (JSON) and the surface rise \[K\], shape `(nx, ny)`.
    #[pyo3(signature = (conductivity, diffusivity, block_length, source, refined_layers))]
    fn heat<'py>(
        &self,
        py: Python<'py>,
        conductivity: f64,
        diffusivity: f64,
        block_length: Option<f64>,
        source: Option<&str>,
        refined_layers: bool,
    ) -> PyResult<(String, Bound<'py, PyArray2<f64>>)> {
        let periodic = self.problem.formulation == Formulation::Periodic;
        let layered = self.problem.layer.is_some();
        let kind = match source {
            Some(s) => s.parse::<SourceKind>().map_err(value_error)?,
            None => SourceKind::default_for(periodic, layered),
        };
        if let Some(why) = kind.unsupported(periodic, layered) {
            return Err(value_error(format!(
                "source=\"{}\": {why}; pass source=\"surface\" (the default on a pad or a layer)",
                kind.name()
            )));
        }
        if block_length.is_some() && !periodic {
            return Err(value_error(
                "block_length is for a periodic cell's background heating; this result is a pad, whose steady rise needs none: drop it",
            ));
        }
        if refined_layers && kind == SourceKind::Surface {
            return Err(value_error(
                "refined_layers refines the volume source's depth layers; the surface source has none: drop it or pass source=\"volume\" (periodic cells)",
            ));
        }
        let rule = if refined_layers {
            DepthRule::refined()
        } else {
            DepthRule::default()
        };
        let mut problem = self.problem.clone();
        if let Some(h) = self.solved.heated() {
            problem.material = problem
                .material
                .at_temperature(h.report.effective_temperature)
                .map_err(|e| to_py(py, e.into()))?;
        }
        let solution = self.solution();
        let conduction = Conduction {
            conductivity,
            diffusivity,
        };
        // Ctrl-C is polled between the volume source's depth nodes.
        let mut observer = PyObserver::new(None);
        let heat = py
            .detach(|| {
                problem.contact_heating_until(
                    solution,
                    conduction,
                    block_length,
                    kind,
                    &rule,
                    &mut || observer.cancelled(),
                )
            })
            .map_err(|e| observer.exception(py, e, "heat"))?;
        let report = serde_json::to_string(&heat.report()).unwrap_or_default();
        Ok((report, self.field(py, &heat.temperature.rise)?))
    }

    /// The convergence report, as JSON.
    fn convergence_json(&self) -> String {
        serde_json::to_string(&self.solution().info).unwrap_or_default()
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
        let solved = &self.solved;
        py.detach(|| match solved {
            Solved::Isothermal(s) => s.write(&directory),
            Solved::Heated(h) => h.write(&directory),
        })
        .map_err(|e| Python::attach(|py| to_py(py, e)))
    }
}
