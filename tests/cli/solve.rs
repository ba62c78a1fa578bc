//! `viscoslide solve` end to end: outputs, fixed summary keys, and clear
//! one-line errors that write nothing.

use std::path::Path;
use std::process::Command;

const CONFIG: &str = r#"
[material]
model = "sls"
relaxed_modulus = 3.3333333333333335e6
glassy_modulus = 1.0e7
creep_time = 0.01
poisson = 0.5

[surface.generate]
n = 48
length = 0.01
hurst = 0.8
scales = 8
rms_slope = 0.02
seed = 3

[loading]
normal_load = 0.30
xi = 1.17e-2
"#;

fn run(dir: &Path, config: &str, extra: &[&str]) -> (bool, String, String) {
    let cfg = dir.join("c.toml");
    std::fs::write(&cfg, config).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_viscoslide"))
        .arg("solve")
        .arg(&cfg)
        .args(["--backend", "cpu", "--out"])
        .arg(dir.join("out"))
        .args(extra)
        .output()
        .unwrap();
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn solve_writes_every_output_with_the_fixed_keys() {
    let tmp = tempfile::tempdir().unwrap();
    let (ok, stdout, stderr) = run(tmp.path(), CONFIG, &[]);
    assert!(ok, "{stderr}");
    assert!(stdout.contains("friction coefficient"), "{stdout}");
    let out = tmp.path().join("out");
    for f in [
        "summary.json",
        "pressure.npy",
        "displacement.npy",
        "gap.npy",
        "contact.npy",
        "pressure.png",
        "contact.png",
    ] {
        assert!(out.join(f).is_file(), "missing {f}");
    }
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    for key in [
        "friction_coefficient",
        "friction_coefficient_dissipation",
        "contact_area_fraction",
        "contact_area",
        "approach",
        "max_pressure",
        "mean_pressure",
        "normal_load",
        "speed",
        "xi",
        "grid",
        "cell_size",
        "iterations",
        "matvecs",
        "residual",
        "backend",
        "wall_time_s",
        "seed",
        "version",
        "peak_memory_bytes",
    ] {
        assert!(s.get(key).is_some(), "summary.json lacks {key}");
    }
    assert_eq!(s["grid"], serde_json::json!([48, 48]));
    assert_eq!(s["seed"], 3);
    assert!((s["normal_load"].as_f64().unwrap() - 0.30).abs() < 1e-9);
    assert!((s["xi"].as_f64().unwrap() - 1.17e-2).abs() < 1e-12);
    assert!(s["friction_coefficient"].as_f64().unwrap() > 0.0);
    let (nx, ny, p) = viscoslide::io::npy::read_2d(out.join("pressure.npy")).unwrap();
    assert_eq!((nx, ny), (48, 48));
    assert!(p.iter().all(|v| *v >= 0.0));
}

#[test]
fn bad_inputs_fail_with_one_line_and_write_nothing() {
    let cases: Vec<(String, Vec<&str>, &str)> = vec![
        (
            CONFIG.replace("normal_load = 0.30", "normal_load = 0.0"),
            vec![],
            "normal load",
        ),
        (
            CONFIG.replace("normal_load = 0.30", "normal_load = -1.0"),
            vec![],
            "normal load",
        ),
        (
            CONFIG.replace("seed = 3", "seed = 3\ncolour = 2"),
            vec![],
            "colour",
        ),
        (
            CONFIG.replace(
                "relaxed_modulus = 3.3333333333333335e6",
                "relaxed_modulus = -3e6",
            ),
            vec![],
            "relaxed_modulus",
        ),
        (
            CONFIG.to_string(),
            vec!["--set", "surface.generate.n=2000000"],
            "memory",
        ),
        (
            CONFIG.replace("xi = 1.17e-2", "xi = 1.17e-2\nspeed = 1.0"),
            vec![],
            "only one of speed",
        ),
    ];
    for (config, extra, needle) in cases {
        let tmp = tempfile::tempdir().unwrap();
        let (ok, _, stderr) = run(tmp.path(), &config, &extra);
        assert!(!ok, "should fail: {needle}");
        let line = stderr
            .lines()
            .find(|l| l.starts_with("error:"))
            .unwrap_or_else(|| panic!("no error line: {stderr}"));
        assert!(line.contains(needle), "error for {needle}: {line}");
        assert!(!tmp.path().join("out").exists(), "{needle}: output written");
    }
}

/// The rough 32 x 32 map (8 scales, rms slope 0.02, seed 3) the file
/// tests write as `h.npy`.
fn rough_map() -> viscoslide::surface::HeightMap {
    use viscoslide::surface::{generate, GenerateParams, Normalisation, UpperCutoff};
    generate(&GenerateParams {
        nx: 32,
        ny: 32,
        length: 0.01,
        hurst: 0.8,
        upper: UpperCutoff::Scales(8.0),
        normalisation: Normalisation::RmsSlope(0.02),
        seed: 3,
        ..GenerateParams::default()
    })
    .unwrap()
}

/// [`CONFIG`] on the map `h.npy` (1 cm) with the `[surface]` line `extra`.
fn on_file(extra: &str) -> String {
    CONFIG.replace(
        "[surface.generate]\nn = 48\nlength = 0.01\nhurst = 0.8\nscales = 8\nrms_slope = 0.02\nseed = 3\n",
        &format!("[surface]\nfile = \"h.npy\"\nlength = 0.01\n{extra}\n"),
    )
}

#[test]
fn nan_heights_in_a_surface_file_are_rejected() {
    let tmp = tempfile::tempdir().unwrap();
    let mut z = vec![0.0; 16 * 16];
    z[37] = f64::NAN;
    std::fs::write(
        tmp.path().join("h.npy"),
        viscoslide::io::npy::encode_f64(&[16, 16], &z),
    )
    .unwrap();
    let config = on_file("");
    let (ok, _, stderr) = run(tmp.path(), &config, &[]);
    assert!(!ok);
    assert!(
        stderr.to_lowercase().contains("nan") || stderr.contains("finite"),
        "{stderr}"
    );
    // The fix it names is the config's key (solve has no --fill-missing).
    assert!(stderr.contains("[surface] fill_missing = true"), "{stderr}");
    assert!(!tmp.path().join("out").exists());
}

/// Missing points filled by harmonic interpolation are counted in
/// `summary.json` (`filled_points`) and noted on the console; more than 5 %
/// of the map filled is warned about, since the filling is smooth and the
/// roughness there is missing (before, a map mostly missing was solved as
/// a smooth pad without a word).
#[test]
fn filled_points_are_counted_and_many_are_warned_about() {
    let rough = rough_map();
    let config = on_file("fill_missing = true");
    // Two points (0.2 %), then a 12 x 12 hole (14 %).
    let holes: [Vec<usize>; 2] = [
        vec![37, 500],
        (0..144).map(|k| (10 + k / 12) * 32 + 10 + k % 12).collect(),
    ];
    for (holes, warned) in holes.iter().zip([false, true]) {
        let tmp = tempfile::tempdir().unwrap();
        let mut z = rough.heights.clone();
        holes.iter().for_each(|&k| z[k] = f64::NAN);
        std::fs::write(
            tmp.path().join("h.npy"),
            viscoslide::io::npy::encode_f64(&[32, 32], &z),
        )
        .unwrap();
        let (ok, _, stderr) = run(tmp.path(), &config, &[]);
        assert!(ok, "{stderr}");
        let s: serde_json::Value = serde_json::from_str(
            &std::fs::read_to_string(tmp.path().join("out/summary.json")).unwrap(),
        )
        .unwrap();
        assert_eq!(s["filled_points"], holes.len(), "{s}");
        let note = format!("note: {} of 1024 points", holes.len());
        assert!(stderr.contains(&note), "{stderr}");
        let warning = s["warnings"]
            .as_array()
            .unwrap()
            .iter()
            .any(|w| w.as_str().unwrap().contains("missing from the contact"));
        assert_eq!(warning, warned, "{}", s["warnings"]);
    }
}

#[test]
fn periodic_formulation_is_typed_and_recorded() {
    let tmp = tempfile::tempdir().unwrap();
    let (ok, _, stderr) = run(
        tmp.path(),
        CONFIG,
        &["--set", "solver.formulation=periodic"],
    );
    assert!(ok, "{stderr}");
    let s: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(tmp.path().join("out/summary.json")).unwrap(),
    )
    .unwrap();
    assert_eq!(s["formulation"], "periodic");
    // On a periodic field the stencil and the Fourier sum are the same sum.
    let (mu, mu_d) = (
        s["friction_coefficient"].as_f64().unwrap(),
        s["friction_coefficient_dissipation"].as_f64().unwrap(),
    );
    assert!(mu > 0.0 && (mu - mu_d).abs() <= 1e-9 * mu, "{mu} vs {mu_d}");
    let tmp = tempfile::tempdir().unwrap();
    let (ok, _, stderr) = run(
        tmp.path(),
        CONFIG,
        &["--set", "solver.formulation=\"sometimes\""],
    );
    assert!(!ok && stderr.contains("formulation"), "{stderr}");
}

