//! Sweeps from Python, planned by the library's sweep planner
//! (`viscoslide::sweep::SweepPlan`, the planner of `viscoslide sweep`):
//! the same `[sweep.vary]` keys and values checked the same way, the same
//! limit and the same order of points (the `vary` values outermost, keys in
//! name order, the last fastest; then loads; then speeds), each
//! combination's configuration made by `viscoslide::sweep::point_config`
//! (every value set as `--set` sets it, typed by the configuration's
//! parser). Every point is built and checked before the first is solved,
//! its `[heating]` too (`"heating.enabled" = [false, true]` gives each
//! speed isothermal and heated, as `viscoslide sweep` does).

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};
use viscoslide::config::{Config, LoadedConfig, SweepConfig};
use viscoslide::heating::HeatingParams;
use viscoslide::problem::Problem;
use viscoslide::sweep::{point_config, Point, SweepPlan};

use crate::errors::value_error;
use crate::material::{section_table, NativeMaterial};
use crate::problem::{self, Sections};
use crate::results::NativeResult;
use crate::solve::{backend_choice, run};
use crate::surface::NativeSurface;

/// The sections of a configuration a Python sweep can vary: those a
/// Python surface, material and the arguments of `solve` make.
const SECTIONS: [&str; 6] = [
    "material", "surface", "loading", "solver", "layer", "heating",
];

/// Name of the configuration in messages.
const NAME: &str = "sweep";

/// The points of a sweep over a Python surface and material, planned and
/// checked; `solve(i)` solves point `i`.
#[pyclass(name = "SweepPlan", module = "viscoslide._native", frozen)]
pub struct NativeSweepPlan {
    surface: Py<NativeSurface>,
    material: Py<NativeMaterial>,
    /// The configuration of the surface, the material and the arguments.
    cfg: LoadedConfig,
    /// The load axis is `mean_pressure` \[Pa\] (else `normal_load` \[N\]).
    pressure: bool,
    plan: SweepPlan,
}

/// A combination of the `vary` values: its configuration, and the surface
/// and material it makes when it varies their keys.
struct Combination {
    config: Config,
    surface: Option<NativeSurface>,
    material: Option<NativeMaterial>,
}

/// A Python value of a `vary` list as a TOML value.
fn toml_value(key: &str, value: &Bound<'_, PyAny>) -> PyResult<toml::Value> {
    if let Ok(b) = value.cast::<PyBool>() {
        return Ok(toml::Value::Boolean(b.is_true()));
    }
    if value.is_instance_of::<PyInt>() {
        return value
            .extract::<i64>()
            .map(toml::Value::Integer)
            .map_err(|_| {
                value_error(format!(
                    "vary \"{key}\": {value} is outside the range of a 64-bit integer"
                ))
            });
    }
    if let Ok(f) = value.cast::<PyFloat>() {
        let x = f.value();
        if !x.is_finite() {
            return Err(value_error(format!(
                "vary \"{key}\": {x} is not a finite number"
            )));
        }
        return Ok(toml::Value::Float(x));
    }
    if value.is_instance_of::<PyString>() {
        return Ok(toml::Value::String(value.extract()?));
    }
    if value.is_instance_of::<PyList>() || value.is_instance_of::<PyTuple>() {
        let items: Vec<Bound<'_, PyAny>> = value.try_iter()?.collect::<PyResult<_>>()?;
        let values = items
            .iter()
            .map(|v| toml_value(key, v))
            .collect::<PyResult<_>>()?;
        return Ok(toml::Value::Array(values));
    }
    if let Ok(d) = value.cast::<PyDict>() {
        let mut table = toml::Table::new();
        for (k, v) in d.iter() {
            let k: String = k.extract().map_err(|_| {
                PyTypeError::new_err(format!(
                    "vary \"{key}\": a table's keys are strings, got {k}"
                ))
            })?;
            table.insert(k, toml_value(key, &v)?);
        }
        return Ok(toml::Value::Table(table));
    }
    Err(PyTypeError::new_err(format!(
        "vary \"{key}\": cannot take {} of type {}; give numbers, strings, booleans, or lists or dicts of them",
        value.repr()?,
        value.get_type().name()?
    )))
}

/// The section a normalised `vary` key belongs to.
fn section_of(key: &str) -> &str {
    key.split('.').next().unwrap_or(key)
}

