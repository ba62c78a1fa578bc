//! Adaptive quadtree mesh against the uniform FFT path at equal finest
//! resolution (physics.md section 7): the level tables, one rows-only
//! product over a contact set, and whole viscoelastic solves at the friction
//! peak (xi = 1.17e-2, paper material, 3 kPa on L = 0.01 m, rms slope
//! 0.02), both meshes in the same run. The adaptive solve includes its
//! solve-certify-refine rounds. Grids shrink to 64 x 64 under `CI`.

use std::hint::black_box;
use std::sync::Arc;
use std::time::Duration;
use viscoslide::response::{Grid, SlidingResponse};

mod common;

use common::{material, surface_gap};
use criterion::{criterion_group, criterion_main, Criterion};
use viscoslide::internals::backend::CpuBackend;
use viscoslide::internals::kernel::SlidingKernel;
use viscoslide::internals::mesh::QuadMesh;
use viscoslide::internals::operator::{
    AdaptiveOperator, GridOperator, LevelTables, OffsetTable, ToeplitzFft,
};
use viscoslide::internals::solver::{self, ContactProblem, Control, SolverParams};
use viscoslide::problem::adaptive::{self, AdaptiveParams};

const SPEED: f64 = 1.17e-2; // xi = v tau / L = 1.17e-2 with tau = 0.01 s, L = 0.01 m
const LOAD: f64 = 0.30;

fn sizes() -> Vec<usize> {
    if std::env::var_os("CI").is_some() {
        vec![64]
    } else {
        vec![128, 256]
    }
}

fn kernel() -> SlidingKernel {
    SlidingKernel::new(&SlidingResponse::new(&material(), SPEED, 0.0, None).unwrap()).unwrap()
}

fn adaptive_solve(tables: &Arc<LevelTables>, g: &[f64]) -> adaptive::AdaptiveSolution {
    let a = tables.cell_size();
    let l00 = tables.coefficient(0, 0, 0);
    adaptive::solve_adaptive(
        g,
        tables.clone(),
        &AdaptiveParams::default(),
        1e-8,
        |m, gm, start, tol| {
            let mut be = CpuBackend::new(AdaptiveOperator::new(tables.clone(), m));
            solver::solve(
                &mut be,
                ContactProblem::new(gm, a * a, l00, Control::Load(LOAD)),
                &SolverParams {
                    tolerance: tol,
                    ..Default::default()
                },
                (start).cloned(),
                &mut solver::Silent,
            )
        },
    )
    .unwrap()
}

fn bench_tables(c: &mut Criterion) {
    let k = kernel();
    let mut group = c.benchmark_group("adaptive_tables");
    group
        .sample_size(10)
        .measurement_time(Duration::from_secs(10));
    for n in sizes() {
        let a = 0.01 / n as f64;
        group.bench_function(format!("{n}x{n}_levels0-5"), |b| {
            b.iter(|| black_box(LevelTables::new(&k, n, n, a, 5).unwrap()))
        });
    }
    group.finish();
}

fn bench_solves(c: &mut Criterion) {
    let k = kernel();
    let mut group = c.benchmark_group("adaptive_vs_uniform_solve");
    group
        .sample_size(10)
        .measurement_time(Duration::from_secs(20));
    for n in sizes() {
        let a = 0.01 / n as f64;
        let g = surface_gap(n);
        let tables = Arc::new(LevelTables::new(&k, n, n, a, 5).unwrap());
        let sol = adaptive_solve(&tables, &g);
        println!(
            "{n}x{n}: adaptive mesh {} unknowns ({:.2}x fewer than {}), {} rounds, {} matvecs",
            sol.report.unknowns,
            (n * n) as f64 / sol.report.unknowns as f64,
            n * n,
            sol.report.rounds,
            sol.info.matvecs
        );
        // Rows-only product over the final contact set (the inner solves).
        let m: &QuadMesh = &sol.mesh;
        let mut op = AdaptiveOperator::new(tables.clone(), m);
        let mut x = vec![0.0; m.len()];
        let mut rows = vec![];
        for (k, cell) in m.cells.iter().enumerate() {
            let f = cell.i as usize * n + cell.j as usize;
            if cell.level == 0 && sol.solution.contact[f] > 0.5 {
                x[k] = sol.solution.pressure[f];
                rows.push(k);
            }
        }
        let mut scratch = vec![0.0; m.len()];
        let mut out = vec![0.0; rows.len()];
        group.bench_function(
            format!("{n}x{n}_rows_product_{}_contact_cells", rows.len()),
            |b| b.iter(|| op.apply_rows(black_box(&x), &rows, &mut scratch, &mut out)),
        );
        group.bench_function(format!("{n}x{n}_adaptive"), |b| {
            b.iter(|| black_box(adaptive_solve(&tables, &g)))
        });
        let table = k.table(&Grid::square(n, n, a).unwrap()).unwrap();
        let tab = OffsetTable {
            nx: n,
            ny: n,
            values: &table.values,
        };
        group.bench_function(format!("{n}x{n}_uniform_fft"), |b| {
            b.iter(|| {
                let mut be = CpuBackend::new(ToeplitzFft::new(tab));
                black_box(
                    solver::solve(
                        &mut be,
                        ContactProblem::new(&g, a * a, tab.get(0, 0), Control::Load(LOAD)),
                        &SolverParams::default(),
                        None,
                        &mut solver::Silent,
                    )
                    .unwrap(),
                )
            })
        });
    }
    group.finish();
}

criterion_group!(benches, bench_tables, bench_solves);
criterion_main!(benches);