#[test]
fn sphere_config_at_rest_is_hertz() {
    // configs/sphere_sliding.toml at v = 0 on a coarser grid: the contact
    // radius within two cells (0.1 mm of 1.0 mm) of Hertz with E0.
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/configs/sphere_sliding.toml"
    ))
    .unwrap();
    let tmp = tempfile::tempdir().unwrap();
    let (ok, _, stderr) = run(
        tmp.path(),
        &text,
        &["--set", "loading.speed=0.0", "--set", "surface.sphere.n=64"],
    );
    assert!(ok, "{stderr}");
    let s: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(tmp.path().join("out/summary.json")).unwrap(),
    )
    .unwrap();
    let area = s["contact_area"].as_f64().unwrap();
    let e_star: f64 = 1e7 / 3.0 / 0.75;
    let a0 = (3.0 * 0.6 * 0.01 / (4.0 * e_star)).cbrt();
    let radius = (area / std::f64::consts::PI).sqrt();
    assert!(
        (radius - a0).abs() < 2.0 * 3.2e-3 / 64.0,
        "{radius} vs {a0}"
    );
    assert!(s["friction_coefficient"].as_f64().unwrap().abs() < 1e-12);
}

/// A sliding sphere is an indenter inside its map, not a rough pad: no flat
/// pad's rim is subtracted from its friction nor warned of (it was: "25 %
/// of the friction is the finite pad's own", for a contact 20 cells from
/// every edge).
#[test]
fn a_sliding_sphere_has_no_pad_rim() {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/configs/sphere_sliding.toml"
    ))
    .unwrap();
    let tmp = tempfile::tempdir().unwrap();
    let (ok, _, stderr) = run(tmp.path(), &text, &["--set", "surface.sphere.n=64"]);
    assert!(ok, "{stderr}");
    assert!(!stderr.contains("finite pad's own"), "{stderr}");
    let s: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(tmp.path().join("out/summary.json")).unwrap(),
    )
    .unwrap();
    assert!(s["friction_coefficient"].as_f64().unwrap() > 0.0);
    assert!(
        s["roughness_friction_coefficient"].is_null(),
        "{}",
        s["roughness_friction_coefficient"]
    );
}