#[pymethods]
impl NativeSweepPlan {
    /// Plan the sweep of `surface` under `material` with the `[loading]`,
    /// `[solver]`, `[layer]` and `[heating]` sections (JSON) over `speeds` (m/s, or `xi`
    /// when `sliding` is `"xi"`), `loads` (N, or Pa when `load` is
    /// `"mean_pressure"`) and the `vary` lists (`[(key, values)]`), and
    /// check every point; a bad key or value is refused in one line naming
    /// it, before anything is solved.
    #[new]
    #[pyo3(signature = (surface, material, loading_json, solver_json, layer_json, heating_json, backend, sliding, speeds, load, loads, vary))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        surface: Bound<'_, NativeSurface>,
        material: Bound<'_, NativeMaterial>,
        loading_json: &str,
        solver_json: &str,
        layer_json: Option<&str>,
        heating_json: Option<&str>,
        backend: Option<&str>,
        sliding: &str,
        speeds: Vec<f64>,
        load: &str,
        loads: Vec<f64>,
        vary: Vec<(String, Vec<Bound<'_, PyAny>>)>,
    ) -> PyResult<Self> {
        backend_choice(backend)?;
        let pressure = match load {
            "normal_load" => false,
            "mean_pressure" => true,
            other => {
                return Err(value_error(format!(
                    "load axis '{other}': expected 'normal_load' or 'mean_pressure'"
                )))
            }
        };
        if pressure {
            if let Some(bad) = loads.iter().find(|p| !(p.is_finite() && **p > 0.0)) {
                return Err(value_error(format!(
                    "mean_pressure must be positive (Pa), got {bad}"
                )));
            }
        }
        let mut lists = BTreeMap::new();
        for (key, values) in &vary {
            let values = values
                .iter()
                .map(|v| toml_value(key, v))
                .collect::<PyResult<Vec<_>>>()?;
            lists.insert(key.clone(), values);
        }
        let (speed, xi) = match sliding {
            "speed" => (Some(speeds), None),
            "xi" => (None, Some(speeds)),
            other => {
                return Err(value_error(format!(
                    "sliding axis '{other}': expected 'speed' or 'xi'"
                )))
            }
        };
        let plan = SweepPlan::new(&SweepConfig {
            speed,
            xi,
            include_static: Some(false),
            normal_load: Some(loads),
            vary: (!lists.is_empty()).then_some(lists),
            ..Default::default()
        })
        .map_err(value_error)?;
        let keys: Vec<String> = plan.points[0].vary.keys().cloned().collect();
        let given_values = surface.get().section.is_none();
        for key in &keys {
            if !SECTIONS.contains(&section_of(key)) {
                return Err(value_error(format!(
                    "[sweep.vary] \"{key}\": a sweep of a Python surface and material varies the keys of [{}]",
                    SECTIONS.join("], [")
                )));
            }
            if section_of(key) == "surface" && given_values {
                return Err(value_error(format!(
                    "[sweep.vary] \"{key}\": the surface was given as values and has no [surface] section to vary; build it with Surface.generate, Surface.self_affine or Surface.from_file"
                )));
            }
        }
        let mut document = problem::document(Sections {
            loading: loading_json,
            solver: solver_json,
            layer: layer_json,
            heating: heating_json,
        })?;
        // Without `vary` the sections are the points' configuration; with
        // it, each combination's is typed once its values are set (a layer
        // may be complete only then).
        let config = if keys.is_empty() {
            problem::parse(&document, NAME)?
        } else {
            Config::default()
        };
        document.insert(
            "material".into(),
            toml::Value::Table(section_table(&material.get().section)),
        );
        // A varied key replaces the surface's own alternative (`q1` its
        // `scales`), as `point_config` sets every value.
        if let Some(s) = &surface.get().section {
            let table = toml::Table::try_from(s).map_err(value_error)?;
            document.insert("surface".into(), toml::Value::Table(table));
        }
        let this = Self {
            surface: surface.unbind(),
            material: material.unbind(),
            cfg: LoadedConfig {
                config,
                path: PathBuf::from(NAME),
                base_dir: PathBuf::from("."),
                document,
            },
            pressure,
            plan,
        };
        // Every point built and checked before the first is solved.
        let mut start = 0;
        while start < this.plan.points.len() {
            let vary = &this.plan.points[start].vary;
            let end = this.plan.points[start..]
                .iter()
                .position(|p| &p.vary != vary)
                .map_or(this.plan.points.len(), |n| start + n);
            let combination = this.combination(&this.plan.points[start])?;
            for point in &this.plan.points[start..end] {
                this.problem(&combination, point)?;
            }
            start = end;
        }
        Ok(this)
    }

