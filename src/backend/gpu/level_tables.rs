//! The operator of a quadtree mesh from influence tables computed on the
//! device (physics.md section 7; CPU twin: [`crate::operator::LevelTables`]
//! and [`crate::operator::AdaptiveOperator`]).
//!
//! Every centre-to-centre offset of a [`QuadMesh`] is a multiple of `a/2`,
//! so the coefficient of a level-`l` source cell is needed on two lattices
//! only: integer offsets `k a` and half-integer ones `(k + 1/2) a`.
//! `shaders/level_table.wgsl` evaluates level 0 on both (the steady-sliding
//! Green's function of Eq. 4 integrated over the cell as in Eq. 6, f32, one
//! coefficient per entry), and `shaders/level_box_sum.wgsl` adds four
//! children into each coarser level, as the host does in f64. The matvec
//! (`shaders/level_matvec.wgsl`) then reads one table entry per (target,
//! nonzero source) pair instead of evaluating the line integral of the pair
//! (as [`super::AdaptiveMatvec`] does for cells anywhere): the tables cost
//! about `8 (n + 2^(L-1))^2` coefficient evaluations once per solve, after
//! which a pair is a memory read. Tables of different levels are separate
//! buffers (each bound in windows where larger than one storage binding,
//! [`super::split`]), so the matvec runs one pass per source level present
//! in the mesh.

use super::adaptive::SourceList;
use super::context::GpuError;
use super::engine::{groups_for, Buf, Engine, Kernel, Params};
use super::plan::{grid, plan, read_scaled};
use crate::mesh::QuadMesh;
use crate::response::SlidingResponse;

/// Invocations per workgroup of `level_table.wgsl` (`LWG`).
const TABLE_WORKGROUP: u64 = 64;

/// One lattice of one level: entry `(r, c)` (row-major, `w` per row) is the
/// offset `(kmin + (r, c)) * 2 + parity` in half fine sides.
#[derive(Debug, Clone)]
struct Lattice {
    kmin: (i64, i64),
    kmax: (i64, i64),
    buf: Buf,
}

impl Lattice {
    fn width(&self) -> usize {
        (self.kmax.1 - self.kmin.1 + 1) as usize
    }

    fn height(&self) -> usize {
        (self.kmax.0 - self.kmin.0 + 1) as usize
    }

    fn len(&self) -> usize {
        self.width() * self.height()
    }
}

/// Level tables `K_l` of a fine grid on the device (dimensionless, f32;
/// `[level][parity]`, parity 0 = integer offsets, 1 = half-integer).
#[derive(Debug, Clone)]
pub struct GpuLevelTables {
    nx: usize,
    ny: usize,
    tables: Vec<[Lattice; 2]>,
    /// `(1 - nu^2)/pi * a * (total compliance)` [m/Pa].
    scale: f64,
}

fn i32_bits(v: i64) -> u32 {
    (v as i32) as u32
}

impl GpuLevelTables {
    /// Tables for an `nx x ny` grid of fine cells of side `cell` \[m\] and
    /// levels `0..=max_level`, for one material and sliding state
    /// (half-spaces only). Ranges as in [`crate::operator::LevelTables`].
    pub fn new(
        engine: &mut Engine,
        response: &SlidingResponse,
        nx: usize,
        ny: usize,
        cell: f64,
        max_level: u8,
    ) -> Result<Self, GpuError> {
        if nx == 0 || ny == 0 || !(cell.is_finite() && cell > 0.0) || max_level > 12 {
            return Err(GpuError::Invalid(format!(
                "level tables for {nx} x {ny} cells of {cell} m up to level {max_level}"
            )));
        }
        let plan = plan(response, cell)?;
        let grow = if max_level == 0 {
            0
        } else {
            (1i64 << (max_level - 1)) + 1
        };
        let (mx, my) = (nx as i64 + grow, ny as i64 + grow);
        let biggest = (2 * mx) as u64 * (2 * my) as u64 * 4;
        let table = ("one level table of the adaptive mesh", biggest);
        engine.check_kernel(
            "the level-0 table kernel of the adaptive mesh",
            Kernel::LevelTable,
            &[("the creep terms", plan.terms_bytes()), table],
        )?;
        engine.check_kernel(
            "the level-sum kernel of the adaptive mesh",
            Kernel::LevelBoxSum,
            &[table, table],
        )?;
        if 2 * my >= 1 << 16 {
            return Err(GpuError::Invalid(format!(
                "level tables {} entries wide (the matvec packs widths into 16 bits)",
                2 * my
            )));
        }
        let terms =
            engine.storage_with("viscoslide creep terms", bytemuck::cast_slice(&plan.terms));
        let level0 = |engine: &mut Engine, kmin: (i64, i64), kmax: (i64, i64), parity: u32| {
            let (w, h) = ((kmax.1 - kmin.1 + 1) as u32, (kmax.0 - kmin.0 + 1) as u32);
            let count = w as u64 * h as u64;
            let buf = engine.create_buffer(
                &format!("viscoslide level-0 table (parity {parity})"),
                4 * count,
                wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            );
            engine.dispatch(
                Kernel::LevelTable,
                &[&terms, &buf],
                Params {
                    i: [w, h, plan.count, parity],
                    j: [i32_bits(kmin.0), i32_bits(kmin.1), 0, 0],
                    f: [plan.e[0], plan.e[1], plan.instantaneous, 0.0],
                },
                grid(count.div_ceil(TABLE_WORKGROUP)),
            );
            Lattice { kmin, kmax, buf }
        };
        let even = level0(engine, (1 - mx, 1 - my), (mx - 1, my - 1), 0);
        let odd = level0(engine, (-mx, -my), (mx - 1, my - 1), 1);
        let mut tables = vec![[even, odd]];
        for l in 1..=max_level {
            let prev = &tables[l as usize - 1];
            let next = if l == 1 {
                // Children at +-a/2: integer offsets draw on the half-integer
                // lattice of level 0 (k - 1 and k), and vice versa (k, k + 1).
                [
                    box_sum(engine, &prev[1], -1, 0, l, 0),
                    box_sum(engine, &prev[0], 0, 1, l, 1),
                ]
            } else {
                let s = 1i64 << (l - 2);
                [
                    box_sum(engine, &prev[0], -s, s, l, 0),
                    box_sum(engine, &prev[1], -s, s, l, 1),
                ]
            };
            tables.push(next);
        }
        engine.flush();
        Ok(Self {
            nx,
            ny,
            tables,
            scale: plan.scale,
        })
    }

