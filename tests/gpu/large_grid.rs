//! The GPU path at 2048 x 2048, the largest grid a 128 MiB storage binding
//! holds (the padded complex FFT buffer is 4096 x 4096 x 8 B = 128 MiB): the
//! device coefficient table against the host's and one matvec against the
//! CPU Toeplitz FFT. Minutes on a CPU-emulated adapter, so it runs only with
//! `VISCOSLIDE_GPU_LARGE=1` (the regular conformance suite covers the same
//! kernels on small grids); it then prints its timings.

use crate::common;
use viscoslide::response::{Grid, SlidingResponse};

use std::time::Instant;

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use viscoslide::internals::backend::gpu::engine::Engine;
use viscoslide::internals::backend::gpu::{self, coefficients, GpuBackend, GpuOptions};
use viscoslide::internals::backend::Backend;
use viscoslide::internals::kernel::SlidingKernel;
use viscoslide::internals::operator::{GridOperator, OffsetTable, ToeplitzFft};

fn rel_l2(a: &[f64], b: &[f64]) -> f64 {
    let num: f64 = a.iter().zip(b).map(|(x, y)| (x - y) * (x - y)).sum();
    let den: f64 = b.iter().map(|y| y * y).sum();
    (num / den).sqrt()
}

#[test]
fn grid_2048_runs_within_the_binding_limit() {
    if std::env::var("VISCOSLIDE_GPU_LARGE").map_or(true, |v| v != "1") {
        eprintln!("skipping the 2048^2 GPU run: set VISCOSLIDE_GPU_LARGE=1 (minutes on lavapipe)");
        return;
    }
    let Some(ctx) = crate::common::gpu_context() else {
        return;
    };
    let n = 2048;
    let a = 0.01 / n as f64;
    let material = common::paper_material();
    let response = SlidingResponse::new(&material, 1.17e-2, 0.0, None).unwrap();
    let kernel = SlidingKernel::new(&response).unwrap();
    let t = Instant::now();
    let host = kernel
        .table(&Grid::square(n, n, a).unwrap())
        .unwrap()
        .values;
    let t_host = t.elapsed().as_secs_f64();
    let mut engine = Engine::new(ctx);
    let t = Instant::now();
    let device =
        coefficients::coefficient_table(&mut engine, &response, &Grid::square(n, n, a).unwrap())
            .unwrap();
    let t_table = t.elapsed().as_secs_f64();
    // Coefficient bound of the conformance suite: 1e-5 relative wherever
    // the value exceeds 1e-6 of the table's maximum.
    let max = host.iter().cloned().fold(0.0f64, f64::max);
    let worst = host
        .iter()
        .zip(&device)
        .filter(|(h, _)| **h > 1e-6 * max)
        .map(|(h, d)| (h - d).abs() / h)
        .fold(0.0f64, f64::max);
    assert!(worst < 1e-5, "coefficient error {worst:.2e}");

    let t = Instant::now();
    let mut g = GpuBackend::with_engine(engine, n, n, &host, GpuOptions::default()).unwrap();
    let t_setup = t.elapsed().as_secs_f64();
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    // A contact-like input: 5 % of the cells loaded.
    let x: Vec<f64> = (0..n * n)
        .map(|_| {
            if rng.random_range(0.0..1.0) < 0.05 {
                rng.random_range(0.0..1e4)
            } else {
                0.0
            }
        })
        .collect();
    let mut xv = g.zeros(n * n);
    g.upload(&x, &mut xv);
    let mut yv = g.zeros(n * n);
    let t = Instant::now();
    g.apply(&xv, &mut yv);
    let mut y = vec![0.0; n * n];
    g.download(&yv, &mut y);
    let t_matvec = t.elapsed().as_secs_f64();
    let mut cpu = ToeplitzFft::new(OffsetTable {
        nx: n,
        ny: n,
        values: &host,
    });
    let mut want = vec![0.0; n * n];
    let t = Instant::now();
    cpu.apply(&x, &mut want);
    let t_cpu = t.elapsed().as_secs_f64();
    let e = rel_l2(&y, &want);
    println!(
        "2048^2 on {}: table {t_table:.1} s (host {t_host:.1} s), coefficient error {worst:.1e}; \
         backend setup {t_setup:.1} s; matvec {t_matvec:.2} s incl. readback (CPU FFT {t_cpu:.2} s), error {e:.1e}",
        g.name()
    );
    assert!(e < 1e-5, "matvec error {e:.2e}");
}

/// A grid whose padded FFT exceeds lavapipe's 128 MiB binding: at 2049^2
/// the work buffers and the spectrum (`8192 x 4097` complex f32, 268 MB
/// each) are bound in three windows (backend::gpu::split). One matvec
/// against the CPU Toeplitz FFT (host table; the device table's 2049^2
/// would take minutes more), same bound as above. Only with
/// `VISCOSLIDE_GPU_LARGE=1`; prints its timings.
#[test]
fn grid_beyond_one_binding_is_split() {
    if std::env::var("VISCOSLIDE_GPU_LARGE").map_or(true, |v| v != "1") {
        eprintln!("skipping the 2049^2 GPU run: set VISCOSLIDE_GPU_LARGE=1 (minutes on lavapipe)");
        return;
    }
    let Some(ctx) = crate::common::gpu_context() else {
        return;
    };
    let n = 2049;
    let engine = Engine::new(ctx);
    let path = gpu::fft_plan::Path::for_device(&engine.ctx.device.limits());
    let work = 8 * gpu::fft_plan::work_elements(n, n, path) as u64;
    let windows = engine.windows(work);
    let a = 0.01 / n as f64;
    let kernel = SlidingKernel::new(
        &SlidingResponse::new(&common::paper_material(), 1.17e-2, 0.0, None).unwrap(),
    )
    .unwrap();
    let host = kernel
        .table(&Grid::square(n, n, a).unwrap())
        .unwrap()
        .values;
    let t = Instant::now();
    let mut g = GpuBackend::with_engine(engine, n, n, &host, GpuOptions::default()).unwrap();
    let t_setup = t.elapsed().as_secs_f64();
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let x: Vec<f64> = (0..n * n)
        .map(|_| {
            if rng.random_range(0.0..1.0) < 0.05 {
                rng.random_range(0.0..1e4)
            } else {
                0.0
            }
        })
        .collect();
    let mut xv = g.zeros(n * n);
    g.upload(&x, &mut xv);
    let mut yv = g.zeros(n * n);
    let mut y = vec![0.0; n * n];
    let mut t_matvec = Vec::new();
    for _ in 0..2 {
        let t = Instant::now();
        g.apply(&xv, &mut yv);
        g.download(&yv, &mut y);
        t_matvec.push(t.elapsed().as_secs_f64());
    }
    let mut cpu = ToeplitzFft::new(OffsetTable {
        nx: n,
        ny: n,
        values: &host,
    });
    let mut want = vec![0.0; n * n];
    let t = Instant::now();
    cpu.apply(&x, &mut want);
    let t_cpu = t.elapsed().as_secs_f64();
    let e = rel_l2(&y, &want);
    println!(
        "2049^2 on {}: FFT buffers {work} B in {windows} windows; backend setup {t_setup:.1} s; \
         matvec {:.2} s, {:.2} s incl. readback (CPU FFT {t_cpu:.2} s), error {e:.1e}",
        g.name(),
        t_matvec[0],
        t_matvec[1]
    );
    if windows == 1 {
        println!("(this adapter binds the FFT buffers whole: nothing was split)");
    }
    assert!(e < 1e-5, "matvec error {e:.2e}");
}
