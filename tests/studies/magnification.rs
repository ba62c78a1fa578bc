//! Magnification studies (physics.md section 12): every level is exactly the
//! surface and the solve `viscoslide solve` makes of its reported keys, the
//! PSD is the same at every level (same `C0`, same Fourier modes), Persson's
//! theory per level is its own integral over the truncated PSD, runs resume
//! and shard like sweeps, and a refused study writes nothing.

use std::f64::consts::PI;
use std::path::{Path, PathBuf};
use std::process::Command;

use num_complex::Complex64;
use serde_json::Value;
use viscoslide::config;
use viscoslide::internals::solver::Silent;
use viscoslide::magnification::{
    self, LevelResult, LevelSpec, LevelSurface, MagnificationParams, Quiet, Study,
};
use viscoslide::problem::{Executor, Problem, Solution};
use viscoslide::surface::{generate_with_target, HeightMap};
use viscoslide::sweep::Shard;

/// SLS of the paper (Fig. 1), 8 scales from q_L = 2 pi / L, 3 kPa: levels
/// at 16 and 32 cells are solved in milliseconds.
const CONFIG: &str = r#"
[material]
model = "sls"
relaxed_modulus = 3.3333333333333335e6
glassy_modulus = 1.0e7
creep_time = 0.01

[surface.generate]
n = 64
length = 0.01
hurst = 0.8
q1 = 5026.548245743669      # 8 q_L
rms_slope = 0.02
seed = 3

[loading]
mean_pressure = 3.0e3
speed = 0.01

[solver]
formulation = "periodic"
"#;

fn write_config(dir: &Path, text: &str) -> PathBuf {
    std::fs::create_dir_all(dir).unwrap();
    let p = dir.join("study.toml");
    std::fs::write(&p, text).unwrap();
    p
}

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("viscoslide-mag-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs().max(1e-300)
}

/// A level against the separate `solve` of its keys. Identical inputs,
/// identical arithmetic: only the order of floating-point sums inside
/// threaded code may differ, far below 1e-9.
fn assert_level_is_the_solve(l: &LevelResult, solution: &Solution) {
    for (a, b, what) in [
        (l.friction_coefficient, solution.friction_coefficient, "mu"),
        (
            l.friction_coefficient_dissipation,
            solution.friction_coefficient_dissipation,
            "mu (dissipation)",
        ),
        (
            l.contact_area_fraction,
            solution.stats.contact_area_fraction,
            "A/A0",
        ),
    ] {
        assert!(rel(a, b) < 1e-9, "q1 = {}: {what} {a} vs solve {b}", l.q1);
    }
    assert_eq!(l.matvecs, solution.info.matvecs);
}

/// A level's Persson friction and area against the independent integral
/// (`brute_force`), to 1e-6 (the tolerance is justified at its callers).
fn assert_persson_is(l: &LevelResult, mu: f64, area: f64) {
    assert!(
        rel(l.persson_friction_coefficient, mu) < 1e-6,
        "q1 = {}: mu {} vs {mu}",
        l.q1,
        l.persson_friction_coefficient
    );
    assert!(
        rel(l.persson_contact_area_fraction, area) < 1e-6,
        "q1 = {}: A {} vs {area}",
        l.q1,
        l.persson_contact_area_fraction
    );
}

fn ql() -> f64 {
    2.0 * PI / 0.01
}

fn study(path: &Path, q1: Vec<f64>) -> Study {
    let cfg = config::load(path, &[]).unwrap();
    Study::new(&cfg, MagnificationParams::new(LevelSpec::Q1(q1))).unwrap()
}

