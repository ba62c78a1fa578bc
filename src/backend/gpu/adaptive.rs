//! Influence coefficients between square cells of different sizes, evaluated
//! on the device in f32 (`shaders/adaptive_coefficients.wgsl`,
//! `shaders/adaptive_matvec.wgsl`; paper Eq. 4 and Eq. 6, physics.md
//! section 3), and the matrix-free operator of a non-uniform mesh (paper
//! Eq. 7 with the coefficients computed on the fly).
//!
//! A source of side `s` under unit pressure displaces the point at offset `d`
//! from its centre by `K(d; s) = s T_s(d / s)` times
//! `(1 - nu^2)/pi * (total compliance)`, where `T_s` is the dimensionless
//! unit-cell coefficient with memory lengths `l_k / s` (CPU twin:
//! [`crate::kernel::SlidingKernel::coefficient`]). The creep terms are
//! classified as in [`super::plan::plan`], per source
//! size: memory lengths below `1e-7` source sides act as relaxed compliance,
//! infinite ones (`v = inf`) as glassy. Half-spaces only.
//!
//! The unknown of cell `S` is `x_S = p_S s_S^2 / a^2` (its force in units of
//! a fine cell's area, `a` the finest side), so the operator is
//! `y_T = sum_S K(x_T - x_S; s_S) x_S (a / s_S)^2`, collocated at cell
//! centres.

use super::context::GpuError;
use super::engine::{groups_for, Buf, Engine, Kernel, Params, WORKGROUP};
use super::plan::{grid, plan, read_scaled, MAX_GROUPS_X};
use crate::response::SlidingResponse;

/// Invocations per workgroup of the pair kernel (`PWG`).
const PAIR_WORKGROUP: u64 = 64;

/// Square cells of a non-uniform mesh: centres `(x, y)` and sides \[m\].
#[derive(Debug, Clone, Default, PartialEq)]
pub struct MeshCells {
    pub x: Vec<f64>,
    pub y: Vec<f64>,
    pub side: Vec<f64>,
}

impl MeshCells {
    /// Number of cells.
    pub fn len(&self) -> usize {
        self.side.len()
    }

    pub fn is_empty(&self) -> bool {
        self.side.is_empty()
    }

    /// The finest side `a` \[m\] (the smallest; NaN for an empty mesh).
    pub fn fine_side(&self) -> f64 {
        if self.side.is_empty() {
            return f64::NAN;
        }
        self.side.iter().copied().fold(f64::INFINITY, f64::min)
    }

    fn check(&self) -> Result<(), GpuError> {
        let n = self.side.len();
        if n == 0 || self.x.len() != n || self.y.len() != n {
            return Err(GpuError::Invalid(format!(
                "mesh with {} x, {} y and {} sides (need the same positive count)",
                self.x.len(),
                self.y.len(),
                n
            )));
        }
        if n > u32::MAX as usize {
            return Err(GpuError::Invalid(format!("{n} cells exceed u32 indices")));
        }
        for k in 0..n {
            let s = self.side[k];
            if !(s.is_finite() && s > 0.0 && self.x[k].is_finite() && self.y[k].is_finite()) {
                return Err(GpuError::Invalid(format!(
                    "cell {k}: centre ({}, {}) m, side {s} m",
                    self.x[k], self.y[k]
                )));
            }
        }
        Ok(())
    }
}

/// `K(t_i - (x_i, y_i); s_i)` [m/Pa] for each pair of a target point
/// `targets[i]` \[m\] and a source cell `sources[i] = (x, y, side)` \[m\] under
/// unit pressure (paper Eq. 4 and Eq. 6), computed on the device in f32.
/// CPU twin: `SlidingKernel::coefficient(dx, dy, side, side).total()`.
pub fn pair_coefficients(
    engine: &mut Engine,
    response: &SlidingResponse,
    targets: &[(f64, f64)],
    sources: &[(f64, f64, f64)],
) -> Result<Vec<f64>, GpuError> {
    if targets.len() != sources.len() {
        return Err(GpuError::Invalid(format!(
            "{} targets and {} sources (one source per target)",
            targets.len(),
            sources.len()
        )));
    }
    if sources.is_empty() {
        return Ok(Vec::new());
    }
    let cells = MeshCells {
        x: sources.iter().map(|s| s.0).collect(),
        y: sources.iter().map(|s| s.1).collect(),
        side: sources.iter().map(|s| s.2).collect(),
    };
    cells.check()?;
    if let Some(k) = targets
        .iter()
        .position(|t| !(t.0.is_finite() && t.1.is_finite()))
    {
        return Err(GpuError::Invalid(format!(
            "target {k}: ({}, {}) m",
            targets[k].0, targets[k].1
        )));
    }
    let unit = cells.fine_side();
    let plan = plan(response, unit)?;
    let count = sources.len();
    engine.check_kernel(
        &format!("the coefficients of {count} source-target pairs"),
        Kernel::AdaptiveCoefficients,
        &[
            ("the creep terms", plan.terms_bytes()),
            ("the source-target pairs", 16 * count as u64),
            ("the pair coefficients", 4 * count as u64),
        ],
    )?;
    let pairs: Vec<f32> = targets
        .iter()
        .zip(sources)
        .flat_map(|(t, s)| {
            [
                ((t.0 - s.0) / s.2) as f32,
                ((t.1 - s.1) / s.2) as f32,
                (s.2 / unit) as f32,
                0.0,
            ]
        })
        .collect();
    let terms = engine.storage_with("viscoslide creep terms", bytemuck::cast_slice(&plan.terms));
    let pairs = engine.storage_with("viscoslide coefficient pairs", bytemuck::cast_slice(&pairs));
    let out = engine.create_buffer(
        "viscoslide pair coefficients",
        4 * count as u64,
        wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
    );
    engine.dispatch(
        Kernel::AdaptiveCoefficients,
        &[&terms, &pairs, &out],
        Params {
            i: [count as u32, plan.count, 0, 0],
            j: [0; 4],
            f: [plan.e[0], plan.e[1], plan.instantaneous, 0.0],
        },
        grid((count as u64).div_ceil(PAIR_WORKGROUP)),
    );
    Ok(read_scaled(engine, &out, count, plan.scale))
}

