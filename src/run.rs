//! One steady-sliding solve from a configuration: build the material, the
//! surface and the coefficient tables, run the constrained iteration on a
//! backend, and compute the scalar results. Orchestration only: the numerics
//! live in `kernel`, `operator`, `solver` and `analysis`.

use std::time::Instant;

use serde::Serialize;

use crate::analysis::{self, ContactStatistics};
use crate::backend::gpu::engine::Engine;
use crate::backend::gpu::{coefficients, GpuBackend, GpuContext, GpuLevelTables, GpuOptions};
use crate::backend::{Backend, CpuBackend};
use crate::config::{Formulation, LoadedConfig, MeshKind};
use crate::error::{Error, Result};
use crate::kernel::{Axis, KernelParams, Layer, SlidingKernel};
use crate::material::Material;
use crate::mesh::{AdaptiveParams, MeshReport};
use crate::operator::{AdaptiveOperator, LevelTables, OffsetTable, SpectralPeriodic, ToeplitzFft};
use crate::solver::{self, ContactSolution, Control, Observer, SolveInfo, SolverParams};
use crate::surface::HeightMap;

/// Everything one solve needs, checked.
#[derive(Debug, Clone)]
pub struct SolveSetup {
    pub material: Material,
    pub surface: HeightMap,
    pub control: Control,
    /// Sliding speed [m/s].
    pub speed: f64,
    /// Sliding direction \[rad\] from +x.
    pub direction_rad: f64,
    pub layer: Option<Layer>,
    pub params: SolverParams,
    pub formulation: Formulation,
    /// Uniform grid or adaptive quadtree (non-periodic formulation).
    pub mesh: MeshKind,
    /// Controls of the adaptive mesh.
    pub adaptive: AdaptiveParams,
    /// Grids of the coarse-to-fine cascade at most (uniform CPU grids).
    pub cascade_levels: usize,
    /// Seed of a generated surface.
    pub seed: Option<u64>,
    /// The merged configuration document.
    pub document: toml::Table,
    /// `[analysis]` settings.
    pub analysis: Option<crate::config::AnalysisConfig>,
}

/// Scalar and field results of a solve.
#[derive(Debug, Clone)]
pub struct SolveOutcome {
    pub solution: ContactSolution,
    pub info: SolveInfo,
    pub stats: ContactStatistics,
    /// `mu = -F_T / F_N` from the exact-work stencil (paper Eq. 9).
    pub friction_coefficient: f64,
    /// `mu` from the dissipated power (Appendix A3-A4).
    pub friction_coefficient_dissipation: f64,
    pub backend: String,
    pub timings: Timings,
    /// Cells solved for: `nx ny` on the uniform grid, the mesh's cells on
    /// the adaptive one.
    pub unknowns: usize,
    /// The adaptive mesh, when one was used.
    pub mesh: Option<MeshReport>,
}

/// Wall-clock split of a solve \[s\].
#[derive(Debug, Clone, Copy, Serialize, Default)]
pub struct Timings {
    pub coefficients_s: f64,
    pub operator_setup_s: f64,
    pub iteration_s: f64,
    pub analysis_s: f64,
    pub total_s: f64,
}

fn invalid(msg: impl Into<String>) -> Error {
    Error::Invalid(msg.into())
}