/// A finite pad reports its own part of the friction: the same pad without
/// roughness at the same load and speed (`smooth_pad_friction_coefficient`),
/// equal to a separate solve of that pad with the roughness scaled to
/// nothing, and the roughness part beside it. Near full contact the pad's
/// rim gives almost all of the friction and is warned about (before, mu =
/// 2.65e-2 stood beside Persson's 1e-3 with no word); at the default load it
/// is 6 % and not warned about. The periodic formulation has no rim.
#[test]
fn a_finite_pad_reports_its_own_friction() {
    let tmp = tempfile::tempdir().unwrap();
    let summary = |dir: &str, load: &str, extra: &[&str]| -> serde_json::Value {
        let d = tmp.path().join(dir);
        std::fs::create_dir_all(&d).unwrap();
        let mut args = vec![
            "--set",
            "surface.generate.n=64",
            "--set",
            "analysis.enabled=false",
        ];
        let load = format!("loading.normal_load={load}");
        args.extend(["--set", &load]);
        args.extend(extra);
        let cfg = Path::new(env!("CARGO_MANIFEST_DIR")).join("configs/default.toml");
        let config = std::fs::read_to_string(cfg).unwrap();
        let (ok, _, stderr) = run(&d, &config, &args);
        assert!(ok, "{stderr}");
        serde_json::from_slice(&std::fs::read(d.join("out/summary.json")).unwrap()).unwrap()
    };
    let f = |s: &serde_json::Value, k: &str| s[k].as_f64().unwrap_or_else(|| panic!("{k}: {s}"));
    let pad_warning = |s: &serde_json::Value| {
        s["warnings"]
            .as_array()
            .unwrap()
            .iter()
            .any(|w| w.as_str().unwrap().contains("finite pad's own"))
    };
    let rough = summary("rough30", "30", &[]);
    let flat = summary(
        "flat30",
        "30",
        &["--set", "surface.generate.rms_slope=1e-7"],
    );
    let (mu, smooth) = (
        f(&rough, "friction_coefficient"),
        f(&rough, "smooth_pad_friction_coefficient"),
    );
    // The flat pad is in full contact: its reference gives what a separate
    // solve of the same pad with a 1e-7 slope gives (1e-7 apart).
    assert_eq!(f(&flat, "contact_area_fraction"), 1.0);
    assert!((smooth / f(&flat, "friction_coefficient") - 1.0).abs() < 1e-6);
    let part = f(&rough, "roughness_friction_coefficient");
    assert!(
        (part / (mu - smooth) - 1.0).abs() < 1e-9,
        "{part} {mu} {smooth}"
    );
    assert!(smooth / mu > 0.9, "{smooth} of {mu}");
    assert!(pad_warning(&rough), "{}", rough["warnings"]);
    let persson = f(&rough, "persson_friction_coefficient");
    let ratio = rough["smooth_pad"]["persson_over_roughness_part"]
        .as_f64()
        .unwrap();
    assert!((ratio / (persson / part) - 1.0).abs() < 1e-12, "{ratio}");
    // At 0.3 N the rim's part is small: no warning.
    let light = summary("rough03", "0.3", &[]);
    let share = light["smooth_pad"]["share"].as_f64().unwrap();
    assert!(share > 0.0 && share < 0.1, "{share}");
    assert!(!pad_warning(&light), "{}", light["warnings"]);
    // The periodic formulation: no pad, no rim.
    let cell = summary(
        "periodic",
        "0.3",
        &["--set", "solver.formulation=\"periodic\""],
    );
    assert!(cell["smooth_pad_friction_coefficient"].is_null());
    assert!(cell["smooth_pad"].is_null());
    // At rest both frictions are zero to round-off (measured: mu =
    // -6.1e-20 with a "-18 %" share): no share to warn about.
    let rest = summary("rest", "0.3", &["--set", "loading.xi=0.0"]);
    assert!(f(&rest, "friction_coefficient").abs() < 1e-14, "{rest}");
    assert!(!pad_warning(&rest), "{}", rest["warnings"]);
}

