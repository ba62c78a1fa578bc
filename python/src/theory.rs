//! Persson's theory for a Python surface and material (the library's
//! `Problem::persson_psd` and `persson::Persson`), and the influence
//! coefficient tables of the sliding kernel (`SlidingKernel`).

use numpy::{IntoPyArray, PyArray1, PyArray2, PyArrayMethods};
use pyo3::prelude::*;
use viscoslide::config::LayerConfig;
use viscoslide::persson::{Persson, PerssonParams};
use viscoslide::problem::Control;
use viscoslide::problem::{Axis, SlidingKernel};
use viscoslide::response::{Grid, SlidingResponse};

use crate::errors::{to_py, value_error};
use crate::material::NativeMaterial;
use crate::problem;
use crate::surface::NativeSurface;

/// Persson's friction coefficient, contact area fraction and `G(q1)` at
/// `speeds` \[m/s\] for `surface` under `material` at the nominal pressure
/// of the `[loading]` section (JSON; `speed`/`xi` ignored). Returns
/// `(mu, A/A0, G(q1), psd kind, nominal pressure, map PSD report as JSON,
/// (temperature, shift factor a_T))`, the report (preprocessing, band,
/// rms-slope check with its warning) for the radial average of a map only,
/// the temperature for a material with WLF constants only (the
/// `[loading] temperature` of the section shifts it).
#[pyfunction]
#[allow(clippy::type_complexity)]
pub fn persson<'py>(
    py: Python<'py>,
    surface: PyRef<'py, NativeSurface>,
    material: PyRef<'py, NativeMaterial>,
    loading_json: &str,
    speeds: Vec<f64>,
) -> PyResult<(
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<f64>>,
    &'static str,
    f64,
    Option<String>,
    Option<(f64, f64)>,
    Vec<String>,
    Vec<String>,
)> {
    let sections = problem::Sections {
        loading: loading_json,
        solver: "{}",
        layer: None,
        heating: None,
    };
    let (problem, _) = problem::build(&surface, &material, sections)?;
    let (psd, kind, report) = problem.persson_psd_report().map_err(value_error)?;
    // As `viscoslide persson` gives them: the material's data ranges, the
    // map PSD's rms-slope check, and what the theory leaves out.
    let mut warnings = problem.persson_curve_warnings(&psd, &speeds);
    warnings.extend(report.as_ref().and_then(|r| r.warning.clone()));
    let notes = problem.persson_notes(report.as_ref());
    let report = report
        .map(|r| serde_json::to_string(&r))
        .transpose()
        .map_err(value_error)?;
    let sigma0 = match problem.control {
        Control::Load(f) => f / (problem.surface.length_x() * problem.surface.length_y()),
        Control::Approach(_) => {
            return Err(value_error(
                "Persson's theory needs a nominal pressure: give normal_load or mean_pressure, not approach",
            ))
        }
    };
    let points = py
        .detach(|| {
            Persson::new(&problem.material, &psd, sigma0, PerssonParams::default())
                .and_then(|t| t.curve(&speeds))
        })
        .map_err(|e| to_py(py, e.into()))?;
    let column = |f: fn(&viscoslide::persson::PerssonPoint) -> f64| {
        points.iter().map(f).collect::<Vec<f64>>().into_pyarray(py)
    };
    Ok((
        column(|p| p.friction_coefficient),
        column(|p| p.contact_area_fraction),
        column(|p| p.g_q1),
        kind,
        sigma0,
        report,
        problem
            .material
            .temperature_shift()
            .map(|t| (t.temperature, t.shift_factor)),
        warnings,
        notes,
    ))
}

/// The influence coefficients `K(i, j)` \[m/Pa\] (or, with `derivative`,
/// the cell-averaged `dK/dx` \[1/Pa\]) of `material` sliding at `speed`
/// \[m/s\] along `direction_deg`, for cells of sides `cell_size` x
/// `cell_size_y` \[m\] (square when `cell_size_y` is `None`), over all
/// offsets of an `nx x ny` grid: shape `(2 nx - 1, 2 ny - 1)`, offset
/// `(i, j)` at index `(i + nx - 1, j + ny - 1)`; with it the warning of a
/// layer thinner than a cell. The cells are checked as `viscoslide
/// kernel` checks them (`SlidingKernel::check_cells`: a layer below the
/// bound of a cell is refused), and a table with a value that is not
/// finite is refused, naming the cell size. With `temperature` \[C\] the
/// material is taken at that temperature (its WLF shift), as `viscoslide
/// kernel` takes it at `[loading] temperature`.
#[pyfunction]
#[pyo3(signature = (material, nx, ny, cell_size, speed, direction_deg, layer_json, derivative, cell_size_y=None, temperature=None))]
#[allow(clippy::too_many_arguments)]
pub fn kernel_table<'py>(
    py: Python<'py>,
    material: PyRef<'py, NativeMaterial>,
    nx: usize,
    ny: usize,
    cell_size: f64,
    speed: f64,
    direction_deg: f64,
    layer_json: Option<&str>,
    derivative: bool,
    cell_size_y: Option<f64>,
    temperature: Option<f64>,
) -> PyResult<(Bound<'py, PyArray2<f64>>, Option<String>)> {
    let (ax, ay) = (cell_size, cell_size_y.unwrap_or(cell_size));
    let layer = layer_json
        .map(|j| {
            serde_json::from_str::<LayerConfig>(j)
                .map_err(|e| value_error(format!("[layer] {e}")))
                .and_then(|l| l.build().map_err(value_error))
        })
        .transpose()?;
    if !direction_deg.is_finite() {
        return Err(value_error(format!(
            "direction_deg must be finite, got {direction_deg}"
        )));
    }
    // The material at the temperature (its WLF shift), as the command's.
    let material = material.material.at(temperature).map_err(value_error)?;
    let response = SlidingResponse::new(
        &material,
        speed,
        viscoslide::response::direction_rad(direction_deg),
        layer,
    )
    .map_err(value_error)?;
    let kernel = SlidingKernel::new(&response).map_err(value_error)?;
    let warning = kernel.check_cells(ax, ay).map_err(value_error)?;
    let grid = Grid::new(nx, ny, (ax, ay)).map_err(value_error)?;
    let table = py
        .detach(|| {
            if derivative {
                kernel.derivative_table(&grid, Axis::X)
            } else {
                kernel.table(&grid)
            }
        })
        .map_err(value_error)?;
    let values = table
        .values
        .into_pyarray(py)
        .reshape([2 * table.nx - 1, 2 * table.ny - 1])?;
    Ok((values, warning))
}
