//! Who runs the iteration: the CPU reference path or a GPU device, and the
//! choice between them for `--backend auto | gpu | cpu`; the seam between
//! the operator layer and the executors: each executor turns an
//! [`OperatorDescription`] into its [`Backend`] (`Executes`). The only
//! module of `problem` that names the executors' concrete backends.

use std::marker::PhantomData;

use crate::backend::gpu::engine::Engine;
pub use crate::backend::gpu::mixed::DeviceTraffic;
use crate::backend::gpu::mixed::{impulse_response, wrapped_table, MixedOperator, TrafficLedger};
use crate::backend::gpu::{coefficients, GpuBackend, GpuContext, GpuLevelTables, GpuOptions};
use crate::backend::{Backend, BackendChoice, CpuBackend};
use crate::config::Precision;
use crate::error::{Error, Result};
use crate::mesh::QuadMesh;
use crate::operator::{
    AdaptiveOperator, GridOperator, OffsetTable, OperatorDescription, PeriodicResponse, Real,
    SpectralPeriodic, ToeplitzFft,
};
use crate::response::Grid;

use super::{invalid, Discretisation, Problem};

/// Who runs the iteration.
#[derive(Clone)]
pub enum Executor {
    /// The CPU reference path (rayon, rustfft), f64.
    Cpu,
    /// A GPU device (wgpu), f32 vectors.
    Gpu(GpuContext),
}

impl std::fmt::Debug for Executor {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Executor::Cpu => write!(f, "Executor::Cpu"),
            Executor::Gpu(ctx) => write!(f, "Executor::Gpu({})", ctx.adapter),
        }
    }
}

impl Executor {
    /// Resolve a backend choice for `problem`: `auto` takes a GPU when one
    /// exists, the problem fits on it and it is not emulated on the CPU;
    /// the CPU for `precision = "f64"`, any GPU that fits for `"f32"`.
    /// Returns the executor and a line saying which was picked and why.
    pub fn select(choice: BackendChoice, problem: &Problem) -> Result<(Executor, String)> {
        let (nx, ny) = (problem.surface.nx, problem.surface.ny);
        Ok(match choice {
            BackendChoice::Cpu => (Executor::Cpu, "backend: cpu".into()),
            BackendChoice::Gpu => {
                let ctx = GpuContext::open()?;
                let line = format!("backend: gpu, adapter {}", ctx.adapter);
                (Executor::Gpu(ctx), line)
            }
            // Only the CPU computes in f64.
            BackendChoice::Auto if problem.precision == Some(Precision::F64) => (
                Executor::Cpu,
                "backend: cpu (auto: precision = \"f64\")".into(),
            ),
            BackendChoice::Auto => match GpuContext::open()
                .and_then(|ctx| GpuBackend::check_fits(&ctx, nx, ny).map(|()| ctx))
            {
                // Only a GPU runs f32 alone, emulated or not.
                Ok(ctx) if problem.precision == Some(Precision::F32) => {
                    let line = format!(
                        "backend: gpu (auto: precision = \"f32\"), adapter {}",
                        ctx.adapter
                    );
                    (Executor::Gpu(ctx), line)
                }
                Ok(ctx) if ctx.adapter.device_type == "Cpu" => (
                    Executor::Cpu,
                    format!(
                        "backend: cpu (auto: the only adapter, {}, is emulated on the CPU and slower than the CPU backend; --backend gpu forces it)",
                        ctx.adapter
                    ),
                ),
                Ok(ctx) => {
                    let line = format!("backend: gpu (auto), adapter {}", ctx.adapter);
                    (Executor::Gpu(ctx), line)
                }
                Err(e) => (Executor::Cpu, format!("backend: cpu (auto: {e})")),
            },
        })
    }
}

/// An executor: turns operator descriptions into backends of its own kind.
/// The cascade, the adaptive rounds, the refinement and the smooth-pad
/// reference are written once against it.
pub(crate) trait Executes {
    /// The backend every description becomes.
    type Backend: Backend;

    /// The executor as `summary.json` names it (`"cpu"`, `"gpu: ADAPTER"`).
    fn name(&self) -> String;

