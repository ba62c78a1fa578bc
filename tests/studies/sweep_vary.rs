//! Sweeps over any config key (`[sweep.vary]`): each value applied as
//! `--set` applies it, crossed with the speed axis; the merged master
//! curve of a temperature sweep collapses exactly (physics.md section
//! 12); bad keys and values are refused in one line before anything is
//! written; a vary sweep resumes and shards like any sweep.

use std::path::Path;
use std::process::Command;

/// WLF constants chosen so that the shift factors are exact powers of
/// ten: `C1 = 2`, `C2 = 10 K`, `T_ref = 0 C` give `log10 a_T = -1` at
/// 10 C, so the reduced speeds `a_T v` of the two temperatures coincide
/// on a decade grid of speeds.
const CONFIG: &str = r#"
[material]
model = "sls"
relaxed_modulus = 3.3333333333333335e6
glassy_modulus = 1.0e7
creep_time = 0.01
wlf = [2.0, 10.0, 0.0]

[surface.generate]
n = 32
length = 0.01
hurst = 0.8
scales = 4
rms_slope = 0.02
seed = 1

[loading]
mean_pressure = 3000.0
speed = 1e-2

[solver]
formulation = "periodic"
tolerance = 1e-10

[analysis]
enabled = false

[sweep]
speed = [0.05, 0.5, 5.0]
include_static = false

[sweep.vary]
VARY
"#;

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

fn write_config(dir: &Path, vary: &str) -> String {
    let p = dir.join("vary.toml");
    std::fs::write(&p, CONFIG.replace("VARY", vary)).unwrap();
    p.display().to_string()
}

/// The rows of a CSV as maps from header to field.
fn read_csv(path: &Path) -> Vec<std::collections::HashMap<String, String>> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header: Vec<String> = lines.next().unwrap().split(',').map(String::from).collect();
    lines
        .map(|l| {
            let fields: Vec<&str> = l.split(',').collect();
            assert_eq!(fields.len(), header.len(), "{l}");
            header
                .iter()
                .cloned()
                .zip(fields.iter().map(|f| f.to_string()))
                .collect()
        })
        .collect()
}