#[test]
fn a_level_is_the_separate_solve_of_its_reported_keys() {
    let dir = tmp("identity");
    let path = write_config(&dir, CONFIG);
    let s = study(&path, vec![3.0 * ql(), 5.0 * ql(), 8.0 * ql()]);
    let run = magnification::run(&s, &Executor::Cpu, None, Shard::ALL, &mut Quiet).unwrap();
    let report = run.report.unwrap();
    assert_eq!(report.levels.len(), 3);
    // The PSD is fixed by the config's rms slope over its whole band, so
    // the coarser levels are less steep.
    assert!(report.levels[0].rms_slope < report.levels[2].rms_slope);
    for l in &report.levels {
        assert!(l.cells_per_shortest_wavelength >= 4.0);
        // What a user does with the table: solve with q1, n and rms_slope set.
        let sets = vec![
            format!("surface.generate.q1={:?}", l.q1),
            format!("surface.generate.n={}", l.n),
            format!("surface.generate.rms_slope={:?}", l.rms_slope),
        ];
        let cfg = config::load(&path, &sets).unwrap();
        let problem = Problem::from_config(&cfg).unwrap();
        let solution = problem.solve(&Executor::Cpu, &mut Silent).unwrap();
        assert_level_is_the_solve(l, &solution);
    }
    // The finest level at the config's own q1 carries the config's rms
    // slope in the continuum (C0 is defined there).
    let top = &s.levels[2];
    assert!(rel(top.rms_slope_continuum, 0.02) < 1e-12);
    // The lattice sum approximates the integral: a few percent on 8 scales.
    assert!(rel(top.rms_slope, 0.02) < 0.1, "{}", top.rms_slope);
    let _ = std::fs::remove_dir_all(&dir);
}

/// The Fourier coefficient `mean(h exp(-i q.x))` of a map at mode `(kx, ky)`.
fn mode(map: &HeightMap, kx: i64, ky: i64) -> Complex64 {
    let mut sum = Complex64::new(0.0, 0.0);
    for i in 0..map.nx {
        for j in 0..map.ny {
            let phase = -2.0
                * PI
                * (kx as f64 * i as f64 / map.nx as f64 + ky as f64 * j as f64 / map.ny as f64);
            sum += map.heights[i * map.ny + j] * Complex64::from_polar(1.0, phase);
        }
    }
    sum / (map.nx * map.ny) as f64
}

#[test]
fn every_level_holds_the_same_psd_and_the_same_fourier_modes() {
    let dir = tmp("modes");
    let path = write_config(&dir, CONFIG);
    let s = study(&path, vec![2.5 * ql(), 4.0 * ql(), 8.0 * ql()]);
    let mut maps = Vec::new();
    for level in &s.levels {
        let LevelSurface::SelfAffine(params) = &level.params else {
            panic!("a self-affine study")
        };
        let (map, target) = generate_with_target(params).unwrap();
        // The generator, given the reported rms slope, lands on the study's C0.
        assert!(
            rel(target.c0, s.psd.c0_m4().unwrap()) < 1e-12,
            "q1 = {}: C0 {} vs {}",
            level.q1,
            target.c0,
            s.psd.c0_m4().unwrap()
        );
        maps.push(map);
    }
    // Modes inside the coarsest band are the same at every level; modes
    // between two cut-offs exist only in the finer level.
    let (coarse, fine) = (&maps[0], &maps[2]);
    assert!(coarse.nx < fine.nx);
    for (kx, ky) in [(1, 0), (0, 2), (-2, 1), (1, -2)] {
        let (a, b) = (mode(coarse, kx, ky), mode(fine, kx, ky));
        assert!(a.norm() > 0.0);
        assert!(
            (a - b).norm() < 1e-10 * a.norm(),
            "mode ({kx}, {ky}): {a} vs {b}"
        );
    }
    let (a, b) = (mode(coarse, 3, 3), mode(fine, 3, 3)); // |k| = 4.24 > 2.5
    assert!(a.norm() < 1e-12 * b.norm() && b.norm() > 0.0);
    let _ = std::fs::remove_dir_all(&dir);
}

