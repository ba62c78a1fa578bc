//! `viscoslide persson` checks the configuration it is given as a solve
//! checks it, and says where its small-slope theory does not hold.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

const BASE: &str = r#"
[material]
model = "sls"
relaxed_modulus = 3.3333333333333335e6
glassy_modulus = 1.0e7
creep_time = 0.01

[surface.generate]
n = 32
length = 0.01
hurst = 0.8
scales = 8
rms_slope = 0.02
seed = 1

[loading]
normal_load = 0.30
xi = 1.17e-2
"#;

fn config(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

fn persson(cfg: &Path, out: &Path, set: &[&str]) -> Output {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_viscoslide"));
    cmd.arg("persson").arg(cfg).arg("--out").arg(out);
    cmd.args(["--speeds", "1e-3,1,3"]);
    for s in set {
        cmd.args(["--set", s]);
    }
    cmd.output().unwrap()
}

#[test]
fn a_loading_section_a_solve_refuses_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let cfg = config(dir.path(), "c.toml", BASE);
    let out = dir.path().join("p");
    for (set, needle) in [
        (
            &["loading.speed=1", "loading.xi=2"][..],
            "give only one of speed (m/s) and xi",
        ),
        (
            &["loading.mean_pressure=1000", "loading.normal_load=0.1"][..],
            "give only one of normal_load (N), mean_pressure (Pa) and approach (m)",
        ),
        (&["loading.xi=nan"][..], "[loading] xi = NaN must be finite"),
        (&["loading.xi=-1"][..], "[loading] xi = -1 must be finite"),
        (
            &["loading.normal_load=-1"][..],
            "[loading] normal_load = -1 N",
        ),
        (
            &["loading.direction_deg=inf"][..],
            "[loading] direction_deg = inf must be finite",
        ),
    ] {
        let o = persson(&cfg, &out, set);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success(), "{set:?} was accepted");
        assert!(err.contains(needle), "{set:?}: {err}");
        assert_eq!(err.trim().lines().count(), 1, "{err}");
        assert!(!out.exists(), "{set:?} left {}", out.display());
    }
    // Both loads in the file: the solve refuses it, so does persson (it
    // used to answer at mean_pressure).
    let both = BASE.replace(
        "normal_load = 0.30",
        "normal_load = 0.30\nmean_pressure = 1e3",
    );
    let o = persson(&config(dir.path(), "both.toml", &both), &out, &[]);
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("give only one of normal_load"));
    // The keys the curve does not read still pass when they are sound.
    let o = persson(&cfg, &out, &["loading.direction_deg=30"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

#[test]
fn a_psd_beyond_the_small_slope_limit_is_warned_about() {
    let dir = tempfile::tempdir().unwrap();
    let cfg = config(dir.path(), "c.toml", BASE);
    let out = dir.path().join("p");
    let o = persson(&cfg, &out, &["surface.generate.rms_slope=3"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    let needle = "the rms slope of the PSD is 3.000e0, beyond 1";
    assert!(err.contains(&format!("warning: {needle}")), "{err}");
    let doc: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("persson.json")).unwrap()).unwrap();
    let warnings = doc["warnings"].as_array().unwrap();
    assert!(
        warnings
            .iter()
            .any(|w| w.as_str().unwrap().contains(needle)),
        "{warnings:?}"
    );
    // A gentle surface: no such warning.
    std::fs::remove_dir_all(&out).unwrap();
    let o = persson(&cfg, &out, &[]);
    assert!(!String::from_utf8_lossy(&o.stderr).contains("rms slope of the PSD"));
}

#[test]
fn speeds_beyond_double_precision_are_refused_or_noted_not_a_panic() {
    let dir = tempfile::tempdir().unwrap();
    let cfg = config(dir.path(), "c.toml", BASE);
    let out = dir.path().join("p");
    let o = Command::new(env!("CARGO_BIN_EXE_viscoslide"))
        .arg("persson")
        .arg(&cfg)
        .args(["--speeds", "1e300,1e308,2", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(err.contains("leave double precision"), "{err}");
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(!out.exists());
    // A solve at such a speed (its glassy limit) notes that Persson's
    // theory was not evaluated instead of panicking.
    let solved = dir.path().join("s");
    let o = Command::new(env!("CARGO_BIN_EXE_viscoslide"))
        .arg("solve")
        .arg(&cfg)
        .args(["--backend", "cpu", "--set", "loading.speed=1e308"])
        .args(["--set", "analysis.enabled=false", "--out"])
        .arg(&solved)
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(text.contains("Persson's theory not evaluated"), "{text}");
}
