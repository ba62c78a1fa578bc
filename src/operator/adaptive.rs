//! The influence operator on a quadtree mesh ([`crate::mesh::QuadMesh`];
//! physics.md section 7): cells of different sizes, so the matrix is no
//! longer Toeplitz and is applied pairwise, matrix-free.
//!
//! Entry `(T, S)` is the displacement at the centre of cell `T` under unit
//! pressure on cell `S` (paper Eq. 6 with the source rectangle of side
//! `2^l a`): `K_l(c_T - c_S)`. Every centre-to-centre offset is a multiple
//! of `a/2` (see [`crate::mesh::quadtree`]), so `K_l` is tabulated exactly
//! on two interleaved lattices per level: integer offsets `k a` (both cells
//! fine, or both coarse) and half-integer offsets `(k + 1/2) a` (one fine,
//! one coarse). Level 0 comes from the kernel module (Love's rectangle
//! integral plus the viscoelastic line integral: [`SlidingKernel::table`]
//! and [`SlidingKernel::try_vertex_table`]); level `l` adds its four
//! children, `K_l(d) = sum_{s = +-1} K_{l-1}(d - s 2^(l-2) a)`, which is
//! exact because Eq. 4 is linear in the pressure and Love's integral is
//! additive over sub-rectangles. Every term is positive, so the sums lose
//! nothing to cancellation.
//!
//! Unknowns: the solver of [`crate::solver`] prescribes the load as
//! `a^2 sum x`, so the unknown of cell `S` is its force in fine-cell units,
//! `x_S = p_S (s_S / a)^2`, and column `S` carries the factor `(a / s_S)^2`.

use rayon::prelude::*;

use super::GridOperator;
use crate::kernel::{KernelError, SlidingKernel};
use crate::mesh::QuadMesh;
use crate::response::Grid;

/// `K_l` on one lattice: entry `k` is the offset `(2k + parity) a/2`.
#[derive(Debug, Clone)]
struct LatticeTable {
    kmin: (i64, i64),
    kmax: (i64, i64),
    w: i64,
    values: Vec<f64>,
}

impl LatticeTable {
    fn new(kmin: (i64, i64), kmax: (i64, i64)) -> Self {
        let w = kmax.1 - kmin.1 + 1;
        let h = kmax.0 - kmin.0 + 1;
        Self {
            kmin,
            kmax,
            w,
            values: vec![0.0; (w * h) as usize],
        }
    }

    #[inline]
    fn get(&self, kx: i64, ky: i64) -> f64 {
        debug_assert!(kx >= self.kmin.0 && kx <= self.kmax.0);
        debug_assert!(ky >= self.kmin.1 && ky <= self.kmax.1);
        self.values[((kx - self.kmin.0) * self.w + ky - self.kmin.1) as usize]
    }

    fn covers(&self, lo: (i64, i64), hi: (i64, i64)) -> bool {
        self.kmin.0 <= lo.0 && self.kmin.1 <= lo.1 && self.kmax.0 >= hi.0 && self.kmax.1 >= hi.1
    }

    /// `out(k) = sum over the four corners (k + (cx, cy))`, `c in {lo, hi}`.
    fn box_sum(&self, lo: i64, hi: i64) -> Self {
        let kmin = (self.kmin.0 - lo, self.kmin.1 - lo);
        let kmax = (self.kmax.0 - hi, self.kmax.1 - hi);
        let mut out = Self::new(kmin, kmax);
        let w = out.w;
        out.values
            .par_chunks_mut(w as usize)
            .enumerate()
            .for_each(|(r, row)| {
                let kx = kmin.0 + r as i64;
                for (c, v) in row.iter_mut().enumerate() {
                    let ky = kmin.1 + c as i64;
                    *v = self.get(kx + lo, ky + lo)
                        + self.get(kx + lo, ky + hi)
                        + self.get(kx + hi, ky + lo)
                        + self.get(kx + hi, ky + hi);
                }
            });
        out
    }
}

/// `K_l` for every level up to the mesh's coarsest, on both lattices
/// (`[level][parity]`, parity 0 = integer offsets, 1 = half-integer).
#[derive(Debug, Clone)]
pub struct LevelTables {
    nx: usize,
    ny: usize,
    cell_size: f64,
    tables: Vec<[LatticeTable; 2]>,
}

