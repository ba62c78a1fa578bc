//! `viscoslide analyze DIR` end to end on a directory laid out like a solve's
//! output (summary.json and the .npy maps written here).

use std::path::Path;
use std::process::Command;

use viscoslide::io::npy;
use viscoslide::surface::{generate, GenerateParams, UpperCutoff};

const N: usize = 128;
const L: f64 = 0.01;

fn viscoslide(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_viscoslide"))
        .args(args)
        .output()
        .unwrap()
}

fn files(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().to_string())
        .collect();
    v.sort();
    v
}

/// A solve-like directory: a generated surface as the displacement, a map of
/// small elliptical spots as the contact, pressure on the spots.
fn solve_dir(dir: &Path) {
    std::fs::create_dir_all(dir).unwrap();
    let u = generate(&GenerateParams {
        nx: N,
        ny: N,
        length: L,
        upper: UpperCutoff::Scales(32.0),
        seed: 2,
        ..GenerateParams::default()
    })
    .unwrap()
    .heights;
    let mut contact = vec![0.0; N * N];
    for (ci, cj) in [
        (20.0, 20.0),
        (20.0, 80.0),
        (70.0, 50.0),
        (100.0, 100.0),
        (90.0, 15.0),
    ] {
        for i in 0..N {
            for j in 0..N {
                let (dx, dy) = (i as f64 + 0.5 - ci, j as f64 + 0.5 - cj);
                if (dx / 3.0).powi(2) + (dy / 5.0).powi(2) <= 1.0 {
                    contact[i * N + j] = 1.0;
                }
            }
        }
    }
    let pressure: Vec<f64> = contact.iter().map(|c| c * 2.5e4).collect();
    for (name, f) in [
        ("displacement.npy", &u),
        ("contact.npy", &contact),
        ("pressure.npy", &pressure),
    ] {
        std::fs::write(dir.join(name), npy::encode_f64(&[N, N], f)).unwrap();
    }
    let summary = serde_json::json!({
        "grid": [N, N],
        "cell_size": L / N as f64,
        "length": [L, L],
        "xi": 0.0117,
        "config": {"surface": {"generate": {"n": N, "length": L, "scales": 32.0}}},
    });
    std::fs::write(dir.join("summary.json"), summary.to_string()).unwrap();
}

#[test]
fn analyze_writes_json_and_figures() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("run");
    solve_dir(&dir);
    let o = viscoslide(&["analyze", dir.to_str().unwrap(), "--levels", "0.5,0.3"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(
        files(&dir),
        [
            "analysis.json",
            "analysis_chi_contours.png",
            "analysis_contact.png",
            "analysis_displacement.png",
            "analysis_m2_polar.png",
            "analysis_pressure.png",
            "analysis_spot_areas.png",
            "contact.npy",
            "displacement.npy",
            "pressure.npy",
            "summary.json",
        ]
    );
    for f in files(&dir).iter().filter(|f| f.ends_with(".png")) {
        let bytes = std::fs::read(dir.join(f)).unwrap();
        assert!(bytes.starts_with(b"\x89PNG"), "{f} is not a PNG");
    }
    let j: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.join("analysis.json")).unwrap()).unwrap();
    for key in [
        "gamma",
        "theta_p_deg",
        "m20",
        "m02",
        "m11",
        "lambda",
        "ellipse_angle_deg",
        "spots",
        "tensor_normalised",
        "band",
        "chi",
    ] {
        assert!(!j[key].is_null(), "analysis.json lacks {key}: {j}");
    }
    // Band from config.surface.generate.scales; five separate spots.
    assert_eq!(j["band"]["zeta1"], 1.0);
    assert_eq!(j["band"]["zeta2"], 32.0);
    assert_eq!(j["spots"]["count"], 5);
    assert_eq!(j["spots"]["connectivity"], "four");
    assert_eq!(j["chi"]["levels"].as_array().unwrap().len(), 2);
    // Spots stretched along y (semi-axes 3 and 5 cells): contours stretched
    // along q_x, lambda = 3/5 up to the pixelation of such small spots.
    let lambda = j["lambda"].as_f64().unwrap();
    let angle = j["ellipse_angle_deg"].as_f64().unwrap();
    assert!((lambda - 0.6).abs() < 0.06, "lambda {lambda}");
    assert!(angle.abs() < 3.0, "angle {angle}");
    let gamma = j["gamma"].as_f64().unwrap();
    assert!(gamma > 0.0 && gamma <= 1.0);
}

