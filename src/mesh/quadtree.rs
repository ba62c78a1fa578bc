//! The quadtree mesh: square cells of side `2^l a` aligned to the fine grid.
//!
//! A cell of level `l` at block index `(i, j)` covers the fine cells
//! `[i 2^l, (i+1) 2^l) x [j 2^l, (j+1) 2^l)`. Positions are kept exactly in
//! half-fine-cell units: the centre of a level-`l` cell is at
//! `i 2^(l+1) + 2^l` (odd for fine cells, even for coarser ones), so every
//! offset between two centres is a multiple of `a/2` and the coefficient
//! tables of [`crate::operator::AdaptiveOperator`] are indexed exactly.

/// One mesh cell.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Cell {
    /// Level `l`: the side is `2^l` fine cells.
    pub level: u8,
    /// Block index along x (in units of `2^l` fine cells).
    pub i: u32,
    /// Block index along y.
    pub j: u32,
}

impl Cell {
    /// Side in fine cells.
    #[inline]
    pub fn span(&self) -> usize {
        1 << self.level
    }

    /// Centre in half-fine-cell units, `(i 2^(l+1) + 2^l, j 2^(l+1) + 2^l)`.
    #[inline]
    pub fn centre_half(&self) -> (i64, i64) {
        let l = self.level as u32;
        (
            ((self.i as i64) << (l + 1)) + (1i64 << l),
            ((self.j as i64) << (l + 1)) + (1i64 << l),
        )
    }

    /// The fine cells it covers, `(x range, y range)`.
    #[inline]
    pub fn fine_ranges(&self) -> (std::ops::Range<usize>, std::ops::Range<usize>) {
        let s = self.span();
        let (x0, y0) = (self.i as usize * s, self.j as usize * s);
        (x0..x0 + s, y0..y0 + s)
    }
}

/// Errors building a mesh; each names the offending value.
#[derive(Debug, thiserror::Error)]
pub enum MeshError {
    #[error("{0}")]
    Invalid(String),
}

/// A quadtree mesh over an `nx x ny` grid of fine square cells of side `a`.
#[derive(Debug, Clone, PartialEq)]
pub struct QuadMesh {
    pub nx: usize,
    pub ny: usize,
    /// Fine cell side `a` \[m\].
    pub cell_size: f64,
    /// Coarsest level allowed.
    pub max_level: u8,
    /// Cells in raster order of their lower-left fine cell.
    pub cells: Vec<Cell>,
    /// Mesh cell covering each fine cell (C order, `ix * ny + iy`).
    owner: Vec<u32>,
}

impl QuadMesh {
    /// Every cell at the finest level: the uniform grid.
    pub fn uniform(nx: usize, ny: usize, cell_size: f64) -> Result<Self, MeshError> {
        Self::from_mask(nx, ny, cell_size, 0, &vec![true; nx * ny])
    }

    /// The coarsest quadtree (levels up to `max_level`) whose finest cells
    /// cover every fine cell with `fine[ix * ny + iy]` set.
    pub fn from_mask(
        nx: usize,
        ny: usize,
        cell_size: f64,
        max_level: u8,
        fine: &[bool],
    ) -> Result<Self, MeshError> {
        let levels: Vec<u8> = fine
            .iter()
            .map(|&f| if f { 0 } else { max_level })
            .collect();
        Self::from_levels(nx, ny, cell_size, max_level, &levels)
    }