    /// Number of points.
    fn __len__(&self) -> usize {
        self.plan.points.len()
    }

    /// The points in plan order as JSON, as `viscoslide sweep` records
    /// them (`index`, `id`, `speed` (`{"speed": v}` or `{"xi": xi}`),
    /// `normal_load`: the value of the load axis, N or Pa; `vary`).
    fn points_json(&self) -> String {
        serde_json::to_string(&self.plan.points).unwrap_or_default()
    }

    /// Solve point `index` (as `solve` does: the GIL released,
    /// interruptible, `progress` called after every outer iteration).
    #[pyo3(signature = (index, backend, progress=None))]
    fn solve(
        &self,
        py: Python<'_>,
        index: usize,
        backend: Option<&str>,
        progress: Option<Py<PyAny>>,
    ) -> PyResult<NativeResult> {
        let point = self.plan.points.get(index).ok_or_else(|| {
            value_error(format!(
                "point {index}: the sweep has {} points",
                self.plan.points.len()
            ))
        })?;
        let combination = self.combination(point)?;
        let (problem, heating) = self.problem(&combination, point)?;
        run(py, &problem, heating.as_ref(), backend, progress)
    }
}

impl NativeSweepPlan {
    /// The configuration of `point`'s `vary` values, and the surface and
    /// material it makes when it varies their keys.
    fn combination(&self, point: &Point) -> PyResult<Combination> {
        let config = point_config(&self.cfg, point).map_err(value_error)?;
        let varies = |section: &str| point.vary.keys().any(|k| section_of(k) == section);
        let at = |e: PyErr| self.named(point, e);
        let surface = match (&config.surface, varies("surface")) {
            (Some(s), true) => {
                Some(NativeSurface::from_config(s.clone(), Path::new(".")).map_err(at)?)
            }
            _ => None,
        };
        let material = match (&config.material, varies("material")) {
            (Some(m), true) => Some(NativeMaterial::build(m.clone(), Path::new(".")).map_err(at)?),
            _ => None,
        };
        Ok(Combination {
            config,
            surface,
            material,
        })
    }

    /// The problem of `point` in its `combination`, and its heated solve's
    /// parameters when `[heating]` is enabled.
    fn problem(
        &self,
        combination: &Combination,
        point: &Point,
    ) -> PyResult<(Problem, Option<HeatingParams>)> {
        let config = &combination.config;
        let mut loading = config.loading.clone().unwrap_or_default();
        loading.set_sliding(point.speed);
        let load = point.normal_load.expect("a Python sweep has a load axis");
        if self.pressure {
            loading.normal_load = None;
            loading.approach = None;
            loading.mean_pressure = Some(load);
        } else {
            loading.set_normal_load(load);
        }
        let surface = combination.surface.as_ref().unwrap_or(self.surface.get());
        let material = combination.material.as_ref().unwrap_or(self.material.get());
        let problem = problem::from_sections(
            surface,
            material,
            &loading,
            &config.solver.clone().unwrap_or_default(),
            config.layer.as_ref(),
            config.heating.as_ref(),
        )
        .map_err(|e| self.named(point, e))?;
        problem
            .check_analysis()
            .map_err(|e| self.named(point, value_error(e)))?;
        let heating =
            problem::heating_params(config.heating.as_ref(), &problem, loading.temperature)
                .map_err(|e| self.named(point, e))?;
        Ok((problem, heating))
    }

    /// `e` with the `vary` values of `point` in front (a value that one
    /// combination cannot take is named with it).
    fn named(&self, point: &Point, e: PyErr) -> PyErr {
        if point.vary.is_empty() {
            return e;
        }
        let values: Vec<String> = point
            .vary
            .iter()
            .map(|(k, v)| format!("\"{k}\" = {v}"))
            .collect();
        let message = Python::attach(|py| e.value(py).to_string());
        value_error(format!(
            "{NAME}: [sweep.vary] {}: {message}",
            values.join(", ")
        ))
    }
}
