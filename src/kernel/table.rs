//! Coefficient tables over all cell offsets of a uniform grid of `a_x x a_y`
//! cells (physics.md section 3, "Discretisation": the operator is
//! block-Toeplitz; section 11: Love's closed form is for a rectangle).
//!
//! When `e_v` is along a grid axis and any layer is thicker than the
//! kernel's thin limit, the tables come from the row march
//! ([`super::march`]): the canonical `+x` problem, mirrored and/or
//! transposed onto the grid's offsets (with the sign of the derivative
//! flipped under a mirror). Layers below that limit (and above the local
//! limit of [`super::thin`]) evaluate only the offsets within the layer's
//! reach and carry the rest of each row by its memory terms
//! ([`super::window`]). The thin-layer band's continuation off the grid
//! axes scatters its few nonzero memories through the layer's lattice
//! kernel ([`super::thin_oblique`]). Other directions and derivatives transverse to
//! `e_v` are evaluated per offset (correct, much slower: ~20-40 us per
//! offset for `K` on a half-space, ~0.2 ms for `D`).

use rayon::prelude::*;

use super::march::canonical;
use super::progress::Progress;
use super::thin_oblique::oblique_table;
use super::window::{windowed, Offsets};
use super::{Axis, SlidingKernel, ThetaRule};
use crate::response::Grid;

/// Values for all offsets of an `nx x ny` grid.
///
/// `values[(di + nx - 1) * (2 ny - 1) + (dj + ny - 1)]` for
/// `di in -(nx-1)..=(nx-1)`, `dj in -(ny-1)..=(ny-1)`: the coefficient at the
/// centre of cell `(i, j)` due to unit pressure on cell `(i - di, j - dj)`.
#[derive(Debug, Clone, PartialEq)]
pub struct CoefficientTable {
    pub nx: usize,
    pub ny: usize,
    /// Cell side along x `a_x` \[m\].
    pub cell_size: f64,
    /// Cell side along y `a_y` \[m\] (equal to `cell_size` for square cells).
    pub cell_size_y: f64,
    pub values: Vec<f64>,
}

impl CoefficientTable {
    /// Flat index of offset `(di, dj)`.
    #[inline]
    pub fn index(&self, di: isize, dj: isize) -> usize {
        let i = (di + self.nx as isize - 1) as usize;
        let j = (dj + self.ny as isize - 1) as usize;
        i * (2 * self.ny - 1) + j
    }

    /// The value at offset `(di, dj)`; panics outside the table.
    #[inline]
    pub fn get(&self, di: isize, dj: isize) -> f64 {
        assert!(
            di.unsigned_abs() < self.nx && dj.unsigned_abs() < self.ny,
            "offset ({di}, {dj}) outside a {} x {} table",
            self.nx,
            self.ny
        );
        self.values[self.index(di, dj)]
    }
}

/// `K` at the vertex offsets `((i + 1/2) a, (j + 1/2) a)`, `i in -nx..nx`,
/// `j in -ny..ny`: the displacement at a cell corner of an `nx x ny` grid
/// due to unit pressure on a cell, the coefficient from a fine source cell
/// to the centre of a coarser (`2^l a`, `l >= 1`) cell of an aligned
/// quadtree ([`crate::mesh`]).
///
/// `values[(i + nx) * 2 ny + (j + ny)]`.
#[derive(Debug, Clone, PartialEq)]
pub struct VertexTable {
    pub nx: usize,
    pub ny: usize,
    /// Cell side `a` \[m\].
    pub cell_size: f64,
    pub values: Vec<f64>,
}

impl VertexTable {
    /// Flat index of the offset `((i + 1/2) a, (j + 1/2) a)`.
    #[inline]
    pub fn index(&self, i: isize, j: isize) -> usize {
        (i + self.nx as isize) as usize * (2 * self.ny) + (j + self.ny as isize) as usize
    }

    /// The value at `((i + 1/2) a, (j + 1/2) a)`; panics outside the table.
    #[inline]
    pub fn get(&self, i: isize, j: isize) -> f64 {
        assert!(
            i >= -(self.nx as isize)
                && i < self.nx as isize
                && j >= -(self.ny as isize)
                && j < self.ny as isize,
            "vertex offset ({i}, {j}) outside a {} x {} table",
            self.nx,
            self.ny
        );
        self.values[self.index(i, j)]
    }
}

/// The orientation of `e_v` when the row march applies (along x or y, sign
/// +1/-1), `None` for other directions and for layers thinner than the
/// kernel's thin limit.
fn march_plan(k: &SlidingKernel, cell: f64) -> Option<(Axis, f64)> {
    // `cell`: the longer side (a panel of the march is at most that long).
    let thin = match (k.theta(), k.thin_limit()) {
        (Some(t), Some(limit)) => t.layer.thickness < limit * cell,
        _ => false,
    };
    orientation(k).filter(|_| !thin)
}

