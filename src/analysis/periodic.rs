//! Friction on a periodic cell from the dissipated power in Fourier space
//! (paper Appendix, Eq. A3-A4; physics.md section 6).
//!
//! For a periodic pressure field on `nx x ny` cells of side `a`, discrete
//! Parseval turns the friction stencil `F_T = a^2 sum_n p_n (D p)_n`
//! (paper Eq. 9 with the spectral slope operator of
//! [`crate::operator::SpectralPeriodic::sliding_slope`]) into the mode sum
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
//! mode and the elastic (`1/E_inf`) part contribute nothing. `F_T < 0`
//! opposes sliding; `mu = -F_T / F_N`.

use crate::kernel::KernelParams;
use crate::material::Material;
use crate::operator::{periodic_friction_weights, PeriodicResponse};

/// `F_T` \[N\] of a periodic pressure field (C order, axis 0 = x) from the
/// Fourier dissipation sum (Appendix Eq. A3-A4), on a half-space.
pub fn friction_force_periodic(
    pressure: &[f64],
    nx: usize,
    ny: usize,
    a: f64,
    material: &Material,
    speed: f64,
    direction_rad: f64,
) -> f64 {
    let params = KernelParams {
        speed,
        direction_rad,
        layer: None,
    };
    friction_force_periodic_with(pressure, nx, ny, a, material, &params)
}

/// [`friction_force_periodic`] for `params`: speed, direction and an
/// optional layer (its compliance ratio `S(|q| h)` multiplies every mode,
/// exactly as in [`crate::operator::SpectralPeriodic::with_params`]).
pub fn friction_force_periodic_with(
    pressure: &[f64],
    nx: usize,
    ny: usize,
    a: f64,
    material: &Material,
    params: &KernelParams,
) -> f64 {
    assert_eq!(pressure.len(), nx * ny, "pressure must hold nx * ny cells");
    if params.speed == 0.0 || !params.speed.is_finite() {
        return 0.0;
    }
    let (power, weights) = periodic_friction_weights(
        pressure,
        nx,
        ny,
        a,
        material,
        params,
        PeriodicResponse::SlidingSlope,
    );
    let total: f64 = power.iter().zip(&weights).map(|(p, w)| p * w).sum();
    total * a * a / (nx * ny) as f64
}

/// Friction force per unit area \[Pa\] of a periodic surface held in full
/// contact, as the exact linear response summed mode by mode: each height
/// mode `h cos(k.x + phi)` contributes
/// `-|k| (k.e_v) h^2 E2(k.v) / (4 (1 - nu^2))` (physics.md section 9, check
/// 2, with `E2(-w) = -E2(w)`); on a layer, divided by `S(|k| h)`
/// ([`full_contact_friction_stress_layered`]). `modes` holds `(kx, ky, h)` with `k` in rad/m;
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

/// [`full_contact_friction_stress`] on a layer: the pressure amplitude of
/// each mode is `1 / S(|k| h)` times the half-space's and the dissipation
/// carries one `S`, so each mode's stress is divided by `S(|k| h)`.
pub fn full_contact_friction_stress_layered(
    modes: &[(f64, f64, f64)],
    material: &Material,
    speed: f64,
    direction_rad: f64,
    layer: Option<&crate::kernel::Layer>,
) -> f64 {
    modes
        .iter()
        .map(|&(kx, ky, h)| {
            let s = layer.map_or(1.0, |l| {
                crate::kernel::thickness::compliance_ratio(
                    l.base,
                    material.poisson,
                    kx.hypot(ky) * l.thickness,
                )
            });
            full_contact_friction_stress(&[(kx, ky, h)], material, speed, direction_rad) / s
        })
        .sum()
}