    /// Whether its products run on a device (f32), so that a finite pad's
    /// solve that does not converge there is repeated on the host in f64
    /// (`smooth_pad.rs`). Default: no.
    fn on_device(&self) -> bool {
        false
    }

    /// The relative rounding of its backends' vectors (f64's on the CPU,
    /// whatever its transforms; f32's on a device).
    fn epsilon(&self) -> f64 {
        f64::EPSILON
    }

    /// Work done once for the fine grid's description before the
    /// iteration (coefficient tables, timed as such): the next
    /// [`Executes::build`] of the same grid uses it. Default: nothing.
    fn prepare(&mut self, description: &OperatorDescription<'_>) -> Result<()> {
        let _ = description;
        Ok(())
    }

    /// The backend of `description` and its self coefficient `L_00`
    /// (`mesh`: the round's quadtree for [`OperatorDescription::Levels`]).
    fn build(
        &mut self,
        description: &OperatorDescription<'_>,
        mesh: Option<&QuadMesh>,
    ) -> Result<(Self::Backend, f64)>;

    /// The device round trips of its backends' products so far (a GPU's
    /// mixed precision, whose products cross the bus); `None` where
    /// products stay where the iteration runs. Default: `None`.
    fn device_traffic(&self) -> Option<DeviceTraffic> {
        None
    }

    /// Take back a backend after its solve (the GPU keeps its engine for
    /// the next round). Default: drop it.
    fn release(&mut self, backend: Self::Backend) {
        drop(backend);
    }
}

/// The CPU executor with transforms in `T` (f32: with f64 products for the
/// refinement, [`Backend::refines`]).
pub(crate) struct CpuExecutor<T> {
    /// The fine grid's host table, computed by [`Executes::prepare`].
    fine: Option<crate::kernel::CoefficientTable>,
    precision: PhantomData<T>,
}

impl<T> CpuExecutor<T> {
    pub(crate) fn new() -> Self {
        Self {
            fine: None,
            precision: PhantomData,
        }
    }
}

impl<T: Real> Executes for CpuExecutor<T> {
    type Backend = CpuBackend<Box<dyn GridOperator>>;

    fn name(&self) -> String {
        "cpu".into()
    }

    fn prepare(&mut self, description: &OperatorDescription<'_>) -> Result<()> {
        if let Some(table) = description.host_table() {
            self.fine = Some(table?);
        }
        Ok(())
    }

    fn build(
        &mut self,
        description: &OperatorDescription<'_>,
        mesh: Option<&QuadMesh>,
    ) -> Result<(Self::Backend, f64)> {
        let (op, l00) = self.operator(description, mesh)?;
        Ok((CpuBackend::new(op), l00))
    }
}

impl<T: Real> CpuExecutor<T> {
    /// The operator of `description` with transforms in `T` and its self
    /// coefficient `L_00` ([`Executes::build`] without the backend).
    fn operator(
        &mut self,
        description: &OperatorDescription<'_>,
        mesh: Option<&QuadMesh>,
    ) -> Result<(Box<dyn GridOperator>, f64)> {
        Ok(match description {
            OperatorDescription::Toeplitz { kernel, grid } => {
                let table = self.table(kernel, grid)?;
                let (op, l00) = toeplitz::<T>(grid, &table.values);
                (Box::new(op), l00)
            }
            OperatorDescription::Periodic { response, grid } => {
                let op = SpectralPeriodic::<T>::in_precision(
                    grid,
                    response,
                    PeriodicResponse::Displacement,
                )
                .with_preconditioner()
                .with_exact();
                let l00 = op.self_coefficient();
                (Box::new(op), l00)
            }
            OperatorDescription::Levels { tables, .. } => {
                let mesh = mesh.ok_or_else(|| invalid("the level tables need a mesh"))?;
                let l00 = tables.coefficient(0, 0, 0);
                (
                    Box::new(AdaptiveOperator::new(std::sync::Arc::clone(tables), mesh)),
                    l00,
                )
            }
        })
    }