    /// `(nx, ny)` of the fine grid.
    pub fn shape(&self) -> (usize, usize) {
        (self.nx, self.ny)
    }

    /// Coarsest level tabulated.
    pub fn max_level(&self) -> u8 {
        (self.tables.len() - 1) as u8
    }

    /// Device memory of the tables \[bytes\].
    pub fn bytes(&self) -> usize {
        self.tables
            .iter()
            .map(|p| 4 * (p[0].len() + p[1].len()))
            .sum()
    }

    /// One lattice read back, in m/Pa: `(kmin, kmax, values)` with entry
    /// `(kx - kmin.0) * (kmax.1 - kmin.1 + 1) + ky - kmin.1` the coefficient
    /// at the offset `(2 kx + parity, 2 ky + parity)` half fine sides (for
    /// tests against [`crate::operator::LevelTables::coefficient`]).
    #[allow(clippy::type_complexity)]
    pub fn read(
        &self,
        engine: &mut Engine,
        level: u8,
        parity: usize,
    ) -> ((i64, i64), (i64, i64), Vec<f64>) {
        let lat = &self.tables[level as usize][parity];
        let v = read_scaled(engine, &lat.buf, lat.len(), self.scale);
        (lat.kmin, lat.kmax, v)
    }
}

/// The next level's lattice: `out(k) = sum over c in {lo, hi}^2 of in(k + c)`.
fn box_sum(
    engine: &mut Engine,
    input: &Lattice,
    lo: i64,
    hi: i64,
    level: u8,
    parity: u32,
) -> Lattice {
    let kmin = (input.kmin.0 - lo, input.kmin.1 - lo);
    let kmax = (input.kmax.0 - hi, input.kmax.1 - hi);
    let (w, h) = (
        (kmax.1 - kmin.1 + 1) as usize,
        (kmax.0 - kmin.0 + 1) as usize,
    );
    let out = Lattice {
        kmin,
        kmax,
        buf: engine.create_buffer(
            &format!("viscoslide level-{level} table (parity {parity})"),
            4 * (w * h) as u64,
            wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        ),
    };
    engine.dispatch(
        Kernel::LevelBoxSum,
        &[&input.buf, &out.buf],
        Params {
            i: [
                out.width() as u32,
                out.height() as u32,
                input.width() as u32,
                (hi - lo) as u32,
            ],
            ..Default::default()
        },
        groups_for(out.len() as u64),
    );
    out
}

/// The operator `y_T = sum_S K_l(S)(c_T - c_S) x_S / 4^l(S)` of a quadtree
/// mesh (paper Eq. 7) from [`GpuLevelTables`]: the vectors are permuted into
/// level order, the nonzero sources compacted (off the contact set
/// `x_S = 0`), then for each source level of the mesh one invocation per
/// target cell sums one table entry per nonzero source of that level (the
/// workgroup stages the sources in workgroup memory, so a pass costs
/// targets x sources of the level and no work is launched for absent
/// pairs), and the result is permuted back.
pub struct LevelMatvec {
    tables: GpuLevelTables,
    /// Mesh positions in level order (u32): the operator works on the
    /// permuted vectors so that the sources of a level are contiguous.
    order: Buf,
    /// `x` and `y` in level order.
    x_sorted: Buf,
    y_sorted: Buf,
    cells: Buf,
    sources: SourceList,
    /// Source levels present in the mesh.
    levels: Vec<u8>,
}