/// The matrix-free operator `y_T = sum_S K(x_T - x_S; s_S) x_S (a / s_S)^2`
/// of a mesh of square cells (paper Eq. 7), every coefficient evaluated on
/// the fly in f32: the sources with `x_S != 0` are compacted into a list
/// (off the contact set `x_S = 0`), then one workgroup per (target cell,
/// chunk of [`WORKGROUP`] listed sources) evaluates one coefficient per
/// invocation and a second pass adds the chunk partials, so a matvec costs
/// about targets x nonzero sources coefficients.
pub struct AdaptiveMatvec {
    terms: Buf,
    cells: Buf,
    pairs: PairWork,
    params: Params,
}

/// The nonzero sources of a vector over `n` cells, compacted per matvec
/// (off the contact set `x_S = 0`): shared by the pairwise operators.
pub(super) struct SourceList {
    /// Positions of the nonzero sources (u32), ascending.
    pub(super) index: Buf,
    /// Block offsets of the compaction; `offsets[chunks]` is the count.
    pub(super) offsets: Buf,
    pub(super) n: usize,
    /// Blocks of [`WORKGROUP`] cells.
    pub(super) chunks: usize,
}

impl SourceList {
    /// Buffers for `n` cells, checked against the device's limits.
    pub(super) fn new(engine: &mut Engine, n: usize) -> Result<Self, GpuError> {
        engine.check_buffer("the mesh cells", 16 * n as u64)?;
        engine.check_buffer(&format!("a vector of {n} cells"), 4 * n as u64)?;
        let chunks = n.div_ceil(WORKGROUP as usize);
        Ok(Self {
            index: engine.create_buffer(
                "viscoslide pairwise source index",
                4 * n as u64,
                wgpu::BufferUsages::STORAGE,
            ),
            offsets: engine.create_buffer(
                "viscoslide pairwise source offsets",
                4 * (chunks as u64 + 1),
                wgpu::BufferUsages::STORAGE,
            ),
            n,
            chunks,
        })
    }

    /// Record the compaction of the nonzero entries of `x` into `index`, in
    /// order, with the block offsets in `offsets` (compact_*.wgsl).
    pub(super) fn record_sources(&self, engine: &mut Engine, x: &Buf) {
        let (n, chunks) = (self.n as u32, self.chunks as u32);
        let select_nonzero = Params {
            i: [n, chunks, 1, 0],
            ..Default::default()
        };
        let block_groups = groups_for(self.chunks as u64 * WORKGROUP as u64);
        engine.dispatch(
            Kernel::CompactCount,
            &[x, &self.offsets],
            select_nonzero,
            block_groups,
        );
        engine.dispatch(
            Kernel::CompactScan,
            &[&self.offsets],
            Params {
                i: [chunks, 0, 0, 0],
                ..Default::default()
            },
            (1, 1),
        );
        engine.dispatch(
            Kernel::CompactWrite,
            &[x, &self.offsets, &self.index],
            select_nonzero,
            block_groups,
        );
    }
}

/// Work space of the on-the-fly operator: the source list and the
/// per-chunk partial sums of every target (`4 n chunks` bytes, bound in
/// windows where larger than one storage binding, [`super::split`]).
pub(super) struct PairWork {
    pub(super) sources: SourceList,
    /// `partials[c n + T]`: target `T`'s sum over source chunk `c`.
    pub(super) partials: Buf,
}

