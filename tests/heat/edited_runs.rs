//! `viscoslide heat --from-run` on a run directory edited by hand: values
//! the heat cannot use are refused in one line naming the file and the
//! value, writing nothing, instead of an answer that misleads.

use std::path::Path;
use std::process::Output;

use viscoslide::io::npy;

use super::cli::viscoslide;

/// A solved 16^2 periodic SLS cell in `dir/run`; returns its path.
fn solved_run(dir: &Path) -> String {
    let cfg = dir.join("cell.toml");
    std::fs::write(
        &cfg,
        "[material]\nmodel = \"sls\"\nrelaxed_modulus = 3.3e6\nglassy_modulus = 1e7\ncreep_time = 0.01\n\n[surface.generate]\nn = 16\nlength = 1e-3\nhurst = 0.8\nscales = 3\nrms_slope = 0.05\nseed = 2\n\n[loading]\nmean_pressure = 2e4\nspeed = 3e-3\n\n[solver]\nformulation = \"periodic\"\n\n[analysis]\nenabled = false\n",
    )
    .unwrap();
    let run = dir.join("run");
    let o = viscoslide(&[
        "solve",
        cfg.to_str().unwrap(),
        "--backend",
        "cpu",
        "--out",
        run.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    run.display().to_string()
}

/// `viscoslide heat --from-run run --out dir/out` with `extra`.
fn heat(run: &str, out: &Path, extra: &[&str]) -> Output {
    let mut args = vec![
        "heat",
        "--from-run",
        run,
        "--conductivity",
        "0.25",
        "--diffusivity",
        "1e-7",
        "--out",
        out.to_str().unwrap(),
    ];
    args.extend(extra);
    viscoslide(&args)
}

/// The refusal of `o`: exit 1, one line holding `word`, nothing at `out`.
fn refused(o: &Output, out: &Path, word: &str) {
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(err.contains(word), "'{err}' lacks '{word}'");
    assert!(!out.exists(), "{} was written", out.display());
}

/// Pressures edited to 1e200 times the solve's: the dissipation (their
/// squares) and the surface work leave f64. Before, the source's NaN
/// total read as "the contact dissipates nothing", every rise zero and
/// `heat_total_w: null` written; now it is refused, for either source.
#[test]
fn a_heat_source_beyond_f64_is_refused_not_read_as_no_heat() {
    let dir = tempfile::tempdir().unwrap();
    let run = solved_run(dir.path());
    let path = Path::new(&run).join("pressure.npy");
    let (nx, ny, p) = npy::read_2d(&path).unwrap();
    let huge: Vec<f64> = p.iter().map(|v| v * 1e200).collect();
    std::fs::write(&path, npy::encode_f64(&[nx, ny], &huge)).unwrap();
    for source in ["volume", "surface"] {
        let out = dir.path().join(source);
        let o = heat(&run, &out, &["--source", source]);
        refused(&o, &out, "beyond the range of f64");
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(err.contains(&format!("the {source} heat source")), "{err}");
    }
}

/// A `cell_size_y` edited into something other than a number (a string
/// such as "2e-6", a list) was taken as absent: the heat ran on square
/// cells of `cell_size`, silently. Now it is refused naming the key; so
/// is a `mesh` that is neither null nor a mesh's report (`false` was
/// refused as an adaptive-mesh solve).
#[test]
fn a_cell_size_y_or_mesh_that_is_not_what_it_names_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let run = solved_run(dir.path());
    let path = Path::new(&run).join("summary.json");
    let original: serde_json::Value =
        serde_json::from_slice(&std::fs::read(&path).unwrap()).unwrap();
    for (k, value) in [serde_json::json!("2e-6"), serde_json::json!([2e-6])]
        .into_iter()
        .enumerate()
    {
        let mut doc = original.clone();
        doc["cell_size_y"] = value;
        std::fs::write(&path, serde_json::to_vec(&doc).unwrap()).unwrap();
        let out = dir.path().join(format!("out{k}"));
        refused(&heat(&run, &out, &[]), &out, "`cell_size_y` = ");
    }
    // A `mesh` edited to something that is not a mesh's report is named
    // as the edit it is, not as an adaptive-mesh solve.
    for (k, value) in [serde_json::json!(false), serde_json::json!("none")]
        .into_iter()
        .enumerate()
    {
        let mut doc = original.clone();
        doc["mesh"] = value;
        std::fs::write(&path, serde_json::to_vec(&doc).unwrap()).unwrap();
        let out = dir.path().join(format!("mesh{k}"));
        let o = heat(&run, &out, &[]);
        refused(&o, &out, "`mesh` = ");
        assert!(!String::from_utf8_lossy(&o.stderr).contains("adaptive-mesh solve"));
    }
    // Absent, the cells are square, as before.
    let mut doc = original.clone();
    doc.as_object_mut().unwrap().remove("cell_size_y");
    std::fs::write(&path, serde_json::to_vec(&doc).unwrap()).unwrap();
    let o = heat(&run, &dir.path().join("square"), &[]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

/// A friction edited to zero or below (`normal_load` 0, a negative
/// `friction_coefficient_dissipation`) against a source that carries
/// heat: the energy balance (`+inf`, `-2.1`) is noted as not belonging
/// together, as any balance off by more than 1 % is. Before, a friction
/// power that was not positive was never noted.
#[test]
fn a_friction_power_edited_to_zero_or_below_is_noted() {
    let dir = tempfile::tempdir().unwrap();
    let run = solved_run(dir.path());
    let path = Path::new(&run).join("summary.json");
    let original: serde_json::Value =
        serde_json::from_slice(&std::fs::read(&path).unwrap()).unwrap();
    for (k, (key, value)) in [
        ("normal_load", 0.0),
        ("friction_coefficient_dissipation", -0.1),
    ]
    .into_iter()
    .enumerate()
    {
        let mut doc = original.clone();
        doc[key] = serde_json::json!(value);
        std::fs::write(&path, serde_json::to_vec(&doc).unwrap()).unwrap();
        let out = dir.path().join(format!("out{k}"));
        let o = heat(&run, &out, &["--block-length", "0.01"]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(o.status.success(), "{err}");
        assert!(err.contains("do not belong together"), "{key}: {err}");
        let report: serde_json::Value =
            serde_json::from_slice(&std::fs::read(out.join("heat.json")).unwrap()).unwrap();
        let notes = report["notes"].as_array().unwrap();
        assert!(
            notes
                .iter()
                .any(|n| n.as_str().unwrap().contains("do not belong together")),
            "{key}: {notes:?}"
        );
    }
}
