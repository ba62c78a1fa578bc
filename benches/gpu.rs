//! GPU backend throughput: the influence-coefficient table
//! (`shaders/coefficients.wgsl`, paper Eq. 6), one matvec (padded FFT
//! convolution, paper Eq. 7: the default workgroup-memory FFT, and the
//! radix-2 passes as `NxN_radix2`, whose bytes `viscoslide gpu plan --n N`
//! predicts) and full contact solves at the friction peak (xi = 1.17e-2, paper
//! material, 3 kPa on L = 0.01 m, rms slope 0.02). Timings include the
//! device work (each measured call ends with a readback or a wait).
//! A mixed-precision product's round trip on a full contact set
//! (`gpu_round_trip`: the transfer alone, and the whole product).
//! The adaptive-mesh matvec runs on the fly on a 1024-cell mesh
//! (`adaptive_matvec`) and from level tables on a 256 x 256 quadtree
//! (`level_matvec`).
//! With `CI` set the grids shrink to 64 x 64 so the bench only proves it
//! runs; `VISCOSLIDE_GPU_BENCH_LARGE=1` adds the 512 x 512 full solve and
//! the 1024 x 1024 matvec (minutes on a CPU-emulated adapter).
//! Without an adapter the bench prints why and measures nothing.

use std::hint::black_box;
use std::time::Duration;
use viscoslide::response::{Grid, SlidingResponse};

mod common;

use common::{material, surface_gap};
use criterion::{criterion_group, criterion_main, Criterion};
use viscoslide::internals::backend::gpu::{FftChoice, GpuBackend, GpuContext, GpuOptions};
use viscoslide::internals::backend::Backend;
use viscoslide::internals::kernel::SlidingKernel;
use viscoslide::internals::solver::{self, ContactProblem, Control, SolverParams};

fn ci() -> bool {
    std::env::var_os("CI").is_some()
}

fn large() -> bool {
    std::env::var("VISCOSLIDE_GPU_BENCH_LARGE").is_ok_and(|v| v == "1")
}

fn table(n: usize) -> Vec<f64> {
    let k = SlidingKernel::new(&SlidingResponse::new(&material(), 1.17e-2, 0.0, None).unwrap())
        .unwrap();
    k.table(&Grid::square(n, n, 0.01 / n as f64).unwrap())
        .unwrap()
        .values
}

fn open() -> Option<GpuContext> {
    match GpuContext::open() {
        Ok(c) => {
            eprintln!("gpu bench on {}", c.adapter);
            Some(c)
        }
        Err(e) => {
            eprintln!("gpu bench skipped: {e}");
            None
        }
    }
}

fn bench_coefficients(c: &mut Criterion) {
    use viscoslide::internals::backend::gpu::{coefficients, engine::Engine};
    let sizes: Vec<usize> = if ci() { vec![64] } else { vec![256, 512] };
    let mut group = c.benchmark_group("gpu_coefficients");
    group.sample_size(10);
    let Some(ctx) = open() else { return };
    let mut engine = Engine::new(ctx);
    let m = material();
    let params = 1.17e-2;
    for n in sizes {
        group.bench_function(format!("{n}x{n}"), |b| {
            b.iter(|| {
                coefficients::coefficient_table(
                    &mut engine,
                    &response(&m, params),
                    &Grid::square(n, n, 0.01 / n as f64).unwrap(),
                )
                .unwrap()
            })
        });
    }
    group.finish();
}

fn bench_matvec(c: &mut Criterion) {
    let sizes: Vec<usize> = if ci() {
        vec![64]
    } else if large() {
        vec![256, 512, 1024]
    } else {
        vec![256, 512]
    };
    let mut group = c.benchmark_group("gpu_matvec");
    group.sample_size(10);
    for n in sizes {
        let t = table(n);
        for (suffix, fft) in [("", FftChoice::Auto), ("_radix2", FftChoice::Radix2)] {
            let Some(ctx) = open() else { return };
            let options = GpuOptions {
                fft,
                ..Default::default()
            };
            let mut be = GpuBackend::new(ctx, n, n, &t, options).unwrap();
            let host: Vec<f64> = (0..n * n).map(|i| (i % 97) as f64).collect();
            let mut x = be.zeros(n * n);
            be.upload(&host, &mut x);
            let mut y = be.zeros(n * n);
            group.bench_function(format!("{n}x{n}{suffix}"), |b| {
                b.iter(|| {
                    be.apply(black_box(&x), &mut y);
                    be.synchronize();
                })
            });
        }
    }
    group.finish();
}

