//! `viscoslide heat` as a user meets it: the three files, the map read
//! back with the input's shape and orientation (equal to the library's
//! rise), the report's numbers, and refusals that write nothing.

use std::path::Path;
use std::process::{Command, Output};
use viscoslide::response::Grid;

use viscoslide::heat::{surface_temperature, Conduction, HeatDomain, HeatSetup};
use viscoslide::io::npy;

pub(super) fn viscoslide(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_viscoslide"))
        .args(args)
        .output()
        .unwrap()
}

/// A 12 x 7 flux map with one hot spot off the middle, written as .npy.
fn write_flux(dir: &Path) -> (String, Vec<f64>) {
    let (nx, ny) = (12, 7);
    let mut flux = vec![0.0; nx * ny];
    flux[8 * ny + 2] = 4e6;
    flux[8 * ny + 3] = 2e6;
    let path = dir.join("flux.npy");
    std::fs::write(&path, npy::encode_f64(&[nx, ny], &flux)).unwrap();
    (path.display().to_string(), flux)
}

fn json(path: &Path) -> serde_json::Value {
    serde_json::from_slice(&std::fs::read(path).unwrap()).unwrap()
}

#[test]
fn heat_writes_the_map_the_figure_and_the_report() {
    let tmp = tempfile::tempdir().unwrap();
    let (flux_path, flux) = write_flux(tmp.path());
    let out = tmp.path().join("out");
    let o = viscoslide(&[
        "heat",
        &flux_path,
        "--cell-size",
        "2e-6",
        "--cell-size-y",
        "3e-6",
        "--speed",
        "0.05",
        "--conductivity",
        "0.25",
        "--diffusivity",
        "1e-7",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    for f in ["temperature.npy", "temperature.png", "heat.json"] {
        assert!(out.join(f).is_file(), "{f} missing");
    }
    let (nx, ny, rise) = npy::read_2d(out.join("temperature.npy")).unwrap();
    assert_eq!((nx, ny), (12, 7));
    let setup = HeatSetup {
        grid: Grid::new(nx, ny, (2e-6, 3e-6)).unwrap(),
        conduction: Conduction {
            conductivity: 0.25,
            diffusivity: 1e-7,
        },
        speed: 0.05,
        direction_rad: 0.0,
        domain: HeatDomain::Pad,
    };
    let want = surface_temperature(setup, &flux).unwrap();
    assert_eq!(rise, want.rise);
    // The hottest cell is the hot spot's row (axis 0 = x), and it is
    // warmer behind it (smaller x) than ahead.
    let hottest = (0..rise.len())
        .max_by(|&a, &b| rise[a].total_cmp(&rise[b]))
        .unwrap();
    assert_eq!(hottest / ny, 8, "{hottest}");
    assert!(rise[7 * ny + 2] > rise[9 * ny + 2]);
    let doc = json(&out.join("heat.json"));
    assert_eq!(doc["grid"], serde_json::json!([12, 7]));
    assert_eq!(doc["formulation"], "non-periodic");
    let power = 6e6 * 2e-6 * 3e-6;
    assert!((doc["total_power_w"].as_f64().unwrap() / power - 1.0).abs() < 1e-14);
    assert!((doc["peclet_number"].as_f64().unwrap() / (0.05 * 2e-6 / 1e-7) - 1.0).abs() < 1e-14);
    // serde_json reads floats back to within an ulp.
    assert!((doc["max_rise_k"].as_f64().unwrap() / want.max() - 1.0).abs() < 1e-15);
    assert!(doc["background_rise_k"].is_null());
    assert_eq!(doc["notes"], serde_json::json!([]));

    // A periodic cell without a block length says so; with one it reports
    // the background.
    let out_dir = out.to_str().unwrap();
    let periodic = |speed: &str, extra: &[&str]| {
        let mut args = vec![
            "heat",
            &flux_path,
            "--cell-size",
            "2e-6",
            "--speed",
            speed,
            "--conductivity",
            "0.25",
            "--diffusivity",
            "1e-7",
            "--periodic",
            "--out",
            out_dir,
        ];
        args.extend(extra);
        let o = viscoslide(&args);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        (
            String::from_utf8_lossy(&o.stderr).into_owned(),
            json(&out.join("heat.json")),
        )
    };
    let (stderr, doc) = periodic("0.05", &[]);
    assert!(stderr.contains("block length"));
    assert_eq!(doc["formulation"], "periodic");
    assert!(doc["notes"][0]
        .as_str()
        .unwrap()
        .contains("no steady state"));
    assert!(
        doc["mean_rise_k"].as_f64().unwrap().abs() < 1e-12 * doc["max_rise_k"].as_f64().unwrap()
    );
    let block = ["--block-length", "0.01"];
    let (_, doc) = periodic("0.05", &[&block[..], &["--direction-deg", "90"]].concat());
    let qbar = 6e6 / 84.0;
    let want = 4.0 / 3.0 * qbar * (1e-7 * 0.01 / 0.05 / std::f64::consts::PI).sqrt() / 0.25;
    let got = doc["background_rise_k"].as_f64().unwrap();
    assert!((got / want - 1.0).abs() < 1e-12, "{got} vs {want}");
    assert!((doc["contact_time_s"].as_f64().unwrap() / 0.2 - 1.0).abs() < 1e-15);
    assert_eq!(doc["notes"], serde_json::json!([]));

    // At 100 m/s one passage (1e-4 s) diffuses heat over sqrt(1e-11) m =
    // 3.2 um, less than the 24 um period's depth 3.8 um over 0.3: the rise
    // is given, with a note on stderr and in the report.
    let (stderr, doc) = periodic("100", &block);
    assert!(
        stderr.contains("note: the cell's longest period"),
        "{stderr}"
    );
    let note = doc["notes"][0].as_str().unwrap();
    assert!(
        note.contains("take a smaller cell or a longer block"),
        "{note}"
    );
}

/// Each refusal: exit status 1, one line on stderr naming the problem,
/// and no output directory.
#[test]
fn refused_runs_write_nothing() {
    let tmp = tempfile::tempdir().unwrap();
    let (flux_path, flux) = write_flux(tmp.path());
    let mut nan = flux.clone();
    nan[5] = f64::NAN;
    let nan_path = tmp.path().join("nan.npy");
    std::fs::write(&nan_path, npy::encode_f64(&[12, 7], &nan)).unwrap();
    let empty_path = tmp.path().join("empty.npy");
    std::fs::write(&empty_path, npy::encode_f64(&[0, 7], &[])).unwrap();
    let flat_path = tmp.path().join("flat.npy");
    std::fs::write(&flat_path, npy::encode_f64(&[84], &flux)).unwrap();
    let out = tmp.path().join("out");
    let base = |file: &str, speed: &str, lam: &str, kappa: &str, cell: &str| -> Vec<String> {
        [
            "heat",
            file,
            "--cell-size",
            cell,
            "--speed",
            speed,
            "--conductivity",
            lam,
            "--diffusivity",
            kappa,
            "--out",
            out.to_str().unwrap(),
        ]
        .iter()
        .map(|s| s.to_string())
        .collect()
    };
    let nan_s = nan_path.to_str().unwrap();
    let empty_s = empty_path.to_str().unwrap();
    let flat_s = flat_path.to_str().unwrap();
    let cases: Vec<(Vec<String>, &[&str])> = vec![
        (
            base(&flux_path, "0", "0.25", "1e-7", "1e-6"),
            &["--speed 0", "positive"],
        ),
        (
            base(&flux_path, "-0.1", "0.25", "1e-7", "1e-6"),
            &["--speed -0.1"],
        ),
        (
            base(&flux_path, "0.1", "-0.25", "1e-7", "1e-6"),
            &["--conductivity -0.25", "W/(m K)"],
        ),
        (
            base(&flux_path, "0.1", "0.25", "0", "1e-6"),
            &["--diffusivity 0", "m^2/s"],
        ),
        (
            base(&flux_path, "0.1", "0.25", "1e-7", "0"),
            &["--cell-size 0"],
        ),
        (
            base(&flux_path, "0.1", "0.25", "1e-7", "nan"),
            &["--cell-size NaN"],
        ),
        (
            base(&flux_path, "0.1", "0.25", "1e-7", "1e-6")
                .into_iter()
                .chain(["--cell-size-y=-1e-6".into()])
                .collect(),
            &["--cell-size-y -0.000001"],
        ),
        (
            base(&flux_path, "0.1", "inf", "1e-7", "1e-6"),
            &["--conductivity inf"],
        ),
        (
            base(&flux_path, "0.1", "0.25", "1e-7", "1e-6")
                .into_iter()
                .chain(["--periodic", "--block-length", "-0.01"].map(String::from))
                .collect(),
            &["--block-length -0.01"],
        ),
        (
            base(nan_s, "0.1", "0.25", "1e-7", "1e-6"),
            &["NaN", "(0, 5)"],
        ),
        (
            base(empty_s, "0.1", "0.25", "1e-7", "1e-6"),
            &["0 x 7", "at least one cell"],
        ),
        (base(flat_s, "0.1", "0.25", "1e-7", "1e-6"), &["2-D"]),
        (
            base("missing.npy", "0.1", "0.25", "1e-7", "1e-6"),
            &["missing.npy"],
        ),
    ];
    for (args, words) in &cases {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let o = viscoslide(&args);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{args:?}: {err}");
        assert_eq!(err.trim().lines().count(), 1, "{args:?}: {err}");
        for w in *words {
            assert!(err.contains(w), "{args:?}: '{err}' lacks '{w}'");
        }
        assert!(!out.exists(), "{args:?} left {}", out.display());
    }
    // A block length needs a periodic cell (clap's refusal).
    let mut args = base(&flux_path, "0.1", "0.25", "1e-7", "1e-6");
    args.extend(["--block-length".to_string(), "0.01".to_string()]);
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let o = viscoslide(&args);
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("--periodic"));
    assert!(!out.exists());
    // A finite rise whose map's total power is beyond f64 (1e300 W/m^2 on
    // cells of 1e100 m, a conductivity of 1e300 W/(m K)) is refused
    // naming the power, not written as `"total_power_w": null` with exit
    // status 0; on cells of 1e-100 m the same flux is answered, its mean
    // (not NaN) and power numbers.
    let huge_path = tmp.path().join("huge.npy");
    let huge: Vec<f64> = flux.iter().map(|q| q * 1e294).collect();
    std::fs::write(&huge_path, npy::encode_f64(&[12, 7], &huge)).unwrap();
    let huge_s = huge_path.to_str().unwrap();
    let o = viscoslide(
        &base(huge_s, "0.1", "1e300", "1e100", "1e100")
            .iter()
            .map(String::as_str)
            .collect::<Vec<_>>(),
    );
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(
        err.contains("total power") && err.contains("beyond the range of f64"),
        "{err}"
    );
    assert!(!out.exists());
    let o = viscoslide(
        &base(huge_s, "0.1", "1e300", "1e-100", "1e-100")
            .iter()
            .map(String::as_str)
            .collect::<Vec<_>>(),
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let doc = json(&out.join("heat.json"));
    let mean = 6e300 / 84.0;
    assert!(
        (doc["mean_flux_w_per_m2"].as_f64().unwrap() / mean - 1.0).abs() < 1e-14,
        "{doc}"
    );
    assert!(
        (doc["total_power_w"].as_f64().unwrap() / (6e300 * 1e-200) - 1.0).abs() < 1e-14,
        "{doc}"
    );
    std::fs::remove_dir_all(&out).unwrap();
    // The options of --from-run's heat source are refused beside a flux
    // map, not ignored.
    for extra in [&["--source", "volume"][..], &["--refined-layers"][..]] {
        let mut args = base(&flux_path, "0.1", "0.25", "1e-7", "1e-6");
        args.extend(extra.iter().map(|s| s.to_string()));
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let o = viscoslide(&args);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{args:?}: {err}");
        assert_eq!(err.trim().lines().count(), 1, "{args:?}: {err}");
        assert!(
            err.contains(extra[0]) && err.contains("--from-run"),
            "{args:?}: {err}"
        );
        assert!(!out.exists(), "{args:?} left {}", out.display());
    }
}

/// `viscoslide heat --from-run DIR` on a periodic solve: the volume source
/// by default, its energy balance in heat.json within the default layers'
/// 1e-3 (refined: 1e-6), the surface source's within 1e-10 (the stencil's
/// own products); the map is the run's shape. On a pad run a block length
/// and a volume source are refused in one line, writing nothing.
#[test]
fn heat_from_a_solved_run() {
    let dir = tempfile::tempdir().unwrap();
    let solve = |formulation: &str| -> String {
        let cfg = dir.path().join(format!("{formulation}.toml"));
        std::fs::write(
            &cfg,
            format!(
                "[material]\nmodel = \"sls\"\nrelaxed_modulus = 3.3e6\nglassy_modulus = 1e7\ncreep_time = 0.01\n\n[surface.generate]\nn = 24\nlength = 1e-3\nhurst = 0.8\nscales = 4\nrms_slope = 0.05\nseed = 2\n\n[loading]\nmean_pressure = 2e4\nspeed = 3e-3\n\n[solver]\ntolerance = 1e-10\nformulation = \"{formulation}\"\n"
            ),
        )
        .unwrap();
        let run = dir.path().join(formulation);
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
    };
    let periodic = solve("periodic");
    let heat = |run: &str, out: &str, extra: &[&str]| -> Output {
        let out = dir.path().join(out);
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
    };
    for (out, extra, kind, tol) in [
        ("v", &["--block-length", "0.01"][..], "volume", 1e-3),
        ("vr", &["--refined-layers"][..], "volume", 1e-6),
        ("s", &["--source", "surface"][..], "surface", 1e-10),
    ] {
        let o = heat(&periodic, out, extra);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let doc = json(&dir.path().join(out).join("heat.json"));
        assert_eq!(doc["source"], kind);
        let balance = doc["energy_balance"].as_f64().unwrap();
        assert!(balance.abs() < tol, "{out}: {balance}");
        assert!(doc["friction_power_w"].as_f64().unwrap() > 0.0);
        assert!(doc["effective_rise_k"].as_f64().unwrap() > 0.0);
        let (nx, ny, t) = npy::read_2d(dir.path().join(out).join("temperature.npy")).unwrap();
        assert_eq!((nx, ny), (24, 24));
        assert!(t.iter().all(|v| v.is_finite()));
        assert!(dir.path().join(out).join("temperature.png").exists());
    }
    let pad = solve("non_periodic");
    let o = heat(&pad, "p", &[]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let doc = json(&dir.path().join("p").join("heat.json"));
    assert_eq!(doc["source"], "surface");
    assert!(doc["energy_balance"].as_f64().unwrap().abs() < 1e-10);
    for (extra, word) in [
        (&["--block-length", "0.01"][..], "block-length"),
        (&["--source", "volume"][..], "periodic cells only"),
        (&["--refined-layers"][..], "surface source has none"),
    ] {
        let o = heat(&pad, "refused", extra);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{err}");
        assert_eq!(err.trim().lines().count(), 1, "{err}");
        assert!(err.contains(word), "{err}");
        assert!(!dir.path().join("refused").exists());
    }
    // The numbers are named by their flags, on a periodic run too.
    for (lam, kappa, block, word) in [
        ("-1", "1e-7", "0.01", "--conductivity -1"),
        ("0.25", "nan", "0.01", "--diffusivity NaN"),
        ("0.25", "1e-7", "0", "--block-length 0"),
    ] {
        let out = dir.path().join("refused");
        let o = viscoslide(&[
            "heat",
            "--from-run",
            &periodic,
            "--conductivity",
            lam,
            "--diffusivity",
            kappa,
            "--block-length",
            block,
            "--out",
            out.to_str().unwrap(),
        ]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{err}");
        assert_eq!(err.trim().lines().count(), 1, "{err}");
        assert!(err.contains(word), "'{err}' lacks '{word}'");
        assert!(!out.exists());
    }
    let missing = dir.path().join("nothing").display().to_string();
    let o = heat(&missing, "refused", &[]);
    assert_eq!(o.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&o.stderr).contains("summary.json"));
}

/// `--from-run` on a layer and at rest, as the heated solve answers them:
/// on a `[layer]` the source defaults to the surface work (the volume
/// source is refused naming the flag, writing nothing) and the heat that
/// reaches deep into the layer is noted (`HeatSetup::layer_note`, the
/// heated solve's warning); a run at rest has zero rise, its outputs
/// written, with the at-rest note.
#[test]
fn heat_from_a_run_on_a_layer_and_at_rest() {
    let dir = tempfile::tempdir().unwrap();
    let solve = |name: &str, extra: &str| -> String {
        let cfg = dir.path().join(format!("{name}.toml"));
        std::fs::write(
            &cfg,
            format!(
                "[material]\nmodel = \"sls\"\nrelaxed_modulus = 3.3e6\nglassy_modulus = 1e7\ncreep_time = 0.01\n\n[surface.generate]\nn = 24\nlength = 1e-3\nhurst = 0.8\nscales = 4\nrms_slope = 0.05\nseed = 2\n\n[solver]\ntolerance = 1e-10\nformulation = \"periodic\"\n\n{extra}"
            ),
        )
        .unwrap();
        let run = dir.path().join(name);
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
    };
    let heat = |run: &str, out: &str, extra: &[&str]| -> Output {
        let out = dir.path().join(out);
        let mut args = vec![
            "heat",
            "--from-run",
            run,
            "--conductivity",
            "0.25",
            "--diffusivity",
            "1e-7",
            "--block-length",
            "0.01",
            "--out",
            out.to_str().unwrap(),
        ];
        args.extend(extra);
        viscoslide(&args)
    };
    // A layer of 1e-4 m (2.4 cells): one passage's heat reaches
    // sqrt(kappa L_b / v) = 5.8e-4 m deep, through it.
    let layer = solve(
        "layer",
        "[loading]\nmean_pressure = 2e4\nspeed = 3e-3\n\n[layer]\nthickness = 1e-4\nbase = \"bonded\"\n",
    );
    let o = heat(&layer, "l", &[]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    let doc = json(&dir.path().join("l").join("heat.json"));
    assert_eq!(doc["source"], "surface");
    let note = "the heat problem is a rubber half-space, but the rubber is a layer 1.000e-4 m thick: heat reaches about 5.774e-4 m deep (the block's passage sqrt(kappa L_b / v))";
    assert!(err.contains(note), "{err}");
    let notes = doc["notes"].as_array().unwrap();
    assert!(
        notes.iter().any(|n| n.as_str().unwrap().starts_with(note)),
        "{notes:?}"
    );
    let o = heat(&layer, "refused", &["--source", "volume"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(
        err.contains("--source volume") && err.contains("give --source surface"),
        "{err}"
    );
    assert!(!dir.path().join("refused").exists());

    let rest = solve("rest", "[loading]\nmean_pressure = 2e4\nspeed = 0.0\n");
    for (out, extra, kind) in [
        ("r", &[][..], "volume"),
        ("rs", &["--source", "surface"][..], "surface"),
    ] {
        let o = heat(&rest, out, extra);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(o.status.success(), "{err}");
        assert!(
            err.contains("note: at rest (speed = 0) nothing is dissipated"),
            "{err}"
        );
        let doc = json(&dir.path().join(out).join("heat.json"));
        assert_eq!(doc["source"], kind);
        for key in [
            "max_rise_k",
            "mean_rise_k",
            "effective_rise_k",
            "background_rise_k",
            "heat_total_w",
            "friction_power_w",
            "energy_balance",
        ] {
            assert_eq!(doc[key].as_f64(), Some(0.0), "{key}: {doc}");
        }
        let (nx, ny, t) = npy::read_2d(dir.path().join(out).join("temperature.npy")).unwrap();
        assert_eq!((nx, ny), (24, 24));
        assert!(t.iter().all(|&v| v == 0.0));
        assert!(dir.path().join(out).join("temperature.png").exists());
    }
}

/// A heated solve's directory keeps its own rise: `viscoslide heat` (from
/// a flux map or `--from-run`, the run itself included) refuses to write
/// its `temperature.npy` and `temperature.png` over the coupled solve's,
/// which its `summary.json` describes, in one line naming `--out`; into
/// an isothermal run's directory, or elsewhere, it writes as before.
#[test]
fn a_heated_solves_directory_is_not_written_over() {
    let dir = tempfile::tempdir().unwrap();
    let cfg = dir.path().join("hot.toml");
    std::fs::write(&cfg, crate::common::heating::HEATED_CELL).unwrap();
    let run = |name: &str, sets: &[&str]| -> String {
        let out = dir.path().join(name);
        let mut args = vec!["solve", cfg.to_str().unwrap(), "--backend", "cpu"];
        for s in sets {
            args.extend(["--set", s]);
        }
        args.extend(["--out", out.to_str().unwrap()]);
        let o = viscoslide(&args);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        out.display().to_string()
    };
    let hot = run("hot", &[]);
    let cold = run("cold", &["heating.enabled=false"]);
    let (flux_path, _) = write_flux(dir.path());
    let from_run = |run: &str, out: &str| {
        viscoslide(&[
            "heat",
            "--from-run",
            run,
            "--conductivity",
            "0.25",
            "--diffusivity",
            "1e-6",
            "--block-length",
            "0.05",
            "--out",
            out,
        ])
    };
    let from_flux = |out: &str| {
        viscoslide(&[
            "heat",
            &flux_path,
            "--cell-size",
            "1e-6",
            "--speed",
            "0.1",
            "--conductivity",
            "0.25",
            "--diffusivity",
            "1e-7",
            "--out",
            out,
        ])
    };
    let before = std::fs::read(Path::new(&hot).join("temperature.npy")).unwrap();
    for o in [from_run(&hot, &hot), from_flux(&hot)] {
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{err}");
        assert_eq!(err.trim().lines().count(), 1, "{err}");
        assert!(
            err.contains("--out") && err.contains("holds a heated solve"),
            "{err}"
        );
        assert_eq!(
            std::fs::read(Path::new(&hot).join("temperature.npy")).unwrap(),
            before
        );
        assert!(!Path::new(&hot).join("heat.json").exists());
    }
    let elsewhere = dir.path().join("hot-heat").display().to_string();
    for o in [from_run(&hot, &elsewhere), from_run(&cold, &cold)] {
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    }
    assert!(Path::new(&cold).join("heat.json").exists());
}

/// The console line of a heated solve counts the scan grid's isothermal
/// solves beside the full grid's (it said "2 isothermal solves" where ten
/// more had run on the scan grid), and names no scan grid where there is
/// none (a grid too small for one).
#[test]
fn a_heated_solve_counts_its_scan_grids_solves() {
    let dir = tempfile::tempdir().unwrap();
    let cfg = dir.path().join("hot.toml");
    std::fs::write(&cfg, crate::common::heating::HEATED_CELL).unwrap();
    for n in [32, 128] {
        let out = dir.path().join(format!("n{n}"));
        let set = format!("surface.generate.n={n}");
        let o = viscoslide(&[
            "solve",
            cfg.to_str().unwrap(),
            "--backend",
            "cpu",
            "--set",
            &set,
            "--out",
            out.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let stdout = String::from_utf8_lossy(&o.stdout);
        let line = stdout
            .lines()
            .find(|l| l.starts_with("heated: effective temperature"))
            .unwrap_or_else(|| panic!("{stdout}"));
        let h = &json(&out.join("summary.json"))["heating"];
        let full = h["fixed_point_evaluations"].as_u64().unwrap();
        let solves = format!(", {full} isothermal solves");
        match h["coarse_grid"].as_array() {
            Some(grid) => {
                let scan = format!(
                    "{solves} and {} on the {} x {} scan grid;",
                    h["coarse_evaluations"], grid[0], grid[1]
                );
                assert!(n == 128 && line.contains(&scan), "{line}\n{scan}");
            }
            None => {
                assert!(n == 32 && line.contains(&format!("{solves};")), "{line}");
                assert!(!line.contains("scan grid"), "{line}");
            }
        }
    }
}