impl SolveSetup {
    /// Read and check the `[material]`, `[surface]`, `[loading]`, `[solver]`
    /// and optional `[layer]` sections.
    pub fn from_config(cfg: &LoadedConfig) -> Result<Self> {
        let material = cfg.material()?.build(&cfg.base_dir)?;
        let surface_cfg = cfg.surface()?;
        let sc = cfg.config.solver.clone().unwrap_or_default();
        let restart = sc.restart.unwrap_or(SolverParams::default().restart);
        // Refuse grids that cannot fit before generating them.
        if let Some(gp) = surface_cfg.generate_params()? {
            check_memory(gp.nx, gp.ny, restart)?;
        }
        let surface = surface_cfg.load(&cfg.base_dir)?;
        check_memory(surface.nx, surface.ny, restart)?;
        let seed = surface_cfg.generate.as_ref().map(|g| g.seed.unwrap_or(0));
        let loading = cfg.config.loading.clone().ok_or_else(|| {
            invalid(format!(
                "{}: section [loading] is required (normal_load or mean_pressure, and speed or xi)",
                cfg.path.display()
            ))
        })?;
        let area0 = surface.length_x() * surface.length_y();
        let control = match (loading.normal_load, loading.mean_pressure, loading.approach) {
            (Some(f), None, None) => Control::Load(f),
            (None, Some(p), None) => Control::Load(p * area0),
            (None, None, Some(d)) => Control::Approach(d),
            (None, None, None) => {
                return Err(invalid(
                    "[loading] needs one of normal_load (N), mean_pressure (Pa) or approach (m)",
                ))
            }
            _ => return Err(invalid(
                "[loading] give only one of normal_load (N), mean_pressure (Pa) and approach (m)",
            )),
        };
        match control {
            Control::Load(f) if !(f.is_finite() && f > 0.0) => {
                return Err(invalid(format!(
                    "[loading] the normal load must be positive, got {f} N"
                )))
            }
            Control::Approach(d) if !(d.is_finite() && d > 0.0) => {
                return Err(invalid(format!(
                    "[loading] approach must be positive, got {d} m"
                )))
            }
            _ => {}
        }
        let speed = match (loading.speed, loading.xi) {
            (Some(v), None) => v,
            (None, Some(xi)) => {
                let terms = &material.spectrum.terms;
                if terms.len() != 1 {
                    return Err(invalid(format!(
                        "[loading] xi = v tau / L needs a single-relaxation material (this one has {} creep terms); give speed (m/s)",
                        terms.len()
                    )));
                }
                xi * surface.length_x() / terms[0].time
            }
            (None, None) => return Err(invalid("[loading] needs speed (m/s) or xi (v tau / L)")),
            _ => return Err(invalid("[loading] give only one of speed (m/s) and xi")),
        };
        if speed.is_nan() || speed < 0.0 {
            return Err(invalid(format!(
                "[loading] speed must be >= 0, got {speed} m/s"
            )));
        }
        let direction_rad = loading.direction_deg.unwrap_or(0.0).to_radians();
        if !direction_rad.is_finite() {
            return Err(invalid("[loading] direction_deg must be finite"));
        }
        let defaults = SolverParams::default();
        let params = SolverParams {
            tolerance: sc.tolerance.unwrap_or(defaults.tolerance),
            max_iterations: sc.max_iterations.unwrap_or(defaults.max_iterations),
            max_matvecs: sc.max_matvecs.unwrap_or(defaults.max_matvecs),
            restart: sc.restart.unwrap_or(defaults.restart),
            precondition: sc.precondition.unwrap_or(defaults.precondition),
        };
        if !(params.tolerance > 0.0 && params.tolerance < 1.0) {
            return Err(invalid(format!(
                "[solver] tolerance must be in (0, 1), got {}",
                params.tolerance
            )));
        }
        let layer = cfg.config.layer.as_ref().map(|l| l.build()).transpose()?;
        let formulation = sc.formulation.unwrap_or_default();
        if layer.is_some() && formulation == Formulation::Periodic {
            return Err(invalid(
                "[layer] is not supported with [solver] formulation = \"periodic\" (use \"non_periodic\")",
            ));
        }
        let mesh = sc.mesh.unwrap_or_default();
        if mesh == MeshKind::Adaptive && formulation == Formulation::Periodic {
            return Err(invalid(
                "[solver] mesh = \"adaptive\" needs formulation = \"non_periodic\" (the periodic formulation is spectral)",
            ));
        }
        let ad = AdaptiveParams::default();
        let adaptive = match &sc.adaptive {
            Some(c) => AdaptiveParams {
                max_level: c.max_level.unwrap_or(ad.max_level),
                initial_fraction: c.initial_fraction.unwrap_or(ad.initial_fraction),
                margin: c.margin.unwrap_or(ad.margin),
                max_rounds: c.max_rounds.unwrap_or(ad.max_rounds),
            },
            None => ad,
        };
        adaptive.check().map_err(invalid)?;
        if sc.cascade_levels == Some(0) {
            return Err(invalid(
                "[solver] cascade_levels must be at least 1 (1: the fine grid only)",
            ));
        }
        if sc.adaptive.is_some() && mesh != MeshKind::Adaptive {
            return Err(invalid(
                "[solver.adaptive] is given but [solver] mesh is not \"adaptive\"",
            ));
        }
        let setup = Self {
            material,
            surface,
            control,
            speed,
            direction_rad,
            layer,
            params,
            formulation,
            mesh,
            adaptive,
            cascade_levels: sc.cascade_levels.unwrap_or(CASCADE_LEVELS),
            seed,
            document: cfg.document.clone(),
            analysis: cfg.config.analysis.clone(),
        };
        Ok(setup)
    }

