//! Wall time of the coefficient tables `K` and `D_x` of an `n x n` grid
//! with a layer `h` cells thick (paper Eq. 5), for BENCHMARKS.md.
//!
//! `cargo run --release --example layer_table_timing -- N H_CELLS SPEED [bonded|frictionless]`
//! (the paper's single-relaxation material, nu = 0.5, cell 0.3125 mm).

use std::time::Instant;
use viscoslide::response::{Grid, Layer, LayerBase, SlidingResponse};

use viscoslide::internals::kernel::{Axis, SlidingKernel};
use viscoslide::material::{CreepSpectrum, Material};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let n: usize = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(256);
    let h_cells: f64 = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(2.0);
    let speed: f64 = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(1e-3);
    let base = match args.get(4).map(String::as_str) {
        Some("frictionless") => LayerBase::Frictionless,
        _ => LayerBase::Bonded,
    };
    let a = 3.125e-4;
    let m = Material::new(
        CreepSpectrum::standard_linear_solid(1e7 / 3.0, 1e7, 0.01).expect("valid material"),
        0.5,
    )
    .expect("valid material");
    let layer = (h_cells > 0.0).then_some(Layer {
        thickness: h_cells * a,
        base,
    });
    let k = SlidingKernel::new(&SlidingResponse::new(&m, speed, 0.0, layer).unwrap())
        .expect("valid kernel");
    let t = Instant::now();
    let table = k.table(&Grid::square(n, n, a).unwrap()).unwrap();
    let tk = t.elapsed().as_secs_f64();
    let t = Instant::now();
    let d = k
        .derivative_table(&Grid::square(n, n, a).unwrap(), Axis::X)
        .unwrap();
    let td = t.elapsed().as_secs_f64();
    println!(
        "n = {n}, h = {h_cells} cells ({base:?}), v = {speed} m/s: K table {tk:.3} s, D_x table {td:.3} s, K(0,0) = {:.10e}, D(1,0) = {:.10e}",
        table.get(0, 0),
        d.get(1, 0)
    );
}