impl PairWork {
    /// Buffers for `n` cells, checked against the device's limits with
    /// `terms` bytes of creep terms bound beside them.
    pub(super) fn new(engine: &mut Engine, n: usize, terms: u64) -> Result<Self, GpuError> {
        let sources = SourceList::new(engine, n)?;
        let chunks = sources.chunks;
        let partial_bytes = 4 * (n as u64) * (chunks as u64);
        let partials = format!("the partial sums of {n} cells ({chunks} source chunks)");
        let (cells, vector, offsets) = (16 * n as u64, 4 * n as u64, 4 * (chunks as u64 + 1));
        engine.check_kernel(
            &format!("the pairwise matvec of {n} cells"),
            Kernel::AdaptiveMatvec,
            &[
                ("the creep terms", terms),
                ("the mesh cells", cells),
                ("a vector", vector),
                ("the source index", vector),
                ("the source offsets", offsets),
                (&partials, partial_bytes),
            ],
        )?;
        engine.check_kernel(
            &format!("the sums of the pairwise matvec of {n} cells"),
            Kernel::AdaptiveSum,
            &[
                (&partials, partial_bytes),
                ("the source offsets", offsets),
                ("a vector", vector),
            ],
        )?;
        if (n as u64) * (chunks as u64) > (MAX_GROUPS_X * MAX_GROUPS_X) {
            return Err(GpuError::Invalid(format!(
                "{n} cells need more workgroups than one dispatch allows"
            )));
        }
        Ok(Self {
            partials: engine.create_buffer(
                "viscoslide pairwise partial sums",
                partial_bytes,
                wgpu::BufferUsages::STORAGE,
            ),
            sources,
        })
    }

    /// The workgroup grid of one (target, source chunk) pass.
    pub(super) fn pair_grid(&self) -> (u32, u32) {
        grid(self.sources.n as u64 * self.sources.chunks as u64)
    }

    /// Record `y_T = c0 sum_c partials[c n + T]` over the source chunks in
    /// use (adaptive_sum.wgsl).
    pub(super) fn record_sums(&self, engine: &mut Engine, y: &Buf, c0: f32) {
        engine.dispatch(
            Kernel::AdaptiveSum,
            &[&self.partials, &self.sources.offsets, y],
            Params {
                i: [self.sources.n as u32, self.sources.chunks as u32, 0, 0],
                j: [0; 4],
                f: [0.0, 0.0, 0.0, c0],
            },
            groups_for(self.sources.n as u64),
        );
    }
}

impl AdaptiveMatvec {
    /// Plan the operator of `cells` for one material and sliding state.
    pub fn new(
        engine: &mut Engine,
        response: &SlidingResponse,
        cells: &MeshCells,
    ) -> Result<Self, GpuError> {
        cells.check()?;
        let n = cells.len();
        let a = cells.fine_side();
        let plan = plan(response, a)?;
        let pairs = PairWork::new(engine, n, plan.terms_bytes())?;
        // Centres in fine sides from the lower-left centre: on a quadtree
        // they are multiples of a / 2, exact in f32.
        let x0 = cells.x.iter().copied().fold(f64::INFINITY, f64::min);
        let y0 = cells.y.iter().copied().fold(f64::INFINITY, f64::min);
        let data: Vec<f32> = (0..n)
            .flat_map(|k| {
                [
                    ((cells.x[k] - x0) / a) as f32,
                    ((cells.y[k] - y0) / a) as f32,
                    (cells.side[k] / a) as f32,
                    0.0,
                ]
            })
            .collect();
        let terms =
            engine.storage_with("viscoslide creep terms", bytemuck::cast_slice(&plan.terms));
        let cells_buf = engine.storage_with("viscoslide mesh cells", bytemuck::cast_slice(&data));
        let chunks = pairs.sources.chunks;
        Ok(Self {
            terms,
            cells: cells_buf,
            pairs,
            params: Params {
                i: [n as u32, plan.count, chunks as u32, 0],
                j: [0; 4],
                f: [plan.e[0], plan.e[1], plan.instantaneous, plan.scale as f32],
            },
        })
    }

    /// Number of cells.
    pub fn len(&self) -> usize {
        self.pairs.sources.n
    }

    pub fn is_empty(&self) -> bool {
        self.pairs.sources.n == 0
    }

    /// Record `y = L x` (f32 vectors of at least [`Self::len`] entries).
    pub fn record_apply(&mut self, engine: &mut Engine, x: &Buf, y: &Buf) {
        let w = &self.pairs;
        w.sources.record_sources(engine, x);
        engine.dispatch(
            Kernel::AdaptiveMatvec,
            &[
                &self.terms,
                &self.cells,
                x,
                &w.sources.index,
                &w.sources.offsets,
                &w.partials,
            ],
            self.params,
            w.pair_grid(),
        );
        w.record_sums(engine, y, self.params.f[3]);
    }
}