    /// `xi = v tau / L` for single-relaxation materials.
    pub fn xi(&self) -> Option<f64> {
        match self.material.spectrum.terms.as_slice() {
            [t] => Some(self.speed * t.time / self.surface.length_x()),
            _ => None,
        }
    }

    /// The steady-sliding kernel of this material, speed, direction and
    /// layer (paper Eq. 4-5).
    pub fn sliding_kernel(&self) -> Result<SlidingKernel> {
        Ok(SlidingKernel::new(
            &self.material,
            KernelParams {
                speed: self.speed,
                direction_rad: self.direction_rad,
                layer: self.layer,
            },
        )?)
    }

    /// Gap profile `g = max(z) - z` (physics.md section 1).
    pub fn gap_profile(&self) -> Vec<f64> {
        let zmax = self
            .surface
            .heights
            .iter()
            .cloned()
            .fold(f64::NEG_INFINITY, f64::max);
        self.surface.heights.iter().map(|z| zmax - z).collect()
    }
}

/// Bytes the CPU path needs for an `nx x ny` grid, roughly: padded FFT
/// buffers and coefficient tables (about 40 grid vectors) plus the Krylov
/// basis of `restart + 1` vectors.
pub fn memory_estimate(nx: usize, ny: usize, restart: usize) -> u64 {
    let n = (nx as u64).saturating_mul(ny as u64);
    n.saturating_mul(8 * (48 + restart as u64))
}

fn check_memory(nx: usize, ny: usize, restart: usize) -> Result<()> {
    let need = memory_estimate(nx, ny, restart);
    if let Some(avail) = available_memory() {
        if need > avail {
            return Err(invalid(format!(
                "a {nx} x {ny} grid needs about {:.1} GiB of memory, but only {:.1} GiB is available",
                need as f64 / (1u64 << 30) as f64,
                avail as f64 / (1u64 << 30) as f64
            )));
        }
    }
    Ok(())
}

fn available_memory() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

/// Solve on the CPU backend (the reference path).
pub fn solve_cpu(setup: &SolveSetup, observer: &mut dyn Observer) -> Result<SolveOutcome> {
    if setup.formulation == Formulation::Periodic {
        return solve_cpu_periodic(setup, observer);
    }
    if setup.mesh == MeshKind::Adaptive {
        return solve_cpu_adaptive(setup, observer);
    }
    let t0 = Instant::now();
    let (nx, ny, a) = (setup.surface.nx, setup.surface.ny, setup.surface.cell_size);
    let kernel = setup.sliding_kernel()?;
    let table = kernel.table(nx, ny, a);
    let t_coeff = t0.elapsed().as_secs_f64();
    let mut fine_table = Some(table);
    let (solution, info, t_iter) = iterate_cascade(setup, observer, |nx, ny, a| {
        let table = match fine_table.take() {
            Some(t) if t.nx == nx && t.ny == ny => t,
            _ => kernel.table(nx, ny, a),
        };
        let tab = OffsetTable {
            nx,
            ny,
            values: &table.values,
        };
        let l00 = tab.get(0, 0);
        (
            CpuBackend::new(ToeplitzFft::new(tab).with_preconditioner()),
            l00,
        )
    })?;
    let t_setup = 0.0;
    let split = (t_coeff, Some(t_setup), t_iter);
    finish(
        setup,
        &kernel,
        solution,
        info,
        "cpu".into(),
        None,
        t0,
        split,
    )
}