impl LevelTables {
    /// Tables for an `nx x ny` fine grid of side `cell` \[m\] and levels
    /// `0..=max_level`.
    pub fn new(
        kernel: &SlidingKernel,
        nx: usize,
        ny: usize,
        cell: f64,
        max_level: u8,
    ) -> Result<Self, KernelError> {
        // Level l shrinks the range by 2^(l-2) per side (one cell at l = 1).
        let grow = if max_level == 0 {
            0
        } else {
            (1usize << (max_level - 1)) + 1
        };
        let (mx, my) = (nx + grow, ny + grow);
        let lattice = Grid::square(mx, my, cell)?;
        let centre = kernel.table(&lattice)?;
        let vertex = kernel.vertex_table(&lattice)?;
        let mut even = LatticeTable::new(
            (1 - mx as i64, 1 - my as i64),
            (mx as i64 - 1, my as i64 - 1),
        );
        even.values.copy_from_slice(&centre.values);
        let mut odd =
            LatticeTable::new((-(mx as i64), -(my as i64)), (mx as i64 - 1, my as i64 - 1));
        odd.values.copy_from_slice(&vertex.values);
        let mut tables = vec![[even, odd]];
        for l in 1..=max_level {
            let prev = &tables[l as usize - 1];
            let next = if l == 1 {
                // Children at +-a/2: integer offsets draw on the half-integer
                // lattice of level 0 (k - 1 and k), and vice versa (k, k + 1).
                [prev[1].box_sum(-1, 0), prev[0].box_sum(0, 1)]
            } else {
                let s = 1i64 << (l - 2);
                [prev[0].box_sum(-s, s), prev[1].box_sum(-s, s)]
            };
            tables.push(next);
        }
        let t = Self {
            nx,
            ny,
            cell_size: cell,
            tables,
        };
        let (ex, ey) = (nx as i64 - 1, ny as i64 - 1);
        for (l, pair) in t.tables.iter().enumerate() {
            assert!(
                pair[0].covers((-ex, -ey), (ex, ey))
                    && pair[1].covers((-ex, -ey), (ex - 1, ey - 1)),
                "level {l} table does not cover the grid"
            );
        }
        Ok(t)
    }

    /// Coarsest level tabulated.
    pub fn max_level(&self) -> u8 {
        (self.tables.len() - 1) as u8
    }

    /// `(nx, ny)` of the fine grid.
    pub fn shape(&self) -> (usize, usize) {
        (self.nx, self.ny)
    }

    /// Fine cell side \[m\].
    pub fn cell_size(&self) -> f64 {
        self.cell_size
    }

    /// `K_l` [m/Pa] at the offset `(dx, dy)` in half-fine-cell units
    /// (`dx`, `dy` both even or both odd): the displacement at that offset
    /// from the centre of a level-`level` cell under unit pressure.
    pub fn coefficient(&self, level: u8, dx: i64, dy: i64) -> f64 {
        let p = dx.rem_euclid(2);
        assert_eq!(p, dy.rem_euclid(2), "offsets of mixed parity ({dx}, {dy})");
        self.tables[level as usize][p as usize].get(dx.div_euclid(2), dy.div_euclid(2))
    }

    /// The level-0 table over the `(2nx-1) x (2ny-1)` integer offsets of the
    /// fine grid, in the layout of [`super::OffsetTable`]: the uniform
    /// grid's Toeplitz operator.
    pub fn uniform_table(&self) -> Vec<f64> {
        let (nx, ny) = (self.nx as i64, self.ny as i64);
        let t = &self.tables[0][0];
        let mut out = Vec::with_capacity(((2 * nx - 1) * (2 * ny - 1)) as usize);
        for di in 1 - nx..nx {
            for dj in 1 - ny..ny {
                out.push(t.get(di, dj));
            }
        }
        out
    }

    /// Bytes held.
    pub fn bytes(&self) -> usize {
        self.tables
            .iter()
            .map(|p| 8 * (p[0].values.len() + p[1].values.len()))
            .sum()
    }
}

/// A point where the displacement is evaluated: a cell centre in
/// half-fine-cell units.
#[derive(Debug, Clone, Copy)]
struct Target {
    /// `floor(centre / 2)`.
    k: (i64, i64),
    /// 1 for a fine-cell centre (odd), 0 for a coarse one (even).
    parity: u8,
}

impl Target {
    fn from_half(hx: i64, hy: i64) -> Self {
        Self {
            k: (hx.div_euclid(2), hy.div_euclid(2)),
            parity: hx.rem_euclid(2) as u8,
        }
    }
}

/// The nonzero sources of one level, with their flat table offsets for
/// fine and for coarse targets.
struct SourceGroup {
    level: usize,
    parity: u8,
    /// `kx w + ky` in the table a target of parity `q` uses, `[q]`.
    flat: [Vec<i64>; 2],
    /// `x_S (a / s_S)^2`.
    weight: Vec<f64>,
}

/// The pairwise operator of a [`QuadMesh`] (CPU, rayon over targets).
pub struct AdaptiveOperator {
    tables: std::sync::Arc<LevelTables>,
    targets: Vec<Target>,
    levels: Vec<u8>,
}

impl AdaptiveOperator {
    /// The operator of `mesh` with the tables `tables` (built for the same
    /// fine grid and at least the mesh's coarsest level).
    pub fn new(tables: std::sync::Arc<LevelTables>, mesh: &QuadMesh) -> Self {
        assert_eq!(
            tables.shape(),
            (mesh.nx, mesh.ny),
            "tables for another grid"
        );
        assert!(
            mesh.cells.iter().all(|c| c.level <= tables.max_level()),
            "the mesh is coarser than its tables"
        );
        let targets = mesh
            .cells
            .iter()
            .map(|c| {
                let (hx, hy) = c.centre_half();
                Target::from_half(hx, hy)
            })
            .collect();
        let levels = mesh.cells.iter().map(|c| c.level).collect();
        Self {
            tables,
            targets,
            levels,
        }
    }

