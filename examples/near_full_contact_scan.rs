//! A measured-like scan for the near-full-contact benchmark (BENCHMARKS.md,
//! "Near-full contact"): a non-periodic self-affine map of 768 x 576 square
//! pixels of 1.667 um (1.28 x 0.96 mm), as a confocal microscope gives it.
//!
//! The map is a window cut from a larger periodic self-affine surface
//! (1536 x 1536 cells of the same size, H = 0.8, self-affine from the
//! longest wave of the large surface down to 6 pixels), so its edges are
//! not periodic; the least-squares plane of the window is removed and the
//! heights are scaled to the rms height `RMS` (m, default 3.3e-7). With the
//! material of `configs/default.toml` at a nominal pressure of 0.1 MPa
//! (`configs/near_full_contact.toml`) about 97 % of the scan is in contact.
//!
//! `cargo run --release --example near_full_contact_scan -- [OUT.npy] [RMS]`
//! (default `out/near_full_contact/scan.npy`).

use std::path::PathBuf;

use viscoslide::surface::{
    detrend, generate, save_npy, Detrend, GenerateParams, HeightMap, Normalisation, NpyPrecision,
    Topography, UpperCutoff,
};

/// Pixel size \[m\].
const PIXEL: f64 = 1.28e-3 / 768.0;
/// Scan shape (x, y).
const SCAN: (usize, usize) = (768, 576);
/// Side of the periodic surface the scan is cut from, in pixels.
const LARGE: usize = 1536;
/// First pixel of the window in the large surface (x, y).
const OFFSET: (usize, usize) = (301, 517);

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let out = PathBuf::from(
        args.next()
            .unwrap_or_else(|| "out/near_full_contact/scan.npy".into()),
    );
    let rms: f64 = match args.next() {
        Some(s) => s.parse().map_err(|e| format!("RMS {s:?}: {e}"))?,
        None => 3.3e-7,
    };
    if !(rms.is_finite() && rms > 0.0) {
        return Err(format!("RMS must be a positive height in m, got {rms}").into());
    }
    let large = generate(&GenerateParams {
        nx: LARGE,
        ny: LARGE,
        length: LARGE as f64 * PIXEL,
        hurst: 0.8,
        upper: UpperCutoff::Scales(LARGE as f64 / 6.0),
        ql: None,
        rolloff_q0: None,
        normalisation: Normalisation::RmsHeight(1.0),
        seed: 26,
        anisotropy: None,
    })?;
    let (nx, ny) = SCAN;
    let mut h = Vec::with_capacity(nx * ny);
    for i in 0..nx {
        for j in 0..ny {
            h.push(large.at(OFFSET.0 + i, OFFSET.1 + j));
        }
    }
    let window = Topography::new(nx, ny, PIXEL, PIXEL, h, "window")?;
    let mut heights = detrend(&window, Detrend::Plane).heights;
    let now = (heights.iter().map(|v| v * v).sum::<f64>() / heights.len() as f64).sqrt();
    for v in &mut heights {
        *v *= rms / now;
    }
    let map = HeightMap::new(nx, ny, nx as f64 * PIXEL, heights)?;
    if let Some(dir) = out.parent() {
        std::fs::create_dir_all(dir)?;
    }
    save_npy(&map, &out, NpyPrecision::F64)?;
    println!(
        "wrote {}: {nx} x {ny} pixels of {PIXEL:.4e} m ({:.3e} x {:.3e} m), plane removed, rms height {rms:.3e} m",
        out.display(),
        map.length_x(),
        map.length_y(),
    );
    Ok(())
}
