//! The paper's Eq. 4-5 for a layer (non-periodic, `Theta` on the sliding
//! Green's function) against the exact periodic layer, for a full-contact
//! sinusoid of wavelength `lambda = 16 a` (docs/layers.md).
//!
//! Eq. 4 takes `Theta` at the displaced point `|x + v tau z|`, so its
//! Fourier transform is `S(|q| h) 2 (1 - nu^2) J*(-q.v) / |q|`: the exact
//! layer for a frequency-independent Poisson ratio. The non-periodic table
//! of cell integrals responds to `cos(k x_i)` with the lattice sum
//! `sigma = sum_m m(k_m) sinc(k_m a / 2)` (tests/grid/periodic_layer.rs checks
//! the table against it to 1e-13), the periodic operator with `m(k)`. In
//! full contact under `g = h0 cos(k x)` the pressure amplitude is
//! `h0 / |sigma|` and the friction is proportional to `Im sigma / |sigma|^2`;
//! this prints both ratios (Eq. 5 discrete over exact periodic) for layers of
//! 0.1 to 10 wavelengths and speeds across the loss peak, next to the same
//! ratios for the half-space (the discretisation alone).
//!
//! `cargo run --release --example layer_eq5_vs_periodic`

use num_complex::Complex64;
use viscoslide::material::{CreepSpectrum, Material};
use viscoslide::response::layer::compliance_ratio;
use viscoslide::response::LayerBase;

fn main() {
    let m = Material::new(
        CreepSpectrum::standard_linear_solid(1e7 / 3.0, 1e7, 0.01).expect("valid"),
        0.5,
    )
    .expect("valid");
    let a = 1e-4;
    let lambda = 16.0 * a;
    let k = std::f64::consts::TAU / lambda;
    let tau = m.spectrum.terms[0].time;
    // Loss peak of E2 for the standard linear solid: omega tau = E_inf / E0.
    let v_peak = m.spectrum.glassy_modulus / m.spectrum.relaxed_modulus() / tau / k;
    let mult = |q: f64, v: f64, layer: Option<(LayerBase, f64)>| -> Complex64 {
        let s = layer.map_or(1.0, |(b, h)| compliance_ratio(b, m.poisson, q.abs() * h));
        m.spectrum.compliance(-q * v) * (2.0 * m.composite_factor() * s / q.abs())
    };
    let sigma = |v: f64, layer: Option<(LayerBase, f64)>| -> Complex64 {
        let mut s = Complex64::default();
        for j in -20000i64..=20000 {
            let q = k + std::f64::consts::TAU * j as f64 / a;
            let t = 0.5 * q * a;
            s += mult(q, v, layer) * (t.sin() / t);
        }
        s
    };
    let ratios = |v: f64, layer: Option<(LayerBase, f64)>| -> (f64, f64) {
        let (s, e) = (sigma(v, layer), mult(k, v, layer));
        let pressure = e.norm() / s.norm() - 1.0;
        let friction = if v > 0.0 {
            (s.im / s.norm_sqr()) / (e.im / e.norm_sqr()) - 1.0
        } else {
            0.0
        };
        (pressure, friction)
    };
    println!(
        "lambda = 16 cells, k lambda = 2 pi; v_peak = {v_peak:.4e} m/s (omega tau = E_inf/E0 at k)"
    );
    println!();
    println!("| base | h / lambda | S(k h) | v / v_peak | pressure: layer (half-space) | friction: layer (half-space) |");
    println!("|---|---|---|---|---|---|");
    for base in [LayerBase::Bonded, LayerBase::Frictionless] {
        for hl in [0.1, 0.3, 1.0, 3.0, 10.0] {
            let h = hl * lambda;
            let s = compliance_ratio(base, m.poisson, k * h);
            for vr in [0.0, 0.1, 1.0, 10.0] {
                let v = vr * v_peak;
                let (pl, fl) = ratios(v, Some((base, h)));
                let (ph, fh) = ratios(v, None);
                let fric = if v > 0.0 {
                    format!("{fl:+.2e} ({fh:+.2e})")
                } else {
                    "0 (0)".into()
                };
                println!("| {base:?} | {hl} | {s:.3e} | {vr} | {pl:+.2e} ({ph:+.2e}) | {fric} |");
            }
        }
    }
}