    /// Number of unknowns.
    pub fn len(&self) -> usize {
        self.targets.len()
    }

    /// Whether there are no cells.
    pub fn is_empty(&self) -> bool {
        self.targets.is_empty()
    }

    fn groups(&self, x: &[f64]) -> Vec<SourceGroup> {
        let nl = self.tables.tables.len();
        let mut groups: Vec<SourceGroup> = (0..nl)
            .map(|l| SourceGroup {
                level: l,
                parity: (l == 0) as u8,
                flat: [vec![], vec![]],
                weight: vec![],
            })
            .collect();
        for (s, &v) in x.iter().enumerate() {
            if v == 0.0 {
                continue;
            }
            let l = self.levels[s] as usize;
            let t = self.targets[s];
            let g = &mut groups[l];
            for q in 0..2u8 {
                // k = kT - kS - [target even and source odd].
                let par = (q ^ g.parity) as usize;
                let w = self.tables.tables[l][par].w;
                let corr = (q == 0 && g.parity == 1) as i64;
                g.flat[q as usize].push((t.k.0 + corr) * w + t.k.1 + corr);
            }
            g.weight.push(v / (1u64 << (2 * l)) as f64);
        }
        groups.retain(|g| !g.weight.is_empty());
        groups
    }

    #[inline]
    fn eval(&self, groups: &[SourceGroup], t: Target) -> f64 {
        let mut sum = 0.0;
        for g in groups {
            let q = t.parity as usize;
            let tab = &self.tables.tables[g.level][q ^ g.parity as usize];
            let base = (t.k.0 - tab.kmin.0) * tab.w + (t.k.1 - tab.kmin.1);
            let vals = &tab.values;
            let mut acc = 0.0;
            for (f, w) in g.flat[q].iter().zip(&g.weight) {
                let i = (base - f) as usize;
                debug_assert!(i < vals.len());
                // SAFETY: every centre-to-centre offset of the grid lies in
                // the table's range (checked in `LevelTables::new`), so the
                // flat index is in bounds.
                acc += unsafe { *vals.get_unchecked(i) } * w;
            }
            sum += acc;
        }
        sum
    }

    /// The whole matrix (faer), column `S` scaled by `(a / s_S)^2` as in
    /// [`GridOperator::apply`]: for moderate meshes, e.g. the dense direct
    /// reference solve ([`crate::solver::reference::solve_dense`]).
    pub fn assemble(&self) -> faer::Mat<f64> {
        let n = self.len();
        let mut m = faer::Mat::<f64>::zeros(n, n);
        let mut e = vec![0.0; n];
        let mut col = vec![0.0; n];
        for s in 0..n {
            e[s] = 1.0;
            let groups = self.groups(&e);
            col.par_iter_mut()
                .zip(self.targets.par_iter())
                .for_each(|(c, &t)| *c = self.eval(&groups, t));
            for (r, v) in col.iter().enumerate() {
                m[(r, s)] = *v;
            }
            e[s] = 0.0;
        }
        m
    }

    /// `u` at the centres of the fine cells `fine` (`ix * ny + iy`) due to
    /// the mesh unknowns `x`: the displacement field at full resolution.
    pub fn displacement_at_fine(&self, x: &[f64], fine: &[usize]) -> Vec<f64> {
        assert_eq!(x.len(), self.len());
        let groups = self.groups(x);
        let ny = self.tables.ny;
        fine.par_iter()
            .map(|&f| {
                let (ix, iy) = ((f / ny) as i64, (f % ny) as i64);
                self.eval(&groups, Target::from_half(2 * ix + 1, 2 * iy + 1))
            })
            .collect()
    }
}

impl GridOperator for AdaptiveOperator {
    fn shape(&self) -> (usize, usize) {
        (self.targets.len(), 1)
    }

    fn apply(&mut self, x: &[f64], y: &mut [f64]) {
        assert_eq!(x.len(), self.len());
        assert_eq!(y.len(), self.len());
        let groups = self.groups(x);
        y.par_iter_mut()
            .zip(self.targets.par_iter())
            .with_min_len(64)
            .for_each(|(yt, &t)| *yt = self.eval(&groups, t));
    }

    fn apply_rows(&mut self, x: &[f64], rows: &[usize], _scratch: &mut [f64], out: &mut [f64]) {
        assert_eq!(x.len(), self.len());
        assert_eq!(out.len(), rows.len());
        let groups = self.groups(x);
        out.par_iter_mut()
            .zip(rows.par_iter())
            .with_min_len(64)
            .for_each(|(o, &r)| *o = self.eval(&groups, self.targets[r]));
    }
}