fn assert_fails_cleanly(dir: &Path, args: &[&str], needle: &str) {
    let before = files(dir);
    let mut all = vec!["analyze", dir.to_str().unwrap()];
    all.extend_from_slice(args);
    let o = viscoslide(&all);
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(err.trim_end().lines().count(), 1, "not one line: {err}");
    assert!(err.contains(needle), "{err}");
    assert_eq!(files(dir), before, "the directory changed");
}

#[test]
fn missing_or_inconsistent_inputs_write_nothing() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("run");
    solve_dir(&dir);
    std::fs::remove_file(dir.join("contact.npy")).unwrap();
    assert_fails_cleanly(&dir, &[], "contact.npy: missing");

    solve_dir(&dir);
    std::fs::write(
        dir.join("pressure.npy"),
        npy::encode_f64(&[N / 2, N], &vec![0.0; N * N / 2]),
    )
    .unwrap();
    assert_fails_cleanly(&dir, &[], "disagrees with the grid");

    solve_dir(&dir);
    std::fs::remove_file(dir.join("summary.json")).unwrap();
    assert_fails_cleanly(&dir, &[], "summary.json: missing");

    solve_dir(&dir);
    assert_fails_cleanly(&dir, &["--levels", "0.5,1.5"], "levels");
}

#[test]
fn no_contact_still_writes_every_figure() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("run");
    solve_dir(&dir);
    std::fs::write(
        dir.join("contact.npy"),
        npy::encode_f64(&[N, N], &vec![0.0; N * N]),
    )
    .unwrap();
    let o = viscoslide(&["analyze", dir.to_str().unwrap()]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let j: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.join("analysis.json")).unwrap()).unwrap();
    assert!(j["lambda"].is_null() && j["chi"].is_null());
    assert_eq!(j["spots"]["count"], 0);
    assert_eq!(files(&dir).len(), 11);
}

