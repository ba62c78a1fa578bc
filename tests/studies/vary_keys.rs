//! `[sweep.vary]` keys read as config paths: whitespace and a key given
//! twice (after trimming, as `--set` trims) refused, a value listed twice
//! refused, keys that make a missing section together accepted, a key
//! replacing its alternative as `--set` does, and the number of
//! combinations checked against its limit before anything runs.

use std::path::Path;
use std::process::Command;
use std::time::{Duration, Instant};

/// No `[layer]`, no temperature: the varied keys are the solver's and the
/// layer's.
const CONFIG: &str = r#"
[material]
model = "sls"
relaxed_modulus = 3.3333333333333335e6
glassy_modulus = 1.0e7
creep_time = 0.01

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

[analysis]
enabled = false

[sweep]
speed = [0.05]
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

/// `vary` refused in one line holding every needle, and nothing written.
fn refused(vary: &str, needles: &[&str]) -> Duration {
    let dir = tempfile::tempdir().unwrap();
    let cfg = write_config(dir.path(), vary);
    let out = dir.path().join("never");
    let t0 = Instant::now();
    let (ok, _, err) = viscoslide(&["sweep", &cfg, "--out", out.to_str().unwrap()]);
    let took = t0.elapsed();
    assert!(!ok, "{vary}: accepted");
    for needle in needles {
        assert!(err.contains(needle), "{vary}: {err}");
    }
    assert_eq!(err.trim().lines().count(), 1, "{vary}: {err}");
    assert!(
        !out.exists(),
        "{vary}: a refused sweep wrote {}",
        out.display()
    );
    took
}

#[test]
fn a_key_given_twice_is_refused_naming_both_spellings() {
    refused(
        "\"solver.tolerance\" = [1e-6, 1e-8]\n\"solver.tolerance \" = [1e-7, 1e-9]",
        &[
            "\"solver.tolerance\"",
            "\"solver.tolerance \"",
            "give it once",
        ],
    );
    refused(
        "\"solver.tolerance\" = [1e-6]\n\"solver. tolerance\" = [1e-7]",
        &["\"solver. tolerance\"", "give it once"],
    );
}

#[test]
fn a_key_with_whitespace_is_refused() {
    for key in [
        "solver.tolerance ",
        " solver.tolerance",
        "solver .tolerance",
    ] {
        refused(
            &format!("\"{key}\" = [1e-6, 1e-8]"),
            &[&format!("\"{key}\""), "no spaces", "\"solver.tolerance\""],
        );
    }
}

#[test]
fn a_value_listed_twice_is_refused_naming_key_and_value() {
    refused(
        "\"solver.tolerance\" = [0.5, 0.25, 0.5]",
        &["\"solver.tolerance\"", "0.5 twice"],
    );
    // 7 and 7.0 are one value.
    refused(
        "\"loading.direction_deg\" = [7, 7.0]",
        &["\"loading.direction_deg\"", "twice"],
    );
    refused(
        "\"layer.base\" = [\"bonded\", \"bonded\"]\n\"layer.thickness\" = [1e-3]",
        &["\"layer.base\"", "\"bonded\"", "twice"],
    );
}

/// A vary over `layer.base` and `layer.thickness` builds the `[layer]` the
/// configuration does not have; a bad value among them is still named.
#[test]
fn keys_that_make_a_section_together_are_accepted() {
    let dir = tempfile::tempdir().unwrap();
    let cfg = write_config(
        dir.path(),
        "\"layer.base\" = [\"bonded\", \"frictionless\"]\n\"layer.thickness\" = [1e-3, 2e-3]",
    );
    let out = dir.path().join("run");
    let (ok, stdout, err) = viscoslide(&["sweep", &cfg, "--out", out.to_str().unwrap()]);
    assert!(ok, "{err}");
    assert!(stdout.contains("4 points"), "{stdout}");
    let csv = std::fs::read_to_string(out.join("sweep.csv")).unwrap();
    assert_eq!(csv.lines().count(), 1 + 4, "{csv}");
    refused(
        "\"layer.base\" = [\"bonded\"]\n\"layer.thickness\" = [\"thick\"]",
        &["\"layer.thickness\" = \"thick\""],
    );
}

/// 101 x 100 combinations: refused at once by the stated limit (every
/// combination would otherwise be built before the first solve).
#[test]
fn too_many_combinations_are_refused_before_anything_runs() {
    let list = |n: usize, scale: f64| {
        let v: Vec<String> = (0..n)
            .map(|k| format!("{:e}", scale * (1.0 + k as f64)))
            .collect();
        format!("[{}]", v.join(", "))
    };
    let vary = format!(
        "\"solver.tolerance\" = {}\n\"loading.direction_deg\" = {}",
        list(101, 1e-9),
        list(100, 0.1)
    );
    let took = refused(&vary, &["100 x 101", "10100", "limit of 10000"]);
    assert!(took < Duration::from_secs(10), "{took:?}");
}

/// A key of a pair of which a configuration gives one (`q1` or `scales`,
/// `rms_height` or `rms_slope`, `normal_load` or `mean_pressure`) replaces
/// the configuration's own, as `--set key=value` does; two keys of one
/// pair varied together are refused, as two `--set` of them are.
#[test]
fn a_varied_key_replaces_its_alternative_as_set_does() {
    let dir = tempfile::tempdir().unwrap();
    let cfg = write_config(
        dir.path(),
        "\"surface.generate.q1\" = [1000.0, 1600.0]\n\"surface.generate.rms_height\" = [2e-6]\n\"loading.normal_load\" = [0.3]",
    );
    let out = dir.path().join("run");
    let (ok, stdout, err) = viscoslide(&["sweep", &cfg, "--out", out.to_str().unwrap()]);
    assert!(ok, "{err}");
    assert!(stdout.contains("2 points"), "{stdout}");
    // The merge reads the pinned configuration back the same way.
    assert!(!err.contains("points' own values"), "{err}");
    let point: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(out.join("points").join("p0001.json")).unwrap(),
    )
    .unwrap();
    let one = dir.path().join("one");
    let (ok, _, err) = viscoslide(&[
        "solve",
        &cfg,
        "--set",
        "surface.generate.q1=1600.0",
        "--set",
        "surface.generate.rms_height=2e-6",
        "--set",
        "loading.normal_load=0.3",
        "--set",
        "loading.speed=0.05",
        "--out",
        one.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    let solved: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(one.join("summary.json")).unwrap()).unwrap();
    // The same problem: only the order of sums in threaded code may differ.
    for key in [
        "friction_coefficient",
        "contact_area_fraction",
        "normal_load",
    ] {
        let (a, b) = (point[key].as_f64().unwrap(), solved[key].as_f64().unwrap());
        assert!((a - b).abs() <= 1e-9 * b.abs(), "{key}: {a} vs {b}");
    }
    refused(
        "\"surface.generate.q1\" = [1000.0]\n\"surface.generate.scales\" = [4]",
        &["exactly one of `scales`"],
    );
    refused(
        "\"loading.normal_load\" = [0.3]\n\"loading.mean_pressure\" = [3000.0]",
        &["normal_load"],
    );
}
