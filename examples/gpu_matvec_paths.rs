//! Wall time of one GPU matvec on the default (workgroup-memory) FFT path
//! against the radix-2 passes, interleaved in one run on one device, for
//! BENCHMARKS.md: each round times one matvec of each path (recorded,
//! submitted and waited for), and the medians and their ratio are printed
//! with the traffic of both plans and the agreement of the two results.
//!
//! `cargo run --release --example gpu_matvec_paths -- N ROUNDS`
//! (default 512 and 15; the kernel of the paper material at v = 1.17e-2
//! m/s on L = 0.01 m).

use std::time::Instant;
use viscoslide::response::{Grid, SlidingResponse};

use viscoslide::internals::backend::gpu::{FftChoice, GpuBackend, GpuContext, GpuOptions};
use viscoslide::internals::backend::Backend;
use viscoslide::internals::kernel::SlidingKernel;
use viscoslide::material::{CreepSpectrum, Material};

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    let k = v.len() / 2;
    if v.len() % 2 == 1 {
        v[k]
    } else {
        0.5 * (v[k - 1] + v[k])
    }
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let n: usize = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(512);
    let rounds: usize = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(15);
    let material = Material::new(
        CreepSpectrum::standard_linear_solid(1e6, 1e7, 0.01).expect("valid material"),
        0.5,
    )
    .expect("valid material");
    let kernel = SlidingKernel::new(&SlidingResponse::new(&material, 1.17e-2, 0.0, None).unwrap())
        .expect("valid kernel");
    let table = kernel
        .table(&Grid::square(n, n, 0.01 / n as f64).unwrap())
        .unwrap()
        .values;
    let ctx = GpuContext::open().expect("a GPU adapter (lavapipe will do)");
    println!("adapter: {}", ctx.adapter);
    let mut backends: Vec<(&str, GpuBackend)> =
        [("radix-2", FftChoice::Radix2), ("default", FftChoice::Auto)]
            .into_iter()
            .map(|(name, fft)| {
                let options = GpuOptions {
                    fft,
                    ..Default::default()
                };
                let b = GpuBackend::new(ctx.clone(), n, n, &table, options).expect("grid fits");
                (name, b)
            })
            .collect();
    let host: Vec<f64> = (0..n * n).map(|i| ((i * 7919) % 1009) as f64).collect();
    let mut results = Vec::new();
    let mut times = vec![Vec::new(); backends.len()];
    for round in 0..=rounds {
        for (k, (_, be)) in backends.iter_mut().enumerate() {
            let mut x = be.zeros(n * n);
            be.upload(&host, &mut x);
            let mut y = be.zeros(n * n);
            be.synchronize();
            let t = Instant::now();
            be.apply(&x, &mut y);
            be.synchronize();
            let dt = t.elapsed().as_secs_f64();
            // Round 0 warms the pipelines up and is not counted.
            if round > 0 {
                times[k].push(dt);
            } else {
                let mut out = vec![0.0; n * n];
                be.download(&y, &mut out);
                results.push(out);
            }
        }
    }
    let diff: f64 = results[0]
        .iter()
        .zip(&results[1])
        .map(|(a, b)| (a - b) * (a - b))
        .sum::<f64>()
        .sqrt()
        / results[0].iter().map(|a| a * a).sum::<f64>().sqrt();
    let mut medians = Vec::new();
    for ((name, be), t) in backends.iter().zip(times.iter_mut()) {
        let traffic = be.fft_plan().expect("an FFT matvec").traffic();
        let m = median(t);
        medians.push(m);
        println!(
            "{name:>8}: {} dispatches, {:.1} MB per matvec; median {:.2} ms over {rounds} rounds (min {:.2}, max {:.2})",
            traffic.dispatches,
            traffic.bytes() as f64 / 1e6,
            m * 1e3,
            t.first().unwrap() * 1e3,
            t.last().unwrap() * 1e3,
        );
    }
    println!(
        "{n} x {n}: radix-2 / default = {:.1}; results agree to {diff:.2e} (relative L2)",
        medians[0] / medians[1]
    );
}
