//! `[solver]` and `[solver.adaptive]`: iteration controls, formulation and mesh.

use serde::{Deserialize, Serialize};

/// Which discretisation of the half-space the solver uses. Typed so that a
/// non-periodic run can never silently become periodic.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum Formulation {
    /// Finite rough pad on an infinite solid: exact linear convolution (paper Eq. 6-7).
    #[default]
    NonPeriodic,
    /// Periodic cell solved spectrally (paper Appendix, Eq. A1-A2): the
    /// domain must be much longer than the relaxation length `v tau`.
    Periodic,
}

/// Arithmetic of the contact iteration (physics.md section 13): one choice
/// that every executor honours or refuses in one line
/// (`Problem::precision_on`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum Precision {
    /// Every product and vector in f64 (the CPU).
    #[default]
    F64,
    /// A low-precision iteration refined in f64 to the requested
    /// tolerance: on the CPU the spectra, FFT buffers and the
    /// preconditioner in f32 for the Krylov products, and the residual of
    /// every GMRES restart, the gap, the contact decisions and the load
    /// balance in f64 (GMRES-IR: the f64 answer of the operator with its
    /// spectrum rounded to f32, about 1e-7 relative); on a GPU the f32
    /// iteration on the device, then the f64 iteration on the host from its
    /// answer (uniform grids).
    Mixed,
    /// The low-precision iteration alone: a GPU's f32 answer (residual about
    /// 1e-5 to 1e-4), not refined.
    F32,
}

impl Precision {
    /// The name used in configurations and reports.
    pub fn name(self) -> &'static str {
        match self {
            Self::F64 => "f64",
            Self::Mixed => "mixed",
            Self::F32 => "f32",
        }
    }
}

/// `[solver]`: iteration controls.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub struct SolverConfig {
    /// Relative complementarity residual (default 1e-8).
    pub tolerance: Option<f64>,
    /// Active-set iterations (default 200).
    pub max_iterations: Option<usize>,
    /// Operator applications (default 50000).
    pub max_matvecs: Option<usize>,
    /// GMRES restart length (default 30).
    pub restart: Option<usize>,
    /// Discretisation (default `non_periodic`).
    pub formulation: Option<Formulation>,
    /// Mesh of the non-periodic formulation (default `uniform`).
    pub mesh: Option<MeshKind>,
    /// `[solver.adaptive]`: controls of `mesh = "adaptive"`.
    pub adaptive: Option<AdaptiveConfig>,
    /// Right-precondition the inner solves with the operator's approximate
    /// inverse (default true; uniform CPU grids).
    pub precondition: Option<bool>,
    /// Grids of the coarse-to-fine cascade at most, the fine one included
    /// (default 8; 1: solve on the fine grid only; uniform CPU grids).
    pub cascade_levels: Option<usize>,
    /// `"f64"`, `"mixed"` or `"f32"` ([`Precision`]; physics.md section
    /// 13) on every executor. Default: the executor's own, f64 on the CPU;
    /// on a GPU (f32 on the device) `"mixed"` on a uniform grid (unless
    /// `gpu_refine = false`) and `"f32"` on the adaptive mesh.
    pub precision: Option<Precision>,
    /// The older spelling of a GPU's precision where `precision` is not
    /// given: true (default) `"mixed"`, the device's f32 answer refined in
    /// f64 on the host on a uniform grid; false `"f32"`, the device's answer
    /// alone (residual about 1e-5 to 1e-4). The CPU ignores it; given
    /// beside a `precision` of the other GPU kind (`"mixed"` with false,
    /// `"f32"` with true) it is refused.
    pub gpu_refine: Option<bool>,
}

/// The mesh the non-periodic problem is solved on.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum MeshKind {
    /// Every cell at the surface's resolution: Toeplitz operator, FFT matvec.
    #[default]
    Uniform,
    /// Quadtree: fine cells where contact is possible or found, coarse
    /// elsewhere (physics.md section 7; [`crate::mesh`]).
    Adaptive,
}

/// `[solver.adaptive]` (defaults in `crate::problem::AdaptiveParams`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub struct AdaptiveConfig {
    /// Coarsest cells are `2^max_level` fine cells a side (default 5).
    pub max_level: Option<u8>,
    /// Area fraction, the highest part of the surface, meshed fine from the
    /// start (default 0.1).
    pub initial_fraction: Option<f64>,
    /// Fine cells added around each refinement (default 1).
    pub margin: Option<usize>,
    /// Solve-certify-refine rounds allowed (default 12).
    pub max_rounds: Option<usize>,
}
