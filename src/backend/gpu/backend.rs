//! [`GpuBackend`]: the [`Backend`] of the contact iteration with every vector
//! resident on the device (f32). Per GMRES step the host reads back only
//! reduction partials (one small buffer per batched reduction, finished in
//! f64); per outer iteration it reads back the new contact-set size. The
//! contact set is compacted on the device (`compact_*.wgsl`: block counts,
//! a one-workgroup scan, an ordered write).
//!
//! The operator is the padded FFT convolution of a uniform grid
//! ([`GpuBackend::new`]) or the matrix-free operator of a non-uniform mesh:
//! from device-computed level tables on a quadtree
//! ([`GpuBackend::with_level_tables`], what `solve` uses) or with every
//! coefficient evaluated per pair for cells anywhere
//! ([`GpuBackend::with_adaptive`]).
//!
//! Precision: vectors and the matvec are f32 (relative matvec error about
//! 1e-6); [`Backend::epsilon`] reports `f32::EPSILON`, and the solver clamps
//! its tolerances to it.
//!
//! Over 600 lines: the whole `Backend` trait on device vectors (one dispatch per method, the kernels in `shaders/`), beside the vector and index types it uses.

use rayon::prelude::*;

use super::adaptive::{AdaptiveMatvec, MeshCells};
use super::context::{check_binding_count, GpuContext, GpuError};
use super::engine::{groups_for, Buf, Engine, Kernel, Params, WORKGROUP};
use super::fft::FftMatvec;
pub use super::fft::{FftChoice, SpectrumPrecision};
use super::level_tables::{GpuLevelTables, LevelMatvec};
use super::pool::{Pool, Slot};
use crate::backend::Backend;
use crate::response::SlidingResponse;

/// Workgroups of a grid-stride reduction at most (partials per slot).
const REDUCE_GROUPS: usize = 256;
/// Reduction slots of the partials buffer.
const REDUCE_SLOTS: usize = 64;

/// Modes of the circulant below this fraction of its largest multiplier
/// are clamped there in the preconditioner (as on the host).
const PRECONDITIONER_FLOOR: f64 = 1e-6;

/// Options of [`GpuBackend`].
#[derive(Debug, Clone, Copy, Default)]
pub struct GpuOptions {
    /// Storage of the kernel spectrum.
    pub spectrum: SpectrumPrecision,
    /// The FFT of the uniform-grid matvec.
    pub fft: FftChoice,
    /// Provide the inverse of the padded circulant as the preconditioner of
    /// the uniform-grid operator ([`crate::backend::Backend::precondition`],
    /// as [`crate::operator::ToeplitzFft::with_preconditioner`] on the host;
    /// f32 spectrum only), and the inverse of T. Chan's circulant for
    /// contact sets above half the grid.
    pub preconditioner: bool,
}

/// A device vector: a pool buffer of grid capacity and a logical length.
pub struct GpuVector {
    slot: Slot,
    len: usize,
}

impl GpuVector {
    pub fn len(&self) -> usize {
        self.len
    }

    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    fn buf(&self) -> &Buf {
        self.slot.buf()
    }
}

/// Positions of a contact set on the device (u32).
pub struct GpuIndex {
    slot: Slot,
    len: usize,
}

/// The influence operator of a [`GpuBackend`].
enum Operator {
    /// Uniform grid: the padded FFT convolution of an offset table.
    Fft(FftMatvec),
    /// Non-uniform mesh: coefficients evaluated on the fly.
    Adaptive(AdaptiveMatvec),
    /// Quadtree mesh: coefficients read from level tables.
    Levels(LevelMatvec),
}

/// The GPU executor of one grid and one influence operator.
pub struct GpuBackend {
    engine: Engine,
    pool: Pool,
    matvec: Operator,
    n: usize,
    partials: Buf,
    offsets: Buf,
    blocks: usize,
    /// Two grid vectors for the products on a contact set (scattered input,
    /// full product) and the damped set update, taken at first use.
    set_work: Option<(GpuVector, GpuVector)>,
}

