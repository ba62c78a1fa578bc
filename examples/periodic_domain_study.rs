//! Regenerates the periodic vs non-periodic domain-size study of
//! docs/periodic-vs-nonperiodic.md (table on stdout, plot in docs/):
//! `cargo run --release --example periodic_domain_study` (about a minute).

#[path = "../tests/common/mod.rs"]
mod common;

use std::path::Path;

use common::domain::*;
use viscoslide::internals::plot::{xy_chart, Series, XyChart};

fn main() {
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
