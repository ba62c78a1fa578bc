//! What the GPU coefficient kernels share (`shaders/coefficients.wgsl`,
//! `shaders/adaptive_*.wgsl`, `shaders/level_*.wgsl`): the classification of
//! the creep terms of one (material, speed, direction) into the uniforms the
//! shaders read ([`plan`]), the workgroup grid of a large dispatch
//! ([`grid`]), and the f32 read-back scaled to m/Pa in f64
//! ([`read_scaled`]).

use super::context::GpuError;
use super::engine::{Buf, Engine};
use crate::response::SlidingResponse;

/// Memory lengths below this many cells act as relaxed compliance (the
/// neglected part is about `l |grad L| / L`, below 1e-7).
pub const RELAXED_CELLS: f64 = 1e-7;

/// Workgroups of one dispatch along x (the WebGPU minimum limit).
pub const MAX_GROUPS_X: u64 = 65_535;

/// The creep terms and scales of one (material, speed, direction) at the
/// length unit `unit` \[m\].
pub struct Plan {
    /// `(w_k, 1 / l_k)` of the active terms, `l_k` in units of `unit`.
    pub terms: Vec<f32>,
    pub count: u32,
    /// Glassy-plus-relaxed compliance fraction at `unit`.
    pub instantaneous: f32,
    /// `(1 - nu^2)/pi * unit * (total compliance)` [m/Pa].
    pub scale: f64,
    pub e: [f32; 2],
}

impl Plan {
    /// Bytes of the creep terms' buffer (for the binding checks).
    pub fn terms_bytes(&self) -> u64 {
        std::mem::size_of_val(&self.terms[..]) as u64
    }
}

/// Classify the creep terms of `response` with lengths in units of
/// `unit` \[m\] (half-spaces only).
pub fn plan(response: &SlidingResponse, unit: f64) -> Result<Plan, GpuError> {
    if response.layer().is_some() {
        return Err(GpuError::Invalid(
            "the GPU coefficient kernels cover half-spaces only; finite-thickness coefficients are computed on the host".into(),
        ));
    }
    let total = response.relaxed_compliance();
    let mut instantaneous = response.glassy_compliance();
    let mut terms: Vec<f32> = Vec::new();
    for (compliance, l) in response.creep_lengths(unit) {
        // Relaxed at the unit (the finest side) means relaxed at every
        // larger source; the kernel classifies the rest per source size.
        if l.is_nan() || l < RELAXED_CELLS {
            instantaneous += compliance;
        } else if l.is_finite() {
            terms.extend([(compliance / total) as f32, (1.0 / l) as f32]);
        }
    }
    let count = (terms.len() / 2) as u32;
    if terms.is_empty() {
        terms = vec![0.0, 1.0];
    }
    let (ex, ey) = response.direction();
    Ok(Plan {
        terms,
        count,
        instantaneous: (instantaneous / total) as f32,
        scale: response.prefactor() * unit * total,
        e: [ex as f32, ey as f32],
    })
}

/// Workgroup grid `(x, y)` of `groups` workgroups.
pub fn grid(groups: u64) -> (u32, u32) {
    let groups = groups.max(1);
    let gx = groups.min(MAX_GROUPS_X);
    (gx as u32, groups.div_ceil(gx) as u32)
}

/// Read `count` f32 values of `buf` back and scale them by `scale` in f64:
/// a dimensionless table turned into m/Pa.
pub fn read_scaled(engine: &mut Engine, buf: &Buf, count: usize, scale: f64) -> Vec<f64> {
    engine
        .read_f32(buf, 0, count)
        .iter()
        .map(|&v| scale * v as f64)
        .collect()
}
