//! Inputs shared by the solver benchmarks: the paper's single-relaxation
//! material, the grid sizes (shrunk when `CI` is set) and a self-affine gap
//! profile with a few percent contact at 3 kPa. Each bench uses a subset.
#![allow(dead_code)]

use viscoslide::material::{CreepSpectrum, Material};
use viscoslide::surface::{self, GenerateParams, Normalisation, UpperCutoff};

/// E_inf = 1e7 Pa, E_inf/E0 = 3, creep time 0.01 s, nu = 0.5.
pub fn material() -> Material {
    Material::new(
        CreepSpectrum::standard_linear_solid(1e7 / 3.0, 1e7, 0.01).unwrap(),
        0.5,
    )
    .unwrap()
}

/// 256^2 and 512^2; 64^2 under `CI`.
pub fn sizes() -> Vec<usize> {
    if std::env::var_os("CI").is_some() {
        vec![64]
    } else {
        vec![256, 512]
    }
}

/// Gap profile `max(z) - z` of an `n x n`, 1 cm, H = 0.8 surface with n/8
/// scales and rms slope 0.02 (seed 1).
pub fn surface_gap(n: usize) -> Vec<f64> {
    let params = GenerateParams {
        nx: n,
        ny: n,
        length: 0.01,
        hurst: 0.8,
        upper: UpperCutoff::Scales((n / 8) as f64),
        normalisation: Normalisation::RmsSlope(0.02),
        seed: 1,
        ..Default::default()
    };
    let h = surface::generate(&params).unwrap();
    let zmax = h.heights.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
    h.heights.iter().map(|z| zmax - z).collect()
}
