//! Sliding along x (`e_v = (1, 0)` or `(-1, 0)`): every multiplier depends
//! on `w = -v e_x q_x` only, so a node's stress-rate field of component
//! `c` under multiplier `r` is `sum_kx r(kx) G_c(kx, y) exp(i kx x)` with
//! `G_c(kx, y) = sum_ky P f s_c exp(i ky y)` free of the multiplier
//! (physics.md section 14): the transforms along y run once per component
//! and depth, and each multiplier costs one real transform along x per
//! row.
//!
//! The modes are laid out by column ([`Columns`]): for each `kx >= 0` the
//! whole column of `ky` (the negative `ky` by the Hermitian symmetry of the
//! real field, `F(kx, -ky) = conj F(-kx, ky)`), so that a node fills and
//! transforms contiguous columns; a tiled transpose gives the rows. The
//! same evaluation serves the full grid and the coarser grids of deep
//! nodes (`band.rs`: the modes of the node's band, no Nyquist modes). On
//! the full grid the y-Nyquist modes' mean over the signs of `ky` shares
//! the multiplier of its `kx`; the x-Nyquist column (whose mean over the
//! signs of `kx` mixes `r(w)` and `r(-w)`) is transformed along y per
//! multiplier, and the odd parts' squares (`nyquist.rs`), summed over the
//! multipliers, are added as the rows are squared.

use std::sync::Arc;

use num_complex::Complex64;
use rayon::prelude::*;
use realfft::{ComplexToReal, RealFftPlanner};
use rustfft::{Fft, FftPlanner};

use super::super::stress::unit_component;
use super::form::{accumulate, component, field_for};
use super::nyquist::OddForms;
use super::{Dissipation, RateFn};
use crate::heat::error::HeatError;
use crate::operator::signed_index;
use crate::surface::height_fft;

/// Side of the tiles the transposes move.
const TILE: usize = 32;

/// One mode of a column: `|q|`, `q / |q|` and `P(q) / N`; `nyquist`
/// marks a y-Nyquist mode, whose stress is the mean over the signs of its
/// `ky` (`P` then the half spectrum's coefficient, halved).
#[derive(Clone, Copy, Default)]
pub(super) struct Entry {
    k: f64,
    n: (f64, f64),
    p: Complex64,
    nyquist: bool,
}

/// The modes of one grid's separable evaluation by column: `kx = 0..cols`,
/// each column the `my` values of `ky` (index `j`, `ky` signed as the
/// grid's), and the transforms of the grid.
pub(super) struct Columns {
    mx: usize,
    my: usize,
    cols: usize,
    entries: Vec<Entry>,
    /// Whether the full grid's Nyquist modes are added (the x-Nyquist
    /// column per multiplier and the odd parts).
    full: bool,
    line_y: Arc<dyn Fft<f64>>,
    row_x: Arc<dyn ComplexToReal<f64>>,
}

impl Columns {
    /// The entries' buffer, for the next node's [`Dissipation::band_columns`].
    pub(super) fn recycle(self) -> Vec<Entry> {
        self.entries
    }
}

/// The buffers of a node, kept from node to node (tens of MB on the
/// largest grids: fresh ones cost their page faults).
#[derive(Default)]
pub(super) struct SeparableWork {
    /// `P f` and `t = |q| z` of every entry.
    amp: Vec<(Complex64, f64)>,
    /// One component's columns.
    col: Vec<Complex64>,
    /// `G_c(kx, y)` of every component, by row `y` (`cols` entries).
    g: Vec<Vec<Complex64>>,
    /// The node's density by row `y`.
    sum: Vec<f64>,
}

impl Dissipation {
    /// Whether every multiplier depends on `kx` only.
    pub(super) fn along_x(&self) -> bool {
        self.e.1 == 0.0
    }

    /// The full grid's columns: every mode but `q = 0` and the x-Nyquist
    /// ones (`kx <= (nx - 1) / 2`).
    pub(super) fn full_columns(&self) -> Columns {
        let (nx, ny) = (self.nx, self.ny);
        let cols = (nx - 1) / 2 + 1;
        let mut entries = vec![Entry::default(); cols * ny];
        entries
            .par_chunks_mut(ny)
            .enumerate()
            .for_each(|(kx, column)| {
                for (j, entry) in column.iter_mut().enumerate() {
                    let ky = signed_index(j, ny).0 as isize;
                    if kx == 0 && ky == 0 {
                        continue;
                    }
                    let nyquist = ny % 2 == 0 && 2 * j == ny;
                    let p = if nyquist {
                        self.half_coefficient(kx as isize, ky.abs()) * 0.5
                    } else {
                        self.coefficient(kx as isize, ky)
                    };
                    *entry = self.entry(kx as isize, ky, p, nyquist);
                }
            });
        self.columns(nx, ny, cols, entries, true)
    }

