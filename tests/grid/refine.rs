//! Refinement studies: a case with a known answer at every level (periodic
//! sinusoid in full contact), the Richardson estimator on synthetic
//! sequences, the prolongation between levels, the resolution warning of
//! every solve, and `viscoslide refine` end to end with its one-line errors.

use crate::common;

use std::f64::consts::TAU;
use std::path::Path;
use std::process::Command;

use viscoslide::config::Formulation;
use viscoslide::internals::solver::{Control, Silent, SolverParams};
use viscoslide::problem::{Executor, Problem};
use viscoslide::refine::{
    observed_order, refine_problems, richardson, Quiet, RefineParams, RichardsonParams, Verdict,
};
use viscoslide::surface::{GenerateParams, HeightMap, Normalisation, UpperCutoff};

/// `g = h0 (1 - cos k x)` on an `n x n/4` periodic cell of side 1 cm,
/// pressed hard enough for full contact at the loss peak of the paper's
/// material. Returns the problem and the closed-form friction
/// `k^2 h0^2 E2(k v) / (4 (1 - nu^2) p0)` (physics.md section 9, check 2).
fn sinusoid(n: usize) -> (Problem, f64) {
    let material = common::paper_material();
    let (length, h0) = (0.01, 1e-5);
    let k = TAU / length;
    let a = length / n as f64;
    let ny = n / 4;
    let heights: Vec<f64> = (0..n * ny)
        .map(|c| h0 * (k * ((c / ny) as f64 + 0.5) * a).cos())
        .collect();
    let surface = HeightMap::new(n, ny, length, heights).unwrap();
    let e_inf = material.spectrum.glassy_modulus;
    let p0 = 2.0 * k * h0 * e_inf / (2.0 * material.composite_factor());
    // Loss peak of the standard linear solid: omega tau = E_inf / E0.
    let speed = 3.0 / 0.01 / k;
    let e2 = material.spectrum.modulus(k * speed).im;
    let exact = k * k * h0 * h0 * e2 / (4.0 * material.composite_factor() * p0);
    let load = p0 * length * length / 4.0;
    let problem = Problem::new(material, surface, Control::Load(load), speed)
        .with_formulation(Formulation::Periodic)
        .with_solver_params(SolverParams {
            tolerance: 1e-10,
            ..Default::default()
        });
    (problem, exact)
}

/// Every level of a full-contact sinusoid has the closed-form friction (the
/// grid samples the single mode exactly, the periodic multiplier is the
/// continuous one): 1e-7 relative at 16, 32 and 64 cells per wavelength,
/// full contact everywhere, and the study calls the sequence converged.
#[test]
fn full_contact_sinusoid_agrees_at_every_level() {
    let levels = [16, 32, 64];
    let problems: Vec<Problem> = levels.iter().map(|&n| sinusoid(n).0).collect();
    let exact = sinusoid(16).1;
    let report = refine_problems(
        &problems,
        &Executor::Cpu,
        &RefineParams {
            warm_start: true,
            ..RefineParams::new(levels.to_vec())
        },
        &mut Quiet,
    )
    .unwrap();
    assert_eq!(report.levels.len(), 3);
    for (l, n) in report.levels.iter().zip(levels) {
        assert_eq!(l.n, n);
        let rel = (l.friction_coefficient - exact).abs() / exact;
        println!(
            "n = {n}: mu = {:.12e}, exact {exact:.12e}, rel {rel:.1e}, {} matvecs, warm {}",
            l.friction_coefficient, l.matvecs, l.warm_started
        );
        assert!(
            rel < 1e-7,
            "n = {n}: mu = {}, exact {exact}",
            l.friction_coefficient
        );
        let rel_d = (l.friction_coefficient_dissipation - exact).abs() / exact;
        assert!(rel_d < 1e-7, "n = {n}: dissipation route {rel_d:e}");
        assert_eq!(l.contact_area_fraction, 1.0);
        assert_eq!(l.warm_started, n != 16);
    }
    assert_eq!(
        report.friction.verdict,
        Verdict::Converged,
        "{:?}",
        report.friction
    );
    assert_eq!(report.area.verdict, Verdict::Converged);
    let limit = report.friction.extrapolated.unwrap();
    assert!((limit - exact).abs() < 1e-7 * exact);
}

