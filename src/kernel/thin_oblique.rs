//! The thin-layer law's grid continuation ([`super::thin_band`]) for a
//! sliding direction off the grid axes (physics.md section 3, "Finite
//! thickness", and the line identity of "Discretisation").
//!
//! The continuation is `w = D * (J* p)` on the lattice of cell centres: the
//! layer's lattice kernel `D` (isotropic, independent of `e_v`) applied to
//! the memory `J* p` of Eq. 4 of the cell-constant pressure at the centres.
//! `J* p` at a point `x` is one line integral along the trail,
//! `glassy p(x) + int_0^inf phi(s) p(x + s e_v) ds`. Along a grid axis the
//! trail of a centre runs along its row, through the centres of the row, so
//! the continuation needed only the row's bracket
//! ([`SlidingKernel::law_bracket`]) and `D` as a one-dimensional
//! convolution along the row: that was the only reason it needed a grid
//! axis. Off the axes the trail runs between the grid lines; for a unit
//! pressure on the source cell `[-a_x/2, a_x/2] x [-a_y/2, a_y/2]` it is
//! still in closed form: the trail from `x` is inside the cell for `s` in
//! `[s_in, s_out]` (the intersection of the two slabs), and
//!
//! `B(x) = glassy P(x) + sum_k C_k (e^{-s_in / l_k} - e^{-s_out / l_k})`,
//!
//! `P` the cell's indicator (1/2 on an edge, 1/4 on a corner). A component
//! of `e_v` that vanishes leaves its slab whole, with weight 1 inside, 1/2
//! on an edge and 0 outside, which is the row bracket's convention: on a grid
//! axis `B` is exactly [`SlidingKernel::law_bracket`] on the source's row
//! (and half of it on the two rows whose centre lines are its edges).
//! The coefficient is then the two-dimensional convolution
//!
//! `K(c a + t) = sum_c' D(c - c') B(c' a + t)`
//!
//! over the lattice `c'` shifted by `t` (`t = 0` for the coefficients; the
//! friction stencil's `t = +-a_x/2 e_x` or `+-a_y/2 e_y`, the work of the
//! cell-constant traction on the field, `D_x = [K(d + a_x/2 e_x) -
//! K(d - a_x/2 e_x)] / a_x`, as [`super::thin_band`] takes along `e_v`).
//! On a grid axis this is the on-axis continuation: along `e_v` the same
//! shifted lattice; across it the shifted points lie on the source's edges,
//! `K(j + 1/2) = (K(j) + K(j + 1)) / 2`, the centred difference. So the
//! coefficients and the stencil along `e_v` are continuous as the
//! direction tends to an axis: at `0.01` degrees from an axis the trail of
//! a centre leaves its row after `a / (2 sin 0.01 deg) = 2865 a`, where the
//! memory is gone. The stencil across `e_v` tends to the one-sided
//! difference there (the trail of a point on an edge enters the row or
//! leaves it) and enters the friction with the weight `sin theta`.
//!
//! Cost: `B` is nonzero only on the cells whose trail crosses the source
//! (a strip two or three cells wide upstream), so a table is the scatter
//! of those few values through `D` (`(2 W + 1)^2` per value, `W = R h / a
//! + 8`), not a per-offset evaluation of the resolved cell integral.

use rayon::prelude::*;

use super::thin_band::BandStencil;
use super::{Axis, Coefficient, SlidingKernel};

/// The trail's parameter interval `(lo, hi)` inside the slab `|x| <= half`
/// for a trail moving at `e` along `x`, and the slab's weight (1; for
/// `e = 0`, 1 inside, 1/2 on an edge, 0 outside).
fn slab(x: f64, e: f64, half: f64) -> (f64, f64, f64) {
    if e == 0.0 {
        let w = step(x, half);
        (f64::NEG_INFINITY, f64::INFINITY, w)
    } else {
        let (a, b) = ((-half - x) / e, (half - x) / e);
        (a.min(b), a.max(b), 1.0)
    }
}

/// The indicator of `|x| <= half`, 1/2 on an edge (within `1e-9 half`).
fn step(x: f64, half: f64) -> f64 {
    let d = half - x.abs();
    if d.abs() <= 1e-9 * half {
        0.5
    } else if d > 0.0 {
        1.0
    } else {
        0.0
    }
}

impl SlidingKernel {
    /// `(elastic, memory)` of `B` (module docs) at the point `(x, y)` from
    /// a unit pressure on the `ax x ay` cell at the origin.
    pub(super) fn ray_bracket(&self, (x, y): (f64, f64), (ax, ay): (f64, f64)) -> (f64, f64) {
        let (ex, ey) = self.e;
        let (hx, hy) = (0.5 * ax, 0.5 * ay);
        let pv = step(x, hx) * step(y, hy);
        let (lx, ux, wx) = slab(x, ex, hx);
        let (ly, uy, wy) = slab(y, ey, hy);
        let (s_in, s_out, w) = (lx.max(ly).max(0.0), ux.min(uy), wx * wy);
        let inside = w != 0.0 && s_out > s_in;
        let mem = self
            .terms
            .iter()
            .map(|&(c, l)| {
                let m = if l == 0.0 {
                    pv
                } else if !l.is_finite() || !inside {
                    0.0
                } else {
                    w * ((-s_in / l).exp() - (-s_out / l).exp())
                };
                c * m
            })
            .sum();
        (self.glassy * pv, mem)
    }

