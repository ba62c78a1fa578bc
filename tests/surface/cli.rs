//! `viscoslide surface ...` end to end.

use std::path::Path;
use std::process::Command;

use viscoslide::surface::{generate, GenerateParams, Normalisation, UpperCutoff};

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

#[test]
fn generate_writes_four_files_and_records_seed() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("run");
    let o = viscoslide(&[
        "surface",
        "generate",
        "--n",
        "96",
        "--length",
        "0.01",
        "--hurst",
        "0.8",
        "--scales",
        "32",
        "--rms-height",
        "1e-5",
        "--seed",
        "7",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(
        files(&out),
        ["heights.npy", "psd.csv", "psd.png", "surface.json"]
    );
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("surface.json")).unwrap()).unwrap();
    assert_eq!(json["seed"], 7);
    assert_eq!(json["version"], viscoslide::VERSION);
    assert_eq!(json["params"]["hurst"], 0.8);
    let rms = json["stats"]["rms_height"].as_f64().unwrap();
    assert!((rms / 1e-5 - 1.0).abs() < 1e-12, "{rms}");
    // The heights are the library's, bit for bit.
    let lib = generate(&GenerateParams {
        nx: 96,
        ny: 96,
        length: 0.01,
        hurst: 0.8,
        upper: UpperCutoff::Scales(32.0),
        normalisation: Normalisation::RmsHeight(1e-5),
        seed: 7,
        ..GenerateParams::default()
    })
    .unwrap();
    let a = viscoslide::io::npy::read(out.join("heights.npy")).unwrap();
    assert_eq!(a.shape, vec![96, 96]);
    assert!(a
        .data
        .iter()
        .zip(&lib.heights)
        .all(|(x, y)| x.to_bits() == y.to_bits()));
    // psd.csv: header and three numeric columns.
    let csv = std::fs::read_to_string(out.join("psd.csv")).unwrap();
    let mut lines = csv.lines();
    assert_eq!(lines.next().unwrap(), "q_per_m,c_radial_m4,c_target_m4");
    let row: Vec<f64> = lines
        .next()
        .unwrap()
        .split(',')
        .map(|t| t.parse().unwrap())
        .collect();
    assert_eq!(row.len(), 3);

    // Stats of the written file, as JSON: one period of a periodic
    // surface, taken as it is (no plane removed, no window).
    let o = viscoslide(&[
        "surface",
        "stats",
        out.join("heights.npy").to_str().unwrap(),
        "--length",
        "0.01",
        "--periodic",
        "--json",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let s: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(s["stats"]["nx"], 96);
    let rms2 = s["stats"]["rms_height_real"].as_f64().unwrap();
    assert!((rms2 / rms - 1.0).abs() < 1e-12);
}

#[test]
fn generate_from_config_with_overrides() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = tmp.path().join("c.toml");
    std::fs::write(
        &cfg,
        "[surface.generate]\nn = 64\nlength = 0.01\nhurst = 0.6\nscales = 16\nrms_slope = 0.1\nseed = 1\nanisotropy = { ratio = 2.0, angle_deg = 45.0 }\n",
    )
    .unwrap();
    let out = tmp.path().join("run");
    let o = viscoslide(&[
        "surface",
        "generate",
        "--config",
        cfg.to_str().unwrap(),
        "--set",
        "surface.generate.seed=9",
        "--rms-height",
        "2e-6",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("surface.json")).unwrap()).unwrap();
    assert_eq!(json["seed"], 9);
    // The flag replaced the config's rms_slope.
    assert_eq!(json["params"]["normalisation"]["rms_height"], 2e-6);
    assert_eq!(json["params"]["anisotropy"]["ratio"], 2.0);
    assert_eq!(json["config"]["document"]["surface"]["generate"]["seed"], 9);
    // A stretch of 2 at 45 deg is held (ratio 0.5 asked), unwarned.
    let held = json["slope_ratio"].as_f64().unwrap();
    assert!((held / 0.5 - 1.0).abs() < 0.1, "{held}");
    assert_eq!(json["warnings"], serde_json::json!([]));

    // A stretch beyond q1 / q_L = 16 along x leaves a ridged surface: the
    // command and a solve on it say so, in their JSON and on stderr.
    let ridged = tmp.path().join("ridged");
    let stretch = "surface.generate.anisotropy={ ratio = 20.0, angle_deg = 0.0 }";
    let o = viscoslide(&[
        "surface",
        "generate",
        "--config",
        cfg.to_str().unwrap(),
        "--set",
        stretch,
        "--out",
        ridged.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(
        stderr.contains("warning: anisotropy.ratio = 20") && stderr.contains("ridged"),
        "{stderr}"
    );
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(ridged.join("surface.json")).unwrap()).unwrap();
    assert_eq!(json["slope_ratio"], 0.0);
    assert!(
        json["warnings"][0].as_str().unwrap().contains("ridged"),
        "{json}"
    );
    let solve_cfg = tmp.path().join("solve.toml");
    std::fs::write(
        &solve_cfg,
        format!(
            "{}[material]\nmodel = \"sls\"\nrelaxed_modulus = 3.3e6\nglassy_modulus = 1e7\ncreep_time = 0.01\n[loading]\nmean_pressure = 1e5\nspeed = 1e-3\n[analysis]\nenabled = false\n",
            std::fs::read_to_string(&cfg).unwrap()
        ),
    )
    .unwrap();
    let run = tmp.path().join("solved");
    let o = viscoslide(&[
        "solve",
        solve_cfg.to_str().unwrap(),
        "--set",
        stretch,
        "--backend",
        "cpu",
        "--out",
        run.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let summary: serde_json::Value =
        serde_json::from_slice(&std::fs::read(run.join("summary.json")).unwrap()).unwrap();
    let warnings = summary["warnings"].as_array().unwrap();
    assert!(
        warnings
            .iter()
            .any(|w| w.as_str().unwrap().contains("ridged")),
        "{warnings:?}"
    );
}

/// A bad input fails with a one-line error and leaves no output directory.
#[test]
fn bad_inputs_write_nothing() {
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    let mut nan = vec![0.0; 16];
    nan[5] = f64::NAN;
    std::fs::write(
        d.join("nan.npy"),
        viscoslide::io::npy::encode_f64(&[4, 4], &nan),
    )
    .unwrap();
    std::fs::write(d.join("ragged.txt"), "1 2\n3\n").unwrap();
    let cases: Vec<Vec<String>> = vec![
        vec![
            "surface".into(),
            "stats".into(),
            d.join("nan.npy").display().to_string(),
            "--length".into(),
            "0.01".into(),
        ],
        vec![
            "surface".into(),
            "stats".into(),
            d.join("ragged.txt").display().to_string(),
            "--length".into(),
            "0.01".into(),
        ],
        vec![
            "surface".into(),
            "stats".into(),
            d.join("nan.npy").display().to_string(),
            "--length".into(),
            "-1".into(),
        ],
        "surface generate --n 4 --length 0.01 --hurst 0.8 --scales 2 --rms-height 1e-5"
            .split(' ')
            .map(String::from)
            .collect(),
        "surface generate --n 64 --length 0.01 --hurst 0.8 --scales 64 --rms-height 1e-5"
            .split(' ')
            .map(String::from)
            .collect(),
        "surface generate --n 64 --length 0.01 --hurst 0.8 --scales 8"
            .split(' ')
            .map(String::from)
            .collect(),
    ];
    for (k, mut args) in cases.into_iter().enumerate() {
        let out = d.join(format!("out{k}"));
        args.push("--out".into());
        args.push(out.display().to_string());
        let refs: Vec<&str> = args.iter().map(String::as_str).collect();
        let o = viscoslide(&refs);
        let err = String::from_utf8_lossy(&o.stderr);
        eprintln!("{}: {}", args[1], err.trim());
        assert!(!o.status.success(), "{args:?} should fail");
        assert_eq!(err.trim().lines().count(), 1, "one line: {err}");
        assert!(err.starts_with("error: "), "{err}");
        assert!(!out.exists(), "{} was created", out.display());
    }
}

/// A strip whose shorter side holds fewer than 12 pixels has no trusted
/// PSD band and is warned about (it printed an inverted band without a
/// word); a flat map's PSD cannot be drawn, so `--out` is refused in one
/// line with nothing written, and its statistics print without it.
#[test]
fn a_narrow_strip_and_a_flat_map_are_named() {
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    let strip: Vec<f64> = (0..128 * 8)
        .map(|k| 1e-6 * ((k * 7919 % 1013) as f64 / 1013.0 - 0.5))
        .collect();
    std::fs::write(
        d.join("strip.npy"),
        viscoslide::io::npy::encode_f64(&[128, 8], &strip),
    )
    .unwrap();
    std::fs::write(
        d.join("flat.npy"),
        viscoslide::io::npy::encode_f64(&[32, 32], &[3e-6; 1024]),
    )
    .unwrap();
    let path = |f: &str| d.join(f).to_str().unwrap().to_string();
    let o = viscoslide(&["surface", "stats", &path("strip.npy"), "--length", "0.01"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(
        err.contains("128 x 8 map's shorter side is too short for a trusted band"),
        "{err}"
    );
    let out = d.join("flat_out");
    let o = viscoslide(&[
        "surface",
        "stats",
        &path("flat.npy"),
        "--length",
        "0.005",
        "--out",
        out.to_str().unwrap(),
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        !o.status.success() && err.contains("the map is flat after detrending"),
        "{err}"
    );
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(!out.exists());
    let o = viscoslide(&["surface", "stats", &path("flat.npy"), "--length", "0.005"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

/// `[surface]` keys that describe a file are refused beside
/// `[surface.generate]` by `surface generate --config`, as a solve and
/// `persson` refuse them, instead of being ignored.
#[test]
fn generate_from_config_refuses_the_keys_of_a_file() {
    let tmp = tempfile::tempdir().unwrap();
    let base =
        "[surface.generate]\nn = 32\nlength = 0.01\nhurst = 0.8\nscales = 8\nrms_slope = 0.02\n";
    for (key, needle) in [
        (
            "length_y = 0.02",
            "[surface] length_y = 0.02 applies to a surface `file` only",
        ),
        (
            "periodic = true",
            "[surface] periodic apply to a surface `file`",
        ),
        (
            "detrend = \"none\"",
            "[surface] detrend apply to a surface `file`",
        ),
        (
            "window = \"hann\"",
            "[surface] window apply to a surface `file`",
        ),
        (
            "format = \"npy\"",
            "[surface] format apply to a surface `file`",
        ),
        (
            "fill_missing = true",
            "[surface] fill_missing apply to a surface `file`",
        ),
    ] {
        let cfg = tmp.path().join("c.toml");
        std::fs::write(&cfg, format!("[surface]\n{key}\n{base}")).unwrap();
        let out = tmp.path().join("run");
        let o = viscoslide(&[
            "surface",
            "generate",
            "--config",
            cfg.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success(), "{key} was ignored");
        assert!(err.contains(needle), "{key}: {err}");
        assert_eq!(err.trim().lines().count(), 1, "{err}");
        assert!(!out.exists(), "{key}: output written");
    }
}
