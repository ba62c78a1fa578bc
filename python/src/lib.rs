//! The native part of the `viscoslide` Python package (`viscoslide._native`):
//! thin wrappers over the library API of the `viscoslide` crate, the same
//! API the command line uses. The Python package (`python/viscoslide/`)
//! checks and converts user input, documents the public API and builds on
//! these functions; nothing here computes physics of its own.
//!
//! - [`material`]: a material from `[material]` keys, a file or DMA data.
//! - [`surface`]: a height map generated, read from a file or given.
//! - [`problem`]: a problem from a surface, a material and config sections.
//! - [`solve`]: solves with the GIL released, interruptible, with progress.
//! - [`results`]: a solution's fields, scalars, summary and analysis.
//! - [`sweep`]: sweeps planned by the library's sweep planner.
//! - [`theory`]: Persson's theory and the influence coefficients.
//! - [`magnification`]: magnification studies of a configuration file.
//! - [`heat`]: the surface temperature rise under a heat flux map.
//! - [`errors`]: library errors as Python exceptions.

use pyo3::prelude::*;

mod errors;
mod heat;
mod magnification;
mod material;
mod observer;
mod problem;
mod results;
mod solve;
mod surface;
mod sweep;
mod theory;

/// Native extension of the viscoslide package; use `import viscoslide`.
#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("VERSION", viscoslide::VERSION)?;
    m.add_class::<material::NativeMaterial>()?;
    m.add_class::<surface::NativeSurface>()?;
    m.add_class::<results::NativeResult>()?;
    m.add_function(wrap_pyfunction!(solve::solve, m)?)?;
    m.add_class::<sweep::NativeSweepPlan>()?;
    m.add_function(wrap_pyfunction!(solve::solve_config, m)?)?;
    m.add_function(wrap_pyfunction!(theory::persson, m)?)?;
    m.add_function(wrap_pyfunction!(theory::kernel_table, m)?)?;
    m.add_function(wrap_pyfunction!(magnification::magnification, m)?)?;
    m.add_function(wrap_pyfunction!(heat::surface_temperature, m)?)?;
    Ok(())
}