    /// The fine grid's host table of `kernel` on `grid` when
    /// [`Executes::prepare`] made it, otherwise a new one.
    fn table(
        &mut self,
        kernel: &crate::kernel::SlidingKernel,
        grid: &Grid,
    ) -> Result<crate::kernel::CoefficientTable> {
        Ok(match self.fine.take() {
            Some(t) if (t.nx, t.ny) == grid.size() => t,
            other => {
                self.fine = other;
                kernel.table(grid)?
            }
        })
    }
}

/// The Toeplitz-FFT operator of `grid` from its offset table (`values` as
/// in [`OffsetTable`]) with its preconditioners and exact products in
/// precision `T`, and the self coefficient `L_00`.
fn toeplitz<T: Real>(grid: &Grid, values: &[f64]) -> (ToeplitzFft<T>, f64) {
    let (nx, ny) = grid.size();
    let tab = OffsetTable { nx, ny, values };
    let op = ToeplitzFft::<T>::in_precision(tab)
        .with_preconditioner()
        .with_exact();
    (op, tab.get(0, 0))
}

/// The GPU executor of [`Precision::F32`] (every vector on the device in
/// f32): a half-space's coefficient tables
/// computed on the device (`shaders/coefficients.wgsl`, about 4e-7
/// relative to the host table; a finite layer's on the host, its spectrum
/// on the host in f64), the level tables of the adaptive mesh on the
/// device (`shaders/level_table.wgsl`, `shaders/level_box_sum.wgsl`;
/// half-spaces only). The non-periodic formulation only.
pub(crate) struct GpuExecutor {
    ctx: GpuContext,
    /// Right-precondition the uniform grid's inner solves.
    precondition: bool,
    /// The fine grid's engine and table ([`Executes::prepare`]).
    fine: Option<(Engine, Vec<f64>, (usize, usize))>,
    /// The adaptive mesh's device level tables ([`Executes::prepare`]).
    levels: Option<GpuLevelTables>,
    /// The engine of the adaptive rounds, between rounds.
    engine: Option<Engine>,
}

impl GpuExecutor {
    /// The f32 executor of `ctx` for `problem`, or the one-line refusal of
    /// what the device does not run: the periodic formulation, the adaptive
    /// mesh over a layer.
    pub(crate) fn for_problem(ctx: &GpuContext, problem: &Problem) -> Result<Self> {
        match problem.discretisation() {
            Discretisation::Periodic => return Err(periodic_refused()),
            Discretisation::Adaptive if problem.layer.is_some() => return Err(invalid(
                "the GPU adaptive operator covers half-spaces only; use --backend cpu with [layer]",
            )),
            Discretisation::Uniform | Discretisation::Adaptive => {}
        }
        Ok(Self {
            ctx: ctx.clone(),
            precondition: problem.params.precondition,
            fine: None,
            levels: None,
            engine: None,
        })
    }

    /// The coefficient table of a Toeplitz description on `engine`: a
    /// half-space's on the device, a finite layer's on the host.
    fn table(
        engine: &mut Engine,
        kernel: &crate::kernel::SlidingKernel,
        grid: &Grid,
    ) -> Result<Vec<f64>> {
        Ok(match kernel.response().layer() {
            None => coefficients::coefficient_table(engine, kernel.response(), grid)?,
            Some(_) => kernel.table(grid)?.values,
        })
    }

    fn engine(&mut self) -> Engine {
        self.engine
            .take()
            .unwrap_or_else(|| Engine::new(self.ctx.clone()))
    }
}

impl Executes for GpuExecutor {
    type Backend = GpuBackend;

    fn name(&self) -> String {
        // As `Backend::name` of the GPU backend.
        format!("gpu: {}", self.ctx.adapter)
    }

    fn epsilon(&self) -> f64 {
        f32::EPSILON as f64
    }

    fn on_device(&self) -> bool {
        true
    }