/// Persson's theory written independently of the module: the SLS modulus in
/// closed form, the trapezoidal rule over the full period in phi (spectrally
/// accurate for a periodic integrand) and in ln q on a fine grid, the
/// cumulative trapezoid for G. The PSD is `C0 (q / q_L)^(-2(H+1))` on
/// `[q_L, q1]` (no roll-off), smooth in ln q inside the band.
fn brute_force(c0: f64, hurst: f64, q1: f64, sigma0: f64, v: f64) -> (f64, f64) {
    let (e0, einf, tau, nu) = (1e7 / 3.0, 1e7, 0.01, 0.5);
    let modulus = |w: f64| {
        let j = Complex64::new(1.0 / einf, 0.0)
            + (1.0 / e0 - 1.0 / einf) / Complex64::new(1.0, w * tau);
        1.0 / j
    };
    let s = (1.0 - nu * nu) * sigma0;
    let m = 512;
    let angular = |q: f64| {
        let (mut f, mut k) = (0.0, 0.0);
        for i in 0..m {
            let phi = 2.0 * PI * i as f64 / m as f64;
            let e = modulus(q * v * phi.cos()) / s;
            f += phi.cos() * e.im;
            k += e.norm_sqr();
        }
        let h = 2.0 * PI / m as f64;
        (f * h, k * h)
    };
    let (a, b) = (ql().ln(), q1.ln());
    let n = 20_000;
    let dt = (b - a) / n as f64;
    let (mut g, mut mu) = (0.0, 0.0);
    let mut prev: Option<(f64, f64)> = None;
    for i in 0..=n {
        let q = (a + dt * i as f64).exp();
        let c = c0 * (q / ql()).powf(-2.0 * (hurst + 1.0));
        let (f, k) = angular(q);
        // dq = q dt.
        let dg = q.powi(4) * c * k / 8.0;
        if let Some((pg, _)) = prev {
            g += 0.5 * dt * (pg + dg);
        }
        let p = if g > 0.0 {
            libm::erf(1.0 / (2.0 * g.sqrt()))
        } else {
            1.0
        };
        let dmu = 0.5 * q.powi(4) * c * p * f;
        if let Some((_, pm)) = prev {
            mu += 0.5 * dt * (pm + dmu);
        }
        prev = Some((dg, dmu));
    }
    (mu, libm::erf(1.0 / (2.0 * g.sqrt())))
}

