//! Friction on a periodic cell from the dissipated power in Fourier space
//! (paper Appendix, Eq. A3-A4; physics.md section 6).
//!
//! For a periodic pressure field on `nx x ny` cells of side `a`, discrete
//! Parseval turns the friction stencil `F_T = a^2 sum_n p_n (D p)_n`
//! (paper Eq. 9 with the spectral slope operator of
//! [`crate::operator::SpectralPeriodic::sliding_slope`]) into the mode sum
//!
//! `F_T = (a^2 / N) sum_q |P(q)|^2 Re[i q_v m(q)]
//!      = (a^2 / N) sum_q |P(q)|^2 (-q_v) 2 (1 - nu^2) Im J*(-q.v) / |q|`,
//!
//! with `P(q) = sum_n p_n exp(-i q.x_n)` the discrete transform, `N = nx ny`,
//! `q_v = q.e_v` and `m(q)` the periodic multiplier (Nyquist modes averaged
//! over their signs, as in the operator). This is Eq. A4 with the integral
//! over `q` replaced by the sum over the periodic cell's modes. The `q = 0`
//! mode and the elastic (`1/E_inf`) part contribute nothing. `F_T < 0`
//! opposes sliding; `mu = -F_T / F_N`.

use num_complex::Complex64;
use rayon::prelude::*;
use realfft::RealFftPlanner;
use rustfft::FftPlanner;

use crate::material::Material;
use crate::operator::{periodic_multiplier, PeriodicResponse};

/// `F_T` \[N\] of a periodic pressure field (C order, axis 0 = x) from the
/// Fourier dissipation sum (Appendix Eq. A3-A4).
pub fn friction_force_periodic(
    pressure: &[f64],
    nx: usize,
    ny: usize,
    a: f64,
    material: &Material,
    speed: f64,
    direction_rad: f64,
) -> f64 {
    assert_eq!(pressure.len(), nx * ny, "pressure must hold nx * ny cells");
    if speed == 0.0 || !speed.is_finite() {
        return 0.0;
    }
    let nyh = ny / 2 + 1;
    let r2c = RealFftPlanner::<f64>::new().plan_fft_forward(ny);
    let mut spec = vec![Complex64::default(); nx * nyh];
    spec.par_chunks_mut(nyh).enumerate().for_each_init(
        || (vec![0.0; ny], r2c.make_scratch_vec()),
        |(row, scratch), (i, s)| {
            row.copy_from_slice(&pressure[i * ny..(i + 1) * ny]);
            r2c.process_with_scratch(row, s, scratch)
                .expect("sizes match the plan");
        },
    );
    let fft = FftPlanner::<f64>::new().plan_fft_forward(nx);
    let total: f64 = (0..nyh)
        .into_par_iter()
        .map_init(
            || vec![Complex64::default(); nx],
            |col, j| {
                for (i, c) in col.iter_mut().enumerate() {
                    *c = spec[i * nyh + j];
                }
                fft.process(col);
                // Columns other than DC and Nyquist stand for their Hermitian
                // partners too.
                let weight = if j == 0 || (ny % 2 == 0 && j == nyh - 1) {
                    1.0
                } else {
                    2.0
                };
                let acc: f64 = col
                    .iter()
                    .enumerate()
                    .map(|(i, c)| {
                        let d = periodic_multiplier(
                            material,
                            speed,
                            direction_rad,
                            nx,
                            ny,
                            a,
                            i,
                            j,
                            PeriodicResponse::SlidingSlope,
                        );
                        c.norm_sqr() * d.re
                    })
                    .sum();
                weight * acc
            },
        )
        .sum();
    total * a * a / (nx * ny) as f64
}

/// Friction force per unit area \[Pa\] of a periodic surface held in full
/// contact, as the exact linear response summed mode by mode: each height
/// mode `h cos(k.x + phi)` contributes
/// `-|k| (k.e_v) h^2 E2(k.v) / (4 (1 - nu^2))` (physics.md section 9, check
/// 2, with `E2(-w) = -E2(w)`). `modes` holds `(kx, ky, h)` with `k` in rad/m;
/// the modes must have distinct wavevectors not related by `k -> -k`.
pub fn full_contact_friction_stress(
    modes: &[(f64, f64, f64)],
    material: &Material,
    speed: f64,
    direction_rad: f64,
) -> f64 {
    let (ex, ey) = (direction_rad.cos(), direction_rad.sin());
    modes
        .iter()
        .map(|&(kx, ky, h)| {
            let kv = kx * ex + ky * ey;
            let e2 = material.spectrum.modulus(kv * speed).im;
            -kx.hypot(ky) * kv * h * h * e2 / (4.0 * material.composite_factor())
        })
        .sum()
}