fn num(row: &std::collections::HashMap<String, String>, key: &str) -> f64 {
    row[key]
        .parse()
        .unwrap_or_else(|_| panic!("{key} = {:?}", row[key]))
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// Three temperatures x three speeds: `sweep.csv` keeps the varied key,
/// the temperature, `a_T` and `a_T v` as columns; wherever two rows have
/// the same reduced speed their BEM friction (both routes), contact area
/// and Persson friction agree to 1e-9 relative (each is converged to
/// 1e-10; the problems differ only in where `a_T` multiplies). The
/// collapse is checked on the merged file, and the master curve drawn.
#[test]
fn temperature_sweep_collapses_onto_the_master_curve() {
    let dir = tempfile::tempdir().unwrap();
    let cfg = write_config(dir.path(), "\"loading.temperature\" = [0.0, 10.0, 20.0]");
    let out = dir.path().join("out");
    let (ok, stdout, err) = viscoslide(&["sweep", &cfg, "--out", out.to_str().unwrap()]);
    assert!(ok, "{err}");
    assert!(stdout.contains("9 points"), "{stdout}");
    assert!(out.join("master_curve.png").is_file());
    let rows = read_csv(&out.join("sweep.csv"));
    assert_eq!(rows.len(), 9);
    for r in &rows {
        let t = num(r, "loading.temperature");
        assert_eq!(num(r, "temperature_c"), t);
        // a_T written out independently: log10 a_T = -2 T / (10 + T).
        let a = 10f64.powf(-2.0 * t / (10.0 + t));
        // sweep.csv writes 9 significant digits.
        assert!(rel(num(r, "shift_factor"), a) < 1e-8);
        assert!(rel(num(r, "reduced_speed_m_s"), a * num(r, "speed_m_s")) < 1e-8);
    }
    let mut coincident = 0;
    for (i, a) in rows.iter().enumerate() {
        for b in &rows[i + 1..] {
            if rel(num(a, "reduced_speed_m_s"), num(b, "reduced_speed_m_s")) < 1e-8
                && num(a, "temperature_c") != num(b, "temperature_c")
            {
                coincident += 1;
                for key in [
                    "friction_mean",
                    "friction_dissipation_mean",
                    "area_fraction_mean",
                    "persson_friction",
                    "persson_area_fraction",
                ] {
                    let e = rel(num(a, key), num(b, key));
                    assert!(e < 1e-9, "{key}: {} vs {} ({e:.1e})", a[key], b[key]);
                }
            }
        }
    }
    // 0 C and 10 C share two reduced speeds (a_T = 1, 0.1).
    assert_eq!(coincident, 2);
    // And the curves are not flat: the collapse is not trivial.
    let mu: Vec<f64> = rows.iter().map(|r| num(r, "friction_mean")).collect();
    let (lo, hi) = mu
        .iter()
        .fold((f64::MAX, 0.0f64), |(l, h), &m| (l.min(m), h.max(m)));
    assert!(hi / lo > 1.2, "{mu:?}");
}

/// A varied surface key: each point equals the separate `solve` with the
/// same `--set` (the same code path), to the last digit written.
#[test]
fn a_varied_key_equals_the_separate_solve_with_set() {
    let dir = tempfile::tempdir().unwrap();
    let cfg = write_config(
        dir.path(),
        "\"surface.generate.q1\" = [1000.0, 1600.0]\n\"loading.direction_deg\" = [0.0, 30.0]",
    );
    let text = std::fs::read_to_string(&cfg)
        .unwrap()
        .replace("scales = 4\n", "")
        .replace("speed = [0.05, 0.5, 5.0]", "speed = [0.5]");
    std::fs::write(&cfg, text).unwrap();
    let out = dir.path().join("out");
    let (ok, _, err) = viscoslide(&["sweep", &cfg, "--out", out.to_str().unwrap()]);
    assert!(ok, "{err}");
    let rows = read_csv(&out.join("sweep.csv"));
    assert_eq!(rows.len(), 4);
    for r in &rows {
        let q1 = num(r, "surface.generate.q1");
        let dir_deg = num(r, "loading.direction_deg");
        let one = dir.path().join(format!("one_{q1}_{dir_deg}"));
        let (ok, _, err) = viscoslide(&[
            "solve",
            &cfg,
            "--set",
            &format!("surface.generate.q1={q1:?}"),
            "--set",
            &format!("loading.direction_deg={dir_deg:?}"),
            "--set",
            "loading.speed=0.5",
            "--out",
            one.to_str().unwrap(),
        ]);
        assert!(ok, "{err}");
        let s: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(one.join("summary.json")).unwrap())
                .unwrap();
        let mu = s["friction_coefficient"].as_f64().unwrap();
        // sweep.csv writes 9 significant digits.
        assert!(
            rel(num(r, "friction_mean"), mu) < 1e-8,
            "{} vs {mu}",
            r["friction_mean"]
        );
    }
    // q1 changes the answer (the key reached the surface).
    assert!(
        rel(
            num(&rows[0], "friction_mean"),
            num(&rows[2], "friction_mean")
        ) > 1e-3
    );
}

/// Unknown keys, values of the wrong type, keys the axes set, and a value
/// the material cannot take in any one combination: one line, and no
/// output directory.
#[test]
fn bad_vary_keys_and_values_are_refused_before_anything_is_written() {
    let dir = tempfile::tempdir().unwrap();
    for (vary, needle) in [
        ("\"loading.temprature\" = [7.0]", "temprature"),
        ("\"nosuch.key\" = [1.0]", "nosuch"),
        ("\"loading.temperature\" = [\"hot\"]", "loading.temperature"),
        ("\"loading.temperature\" = [17.0, -95.0]", "T_ref - C2"),
        ("\"loading.speed\" = [1.0]", "loading.speed"),
        ("\"loading.temperature\" = []", "empty"),
        ("\"layer.thickness\" = [-1.0]", "thickness"),
    ] {
        let cfg = write_config(dir.path(), vary);
        let out = dir.path().join("never");
        let (ok, _, err) = viscoslide(&["sweep", &cfg, "--out", out.to_str().unwrap()]);
        assert!(!ok, "{vary}");
        assert!(err.contains(needle), "{vary}: {err}");
        assert_eq!(err.trim().lines().count(), 1, "{vary}: {err}");
        assert!(!out.exists(), "{vary}: nothing written");
    }
}