/// Solve on the adaptive quadtree mesh ([`crate::mesh`]; physics.md
/// section 7) with the pairwise CPU operator: level tables once, then
/// solve-certify-refine rounds. The fields come back on the fine grid, so
/// friction and statistics are computed exactly as for the uniform grid.
fn solve_cpu_adaptive(setup: &SolveSetup, observer: &mut dyn Observer) -> Result<SolveOutcome> {
    let t0 = Instant::now();
    let plan = AdaptivePlan::new(setup)?;
    let t_coeff = t0.elapsed().as_secs_f64();
    let mut t_iter = 0.0;
    let result = crate::mesh::solve_adaptive(
        &setup.gap_profile(),
        plan.tables.clone(),
        &plan.params,
        setup.params.tolerance,
        |mesh, g_mesh, start, tol| {
            let t = Instant::now();
            let mut backend = CpuBackend::new(AdaptiveOperator::new(plan.tables.clone(), mesh));
            let r = plan.solve_round(&mut backend, setup, g_mesh, start, tol, observer);
            t_iter += t.elapsed().as_secs_f64();
            r
        },
    )
    .map_err(|e| invalid(e.to_string()))?;
    plan.outcome(
        setup,
        result,
        "cpu (adaptive mesh)".into(),
        t0,
        t_coeff,
        t_iter,
    )
}

/// What both adaptive executors share: the kernel, the level tables of the
/// fine grid (also the certificate's), the self coefficient and the mesh
/// controls clamped to the grid.
struct AdaptivePlan {
    kernel: SlidingKernel,
    tables: std::sync::Arc<LevelTables>,
    l00: f64,
    params: AdaptiveParams,
}

impl AdaptivePlan {
    fn new(setup: &SolveSetup) -> Result<Self> {
        let (nx, ny, a) = (setup.surface.nx, setup.surface.ny, setup.surface.cell_size);
        let kernel = setup.sliding_kernel()?;
        let max_level = setup.adaptive.max_level.min(max_level_for(nx, ny));
        let tables = std::sync::Arc::new(LevelTables::new(&kernel, nx, ny, a, max_level)?);
        let l00 = tables.coefficient(0, 0, 0);
        let params = AdaptiveParams {
            max_level,
            ..setup.adaptive
        };
        Ok(Self {
            kernel,
            tables,
            l00,
            params,
        })
    }

    /// One round's constrained iteration on `backend` (the mesh's operator)
    /// at the round's tolerance `tol`.
    fn solve_round<B: Backend>(
        &self,
        backend: &mut B,
        setup: &SolveSetup,
        g_mesh: &[f64],
        start: Option<&solver::WarmStart>,
        tol: f64,
        observer: &mut dyn Observer,
    ) -> std::result::Result<(ContactSolution, SolveInfo), solver::SolverError> {
        let a = setup.surface.cell_size;
        solver::solve_from(
            backend,
            g_mesh,
            a * a,
            self.l00,
            setup.control,
            &SolverParams {
                tolerance: tol,
                ..setup.params.clone()
            },
            start,
            observer,
        )
    }

    /// Friction, statistics and timings of a finished adaptive solve.
    fn outcome(
        &self,
        setup: &SolveSetup,
        result: crate::mesh::AdaptiveSolution,
        backend: String,
        t0: Instant,
        t_coeff: f64,
        t_iter: f64,
    ) -> Result<SolveOutcome> {
        let (solution, info) = (result.solution, result.info);
        let split = (t_coeff, None, t_iter);
        finish(
            setup,
            &self.kernel,
            solution,
            info,
            backend,
            Some(result.report),
            t0,
            split,
        )
    }
}

/// Coarsest useful level: blocks no larger than the grid.
fn max_level_for(nx: usize, ny: usize) -> u8 {
    let m = nx.min(ny).max(1);
    (usize::BITS - 1 - m.leading_zeros()) as u8
}