impl GpuBackend {
    /// The executor of an `nx x ny` grid whose operator has the offset
    /// table `table` (`(2nx-1) x (2ny-1)` values, layout of
    /// [`crate::operator::OffsetTable`]).
    pub fn new(
        ctx: GpuContext,
        nx: usize,
        ny: usize,
        table: &[f64],
        options: GpuOptions,
    ) -> Result<Self, GpuError> {
        Self::with_engine(Engine::new(ctx), nx, ny, table, options)
    }

    /// As [`Self::new`] on an engine already in use (e.g. one that has just
    /// computed the table with [`super::coefficients::coefficient_table`]).
    pub fn with_engine(
        mut engine: Engine,
        nx: usize,
        ny: usize,
        table: &[f64],
        options: GpuOptions,
    ) -> Result<Self, GpuError> {
        let n = nx * ny;
        check_vector(
            &engine.ctx.device.limits(),
            &engine.ctx.adapter.name,
            nx,
            ny,
        )?;
        let floor = (options.preconditioner && options.spectrum == SpectrumPrecision::F32)
            .then_some(PRECONDITIONER_FLOOR);
        let matvec = FftMatvec::new(
            &mut engine,
            nx,
            ny,
            table,
            options.spectrum,
            options.fft,
            floor,
        )?;
        Ok(Self::assemble(engine, n, Operator::Fft(matvec)))
    }

    /// The engine back (its pipelines and device stay usable), e.g. to build
    /// the operator of a refined mesh.
    pub fn into_engine(self) -> Engine {
        self.engine
    }

    /// The executor of a non-uniform mesh of square cells (`grid_len` = the
    /// number of cells, vectors in cell order) whose operator is
    /// [`AdaptiveMatvec`] (paper Eq. 7, coefficients of Eq. 4 and Eq. 6
    /// evaluated on the device for every matvec): unknowns are `x_S = p_S s_S^2 / a^2` (`a` the
    /// finest side), so the solver's `cell_area` is `a^2` and its
    /// `self_coefficient` that of a fine cell. Half-spaces only.
    pub fn with_adaptive(
        mut engine: Engine,
        response: &SlidingResponse,
        cells: &MeshCells,
    ) -> Result<Self, GpuError> {
        let matvec = AdaptiveMatvec::new(&mut engine, response, cells)?;
        let n = matvec.len();
        Ok(Self::assemble(engine, n, Operator::Adaptive(matvec)))
    }

    /// The executor of a quadtree mesh (`grid_len` = its cells, in mesh
    /// order) whose operator is [`LevelMatvec`]: one read of the level
    /// tables `tables` (built on this engine for the mesh's fine grid) per
    /// (target, nonzero source) pair. Unknowns and scaling as in
    /// [`Self::with_adaptive`].
    pub fn with_level_tables(
        mut engine: Engine,
        tables: &GpuLevelTables,
        mesh: &crate::mesh::QuadMesh,
    ) -> Result<Self, GpuError> {
        let matvec = LevelMatvec::new(&mut engine, tables, mesh)?;
        let n = matvec.len();
        Ok(Self::assemble(engine, n, Operator::Levels(matvec)))
    }

    fn assemble(mut engine: Engine, n: usize, matvec: Operator) -> Self {
        let usage = wgpu::BufferUsages::STORAGE
            | wgpu::BufferUsages::COPY_SRC
            | wgpu::BufferUsages::COPY_DST;
        let partials = engine.create_buffer(
            "viscoslide reduction partials",
            (4 * REDUCE_GROUPS * REDUCE_SLOTS) as u64,
            usage,
        );
        let blocks = n.div_ceil(WORKGROUP as usize);
        let offsets = engine.create_buffer(
            "viscoslide compaction offsets",
            4 * (blocks as u64 + 1),
            usage,
        );
        Self {
            engine,
            pool: Pool::new(4 * n as u64),
            matvec,
            n,
            partials,
            offsets,
            blocks,
            set_work: None,
        }
    }

