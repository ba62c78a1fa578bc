//! Sliding along x (`e_v = (1, 0)` or `(-1, 0)`): every multiplier depends
//! on `w = -v e_x q_x` only, so a full-grid node's stress-rate field of
//! component `c` under multiplier `r` is
//! `sum_kx r(kx) G_c(kx, y) exp(i kx x)` with
//! `G_c(kx, y) = sum_ky P f s_c exp(i ky y)` free of the multiplier
//! (physics.md section 14): the transforms along y run once per component
//! and depth, and each multiplier costs one real transform along x per
//! row. The half spectrum in `ky` is extended to negative `ky` by its
//! Hermitian symmetry; the y-Nyquist modes' mean over the signs of `ky`
//! shares the multiplier of its `kx`; the x-Nyquist column (whose mean
//! over the signs of `kx` mixes `r(w)` and `r(-w)`) is transformed along
//! y per multiplier, and the odd parts are added as on the general path.

use num_complex::Complex64;
use rayon::prelude::*;

use super::super::stress::{mode_stress, unit_component, ModeStress};
use super::nyquist::NyquistParts;
use super::{accumulate, add, component, scaled, Dissipation, RateFn};
use crate::heat::error::HeatError;

/// The buffers of one full-grid node, kept from node to node (tens of MB
/// each on the largest grids: fresh ones cost their page faults).
#[derive(Default)]
pub(super) struct SeparableWork {
    /// `G_c(kx, y)` of every component.
    g: Vec<Vec<Complex64>>,
    /// The node's density by row `y`.
    sum: Vec<f64>,
}

impl Dissipation {
    /// Whether every multiplier depends on `kx` only.
    pub(super) fn along_x(&self) -> bool {
        self.e.1 == 0.0
    }

