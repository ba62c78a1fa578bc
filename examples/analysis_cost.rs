//! Wall-clock cost of each part of the analysis of one solve (friction
//! routes, contact statistics, Persson, the Section IV analysis and its
//! figures, the field files), for BENCHMARKS.md "Analysis cost".
//!
//! ```sh
//! cargo run --release --example analysis_cost -- CONFIG DIR [--set KEY=VALUE ...]
//! ```
//!
//! `DIR` holds the `pressure.npy`, `displacement.npy`, `contact.npy` and
//! `gap.npy` of a solve of `CONFIG` with the same overrides; nothing is
//! written into it (the figures go to a temporary directory).

use std::path::Path;
use std::time::Instant;
use viscoslide::response::{Grid, SlidingResponse};

use viscoslide::internals::analysis::{
    self, figures, AnalysisInputs, AnalysisParams, Connectivity,
};
use viscoslide::internals::solver::ContactSolution;
use viscoslide::io::npy;
use viscoslide::problem::Problem;
use viscoslide::surface::{psd_2d, HeightMap};

/// CPU time of this process (all threads) \[s\], from /proc (Linux; 0
/// elsewhere): on a shared machine it varies less than the wall clock.
fn cpu_s() -> f64 {
    let stat = std::fs::read_to_string("/proc/self/stat").unwrap_or_default();
    let fields: Vec<&str> = stat
        .rsplit_once(')')
        .map_or("", |(_, rest)| rest)
        .split_whitespace()
        .collect();
    let tick = |k: usize| {
        fields
            .get(k)
            .and_then(|v| v.parse::<f64>().ok())
            .unwrap_or(0.0)
    };
    // utime and stime are fields 14 and 15 of stat (11 and 12 after the name).
    (tick(11) + tick(12)) / 100.0
}

fn timed<T>(label: &str, f: impl FnOnce() -> T) -> T {
    let (t, c) = (Instant::now(), cpu_s());
    let v = f();
    println!(
        "{label:<34} {:>9.3} s wall {:>9.2} s cpu",
        t.elapsed().as_secs_f64(),
        cpu_s() - c
    );
    v
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.len() < 2 {
        eprintln!("usage: analysis_cost CONFIG DIR [--set KEY=VALUE ...]");
        std::process::exit(2);
    }
    let sets: Vec<String> = args[2..]
        .chunks(2)
        .filter(|c| c[0] == "--set" && c.len() == 2)
        .map(|c| c[1].clone())
        .collect();
    let cfg = viscoslide::config::load(Path::new(&args[0]), &sets).expect("config");
    let problem = Problem::from_config(&cfg).expect("problem");
    let dir = Path::new(&args[1]);
    let read = |n: &str| npy::read(dir.join(n)).expect(n).data;
    let (nx, ny, (a, a_y)) = (
        problem.surface.nx,
        problem.surface.ny,
        problem.surface.cell(),
    );
    let sol = ContactSolution {
        pressure: read("pressure.npy"),
        displacement: read("displacement.npy"),
        gap: read("gap.npy"),
        contact: read("contact.npy"),
        approach: 0.0,
    };
    println!("{nx} x {ny} cells, contact fraction {:.4}", {
        sol.contact.iter().filter(|&&c| c > 0.5).count() as f64 / (nx * ny) as f64
    });
    let (total, cpu0) = (Instant::now(), cpu_s());
    timed("contact statistics", || {
        analysis::contact_statistics(&sol.pressure, &sol.contact, nx, ny, (a, a_y))
    });
    timed("friction, both routes + stats", || {
        problem.friction_and_stats(&sol).expect("friction")
    });
    timed("  dissipation route alone", || {
        analysis::friction::friction_force_dissipation(
            &sol.pressure,
            &Grid::new(nx, ny, (a, a_y)).unwrap(),
            &SlidingResponse::new(
                &problem.material,
                problem.speed,
                problem.direction_rad,
                problem.layer.as_ref().copied(),
            )
            .unwrap(),
        )
    });
    timed("persson estimate", || problem.persson_estimate(1e5).is_ok());
    let params = AnalysisParams::default();
    let inputs = AnalysisInputs {
        nx,
        ny,
        cell_size: a,
        cell_size_y: a_y,
        displacement: &sol.displacement,
        contact: &sol.contact,
        pressure: &sol.pressure,
        scales: None,
        xi: None,
    };
    timed("  m2: psd + Eq. 11-13", || {
        let map = HeightMap::with_cells(nx, ny, a, a_y, sol.displacement.clone()).unwrap();
        let psd = psd_2d(&map, params.window).unwrap();
        analysis::deformed_anisotropy(&psd, 1.0, (nx.min(ny) / 2) as f64)
    });
    let spots = timed("  spots (4- and 8-connected)", || {
        let s = analysis::find_spots(&sol.contact, nx, ny, Connectivity::Four);
        analysis::find_spots(&sol.contact, nx, ny, Connectivity::Eight);
        s
    });
    let radius = {
        let (mut sw, mut sv) = (0.0, 0.0);
        for s in &spots {
            sw += s.cells as f64;
            sv += s.cells as f64 * s.major_variance();
        }
        1.5 * (4.0 * (sv / sw).sqrt()).max(2.0)
    };
    let spec = timed("  C_chi spectrum", || {
        analysis::chi_spectrum(&sol.contact, nx, ny, (a, a), radius)
    });
    timed("  C_chi contours + ellipses", || {
        for &l in &params.chi_levels {
            analysis::contour_level(&spec, l, params.rays);
        }
    });
    let report = timed("analyze (all of Section IV)", || {
        analysis::analyze(&inputs, &params).expect("analysis")
    });
    let tmp = std::env::temp_dir().join(format!("analysis_cost_{}", std::process::id()));
    std::fs::create_dir_all(&tmp).unwrap();
    let p = |n: &str| tmp.join(n);
    timed("  figure: contact map", || {
        figures::contact_map(&p("c.png"), &inputs, &report).unwrap()
    });
    timed("  figure: m2 polar", || {
        figures::m2_polar(&p("m.png"), &inputs, &report).unwrap()
    });
    timed("  figure: chi contours", || {
        figures::chi_contours(&p("x.png"), &inputs, &report).unwrap()
    });
    timed("  figure: pressure map", || {
        figures::field_map(&p("p.png"), &inputs, "p", &sol.pressure, "p").unwrap()
    });
    timed("  figure: spot areas", || {
        figures::spot_areas(&p("s.png"), &report).unwrap()
    });
    timed("npy encoding (4 fields)", || {
        for f in [&sol.pressure, &sol.displacement, &sol.gap, &sol.contact] {
            std::fs::write(p("f.npy"), npy::encode_f64(&[nx, ny], f)).unwrap();
        }
    });
    std::fs::remove_dir_all(&tmp).ok();
    println!(
        "{:<34} {:>9.3} s wall {:>9.2} s cpu",
        "total of the above",
        total.elapsed().as_secs_f64(),
        cpu_s() - cpu0
    );
}
