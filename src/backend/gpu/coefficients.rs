//! The influence-coefficient table computed on the device in f32
//! (`shaders/coefficients.wgsl`; paper Eq. 4 and Eq. 6, physics.md
//! section 3; CPU twin: [`crate::kernel::SlidingKernel::table`]). The host
//! classifies the creep terms (memory lengths below `1e-7` cells act as
//! relaxed compliance) and scales the dimensionless table by
//! `(1 - nu^2)/pi * a * (total compliance)` in f64. Half-spaces only: the
//! finite-thickness factor `Theta` (Eq. 5) stays on the host.

use super::context::GpuError;
use super::engine::{Engine, Kernel, Params};
use super::plan::{grid as dispatch_grid, plan, read_scaled};
use crate::response::{Grid, SlidingResponse};
/// Invocations per workgroup of the coefficient kernel (`CWG`).
const COEFF_WORKGROUP: u64 = 64;

/// The `(2nx-1) x (2ny-1)` offset table [m/Pa] of `grid` in the layout of
/// [`crate::kernel::CoefficientTable`]. On cells of sides `(a_x, a_y)`
/// (Love's rectangle, physics.md section 11) lengths are in units of `a_x`,
/// the source cell `1 x a_y / a_x`.
pub fn coefficient_table(
    engine: &mut Engine,
    response: &SlidingResponse,
    grid: &Grid,
) -> Result<Vec<f64>, GpuError> {
    let ((nx, ny), (ax, ay)) = (grid.size(), grid.cell());
    let plan = plan(response, ax)?;
    let count = (2 * nx - 1) * (2 * ny - 1);
    // The table is written through binding windows when larger than one
    // binding (shaders/coefficients.wgsl, backend::gpu::split).
    engine.check_buffer("the coefficient table", 4 * count as u64)?;
    engine.check_bindings(
        "the coefficient table",
        1 + engine.windows(4 * count as u64),
    )?;
    let terms = engine.storage_with("viscoslide creep terms", bytemuck::cast_slice(&plan.terms));
    let out = engine.create_buffer(
        "viscoslide coefficient table",
        4 * count as u64,
        wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
    );
    engine.dispatch(
        Kernel::Coefficients,
        &[&terms, &out],
        Params {
            i: [nx as u32, ny as u32, plan.count, 0],
            j: [0; 4],
            f: [plan.e[0], plan.e[1], plan.instantaneous, (ay / ax) as f32],
        },
        dispatch_grid((count as u64).div_ceil(COEFF_WORKGROUP)),
    );
    Ok(read_scaled(engine, &out, count, plan.scale))
}
