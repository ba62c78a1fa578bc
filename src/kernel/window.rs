//! Coefficient tables of layers thinner than the row march's limit (half a
//! cell) but above the local limit of [`super::thin`] (physics.md section 3,
//! "Finite thickness"), sliding along a grid axis.
//!
//! The layer's cell integral `M` vanishes beyond the reach `R h` of `Theta`,
//! so on a row along `e_v` the spatial factor is zero upstream of
//! `s_ref = -(a/2 + R h)` (the along coordinate of the source's trailing
//! edge less the reach). Per creep term the memory integral
//! `E_k(p) = int_0^inf (1/l_k) e^{-s/l_k} g(p + s e_v) ds` then obeys
//! `E_k(p) = e^{-(s_ref - p)/l_k} E_k(s_ref)` exactly for every `p <= s_ref`
//! on the row: one evaluation per term and row at `s_ref` carries every
//! target upstream of it, and only the targets within the reach are
//! evaluated per offset. The same holds for the width-averaged `Kbar` of the
//! friction stencil along `e_v`. Cost: about `(2 R h / a + 2)^2` per-offset
//! evaluations instead of `(2 R h / a + 2) n` (a 64^2 table at `h = a/16`:
//! 40-85 s before).

use rayon::prelude::*;

use super::line::{memory_integral, KinkLine, LineProblem, RELAXED};
use super::progress::Progress;
use super::{cell_kinks, Axis, Cell, SlidingKernel};

/// Offsets `((i + shift) a_x, (j + shift) a_y)`, `i = first.0 ..
/// first.0 + width.0` (row-major in x), likewise in y.
pub(super) struct Offsets {
    pub first: (isize, isize),
    pub width: (usize, usize),
    pub shift: f64,
}

impl SlidingKernel {
    /// Per creep term `(C_k, l_k)`: `int_0^inf (1/l_k) e^{-s/l_k} g(x + s e_v, y) ds`,
    /// `g` the spatial factor or, with `average`, its width average
    /// transverse to that axis; zero for relaxed, glassy and empty terms.
    fn memory_terms(&self, cell: &Cell, x: f64, y: f64, average: Option<Axis>) -> Vec<f64> {
        let (ax, ay) = (cell.love.ax, cell.love.ay);
        let margin = if average.is_some() { ax.max(ay) } else { 0.0 };
        if self.out_of_reach(cell, x, y, margin) {
            return vec![0.0; self.terms.len()];
        }
        let spatial = self.spatial(cell);
        let g = |px: f64, py: f64| match average {
            None => spatial(px, py),
            Some(axis) => self.transverse_average(cell, px, py, axis),
        };
        let mut kinks = cell_kinks(ax, ay).to_vec();
        match average {
            Some(Axis::X) => kinks.extend([KinkLine::Y(-ay), KinkLine::Y(0.0), KinkLine::Y(ay)]),
            Some(Axis::Y) => kinks.extend([KinkLine::X(-ax), KinkLine::X(0.0), KinkLine::X(ax)]),
            None => {}
        }
        let scale = cell.love.eval(x, y);
        self.terms
            .iter()
            .map(|&(c, l)| {
                if c == 0.0 || !l.is_finite() || l < RELAXED * ax.min(ay) {
                    return 0.0;
                }
                let problem = LineProblem {
                    d: (x, y),
                    e: self.e,
                    terms: &[(1.0, l)],
                    a_min: ax.min(ay),
                    a_max: ax.max(ay),
                    kinks: &kinks,
                    abs_tol: self.tol() * scale,
                    rel_tol: self.tol(),
                };
                memory_integral(&problem, g)
            })
            .collect()
    }

    /// `prefactor sum_k C_k e^{(p - s_ref)/l_k} E_k(s_ref)` for `p <= s_ref`.
    fn extrapolate(&self, at_ref: &[f64], p: f64, s_ref: f64) -> f64 {
        let mut s = 0.0;
        for (&(c, l), e) in self.terms.iter().zip(at_ref) {
            if *e != 0.0 {
                s += c * ((p - s_ref) / l).exp() * e;
            }
        }
        self.prefactor * s
    }
}