/// A mixed-precision product's round trip on a full contact set (the
/// smooth pad's case): the set's f64 values converted and written to the
/// device and read back as f64 (`transfer`), and the whole product through
/// [`MixedOperator::apply_set`] (`mixed_product`: the transfer, the
/// positions compared, scatter, matvec and gather on the device).
fn bench_round_trip(c: &mut Criterion) {
    use viscoslide::internals::backend::gpu::mixed::MixedOperator;
    use viscoslide::internals::operator::{GridOperator, GridWork, OffsetTable, ToeplitzFft};
    let sizes: Vec<usize> = if ci() {
        vec![64]
    } else if large() {
        vec![512, 1024, 2048]
    } else {
        vec![512, 1024]
    };
    let mut group = c.benchmark_group("gpu_round_trip");
    group.sample_size(10);
    for n in sizes {
        let Some(ctx) = open() else { return };
        let t = table(n);
        let mut be = GpuBackend::new(ctx, n, n, &t, GpuOptions::default()).unwrap();
        let host: Vec<f64> = (0..n * n).map(|i| (i % 97) as f64 - 48.0).collect();
        let mut back = vec![0.0; n * n];
        let mut x = be.zeros(n * n);
        group.bench_function(format!("transfer_{n}x{n}"), |b| {
            b.iter(|| {
                be.upload(black_box(&host), &mut x);
                be.download(&x, &mut back);
            })
        });
        drop(x);
        let exact = ToeplitzFft::new(OffsetTable {
            nx: n,
            ny: n,
            values: &t,
        });
        let mut op = MixedOperator::new(be, Box::new(exact));
        let cells: Vec<usize> = (0..n * n).collect();
        let mut work = GridWork::default();
        group.bench_function(format!("mixed_product_{n}x{n}"), |b| {
            b.iter(|| op.apply_set(&cells, black_box(&host), &mut back, &mut work))
        });
    }
    group.finish();
}

fn bench_solve(c: &mut Criterion) {
    let sizes: Vec<usize> = if ci() {
        vec![64]
    } else if large() {
        vec![256, 512]
    } else {
        vec![256]
    };
    let mut group = c.benchmark_group("gpu_solve");
    group
        .sample_size(10)
        .measurement_time(Duration::from_secs(30));
    for n in sizes {
        let Some(ctx) = open() else { return };
        let a = 0.01 / n as f64;
        let t = table(n);
        let l00 = t[(n - 1) * (2 * n - 1) + n - 1];
        let g = surface_gap(n);
        let mut be = GpuBackend::new(ctx, n, n, &t, GpuOptions::default()).unwrap();
        let load = 3e3 * 0.01 * 0.01;
        group.bench_function(format!("viscoelastic_peak_{n}x{n}"), |b| {
            b.iter(|| {
                let (sol, info) = solver::solve(
                    &mut be,
                    ContactProblem::new(black_box(&g), a * a, l00, Control::Load(load)),
                    &SolverParams::default(),
                    None,
                    &mut solver::Silent,
                )
                .unwrap();
                black_box((sol.approach, info.matvecs))
            })
        });
    }
    group.finish();
}

/// A quadtree-like mesh: a `2f x 2f` patch of fine cells (side `a`) centred
/// at the origin, surrounded by `levels - 1` rings of 2a, 4a, ... cells, each
/// ring doubling the half-width.
fn ring_mesh(f: usize, levels: u32, a: f64) -> viscoslide::internals::backend::gpu::MeshCells {
    let mut cells = viscoslide::internals::backend::gpu::MeshCells::default();
    let (mut inner, mut outer) = (0i64, f as i64);
    for level in 0..levels {
        let side = 1i64 << level;
        for i in (-outer..outer).step_by(side as usize) {
            for j in (-outer..outer).step_by(side as usize) {
                if !(i >= -inner && i < inner && j >= -inner && j < inner) {
                    cells.x.push((i as f64 + 0.5 * side as f64) * a);
                    cells.y.push((j as f64 + 0.5 * side as f64) * a);
                    cells.side.push(side as f64 * a);
                }
            }
        }
        inner = outer;
        outer *= 2;
    }
    cells
}