#[test]
fn band_defaults_from_summary_config() {
    use viscoslide::internals::analysis::read_summary;
    let tmp = tempfile::tempdir().unwrap();
    let q0 = 2.0 * std::f64::consts::PI / L;
    let cases = [
        (
            serde_json::json!({"scales": 16, "ql": 2.0 * q0}),
            Some(32.0),
        ),
        (serde_json::json!({"q1": 20.0 * q0}), Some(20.0)),
        (serde_json::json!({"hurst": 0.8}), None),
    ];
    for (k, (generate, want)) in cases.into_iter().enumerate() {
        let p = tmp.path().join(format!("s{k}.json"));
        let doc = serde_json::json!({
            "grid": [N, N],
            "cell_size": L / N as f64,
            "config": {"surface": {"generate": generate}},
        });
        std::fs::write(&p, doc.to_string()).unwrap();
        let s = read_summary(&p).unwrap();
        match (s.scales, want) {
            (Some(a), Some(b)) => assert!((a - b).abs() < 1e-9, "{a} vs {b}"),
            (a, b) => assert_eq!(a, b),
        }
    }
    let p = tmp.path().join("bad.json");
    std::fs::write(&p, r#"{"grid": [4]}"#).unwrap();
    let e = read_summary(&p).unwrap_err().to_string();
    assert!(e.contains("grid"), "{e}");
}

/// `summary.json` of `dir` with `key` set to `value`.
fn set_summary(dir: &Path, key: &str, value: serde_json::Value) {
    let p = dir.join("summary.json");
    let mut doc: serde_json::Value = serde_json::from_slice(&std::fs::read(&p).unwrap()).unwrap();
    doc[key] = value;
    std::fs::write(&p, doc.to_string()).unwrap();
}

fn analysis_json(dir: &Path) -> serde_json::Value {
    serde_json::from_slice(&std::fs::read(dir.join("analysis.json")).unwrap()).unwrap()
}

#[test]
fn the_taper_defaults_to_the_runs_formulation() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("run");
    let taper_warning = |j: &serde_json::Value| {
        j["warnings"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|w| w.as_str().unwrap().contains("taper"))
            .count()
    };
    // A periodic run: no taper, as the solve's own analysis; the same
    // numbers as --periodic, and no warning.
    solve_dir(&dir);
    set_summary(&dir, "formulation", "periodic".into());
    let o = viscoslide(&["analyze", dir.to_str().unwrap()]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let default = analysis_json(&dir);
    assert_eq!(default["window"], "none");
    assert_eq!(taper_warning(&default), 0, "{default}");
    let o = viscoslide(&["analyze", dir.to_str().unwrap(), "--periodic"]);
    assert!(o.status.success());
    assert_eq!(analysis_json(&dir)["gamma"], default["gamma"]);
    assert_eq!(analysis_json(&dir)["theta_p_deg"], default["theta_p_deg"]);
    // An explicit Hann window overrides it, and says so.
    let o = viscoslide(&["analyze", dir.to_str().unwrap(), "--window", "hann"]);
    assert!(o.status.success());
    let hann = analysis_json(&dir);
    assert_eq!(hann["window"], "hann");
    assert_ne!(hann["gamma"], default["gamma"]);
    assert_eq!(taper_warning(&hann), 1, "{hann}");
    assert!(String::from_utf8_lossy(&o.stderr).contains("warning: the solve is periodic"));

    // A non-periodic run (or one whose summary does not say): Hann; no
    // taper asked for is warned about.
    for formulation in [serde_json::json!("non_periodic"), serde_json::Value::Null] {
        solve_dir(&dir);
        set_summary(&dir, "formulation", formulation.clone());
        let o = viscoslide(&["analyze", dir.to_str().unwrap()]);
        assert!(o.status.success());
        let j = analysis_json(&dir);
        assert_eq!(j["window"], "hann");
        assert_eq!(taper_warning(&j), 0, "{j}");
        let o = viscoslide(&["analyze", dir.to_str().unwrap(), "--periodic"]);
        assert!(o.status.success());
        let want = usize::from(!formulation.is_null());
        assert_eq!(taper_warning(&analysis_json(&dir)), want, "{formulation}");
    }

    // An unknown formulation is refused in one line, writing nothing.
    solve_dir(&dir);
    set_summary(&dir, "formulation", "spectral".into());
    assert_fails_cleanly(&dir, &[], "`formulation` must be");
}

/// `analyze DIR` takes the band and levels of the run's own `[analysis]`
/// section (it took the defaults, and rewrote `analysis.json` with
/// another band); a flag replaces only its own setting.
#[test]
fn the_runs_analysis_section_is_the_default() {
    let tmp = tempfile::tempdir().unwrap();
    let run = tmp.path().join("run");
    let config = concat!(env!("CARGO_MANIFEST_DIR"), "/configs/default.toml");
    let o = viscoslide(&[
        "solve",
        config,
        "--set",
        "surface.generate.n=64",
        "--set",
        "surface.generate.scales=8",
        "--set",
        "analysis.zeta1=2.0",
        "--set",
        "analysis.zeta2=6.0",
        "--set",
        "analysis.chi_levels=[0.6]",
        "--backend",
        "cpu",
        "--out",
        run.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let own = analysis_json(&run);
    assert_eq!(own["band"]["zeta1"], 2.0);
    assert_eq!(own["band"]["zeta2"], 6.0);
    let o = viscoslide(&["analyze", run.to_str().unwrap()]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let again = analysis_json(&run);
    for key in [
        "gamma",
        "theta_p_deg",
        "band",
        "lambda",
        "lambda_level",
        "window",
    ] {
        assert_eq!(again[key], own[key], "{key}");
    }
    let o = viscoslide(&["analyze", run.to_str().unwrap(), "--zeta2", "4"]);
    assert!(o.status.success());
    let narrower = analysis_json(&run);
    assert_eq!(narrower["band"]["zeta1"], 2.0);
    assert_eq!(narrower["band"]["zeta2"], 4.0);
    assert_eq!(narrower["lambda_level"], own["lambda_level"]);

    // A summary whose [analysis] cannot be read is refused by name.
    let dir = tmp.path().join("synthetic");
    solve_dir(&dir);
    set_summary(
        &dir,
        "config",
        serde_json::json!({"analysis": {"zeta1": "two"}}),
    );
    assert_fails_cleanly(&dir, &[], "config.analysis");
}
