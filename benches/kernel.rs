//! Coefficient-table throughput (physics.md section 3): the full
//! `(2n-1)^2` table for the paper's single-relaxation material at
//! `v tau / a = 3` (and its friction-stencil table `D_x`) and for a 34-term
//! spectrum; and the 256^2 table (`K` and `D_x`) of a layer two cells thick
//! (bonded, cell integrals of Eq. 5). Set `CI` to shrink to 128^2.

use std::hint::black_box;
use viscoslide::response::{Grid, Layer, LayerBase, SlidingResponse};

use criterion::{criterion_group, criterion_main, Criterion};
use viscoslide::internals::kernel::{Axis, SlidingKernel};
use viscoslide::material::{CreepSpectrum, CreepTerm, Material};

fn sls() -> Material {
    let s = CreepSpectrum::standard_linear_solid(1e7 / 3.0, 1e7, 0.01).unwrap();
    Material::new(s, 0.5).unwrap()
}

/// 34 creep times in ratio e from 1e6 s down to 4.7e-9 s, log-normal-like
/// compliances summing to `1/E0 - 1/E_inf` (`E0 = 1e6`, `E_inf = 1e9` Pa);
/// the same spectrum as tests/kernel/accuracy.rs.
fn spectrum34() -> Material {
    let (e0, e_inf) = (1e6, 1e9);
    let total = 1.0 / e0 - 1.0 / e_inf;
    let raw: Vec<f64> = (0..34)
        .map(|k| (-((k as f64 - 16.5) / 8.0).powi(2)).exp())
        .collect();
    let sum: f64 = raw.iter().sum();
    let terms = raw
        .iter()
        .enumerate()
        .map(|(k, r)| CreepTerm {
            compliance: total * r / sum,
            time: 1e6 * (-(33.0 - k as f64)).exp(),
        })
        .collect();
    Material::new(CreepSpectrum::new(e_inf, terms).unwrap(), 0.5).unwrap()
}

fn bench(c: &mut Criterion) {
    let ci = std::env::var_os("CI").is_some();
    let n = if ci { 128 } else { 1024 };
    let cell = 1e-3;
    let mut group = c.benchmark_group("kernel_table");
    group.sample_size(10);
    let sls_kernel =
        SlidingKernel::new(&SlidingResponse::new(&sls(), 3.0 * cell / 0.01, 0.0, None).unwrap())
            .unwrap();
    group.bench_function(format!("sls_vtau3_{n}"), |b| {
        b.iter(|| {
            black_box(
                sls_kernel
                    .table(&Grid::square(black_box(n), n, cell).unwrap())
                    .unwrap(),
            )
        })
    });
    group.bench_function(format!("sls_vtau3_dx_{n}"), |b| {
        b.iter(|| {
            black_box(
                sls_kernel
                    .derivative_table(&Grid::square(black_box(n), n, cell).unwrap(), Axis::X)
                    .unwrap(),
            )
        })
    });
    let spec_kernel =
        SlidingKernel::new(&SlidingResponse::new(&spectrum34(), 1e-3, 0.0, None).unwrap()).unwrap();
    group.bench_function(format!("spectrum34_{n}"), |b| {
        b.iter(|| {
            black_box(
                spec_kernel
                    .table(&Grid::square(black_box(n), n, cell).unwrap())
                    .unwrap(),
            )
        })
    });
    let nl = if ci { 128 } else { 256 };
    let layer_kernel = SlidingKernel::new(
        &SlidingResponse::new(
            &sls(),
            3.0 * cell / 0.01,
            0.0,
            Some(Layer {
                thickness: 2.0 * cell,
                base: LayerBase::Bonded,
            }),
        )
        .unwrap(),
    )
    .unwrap();
    group.bench_function(format!("layer_2cells_{nl}"), |b| {
        b.iter(|| {
            black_box(
                layer_kernel
                    .table(&Grid::square(black_box(nl), nl, cell).unwrap())
                    .unwrap(),
            )
        })
    });
    group.bench_function(format!("layer_2cells_dx_{nl}"), |b| {
        b.iter(|| {
            black_box(
                layer_kernel
                    .derivative_table(&Grid::square(black_box(nl), nl, cell).unwrap(), Axis::X)
                    .unwrap(),
            )
        })
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