    /// The coarsest quadtree (levels up to `max_level`) in which the cell
    /// covering fine cell `f` has a level of at most `allowed[f]`. Blocks of
    /// side `2^max_level` tile the grid; a block is split while a fine cell
    /// in it allows less or it reaches past the grid's edge.
    pub fn from_levels(
        nx: usize,
        ny: usize,
        cell_size: f64,
        max_level: u8,
        allowed: &[u8],
    ) -> Result<Self, MeshError> {
        if nx == 0 || ny == 0 {
            return Err(MeshError::Invalid(format!(
                "a mesh needs at least one fine cell per side, got {nx} x {ny}"
            )));
        }
        if !(cell_size.is_finite() && cell_size > 0.0) {
            return Err(MeshError::Invalid(format!(
                "the fine cell side must be positive, got {cell_size} m"
            )));
        }
        if max_level > 20 {
            return Err(MeshError::Invalid(format!(
                "max_level {max_level} is beyond 20 (blocks of 2^20 cells)"
            )));
        }
        if allowed.len() != nx * ny {
            return Err(MeshError::Invalid(format!(
                "the refinement map has {} entries, the grid {nx} x {ny} needs {}",
                allowed.len(),
                nx * ny
            )));
        }
        // Min-pyramid: pyramid[l][(bi, bj)] = smallest allowed level in the
        // level-l block (bi, bj), over the part of it inside the grid.
        let mut pyramid: Vec<(usize, usize, Vec<u8>)> = vec![(nx, ny, allowed.to_vec())];
        for _ in 0..max_level {
            let (px, py, prev) = pyramid.last().unwrap();
            let (qx, qy) = (px.div_ceil(2), py.div_ceil(2));
            let mut next = vec![u8::MAX; qx * qy];
            for bx in 0..*px {
                for by in 0..*py {
                    let t = &mut next[(bx / 2) * qy + by / 2];
                    *t = (*t).min(prev[bx * py + by]);
                }
            }
            pyramid.push((qx, qy, next));
        }
        let finer_needed = |c: &Cell| -> bool {
            let (_, py, v) = &pyramid[c.level as usize];
            v[c.i as usize * py + c.j as usize] < c.level
        };
        let top = 1usize << max_level;
        let mut cells = Vec::new();
        let mut stack = Vec::new();
        for bi in 0..nx.div_ceil(top) {
            for bj in 0..ny.div_ceil(top) {
                stack.push(Cell {
                    level: max_level,
                    i: bi as u32,
                    j: bj as u32,
                });
                while let Some(c) = stack.pop() {
                    let (xr, yr) = c.fine_ranges();
                    if xr.start >= nx || yr.start >= ny {
                        continue;
                    }
                    let inside = xr.end <= nx && yr.end <= ny;
                    let split = c.level > 0 && (!inside || finer_needed(&c));
                    if split {
                        for (di, dj) in [(1, 1), (1, 0), (0, 1), (0, 0)] {
                            stack.push(Cell {
                                level: c.level - 1,
                                i: 2 * c.i + di,
                                j: 2 * c.j + dj,
                            });
                        }
                    } else {
                        cells.push(c);
                    }
                }
            }
        }
        cells.sort_by_key(|c| {
            let (xr, yr) = c.fine_ranges();
            (xr.start, yr.start)
        });
        let mut owner = vec![u32::MAX; nx * ny];
        for (k, c) in cells.iter().enumerate() {
            let (xr, yr) = c.fine_ranges();
            for ix in xr {
                for iy in yr.clone() {
                    owner[ix * ny + iy] = k as u32;
                }
            }
        }
        debug_assert!(owner.iter().all(|&o| o != u32::MAX));
        Ok(Self {
            nx,
            ny,
            cell_size,
            max_level,
            cells,
            owner,
        })
    }

    /// Number of cells (the unknowns of the contact problem).
    pub fn len(&self) -> usize {
        self.cells.len()
    }

    /// Whether the mesh has no cells (never, for a built mesh).
    pub fn is_empty(&self) -> bool {
        self.cells.is_empty()
    }

    /// Number of cells per level, index = level.
    pub fn level_counts(&self) -> Vec<usize> {
        let mut out = vec![0; self.max_level as usize + 1];
        for c in &self.cells {
            out[c.level as usize] += 1;
        }
        out
    }

    /// The mesh cell that covers fine cell `(ix, iy)`.
    #[inline]
    pub fn owner(&self, ix: usize, iy: usize) -> usize {
        self.owner[ix * self.ny + iy] as usize
    }

    /// Side of cell `k` \[m\].
    pub fn side(&self, k: usize) -> f64 {
        self.cell_size * self.cells[k].span() as f64
    }

    /// Centre of cell `k` \[m\], the origin at the grid's lower-left corner.
    pub fn centre(&self, k: usize) -> (f64, f64) {
        let (hx, hy) = self.cells[k].centre_half();
        (
            0.5 * hx as f64 * self.cell_size,
            0.5 * hy as f64 * self.cell_size,
        )
    }

    /// Height rule: a coarse cell stands at the HIGHEST point it covers, so
    /// its gap profile is the minimum of the fine gaps `g = max z - z`
    /// (physics.md section 1) over its fine cells. The rule is conservative:
    /// a coarse cell open at its centre with this height has every covered
    /// fine cell at least as far from the rigid surface at that point.
    pub fn restrict_gap(&self, g_fine: &[f64]) -> Vec<f64> {
        assert_eq!(g_fine.len(), self.nx * self.ny, "fine gap length");
        self.cells
            .iter()
            .map(|c| {
                let (xr, yr) = c.fine_ranges();
                let mut m = f64::INFINITY;
                for ix in xr {
                    for iy in yr.clone() {
                        m = m.min(g_fine[ix * self.ny + iy]);
                    }
                }
                m
            })
            .collect()
    }

