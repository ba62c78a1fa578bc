//! `viscoslide surface resample`: square pixels from a scan with
//! non-square ones, what it reports, and its refusals.

use std::path::Path;
use std::process::Command;

use viscoslide::surface::{encode_x3p, read_topography, ReadOptions, Topography, X3pType};

fn viscoslide(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_viscoslide"))
        .args(args)
        .output()
        .unwrap()
}

/// Smooth and asymmetric [m], for positions in m.
fn surface(x: f64, y: f64) -> f64 {
    1e-7 * ((2.1e4 * x + 0.4).sin() * (0.9e4 * y - 0.3).cos() + 2e4 * x)
}

/// 60 x 24 pixels of 1 um x 2.5 um (a 60 um square).
fn scan() -> Topography {
    let (nx, ny, dx, dy) = (60, 24, 1e-6, 2.5e-6);
    let h = (0..nx * ny)
        .map(|k| surface(((k / ny) as f64 + 0.5) * dx, ((k % ny) as f64 + 0.5) * dy))
        .collect();
    Topography::new(nx, ny, dx, dy, h, "scan").unwrap()
}

#[test]
fn resample_gives_square_pixels_and_says_what_it_did() {
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    let input = d.join("scan.x3p");
    std::fs::write(&input, encode_x3p(&scan(), X3pType::F64, None).unwrap()).unwrap();
    let out = d.join("square");
    let o = viscoslide(&[
        "surface",
        "resample",
        input.to_str().unwrap(),
        "--pixel",
        "1.25e-6",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(
        stdout.contains("60 x 24 points") && stdout.contains("48 x 48 points"),
        "{stdout}"
    );
    let t = read_topography(&out.join("heights.x3p"), &ReadOptions::default()).unwrap();
    assert_eq!((t.nx, t.ny), (48, 48));
    assert!((t.dx / 1.25e-6 - 1.0).abs() < 1e-12 && (t.dy / 1.25e-6 - 1.0).abs() < 1e-12);
    // The spline error on this surface (wavelengths of 300 and 700 um,
    // pixels of 1 and 2.5 um) is below 1e-5 of its amplitude; x stays
    // along axis 0.
    for k in 0..t.nx * t.ny {
        let (x, y) = (
            ((k / t.ny) as f64 + 0.5) * t.dx,
            ((k % t.ny) as f64 + 0.5) * t.dy,
        );
        assert!((t.heights[k] - surface(x, y)).abs() < 1e-12, "{k}");
    }
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("resample.json")).unwrap()).unwrap();
    assert_eq!(json["method"], "spline");
    assert_eq!(json["from"]["shape"], serde_json::json!([60, 24]));
    assert_eq!(json["to"]["shape"], serde_json::json!([48, 48]));
    assert_eq!(json["to"]["pixel_m"][1].as_f64(), Some(1.25e-6));

    // Fourier to a number of points, written as .npy.
    let out2 = d.join("fourier");
    let o = viscoslide(&[
        "surface",
        "resample",
        input.to_str().unwrap(),
        "--n",
        "30,30",
        "--method",
        "fourier",
        "--output-format",
        "npy",
        "--out",
        out2.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let t = read_topography(
        &out2.join("heights.npy"),
        &ReadOptions {
            length: Some(60e-6),
            ..Default::default()
        },
    )
    .unwrap();
    assert_eq!((t.nx, t.ny), (30, 30));
}

#[test]
fn resample_refuses_bad_input_in_one_line_and_writes_nothing() {
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    let input = d.join("scan.x3p");
    std::fs::write(&input, encode_x3p(&scan(), X3pType::F64, None).unwrap()).unwrap();
    let mut holes = scan();
    holes.heights[100] = f64::NAN;
    let holed = d.join("holes.x3p");
    std::fs::write(&holed, encode_x3p(&holes, X3pType::F64, None).unwrap()).unwrap();
    let p = |n: &str| d.join(n).display().to_string();
    let i = input.to_str().unwrap();
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (vec![i, "--pixel", "0"], "pixel size along x"),
        (vec![i, "--pixel", "1e-6,-1e-6"], "pixel size along y"),
        (vec![i, "--pixel", "1e-11"], "2^28"),
        (vec![i, "--n", "100000,100000"], "2^28"),
        (vec![i, "--pixel", "abc"], "not a number"),
        (
            vec![i, "--pixel", "1e-6", "--method", "linear"],
            "spline or fourier",
        ),
        (
            vec![holed.to_str().unwrap(), "--pixel", "1e-6"],
            "--fill-missing",
        ),
    ];
    for (k, (args, want)) in cases.iter().enumerate() {
        let out = p(&format!("out{k}"));
        let mut all = vec!["surface", "resample"];
        all.extend(args);
        all.extend(["--out", &out]);
        let o = viscoslide(&all);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success(), "{args:?}");
        assert_eq!(err.trim().lines().count(), 1, "{args:?}: {err}");
        assert!(err.contains(want), "{args:?}: {err}");
        assert!(!Path::new(&out).exists(), "{args:?}");
    }
    // With --fill-missing the holed scan resamples.
    let o = viscoslide(&[
        "surface",
        "resample",
        holed.to_str().unwrap(),
        "--pixel",
        "1e-6",
        "--fill-missing",
        "--out",
        &p("filled"),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(d.join("filled/resample.json")).unwrap()).unwrap();
    assert!(
        json["missing"].as_str().unwrap().contains("filled"),
        "{json}"
    );
}

/// `--n 30` is 30 x 30 points: said on stdout and in `resample.json`.
/// `--method fourier` on a scan (its opposite edges do not meet) warns
/// that the map is taken as a period and rings at its edges, on stderr
/// and in `resample.json`; on a periodic map it does not.
#[test]
fn a_single_n_is_stated_and_fourier_on_a_scan_is_warned_about() {
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    let input = d.join("scan.x3p");
    std::fs::write(&input, encode_x3p(&scan(), X3pType::F64, None).unwrap()).unwrap();
    // One period of a smooth periodic surface on the scan's pixels.
    let (nx, ny, dx, dy) = (60, 24, 1e-6, 2.5e-6);
    let tau = 2.0 * std::f64::consts::PI;
    let h = (0..nx * ny)
        .map(|k| {
            let (x, y) = (
                ((k / ny) as f64 + 0.5) / nx as f64,
                ((k % ny) as f64 + 0.5) / ny as f64,
            );
            1e-7 * ((tau * x).sin() * (2.0 * tau * y).cos() + 0.3 * (tau * (x + y)).cos())
        })
        .collect();
    let period = d.join("period.x3p");
    let p = Topography::new(nx, ny, dx, dy, h, "period").unwrap();
    std::fs::write(&period, encode_x3p(&p, X3pType::F64, None).unwrap()).unwrap();
    let read = |out: &Path| -> serde_json::Value {
        serde_json::from_slice(&std::fs::read(out.join("resample.json")).unwrap()).unwrap()
    };
    for (file, method, ringing) in [
        (&input, "fourier", true),
        (&input, "spline", false),
        (&period, "fourier", false),
    ] {
        let out = d.join(format!(
            "{}-{method}",
            file.file_stem().unwrap().to_string_lossy()
        ));
        let o = viscoslide(&[
            "surface",
            "resample",
            file.to_str().unwrap(),
            "--n",
            "30",
            "--method",
            method,
            "--out",
            out.to_str().unwrap(),
        ]);
        let (stdout, stderr) = (
            String::from_utf8_lossy(&o.stdout),
            String::from_utf8_lossy(&o.stderr),
        );
        assert!(o.status.success(), "{stderr}");
        let said = "--n 30: 30 x 30 points (one value: the same along x and y)";
        assert!(stdout.contains(said), "{stdout}");
        let json = read(&out);
        assert_eq!(json["requested"], said, "{json}");
        assert_eq!(json["to"]["shape"], serde_json::json!([30, 30]));
        let warned = json["warnings"]
            .as_array()
            .unwrap()
            .iter()
            .any(|w| w.as_str().unwrap().contains("opposite edges do not meet"));
        assert_eq!(warned, ringing, "{method} {}: {json}", file.display());
        assert_eq!(
            stderr.contains("warning: Fourier interpolation takes the map as one period"),
            ringing,
            "{stderr}"
        );
    }
    // Two values are taken as given, without the note.
    let out = d.join("two");
    let o = viscoslide(&[
        "surface",
        "resample",
        input.to_str().unwrap(),
        "--n",
        "30,20",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success());
    assert_eq!(read(&out)["requested"], "--n 30,20: 30 x 20 points");
}
