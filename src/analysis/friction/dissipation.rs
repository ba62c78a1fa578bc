//! The dissipation route (paper Appendix, Eq. A3-A4; physics.md section 6):
//! the friction integral in Fourier space, for both formulations.
//!
//! Non-periodic grid ([`friction_force_dissipation`]):
//! `F_T = (2 pi)^-2 int d^2q |p^(q)|^2 Re[i q_v G^(q)]` with
//! `G^(q) = 2 (1 - nu^2) J*(-q.v) / |q|`, where `p^(q) = S(q) P(q)`: `P` is
//! the discrete transform of the cell pressures and `S` the transform of
//! one cell (a product of sincs). The integral over the plane folds onto
//! one Brillouin zone, sampled on the zero-padded FFT grid, with the alias
//! images summed explicitly.
//!
//! Periodic cell ([`friction_force_periodic`]): for a periodic pressure
//! field on `nx x ny` cells of side `a`, discrete Parseval turns the
//! friction stencil `F_T = a^2 sum_n p_n (D p)_n` (paper Eq. 9 with the
//! spectral slope operator of
//! [`crate::operator::SpectralPeriodic`] with [`crate::operator::PeriodicResponse::SlidingSlope`]) into the mode sum
//!
//! `F_T = (a^2 / N) sum_q |P(q)|^2 Re[i q_v m(q)]
//!      = (a^2 / N) sum_q |P(q)|^2 (-q_v) 2 (1 - nu^2) S(|q| h) Im J*(-q.v) / |q|`,
//!
//! with `P(q) = sum_n p_n exp(-i q.x_n)` the discrete transform, `N = nx ny`,
//! `q_v = q.e_v` and `m(q)` the periodic multiplier (Nyquist modes averaged
//! over their signs, as in the operator). This is Eq. A4 with the integral
//! over `q` replaced by the sum over the periodic cell's modes (`S = 1` on a
//! half-space). The multiplier is the operator's own
//! ([`crate::operator::SpectralPeriodic`]). The `q = 0`
//! mode and the elastic (`1/E_inf`) part contribute nothing.

use num_complex::Complex64;
use rayon::prelude::*;
use realfft::RealFftPlanner;
use rustfft::FftPlanner;

use crate::operator::{column_weight, half_spectrum, multiplier_half_spectrum, PeriodicResponse};
use crate::response::{Grid, SlidingResponse};

/// Alias images summed on each side in each direction.
const ALIASES: i32 = 3;

/// Zero-padding factor of the Fourier quadrature.
const PAD: usize = 4;

/// `F_T` \[N\] from the dissipated power in Fourier space (Appendix A3-A4)
/// of the cell pressures on `grid` (C order, axis 0 = x). On a layer the
/// half-space transfer function is multiplied by the layer's compliance
/// ratio `S(|q| h)`: the Fourier transform of the paper's Eq. 4-5 (`Theta`
/// at the displaced point along the trail), whose cell integrals the
/// coefficients of [`crate::kernel`] are, so the two routes evaluate the
/// same integral (up to this quadrature's zone sampling and alias
/// truncation). On cells of sides `(a_x, a_y)` (physics.md section 11) the
/// zone is `2 pi / a_x x 2 pi / a_y` and `S` the product of the sincs of
/// each side.
pub fn friction_force_dissipation(
    pressure: &[f64],
    grid: &Grid,
    response: &SlidingResponse,
) -> f64 {
    zone_sum(pressure, grid, response, true, false)
}

/// The dissipation route for a layer on the thin-layer law of
/// [`crate::kernel::SlidingKernel::is_thin_law`] (a bonded incompressible
/// layer far below a cell, `kernel/thin_law.rs`): the pressure is taken as
/// band-limited, `|P(q)|^2` times the layer's continuous multiplier over
/// the zone without the cell's sincs and alias images, as the periodic
/// formulation does (Eq. A4). The cell-constant pressure's own image sum
/// would add the displacement spikes at its jumps (`|c2| a / (2 h)` times
/// the law's response), which the law's discretisation leaves out; the
/// routes then agree to the stencil's `O((q a)^2)`.
pub fn friction_force_dissipation_thin_law(
    pressure: &[f64],
    grid: &Grid,
    response: &SlidingResponse,
) -> f64 {
    zone_sum(pressure, grid, response, false, true)
}

