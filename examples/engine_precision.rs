//! Wall time of one product of the periodic operator (paper Eq. A2) in f64
//! and in f32, on the whole grid and on a set of 0.5 % of its cells (the
//! Krylov products of a contact iteration), for the mixed-precision
//! budget of BENCHMARKS.md.
//!
//! `cargo run --release --example engine_precision -- [N] [REPEATS]`
//! (default 2048^2, 20 repeats; each precision is timed twice, alternating).

use std::time::Instant;
use viscoslide::response::{Grid, SlidingResponse};

use viscoslide::internals::operator::{
    GridOperator, GridWork, PeriodicResponse, Real, SpectralPeriodic,
};
use viscoslide::material::{CreepSpectrum, Material};

/// Mean over `repeats` products after one warm-up, in ms.
fn mean_ms(repeats: usize, mut product: impl FnMut()) -> f64 {
    product();
    let t = Instant::now();
    for _ in 0..repeats {
        product();
    }
    t.elapsed().as_secs_f64() * 1e3 / repeats as f64
}

fn time<T: Real>(n: usize, repeats: usize, material: &Material)
where
    SpectralPeriodic<T>: GridOperator,
{
    let sliding = SlidingResponse::new(material, 1e-2, 0.0, None).unwrap();
    let grid = Grid::square(n, n, 1e-5).unwrap();
    let t = Instant::now();
    let mut op =
        SpectralPeriodic::<T>::in_precision(&grid, &sliding, PeriodicResponse::Displacement);
    let build = t.elapsed().as_secs_f64() * 1e3;
    let x: Vec<f64> = (0..n * n).map(|k| ((k * 7919) % 101) as f64).collect();
    let mut y = vec![0.0; n * n];
    let grid = mean_ms(repeats, || op.apply(&x, &mut y));
    // One cell in 200, spread over the grid by a multiplicative hash.
    let cells: Vec<usize> = (0..n * n)
        .filter(|k| k.wrapping_mul(2_654_435_761) % 200 == 0)
        .collect();
    let xs: Vec<f64> = cells.iter().map(|&c| x[c]).collect();
    let mut ys = vec![0.0; cells.len()];
    let mut work = GridWork::default();
    let set = mean_ms(repeats, || op.apply_set(&cells, &xs, &mut ys, &mut work));
    println!(
        "f{}  {n}^2  operator {build:.0} ms  grid product {grid:.1} ms  set product ({} cells) {set:.1} ms",
        T::BYTES * 8,
        cells.len()
    );
}

fn main() {
    let mut args = std::env::args().skip(1);
    let n: usize = args
        .next()
        .map_or(2048, |s| s.parse().expect("N: a grid side"));
    let repeats: usize = args
        .next()
        .map_or(20, |s| s.parse().expect("REPEATS: a count"));
    let material = Material::new(
        CreepSpectrum::standard_linear_solid(1e7 / 3.0, 1e7, 0.01).expect("valid spectrum"),
        0.5,
    )
    .expect("valid material");
    for _ in 0..2 {
        time::<f64>(n, repeats, &material);
        time::<f32>(n, repeats, &material);
    }
}