    /// The columns of a coarse `mx x my` grid holding the band `|kx| <= bx`,
    /// `|ky| <= by` (`band.rs`: below both grids' Nyquist modes), written
    /// over `entries` (a previous node's buffer, [`Columns::recycle`]).
    pub(super) fn band_columns(
        &self,
        (mx, my): (usize, usize),
        (bx, by): (usize, usize),
        mut entries: Vec<Entry>,
    ) -> Columns {
        debug_assert!(4 * bx < mx && 4 * by < my && 2 * bx < self.nx && 2 * by < self.ny);
        let cols = bx + 1;
        entries.clear();
        entries.resize(cols * my, Entry::default());
        for (kx, column) in entries.chunks_mut(my).enumerate() {
            for ky in -(by as isize)..=by as isize {
                if kx == 0 && ky == 0 {
                    continue;
                }
                let j = ky.rem_euclid(my as isize) as usize;
                column[j] = self.entry(kx as isize, ky, self.coefficient(kx as isize, ky), false);
            }
        }
        self.columns(mx, my, cols, entries, false)
    }

    fn columns(
        &self,
        mx: usize,
        my: usize,
        cols: usize,
        entries: Vec<Entry>,
        full: bool,
    ) -> Columns {
        Columns {
            mx,
            my,
            cols,
            entries,
            full,
            line_y: FftPlanner::<f64>::new().plan_fft_inverse(my),
            row_x: RealFftPlanner::<f64>::new().plan_fft_inverse(mx),
        }
    }

    fn entry(&self, kx: isize, ky: isize, p: Complex64, nyquist: bool) -> Entry {
        let tau2 = std::f64::consts::TAU;
        let q = (
            tau2 * kx as f64 / self.length.0,
            tau2 * ky as f64 / self.length.1,
        );
        let k = q.0.hypot(q.1);
        Entry {
            k,
            n: (q.0 / k, q.1 / k),
            p,
            nyquist,
        }
    }