/// A pad on a bonded layer thinner than a cell (the thin-layer band, no
/// preconditioner) gets its smooth pad too: plain GMRES on the pad's full
/// contact takes several times the rough solve's matvecs (here about 3.7x),
/// and the budget of 3 rough solves used to leave it unanswered ("not
/// computed ... 302 matvecs, residual 3e-9").
#[test]
fn a_pad_on_a_sub_cell_layer_reports_its_own_friction() {
    let config = r#"
[material]
model = "sls"
relaxed_modulus = 3.0e6
glassy_modulus = 3.0e8
creep_time = 1e-3
poisson = 0.5

[surface.generate]
n = 64
length = 1e-3
hurst = 0.8
scales = 6
rms_slope = 0.05
seed = 1

[loading]
mean_pressure = 1e6
speed = 0.01
direction_deg = 30.0

[layer]
thickness = 3.1e-6
base = "bonded"

[analysis]
enabled = false
"#;
    let tmp = tempfile::tempdir().unwrap();
    let (ok, _, stderr) = run(tmp.path(), config, &[]);
    assert!(ok, "{stderr}");
    let s: serde_json::Value =
        serde_json::from_slice(&std::fs::read(tmp.path().join("out/summary.json")).unwrap())
            .unwrap();
    let warnings = s["warnings"].to_string();
    assert!(!warnings.contains("was not computed"), "{warnings}");
    let pad = &s["smooth_pad"];
    let (rough, own) = (
        s["matvecs"].as_u64().unwrap(),
        pad["matvecs"].as_u64().unwrap(),
    );
    assert!(own > 3 * rough, "{own} pad matvecs, {rough} rough");
    let share = pad["share"].as_f64().unwrap();
    assert!(share > 0.0 && share < 0.01, "{share}");
}