/// The zone quadrature of [`friction_force_dissipation`]. With
/// `fast`, sliding along x on a half-space (the common case) takes the
/// fast path: the weight of a mode, a sum over its 49 alias images, is
/// computed once for `+-q_x` (it is even in `q_x`: `q_x Im J*(-q_x v)` is)
/// from per-row factors, with `sqrt` in place of `hypot`, in a loop the
/// compiler vectorises; otherwise, and always without `fast`, every image
/// is evaluated in full (the reference, equal to round-off).
fn zone_sum(
    pressure: &[f64],
    grid: &Grid,
    response: &SlidingResponse,
    fast: bool,
    band_limited: bool,
) -> f64 {
    let ((nx, ny), (ax, ay)) = (grid.size(), grid.cell());
    let speed = response.speed();
    if speed == 0.0 || !speed.is_finite() {
        return 0.0;
    }
    // Zero padding by PAD samples |P|^2 finely enough for the trapezoidal
    // rule over the zone: the integrand has a cusp at q = 0 (|q|^-1 q_v^2)
    // where the error falls like the cube of the spacing (measured on a
    // sliding sphere: 3.4 % with padding 2, 0.3 % with 4, 0.03 % with 8).
    let mx = crate::operator::fast_size(PAD * nx);
    let my = crate::operator::fast_size(PAD * ny);
    let myh = my / 2 + 1;
    let mut rp = RealFftPlanner::<f64>::new();
    let r2c = rp.plan_fft_forward(my);
    // Row transforms of the nx non-zero rows only (O(N) memory).
    let mut spec = vec![Complex64::default(); nx * myh];
    spec.par_chunks_mut(myh).enumerate().for_each_init(
        || (vec![0.0; my], r2c.make_scratch_vec()),
        |(row, scratch), (i, s)| {
            row.fill(0.0);
            row[..ny].copy_from_slice(&pressure[i * ny..(i + 1) * ny]);
            r2c.process_with_scratch(row, s, scratch)
                .expect("sizes match the plan");
        },
    );
    let fft = FftPlanner::<f64>::new().plan_fft_forward(mx);
    let (ex, ey) = response.direction();
    let layer = response.layer();
    let two_pi = 2.0 * std::f64::consts::PI;
    let (gx, gy) = (two_pi / ax, two_pi / ay);
    let composite = response.material().composite_factor();
    let sinc = |t: f64| {
        if t.abs() < 1e-8 {
            1.0 - t * t / 6.0
        } else {
            t.sin() / t
        }
    };
    let along_x = ey.abs() < 1e-15;
    let aliases = if band_limited { 0 } else { ALIASES };
    let na = 2 * aliases as usize + 1;
    let sinc = |t: f64| if band_limited { 1.0 } else { sinc(t) };
    // For sliding along x, Im J* depends on q_x only: cache it per (i, alias).
    let mut imj_cache = vec![0.0; if along_x { mx * na } else { 0 }];
    let qx_of = |i: usize| {
        let k = if i <= mx / 2 {
            i as f64
        } else {
            i as f64 - mx as f64
        };
        two_pi * k / (mx as f64 * ax)
    };
    let qy_of = |j: usize| two_pi * j as f64 / (my as f64 * ay);
    let mut qxs = vec![0.0; mx * na];
    let mut sx2s = vec![0.0; mx * na];
    for i in 0..mx {
        for (k, m) in (-aliases..=aliases).enumerate() {
            let qx = qx_of(i) + m as f64 * gx;
            let s = sinc(0.5 * qx * ax);
            qxs[i * na + k] = qx;
            sx2s[i * na + k] = s * s;
            if along_x {
                imj_cache[i * na + k] = response.compliance_along(qx * ex).im;
            }
        }
    }
    let fast = fast && along_x && layer.is_none();
    // Fast path: the x factor of each image, sinc^2 (-q_x) 2 (1 - nu^2) Im J*.
    let xfactor: Vec<f64> = if fast {
        (0..mx * na)
            .map(|k| sx2s[k] * (-qxs[k] * ex * 2.0 * composite * imj_cache[k]))
            .collect()
    } else {
        Vec::new()
    };
    let total: f64 = (0..myh)
        .into_par_iter()
        .map_init(
            || (vec![Complex64::default(); mx], vec![0.0; mx / 2 + 1]),
            |(col, wcol), j| {
                for (i, c) in col.iter_mut().enumerate() {
                    *c = if i < nx {
                        spec[i * myh + j]
                    } else {
                        Complex64::default()
                    };
                }
                fft.process(col);
                let weight = column_weight(j, my);
                let qy0 = qy_of(j);
                let mut qys = vec![0.0; na];
                let mut sy2 = vec![0.0; na];
                for (k, m) in (-aliases..=aliases).enumerate() {
                    qys[k] = qy0 + m as f64 * gy;
                    let s = sinc(0.5 * qys[k] * ay);
                    sy2[k] = s * s;
                }
                if fast {
                    // w(i) = sum_mi X(i, mi) sum_k sy2_k / |q|, for
                    // i <= mx / 2; row mx - i (q_x -> -q_x) has the same.
                    for (i, w) in wcol.iter_mut().enumerate() {
                        let mut sum = 0.0;
                        for mi in 0..na {
                            let qx = qxs[i * na + mi];
                            let mut inner = 0.0;
                            for k in 0..na {
                                let q2 = qx * qx + qys[k] * qys[k];
                                inner += if q2 > 0.0 { sy2[k] / q2.sqrt() } else { 0.0 };
                            }
                            sum += xfactor[i * na + mi] * inner;
                        }
                        *w = sum;
                    }
                    let acc: f64 = col
                        .iter()
                        .enumerate()
                        .map(|(i, c)| c.norm_sqr() * wcol[i.min(mx - i)])
                        .sum();
                    return weight * acc;
                }
                let mut acc = 0.0;
                for (i, c) in col.iter().enumerate() {
                    let p2 = c.norm_sqr();
                    if p2 == 0.0 {
                        continue;
                    }
                    let mut w = 0.0;
                    for mi in 0..na {
                        let qx = qxs[i * na + mi];
                        let sx2 = sx2s[i * na + mi];
                        for k in 0..na {
                            let qy = qys[k];
                            let q = qx.hypot(qy);
                            if q == 0.0 {
                                continue;
                            }
                            let qv = qx * ex + qy * ey;
                            let imj = if along_x {
                                imj_cache[i * na + mi]
                            } else {
                                response.compliance_along(qv).im
                            };
                            // Re[i q_v G^] = -q_v Im G^ = -q_v 2 (1-nu^2) S Im J* / |q|
                            let ratio = response.layer_ratio(q);
                            w += sx2 * sy2[k] * ratio * (-qv * 2.0 * composite * imj / q);
                        }
                    }
                    acc += p2 * w;
                }
                weight * acc
            },
        )
        .sum();
    // P(q) = ax ay sum p e^{-iqx}: |P|^2 = (ax ay)^2 |FFT|^2; the zone
    // integral is sum dq^2 / (2 pi)^2 with dq^2 = (2 pi)^2 / (mx my ax ay).
    total * ax * ay / (mx as f64 * my as f64)
}

