//! `viscoslide kernel`: JSON keys and values agree with the library, and bad
//! input is rejected with a one-line error.

use std::process::Command;
use viscoslide::response::SlidingResponse;

use viscoslide::internals::kernel::{Axis, SlidingKernel};
use viscoslide::material::{CreepSpectrum, Material};

const CONFIG: &str = "[material]\nmodel = \"sls\"\nrelaxed_modulus = 2e6\nglassy_modulus = 1e7\ncreep_time = 0.01\npoisson = 0.5\n";

/// `viscoslide kernel --config PATH ARGS --json`, parsed.
fn kernel_json(path: &std::path::Path, args: &[&str]) -> serde_json::Value {
    let out = Command::new(env!("CARGO_BIN_EXE_viscoslide"))
        .args(["kernel", "--config"])
        .arg(path)
        .args(args)
        .arg("--json")
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).unwrap()
}

#[test]
fn json_output_matches_the_library() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("c.toml");
    std::fs::write(&path, CONFIG).unwrap();
    let v = kernel_json(
        &path,
        &[
            "--cell-size",
            "1e-3",
            "--speed",
            "0.3",
            "--offset",
            "0,0",
            "--offset",
            "-2,1",
        ],
    );
    let rows = v.as_array().unwrap();
    assert_eq!(rows.len(), 2);
    let m = Material::new(
        CreepSpectrum::standard_linear_solid(2e6, 1e7, 0.01).unwrap(),
        0.5,
    )
    .unwrap();
    let k = SlidingKernel::new(&SlidingResponse::new(&m, 0.3, 0.0, None).unwrap()).unwrap();
    let r = &rows[1];
    assert_eq!(r["i"], -2);
    assert_eq!(r["j"], 1);
    let c = k.coefficient(-2e-3, 1e-3, 1e-3, 1e-3);
    // serde_json's default float parser may be one ulp off.
    let close = |key: &str, want: f64| {
        let got = r[key].as_f64().unwrap();
        assert!(
            (got - want).abs() <= 1e-15 * want.abs(),
            "{key}: {got} {want}"
        );
    };
    close("K", c.total());
    close("K_elastic", c.elastic);
    close("K_viscoelastic", c.viscoelastic);
    close("dK_dx", k.derivative(-2e-3, 1e-3, 1e-3, 1e-3, Axis::X));

    // Rectangular cells: offsets in units of each side, the library's
    // coefficient of the 1e-3 x 4e-4 cell.
    let v = kernel_json(
        &path,
        &[
            "--cell-size",
            "1e-3",
            "--cell-size-y",
            "4e-4",
            "--speed",
            "0.3",
            "--offset",
            "-2,1",
        ],
    );
    let r = &v.as_array().unwrap()[0];
    let c = k.coefficient(-2e-3, 4e-4, 1e-3, 4e-4);
    let got = r["K"].as_f64().unwrap();
    assert!(
        (got - c.total()).abs() <= 1e-15 * c.total().abs(),
        "{got} {c:?}"
    );
    let d = k.derivative(-2e-3, 4e-4, 1e-3, 4e-4, Axis::X);
    let got = r["dK_dx"].as_f64().unwrap();
    assert!((got - d).abs() <= 1e-15 * d.abs(), "{got} {d}");
}

#[test]
fn bad_input_is_reported() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("c.toml");
    std::fs::write(&path, CONFIG).unwrap();
    for extra in [
        vec!["--speed", "-1", "--cell-size", "1e-3"],
        vec!["--speed", "1", "--cell-size", "0"],
        vec![
            "--speed",
            "1",
            "--cell-size",
            "1e-3",
            "--set",
            "layer.thickness=-1",
            "--set",
            "layer.base=bonded",
        ],
        // --collocation is a layer's rule: refused without one, not ignored.
        vec!["--speed", "1", "--cell-size", "1e-3", "--collocation"],
    ] {
        let out = Command::new(env!("CARGO_BIN_EXE_viscoslide"))
            .args(["kernel", "--config"])
            .arg(&path)
            .args(["--offset", "0,0"])
            .args(&extra)
            .output()
            .unwrap();
        assert!(!out.status.success(), "{extra:?}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.trim().lines().count() == 1, "{err}");
        if extra.contains(&"--collocation") {
            assert!(
                err.contains("--collocation") && err.contains("[layer]"),
                "{err}"
            );
        }
    }
}