/// The periodic formulation under approach control: its displacements have
/// zero mean, so the contact closes at the approach `max(z) - mean(z)` and
/// no larger approach has a solution. Below it every approach converges (up
/// to 99 % contact); at and beyond it the approach is refused in one line
/// naming the bound, before anything is written (before: "the surfaces do
/// not touch" just past it, and 50,002 matvecs ending in "no convergence,
/// residual 5e-16" far past it). The non-periodic formulation solves the
/// same approaches.
#[test]
fn a_periodic_approach_beyond_full_contact_is_refused_naming_the_bound() {
    // CONFIG's material on the issue's surface, under approach control.
    let config = CONFIG
        .replace("n = 48", "n = 64")
        .replace("rms_slope = 0.02", "rms_slope = 0.005")
        .replace("seed = 3", "seed = 1")
        .replace(
            "normal_load = 0.30\nxi = 1.17e-2",
            "speed = 0.01\napproach = 1.1e-5",
        )
        + "\n[solver]\nformulation = \"periodic\"\n\n[analysis]\nenabled = false\n";
    let config = config.as_str();
    let tmp = tempfile::tempdir().unwrap();
    let map = viscoslide::surface::generate(&viscoslide::surface::GenerateParams {
        nx: 64,
        ny: 64,
        length: 0.01,
        hurst: 0.8,
        upper: viscoslide::surface::UpperCutoff::Scales(8.0),
        normalisation: viscoslide::surface::Normalisation::RmsSlope(0.005),
        seed: 1,
        ..Default::default()
    })
    .unwrap();
    let n = map.heights.len() as f64;
    let top = map.heights.iter().copied().fold(f64::MIN, f64::max);
    let full = top - map.heights.iter().sum::<f64>() / n;
    for (approach, area_above) in [(0.95 * full, 0.5), (0.9999 * full, 0.98)] {
        let a = format!("loading.approach={approach:e}");
        let (ok, _, stderr) = run(tmp.path(), config, &["--set", &a]);
        assert!(ok, "{approach:e}: {stderr}");
        let s: serde_json::Value =
            serde_json::from_slice(&std::fs::read(tmp.path().join("out/summary.json")).unwrap())
                .unwrap();
        let area = s["contact_area_fraction"].as_f64().unwrap();
        assert!(area > area_above && area < 1.0, "{approach:e}: {area}");
        std::fs::remove_dir_all(tmp.path().join("out")).unwrap();
    }
    for approach in [full, 1.2e-5, 1e-3] {
        let a = format!("loading.approach={approach:e}");
        let (ok, _, stderr) = run(tmp.path(), config, &["--set", &a]);
        assert!(!ok, "{approach:e} solved");
        assert_eq!(stderr.trim().lines().count(), 1, "{stderr}");
        assert!(
            stderr.contains("full contact of the periodic cell")
                && stderr.contains(&format!("{full:.6e}")),
            "{stderr}"
        );
        assert!(!tmp.path().join("out").exists());
        // The finite pad takes it.
        let (ok, _, stderr) = run(
            tmp.path(),
            config,
            &["--set", &a, "--set", "solver.formulation=\"non_periodic\""],
        );
        assert!(ok, "{approach:e} non-periodic: {stderr}");
        std::fs::remove_dir_all(tmp.path().join("out")).unwrap();
    }
}