/// The orientation of `e_v` along a grid axis (axis, sign), if it is.
fn orientation(k: &SlidingKernel) -> Option<(Axis, f64)> {
    let (ex, ey) = k.e;
    match (ex, ey) {
        (x, y) if x == 1.0 && y == 0.0 => Some((Axis::X, 1.0)),
        (x, y) if x == -1.0 && y == 0.0 => Some((Axis::X, -1.0)),
        (x, y) if x == 0.0 && y == 1.0 => Some((Axis::Y, 1.0)),
        (x, y) if x == 0.0 && y == -1.0 => Some((Axis::Y, -1.0)),
        _ => None,
    }
}

/// Offsets of a table: `(i + s) a_x, (j + s) a_y` with `s = 0` (cell centres,
/// `i in -(nx-1)..=(nx-1)`) or `s = 1/2` (vertices, `i in -nx..nx`).
#[derive(Clone, Copy)]
struct Lattice {
    nx: usize,
    ny: usize,
    vertex: bool,
}

impl Lattice {
    /// First index along x and y.
    fn first(&self) -> (isize, isize) {
        let o = if self.vertex { 0 } else { 1 };
        (o - self.nx as isize, o - self.ny as isize)
    }

    /// Values along x and y.
    fn width(&self) -> (usize, usize) {
        let o = if self.vertex { 0 } else { 1 };
        (2 * self.nx - o, 2 * self.ny - o)
    }

    fn shift(&self) -> f64 {
        if self.vertex {
            0.5
        } else {
            0.0
        }
    }
}

/// Table values on `lat` (row-major in x), by the row march where it
/// applies and per offset otherwise.
fn values(
    k: &SlidingKernel,
    lat: Lattice,
    a: (f64, f64),
    derivative: Option<Axis>,
    force_per_offset: bool,
) -> Vec<f64> {
    if k.is_band(a.0, a.1) {
        // The vertex offsets of the adaptive mesh lie off the band
        // kernel's lattice: they keep the resolved cell integral.
        if lat.vertex {
            return values(
                &k.clone().without_local_limit(),
                lat,
                a,
                derivative,
                force_per_offset,
            );
        }
        if k.frame(0.0, 0.0, a.0, a.1).is_none() {
            if let Some(b) = k.band_stencil(a.0, a.1) {
                return oblique_table(k, &b, (lat.first(), lat.width()), a, derivative);
            }
        }
        return per_offset(k, lat, a, derivative);
    }
    let orient = march_plan(k, a.0.max(a.1)).filter(|_| !force_per_offset);
    match orient {
        Some((slide_axis, sign)) if derivative.is_none_or(|d| d == slide_axis) => {
            marched(k, lat, a, derivative.is_some(), slide_axis, sign)
        }
        _ => match orientation(k) {
            // A layer below the march's limit, above the local limit.
            Some((slide_axis, _))
                if !force_per_offset
                    && k.theta().is_some()
                    && k.theta_rule() == ThetaRule::CellIntegral
                    && !k.is_thin(a.0, a.1)
                    && derivative.is_none_or(|d| d == slide_axis) =>
            {
                let offsets = Offsets {
                    first: lat.first(),
                    width: lat.width(),
                    shift: lat.shift(),
                };
                windowed(k, offsets, a, derivative, slide_axis)
            }
            _ => match derivative {
                Some(axis) if !force_per_offset => per_offset_derivative(k, lat, a, axis),
                _ => per_offset(k, lat, a, derivative),
            },
        },
    }
}

/// Per-offset evaluation of every entry (rayon over rows).
fn per_offset(
    k: &SlidingKernel,
    lat: Lattice,
    (ax, ay): (f64, f64),
    derivative: Option<Axis>,
) -> Vec<f64> {
    let cell = k.cell(ax, ay);
    let (wx, wy) = lat.width();
    let (fx, fy) = lat.first();
    let s = lat.shift();
    let progress = Progress::new("coefficient table (per offset)", wx as u64);
    let mut out = vec![0.0; wx * wy];
    out.par_chunks_mut(wy).enumerate().for_each(|(ii, row)| {
        let x = ((ii as isize + fx) as f64 + s) * ax;
        for (jj, v) in row.iter_mut().enumerate() {
            let y = ((jj as isize + fy) as f64 + s) * ay;
            *v = match derivative {
                None => k.coefficient_with(&cell, x, y).total(),
                Some(axis) => k.derivative_with(&cell, x, y, axis),
            };
        }
        progress.inc();
    });
    progress.finish();
    out
}