    /// `K(d)` of the module docs at the offset `(dx, dy)` (any point: the
    /// lattice shifted by `d - c a`, `c` the nearest centre).
    pub(crate) fn oblique_coefficient(
        &self,
        b: &BandStencil,
        (ax, ay): (f64, f64),
        (dx, dy): (f64, f64),
    ) -> Coefficient {
        let (i, j) = ((dx / ax).round(), (dy / ay).round());
        if !i.is_finite() || !j.is_finite() {
            return Coefficient::NAN;
        }
        let (tx, ty) = (dx - i * ax, dy - j * ay);
        let (i, j) = (i as i64, j as i64);
        let w = b.half as i64;
        let mut out = Coefficient::default();
        for si in i - w..=i + w {
            for sj in j - w..=j + w {
                let d = b.get(i - si, j - sj);
                if d == 0.0 {
                    continue;
                }
                let (el, mem) =
                    self.ray_bracket((si as f64 * ax + tx, sj as f64 * ay + ty), (ax, ay));
                out.elastic += d * el;
                out.viscoelastic += d * mem;
            }
        }
        out
    }

    /// The friction stencil of the module docs along `axis`.
    pub(crate) fn oblique_derivative(
        &self,
        b: &BandStencil,
        (ax, ay): (f64, f64),
        (dx, dy): (f64, f64),
        axis: Axis,
    ) -> f64 {
        let (ex, ey, a) = match axis {
            Axis::X => (0.5 * ax, 0.0, ax),
            Axis::Y => (0.0, 0.5 * ay, ay),
        };
        let k = |x: f64, y: f64| self.oblique_coefficient(b, (ax, ay), (x, y)).total();
        (k(dx + ex, dy + ey) - k(dx - ex, dy - ey)) / a
    }
}