impl LevelMatvec {
    /// The operator of `mesh` (same fine grid as `tables`, no coarser level
    /// than they hold).
    pub fn new(
        engine: &mut Engine,
        tables: &GpuLevelTables,
        mesh: &QuadMesh,
    ) -> Result<Self, GpuError> {
        if tables.shape() != (mesh.nx, mesh.ny) {
            return Err(GpuError::Invalid(format!(
                "level tables of a {} x {} grid for a mesh of {} x {}",
                tables.nx, tables.ny, mesh.nx, mesh.ny
            )));
        }
        let n = mesh.len();
        if n == 0 {
            return Err(GpuError::Invalid("a mesh without cells".into()));
        }
        let mut present = [false; 13];
        for c in &mesh.cells {
            if c.level > tables.max_level() {
                return Err(GpuError::Invalid(format!(
                    "a level-{} cell, but the tables stop at level {}",
                    c.level,
                    tables.max_level()
                )));
            }
            present[c.level as usize] = true;
        }
        let sources = SourceList::new(engine, n)?;
        for (l, &here) in present.iter().enumerate() {
            let Some([even, odd]) = tables.tables.get(l).filter(|_| here) else {
                continue;
            };
            let vector = 4 * n as u64;
            engine.check_kernel(
                &format!("the level-{l} pass of the quadtree matvec ({n} cells)"),
                Kernel::LevelMatvec,
                &[
                    ("a level table of the adaptive mesh", even.buf.buffer.size()),
                    ("a level table of the adaptive mesh", odd.buf.buffer.size()),
                    ("the quadtree cells", 16 * n as u64),
                    ("a vector", vector),
                    ("the source index", vector),
                    ("the source offsets", 4 * (sources.chunks as u64 + 1)),
                    ("a vector", vector),
                ],
            )?;
        }
        let mut order: Vec<u32> = (0..n as u32).collect();
        order.sort_by_key(|&k| mesh.cells[k as usize].level);
        let data: Vec<i32> = order
            .iter()
            .map(|&k| &mesh.cells[k as usize])
            .flat_map(|c| {
                let (hx, hy) = c.centre_half();
                [
                    hx.div_euclid(2) as i32,
                    hy.div_euclid(2) as i32,
                    hx.rem_euclid(2) as i32,
                    c.level as i32,
                ]
            })
            .collect();
        let cells = engine.storage_with("viscoslide quadtree cells", bytemuck::cast_slice(&data));
        let order = engine.storage_with("viscoslide quadtree order", bytemuck::cast_slice(&order));
        let vector = |engine: &mut Engine, label: &str| {
            engine.create_buffer(label, 4 * n as u64, wgpu::BufferUsages::STORAGE)
        };
        let x_sorted = vector(engine, "viscoslide level-ordered x");
        let y_sorted = vector(engine, "viscoslide level-ordered y");
        Ok(Self {
            tables: tables.clone(),
            order,
            x_sorted,
            y_sorted,
            cells,
            sources,
            levels: (0..=12u8).filter(|&l| present[l as usize]).collect(),
        })
    }

    /// Number of cells.
    pub fn len(&self) -> usize {
        self.sources.n
    }

    pub fn is_empty(&self) -> bool {
        self.sources.n == 0
    }

    /// Record `y = L x` (f32 vectors of at least [`Self::len`] entries).
    pub fn record_apply(&mut self, engine: &mut Engine, x: &Buf, y: &Buf) {
        let w = &self.sources;
        let permute = Params {
            i: [w.n as u32, 0, 0, 0],
            ..Default::default()
        };
        let elementwise = groups_for(w.n as u64);
        engine.dispatch(
            Kernel::Gather,
            &[&self.order, x, &self.x_sorted],
            permute,
            elementwise,
        );
        let xs = &self.x_sorted;
        w.record_sources(engine, xs);
        for (k, &level) in self.levels.iter().enumerate() {
            let [even, odd] = &self.tables.tables[level as usize];
            engine.dispatch(
                Kernel::LevelMatvec,
                &[
                    &even.buf,
                    &odd.buf,
                    &self.cells,
                    xs,
                    &w.index,
                    &w.offsets,
                    &self.y_sorted,
                ],
                Params {
                    i: [
                        w.n as u32,
                        w.chunks as u32,
                        level as u32 | ((k == 0) as u32) << 8,
                        even.width() as u32 | (odd.width() as u32) << 16,
                    ],
                    j: [
                        i32_bits(even.kmin.0),
                        i32_bits(even.kmin.1),
                        i32_bits(odd.kmin.0),
                        i32_bits(odd.kmin.1),
                    ],
                    f: [0.0, 0.0, 0.0, self.tables.scale as f32],
                },
                elementwise,
            );
        }
        engine.dispatch(
            Kernel::Scatter,
            &[&self.order, &self.y_sorted, y],
            permute,
            elementwise,
        );
    }
}
