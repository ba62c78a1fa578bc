//! The influence-coefficient table computed on the device in f32
//! (`shaders/coefficients.wgsl`; paper Eq. 4 and Eq. 6, physics.md
//! section 3; CPU twin: [`crate::kernel::SlidingKernel::table`]). The host
//! classifies the creep terms (memory lengths below `1e-7` cells act as
//! relaxed compliance) and scales the dimensionless table by
//! `(1 - nu^2)/pi * a * (total compliance)` in f64. Half-spaces only: the
//! finite-thickness factor `Theta` (Eq. 5) stays on the host.

use super::context::GpuError;
use super::engine::{Engine, Kernel, Params};
use super::plan::{grid, plan, read_scaled};
use crate::kernel::KernelParams;
use crate::material::Material;
/// Invocations per workgroup of the coefficient kernel (`CWG`).
const COEFF_WORKGROUP: u64 = 64;

/// The `(2nx-1) x (2ny-1)` offset table [m/Pa] of a square-cell grid (cell
/// side `cell` \[m\]) in the layout of [`crate::kernel::CoefficientTable`].
pub fn coefficient_table(
    engine: &mut Engine,
    material: &Material,
    params: &KernelParams,
    nx: usize,
    ny: usize,
    cell: f64,
) -> Result<Vec<f64>, GpuError> {
    coefficient_table_rect(engine, material, params, nx, ny, (cell, cell))
}

/// [`coefficient_table`] on cells of sides `(a_x, a_y)` \[m\] (Love's
/// rectangle, physics.md section 11): lengths in units of `a_x`, the source
/// cell `1 x a_y / a_x`.
pub fn coefficient_table_rect(
    engine: &mut Engine,
    material: &Material,
    params: &KernelParams,
    nx: usize,
    ny: usize,
    (ax, ay): (f64, f64),
) -> Result<Vec<f64>, GpuError> {
    let ok = |a: f64| a.is_finite() && a > 0.0;
    if !ok(ax) || !ok(ay) || nx == 0 || ny == 0 {
        return Err(GpuError::Invalid(format!(
            "grid {nx} x {ny} with cell {ax} m x {ay} m"
        )));
    }
    let plan = plan(material, params, ax)?;
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
        grid((count as u64).div_ceil(COEFF_WORKGROUP)),
    );
    Ok(read_scaled(engine, &out, count, plan.scale))
}