/// Synthetic `f(h) = f* + C h^p`: order and limit recovered exactly, for
/// ratio-2 grids (`p = log2`) and for other ratios.
#[test]
fn richardson_recovers_a_known_order_and_limit() {
    let params = RichardsonParams::default();
    for cells in [[512.0, 1024.0, 2048.0], [100.0, 150.0, 330.0]] {
        let h: Vec<f64> = cells.iter().map(|n| 0.01 / n).collect();
        for (limit, c, p) in [(0.23, -40.0, 1.0), (0.05, 3e3, 2.0), (1.0, 0.5, 0.75)] {
            let f: Vec<f64> = h.iter().map(|h| limit + c * h.powf(p)).collect();
            let r = richardson(&h, &f, &params);
            assert_eq!(r.verdict, Verdict::Asymptotic, "{r:?}");
            assert_eq!(r.asymptotic, Some(true));
            let po = r.observed_order.unwrap();
            assert!((po - p).abs() < 1e-9 * p, "{cells:?}: order {po} != {p}");
            let e = r.extrapolated.unwrap();
            assert!(
                (e - limit).abs() < 1e-12 * limit.abs().max(1.0),
                "{e} != {limit}"
            );
            // The error estimate is the distance of the finest level to the limit.
            let true_error = (f[2] - limit).abs();
            assert!((r.error_estimate - true_error).abs() < 1e-9 * true_error);
        }
    }
    // The plain formula for ratio 2.
    let p = observed_order([4.0, 2.0, 1.0], [1.0 + 16.0, 1.0 + 4.0, 1.0 + 1.0]).unwrap();
    assert!((p - 2.0).abs() < 1e-14);
}

/// The experiment's measured sequence (issue 16: 0.206, 0.238, 0.227 at
/// 512, 1024, 2048) is non-monotone: flagged, no extrapolation; so are an
/// order outside 0.5..4 and growing changes.
#[test]
fn non_asymptotic_sequences_are_flagged() {
    let params = RichardsonParams::default();
    let h = [0.01 / 512.0, 0.01 / 1024.0, 0.01 / 2048.0];
    let r = richardson(&h, &[0.2061, 0.2380, 0.2267], &params);
    assert_eq!(r.verdict, Verdict::NotAsymptotic);
    assert_eq!(r.asymptotic, Some(false));
    assert_eq!(r.extrapolated, None);
    assert!(
        r.message.contains("NOT in the asymptotic range"),
        "{}",
        r.message
    );
    assert!(r.message.contains("non-monotone"), "{}", r.message);
    assert!((r.error_estimate - 0.0319).abs() < 1e-12);
    // Four levels: the verdict is the finest three's, the orders are all listed.
    let r = richardson(
        &[8.0, 4.0, 2.0, 1.0],
        &[0.9, 1.0 + 16.0, 1.0 + 4.0, 1.0 + 1.0],
        &params,
    );
    assert_eq!(r.verdict, Verdict::Asymptotic);
    assert_eq!(r.orders.len(), 2);
    assert!(r.orders[0].is_none());
    let r = richardson(
        &[4.0, 2.0, 1.0],
        &[1.0, 1.0 - 0.1, 1.0 - 0.1 - 0.1 / 64.0],
        &params,
    );
    assert_eq!(r.verdict, Verdict::NotAsymptotic, "order 6: {r:?}");
    let r = richardson(&[4.0, 2.0, 1.0], &[1.0, 1.01, 1.03], &params);
    assert_eq!(r.verdict, Verdict::NotAsymptotic, "growing: {r:?}");
    // Two levels: the order is assumed and said so.
    let r = richardson(&[2.0, 1.0], &[0.2061, 0.2380], &params);
    assert_eq!(r.verdict, Verdict::AssumedOrder);
    assert_eq!(r.asymptotic, None);
    assert_eq!(r.order_used, Some(1.0));
    assert!((r.extrapolated.unwrap() - (0.2380 + 0.0319)).abs() < 1e-12);
}

fn rough(n: usize) -> Problem {
    let surface = GenerateParams {
        nx: n,
        ny: n,
        upper: UpperCutoff::Scales(16.0),
        normalisation: Normalisation::RmsSlope(0.02),
        seed: 3,
        ..Default::default()
    };
    Problem::generated(
        common::paper_material(),
        surface,
        Control::Load(0.3),
        0.0117,
    )
    .unwrap()
}