    fn prepare(&mut self, description: &OperatorDescription<'_>) -> Result<()> {
        match description {
            OperatorDescription::Toeplitz { kernel, grid } => {
                let mut engine = Engine::new(self.ctx.clone());
                let table = Self::table(&mut engine, kernel, grid)?;
                self.fine = Some((engine, table, grid.size()));
            }
            OperatorDescription::Levels { kernel, tables } => {
                let mut engine = self.engine();
                let (nx, ny) = tables.shape();
                self.levels = Some(GpuLevelTables::new(
                    &mut engine,
                    kernel.response(),
                    nx,
                    ny,
                    tables.cell_size(),
                    tables.max_level(),
                )?);
                self.engine = Some(engine);
            }
            OperatorDescription::Periodic { .. } => return Err(periodic_refused()),
        }
        Ok(())
    }

    fn build(
        &mut self,
        description: &OperatorDescription<'_>,
        mesh: Option<&QuadMesh>,
    ) -> Result<(Self::Backend, f64)> {
        match description {
            OperatorDescription::Toeplitz { kernel, grid } => {
                // The fine grid's engine and table are made once; the
                // coarse grids' on demand, each level on an engine of its
                // own.
                let (engine, table) = match self.fine.take() {
                    Some((engine, table, shape)) if shape == grid.size() => (engine, table),
                    other => {
                        self.fine = other;
                        let mut engine = Engine::new(self.ctx.clone());
                        let table = Self::table(&mut engine, kernel, grid)?;
                        (engine, table)
                    }
                };
                let (nx, ny) = grid.size();
                let l00 = OffsetTable {
                    nx,
                    ny,
                    values: &table,
                }
                .get(0, 0);
                let options = GpuOptions {
                    preconditioner: self.precondition,
                    ..GpuOptions::default()
                };
                let backend = GpuBackend::with_engine(engine, nx, ny, &table, options)?;
                Ok((backend, l00))
            }
            OperatorDescription::Levels { kernel, tables } => {
                let mesh = mesh.ok_or_else(|| invalid("the level tables need a mesh"))?;
                if self.levels.is_none() {
                    self.prepare(&OperatorDescription::Levels { kernel, tables })?;
                }
                let engine = self.engine();
                let levels = self.levels.as_ref().expect("prepared above");
                let backend = GpuBackend::with_level_tables(engine, levels, mesh)?;
                Ok((backend, tables.coefficient(0, 0, 0)))
            }
            OperatorDescription::Periodic { .. } => Err(periodic_refused()),
        }
    }

    fn release(&mut self, backend: GpuBackend) {
        self.engine = Some(backend.into_engine());
    }
}

/// The GPU executor of [`Precision::Mixed`]: the CPU's mixed-precision
/// iteration ([`CpuBackend`], f64 vectors on the host, every GMRES
/// restart's residual in f64, [`Backend::refines`]) over an operator whose
/// f32 products (the Krylov products and the preconditioner) run on the
/// device and whose exact products are the host's f64 operator of the same
/// description ([`MixedOperator`]). The device's table is the host's f64
/// coefficient table rounded to f32 (the non-periodic formulation) or the
/// periodic cell's circulant written as an offset table
/// ([`wrapped_table`]); its preconditioner is the device backend's (the
/// inverse of the padded circulant or of T. Chan's circulant), or on a
/// periodic cell the host's inverse multiplier as a second circulant on
/// the device.
/// Uniform grids (one or a cascade), either formulation.
pub(crate) struct GpuMixedExecutor {
    ctx: GpuContext,
    /// Right-precondition the inner solves.
    precondition: bool,
    /// The host's f64 operators (and the fine grid's table, prepared).
    host: CpuExecutor<f64>,
    /// The round trips of every operator it builds.
    traffic: TrafficLedger,
}

impl GpuMixedExecutor {
    /// The mixed executor of `ctx` for `problem`, or the one-line refusal
    /// of the adaptive mesh (whose rounds have no mixed iteration).
    pub(crate) fn for_problem(ctx: &GpuContext, problem: &Problem) -> Result<Self> {
        if problem.discretisation() == Discretisation::Adaptive {
            return Err(invalid(
                "[solver] precision = \"mixed\" runs on uniform grids; use precision = \"f32\" on the GPU's adaptive mesh or --backend cpu",
            ));
        }
        Ok(Self {
            ctx: ctx.clone(),
            precondition: problem.params.precondition,
            host: CpuExecutor::new(),
            traffic: TrafficLedger::default(),
        })
    }
}