/// `F_T` \[N\] of a periodic pressure field on `grid` (C order, axis 0 =
/// x) from the Fourier dissipation sum (Appendix Eq. A3-A4): the mode sum
/// times the cell area `a_x a_y / N`. A layer's compliance ratio
/// `S(|q| h)` multiplies every mode, exactly as in
/// [`crate::operator::SpectralPeriodic`].
pub fn friction_force_periodic(pressure: &[f64], grid: &Grid, response: &SlidingResponse) -> f64 {
    let ((nx, ny), cell) = (grid.size(), grid.cell());
    assert_eq!(pressure.len(), nx * ny, "pressure must hold nx * ny cells");
    if response.speed() == 0.0 || !response.speed().is_finite() {
        return 0.0;
    }
    // |P|^2 and column_weight * Re[i q_v m(q)] on the half spectrum, both
    // column-major (`ny / 2 + 1` columns of `nx` modes).
    let power: Vec<f64> = half_spectrum(pressure, nx, ny)
        .iter()
        .map(|c| c.norm_sqr())
        .collect();
    let slope = multiplier_half_spectrum(response, grid, PeriodicResponse::SlidingSlope);
    let weights: Vec<f64> = slope
        .chunks_exact(nx)
        .enumerate()
        .flat_map(|(j, col)| col.iter().map(move |v| column_weight(j, ny) * v.re))
        .collect();
    let total: f64 = power.iter().zip(&weights).map(|(p, w)| p * w).sum();
    total * cell.0 * cell.1 / (nx * ny) as f64
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::{CreepSpectrum, Material};

    #[test]
    fn fast_path_equals_the_image_by_image_sum() {
        // An irregular pressure patch on a rectangular grid, SLS material
        // at the friction peak: the fast path (sliding along x, half-space)
        // against the full evaluation of every alias image.
        let spectrum = CreepSpectrum::standard_linear_solid(1e7 / 3.0, 1e7, 0.01).unwrap();
        let material = Material::new(spectrum, 0.5).unwrap();
        let (nx, ny, a) = (21, 13, 1e-5);
        let p: Vec<f64> = (0..nx * ny)
            .map(|k| {
                let (i, j) = ((k / ny) as f64, (k % ny) as f64);
                (1e5 * ((0.7 * i).sin() + (0.45 * j + 0.2 * i).cos() + 0.8)).max(0.0)
            })
            .collect();
        for speed in [1e-4, 3e-3, 0.1] {
            let response = SlidingResponse::new(&material, speed, 0.0, None).unwrap();
            let grid = Grid::square(nx, ny, a).unwrap();
            let run = |fast| zone_sum(&p, &grid, &response, fast, false);
            let (fast, slow) = (run(true), run(false));
            // The same terms summed in another order, sqrt for hypot:
            // round-off of a sum of ~1e5 terms of one sign per mode.
            assert!(
                slow != 0.0 && (fast / slow - 1.0).abs() < 1e-11,
                "{fast} {slow}"
            );
        }
    }
}