/// A coarse solution prolonged to the next grid carries the load, keeps
/// the indenter's position and is a start only: the warm and cold solves of
/// the fine grid agree.
#[test]
fn prolonged_start_carries_the_load_and_changes_only_the_path() {
    let coarse = rough(32);
    let fine = coarse.with_grid(64).unwrap();
    let sc = coarse.solve(&Executor::Cpu, &mut Silent).unwrap();
    let start = fine.prolong(&coarse, &sc).unwrap();
    let a = fine.surface.cell_size;
    assert_eq!(start.pressure.len(), 64 * 64);
    let load: f64 = a * a * start.pressure.iter().sum::<f64>();
    assert!((load - 0.3).abs() < 1e-12 * 0.3, "load {load}");
    assert!(start
        .pressure
        .iter()
        .zip(&start.contact)
        .all(|(&p, &m)| p >= 0.0 && (m > 0.5 || p == 0.0)));
    let zmax = |p: &Problem| p.surface.heights.iter().cloned().fold(f64::MIN, f64::max);
    let shift = start.approach - sc.fields.approach;
    assert!((shift - (zmax(&fine) - zmax(&coarse))).abs() < 1e-18);
    let warm = fine
        .solve_from(&Executor::Cpu, Some(&start), &mut Silent)
        .unwrap();
    let cold = fine.solve(&Executor::Cpu, &mut Silent).unwrap();
    assert_eq!(warm.fields.contact, cold.fields.contact);
    let rel =
        (warm.friction_coefficient - cold.friction_coefficient).abs() / cold.friction_coefficient;
    assert!(rel < 1e-6, "warm and cold friction differ by {rel:e}");
    println!(
        "64^2: warm start {} matvecs, cold {}",
        warm.info.matvecs, cold.info.matvecs
    );
}

/// Every solve states its cells per shortest wavelength and warns below 4.
#[test]
fn solves_state_their_resolution_and_warn_below_four_cells() {
    let coarse = rough(32);
    assert_eq!(coarse.cells_per_shortest_wavelength(), Some(2.0));
    let s = coarse.solve(&Executor::Cpu, &mut Silent).unwrap();
    let summary = s.summary();
    assert_eq!(summary["cells_per_shortest_wavelength"], 2.0);
    let warnings = summary["warnings"].as_array().unwrap();
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    assert!(warnings[0].as_str().unwrap().contains("below 4"));
    let fine = coarse.with_grid(64).unwrap();
    assert_eq!(fine.cells_per_shortest_wavelength(), Some(4.0));
    assert!(fine.resolution_warning().is_none());
    // A surface given as values: the grid's Nyquist wavelength, 2 cells.
    let given = Problem::new(
        common::paper_material(),
        coarse.surface.clone(),
        Control::Load(0.3),
        0.0117,
    );
    assert_eq!(given.cells_per_shortest_wavelength(), Some(2.0));
    assert!(given.resolution_warning().unwrap().contains("Nyquist"));
}

fn cli(dir: &Path, args: &[&str]) -> (bool, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_viscoslide"))
        .arg("refine")
        .arg(Path::new(env!("CARGO_MANIFEST_DIR")).join("configs/default.toml"))
        .args([
            "--backend",
            "cpu",
            "--set",
            "surface.generate.scales=16",
            "--out",
        ])
        .arg(dir.join("out"))
        .args(args)
        .output()
        .unwrap();
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn refine_cli_writes_the_report_with_the_fixed_keys() {
    let tmp = tempfile::tempdir().unwrap();
    let (ok, stdout, stderr) = cli(tmp.path(), &["--levels", "32,64,128"]);
    assert!(ok, "{stderr}");
    for k in 1..=3 {
        assert!(stderr.contains(&format!("level {k}/3")), "{stderr}");
    }
    assert!(
        stderr.contains("warning:") && stderr.contains("below 4"),
        "{stderr}"
    );
    assert!(stdout.contains("friction coefficient"), "{stdout}");
    let out = tmp.path().join("out");
    assert!(out.join("refine.png").is_file());
    let doc: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("refine.json")).unwrap()).unwrap();
    let levels = doc["levels"].as_array().unwrap();
    assert_eq!(levels.len(), 3);
    for (l, n) in levels.iter().zip([32, 64, 128]) {
        assert_eq!(l["n"], n);
        for key in [
            "cells_per_shortest_wavelength",
            "friction_coefficient",
            "friction_coefficient_dissipation",
            "contact_area_fraction",
            "matvecs",
            "wall_time_s",
        ] {
            assert!(l[key].is_number(), "level {n}: {key} in {l}");
        }
    }
    assert_eq!(levels[0]["cells_per_shortest_wavelength"], 2.0);
    assert_eq!(levels[2]["cells_per_shortest_wavelength"], 8.0);
    for q in ["friction_coefficient", "contact_area_fraction"] {
        let r = &doc["richardson"][q];
        for key in [
            "verdict",
            "asymptotic",
            "observed_order",
            "extrapolated",
            "error_estimate",
            "message",
        ] {
            assert!(r.get(key).is_some(), "{q}: {key} missing in {r}");
        }
    }
    assert_eq!(doc["warm_start"], false, "the cascade is the default start");
    assert_eq!(doc["seed"], 1);
}

