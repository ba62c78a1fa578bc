//! Periodic vs non-periodic formulation on the same rough surface in partial
//! contact, as a function of the domain length over the relaxation length,
//! `L / (v tau)` (the caveat of the paper's Appendix, quantified;
//! physics.md section 6).
//!
//! `domain_study` (ignored: about a minute) regenerates the table and plot
//! of docs/periodic-vs-nonperiodic.md:
//! `cargo test --release --test periodic_domain_study -- --ignored --nocapture`.

mod common;

use std::path::Path;

use viscoslide::analysis::{friction_force_periodic, friction_force_stencil};
use viscoslide::backend::CpuBackend;
use viscoslide::operator::SpectralPeriodic;
use viscoslide::plot::{xy_chart, Series, XyChart};
use viscoslide::solver::{self, Control, SolverParams};

const LENGTH: f64 = 0.01;
const TAU: f64 = 0.01;
/// Nominal pressures [Pa]: about 1 % and 5 % of contact at this slope.
const LOADS: [f64; 2] = [2e3, 1e4];
const SLOPE: f64 = 0.1;

/// `(mu, contact fraction)` of one formulation.
#[derive(Debug, Clone, Copy)]
struct Outcome {
    mu: f64,
    area: f64,
}

fn surface(n: usize) -> Vec<f64> {
    common::trig_surface(n, LENGTH, 16, 0.8, SLOPE, 11)
}

fn periodic(z: &[f64], n: usize, speed: f64, p0: f64) -> Outcome {
    let material = common::paper_material();
    let a = LENGTH / n as f64;
    let op = SpectralPeriodic::new(n, n, a, &material, speed, 0.0);
    let l00 = op.self_coefficient();
    let mut be = CpuBackend::new(op);
    let load = p0 * LENGTH * LENGTH;
    let (sol, _) = solver::solve(
        &mut be,
        &common::gap_of(z),
        a * a,
        l00,
        Control::Load(load),
        &SolverParams::default(),
        &mut solver::Silent,
    )
    .unwrap();
    let mut d = SpectralPeriodic::sliding_slope(n, n, a, &material, speed, 0.0);
    let fs = friction_force_stencil(&mut d, &sol.pressure, a);
    let ff = friction_force_periodic(&sol.pressure, n, n, a, &material, speed, 0.0);
    assert!((fs - ff).abs() <= 1e-9 * ff.abs() + 1e-12 * load);
    Outcome {
        mu: -fs / load,
        area: sol.contact.iter().sum::<f64>() / (n * n) as f64,
    }
}

fn non_periodic(z: &[f64], n: usize, speed: f64, p0: f64) -> Outcome {
    let material = common::paper_material();
    let a = LENGTH / n as f64;
    let (sol, _, kernel) = common::solve_grid(
        &material,
        z,
        n,
        LENGTH,
        speed,
        Control::Load(p0 * LENGTH * LENGTH),
    );
    let (mu, _) = common::friction(&kernel, &material, &sol, n, a, speed);
    Outcome {
        mu,
        area: sol.contact.iter().sum::<f64>() / (n * n) as f64,
    }
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// At about 1 % contact, on a domain 30 relaxation lengths long, the two
/// formulations agree on friction and area within the 2 % the study finds
/// for `L / (v tau) >= 10` (measured: 0.6 % and 0.7 % on 256^2); on a domain
/// shorter than the relaxation length they do not (the periodic cell then
/// feeds the material its own repeated history: 19 % at `L / (v tau) = 0.3`).
#[test]
fn partial_contact_agrees_on_long_domain_only() {
    // 128^2 already gives 2.0 % on mu here (contact spots of a few cells):
    // the agreement needs the resolution too.
    let n = 256;
    let z = surface(n);
    let long = LENGTH / (30.0 * TAU);
    let (p, q) = (
        periodic(&z, n, long, LOADS[0]),
        non_periodic(&z, n, long, LOADS[0]),
    );
    println!("L/(v tau) = 30, {n}^2: periodic {p:?}, non-periodic {q:?}");
    assert!(p.area > 0.002 && p.area < 0.05, "partial contact expected");
    assert!(rel(p.mu, q.mu) < 0.02, "mu {} vs {}", p.mu, q.mu);
    assert!(rel(p.area, q.area) < 0.02, "area {} vs {}", p.area, q.area);
    let short = LENGTH / (0.3 * TAU);
    let (p, q) = (
        periodic(&z, n, short, LOADS[0]),
        non_periodic(&z, n, short, LOADS[0]),
    );
    println!("L/(v tau) = 0.3, {n}^2: periodic {p:?}, non-periodic {q:?}");
    assert!(rel(p.mu, q.mu) > 0.1, "mu {} vs {}", p.mu, q.mu);
}

#[test]
#[ignore = "domain study: about a minute; regenerates docs/periodic-vs-nonperiodic.png"]
fn domain_study() {
    let ratios = [0.1, 0.3, 1.0, 3.0, 10.0, 30.0, 100.0];
    let mut series = Vec::new();
    for (c, (p0, n)) in [(LOADS[0], 256usize), (LOADS[1], 128), (LOADS[1], 256)]
        .into_iter()
        .enumerate()
    {
        let z = surface(n);
        let e0 = periodic(&z, n, 0.0, p0);
        let n0 = non_periodic(&z, n, 0.0, p0);
        println!("\np0 = {p0} Pa, {n}^2 cells");
        println!("| L/(v tau) | v tau / a | v [m/s] | mu periodic | mu non-periodic | rel. diff mu | A/A0 periodic | A/A0 non-periodic | rel. diff A |");
        println!("|---|---|---|---|---|---|---|---|---|");
        println!(
            "| inf (v = 0) | 0 | 0 | {:.2e} | {:.2e} | - | {:.5} | {:.5} | {:.2} % |",
            e0.mu,
            n0.mu,
            e0.area,
            n0.area,
            100.0 * rel(e0.area, n0.area)
        );
        let mut rows = Vec::new();
        for &r in &ratios {
            let speed = LENGTH / (r * TAU);
            let p = periodic(&z, n, speed, p0);
            let q = non_periodic(&z, n, speed, p0);
            println!(
                "| {r} | {:.2} | {speed:.4} | {:.4e} | {:.4e} | {:.2} % | {:.5} | {:.5} | {:.2} % |",
                n as f64 / r,
                p.mu,
                q.mu,
                100.0 * rel(p.mu, q.mu),
                p.area,
                q.area,
                100.0 * rel(p.area, q.area)
            );
            rows.push((r, p, q));
        }
        if n != 256 {
            continue;
        }
        let pts = |f: &dyn Fn(&(f64, Outcome, Outcome)) -> f64| -> Vec<(f64, f64)> {
            rows.iter().map(|t| (t.0, f(t))).collect()
        };
        series.push(Series::line(
            format!("periodic, {p0} Pa"),
            pts(&|t| t.1.mu),
            c,
        ));
        series.push(Series::points(
            format!("non-periodic, {p0} Pa"),
            pts(&|t| t.2.mu),
            c,
        ));
    }
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/periodic-vs-nonperiodic.png");
    std::fs::create_dir_all(path.parent().unwrap()).unwrap();
    xy_chart(
        &path,
        &XyChart {
            title: "Periodic vs non-periodic, same surface, 256^2".into(),
            x_label: "L / (v tau)".into(),
            y_label: "friction coefficient mu".into(),
            log_x: true,
            log_y: true,
            series,
        },
    )
    .unwrap();
}
