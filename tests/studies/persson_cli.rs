//! `viscoslide persson` end to end: the three PSD sources, default speeds,
//! and one-line errors that leave nothing behind.

use std::path::{Path, PathBuf};
use std::process::Command;

use viscoslide::surface::{self, GenerateParams, Normalisation, UpperCutoff};

fn viscoslide(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_viscoslide"))
        .args(args)
        .output()
        .unwrap()
}

fn repo(p: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join(p)
        .display()
        .to_string()
}

fn files(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().to_string())
        .collect();
    v.sort();
    v
}

fn json(dir: &Path) -> serde_json::Value {
    serde_json::from_slice(&std::fs::read(dir.join("persson.json")).unwrap()).unwrap()
}

/// The material of [`SLS`], built in the library.
fn sls_material() -> viscoslide::material::Material {
    use viscoslide::material::{CreepSpectrum, Material};
    Material::new(
        CreepSpectrum::standard_linear_solid(1e7 / 3.0, 1e7, 0.01).unwrap(),
        0.5,
    )
    .unwrap()
}

const SLS: &str = "[material]\nmodel = \"sls\"\nrelaxed_modulus = 3.3333333333333335e6\nglassy_modulus = 1.0e7\ncreep_time = 0.01\n";

#[test]
fn fig1_config_writes_three_files_with_xi_over_the_sweep_range() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("p");
    let o = viscoslide(&[
        "persson",
        &repo("configs/paper_friction_speed.toml"),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(files(&out), ["persson.csv", "persson.json", "persson.png"]);
    let j = json(&out);
    let xi = j["xi"].as_array().unwrap();
    let v = j["speed"].as_array().unwrap();
    assert_eq!(xi.len(), 100);
    // [sweep] xi_range = [1e-4, 1.0, 17]; xi = v tau / L with tau / L = 1.
    assert!((xi[0].as_f64().unwrap() - 1e-4).abs() < 1e-15);
    assert!((xi[99].as_f64().unwrap() - 1.0).abs() < 1e-12);
    assert!((v[0].as_f64().unwrap() - 1e-4).abs() < 1e-15);
    // F_N = 0.30 N on 1 cm^2.
    assert!((j["inputs"]["sigma0_pa"].as_f64().unwrap() - 3e3).abs() < 1e-9);
    assert_eq!(j["inputs"]["psd"]["source"]["kind"], "self_affine");
    let rms_slope = j["inputs"]["psd"]["rms_slope"].as_f64().unwrap();
    assert!(
        (rms_slope - 0.02).abs() < 1e-12,
        "continuum C0: {rms_slope}"
    );
    let csv = std::fs::read_to_string(out.join("persson.csv")).unwrap();
    assert!(csv.starts_with("speed_m_per_s,xi,friction_coefficient,contact_area_fraction"));
    assert_eq!(csv.lines().count(), 101);
}

fn write_config(dir: &Path, text: &str) -> PathBuf {
    let p = dir.join("c.toml");
    std::fs::write(&p, text).unwrap();
    p
}

#[test]
fn surface_file_and_csv_sources_and_explicit_speeds() {
    let tmp = tempfile::tempdir().unwrap();
    let params = GenerateParams {
        nx: 128,
        ny: 128,
        length: 0.01,
        hurst: 0.8,
        // The band reaches the grid's Nyquist wavenumber: no round-off bins.
        upper: UpperCutoff::Scales(64.0),
        normalisation: Normalisation::RmsSlope(0.02),
        seed: 3,
        ..GenerateParams::default()
    };
    let map = surface::generate(&params).unwrap();
    surface::save_npy(&map, &tmp.path().join("h.npy"), surface::NpyPrecision::F64).unwrap();
    let cfg = write_config(
        tmp.path(),
        &format!("{SLS}[surface]\nfile = \"h.npy\"\nlength = 0.01\nperiodic = true\n[loading]\nmean_pressure = 3e3\nspeed = 0.01\n"),
    );
    let out = tmp.path().join("file");
    let o = viscoslide(&[
        "persson",
        cfg.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--speeds",
        "1e-3,1e-1,5",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let j = json(&out);
    assert_eq!(j["inputs"]["psd"]["source"]["kind"], "surface_file");
    assert_eq!(j["speed"].as_array().unwrap().len(), 5);
    let mu_file: Vec<f64> = j["friction_coefficient"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect();
    assert!(mu_file.iter().all(|m| *m > 0.0));

    // The same (periodic) surface through `surface stats --out`'s psd.csv.
    let stats = tmp.path().join("stats");
    let o = viscoslide(&[
        "surface",
        "stats",
        tmp.path().join("h.npy").to_str().unwrap(),
        "--length",
        "0.01",
        "--periodic",
        "--out",
        stats.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let out2 = tmp.path().join("csv");
    let o = viscoslide(&[
        "persson",
        cfg.to_str().unwrap(),
        "--out",
        out2.to_str().unwrap(),
        "--speeds",
        "1e-3,1e-1,5",
        "--psd",
        stats.join("psd.csv").to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let j2 = json(&out2);
    assert_eq!(j2["inputs"]["psd"]["source"]["kind"], "table");
    for (a, b) in mu_file
        .iter()
        .zip(j2["friction_coefficient"].as_array().unwrap())
    {
        let b = b.as_f64().unwrap();
        // psd.csv holds 11 significant digits.
        assert!((a - b).abs() < 1e-8 * a, "{a} vs {b}");
    }
}

#[test]
fn default_speeds_centre_on_the_loss_peak_without_a_sweep() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = write_config(
        tmp.path(),
        &format!("{SLS}[surface.generate]\nn = 64\nlength = 0.01\nhurst = 0.8\nscales = 16\nrms_slope = 0.02\n[loading]\nnormal_load = 0.3\nspeed = 0.01\n"),
    );
    let out = tmp.path().join("p");
    let o = viscoslide(&[
        "persson",
        cfg.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let j = json(&out);
    let v = j["speed"].as_array().unwrap();
    assert_eq!(v.len(), 100);
    let ratio = v[99].as_f64().unwrap() / v[0].as_f64().unwrap();
    assert!((ratio / 1e4 - 1.0).abs() < 1e-9);
    assert!(j["inputs"]["speeds"]["origin"]
        .as_str()
        .unwrap()
        .contains("loss peak"));
}

#[test]
fn bad_psd_tables_are_one_line_errors_and_write_nothing() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = write_config(
        tmp.path(),
        &format!("{SLS}[loading]\nmean_pressure = 3e3\nspeed = 0.01\n"),
    );
    let cases = [
        ("q,C\n1e3,1e-20\n", "at least 2 rows"),
        ("1e3,1e-20\n0,1e-21\n", "finite and positive"),
        ("1e3,1e-20\n-2e3,1e-21\n", "finite and positive"),
        ("1e3,1e-20\n2e3,-1e-21\n", "finite and positive"),
        ("1e3,1e-20\n2e3,0\n", "finite and positive"),
        ("1e3,1e-20\n2e3,NaN\n", "finite and positive"),
        ("1e3,NaN\n2e3,1e-21\n", "finite and positive"),
        ("2e3,1e-20\n1e3,1e-21\n", "increase strictly"),
        ("1e3,1e-20\n1e3,1e-21\n", "increase strictly"),
        ("1e3,1e-20\n2e3,abc\n", "cannot read 'abc'"),
    ];
    for (i, (text, want)) in cases.iter().enumerate() {
        let csv = tmp.path().join(format!("bad{i}.csv"));
        std::fs::write(&csv, text).unwrap();
        let out = tmp.path().join(format!("out{i}"));
        let o = viscoslide(&[
            "persson",
            cfg.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--speeds",
            "1e-3,1e-1,5",
            "--psd",
            csv.to_str().unwrap(),
        ]);
        assert!(!o.status.success(), "{text:?} was accepted");
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(err.trim_end().lines().count(), 1, "{text:?}: {err}");
        assert!(err.contains(want), "{text:?}: {err}");
        assert!(!out.exists(), "{text:?}: output directory was created");
    }
    // A map without roughness, and one too small to hold two radial bins,
    // are named as such (before: "a tabulated PSD needs at least 2 rows,
    // found 0").
    let maps: [(usize, Vec<f64>, &str); 2] = [
        (32, vec![0.0; 1024], "the 32 x 32 map has no roughness"),
        (
            3,
            vec![0.0, 1e-6, 0.0, 2e-6, 0.0, -1e-6, 0.0, 0.0, 1e-6],
            "the 3 x 3 map has power in 1 radial bin(s)",
        ),
    ];
    for (i, (n, heights, want)) in maps.iter().enumerate() {
        let dir = tmp.path().join(format!("map{i}"));
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(
            dir.join("h.npy"),
            viscoslide::io::npy::encode_f64(&[*n, *n], heights),
        )
        .unwrap();
        let cfg = write_config(
            &dir,
            &format!("{SLS}[surface]\nfile = \"h.npy\"\nlength = 0.01\n[loading]\nmean_pressure = 3e3\nspeed = 0.01\n"),
        );
        let out = dir.join("out");
        let o = viscoslide(&[
            "persson",
            cfg.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success() && err.contains(want), "{err}");
        assert_eq!(err.trim_end().lines().count(), 1, "{err}");
        assert!(!out.exists());
    }
}

#[test]
fn anisotropic_surface_and_missing_pressure_are_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = write_config(
        tmp.path(),
        &format!("{SLS}[surface.generate]\nn = 64\nlength = 0.01\nhurst = 0.8\nscales = 8\nrms_slope = 0.02\nanisotropy = {{ ratio = 2.0, angle_deg = 30.0 }}\n[loading]\nmean_pressure = 3e3\n"),
    );
    let out = tmp.path().join("p");
    let o = viscoslide(&[
        "persson",
        cfg.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("anisotropic") && err.trim_end().lines().count() == 1,
        "{err}"
    );
    assert!(!out.exists());

    let cfg = write_config(
        tmp.path(),
        &format!("{SLS}[surface.generate]\nn = 64\nlength = 0.01\nhurst = 0.8\nscales = 8\nrms_slope = 0.02\n[loading]\napproach = 1e-6\n"),
    );
    let o = viscoslide(&[
        "persson",
        cfg.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("nominal pressure"), "{err}");
    assert!(!out.exists());
}

const ROUGH: &str = "[surface.generate]\nn = 32\nlength = 0.01\nhurst = 0.8\nscales = 8\nrms_slope = 0.02\nseed = 1\n";

/// `viscoslide solve CFG --backend cpu --out OUT`, which must succeed: its
/// `summary.json` and stdout.
fn solved(cfg: &Path, out: &Path) -> (serde_json::Value, String) {
    let o = viscoslide(&[
        "solve",
        cfg.to_str().unwrap(),
        "--backend",
        "cpu",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let s = serde_json::from_slice(&std::fs::read(out.join("summary.json")).unwrap()).unwrap();
    (s, String::from_utf8_lossy(&o.stdout).into_owned())
}

#[test]
fn solve_records_persson_beside_the_simulation() {
    use viscoslide::persson::{Persson, PerssonParams};
    let tmp = tempfile::tempdir().unwrap();
    let cfg = write_config(
        tmp.path(),
        &format!(
            "{SLS}{ROUGH}[loading]\nnormal_load = 0.3\nspeed = 0.01\n[analysis]\nenabled = false\n"
        ),
    );
    let (s, stdout) = solved(&cfg, &tmp.path().join("s"));
    assert!(stdout.contains("Persson's theory at this speed"));
    let mu = s["persson_friction_coefficient"].as_f64().unwrap();
    let area = s["persson_contact_area_fraction"].as_f64().unwrap();
    // The same theory from the library: continuum PSD, 0.3 N on 1 cm^2.
    let params = GenerateParams {
        nx: 32,
        ny: 32,
        length: 0.01,
        hurst: 0.8,
        upper: UpperCutoff::Scales(8.0),
        normalisation: Normalisation::RmsSlope(0.02),
        seed: 1,
        ..GenerateParams::default()
    };
    let (psd, _) = viscoslide::persson::psd::continuum_self_affine(&params).unwrap();
    let m = sls_material();
    let p = Persson::new(&m, &psd, 0.3 / 1e-4, PerssonParams::default())
        .unwrap()
        .point(0.01)
        .unwrap();
    assert!(
        (mu / p.friction_coefficient - 1.0).abs() < 1e-9,
        "{mu} vs {p:?}"
    );
    assert!((area / p.contact_area_fraction - 1.0).abs() < 1e-9);
    assert_eq!(s["persson"]["psd"], "self_affine");
    assert_eq!(s["persson"]["notes"], serde_json::json!([]));
}

/// What Persson's theory leaves out is noted beside a solve's Persson
/// numbers as `viscoslide persson` notes it: a `[layer]` (the theory is for
/// a half-space) and a map whose slopes are anisotropic (the theory sees
/// its radial average). Before, a solve printed both beside the simulation
/// without a word.
#[test]
fn solve_notes_what_persson_leaves_out() {
    let tmp = tempfile::tempdir().unwrap();
    let solve = |name: &str, config: &str| -> (serde_json::Value, String) {
        let dir = tmp.path().join(name);
        std::fs::create_dir_all(&dir).unwrap();
        solved(&write_config(&dir, config), &dir.join("out"))
    };
    let loading = "[loading]\nnormal_load = 0.3\nspeed = 0.01\n[analysis]\nenabled = false\n";
    let notes = |s: &serde_json::Value| s["persson"]["notes"].as_array().unwrap().clone();
    let (layered, stdout) = solve(
        "layer",
        &format!("{SLS}{ROUGH}{loading}[layer]\nthickness = 2e-4\nbase = \"bonded\"\n"),
    );
    let n = notes(&layered);
    assert_eq!(n.len(), 1, "{n:?}");
    let note = n[0].as_str().unwrap();
    assert!(
        note.contains("[layer] (h = 2.000e-4 m)") && note.contains("half-space"),
        "{note}"
    );
    assert!(stdout.contains(&format!("note: {note}")), "{stdout}");

    // A map stretched 3 times along x (mean square slopes 1:9) read as a file.
    let mut p = GenerateParams {
        nx: 64,
        ny: 64,
        length: 0.01,
        hurst: 0.8,
        upper: UpperCutoff::Scales(8.0),
        normalisation: Normalisation::RmsSlope(0.02),
        seed: 1,
        ..GenerateParams::default()
    };
    p.anisotropy = Some(surface::Anisotropy {
        ratio: 3.0,
        angle_deg: 0.0,
    });
    let dir = tmp.path().join("aniso");
    std::fs::create_dir_all(&dir).unwrap();
    let save = |p: &GenerateParams| {
        let map = surface::generate(p).unwrap();
        surface::save_npy(&map, &dir.join("h.npy"), surface::NpyPrecision::F64).unwrap();
    };
    save(&p);
    let file = "[surface]\nfile = \"h.npy\"\nlength = 0.01\nperiodic = true\n[solver]\nformulation = \"periodic\"\n";
    let (aniso, _) = solve("aniso", &format!("{SLS}{file}{loading}"));
    let n = notes(&aniso);
    assert_eq!(n.len(), 1, "{n:?}");
    assert!(
        n[0].as_str()
            .unwrap()
            .contains("slopes are anisotropic (gamma = 0.0"),
        "{n:?}"
    );
    // The same map unstretched: no note.
    p.anisotropy = None;
    save(&p);
    let (iso, _) = solve("aniso", &format!("{SLS}{file}{loading}"));
    assert_eq!(notes(&iso), Vec::<serde_json::Value>::new());
}

fn csv_column(text: &str, name: &str) -> Vec<String> {
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let k = header.iter().position(|h| *h == name).unwrap();
    lines
        .map(|l| l.split(',').nth(k).unwrap().to_string())
        .collect()
}

#[test]
fn merge_draws_and_tabulates_persson() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = write_config(
        tmp.path(),
        &format!("{SLS}{ROUGH}[loading]\nnormal_load = 0.3\nspeed = 0.01\n[analysis]\nenabled = false\n[sweep]\nspeed = [0.003, 0.03]\n"),
    );
    let out = tmp.path().join("sw");
    let o = viscoslide(&[
        "sweep",
        cfg.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    for f in [
        "friction_vs_xi.png",
        "area_ratio_vs_xi.png",
        "area_fraction_vs_xi.png",
    ] {
        assert!(out.join(f).exists(), "{f}");
    }
    let csv = std::fs::read_to_string(out.join("sweep.csv")).unwrap();
    let mu: Vec<f64> = csv_column(&csv, "persson_friction")
        .iter()
        .map(|s| s.parse().unwrap())
        .collect();
    let ratio: Vec<f64> = csv_column(&csv, "persson_area_ratio")
        .iter()
        .map(|s| s.parse().unwrap())
        .collect();
    assert_eq!(mu.len(), 3);
    assert_eq!(mu[0], 0.0);
    assert!(mu[1] > 0.0 && mu[2] > 0.0);
    assert_eq!(ratio[0], 1.0);
    assert!(ratio[2] < ratio[1] && ratio[1] < 1.0);

    // A sphere: the theory does not apply, the merge still works.
    let cfg = write_config(
        tmp.path(),
        &format!("{SLS}[surface.sphere]\nn = 16\nlength = 0.01\nradius = 0.05\n[loading]\nnormal_load = 0.01\nspeed = 0.01\n[analysis]\nenabled = false\n[sweep]\nspeed = [0.01]\n"),
    );
    let out = tmp.path().join("sphere");
    let o = viscoslide(&[
        "sweep",
        cfg.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let csv = std::fs::read_to_string(out.join("sweep.csv")).unwrap();
    assert!(csv_column(&csv, "persson_friction")
        .iter()
        .all(|s| s.is_empty()));
}

/// A surface synthesised from a PSD table (`[surface.generate] psd`): the
/// theory uses the table itself over the band the grid carries (`2 pi / L`
/// to `pi / a`), in `persson` and beside a solve alike, not the radial
/// average of one realisation; and the surface re-discretises for a
/// refinement study (`with_grid`).
#[test]
fn a_surface_synthesised_from_a_table_uses_the_table() {
    use viscoslide::persson::{Persson, PerssonParams};
    use viscoslide::problem::Problem;
    use viscoslide::surface::TabulatedPsd;
    let tmp = tempfile::tempdir().unwrap();
    // A power law with a roll-off, reaching beyond the 64^2 grid's Nyquist
    // wavenumber (pi / a = 2.0e4 1/m) and starting below 2 pi / L.
    let q: Vec<f64> = (0..40).map(|k| 300.0 * 1.2f64.powi(k)).collect();
    let c: Vec<f64> = q
        .iter()
        .map(|&q| 1e-17 * (q.max(2e3) / 2e3).powf(-3.6))
        .collect();
    let table = TabulatedPsd::new(q, c, "psd").unwrap();
    std::fs::write(tmp.path().join("psd.csv"), table.to_csv()).unwrap();
    let cfg = write_config(
        tmp.path(),
        &format!("{SLS}[surface.generate]\nn = 64\nlength = 0.01\nseed = 2\npsd = \"psd.csv\"\n[loading]\nmean_pressure = 3e3\nspeed = 0.01\n[analysis]\nenabled = false\n"),
    );
    let m = sls_material();
    let reread = TabulatedPsd::from_csv(&tmp.path().join("psd.csv")).unwrap();
    let band = |n: usize| {
        let a = 0.01 / n as f64;
        reread
            .within(
                std::f64::consts::TAU / 0.01,
                std::f64::consts::PI / a,
                "psd",
            )
            .unwrap()
    };
    let expect = Persson::new(&m, &band(64), 3e3, PerssonParams::default())
        .unwrap()
        .point(0.01)
        .unwrap();

    let out = tmp.path().join("p");
    let o = viscoslide(&[
        "persson",
        cfg.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--speeds",
        "0.01,0.1,2",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let j = json(&out);
    let source = &j["inputs"]["psd"]["source"];
    assert_eq!(source["kind"], "generated_table", "{source}");
    assert_eq!(source["rows"], 40);
    assert!(
        (source["q_max_per_m"].as_f64().unwrap() / (std::f64::consts::PI * 6400.0) - 1.0).abs()
            < 1e-12
    );
    let mu0 = j["friction_coefficient"][0].as_f64().unwrap();
    assert!(
        (mu0 / expect.friction_coefficient - 1.0).abs() < 1e-9,
        "{mu0} vs {expect:?}"
    );

    let solved = tmp.path().join("s");
    let o = viscoslide(&[
        "solve",
        cfg.to_str().unwrap(),
        "--backend",
        "cpu",
        "--out",
        solved.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let s: serde_json::Value =
        serde_json::from_slice(&std::fs::read(solved.join("summary.json")).unwrap()).unwrap();
    assert_eq!(s["persson"]["psd"], "generated_table");
    let mu = s["persson_friction_coefficient"].as_f64().unwrap();
    assert!(
        (mu / expect.friction_coefficient - 1.0).abs() < 1e-9,
        "{mu} vs {expect:?}"
    );

    // The same surface on a finer grid: the coarse grid's modes unchanged,
    // the theory over the finer grid's wider band.
    let loaded = viscoslide::config::load(&cfg, &[]).unwrap();
    let coarse = Problem::from_config(&loaded).unwrap();
    let fine = coarse.with_grid(128).unwrap();
    assert_eq!((fine.surface.nx, fine.surface.ny), (128, 128));
    let (psd_fine, kind) = fine.persson_psd().unwrap();
    assert_eq!(kind, "generated_table");
    assert_eq!(psd_fine, band(128));
    let h = |p: &Problem| {
        let mut f = p.surface.heights.clone();
        let mean = f.iter().sum::<f64>() / f.len() as f64;
        f.iter_mut().for_each(|v| *v -= mean);
        f
    };
    // Block means of the fine map against the coarse map: equal up to the
    // modes beyond the coarse band (small on this steep spectrum).
    let (hc, hf) = (h(&coarse), h(&fine));
    let restricted = viscoslide::internals::solver::cascade::restrict_mean(&hf, 128, 128);
    let rms = (hc.iter().map(|v| v * v).sum::<f64>() / hc.len() as f64).sqrt();
    let diff = (hc
        .iter()
        .zip(&restricted)
        .map(|(a, b)| (a - b) * (a - b))
        .sum::<f64>()
        / hc.len() as f64)
        .sqrt();
    eprintln!("block means against the coarse map: {diff:.3e} rms, map {rms:.3e} rms");
    assert!(diff < 0.2 * rms, "diff {diff:e} against rms {rms:e}");
}
