//! Periodic spectral operator (paper Appendix, Eq. A1-A2): one matvec
//! against the non-periodic padded-FFT convolution on the same grid, and a
//! full viscoelastic solve at the friction peak (xi = 1.17e-2, a few percent
//! contact). With `CI` set the grids shrink so the bench only proves it runs.

use std::hint::black_box;
use std::time::Duration;
use viscoslide::internals::operator::PeriodicResponse;
use viscoslide::response::{Grid, SlidingResponse};

mod common;

use common::{material, sizes, surface_gap};
use criterion::{criterion_group, criterion_main, Criterion};
use viscoslide::internals::backend::CpuBackend;
use viscoslide::internals::kernel::SlidingKernel;
use viscoslide::internals::operator::{GridOperator, OffsetTable, SpectralPeriodic, ToeplitzFft};
use viscoslide::internals::solver::{self, ContactProblem, Control, SolverParams};

fn bench(c: &mut Criterion) {
    let m = material();
    let (length, speed) = (0.01, 1.17e-2);
    let mut group = c.benchmark_group("periodic");
    group
        .sample_size(10)
        .measurement_time(Duration::from_secs(10));
    for n in sizes() {
        let a = length / n as f64;
        let x: Vec<f64> = (0..n * n).map(|k| ((k * 7919) % 101) as f64).collect();
        let mut y = vec![0.0; n * n];
        let mut op = SpectralPeriodic::new(
            &Grid::square(n, n, a).unwrap(),
            &SlidingResponse::new(&m, speed, 0.0, None).unwrap(),
            PeriodicResponse::Displacement,
        );
        group.bench_function(format!("matvec_periodic_{n}"), |b| {
            b.iter(|| op.apply(black_box(&x), &mut y))
        });
        let kernel =
            SlidingKernel::new(&SlidingResponse::new(&m, speed, 0.0, None).unwrap()).unwrap();
        let table = kernel.table(&Grid::square(n, n, a).unwrap()).unwrap();
        let mut np = ToeplitzFft::new(OffsetTable {
            nx: n,
            ny: n,
            values: &table.values,
        });
        group.bench_function(format!("matvec_nonperiodic_{n}"), |b| {
            b.iter(|| np.apply(black_box(&x), &mut y))
        });
        group.bench_function(format!("build_periodic_{n}"), |b| {
            b.iter(|| {
                black_box(SpectralPeriodic::new(
                    &Grid::square(n, n, a).unwrap(),
                    &SlidingResponse::new(&m, speed, 0.0, None).unwrap(),
                    PeriodicResponse::Displacement,
                ))
            })
        });
        let g = surface_gap(n);
        let l00 = op.self_coefficient();
        let mut be = CpuBackend::new(op);
        let mut last = None;
        group.bench_function(format!("solve_periodic_{n}"), |b| {
            b.iter(|| {
                let r = solver::solve(
                    &mut be,
                    ContactProblem::new(&g, a * a, l00, Control::Load(0.3)),
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
                "solve_periodic_{n}: {} iterations, {} matvecs, residual {:.2e}",
                info.iterations, info.matvecs, info.residual
            );
        }
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
