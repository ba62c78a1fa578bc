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

use super::super::stress::{mode_stress, unit_component, ModeStress};
use super::{accumulate, add, component, scaled, Dissipation, RateFn};
use crate::heat::error::HeatError;

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
        // `G_c(kx, y)` for `kx <= kmax`, stored by row `y` (`hx` entries).
        let mut half = vec![Complex64::default(); nx * (ny / 2 + 1)];
        let mut col = vec![Complex64::default(); ny];
        let mut scratch_y = vec![Complex64::default(); self.line_y.get_inplace_scratch_len()];
        let mut g: Vec<Vec<Complex64>> = Vec::with_capacity(count);
        for c in 0..count {
            for (m, &(a, t)) in self.regular.iter().zip(&pf) {
                half[m.index] = a * unit_component(m.n, t, nu, c);
            }
            for (i, s) in y_nyquist.iter().enumerate() {
                half[(ny / 2) * nx + i] = component(s, c);
            }
            let mut gc = vec![Complex64::default(); ny * hx];
            for kx in 0..=kmax {
                for (j, v) in col.iter_mut().enumerate() {
                    *v = if 2 * j <= ny {
                        half[j * nx + kx]
                    } else {
                        half[(ny - j) * nx + (nx - kx) % nx].conj()
                    };
                }
                self.line_y.process_with_scratch(&mut col, &mut scratch_y);
                for (y, v) in col.iter().enumerate() {
                    gc[y * hx + kx] = *v;
                }
            }
            g.push(gc);
        }
        let (dev, trace) = (weight * (1.0 + nu), weight * (1.0 - 2.0 * nu) / 3.0);
        let mut sum = vec![0.0; nx * ny];
        let mut field = vec![0.0; nx * ny];
        let mut first = vec![0.0; nx * ny];
        let mut row = vec![Complex64::default(); hx];
        let mut scratch_x = self.row_x.make_scratch_vec();
        let mut nyq = vec![0.0; ny];
        for rate in rates {
            let r: Vec<Complex64> = (0..=kmax)
                .map(|kx| {
                    let qx = tau2 * kx as f64 / self.length.0;
                    rate.at(-self.speed * (qx * self.e.0))
                })
                .collect();
            let nyquist = self.nyquist_parts(rate, z);
            for (c, gc) in g.iter().enumerate() {
                // The x-Nyquist column along y (Hermitian in `ky`: real).
                if nx % 2 == 0 {
                    for (j, v) in col.iter_mut().enumerate() {
                        *v = if 2 * j <= ny {
                            component(&nyquist.row[j].mean, c)
                        } else {
                            component(&nyquist.row[ny - j].mean, c).conj()
                        };
                    }
                    self.line_y.process_with_scratch(&mut col, &mut scratch_y);
                    nyq.iter_mut().zip(&col).for_each(|(o, v)| *o = v.re);
                }
                for ((gy, o), &ny_y) in gc.chunks(hx).zip(field.chunks_mut(nx)).zip(&nyq) {
                    for ((v, g), r) in row.iter_mut().zip(gy).zip(&r) {
                        *v = g * r;
                    }
                    row[0].im = 0.0;
                    if nx % 2 == 0 {
                        row[hx - 1] = Complex64::new(ny_y, 0.0);
                    }
                    self.row_x
                        .process_with_scratch(&mut row, o, &mut scratch_x)
                        .map_err(|e| {
                            HeatError::Transform(format!("inverse real FFT failed: {e}"))
                        })?;
                }
                accumulate(c, &field, &mut first, &mut sum, dev, trace);
            }
            self.add_nyquist(&nyquist, weight, out);
        }
        // `sum` is by row y; `out` by x.
        for (y, s) in sum.chunks(nx).enumerate() {
            for (x, v) in s.iter().enumerate() {
                out[x * ny + y] += v;
            }
        }
        Ok(())
    }
}