/// One matrix-free matvec of the adaptive-mesh operator (coefficients of
/// paper Eq. 4/6 evaluated on the fly, paper Eq. 7) at the friction peak:
/// 1024 cells (a 16 x 16 fine patch and rings of 2a ... 16a), the first 300
/// of them (the fine patch and part of the 2a ring) carrying pressure.
/// Under `CI`: 208 cells, 64 nonzero.
fn bench_adaptive_matvec(c: &mut Criterion) {
    let (f, levels, nonzero) = if ci() { (4, 4, 64) } else { (8, 5, 300) };
    let mut group = c.benchmark_group("adaptive_matvec");
    group.sample_size(10);
    let Some(ctx) = open() else { return };
    let a = 1e-4;
    let cells = ring_mesh(f, levels, a);
    let n = cells.len();
    let params = 1.17e-2;
    let engine = viscoslide::internals::backend::gpu::engine::Engine::new(ctx);
    let mut be = GpuBackend::with_adaptive(engine, &response(&material(), params), &cells).unwrap();
    let host: Vec<f64> = (0..n)
        .map(|i| {
            if i < nonzero {
                1e5 + (i % 7) as f64
            } else {
                0.0
            }
        })
        .collect();
    let mut x = be.zeros(n);
    be.upload(&host, &mut x);
    let mut y = be.zeros(n);
    group.bench_function(format!("{n}_cells_{nonzero}_nonzero"), |b| {
        b.iter(|| {
            be.apply(black_box(&x), &mut y);
            be.synchronize();
        })
    });
    group.finish();
}

/// The quadtree operator from device-computed level tables
/// (`level_table.wgsl`, `level_box_sum.wgsl`, `level_matvec.wgsl`): building
/// the tables of levels 0-5 for a 256 x 256 fine grid, and one matvec on the
/// quadtree that keeps fine the lowest 5 % of the surface's gap (the
/// bench surface at the friction peak), every fine cell carrying pressure.
/// Under `CI`: a 64 x 64 grid.
fn bench_level_matvec(c: &mut Criterion) {
    use viscoslide::internals::backend::gpu::{engine::Engine, GpuLevelTables};
    use viscoslide::internals::mesh::QuadMesh;
    let n = if ci() { 64 } else { 256 };
    let mut group = c.benchmark_group("level_matvec");
    group.sample_size(10);
    let Some(ctx) = open() else { return };
    let a = 0.01 / n as f64;
    let params = 1.17e-2;
    let m = material();
    let mut engine = Engine::new(ctx);
    group.bench_function(format!("tables_{n}x{n}_levels0-5"), |b| {
        b.iter(|| GpuLevelTables::new(&mut engine, &response(&m, params), n, n, a, 5).unwrap())
    });
    let tables = GpuLevelTables::new(&mut engine, &response(&m, params), n, n, a, 5).unwrap();
    let g = surface_gap(n);
    let mut sorted = g.clone();
    sorted.sort_by(f64::total_cmp);
    let cut = sorted[g.len() / 20];
    let fine: Vec<bool> = g.iter().map(|&v| v <= cut).collect();
    let mesh = QuadMesh::from_mask(n, n, a, 5, &fine).unwrap();
    let cells = mesh.len();
    let host: Vec<f64> = mesh
        .cells
        .iter()
        .map(|c| if c.level == 0 { 1e5 } else { 0.0 })
        .collect();
    let nonzero = host.iter().filter(|&&v| v != 0.0).count();
    let mut be = GpuBackend::with_level_tables(engine, &tables, &mesh).unwrap();
    let mut x = be.zeros(cells);
    be.upload(&host, &mut x);
    let mut y = be.zeros(cells);
    group.bench_function(format!("{cells}_cells_{nonzero}_nonzero"), |b| {
        b.iter(|| {
            be.apply(black_box(&x), &mut y);
            be.synchronize();
        })
    });
    group.finish();
}

criterion_group!(
    name = benches;
    // 10 s per benchmark unless `--measurement-time` says otherwise (a
    // group's own setting would override the command line, which the GPU
    // machine's short run needs: `scripts/gpu-run`'s criterion step).
    config = Criterion::default().measurement_time(Duration::from_secs(10));
    targets =
    bench_coefficients,
    bench_matvec,
    bench_round_trip,
    bench_solve,
    bench_adaptive_matvec,
    bench_level_matvec
);
criterion_main!(benches);

/// The half-space response of `material` sliding along +x at `speed` [m/s].
fn response(material: &viscoslide::material::Material, speed: f64) -> SlidingResponse {
    SlidingResponse::new(material, speed, 0.0, None).unwrap()
}