/// A contact of a few cells is at the grid's resolution and warned about
/// (before, one cell in contact at 3e-4 N gave a friction that only
/// followed the load, beside Persson's, without a word); the default
/// load's 300 cells are not.
#[test]
fn a_contact_of_a_few_cells_is_warned() {
    let tmp = tempfile::tempdir().unwrap();
    let config =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("configs/default.toml"))
            .unwrap();
    for (dir, load, warned) in [("tiny", "3e-4", true), ("default", "0.3", false)] {
        let d = tmp.path().join(dir);
        std::fs::create_dir_all(&d).unwrap();
        let load = format!("loading.normal_load={load}");
        let args = [
            "--set",
            "surface.generate.n=64",
            "--set",
            "surface.generate.scales=8",
            "--set",
            "analysis.enabled=false",
            "--set",
            &load,
        ];
        let (ok, _, stderr) = run(&d, &config, &args);
        assert!(ok, "{stderr}");
        let s: serde_json::Value =
            serde_json::from_slice(&std::fs::read(d.join("out/summary.json")).unwrap()).unwrap();
        let cells = s["contact_cells"].as_u64().unwrap();
        let warning = s["warnings"]
            .as_array()
            .unwrap()
            .iter()
            .filter_map(|w| w.as_str())
            .find(|w| w.contains("the contact holds only"));
        assert_eq!(
            warning.is_some(),
            warned,
            "{cells} cells: {}",
            s["warnings"]
        );
        assert_eq!(cells < 16, warned, "{cells}");
        if let Some(w) = warning {
            assert!(
                w.contains(&format!("only {cells} cell")) && w.contains("64 x 64"),
                "{w}"
            );
            assert!(stderr.contains(w), "{stderr}");
        }
    }
}

/// A map marked periodic solved as a finite pad only because no
/// formulation was given is warned about (Python's `formulation="auto"`
/// solves it periodic; the two differ); a formulation given is a choice.
#[test]
fn a_periodic_map_solved_as_a_pad_by_default_is_warned() {
    let map = rough_map();
    let config = on_file("periodic = true");
    for (extra, warned) in [
        (None, true),
        (Some("solver.formulation=\"non_periodic\""), false),
        (Some("solver.formulation=\"periodic\""), false),
    ] {
        let tmp = tempfile::tempdir().unwrap();
        std::fs::write(
            tmp.path().join("h.npy"),
            viscoslide::io::npy::encode_f64(&[32, 32], &map.heights),
        )
        .unwrap();
        let args: Vec<&str> = extra.iter().flat_map(|e| ["--set", *e]).collect();
        let (ok, _, stderr) = run(tmp.path(), &config, &args);
        assert!(ok, "{stderr}");
        let s: serde_json::Value = serde_json::from_str(
            &std::fs::read_to_string(tmp.path().join("out/summary.json")).unwrap(),
        )
        .unwrap();
        let warning = s["warnings"].as_array().unwrap().iter().any(|w| {
            w.as_str().unwrap().contains(
                "marked periodic ([surface] periodic = true) but is solved as a finite pad",
            )
        });
        assert_eq!(warning, warned, "{extra:?}: {}", s["warnings"]);
    }
}