/// Run the constrained iteration of `setup` on `backend` (`l00` the self
/// coefficient); returns the solution, its convergence report and the
/// iteration's wall time \[s\].
fn iterate<B: Backend>(
    setup: &SolveSetup,
    backend: &mut B,
    l00: f64,
    observer: &mut dyn Observer,
) -> Result<(ContactSolution, SolveInfo, f64)> {
    let a = setup.surface.cell_size;
    let t1 = Instant::now();
    let (solution, info) = solver::solve(
        backend,
        &setup.gap_profile(),
        a * a,
        l00,
        setup.control,
        &setup.params,
        observer,
    )?;
    Ok((solution, info, t1.elapsed().as_secs_f64()))
}

/// Grids of the coarse-to-fine cascade: the fine grid halved while even,
/// down to this many cells a side at least.
const CASCADE_COARSEST: usize = 64;
/// Grids of the cascade at most (the fine one included), by default.
const CASCADE_LEVELS: usize = 8;

/// The constrained iteration of `setup` as a coarse-to-fine cascade
/// ([`solver::solve_cascade`]) on CPU backends built by
/// `build(nx, ny, cell_size)` (returning the backend and its self
/// coefficient); the coarse grids' gap profiles are the fine one's 2 x 2
/// block means. Returns the solution, its convergence report and the
/// iteration's wall time \[s\] (coarse grids' setup included).
fn iterate_cascade<Op, F>(
    setup: &SolveSetup,
    observer: &mut dyn Observer,
    mut build: F,
) -> Result<(ContactSolution, SolveInfo, f64)>
where
    Op: crate::operator::GridOperator,
    F: FnMut(usize, usize, f64) -> (CpuBackend<Op>, f64),
{
    let (nx, ny, a) = (setup.surface.nx, setup.surface.ny, setup.surface.cell_size);
    let t1 = Instant::now();
    let shapes = solver::cascade::cascade_shapes(nx, ny, CASCADE_COARSEST, setup.cascade_levels);
    let mut gaps = vec![setup.gap_profile()];
    for w in shapes.windows(2).rev() {
        let (fx, fy) = w[1];
        let coarse = solver::cascade::restrict_mean(gaps.last().expect("fine gap"), fx, fy);
        gaps.push(coarse);
    }
    gaps.reverse();
    let levels = shapes.len();
    let (solution, info) = solver::solve_cascade(
        &shapes,
        |k, (lx, _ly)| {
            let cell = a * (nx / lx) as f64;
            let (backend, l00) = build(lx, shapes[k].1, cell);
            Ok(solver::CascadeLevel {
                backend,
                gap: std::mem::take(&mut gaps[k]),
                cell_area: cell * cell,
                self_coefficient: l00,
            })
        },
        setup.control,
        &setup.params,
        None,
        observer,
    )?;
    debug_assert_eq!(info.levels.len(), levels);
    Ok((solution, info, t1.elapsed().as_secs_f64()))
}

/// Solve a periodic cell spectrally (paper Appendix, Eq. A1-A2): the same
/// constrained iteration on the [`SpectralPeriodic`] operator; friction by
/// the spectral slope stencil and by the Fourier dissipation sum (A3-A4).
fn solve_cpu_periodic(setup: &SolveSetup, observer: &mut dyn Observer) -> Result<SolveOutcome> {
    let t0 = Instant::now();
    let (nx, ny, a) = (setup.surface.nx, setup.surface.ny, setup.surface.cell_size);
    let (m, v, dir) = (&setup.material, setup.speed, setup.direction_rad);
    let t_setup = 0.0;
    let (solution, info, t_iter) = iterate_cascade(setup, observer, |nx, ny, a| {
        let op = SpectralPeriodic::new(nx, ny, a, m, v, dir).with_preconditioner();
        let l00 = op.self_coefficient();
        (CpuBackend::new(op), l00)
    })?;
    let t2 = Instant::now();
    let stats = analysis::contact_statistics(&solution.pressure, &solution.contact, nx, ny, a);
    let load = stats.normal_load;
    let mut slope = SpectralPeriodic::sliding_slope(nx, ny, a, m, v, dir);
    let force = analysis::friction_force_stencil(&mut slope, &solution.pressure, a);
    let force_d = analysis::friction_force_periodic(&solution.pressure, nx, ny, a, m, v, dir);
    let t_an = t2.elapsed().as_secs_f64();
    Ok(SolveOutcome {
        solution,
        info,
        stats,
        friction_coefficient: -force / load,
        friction_coefficient_dissipation: -force_d / load,
        backend: "cpu".into(),
        unknowns: nx * ny,
        mesh: None,
        timings: Timings {
            coefficients_s: 0.0,
            operator_setup_s: t_setup,
            iteration_s: t_iter,
            analysis_s: t_an,
            total_s: t0.elapsed().as_secs_f64(),
        },
    })
}