/// The table of `K` (`derivative = None`) or of the friction stencil along
/// `derivative` on the offsets `(i a_x, j a_y)`, `i = first.0 .. first.0 +
/// width.0` (row-major in x), likewise in y: the scatter of the module
/// docs, equal to [`SlidingKernel::oblique_coefficient`] per offset up to
/// the order of the sums.
pub(super) fn oblique_table(
    k: &SlidingKernel,
    b: &BandStencil,
    (first, width): ((isize, isize), (usize, usize)),
    (ax, ay): (f64, f64),
    derivative: Option<Axis>,
) -> Vec<f64> {
    let w = b.half as isize;
    let shifts: Vec<((f64, f64), f64)> = match derivative {
        None => vec![((0.0, 0.0), 1.0)],
        Some(Axis::X) => vec![((0.5 * ax, 0.0), 1.0 / ax), ((-0.5 * ax, 0.0), -1.0 / ax)],
        Some(Axis::Y) => vec![((0.0, 0.5 * ay), 1.0 / ay), ((0.0, -0.5 * ay), -1.0 / ay)],
    };
    // The sample lattice: every source within `W` of a target.
    let (sx, sy) = (first.0 - w, first.1 - w);
    let (nsx, nsy) = (width.0 + 2 * b.half, width.1 + 2 * b.half);
    // Per sample row, the nonzero `(j', weight B)` of all shifts.
    let rows: Vec<Vec<(isize, f64)>> = (0..nsx)
        .into_par_iter()
        .map(|r| {
            let si = r as isize + sx;
            let mut row = vec![];
            for c in 0..nsy {
                let sj = c as isize + sy;
                let mut v = 0.0;
                for &((tx, ty), wt) in &shifts {
                    let (el, mem) =
                        k.ray_bracket((si as f64 * ax + tx, sj as f64 * ay + ty), (ax, ay));
                    v += wt * (el + mem);
                }
                if v != 0.0 {
                    row.push((sj, v));
                }
            }
            row
        })
        .collect();
    let mut out = vec![0.0; width.0 * width.1];
    out.par_chunks_mut(width.1)
        .enumerate()
        .for_each(|(ii, target)| {
            let i = ii as isize + first.0;
            for di in -w..=w {
                let r = (i - di - sx) as usize;
                for &(sj, v) in &rows[r] {
                    // Targets j = sj + dj inside the table.
                    let lo = (first.1 - sj).max(-w);
                    let hi = (first.1 + width.1 as isize - 1 - sj).min(w);
                    for dj in lo..=hi {
                        let d = b.get(di as i64, dj as i64);
                        target[(sj + dj - first.1) as usize] += d * v;
                    }
                }
            }
        });
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::{CreepSpectrum, Material};
    use crate::response::{Grid, Layer, LayerBase, SlidingResponse};

    const A: f64 = 1e-4;

    /// The paper's material on a bonded incompressible layer `h = a/2`
    /// (inside the band), `v tau = 0.75 a`, sliding at `deg`.
    fn kernel(deg: f64) -> SlidingKernel {
        let m = Material::new(
            CreepSpectrum::standard_linear_solid(1e7 / 3.0, 1e7, 0.01).unwrap(),
            0.5,
        )
        .unwrap();
        let layer = Layer {
            thickness: 0.5 * A,
            base: LayerBase::Bonded,
        };
        let r = SlidingResponse::new(&m, 0.75 * A / 0.01, deg.to_radians(), Some(layer)).unwrap();
        let k = SlidingKernel::new(&r).unwrap();
        assert!(k.is_band(A, A));
        k
    }

    const OFFSETS: [(f64, f64); 8] = [
        (0.0, 0.0),
        (1.0, 0.0),
        (-1.0, 0.0),
        (-3.0, 0.0),
        (0.0, 1.0),
        (-1.0, 1.0),
        (-2.0, -1.0),
        (4.0, 2.0),
    ];

    /// On a grid axis (0, 90 and 180 degrees) the two-dimensional
    /// convolution of the module docs is the row continuation of
    /// `kernel/thin_band.rs`: coefficients and both friction stencils
    /// (along: cell edges; across: the centred difference) equal to the
    /// order of the sums (asserted 1e-12 of the self coefficient, whose
    /// terms are of its size).
    #[test]
    fn on_a_grid_axis_it_is_the_row_continuation() {
        for deg in [0.0, 90.0, 180.0] {
            let k = kernel(deg);
            let b = k.band_stencil(A, A).unwrap();
            let k00 = k.band_coefficient(&b, A, A, 0.0, 0.0).total().abs();
            for (i, j) in OFFSETS {
                let d = (i * A, j * A);
                let row = k.band_coefficient(&b, A, A, d.0, d.1);
                let oblique = k.oblique_coefficient(&b, (A, A), d);
                assert!(
                    (row.elastic - oblique.elastic).abs() < 1e-12 * k00
                        && (row.viscoelastic - oblique.viscoelastic).abs() < 1e-12 * k00,
                    "{deg} deg, ({i}, {j}): {row:?} vs {oblique:?}"
                );
                for axis in [Axis::X, Axis::Y] {
                    let row = k.band_derivative(&b, (A, A), d, axis);
                    let oblique = k.oblique_derivative(&b, (A, A), d, axis);
                    assert!(
                        (row - oblique).abs() < 1e-12 * k00 / A,
                        "{deg} deg, ({i}, {j}), {axis:?}: {row:e} vs {oblique:e}"
                    );
                }
            }
        }
    }

    /// The table's scatter against the per-offset sums, off the axes and
    /// a hair off one (asserted 1e-12 of the largest entry: the same terms
    /// summed in another order); and `1e-3` degrees off the x axis the
    /// trail of a centre leaves its row after `a / (2 sin 1e-3 deg)`,
    /// 28,600 cells: `K` and the stencil along x equal the on-axis tables
    /// but for the trail's length through a cell, longer by `1 / cos theta
    /// - 1 = 1.5e-10` (the memory's `e^{-s / l}` moves by that times `s / l`,
    /// a few: measured 5.8e-11 of the largest entry, asserted 1e-9); the
    /// stencil across differs by the one-sided difference (it enters the
    /// friction times `sin theta`).
    #[test]
    fn tables_are_the_per_offset_sums_and_continuous_at_an_axis() {
        let grid = Grid::square(5, 5, A).unwrap();
        let max = |v: &[f64]| v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        for deg in [1e-3, 10.0, 45.0, 120.0] {
            let k = kernel(deg);
            let b = k.band_stencil(A, A).unwrap();
            for derivative in [None, Some(Axis::X), Some(Axis::Y)] {
                let t = match derivative {
                    None => k.table(&grid).unwrap(),
                    Some(axis) => k.derivative_table(&grid, axis).unwrap(),
                };
                let scale = max(&t.values);
                for i in -4..=4 {
                    for j in -4..=4 {
                        let d = (i as f64 * A, j as f64 * A);
                        let v = match derivative {
                            None => k.oblique_coefficient(&b, (A, A), d).total(),
                            Some(axis) => k.oblique_derivative(&b, (A, A), d, axis),
                        };
                        let e = (t.get(i, j) - v).abs() / scale;
                        assert!(e < 1e-12, "{deg} deg {derivative:?} ({i}, {j}): {e:e}");
                    }
                }
            }
        }
        let (on, off) = (kernel(0.0), kernel(1e-3));
        for derivative in [None, Some(Axis::X)] {
            let table = |k: &SlidingKernel| match derivative {
                None => k.table(&grid).unwrap(),
                Some(axis) => k.derivative_table(&grid, axis).unwrap(),
            };
            let (t0, t1) = (table(&on), table(&off));
            let scale = max(&t0.values);
            let e = t0
                .values
                .iter()
                .zip(&t1.values)
                .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
            assert!(e < 1e-9 * scale, "{derivative:?}: {e:e} of {scale:e}");
        }
    }
}
