//! Frictional heating's cost per evaluation of the heated solve (physics.md
//! section 14, issue #40): the heat source of a solved contact (the creep
//! elements' dissipation on the default depth layers, and the cheaper
//! surface work flux) and the heat problem's rise under each, on the paper
//! experiment's SBR-like rubber and surface at 17 C, 1e-4 m/s, 1 cm block.
//! The contact is solved once per size, outside the timings; the
//! isothermal solve is timed beside them for the ratio issue #40's
//! targets are stated in. With `CI` set the grid shrinks so the bench only
//! proves it runs.

use std::hint::black_box;
use std::path::Path;
use std::time::Duration;

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use viscoslide::config;
use viscoslide::heat::{
    Conduction, DepthRule, HeatDomain, HeatSetup, HeatSolver, HeatSource, SourceKind,
};
use viscoslide::internals::solver::Silent;
use viscoslide::problem::{Executor, Problem};

/// 256^2 and 512^2 (the paper's surface with its upper cut-off scaled to
/// keep 4.1 cells per shortest wavelength); 64^2 under `CI`.
fn sizes() -> Vec<usize> {
    if std::env::var_os("CI").is_some() {
        vec![64]
    } else {
        vec![256, 512]
    }
}

/// The paper experiment at 17 C on an `n x n` grid, its analysis off.
fn problem(n: usize) -> Problem {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("configs/paper_experiment.toml");
    // q1 = 6.31e6 1/m at 1024^2: scaled with the grid.
    let q1 = 6.31e6 * n as f64 / 1024.0;
    let sets = [
        format!("surface.generate.n={n}"),
        format!("surface.generate.q1={q1}"),
        "loading.temperature=17.0".to_string(),
        "analysis.enabled=false".to_string(),
    ];
    Problem::from_config(&config::load(&path, &sets).unwrap()).unwrap()
}

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("heat");
    let quick = std::env::var_os("CI").is_some();
    group
        .sample_size(10)
        .measurement_time(Duration::from_secs(if quick { 2 } else { 20 }));
    let rubber = Conduction {
        conductivity: 0.25,
        diffusivity: 1.16e-7,
    };
    for n in sizes() {
        let p = problem(n);
        let solution = p.solve(&Executor::Cpu, &mut Silent).unwrap();
        let (grid, response) = (p.grid().unwrap(), p.response().unwrap());
        let rule = DepthRule::default();
        let pressure = &solution.fields.pressure;
        let setup = HeatSetup {
            grid,
            conduction: rubber,
            speed: response.speed(),
            direction_rad: response.direction_rad(),
            domain: HeatDomain::Periodic {
                block_length: Some(0.01),
            },
        };
        group.throughput(Throughput::Elements((n * n) as u64));
        group.bench_function(format!("isothermal_solve_{n}"), |b| {
            b.iter(|| black_box(p.solve(&Executor::Cpu, &mut Silent).unwrap()))
        });
        for kind in [SourceKind::Volume, SourceKind::Surface] {
            let name = match kind {
                SourceKind::Volume => "volume",
                SourceKind::Surface => "surface",
            };
            let source = || HeatSource::from_contact(kind, pressure, &grid, &response, &rule);
            group.bench_function(format!("{name}_source_{n}"), |b| {
                b.iter(|| black_box(source().unwrap()))
            });
            let source = source().unwrap();
            let mut solver = HeatSolver::new(setup).unwrap();
            group.bench_function(format!("{name}_rise_{n}"), |b| {
                b.iter(|| black_box(solver.under(&source).unwrap()))
            });
        }
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
