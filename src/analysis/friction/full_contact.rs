//! The exact friction of a periodic surface held in full contact, mode by
//! mode (physics.md section 9, check 2): the reference the periodic
//! routes of [`super::stencil`] and [`super::dissipation`] are checked
//! against.

use crate::material::Material;

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