    /// Whether an `nx x ny` grid fits the device: its grid vectors
    /// (`check_vector`) and the FFT's work buffers and spectrum (`8 mx
    /// (my / 2 + 1)` bytes on the workgroup-memory path, `8 mx my` on the
    /// radix-2 fallback; bound in windows when larger than one binding),
    /// [`super::fft::check_device`].
    pub fn check_fits(ctx: &GpuContext, nx: usize, ny: usize) -> Result<(), GpuError> {
        let limits = ctx.device.limits();
        let path = super::fft_plan::Path::for_device(&limits);
        check_vector(&limits, &ctx.adapter.name, nx, ny)?;
        super::fft::check_device(&limits, &ctx.adapter.name, nx, ny, path).map(|_| ())
    }

    /// The dispatch plan of the uniform-grid matvec (`None` for the mesh
    /// operators).
    pub fn fft_plan(&self) -> Option<&super::fft_plan::MatvecPlan> {
        match &self.matvec {
            Operator::Fft(m) => Some(m.plan()),
            Operator::Adaptive(_) | Operator::Levels(_) => None,
        }
    }

    /// Device buffers created by this backend's engine, by array:
    /// `(label, buffers, bytes)` ([`Engine::allocations`]); after a solve
    /// the grid vectors' count is the most the iteration held at once.
    pub fn allocations(&self) -> Vec<(String, usize, u64)> {
        self.engine.allocations()
    }

    /// The adapter the backend runs on.
    pub fn adapter(&self) -> &super::AdapterSummary {
        &self.engine.ctx.adapter
    }

    /// Padded FFT shape `(mx, my)`; `(0, 0)` for the adaptive operator.
    pub fn padded_shape(&self) -> (usize, usize) {
        match &self.matvec {
            Operator::Fft(m) => (m.mx, m.my),
            Operator::Adaptive(_) | Operator::Levels(_) => (0, 0),
        }
    }

    /// The contact set of the grid cells `cells` (sorted, each below
    /// [`Backend::grid_len`]) as a device index: one upload of `|cells|`
    /// u32 positions (an executor whose sets are made on the host,
    /// [`super::mixed::MixedOperator`]).
    pub(crate) fn index_from(&mut self, cells: &[usize]) -> GpuIndex {
        self.check_len(cells.len());
        let slot = self.pool.take(&mut self.engine);
        let positions: Vec<u32> = cells
            .par_iter()
            .map(|&c| {
                assert!(c < self.n, "cell {c} on a grid of {}", self.n);
                c as u32
            })
            .collect();
        self.engine
            .write(slot.buf(), 0, bytemuck::cast_slice(&positions));
        GpuIndex {
            slot,
            len: cells.len(),
        }
    }

    /// Wait until the device has finished all submitted work.
    pub fn synchronize(&mut self) {
        self.engine.flush();
        let _ = self
            .engine
            .ctx
            .device
            .poll(wgpu::PollType::wait_indefinitely());
    }

    fn reduce_groups(len: usize) -> usize {
        len.div_ceil(WORKGROUP as usize).clamp(1, REDUCE_GROUPS)
    }

    /// Sums (f64) of `slots` consecutive reduction slots of `groups` partials.
    fn finish(&mut self, slots: usize, groups: usize) -> Vec<f64> {
        let p = self.engine.read_f32(&self.partials, 0, slots * groups);
        p.chunks_exact(groups)
            .map(|c| c.iter().map(|&v| v as f64).sum())
            .collect()
    }

    fn elementwise(&mut self, kernel: Kernel, bufs: &[&Buf], len: usize, f: [f32; 4]) {
        if len == 0 {
            return;
        }
        self.engine.dispatch(
            kernel,
            bufs,
            Params {
                i: [len as u32, 0, 0, 0],
                f,
                ..Default::default()
            },
            groups_for(len as u64),
        );
    }

    /// The two grid work vectors of the set products (allocated once).
    fn take_work(&mut self) -> (GpuVector, GpuVector) {
        match self.set_work.take() {
            Some(w) => w,
            None => {
                let n = self.n;
                (self.zeros(n), self.zeros(n))
            }
        }
    }

    fn check_len(&self, len: usize) {
        assert!(
            len <= self.n,
            "vector of {len} entries on a grid of {}",
            self.n
        );
    }
}

