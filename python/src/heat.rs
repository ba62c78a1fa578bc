//! The steady surface temperature rise of a rubber half-space sliding past
//! a surface heat flux map (the library's `heat::surface_temperature`),
//! solved with the GIL released.

use numpy::{IntoPyArray, PyArray2, PyArrayMethods, PyReadonlyArray2};
use pyo3::prelude::*;
use viscoslide::heat::{surface_temperature as solve, Conduction, HeatDomain, HeatSetup};
use viscoslide::response::Grid;

use crate::errors::to_py;

/// The surface rise \[K\] at the cell centres (axis 0 = x, the shape of
/// `flux`) under `flux` \[W/m^2\] on cells of `cell_size` x `cell_size_y`
/// \[m\] (square when `None`), sliding at `speed` \[m/s\] along
/// `direction_deg` from +x, for a pad (`periodic` false) or one period of
/// a periodic cell (with the block's background heating when
/// `block_length` \[m\] is given); with it, the setup's notes
/// (`HeatSetup::notes`: what the rise leaves out or may overstate).
#[pyfunction]
#[pyo3(signature = (flux, cell_size, speed, conductivity, diffusivity, periodic, block_length, direction_deg, cell_size_y=None))]
#[allow(clippy::too_many_arguments)]
pub fn surface_temperature<'py>(
    py: Python<'py>,
    flux: PyReadonlyArray2<'py, f64>,
    cell_size: f64,
    speed: f64,
    conductivity: f64,
    diffusivity: f64,
    periodic: bool,
    block_length: Option<f64>,
    direction_deg: f64,
    cell_size_y: Option<f64>,
) -> PyResult<(Bound<'py, PyArray2<f64>>, Vec<String>)> {
    let view = flux.as_array();
    let (nx, ny) = view.dim();
    let values: Vec<f64> = view.iter().copied().collect();
    let setup = HeatSetup {
        grid: Grid::new(nx, ny, (cell_size, cell_size_y.unwrap_or(cell_size)))
            .map_err(|e| to_py(py, e.into()))?,
        conduction: Conduction {
            conductivity,
            diffusivity,
        },
        speed,
        direction_rad: viscoslide::response::direction_rad(direction_deg),
        domain: if periodic {
            HeatDomain::Periodic { block_length }
        } else {
            HeatDomain::Pad
        },
    };
    let t = py
        .detach(|| solve(setup, &values))
        .map_err(|e| to_py(py, e.into()))?;
    Ok((t.rise.into_pyarray(py).reshape([nx, ny])?, setup.notes()))
}
