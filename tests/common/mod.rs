//! Shared helpers for the integration tests.
#![allow(dead_code)]

pub mod domain;
pub mod gwy;
pub mod heating;

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use viscoslide::internals::backend::CpuBackend;
use viscoslide::internals::kernel::SlidingKernel;
use viscoslide::internals::operator::{OffsetTable, ToeplitzFft};
use viscoslide::internals::solver::{
    self, ContactProblem, ContactSolution, Control, SolveInfo, SolverParams,
};
use viscoslide::material::{CreepSpectrum, Material};
use viscoslide::response::{Grid, SlidingResponse};

/// The source tree the tests read configs and shaders from: the directory
/// named by `VISCOSLIDE_SOURCE_DIR` when set (a test executable run from a
/// copy of the repository at another path, as `scripts/gpu-run` does), else
/// the one the tests were built in.
pub fn source_dir() -> std::path::PathBuf {
    match std::env::var_os("VISCOSLIDE_SOURCE_DIR") {
        Some(dir) if !dir.is_empty() => std::path::PathBuf::from(dir),
        _ => std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")),
    }
}

/// The paper's single-relaxation material: E_inf = 1e7 Pa, E_inf/E0 = 3,
/// creep time 0.01 s, nu = 0.5.
pub fn paper_material() -> Material {
    Material::new(
        CreepSpectrum::standard_linear_solid(1e7 / 3.0, 1e7, 0.01).unwrap(),
        0.5,
    )
    .unwrap()
}

/// Band-limited isotropic random surface evaluated as a trigonometric sum,
/// so the same surface can be sampled on grids of any resolution: modes with
/// integer wave numbers `1 <= |k| <= kmax` (in units of 2 pi / L), amplitude
/// `|k|^-(1+H)`, random phases; scaled to the rms slope `slope`. Returns
/// heights at cell centres, C order, axis 0 = x.
pub fn trig_surface(
    n: usize,
    length: f64,
    kmax: i32,
    hurst: f64,
    slope: f64,
    seed: u64,
) -> Vec<f64> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut modes = Vec::new();
    for kx in -kmax..=kmax {
        for ky in 0..=kmax {
            if ky == 0 && kx <= 0 {
                continue;
            }
            let k2 = (kx * kx + ky * ky) as f64;
            if k2 > (kmax * kmax) as f64 {
                continue;
            }
            let amp = k2.powf(-(1.0 + hurst) / 2.0);
            modes.push((
                kx as f64,
                ky as f64,
                amp,
                rng.random_range(0.0..std::f64::consts::TAU),
            ));
        }
    }
    let q = std::f64::consts::TAU / length;
    // rms slope of sum A cos(q k.x + phi) is sqrt(sum A^2 q^2 |k|^2 / 2).
    let s2: f64 = modes
        .iter()
        .map(|m| m.2 * m.2 * q * q * (m.0 * m.0 + m.1 * m.1) / 2.0)
        .sum();
    let scale = slope / s2.sqrt();
    let a = length / n as f64;
    let mut z = vec![0.0; n * n];
    for i in 0..n {
        for j in 0..n {
            let (x, y) = ((i as f64 + 0.5) * a, (j as f64 + 0.5) * a);
            z[i * n + j] = scale
                * modes
                    .iter()
                    .map(|m| m.2 * (q * (m.0 * x + m.1 * y) + m.3).cos())
                    .sum::<f64>();
        }
    }
    z
}

/// `g = max(z) - z`.
pub fn gap_of(z: &[f64]) -> Vec<f64> {
    let m = z.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
    z.iter().map(|v| m - v).collect()
}

/// Solve on an `n x n` grid of side `length` at `speed`; returns the
/// solution, its info and the kernel.
pub fn solve_grid(
    material: &Material,
    heights: &[f64],
    n: usize,
    length: f64,
    speed: f64,
    control: Control,
) -> (ContactSolution, SolveInfo, SlidingKernel) {
    let a = length / n as f64;
    let kernel =
        SlidingKernel::new(&SlidingResponse::new(material, speed, 0.0, None).unwrap()).unwrap();
    let table = kernel.table(&Grid::square(n, n, a).unwrap()).unwrap();
    let tab = OffsetTable {
        nx: n,
        ny: n,
        values: &table.values,
    };
    let mut be = CpuBackend::new(ToeplitzFft::new(tab));
    let (sol, info) = solver::solve(
        &mut be,
        ContactProblem::new(gap_of(heights), a * a, tab.get(0, 0), control),
        &SolverParams::default(),
        None,
        &mut solver::Silent,
    )
    .unwrap();
    (sol, info, kernel)
}

/// The rough patch of the GPU solve comparisons: `n x n` cells on
/// L = 0.01 m, [`trig_surface`] with 16 modes, H = 0.8, rms slope 0.02
/// (seed 11), pressed by 3 kPa nominal, the paper's material
/// ([`paper_material`]) sliding at `speed` along +x.
pub struct RoughPatch {
    pub material: Material,
    pub kernel: SlidingKernel,
    /// Cell side \[m\].
    pub a: f64,
    /// The offset table of the grid (`(2n - 1)^2` coefficients).
    pub table: Vec<f64>,
    /// Its self coefficient `L_00`.
    pub l00: f64,
    /// The gap profile of the surface.
    pub gap: Vec<f64>,
    /// The load: 3 kPa on the patch.
    pub control: Control,
}