/// A grid vector (`4 nx ny` bytes) must fit one buffer; larger than one
/// storage binding, it is bound in windows ([`super::split`]), and the
/// kernel that binds the most vectors (`dot.wgsl`: five and the partials)
/// must stay within the device's bindings per kernel (lavapipe: 32).
fn check_vector(
    limits: &wgpu::Limits,
    adapter: &str,
    nx: usize,
    ny: usize,
) -> Result<(), GpuError> {
    let need = 4 * (nx as u64) * (ny as u64);
    let what = format!("a {nx} x {ny} grid vector");
    if need > limits.max_buffer_size {
        return Err(GpuError::TooLarge {
            what,
            need,
            limit: limits.max_buffer_size,
            per: "per buffer",
            adapter: adapter.to_string(),
        });
    }
    let binding = limits
        .max_storage_buffer_binding_size
        .min(limits.max_buffer_size);
    let windows = if need <= binding {
        1
    } else {
        let align = limits.min_storage_buffer_offset_alignment.into();
        super::split::windows(need, super::split::window_bytes(binding, align))
    };
    // Five vectors and the reduction partials (split too under a binding
    // limit below their 64 KiB, which only tests set).
    let partials = (4 * REDUCE_GROUPS * REDUCE_SLOTS) as u64;
    let bindings = 5 * windows + partials.div_ceil(binding);
    check_binding_count(&what, bindings, limits, adapter)
}

impl Backend for GpuBackend {
    type Vector = GpuVector;
    type Index = GpuIndex;
    /// A grid vector of 0.0 / 1.0.
    type Mask = GpuVector;

    fn name(&self) -> String {
        format!("gpu: {}", self.engine.ctx.adapter)
    }

    fn epsilon(&self) -> f64 {
        f32::EPSILON as f64
    }

    fn grid_len(&self) -> usize {
        self.n
    }

    fn zeros(&mut self, len: usize) -> GpuVector {
        self.check_len(len);
        let slot = self.pool.take(&mut self.engine);
        self.engine.clear(slot.buf());
        GpuVector { slot, len }
    }

    fn resize(&mut self, v: &mut GpuVector, len: usize) {
        self.check_len(len);
        v.len = len;
    }

    fn upload(&mut self, host: &[f64], dst: &mut GpuVector) {
        assert_eq!(host.len(), dst.len, "upload length");
        self.engine.write_f64_as_f32(dst.buf(), host);
    }

    fn download(&mut self, src: &GpuVector, host: &mut [f64]) {
        assert_eq!(host.len(), src.len, "download length");
        self.engine.read_f32_as_f64(src.buf(), host);
    }

    fn mask_from(&mut self, host: &[f64]) -> GpuVector {
        let mut mask = self.zeros(host.len());
        self.upload(host, &mut mask);
        mask
    }

    fn copy(&mut self, src: &GpuVector, dst: &mut GpuVector) {
        assert_eq!(src.len, dst.len, "copy length");
        self.engine
            .copy(src.buf(), 0, dst.buf(), 0, 4 * src.len as u64);
    }

    fn apply(&mut self, x: &GpuVector, y: &mut GpuVector) {
        assert_eq!(x.len, self.n);
        assert_eq!(y.len, self.n);
        match &mut self.matvec {
            Operator::Fft(m) => m.record_apply(&mut self.engine, x.buf(), y.buf()),
            Operator::Adaptive(m) => m.record_apply(&mut self.engine, x.buf(), y.buf()),
            Operator::Levels(m) => m.record_apply(&mut self.engine, x.buf(), y.buf()),
        }
    }

    fn has_preconditioner(&self) -> bool {
        matches!(&self.matvec, Operator::Fft(m) if m.has_inverse())
    }

    fn set_contact_fraction(&mut self, fraction: f64) {
        if let Operator::Fft(m) = &mut self.matvec {
            m.set_contact_fraction(&mut self.engine, fraction);
        }
    }