/// A vary sweep stopped after three points resumes without solving them
/// again, and two shards merge to the same table as the whole run.
#[test]
fn a_vary_sweep_resumes_and_shards() {
    let dir = tempfile::tempdir().unwrap();
    let cfg = write_config(dir.path(), "\"loading.temperature\" = [0.0, 10.0]");
    let whole = dir.path().join("whole");
    let w = whole.to_str().unwrap();
    let (ok, stdout, err) = viscoslide(&["sweep", &cfg, "--out", w, "--limit", "3"]);
    assert!(ok, "{err}");
    assert!(stdout.contains("0 already done, 3 solved now"), "{stdout}");
    let (ok, stdout, err) = viscoslide(&["sweep", &cfg, "--out", w]);
    assert!(ok, "{err}");
    assert!(stdout.contains("3 already done, 3 solved now"), "{stdout}");
    let sharded = dir.path().join("sharded");
    let s = sharded.to_str().unwrap();
    for k in ["1/2", "0/2"] {
        let (ok, _, err) = viscoslide(&["sweep", &cfg, "--out", s, "--shard", k]);
        assert!(ok, "{err}");
    }
    assert!(
        !sharded.join("sweep.csv").exists(),
        "a shard does not merge"
    );
    let (ok, _, err) = viscoslide(&["merge", s]);
    assert!(ok, "{err}");
    let strip = |p: &Path| -> Vec<std::collections::HashMap<String, String>> {
        read_csv(&p.join("sweep.csv"))
    };
    let (a, b) = (strip(&whole), strip(&sharded));
    assert_eq!(a.len(), 6);
    for (x, y) in a.iter().zip(&b) {
        for key in [
            "loading.temperature",
            "speed_m_s",
            "friction_mean",
            "area_fraction_mean",
        ] {
            assert_eq!(x[key], y[key], "{key}");
        }
    }
    // Points 0..2 are the 0 C points (the vary values are outermost).
    let p: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(sharded.join("points/p0004.json")).unwrap())
            .unwrap();
    assert_eq!(
        p["point"]["vary"]["loading.temperature"],
        serde_json::json!(10.0)
    );
    assert_eq!(p["temperature"], serde_json::json!(10.0));
}

/// A point whose solve fails (one matvec allowed) ends the run with its
/// error, named by its settings on the line before; the points solved
/// before it are written and read back whole.
#[test]
fn a_point_that_fails_is_named_and_the_points_before_it_kept() {
    let dir = tempfile::tempdir().unwrap();
    let cfg = write_config(dir.path(), "\"solver.max_matvecs\" = [100000, 1]");
    let out = dir.path().join("out");
    let (ok, _, err) = viscoslide(&["sweep", &cfg, "--out", out.to_str().unwrap()]);
    assert!(!ok, "{err}");
    let lines: Vec<&str> = err.trim().lines().collect();
    let error = lines.last().unwrap();
    assert!(error.starts_with("error: "), "{err}");
    let note = lines[lines.len() - 2];
    assert!(
        note.starts_with("note: point p0003 (v = 0.05 m/s, solver.max_matvecs = 1) failed"),
        "{err}"
    );
    for id in ["p0000", "p0001", "p0002"] {
        let text = std::fs::read_to_string(out.join("points").join(format!("{id}.json"))).unwrap();
        let v: serde_json::Value = serde_json::from_str(&text).unwrap();
        assert!(v["friction_coefficient"].as_f64().unwrap() > 0.0, "{id}");
    }
    assert!(!out.join("points").join("p0003.json").exists());
}