impl RoughPatch {
    /// The solver's default solve of the patch on `backend`.
    pub fn solve<B: viscoslide::internals::backend::Backend>(
        &self,
        backend: &mut B,
    ) -> (ContactSolution, SolveInfo) {
        solver::solve(
            backend,
            ContactProblem::new(&self.gap, self.a * self.a, self.l00, self.control),
            &SolverParams::default(),
            None,
            &mut solver::Silent,
        )
        .unwrap()
    }
}

pub fn rough_patch(n: usize, speed: f64) -> RoughPatch {
    let length = 0.01;
    let a = length / n as f64;
    let material = paper_material();
    let kernel =
        SlidingKernel::new(&SlidingResponse::new(&material, speed, 0.0, None).unwrap()).unwrap();
    let table = kernel
        .table(&Grid::square(n, n, a).unwrap())
        .unwrap()
        .values;
    let l00 = OffsetTable {
        nx: n,
        ny: n,
        values: &table,
    }
    .get(0, 0);
    RoughPatch {
        material,
        kernel,
        a,
        table,
        l00,
        gap: gap_of(&trig_surface(n, length, 16, 0.8, 0.02, 11)),
        control: Control::Load(3e3 * length * length),
    }
}

/// Friction coefficients `(stencil, dissipation)` of a solution along +x.
pub fn friction(
    kernel: &SlidingKernel,
    material: &Material,
    sol: &ContactSolution,
    n: usize,
    a: f64,
    speed: f64,
) -> (f64, f64) {
    use viscoslide::internals::analysis;
    use viscoslide::internals::kernel::Axis;
    let d = kernel
        .derivative_table(&Grid::square(n, n, a).unwrap(), Axis::X)
        .unwrap();
    let mut op = ToeplitzFft::new(OffsetTable {
        nx: n,
        ny: n,
        values: &d.values,
    });
    let load: f64 = sol.pressure.iter().sum::<f64>() * a * a;
    let fs = analysis::friction_force_stencil(&mut op, &sol.pressure, a * a);
    let fd = analysis::friction_force_dissipation(
        &sol.pressure,
        &Grid::square(n, n, a).unwrap(),
        &SlidingResponse::new(material, speed, 0.0, None).unwrap(),
    );
    (-fs / load, -fd / load)
}

/// Open a GPU for a test or explain why not. With `REQUIRE_GPU=1` a missing
/// adapter is a failure (CI installs lavapipe); otherwise the caller skips
/// with the printed reason.
pub fn gpu_context() -> Option<viscoslide::internals::backend::gpu::GpuContext> {
    gpu_context_with_limits(None, None)
}

/// As [`gpu_context`] with the largest storage binding and buffer lowered
/// (`GpuContext::open_with_limits`).
pub fn gpu_context_with_limits(
    binding: Option<u64>,
    buffer: Option<u64>,
) -> Option<viscoslide::internals::backend::gpu::GpuContext> {
    match viscoslide::internals::backend::gpu::GpuContext::open_with_limits(binding, buffer) {
        Ok(c) => Some(c),
        Err(e) => {
            if std::env::var("REQUIRE_GPU").is_ok_and(|v| v == "1") {
                panic!("REQUIRE_GPU=1 but no usable GPU: {e}");
            }
            eprintln!("skipping GPU test: {e}");
            None
        }
    }
}

/// A rough periodic or non-periodic 64^2 problem of the SLS material
/// solved to 1e-10 in `precision` at `speed` m/s, `extra` lines added to
/// its `[solver]` section (the mixed-precision tests of the CPU and the
/// GPU).
pub fn mixed_case(
    formulation: &str,
    precision: &str,
    speed: f64,
    extra: &str,
) -> viscoslide::problem::Problem {
    let text = MIXED_CASE
        .replace("FORMULATION", formulation)
        .replace("PRECISION", precision)
        .replace("SPEED", &format!("{speed:e}"))
        .replace("EXTRA", extra);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("c.toml");
    std::fs::write(&path, text).unwrap();
    viscoslide::problem::Problem::from_config(&viscoslide::config::load(&path, &[]).unwrap())
        .unwrap()
}

const MIXED_CASE: &str = r#"
[material]
model = "sls"
relaxed_modulus = 3.3333333333333335e6
glassy_modulus = 1.0e7
creep_time = 0.01

[surface.generate]
n = 64
length = 0.01
hurst = 0.8
scales = 6
rms_slope = 0.05
seed = 7

[loading]
mean_pressure = 2.0e4
speed = SPEED

[solver]
tolerance = 1e-10
formulation = "FORMULATION"
precision = "PRECISION"
EXTRA

[analysis]
enabled = false
"#;