/// Solve on the GPU backend (f32 on the device, [`crate::backend::gpu`]):
/// the coefficient table of a half-space is computed on the device
/// (`shaders/coefficients.wgsl`, about 4e-7 relative to the host table; a
/// finite layer's table on the host), its spectrum on the host in f64; the
/// contact iteration runs on `ctx`'s device, and the friction analysis uses
/// the downloaded pressure with the host's derivative tables, as in
/// [`solve_cpu`]. The GPU path implements the non-periodic formulation.
pub fn solve_gpu(
    setup: &SolveSetup,
    ctx: GpuContext,
    observer: &mut dyn Observer,
) -> Result<SolveOutcome> {
    if setup.formulation == Formulation::Periodic {
        return Err(invalid(
            "the GPU path solves the non-periodic formulation; use --backend cpu for formulation = \"periodic\"",
        ));
    }
    if setup.mesh == MeshKind::Adaptive {
        return solve_gpu_adaptive(setup, ctx, observer);
    }
    let t0 = Instant::now();
    let (nx, ny, a) = (setup.surface.nx, setup.surface.ny, setup.surface.cell_size);
    let kernel = setup.sliding_kernel()?;
    let mut engine = Engine::new(ctx);
    let table = match setup.layer {
        None => coefficients::coefficient_table(
            &mut engine,
            &setup.material,
            kernel.params(),
            nx,
            ny,
            a,
        )
        .map_err(|e| invalid(e.to_string()))?,
        Some(_) => kernel.table(nx, ny, a).values,
    };
    let t_coeff = t0.elapsed().as_secs_f64();
    let l00 = OffsetTable {
        nx,
        ny,
        values: &table,
    }
    .get(0, 0);
    let mut backend = GpuBackend::with_engine(engine, nx, ny, &table, GpuOptions::default())
        .map_err(|e| invalid(e.to_string()))?;
    let name = backend.name();
    let t_setup = t0.elapsed().as_secs_f64() - t_coeff;
    let (solution, info, t_iter) = iterate(setup, &mut backend, l00, observer)?;
    drop(backend);
    let split = (t_coeff, Some(t_setup), t_iter);
    finish(setup, &kernel, solution, info, name, None, t0, split)
}

/// The adaptive mesh on the GPU: the level tables are computed on the
/// device once (`shaders/level_table.wgsl`, `shaders/level_box_sum.wgsl`,
/// f32) and each round's contact iteration runs there with the pairwise
/// operator that reads them (`shaders/level_matvec.wgsl`); the certificate
/// of each round and the friction analysis use the host's f64 level tables,
/// as in [`solve_cpu`]. Half-spaces only.
fn solve_gpu_adaptive(
    setup: &SolveSetup,
    ctx: GpuContext,
    observer: &mut dyn Observer,
) -> Result<SolveOutcome> {
    if setup.layer.is_some() {
        return Err(invalid(
            "the GPU adaptive operator covers half-spaces only; use --backend cpu with [layer]",
        ));
    }
    let t0 = Instant::now();
    let plan = AdaptivePlan::new(setup)?;
    let mut eng = Engine::new(ctx);
    let (nx, ny) = plan.tables.shape();
    let tables = GpuLevelTables::new(
        &mut eng,
        &setup.material,
        plan.kernel.params(),
        nx,
        ny,
        plan.tables.cell_size(),
        plan.tables.max_level(),
    )
    .map_err(|e| invalid(e.to_string()))?;
    let t_coeff = t0.elapsed().as_secs_f64();
    let mut engine = Some(eng);
    let mut name = String::new();
    let mut t_iter = 0.0;
    let mut gpu_error: Option<String> = None;
    let result = crate::mesh::solve_adaptive(
        &setup.gap_profile(),
        plan.tables.clone(),
        &plan.params,
        setup.params.tolerance,
        |mesh, g_mesh, start, tol| {
            let t = Instant::now();
            let eng = engine.take().expect("engine returned after each round");
            let mut backend = match GpuBackend::with_level_tables(eng, &tables, mesh) {
                Ok(b) => b,
                Err(e) => {
                    gpu_error = Some(e.to_string());
                    return Err(solver::SolverError::Invalid(e.to_string()));
                }
            };
            name = backend.name();
            let r = plan.solve_round(&mut backend, setup, g_mesh, start, tol, observer);
            engine = Some(backend.into_engine());
            t_iter += t.elapsed().as_secs_f64();
            r
        },
    )
    .map_err(|e| invalid(gpu_error.clone().unwrap_or_else(|| e.to_string())))?;
    plan.outcome(
        setup,
        result,
        format!("{name} (adaptive mesh)"),
        t0,
        t_coeff,
        t_iter,
    )
}

