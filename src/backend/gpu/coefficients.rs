//! The influence-coefficient table computed on the device in f32
//! (`shaders/coefficients.wgsl`; paper Eq. 4 and Eq. 6, physics.md
//! section 3; CPU twin: [`crate::kernel::SlidingKernel::table`]). The host
//! classifies the creep terms (memory lengths below `1e-7` cells act as
//! relaxed compliance) and scales the dimensionless table by
//! `(1 - nu^2)/pi * a * (total compliance)` in f64. Half-spaces only: the
//! finite-thickness factor `Theta` (Eq. 5) stays on the host.

use super::context::GpuError;
use super::engine::{Engine, Kernel, Params};
use crate::kernel::KernelParams;
use crate::material::Material;

/// Memory lengths below this many cells act as relaxed compliance (the
/// neglected part is about `l |grad L| / L`, below 1e-7).
pub(super) const RELAXED_CELLS: f64 = 1e-7;
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
    if params.layer.is_some() {
        return Err(GpuError::Invalid(
            "the GPU coefficient kernel covers half-spaces only; finite-thickness tables are computed on the host".into(),
        ));
    }
    if !(cell.is_finite() && cell > 0.0) || nx == 0 || ny == 0 {
        return Err(GpuError::Invalid(format!(
            "grid {nx} x {ny} with cell {cell} m"
        )));
    }
    if params.speed.is_nan() || params.speed < 0.0 || !params.direction_rad.is_finite() {
        return Err(GpuError::Invalid(format!(
            "speed {} m/s and direction {} rad",
            params.speed, params.direction_rad
        )));
    }
    let count = (2 * nx - 1) * (2 * ny - 1);
    engine.check_binding("the coefficient table", 4 * count as u64)?;
    let spectrum = &material.spectrum;
    let total =
        spectrum.glassy_compliance() + spectrum.terms.iter().map(|t| t.compliance).sum::<f64>();
    let mut instantaneous = spectrum.glassy_compliance();
    let mut active: Vec<f32> = Vec::new();
    for t in &spectrum.terms {
        let l = params.speed * t.time / cell;
        if l.is_nan() || l < RELAXED_CELLS {
            instantaneous += t.compliance;
        } else if l.is_finite() {
            active.extend([(t.compliance / total) as f32, (1.0 / l) as f32]);
        }
    }
    let terms = if active.is_empty() {
        vec![0.0f32, 1.0]
    } else {
        active.clone()
    };
    let terms_buf = engine.storage_with("viscoslide creep terms", bytemuck::cast_slice(&terms));
    let out = engine.create_buffer(
        "viscoslide coefficient table",
        4 * count as u64,
        wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
    );
    let (s, c) = params.direction_rad.sin_cos();
    let snap = |x: f64| if x.abs() < 1e-15 { 0.0 } else { x };
    let groups = (count as u64).div_ceil(COEFF_WORKGROUP);
    let gx = groups.min(65_535);
    engine.dispatch(
        Kernel::Coefficients,
        &[&terms_buf, &out],
        Params {
            i: [nx as u32, ny as u32, (active.len() / 2) as u32, 0],
            j: [0; 4],
            f: [
                snap(c) as f32,
                snap(s) as f32,
                (instantaneous / total) as f32,
                0.0,
            ],
        },
        (gx as u32, groups.div_ceil(gx) as u32),
    );
    let dimensionless = engine.read_f32(&out, 0, count);
    let scale = material.composite_factor() / std::f64::consts::PI * cell * total;
    Ok(dimensionless.iter().map(|&v| scale * v as f64).collect())
}
