//! Surface generation and PSD at 1024^2 and 4096^2 (256^2 and 512^2 with a
//! small sample size when `CI` is set).

use std::hint::black_box;
use std::time::Duration;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use viscoslide::surface::{
    generate, psd_2d, radial_average, GenerateParams, Normalisation, UpperCutoff, Window,
};

fn params(n: usize) -> GenerateParams {
    GenerateParams {
        nx: n,
        ny: n,
        length: 0.01,
        hurst: 0.8,
        upper: UpperCutoff::Scales((n / 4) as f64),
        normalisation: Normalisation::RmsHeight(1e-5),
        seed: 1,
        ..GenerateParams::default()
    }
}

fn bench(c: &mut Criterion) {
    let ci = std::env::var_os("CI").is_some();
    let sizes: &[usize] = if ci { &[256, 512] } else { &[1024, 4096] };
    let mut g = c.benchmark_group("surface");
    g.sample_size(10);
    if ci {
        g.warm_up_time(Duration::from_millis(200));
        g.measurement_time(Duration::from_secs(1));
    }
    for &n in sizes {
        g.throughput(Throughput::Elements((n * n) as u64));
        if !ci {
            g.measurement_time(Duration::from_secs(if n >= 4096 { 30 } else { 5 }));
        }
        let p = params(n);
        g.bench_with_input(BenchmarkId::new("generate", n), &p, |b, p| {
            b.iter(|| generate(black_box(p)).expect("valid parameters"))
        });
        let map = generate(&p).expect("valid parameters");
        g.bench_with_input(BenchmarkId::new("psd_radial", n), &map, |b, m| {
            b.iter(|| {
                let psd = psd_2d(black_box(m), Window::None).expect("valid map");
                radial_average(&psd)
            })
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