    /// `out += weight sum_rates D_rate(z)` on the full grid, sliding along
    /// x (module docs).
    pub(super) fn add_separable(
        &self,
        rates: &[RateFn],
        z: f64,
        weight: f64,
        work: &mut SeparableWork,
        out: &mut [f64],
    ) -> Result<(), HeatError> {
        let (nx, ny, nu) = (self.nx, self.ny, self.nu);
        let hx = nx / 2 + 1;
        // The largest kx that is not a Nyquist one.
        let kmax = (nx - 1) / 2;
        let count = if nu == 0.5 { 5 } else { 6 };
        let tau2 = std::f64::consts::TAU;
        // `P f` and `t` of the regular modes at this depth.
        let pf: Vec<(Complex64, f64)> = self
            .regular
            .iter()
            .map(|m| {
                let t = m.k * z;
                (m.p * (-t).exp(), t)
            })
            .collect();
        // The y-Nyquist modes' stresses (mean over the signs of `ky`)
        // times `P`, by `i` (the x-Nyquist one left out).
        let y_nyquist: Vec<ModeStress> = if ny % 2 == 0 {
            (0..nx)
                .map(|i| {
                    let (kx, nyq_x) = crate::operator::signed_index(i, nx);
                    let mut mean = ModeStress::default();
                    if !nyq_x {
                        let p = self.spectrum[(ny / 2) * nx + i];
                        let qx = tau2 * kx / self.length.0;
                        let qy = tau2 * (ny / 2) as f64 / self.length.1;
                        for b in [1.0, -1.0] {
                            let s = mode_stress((qx, b * qy), z, nu);
                            add(&mut mean, &scaled(&s, p / 2.0));
                        }
                    }
                    mean
                })
                .collect()
        } else {
            Vec::new()
        };
        // `G_c(kx, y)` for `kx <= kmax`, stored by row `y` (`hx` entries),
        // one buffer per component.
        let line_y = &self.line_y;
        let half_len = nx * (ny / 2 + 1);
        work.g.resize_with(count, Vec::new);
        work.g.par_iter_mut().enumerate().for_each_init(
            || {
                (
                    vec![Complex64::default(); half_len],
                    vec![Complex64::default(); ny],
                    vec![Complex64::default(); line_y.get_inplace_scratch_len()],
                )
            },
            |(half, col, scratch), (c, gc)| {
                for (m, &(a, t)) in self.regular.iter().zip(&pf) {
                    half[m.index] = a * unit_component(m.n, t, nu, c);
                }
                for (i, s) in y_nyquist.iter().enumerate() {
                    half[(ny / 2) * nx + i] = component(s, c);
                }
                gc.resize(ny * hx, Complex64::default());
                for kx in 0..=kmax {
                    for (j, v) in col.iter_mut().enumerate() {
                        *v = if 2 * j <= ny {
                            half[j * nx + kx]
                        } else {
                            half[(ny - j) * nx + (nx - kx) % nx].conj()
                        };
                    }
                    line_y.process_with_scratch(col, scratch);
                    for (y, v) in col.iter().enumerate() {
                        gc[y * hx + kx] = *v;
                    }
                }
            },
        );
        // Per multiplier: its values at `kx <= kmax`, the x-Nyquist column
        // of every component along y (Hermitian in `ky`: real), and the
        // Nyquist modes' parts.
        let per_rate: Vec<(Vec<Complex64>, Vec<f64>, NyquistParts)> = rates
            .par_iter()
            .map(|rate| {
                let r: Vec<Complex64> = (0..=kmax)
                    .map(|kx| {
                        let qx = tau2 * kx as f64 / self.length.0;
                        rate.at(-self.speed * (qx * self.e.0))
                    })
                    .collect();
                let nyquist = self.nyquist_parts(rate, z);
                let mut columns = Vec::new();
                if nx % 2 == 0 {
                    let mut col = vec![Complex64::default(); ny];
                    let mut scratch = vec![Complex64::default(); line_y.get_inplace_scratch_len()];
                    for c in 0..count {
                        for (j, v) in col.iter_mut().enumerate() {
                            *v = if 2 * j <= ny {
                                component(&nyquist.row[j].mean, c)
                            } else {
                                component(&nyquist.row[ny - j].mean, c).conj()
                            };
                        }
                        line_y.process_with_scratch(&mut col, &mut scratch);
                        columns.extend(col.iter().map(|v| v.re));
                    }
                }
                (r, columns, nyquist)
            })
            .collect();
        let (dev, trace) = (weight * (1.0 + nu), weight * (1.0 - 2.0 * nu) / 3.0);
        // Row by row: every multiplier's components transformed along x
        // and squared while the row is in cache.
        work.sum.resize(nx * ny, 0.0);
        let g = &work.g;
        let row_x = &self.row_x;
        work.sum.par_chunks_mut(nx).enumerate().try_for_each_init(
            || {
                (
                    vec![Complex64::default(); hx],
                    vec![0.0; nx],
                    vec![0.0; nx],
                    row_x.make_scratch_vec(),
                )
            },
            |(row, field, first, scratch), (y, sum)| {
                sum.fill(0.0);
                for (r, columns, _) in &per_rate {
                    for (c, gc) in g.iter().enumerate() {
                        let gy = &gc[y * hx..(y + 1) * hx];
                        for ((v, g), r) in row.iter_mut().zip(gy).zip(r) {
                            *v = g * r;
                        }
                        row[0].im = 0.0;
                        if nx % 2 == 0 {
                            row[hx - 1] = Complex64::new(columns[c * ny + y], 0.0);
                        }
                        row_x
                            .process_with_scratch(row, field, scratch)
                            .map_err(|e| {
                                HeatError::Transform(format!("inverse real FFT failed: {e}"))
                            })?;
                        accumulate(c, field, first, sum, dev, trace);
                    }
                }
                Ok::<(), HeatError>(())
            },
        )?;
        for (_, _, nyquist) in &per_rate {
            self.add_nyquist(nyquist, weight, out);
        }
        // `sum` is by row y; `out` by x.
        for (y, s) in work.sum.chunks(nx).enumerate() {
            for (x, v) in s.iter().enumerate() {
                out[x * ny + y] += v;
            }
        }
        Ok(())
    }
}