impl Executes for GpuMixedExecutor {
    type Backend = CpuBackend<MixedOperator>;

    fn name(&self) -> String {
        format!("gpu: {}", self.ctx.adapter)
    }

    fn on_device(&self) -> bool {
        true
    }

    fn device_traffic(&self) -> Option<DeviceTraffic> {
        Some(*self.traffic.lock().unwrap_or_else(|e| e.into_inner()))
    }

    fn prepare(&mut self, description: &OperatorDescription<'_>) -> Result<()> {
        self.host.prepare(description)
    }

    fn build(
        &mut self,
        description: &OperatorDescription<'_>,
        mesh: Option<&QuadMesh>,
    ) -> Result<(Self::Backend, f64)> {
        let (nx, ny) = description.shape();
        let options = GpuOptions {
            preconditioner: self.precondition,
            ..GpuOptions::default()
        };
        let engine = Engine::new(self.ctx.clone());
        let (op, l00) = match description {
            OperatorDescription::Toeplitz { kernel, grid } => {
                let table = self.host.table(kernel, grid)?;
                let device = GpuBackend::with_engine(engine, nx, ny, &table.values, options)?;
                let (exact, l00) = toeplitz::<f64>(grid, &table.values);
                (MixedOperator::new(device, Box::new(exact)), l00)
            }
            OperatorDescription::Periodic { .. } => {
                // The circulant and the host's inverse multiplier (its
                // preconditioner), each as the offset table of its
                // circulant on the device.
                let (mut exact, l00) = self.host.operator(description, mesh)?;
                let n = nx * ny;
                let c = impulse_response(n, |x, y| exact.apply_exact(x, y));
                let k = self
                    .precondition
                    .then(|| impulse_response(n, |x, y| exact.precondition(x, y)));
                let plain = GpuOptions::default();
                let table = wrapped_table(nx, ny, &c);
                let device = GpuBackend::with_engine(engine, nx, ny, &table, plain)?;
                let mut op = MixedOperator::new(device, exact);
                if let Some(k) = k {
                    let engine = Engine::new(self.ctx.clone());
                    let table = wrapped_table(nx, ny, &k);
                    op = op.with_inverse(GpuBackend::with_engine(engine, nx, ny, &table, plain)?);
                }
                (op, l00)
            }
            OperatorDescription::Levels { .. } => {
                return Err(invalid(
                    "[solver] precision = \"mixed\" runs on uniform grids, not the adaptive mesh",
                ))
            }
        };
        Ok((
            CpuBackend::new(op.recording_into(self.traffic.clone())),
            l00,
        ))
    }
}

/// The GPU executor's refusal of the periodic formulation in f32. An
/// explicit `precision = "f32"` is refused with the periodic formulation
/// by [`Problem::check`]; this is the route of `gpu_refine = false`, whose
/// own fix is to drop it (`precision = "mixed"` beside it disagrees).
pub(crate) fn periodic_refused() -> Error {
    invalid(
        "[solver] gpu_refine = false keeps the GPU's f32 iteration, which solves the non-periodic formulation; for formulation = \"periodic\" remove gpu_refine (a GPU then runs precision = \"mixed\") or use --backend cpu",
    )
}

/// A GPU's refusal of [`Precision::F64`].
pub(crate) fn gpu_f64_refused() -> Error {
    invalid(
        "[solver] precision = \"f64\": a GPU computes in f32; use precision = \"mixed\" (f32 products on the device, f64 residuals on the host) or --backend cpu",
    )
}

/// The CPU's refusal of [`Precision::F32`].
pub(crate) fn cpu_f32_refused() -> Error {
    invalid(
        "[solver] precision = \"f32\" is a GPU's f32 iteration alone; the CPU computes in \"f64\" or \"mixed\" (or use --backend gpu)",
    )
}
