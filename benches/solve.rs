//! Contact-solver throughput on the CPU path: one matvec (padded-FFT
//! convolution) and full solves, viscoelastic at the friction peak
//! (xi = 1.17e-2, a few percent contact) and elastic (v = 0).
//! With `CI` set the grids shrink so the bench only proves it runs.

use std::hint::black_box;
use std::time::Duration;
use viscoslide::response::{Grid, SlidingResponse};

mod common;

use common::{material, sizes, surface_gap};
use criterion::{criterion_group, criterion_main, Criterion};
use viscoslide::internals::backend::CpuBackend;
use viscoslide::internals::kernel::SlidingKernel;
use viscoslide::internals::operator::{GridOperator, OffsetTable, ToeplitzFft};
use viscoslide::internals::solver::{self, ContactProblem, Control, SolverParams};

fn bench(c: &mut Criterion) {
    let m = material();
    let mut group = c.benchmark_group("solve");
    group
        .sample_size(10)
        .measurement_time(Duration::from_secs(20));
    for n in sizes() {
        let a = 0.01 / n as f64;
        let g = surface_gap(n);
        for (label, speed) in [("viscoelastic_peak", 1.17e-2), ("elastic", 0.0)] {
            if label == "elastic" && n < 512 && std::env::var_os("CI").is_none() {
                continue;
            }
            let kernel =
                SlidingKernel::new(&SlidingResponse::new(&m, speed, 0.0, None).unwrap()).unwrap();
            let table = kernel.table(&Grid::square(n, n, a).unwrap()).unwrap();
            let tab = OffsetTable {
                nx: n,
                ny: n,
                values: &table.values,
            };
            let mut op = ToeplitzFft::new(tab);
            if label == "viscoelastic_peak" {
                let x: Vec<f64> = (0..n * n).map(|k| ((k * 7919) % 101) as f64).collect();
                let mut y = vec![0.0; n * n];
                group.bench_function(format!("matvec_{n}"), |b| {
                    b.iter(|| op.apply(black_box(&x), &mut y))
                });
            }
            let mut be = CpuBackend::new(op);
            let mut last = None;
            group.bench_function(format!("{label}_{n}"), |b| {
                b.iter(|| {
                    let r = solver::solve(
                        &mut be,
                        ContactProblem::new(&g, a * a, tab.get(0, 0), Control::Load(0.3)),
                        &SolverParams::default(),
                        None,
                        &mut solver::Silent,
                    )
                    .unwrap();
                    last = Some(r.1.clone());
                    black_box(r)
                })
            });
            if let Some(info) = last {
                eprintln!(
                    "{label}_{n}: {} iterations, {} matvecs, residual {:.2e}",
                    info.iterations, info.matvecs, info.residual
                );
            }
        }
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