/// Table values of `K` (or of `D` along `derivative`, which must be the
/// sliding axis) for a layer below the row march's limit, `e_v` along
/// `slide_axis` (module docs).
pub(super) fn windowed(
    k: &SlidingKernel,
    g: Offsets,
    (ax, ay): (f64, f64),
    derivative: Option<Axis>,
    slide_axis: Axis,
) -> Vec<f64> {
    let cell = k.cell(ax, ay);
    let Some(reach) = cell.layer.as_ref().map(|lc| lc.reach()) else {
        unreachable!("windowed tables need the cell integrals of a layer")
    };
    let (ex, ey) = k.e;
    let aa = match slide_axis {
        Axis::X => ax,
        Axis::Y => ay,
    };
    let s_ref = -(0.5 * aa + reach);
    let (fx, fy) = g.first;
    let (wx, wy) = g.width;
    let pos = |i: usize, j: usize| {
        (
            ((i as isize + fx) as f64 + g.shift) * ax,
            ((j as isize + fy) as f64 + g.shift) * ay,
        )
    };
    // Per-term memory at `s_ref` on every row along `e_v`.
    let rows = match slide_axis {
        Axis::X => wy,
        Axis::Y => wx,
    };
    let refs: Vec<Vec<f64>> = (0..rows)
        .into_par_iter()
        .map(|r| {
            let (x, y) = match slide_axis {
                Axis::X => (s_ref * ex, pos(0, r).1),
                Axis::Y => (pos(r, 0).0, s_ref * ey),
            };
            k.memory_terms(&cell, x, y, derivative)
        })
        .collect();
    let along = |x: f64, y: f64| x * ex + y * ey;
    let row_of = |i: usize, j: usize| match slide_axis {
        Axis::X => j,
        Axis::Y => i,
    };
    let mut out = vec![0.0; wx * wy];
    let Some(axis) = derivative else {
        let progress = Progress::new("coefficient table (layer window)", wx as u64);
        out.par_chunks_mut(wy).enumerate().for_each(|(i, row)| {
            for (j, v) in row.iter_mut().enumerate() {
                let (x, y) = pos(i, j);
                let p = along(x, y);
                *v = if p <= s_ref {
                    k.extrapolate(&refs[row_of(i, j)], p, s_ref)
                } else {
                    k.coefficient_with(&cell, x, y).total()
                };
            }
            progress.inc();
        });
        progress.finish();
        return out;
    };
    // `Kbar` at the target edges `pos - a/2` (index m) and `pos + a/2`
    // (m + 1) along `axis`, each shared by two neighbouring targets.
    let (kx, ky, a) = match axis {
        Axis::X => (wx + 1, wy, ax),
        Axis::Y => (wx, wy + 1, ay),
    };
    let progress = Progress::new("friction-stencil table (layer window)", kx as u64);
    let mut kbar = vec![0.0; kx * ky];
    kbar.par_chunks_mut(ky).enumerate().for_each(|(i, row)| {
        for (j, v) in row.iter_mut().enumerate() {
            let (x, y) = pos(i, j);
            let (x, y) = match axis {
                Axis::X => (x - 0.5 * ax, y),
                Axis::Y => (x, y - 0.5 * ay),
            };
            let p = along(x, y);
            let r = row_of(i.min(wx - 1), j.min(wy - 1));
            *v = if p <= s_ref {
                k.extrapolate(&refs[r], p, s_ref)
            } else {
                k.kbar(&cell, x, y, axis)
            };
        }
        progress.inc();
    });
    for i in 0..wx {
        for j in 0..wy {
            let (lo, hi) = match axis {
                Axis::X => (i * ky + j, (i + 1) * ky + j),
                Axis::Y => (i * ky + j, i * ky + j + 1),
            };
            out[i * wy + j] = (kbar[hi] - kbar[lo]) / a;
        }
    }
    progress.finish();
    out
}