    /// A mesh field on the fine grid, each fine cell taking its cell's value.
    pub fn prolong(&self, mesh_values: &[f64]) -> Vec<f64> {
        assert_eq!(mesh_values.len(), self.len(), "mesh field length");
        self.owner
            .iter()
            .map(|&o| mesh_values[o as usize])
            .collect()
    }

    /// Fine cells that lie inside coarse (level >= 1) cells, `ix * ny + iy`.
    pub fn fine_cells_in_coarse(&self) -> Vec<usize> {
        let mut out = Vec::new();
        for c in self.cells.iter().filter(|c| c.level > 0) {
            let (xr, yr) = c.fine_ranges();
            for ix in xr {
                for iy in yr.clone() {
                    out.push(ix * self.ny + iy);
                }
            }
        }
        out.sort_unstable();
        out
    }
}

/// Grow a fine mask by `radius` cells (square neighbourhood).
pub fn dilate(mask: &[bool], nx: usize, ny: usize, radius: usize) -> Vec<bool> {
    if radius == 0 {
        return mask.to_vec();
    }
    // Separable: along y, then along x.
    let mut tmp = vec![false; nx * ny];
    for ix in 0..nx {
        for iy in 0..ny {
            if mask[ix * ny + iy] {
                let lo = iy.saturating_sub(radius);
                let hi = (iy + radius).min(ny - 1);
                for t in &mut tmp[ix * ny + lo..=ix * ny + hi] {
                    *t = true;
                }
            }
        }
    }
    let mut out = vec![false; nx * ny];
    for ix in 0..nx {
        let lo = ix.saturating_sub(radius);
        let hi = (ix + radius).min(nx - 1);
        for iy in 0..ny {
            if tmp[ix * ny + iy] {
                for jx in lo..=hi {
                    out[jx * ny + iy] = true;
                }
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tiles_the_grid_exactly_once() {
        let (nx, ny) = (37, 23);
        let mut mask = vec![false; nx * ny];
        mask[5 * ny + 7] = true;
        mask[30 * ny + 20] = true;
        let m = QuadMesh::from_mask(nx, ny, 1e-3, 4, &mask).unwrap();
        let area: usize = m.cells.iter().map(|c| c.span() * c.span()).sum();
        assert_eq!(area, nx * ny);
        assert_eq!(m.cells[m.owner(5, 7)].level, 0);
        assert_eq!(m.cells[m.owner(30, 20)].level, 0);
        assert!(m.cells.iter().any(|c| c.level == 4));
        for (k, c) in m.cells.iter().enumerate() {
            let (xr, yr) = c.fine_ranges();
            assert!(xr.end <= nx && yr.end <= ny);
            assert_eq!(m.owner(xr.start, yr.start), k);
        }
    }

    #[test]
    fn centres_in_half_units() {
        let c = Cell {
            level: 2,
            i: 3,
            j: 1,
        };
        // Covers fine x in [12, 16): centre 14 a = 28 half-units.
        assert_eq!(c.centre_half(), (28, 12));
        let f = Cell {
            level: 0,
            i: 5,
            j: 0,
        };
        assert_eq!(f.centre_half(), (11, 1));
    }

    #[test]
    fn height_rule_takes_the_highest_point() {
        let (nx, ny) = (8, 8);
        let mut mask = vec![false; nx * ny];
        mask[0] = true;
        let m = QuadMesh::from_mask(nx, ny, 1.0, 2, &mask).unwrap();
        let g: Vec<f64> = (0..nx * ny).map(|k| 1.0 + k as f64).collect();
        let gm = m.restrict_gap(&g);
        let k = m.owner(4, 4); // a 4 x 4 block from (4, 4)
        assert_eq!(m.cells[k].level, 2);
        assert_eq!(gm[k], g[4 * ny + 4]);
        assert_eq!(gm[m.owner(0, 0)], 1.0);
    }

    #[test]
    fn dilation_is_a_square_neighbourhood() {
        let (nx, ny) = (7, 6);
        let mut mask = vec![false; nx * ny];
        mask[3 * ny + 2] = true;
        let d = dilate(&mask, nx, ny, 1);
        let count = d.iter().filter(|&&b| b).count();
        assert_eq!(count, 9);
        assert!(d[2 * ny + 1] && d[4 * ny + 3] && !d[5 * ny + 2]);
    }
}
