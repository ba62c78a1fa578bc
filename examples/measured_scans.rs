//! A small measured-like data set: two scans of one rough surface at two
//! magnifications, written as ISO 25178-72 `.x3p` files, as a profilometer
//! and a microscope would give them (see README, "Measured surfaces").
//!
//! The "true" surface is a 1 cm periodic self-affine surface (H = 0.8, flat
//! below q0 = 5e3 1/m) synthesised from a PSD table. The scans are
//! non-periodic crops with a tilt, a little noise, and (high
//! magnification) a few invalid points:
//!
//! - `scan_low.x3p`: 256 x 256 points, 19.5 um pixels (5 mm), int32 heights
//!   in nm-scale steps, like a stylus profilometer;
//! - `scan_high.x3p`: 256 x 256 points, 4.9 um pixels (1.25 mm), float32,
//!   with 0.3 % of the points invalid, like an optical microscope.
//!
//! Also writes `true_psd.csv`, the PSD the surface was made from.
//!
//! `cargo run --release --example measured_scans -- OUT_DIR`

use std::f64::consts::PI;
use std::path::PathBuf;

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use viscoslide::surface::{
    encode_x3p, generate_from_table, HeightMap, SynthParams, TabulatedPsd, Topography, X3pType,
};

fn crop(
    map: &HeightMap,
    i0: usize,
    j0: usize,
    n: usize,
    tilt: (f64, f64),
    noise: f64,
    seed: u64,
) -> Topography {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let a = map.cell_size;
    let mut h = vec![0.0; n * n];
    for i in 0..n {
        for j in 0..n {
            let e: f64 = rng.random::<f64>() - 0.5;
            h[i * n + j] =
                map.at(i0 + i, j0 + j) + tilt.0 * i as f64 * a + tilt.1 * j as f64 * a + noise * e;
        }
    }
    Topography::new(n, n, a, a, h, "scan").expect("valid scan")
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let out = PathBuf::from(
        std::env::args()
            .nth(1)
            .unwrap_or_else(|| "out/measured".into()),
    );
    std::fs::create_dir_all(&out)?;
    let length = 0.01;
    // Self-affine PSD, H = 0.8, flat below q0; scaled to an rms slope of
    // 0.02 over the band a 256-cell solve of the 1 cm surface resolves.
    let (q0, q_top) = (5.0e3, 2.0e6);
    let shape = |q: f64| if q < q0 { 1.0 } else { (q / q0).powf(-3.6) };
    let qs: Vec<f64> = vec![2.0 * PI / length, q0, q_top];
    let unit = TabulatedPsd::new(qs.clone(), qs.iter().map(|&q| shape(q)).collect(), "psd")?;
    let q_solve = PI * 256.0 / length;
    let solve_band = TabulatedPsd::new(
        vec![2.0 * PI / length, q0, q_solve],
        vec![1.0, 1.0, shape(q_solve)],
        "band",
    )?;
    let c0 = 0.02f64.powi(2) / solve_band.moment(2);
    let truth = TabulatedPsd::new(qs.clone(), unit.c().iter().map(|c| c * c0).collect(), "psd")?;
    std::fs::write(out.join("true_psd.csv"), truth.to_csv())?;

    // Low magnification: the true surface on a 512 grid (19.5 um), cropped.
    let seed = 2014;
    let coarse = generate_from_table(
        &truth,
        &SynthParams {
            nx: 512,
            ny: 512,
            length,
            seed,
            q1: None,
            below: Default::default(),
        },
    )?;
    let low = crop(&coarse, 100, 180, 256, (2e-3, -1e-3), 5e-8, 1);
    std::fs::write(
        out.join("scan_low.x3p"),
        encode_x3p(&low, X3pType::I32, Some("synthetic low-magnification scan"))?,
    )?;

    // High magnification: the same surface on a 2048 grid (4.9 um), cropped
    // inside the low-magnification field, with invalid points.
    let fine = generate_from_table(
        &truth,
        &SynthParams {
            nx: 2048,
            ny: 2048,
            length,
            seed,
            q1: None,
            below: Default::default(),
        },
    )?;
    let mut high = crop(&fine, 700, 900, 256, (-1e-3, 3e-3), 1e-8, 2);
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let n = high.heights.len();
    for _ in 0..n * 3 / 1000 {
        let k = rng.random_range(0..n);
        high.heights[k] = f64::NAN;
    }
    std::fs::write(
        out.join("scan_high.x3p"),
        encode_x3p(
            &high,
            X3pType::F32,
            Some("synthetic high-magnification scan"),
        )?,
    )?;
    println!(
        "wrote {}: scan_low.x3p (256 x 256, {:.2e} m pixels), scan_high.x3p (256 x 256, {:.2e} m pixels, {} invalid points), true_psd.csv",
        out.display(),
        low.dx,
        high.dx,
        high.missing()
    );
    Ok(())
}