    fn precondition(&mut self, x: &GpuVector, y: &mut GpuVector) {
        assert_eq!(x.len, self.n);
        assert_eq!(y.len, self.n);
        match &mut self.matvec {
            Operator::Fft(m) if m.has_inverse() => {
                m.record_inverse(&mut self.engine, x.buf(), y.buf())
            }
            _ => self.copy(x, y),
        }
    }

    fn apply_set(&mut self, index: &GpuIndex, x: &GpuVector, y: &mut GpuVector) {
        let (mut full, mut product) = self.take_work();
        self.scatter(index, x, &mut full);
        self.apply(&full, &mut product);
        self.gather(index, &product, y);
        self.set_work = Some((full, product));
    }

    fn apply_set_exact(&mut self, index: &GpuIndex, x: &GpuVector, y: &mut GpuVector) {
        self.apply_set(index, x, y);
    }

    fn precondition_set(&mut self, index: &GpuIndex, x: &GpuVector, y: &mut GpuVector) {
        let (mut full, mut product) = self.take_work();
        self.scatter(index, x, &mut full);
        self.precondition(&full, &mut product);
        self.gather(index, &product, y);
        self.set_work = Some((full, product));
    }

    fn dot(&mut self, a: &GpuVector, b: &GpuVector) -> f64 {
        let mut out = [0.0];
        self.dots(std::slice::from_ref(a), b, &mut out);
        out[0]
    }

    fn dots(&mut self, basis: &[GpuVector], w: &GpuVector, out: &mut [f64]) {
        let len = w.len;
        let groups = Self::reduce_groups(len);
        for (chunk, out_chunk) in basis.chunks(REDUCE_SLOTS).zip(out.chunks_mut(REDUCE_SLOTS)) {
            for (q, four) in chunk.chunks(4).enumerate() {
                let b: Vec<&Buf> = (0..4).map(|c| four[c.min(four.len() - 1)].buf()).collect();
                self.engine.dispatch(
                    Kernel::Dot,
                    &[b[0], b[1], b[2], b[3], w.buf(), &self.partials],
                    Params {
                        i: [len as u32, 4 * q as u32, groups as u32, four.len() as u32],
                        ..Default::default()
                    },
                    (groups as u32, 1),
                );
            }
            let sums = self.finish(chunk.len(), groups);
            out_chunk[..chunk.len()].copy_from_slice(&sums);
        }
    }

    fn axpy(&mut self, alpha: f64, x: &GpuVector, y: &mut GpuVector) {
        assert_eq!(x.len, y.len, "axpy length");
        self.elementwise(
            Kernel::Axpy,
            &[x.buf(), y.buf()],
            y.len,
            [alpha as f32, 0.0, 0.0, 0.0],
        );
    }

    fn combine(&mut self, coeffs: &[f64], basis: &[GpuVector], y: &mut GpuVector) {
        for (cs, four) in coeffs.chunks(4).zip(basis.chunks(4)) {
            let mut f = [0.0f32; 4];
            for (k, &c) in cs.iter().enumerate() {
                f[k] = c as f32;
            }
            let b: Vec<&Buf> = (0..4).map(|c| four[c.min(four.len() - 1)].buf()).collect();
            self.elementwise(
                Kernel::Combine,
                &[b[0], b[1], b[2], b[3], y.buf()],
                y.len,
                f,
            );
        }
    }

    fn scale(&mut self, alpha: f64, x: &mut GpuVector) {
        self.elementwise(
            Kernel::Scale,
            &[x.buf()],
            x.len,
            [alpha as f32, 0.0, 0.0, 0.0],
        );
    }

    fn add_scalar(&mut self, alpha: f64, x: &mut GpuVector) {
        self.elementwise(
            Kernel::AddScalar,
            &[x.buf()],
            x.len,
            [alpha as f32, 0.0, 0.0, 0.0],
        );
    }

    fn sum(&mut self, x: &GpuVector) -> f64 {
        let groups = Self::reduce_groups(x.len);
        self.engine.dispatch(
            Kernel::Sum,
            &[x.buf(), &self.partials],
            Params {
                i: [x.len as u32, 0, groups as u32, 0],
                ..Default::default()
            },
            (groups as u32, 1),
        );
        self.finish(1, groups)[0]
    }