/// Bad level lists: one line on stderr, a failure status, nothing written.
#[test]
fn bad_levels_fail_in_one_line_and_write_nothing() {
    for (levels, expect) in [
        ("64,32", "coarse to fine"),
        ("32,32,64", "twice"),
        ("64", "at least two"),
        ("32,x", "not a grid size"),
        ("4,32", "at least 8"),
        ("32,64,3000000", "memory"),
    ] {
        let tmp = tempfile::tempdir().unwrap();
        let (ok, _, stderr) = cli(tmp.path(), &["--levels", levels]);
        assert!(!ok, "{levels} accepted");
        let lines: Vec<&str> = stderr
            .lines()
            .filter(|l| !l.starts_with("backend:"))
            .collect();
        assert_eq!(lines.len(), 1, "{levels}: {stderr}");
        assert!(
            lines[0].starts_with("error:") && lines[0].contains(expect),
            "{levels}: {stderr}"
        );
        assert!(!tmp.path().join("out").exists(), "{levels}: output written");
    }
}

/// Under approach control the indenter keeps its place on another grid:
/// the approach (measured from the highest summit) grows by the rise of
/// the summit, and a well-resolved surface carries nearly the same load.
#[test]
fn with_grid_keeps_the_indenter_in_place_under_approach_control() {
    let surface = |n: usize| GenerateParams {
        nx: n,
        ny: n,
        upper: UpperCutoff::Scales(8.0),
        normalisation: Normalisation::RmsSlope(0.02),
        seed: 5,
        ..Default::default()
    };
    let d = 2e-6;
    let coarse = Problem::generated(
        common::paper_material(),
        surface(64),
        Control::Approach(d),
        0.0117,
    )
    .unwrap();
    let fine = coarse.with_grid(128).unwrap();
    let top = |p: &Problem| p.surface.heights.iter().cloned().fold(f64::MIN, f64::max);
    let rise = top(&fine) - top(&coarse);
    assert!(
        rise > 0.0,
        "sampling the same modes at more points finds a higher summit"
    );
    match fine.control {
        Control::Approach(df) => assert!((df - (d + rise)).abs() <= 1e-15, "{df} vs {d} + {rise}"),
        other => panic!("{other:?}"),
    }
    let load = |p: &Problem| {
        let s = p.solve(&Executor::Cpu, &mut Silent).unwrap();
        s.fields.pressure.iter().sum::<f64>() * p.surface.cell_size.powi(2)
    };
    let (fc, ff) = (load(&coarse), load(&fine));
    println!("load on 64^2 {fc:.4e} N, on 128^2 {ff:.4e} N, summit rise {rise:.3e} m");
    assert!((ff / fc - 1.0).abs() < 0.05, "{fc} vs {ff}");
}

/// A level keeps the map's side along y exactly: `n ny / nx` cells along y
/// must be whole, else the level would be another map (and, under a
/// prescribed load, another nominal pressure). Refused before any solve.
#[test]
fn a_level_that_cannot_keep_the_side_along_y_is_refused() {
    let surface = GenerateParams {
        nx: 32,
        ny: 24,
        upper: UpperCutoff::Scales(4.0),
        normalisation: Normalisation::RmsSlope(0.02),
        seed: 5,
        ..Default::default()
    };
    let p = Problem::generated(
        common::paper_material(),
        surface,
        Control::Load(0.3),
        0.0117,
    )
    .unwrap();
    let ok = p.with_grid(16).unwrap();
    assert_eq!((ok.surface.nx, ok.surface.ny), (16, 12));
    assert_eq!(ok.surface.length_y(), p.surface.length_y());
    let err = p.with_grid(22).unwrap_err().to_string();
    assert!(
        err.contains("16.500 cells along y") && err.contains("multiple of 4"),
        "{err}"
    );

    let tmp = tempfile::tempdir().unwrap();
    let (ok, _, stderr) = cli(
        tmp.path(),
        &["--set", "surface.generate.ny=192", "--levels", "64,66"],
    );
    assert!(!ok, "the 66-cell level was solved on a rounded grid");
    let lines: Vec<&str> = stderr
        .lines()
        .filter(|l| !l.starts_with("backend:"))
        .collect();
    assert_eq!(lines.len(), 1, "{stderr}");
    assert!(
        lines[0].starts_with("error: invalid argument: --levels 66: 66 cells"),
        "{stderr}"
    );
    assert!(!tmp.path().join("out").exists());
}