    /// `out += weight sum_rates D_rate(z)` on the grid of `columns` (`out`
    /// C order, axis 0 = x; module docs).
    pub(super) fn add_separable(
        &self,
        columns: &Columns,
        rates: &[RateFn],
        z: f64,
        weight: f64,
        work: &mut SeparableWork,
        out: &mut [f64],
    ) -> Result<(), HeatError> {
        let (mx, my, cols, nu) = (columns.mx, columns.my, columns.cols, self.nu);
        let hx = mx / 2 + 1;
        let count = if nu == 0.5 { 5 } else { 6 };
        let tau2 = std::f64::consts::TAU;
        // `P f` and `t` of every entry at this depth.
        work.amp.resize(columns.entries.len(), Default::default());
        work.amp
            .par_chunks_mut(4096)
            .zip(columns.entries.par_chunks(4096))
            .for_each(|(amp, entries)| {
                for (a, e) in amp.iter_mut().zip(entries) {
                    let t = e.k * z;
                    *a = (e.p * (-t).exp(), t);
                }
            });
        // `G_c(kx, y)`: each column filled and transformed along y, then
        // the columns transposed into rows.
        work.col.resize(cols * my, Complex64::default());
        work.g.resize_with(count, Vec::new);
        let line_y = &columns.line_y;
        for (c, gc) in work.g.iter_mut().enumerate() {
            work.col
                .par_chunks_mut(my)
                .zip(columns.entries.par_chunks(my))
                .zip(work.amp.par_chunks(my))
                .for_each_init(
                    || vec![Complex64::default(); line_y.get_inplace_scratch_len()],
                    |scratch, ((col, entries), amp)| {
                        for ((v, e), &(a, t)) in col.iter_mut().zip(entries).zip(amp) {
                            *v = if e.nyquist {
                                let mirror = (e.n.0, -e.n.1);
                                a * (unit_component(e.n, t, nu, c)
                                    + unit_component(mirror, t, nu, c))
                            } else {
                                a * unit_component(e.n, t, nu, c)
                            };
                        }
                        line_y.process_with_scratch(col, scratch);
                    },
                );
            gc.resize(my * cols, Complex64::default());
            height_fft::transpose_into(&work.col, cols, my, gc);
        }
        // Per multiplier: its values at `kx < cols`; on the full grid the
        // x-Nyquist column of every component along y (Hermitian in `ky`:
        // real), and the odd parts' squares summed over the multipliers.
        let per_rate: Vec<(Vec<Complex64>, Vec<f64>, OddForms)> = rates
            .par_iter()
            .map(|rate| {
                let r: Vec<Complex64> = (0..cols)
                    .map(|kx| {
                        let qx = tau2 * kx as f64 / self.length.0;
                        rate.at(-self.speed * (qx * self.e.0))
                    })
                    .collect();
                let mut x_nyquist = Vec::new();
                let mut odd = OddForms::default();
                if columns.full && (mx % 2 == 0 || my % 2 == 0) {
                    let nyquist = self.nyquist_parts(rate, z);
                    if mx % 2 == 0 {
                        let mut col = vec![Complex64::default(); my];
                        let mut scratch =
                            vec![Complex64::default(); line_y.get_inplace_scratch_len()];
                        for c in 0..count {
                            for (j, v) in col.iter_mut().enumerate() {
                                *v = if 2 * j <= my {
                                    component(&nyquist.row[j].mean, c)
                                } else {
                                    component(&nyquist.row[my - j].mean, c).conj()
                                };
                            }
                            line_y.process_with_scratch(&mut col, &mut scratch);
                            x_nyquist.extend(col.iter().map(|v| v.re));
                        }
                    }
                    odd = self.odd_forms(&nyquist);
                }
                (r, x_nyquist, odd)
            })
            .collect();
        let mut odd = OddForms::default();
        per_rate.iter().for_each(|(_, _, o)| odd.add(o));
        let (dev, trace) = (weight * (1.0 + nu), weight * (1.0 - 2.0 * nu) / 3.0);
        // Row by row: every multiplier's components transformed along x
        // and squared while the row is in cache.
        work.sum.resize(mx * my, 0.0);
        let g = &work.g;
        let row_x = &columns.row_x;
        work.sum.par_chunks_mut(mx).enumerate().try_for_each_init(
            || {
                (
                    vec![Complex64::default(); hx],
                    vec![0.0; mx],
                    vec![0.0; mx],
                    row_x.make_scratch_vec(),
                )
            },
            |(row, field, first, scratch), (y, sum)| {
                for (x, s) in sum.iter_mut().enumerate() {
                    *s = weight * odd.at(x, y);
                }
                for (r, x_nyquist, _) in &per_rate {
                    for (c, gc) in g.iter().enumerate() {
                        let gy = &gc[y * cols..(y + 1) * cols];
                        for ((v, g), r) in row.iter_mut().zip(gy).zip(r) {
                            *v = g * r;
                        }
                        row[cols..].fill(Complex64::default());
                        row[0].im = 0.0;
                        if columns.full && mx % 2 == 0 {
                            row[hx - 1] = Complex64::new(x_nyquist[c * my + y], 0.0);
                        }
                        row_x
                            .process_with_scratch(row, field_for(c, field, first), scratch)
                            .map_err(|e| {
                                HeatError::Transform(format!("inverse real FFT failed: {e}"))
                            })?;
                        accumulate(c, field, first, sum, dev, trace);
                    }
                }
                Ok::<(), HeatError>(())
            },
        )?;
        // `sum` is by row y; `out` by x.
        transpose_add(&work.sum, out, mx, my);
        Ok(())
    }
}

/// `out[x * my + y] += sum[y * mx + x]`, tile by tile.
fn transpose_add(sum: &[f64], out: &mut [f64], mx: usize, my: usize) {
    out.par_chunks_mut(TILE * my)
        .enumerate()
        .for_each(|(block, out)| {
            let x0 = block * TILE;
            let width = out.len() / my;
            for y0 in (0..my).step_by(TILE) {
                for x in 0..width {
                    for y in y0..(y0 + TILE).min(my) {
                        out[x * my + y] += sum[y * mx + x0 + x];
                    }
                }
            }
        });
}
