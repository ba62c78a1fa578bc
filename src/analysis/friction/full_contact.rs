//! The exact friction of a periodic surface held in full contact, mode by
//! mode (physics.md section 9, check 2): the reference the periodic
//! routes of [`super::stencil`] and [`super::dissipation`] are checked
//! against.

use crate::response::SlidingResponse;

/// Friction force per unit area \[Pa\] of a periodic surface held in full
/// contact, as the exact linear response summed mode by mode: each height
/// mode `h cos(k.x + phi)` contributes
/// `-|k| (k.e_v) h^2 E2(k.v) / (4 (1 - nu^2))` (physics.md section 9, check
/// 2, with `E2(-w) = -E2(w)`); on a layer, divided by `S(|k| h)` (the
/// pressure amplitude of each mode is `1 / S` times the half-space's and the
/// dissipation carries one `S`). `modes` holds `(kx, ky, h)` with `k` in
/// rad/m; the modes must have distinct wavevectors not related by
/// `k -> -k`.
pub fn full_contact_friction_stress(modes: &[(f64, f64, f64)], response: &SlidingResponse) -> f64 {
    let material = response.material();
    modes
        .iter()
        .map(|&(kx, ky, h)| {
            let kv = response.along((kx, ky));
            let e2 = material.spectrum.modulus(kv * response.speed()).im;
            let stress = -kx.hypot(ky) * kv * h * h * e2 / (4.0 * material.composite_factor());
            stress / response.layer_ratio(kx.hypot(ky))
        })
        .sum()
}