    fn index_of(&mut self, mask: &GpuVector) -> GpuIndex {
        assert_eq!(mask.len, self.n, "index_of needs a grid mask");
        let slot = self.pool.take(&mut self.engine);
        let shape = Params {
            i: [self.n as u32, self.blocks as u32, 0, 0],
            ..Default::default()
        };
        let blocks = groups_for(self.blocks as u64 * WORKGROUP as u64);
        self.engine.dispatch(
            Kernel::CompactCount,
            &[mask.buf(), &self.offsets],
            shape,
            blocks,
        );
        self.engine.dispatch(
            Kernel::CompactScan,
            &[&self.offsets],
            Params {
                i: [self.blocks as u32, 0, 0, 0],
                ..Default::default()
            },
            (1, 1),
        );
        self.engine.dispatch(
            Kernel::CompactWrite,
            &[mask.buf(), &self.offsets, slot.buf()],
            shape,
            blocks,
        );
        let len = self.engine.read_u32(&self.offsets, self.blocks as u64) as usize;
        GpuIndex { slot, len }
    }

    fn index_len(&self, index: &GpuIndex) -> usize {
        index.len
    }

    fn gather(&mut self, index: &GpuIndex, full: &GpuVector, short: &mut GpuVector) {
        assert_eq!(short.len, index.len, "gather length");
        self.elementwise(
            Kernel::Gather,
            &[index.slot.buf(), full.buf(), short.buf()],
            index.len,
            [0.0; 4],
        );
    }

    fn scatter(&mut self, index: &GpuIndex, short: &GpuVector, full: &mut GpuVector) {
        assert_eq!(short.len, index.len, "scatter length");
        self.engine.clear(full.buf());
        self.elementwise(
            Kernel::Scatter,
            &[index.slot.buf(), short.buf(), full.buf()],
            index.len,
            [0.0; 4],
        );
    }

    fn gap(&mut self, g: &GpuVector, u: &GpuVector, delta: f64, out: &mut GpuVector) {
        self.elementwise(
            Kernel::Gap,
            &[g.buf(), u.buf(), out.buf()],
            out.len,
            [delta as f32, 0.0, 0.0, 0.0],
        );
    }

    fn update_active_set(
        &mut self,
        p: &GpuVector,
        gap: &GpuVector,
        mask: &mut GpuVector,
    ) -> (usize, usize) {
        let groups = Self::reduce_groups(mask.len);
        self.engine.dispatch(
            Kernel::ActiveSet,
            &[p.buf(), gap.buf(), mask.buf(), &self.partials],
            Params {
                i: [mask.len as u32, 0, groups as u32, 0],
                ..Default::default()
            },
            (groups as u32, 1),
        );
        let s = self.finish(2, groups);
        (s[0].round() as usize, s[1].round() as usize)
    }

    fn newton_set(
        &mut self,
        p: &GpuVector,
        gap: &GpuVector,
        stiffness: f64,
        mask: &mut GpuVector,
    ) -> (usize, usize) {
        // With w = p - k gap, "in: w > 0; out: -w < 0" is {p > k gap} for
        // every cell, whichever side it was on.
        let (mut w, mut minus_w) = self.take_work();
        self.copy(p, &mut w);
        self.axpy(-stiffness, gap, &mut w);
        self.copy(&w, &mut minus_w);
        self.scale(-1.0, &mut minus_w);
        let counts = self.update_active_set(&w, &minus_w, mask);
        self.set_work = Some((w, minus_w));
        counts
    }

    fn complementarity(&mut self, p: &GpuVector, gap: &GpuVector, stiffness: f64) -> (f64, f64) {
        let groups = Self::reduce_groups(p.len);
        self.engine.dispatch(
            Kernel::Complementarity,
            &[p.buf(), gap.buf(), &self.partials],
            Params {
                i: [p.len as u32, 0, groups as u32, 0],
                f: [stiffness as f32, 0.0, 0.0, 0.0],
                ..Default::default()
            },
            (groups as u32, 1),
        );
        let s = self.finish(2, groups);
        (s[0], s[1])
    }
}