#[test]
fn persson_per_level_is_its_own_integral_over_the_truncated_psd() {
    let dir = tmp("persson");
    let path = write_config(&dir, CONFIG);
    let s = study(&path, vec![2.0 * ql(), 4.0 * ql(), 8.0 * ql()]);
    let run = magnification::run(&s, &Executor::Cpu, None, Shard::ALL, &mut Quiet).unwrap();
    let report = run.report.unwrap();
    for l in &report.levels {
        let (mu, area) = brute_force(s.psd.c0_m4().unwrap(), 0.8, l.q1, 3.0e3, 0.01);
        // The module's quadrature is good to about 1e-9; the brute force's
        // trapezoid in ln q (2e4 steps over at most ln 8) to about 1e-8.
        assert_persson_is(l, mu, area);
    }
    // Friction grows and area falls with the cut-off (physics.md section 12).
    let theory: Vec<(f64, f64)> = report
        .levels
        .iter()
        .map(|l| {
            (
                l.persson_friction_coefficient,
                l.persson_contact_area_fraction,
            )
        })
        .collect();
    assert!(
        theory
            .windows(2)
            .all(|w| w[1].0 > w[0].0 && w[1].1 < w[0].1),
        "{theory:?}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

fn viscoslide(args: &[&str]) -> (bool, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_viscoslide"))
        .args(args)
        .output()
        .unwrap();
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

fn points(dir: &Path) -> Vec<(String, std::time::SystemTime)> {
    let Ok(rd) = std::fs::read_dir(dir.join("points")) else {
        return Vec::new();
    };
    let mut v: Vec<_> = rd
        .map(|e| e.unwrap())
        .map(|e| {
            (
                e.file_name().to_string_lossy().into_owned(),
                e.metadata().unwrap().modified().unwrap(),
            )
        })
        .collect();
    v.sort();
    v
}

#[test]
fn shards_resume_and_the_report_match_one_run() {
    let dir = tmp("shards");
    let path = write_config(&dir, CONFIG);
    let cfg = path.to_str().unwrap();
    let scales = "--scales=3,5,8";
    let speeds = "--speeds=0.003,0.01";
    let one = dir.join("one");
    let (ok, _, err) = viscoslide(&[
        "magnification",
        cfg,
        scales,
        speeds,
        "--backend",
        "cpu",
        "--out",
        one.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    let json: Value =
        serde_json::from_str(&std::fs::read_to_string(one.join("magnification.json")).unwrap())
            .unwrap();
    assert_eq!(json["levels"].as_array().unwrap().len(), 6);
    assert!(json["speed"].is_null(), "two speeds: no single speed");
    for key in [
        "q1",
        "n",
        "cells_per_shortest_wavelength",
        "rms_height",
        "rms_slope",
        "friction_coefficient",
        "friction_coefficient_dissipation",
        "contact_area_fraction",
        "persson_friction_coefficient",
        "persson_contact_area_fraction",
        "matvecs",
        "wall_time_s",
        "speed",
    ] {
        assert!(
            json["levels"][0].get(key).is_some(),
            "levels[0] lacks {key}"
        );
    }
    assert!(json["warnings"].is_array());
    assert!(one.join("magnification.csv").is_file() && one.join("magnification.png").is_file());
    let csv = std::fs::read_to_string(one.join("magnification.csv")).unwrap();
    assert_eq!(csv.lines().count(), 7);

    // Two shards into another directory: the first leaves no report.
    let sharded = dir.join("sharded");
    let out = sharded.to_str().unwrap();
    let (ok, stdout, err) = viscoslide(&[
        "magnification",
        cfg,
        scales,
        speeds,
        "--backend",
        "cpu",
        "--shard",
        "0/2",
        "--out",
        out,
    ]);
    assert!(ok, "{err}");
    assert!(stdout.contains("3 in this shard"), "{stdout}");
    assert_eq!(points(&sharded).len(), 3);
    assert!(!sharded.join("magnification.json").exists());
    let before = points(&sharded);
    let (ok, _, err) = viscoslide(&[
        "magnification",
        cfg,
        scales,
        speeds,
        "--backend",
        "cpu",
        "--shard",
        "1/2",
        "--out",
        out,
    ]);
    assert!(ok, "{err}");
    assert_eq!(points(&sharded).len(), 6);
    // Resume: nothing solved again, the shard-0 points untouched.
    let (ok, stdout, err) = viscoslide(&[
        "magnification",
        cfg,
        scales,
        speeds,
        "--backend",
        "cpu",
        "--out",
        out,
    ]);
    assert!(ok, "{err}");
    assert!(stdout.contains("6 already done, 0 solved now"), "{stdout}");
    let after = points(&sharded);
    for p in &before {
        assert!(after.contains(p), "{} was rewritten", p.0);
    }
    let merged: Value =
        serde_json::from_str(&std::fs::read_to_string(sharded.join("magnification.json")).unwrap())
            .unwrap();
    for (a, b) in json["levels"]
        .as_array()
        .unwrap()
        .iter()
        .zip(merged["levels"].as_array().unwrap())
    {
        for key in [
            "q1",
            "friction_coefficient",
            "contact_area_fraction",
            "persson_friction_coefficient",
        ] {
            assert_eq!(a[key], b[key], "{key}");
        }
    }
    // Another study into the same directory is refused.
    let (ok, _, err) = viscoslide(&["magnification", cfg, "--scales=3,8", "--out", out]);
    assert!(!ok && err.contains("different configuration"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A study whose first point fails keeps its directory from no corrected
/// study: with no finished point, a run holding the directory alone
/// replaces its pin.
#[test]
fn a_study_that_finished_no_point_does_not_keep_its_directory() {
    let dir = tmp("no-point");
    let path = write_config(&dir, CONFIG);
    let cfg = path.to_str().unwrap();
    let out = dir.join("out");
    let o = out.to_str().unwrap();
    let study = [
        "magnification",
        cfg,
        "--scales=3,5",
        "--backend",
        "cpu",
        "--out",
        o,
    ];
    let failing = [&study[..], &["--set", "solver.max_matvecs=1"]].concat();
    let (ok, _, err) = viscoslide(&failing);
    assert!(!ok, "{err}");
    assert!(out.join("magnification.toml").is_file());
    assert!(points(&out).is_empty());
    let (ok, stdout, err) = viscoslide(&study);
    assert!(ok, "{err}");
    assert!(stdout.contains("0 already done, 2 solved now"), "{stdout}");
    assert!(out.join("magnification.json").is_file());
    let (ok, _, err) = viscoslide(&failing);
    assert!(!ok && err.contains("different configuration"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn refused_studies_write_nothing() {
    let dir = tmp("refusals");
    let path = write_config(&dir, CONFIG);
    let cfg = path.to_str().unwrap();
    let approach = write_config(
        &dir.join("approach"),
        &CONFIG.replace("mean_pressure = 3.0e3", "approach = 1e-6"),
    );
    let sphere = write_config(
        &dir.join("sphere"),
        r#"
[material]
model = "sls"
relaxed_modulus = 3.3333333333333335e6
glassy_modulus = 1.0e7
creep_time = 0.01
[surface.sphere]
n = 32
length = 0.01
radius = 0.01
[loading]
normal_load = 0.1
speed = 0.0
"#,
    );
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (vec![cfg, "--q1=5100"], "exceeds the configuration's q1"),
        (vec![cfg, "--q1=600"], "must exceed"),
        (vec![cfg, "--scales=4,2"], "increase strictly"),
        (vec![cfg, "--scales=4,x"], "not a finite number"),
        (
            vec![cfg, "--scales=4", "--cells-per-wavelength=1.5"],
            "(--cells-per-wavelength) must be at least 2",
        ),
        (vec![cfg, "--scales=4", "--speeds=0.1,-1"], ">= 0"),
        (vec![cfg], "exactly one of q1 (--q1"),
        (
            vec![approach.to_str().unwrap(), "--scales=4"],
            "prescribed load",
        ),
        (
            vec![sphere.to_str().unwrap(), "--scales=4"],
            "generated self-affine surface",
        ),
    ];
    for (args, want) in cases {
        let out = dir.join("out");
        let mut all = vec!["magnification"];
        all.extend(args.iter().copied());
        all.extend(["--out", out.to_str().unwrap()]);
        let (ok, _, err) = viscoslide(&all);
        assert!(!ok, "{args:?} was accepted");
        assert!(err.contains(want), "{args:?}: {err}");
        assert_eq!(
            err.trim().lines().count(),
            1,
            "{args:?}: one line, got {err}"
        );
        assert!(!out.exists(), "{args:?} created {}", out.display());
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_configs_own_grid_need_not_carry_its_q1() {
    // n = 8 reaches 4 q_L, the config's q1 is 8 q_L: a solve would refuse
    // it, a study plans its own grids and the same levels.
    let dir = tmp("owngrid");
    let coarse = write_config(&dir.join("a"), &CONFIG.replace("n = 64", "n = 8"));
    let fine = write_config(&dir.join("b"), CONFIG);
    let (a, b) = (
        study(&coarse, vec![3.0 * ql(), 8.0 * ql()]),
        study(&fine, vec![3.0 * ql(), 8.0 * ql()]),
    );
    assert_eq!(a.psd, b.psd);
    for (x, y) in a.levels.iter().zip(&b.levels) {
        assert_eq!((x.n, x.rms_slope), (y.n, y.rms_slope));
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The paper's SLS and loading of [`CONFIG`] on a surface synthesised from
/// a PSD table (`table.csv`, written by [`write_table_config`]).
const TABLE_CONFIG: &str = r#"
[material]
model = "sls"
relaxed_modulus = 3.3333333333333335e6
glassy_modulus = 1.0e7
creep_time = 0.01

[surface.generate]
n = 64
length = 0.01
psd = "table.csv"
seed = 3

[loading]
mean_pressure = 3.0e3
speed = 0.01

[solver]
formulation = "periodic"
"#;

/// `C0` of the power law `C0 (q / q_L)^(-2(H+1))`, H = 0.8, with rms slope
/// 0.02 over `[q_L, 8 q_L]` (continuum: `2 pi C0 q_L^3.6 (q1^0.4 - q_L^0.4) / 0.4`).
fn table_c0() -> f64 {
    let (ql, q1) = (ql(), 8.0 * ql());
    0.02f64.powi(2) * 0.4 / (2.0 * PI * ql.powf(3.6) * (q1.powf(0.4) - ql.powf(0.4)))
}

/// A config on a four-row table of the power law of [`table_c0`], from
/// below `q_L` to `8 q_L` (log-log interpolation is exact on a power law,
/// so [`brute_force`] is its integral).
fn write_table_config(dir: &Path) -> PathBuf {
    let path = write_config(dir, TABLE_CONFIG);
    let mut csv = String::from("q,C\n");
    for q in [300.0, 1.0e3, 3.0e3, 8.0 * ql()] {
        let c = table_c0() * (q / ql()).powf(-3.6);
        csv.push_str(&format!("{q:e},{c:e}\n"));
    }
    std::fs::write(dir.join("table.csv"), csv).unwrap();
    path
}

#[test]
fn a_table_level_is_the_separate_solve_with_q1_and_n() {
    let dir = tmp("table-identity");
    let path = write_table_config(&dir);
    let s = study(&path, vec![3.0 * ql(), 5.0 * ql(), 8.0 * ql()]);
    assert!(s.psd.c0_m4().is_none());
    let run = magnification::run(&s, &Executor::Cpu, None, Shard::ALL, &mut Quiet).unwrap();
    let report = run.report.unwrap();
    assert_eq!(report.levels.len(), 3);
    assert!(report.levels[0].rms_slope < report.levels[2].rms_slope);
    for (l, plan) in report.levels.iter().zip(&s.levels) {
        assert!(l.cells_per_shortest_wavelength >= 4.0);
        // A table has no amplitude key: q1 and n only.
        let sets = vec![
            format!("surface.generate.q1={:?}", l.q1),
            format!("surface.generate.n={}", l.n),
        ];
        let cfg = config::load(&path, &sets).unwrap();
        let problem = Problem::from_config(&cfg).unwrap();
        // The reported rms height is the map's (Parseval: round-off only).
        let h = &problem.surface.heights;
        let ms = h.iter().map(|v| v * v).sum::<f64>() / h.len() as f64;
        assert!(rel(l.rms_height, ms.sqrt()) < 1e-10, "q1 = {}", l.q1);
        // Persson's PSD of `solve` / `persson` is the level's truncated table.
        let (psd, kind) = problem.persson_psd().unwrap();
        assert_eq!(kind, "generated_table");
        for k in [0, 2] {
            assert!(rel(psd.moment(k), plan.psd.moment(k)) < 1e-12, "moment {k}");
        }
        assert!(rel(psd.q_max(), l.q1) < 1e-15);
        let solution = problem.solve(&Executor::Cpu, &mut Silent).unwrap();
        assert_level_is_the_solve(l, &solution);
        // Persson per level: the independent integral over the power law
        // the table holds, cut at q1 (tolerances as for the self-affine
        // study above).
        let (mu, area) = brute_force(table_c0(), 0.8, l.q1, 3.0e3, 0.01);
        assert_persson_is(l, mu, area);
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_q1_cut_of_the_table_synthesis_keeps_the_lower_modes_and_removes_the_upper() {
    let dir = tmp("table-cut");
    let path = write_table_config(&dir);
    let load = |sets: &[String]| {
        let cfg = config::load(&path, sets).unwrap();
        cfg.surface().unwrap().load(&cfg.base_dir).unwrap()
    };
    let n = ["surface.generate.n=32".to_string()];
    let full = load(&n);
    let q1 = 4.5 * ql();
    let cut = load(&[n[0].clone(), format!("surface.generate.q1={q1:?}")]);
    let big = full.heights.iter().map(|h| h.abs()).fold(0.0, f64::max);
    let (mut kept, mut removed) = (0, 0);
    for kx in -15i64..=16 {
        for ky in -15i64..=16 {
            let q = ql() * ((kx * kx + ky * ky) as f64).sqrt();
            let (a, b) = (mode(&full, kx, ky), mode(&cut, kx, ky));
            // The same amplitude and phase, through the same inverse FFT and
            // a direct sum: round-off only.
            if q <= q1 * (1.0 - 1e-12) {
                assert!((a - b).norm() <= 1e-12 * big, "({kx}, {ky}): {a} vs {b}");
                kept += usize::from(a.norm() > 1e-6 * big);
            } else if q > q1 * (1.0 + 1e-12) {
                assert!(b.norm() <= 1e-12 * big, "({kx}, {ky}) kept: {b}");
                removed += usize::from(a.norm() > 1e-6 * big);
            }
        }
    }
    assert!(kept > 40 && removed > 40, "{kept} kept, {removed} removed");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_table_level_above_the_table_is_refused() {
    let dir = tmp("table-refusal");
    let path = write_table_config(&dir);
    let out = dir.join("out");
    let q1 = format!("--q1={:e}", 9.0 * ql());
    let (ok, _, err) = viscoslide(&[
        "magnification",
        path.to_str().unwrap(),
        &q1,
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(!ok && err.contains("largest q of the PSD table"), "{err}");
    assert_eq!(err.trim().lines().count(), 1, "one line, got {err}");
    assert!(!out.exists());
    let _ = std::fs::remove_dir_all(&dir);
}

/// `magnification.json` states the temperature of the study's material and
/// its WLF shift factor (as `summary.json` does), `null` without WLF
/// constants.
#[test]
fn the_report_states_the_temperature_and_the_shift_factor() {
    let dir = tmp("shift");
    let with_wlf = CONFIG
        .replace(
            "creep_time = 0.01\n",
            "creep_time = 0.01\nwlf = [8.86, 101.6, 17.0]\n",
        )
        .replace("speed = 0.01\n", "speed = 0.01\ntemperature = 7.0\n");
    for (text, shift) in [(with_wlf.as_str(), true), (CONFIG, false)] {
        let path = write_config(&dir, text);
        let s = study(&path, vec![3.0 * ql(), 5.0 * ql()]);
        let run = magnification::run(&s, &Executor::Cpu, None, Shard::ALL, &mut Quiet).unwrap();
        let json = run.report.unwrap().to_json();
        if shift {
            let wlf = viscoslide::material::Wlf::new(8.86, 101.6, 17.0).unwrap();
            assert_eq!(json["temperature"].as_f64(), Some(7.0), "{json}");
            assert_eq!(json["reference_temperature"].as_f64(), Some(17.0));
            assert_eq!(
                json["shift_factor"].as_f64(),
                Some(wlf.shift_factor(7.0).unwrap())
            );
            assert!(json["shift_factor"].as_f64().unwrap() > 9.0);
        } else {
            for key in ["temperature", "shift_factor", "reference_temperature"] {
                assert!(json[key].is_null(), "{key}: {json}");
            }
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The levels are isothermal: a `[heating]` section is refused in one line
/// naming it and the fix, before anything is written; with heating
/// disabled the same study runs.
#[test]
fn a_study_with_heating_is_refused_naming_the_fix() {
    let dir = tmp("heating");
    let heated = format!(
        "{CONFIG}\n[heating]\nconductivity = 0.25\ndiffusivity = 1.16e-7\nblock_length = 0.01\n"
    );
    let path = write_config(&dir, &heated);
    let p = path.to_str().unwrap();
    let out = dir.join("out");
    let o = out.to_str().unwrap();
    let args = [
        "magnification",
        p,
        "--scales",
        "4,8",
        "--backend",
        "cpu",
        "--out",
        o,
    ];
    let (ok, _, err) = viscoslide(&args);
    assert!(!ok);
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(err.contains("[heating]"), "{err}");
    assert!(err.contains("--set heating.enabled=false"), "{err}");
    assert!(!out.exists(), "a refused study writes nothing");
    let (ok, _, err) = viscoslide(&[&args[..], &["--set", "heating.enabled=false"]].concat());
    assert!(ok, "{err}");
    assert!(out.join("magnification.json").exists());
    let _ = std::fs::remove_dir_all(&dir);
}