/// Per-offset table of the cell-averaged derivative `D_x` or `D_y`:
/// `[Kbar(x + a/2) - Kbar(x - a/2)] / a` along `axis`
/// ([`SlidingKernel::derivative_with`]), each `Kbar` evaluated once on the
/// lattice shifted by half a cell and shared by the two offsets it lies
/// between, where [`per_offset`] evaluates it twice (half the memory
/// integrals: the table of an off-axis layer takes 10 `K` tables' time).
/// A thin layer's tables (`thin`, `band`) have their own stencils and go
/// entry by entry.
fn per_offset_derivative(
    k: &SlidingKernel,
    lat: Lattice,
    (ax, ay): (f64, f64),
    axis: Axis,
) -> Vec<f64> {
    let cell = k.cell(ax, ay);
    if cell.thin.is_some() || cell.band.is_some() {
        return per_offset(k, lat, (ax, ay), Some(axis));
    }
    let (wx, wy) = lat.width();
    let (fx, fy) = lat.first();
    let s = lat.shift();
    let x_of = |ii: usize| ((ii as isize + fx) as f64 + s) * ax;
    let y_of = |jj: usize| ((jj as isize + fy) as f64 + s) * ay;
    // Kbar on the half-shifted lattice: one more value along `axis`.
    let (hx, hy) = match axis {
        Axis::X => (wx + 1, wy),
        Axis::Y => (wx, wy + 1),
    };
    let progress = Progress::new("derivative table (per offset)", hx as u64);
    let mut half = vec![0.0; hx * hy];
    half.par_chunks_mut(hy).enumerate().for_each(|(ii, row)| {
        for (jj, v) in row.iter_mut().enumerate() {
            *v = match axis {
                Axis::X => k.kbar(&cell, x_of(ii) - 0.5 * ax, y_of(jj), Axis::X),
                Axis::Y => k.kbar(&cell, x_of(ii), y_of(jj) - 0.5 * ay, Axis::Y),
            };
        }
        progress.inc();
    });
    progress.finish();
    let mut out = vec![0.0; wx * wy];
    out.par_chunks_mut(wy).enumerate().for_each(|(ii, row)| {
        for (jj, v) in row.iter_mut().enumerate() {
            *v = match axis {
                Axis::X => (half[(ii + 1) * hy + jj] - half[ii * hy + jj]) / ax,
                Axis::Y => (half[ii * hy + jj + 1] - half[ii * hy + jj]) / ay,
            };
        }
    });
    out
}

/// The canonical `+x` march mapped onto `lat`'s offsets.
fn marched(
    k: &SlidingKernel,
    lat: Lattice,
    (ax, ay): (f64, f64),
    derivative: bool,
    slide_axis: Axis,
    sign: f64,
) -> Vec<f64> {
    // Canonical problem: sliding along +x, `na` cells of side `aa` along,
    // `nt` cells of side `at` across.
    let (na, nt, aa, at) = match slide_axis {
        Axis::X => (lat.nx, lat.ny, ax, ay),
        Axis::Y => (lat.ny, lat.nx, ay, ax),
    };
    let canon = canonical(
        k,
        na,
        nt,
        (aa, at),
        derivative,
        slide_axis,
        sign,
        lat.vertex,
    );
    let canon_lat = Lattice {
        nx: na,
        ny: nt,
        vertex: lat.vertex,
    };
    let (cfa, cft) = canon_lat.first();
    let wt = canon_lat.width().1;
    let (wx, wy) = lat.width();
    let (fx, fy) = lat.first();
    // Mirroring the offset `along + s` gives `-along - 2s`.
    let mirror = if lat.vertex { 1 } else { 0 };
    let flip = if derivative && sign < 0.0 { -1.0 } else { 1.0 };
    let mut out = vec![0.0; wx * wy];
    for ii in 0..wx {
        for jj in 0..wy {
            let (i, j) = (ii as isize + fx, jj as isize + fy);
            let (along, across) = match slide_axis {
                Axis::X => (i, j),
                Axis::Y => (j, i),
            };
            let along = if sign > 0.0 { along } else { -along - mirror };
            let ia = (along - cfa) as usize;
            let it = (across - cft) as usize;
            out[ii * wy + jj] = flip * canon[ia * wt + it];
        }
    }
    out
}

/// [`CoefficientTable`] of `K` or of the derivative along `derivative`: by
/// the row march where it applies, or per offset everywhere when
/// `force_per_offset` (the reference).
pub(super) fn build(
    k: &SlidingKernel,
    grid: &Grid,
    derivative: Option<Axis>,
    force_per_offset: bool,
) -> CoefficientTable {
    let ((nx, ny), (ax, ay)) = (grid.size(), grid.cell());
    let lat = Lattice {
        nx,
        ny,
        vertex: false,
    };
    CoefficientTable {
        nx,
        ny,
        cell_size: ax,
        cell_size_y: ay,
        values: values(k, lat, (ax, ay), derivative, force_per_offset),
    }
}

/// [`VertexTable`] of `K`.
pub(super) fn build_vertex(k: &SlidingKernel, nx: usize, ny: usize, cell: f64) -> VertexTable {
    let lat = Lattice {
        nx,
        ny,
        vertex: true,
    };
    VertexTable {
        nx,
        ny,
        cell_size: cell,
        values: values(k, lat, (cell, cell), None, false),
    }
}