/// Cells so far from a contact's scales that a coefficient is not finite
/// (the far field's powers of the cell underflow or overflow) are refused
/// in one line naming the cell size, as JSON and as a table, not printed
/// as `NaN` or `null`; the glassy limit `--speed inf` is a speed.
#[test]
fn a_coefficient_that_is_not_finite_is_refused_naming_the_cell_size() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("c.toml");
    std::fs::write(&path, CONFIG).unwrap();
    for (cell, json) in [("1e-300", false), ("1e200", true), ("1e-300", true)] {
        let mut cmd = Command::new(env!("CARGO_BIN_EXE_viscoslide"));
        cmd.args(["kernel", "--config"]).arg(&path).args([
            "--cell-size",
            cell,
            "--speed",
            "0.01",
            "--offset",
            "0,0",
        ]);
        if json {
            cmd.arg("--json");
        }
        let out = cmd.output().unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{cell}: {err}");
        assert!(
            out.stdout.is_empty(),
            "{}",
            String::from_utf8_lossy(&out.stdout)
        );
        assert_eq!(err.trim().lines().count(), 1, "{err}");
        assert!(
            err.contains(&format!("the cell size {cell} m is beyond the range")),
            "{err}"
        );
    }
    let glassy = kernel_json(
        &path,
        &["--cell-size", "1e-3", "--speed", "inf", "--offset", "0,0"],
    );
    let k = &glassy[0];
    assert_eq!(k["K_viscoelastic"].as_f64(), Some(0.0));
    assert!(k["K"].as_f64().unwrap() > 0.0);
}

#[test]
fn loading_temperature_shifts_the_kernel_by_its_speed() {
    // physics.md section 12: E(w, T) = E(a_T w, T_ref), so the kernel of a
    // config at T and speed v is the kernel at T_ref and speed a_T v.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("c.toml");
    std::fs::write(&path, format!("{CONFIG}wlf = [8.86, 101.6, 17.0]\n")).unwrap();
    let args = |speed: &str, set: &[&str]| -> Vec<String> {
        let mut a: Vec<String> = ["--cell-size", "1e-3", "--speed", speed, "--offset", "1,0"]
            .iter()
            .map(|s| s.to_string())
            .collect();
        for s in set {
            a.extend(["--set".to_string(), s.to_string()]);
        }
        a
    };
    let run = |a: Vec<String>| {
        let a: Vec<&str> = a.iter().map(String::as_str).collect();
        kernel_json(&path, &a)[0].clone()
    };
    let log10_a = -8.86 * 20.0 / (101.6 + 20.0);
    let a_t = 10f64.powf(log10_a);
    let warm = run(args("0.3", &["loading.temperature=37"]));
    let reference = run(args(&format!("{:e}", 0.3 * a_t), &[]));
    let unshifted = run(args("0.3", &[]));
    for key in ["K", "K_viscoelastic", "dK_dx"] {
        let (w, r) = (
            warm[key].as_f64().unwrap(),
            reference[key].as_f64().unwrap(),
        );
        assert!((w - r).abs() <= 1e-12 * r.abs(), "{key}: {w} against {r}");
        let u = unshifted[key].as_f64().unwrap();
        assert!(
            (w - u).abs() > 1e-3 * u.abs(),
            "{key}: the temperature was ignored"
        );
    }
    // A temperature beyond the WLF range is refused as the solve refuses it.
    let out = Command::new(env!("CARGO_BIN_EXE_viscoslide"))
        .args(["kernel", "--config"])
        .arg(&path)
        .args(args("0.3", &["loading.temperature=-200"]))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(err.contains("temperature") && err.contains("-200"), "{err}");
    assert_eq!(err.trim().lines().count(), 1, "{err}");
}
