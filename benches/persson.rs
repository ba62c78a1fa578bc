//! Persson's theory: a 100-speed curve (friction and contact area) for the
//! 34-term SBR-like creep spectrum of configs/paper_experiment.toml on its
//! 251-scale self-affine surface at 94 kPa. Shorter measurement when `CI`
//! is set.

use std::hint::black_box;
use std::time::Duration;

use criterion::{criterion_group, criterion_main, Criterion};
use viscoslide::material::load_material_file;
use viscoslide::persson::{self, Persson, PerssonParams};
use viscoslide::surface::{GenerateParams, Normalisation, UpperCutoff};

fn bench(c: &mut Criterion) {
    let ci = std::env::var_os("CI").is_some();
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("configs/data/sbr_like_material.toml");
    let material = load_material_file(&path, Some(0.5)).expect("shipped material");
    let surface = GenerateParams {
        nx: 1024,
        ny: 1024,
        length: 2.5032990e-4,
        hurst: 0.82,
        upper: UpperCutoff::Q1(6.31e6),
        normalisation: Normalisation::RmsSlope(0.5),
        ..GenerateParams::default()
    };
    let (psd, _) = persson::psd::continuum_self_affine(&surface).expect("valid surface");
    let theory =
        Persson::new(&material, &psd, 94e3, PerssonParams::default()).expect("valid inputs");
    let mut g = c.benchmark_group("persson");
    g.sample_size(if ci { 10 } else { 30 });
    if ci {
        g.warm_up_time(Duration::from_millis(200));
        g.measurement_time(Duration::from_secs(1));
    }
    // The experiment's measured range, and eleven decades.
    for (name, from, to) in [
        ("curve100_1e-6_1e-3", 1e-6, 1e-3),
        ("curve100_1e-8_1e3", 1e-8, 1e3),
    ] {
        let speeds = persson::log_speeds(from, to, 100);
        g.bench_function(name, |b| {
            b.iter(|| theory.curve(black_box(&speeds)).expect("valid speeds"))
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