/// The outcome of a non-periodic solve: friction by both routes on the
/// fine-grid fields, and the wall-clock split `(coefficients, operator
/// setup, iteration)` \[s\] since `t0`; an operator setup of `None` is the
/// time not accounted for otherwise (the adaptive mesh's rounds).
#[allow(clippy::too_many_arguments)]
fn finish(
    setup: &SolveSetup,
    kernel: &SlidingKernel,
    solution: ContactSolution,
    info: SolveInfo,
    backend: String,
    mesh: Option<MeshReport>,
    t0: Instant,
    (t_coeff, t_setup, t_iter): (f64, Option<f64>, f64),
) -> Result<SolveOutcome> {
    let t2 = Instant::now();
    let (mu, mu_d, stats) = friction_and_stats(setup, kernel, &solution)?;
    let t_an = t2.elapsed().as_secs_f64();
    let total = t0.elapsed().as_secs_f64();
    let unknowns = mesh
        .as_ref()
        .map_or(setup.surface.nx * setup.surface.ny, |m| m.unknowns);
    Ok(SolveOutcome {
        solution,
        info,
        stats,
        friction_coefficient: mu,
        friction_coefficient_dissipation: mu_d,
        backend,
        unknowns,
        mesh,
        timings: Timings {
            coefficients_s: t_coeff,
            operator_setup_s: t_setup.unwrap_or(total - t_coeff - t_iter - t_an),
            iteration_s: t_iter,
            analysis_s: t_an,
            total_s: total,
        },
    })
}

/// Friction by both routes and the contact statistics.
pub fn friction_and_stats(
    setup: &SolveSetup,
    kernel: &SlidingKernel,
    solution: &ContactSolution,
) -> Result<(f64, f64, ContactStatistics)> {
    let (nx, ny, a) = (setup.surface.nx, setup.surface.ny, setup.surface.cell_size);
    let stats = analysis::contact_statistics(&solution.pressure, &solution.contact, nx, ny, a);
    let load = stats.normal_load;
    if load.is_nan() || load <= 0.0 {
        return Err(invalid(
            "the solution carries no load: the surfaces do not touch",
        ));
    }
    let (c, s) = (setup.direction_rad.cos(), setup.direction_rad.sin());
    let mut force = 0.0;
    for (axis, w) in [(Axis::X, c), (Axis::Y, s)] {
        if w.abs() < 1e-15 {
            continue;
        }
        let d = kernel.derivative_table(nx, ny, a, axis);
        let mut op = ToeplitzFft::new(OffsetTable {
            nx,
            ny,
            values: &d.values,
        });
        force += w * analysis::friction_force_stencil(&mut op, &solution.pressure, a);
    }
    let force_d = analysis::friction::friction_force_dissipation_layered(
        &solution.pressure,
        nx,
        ny,
        a,
        &setup.material.spectrum,
        setup.material.poisson,
        setup.speed,
        setup.direction_rad,
        setup.layer.as_ref(),
    );
    Ok((-force / load, -force_d / load, stats))
}
