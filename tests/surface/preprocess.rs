//! One preprocessing rule for measured maps (physics.md section 11): a
//! scan read from any file loses its mean plane before the solve and
//! before any PSD, PSDs use the Hann window, Persson's theory beside a
//! solve sees the windowed radial average over the scan's trusted band,
//! and a PSD whose rms slope disagrees with the map's real-space rms slope
//! is warned about.

use std::path::Path;
use std::process::Command;

use viscoslide::config;
use viscoslide::problem::Problem;
use viscoslide::surface::{
    self, Detrend, GenerateParams, HeightMap, Normalisation, Preprocessing, UpperCutoff, Window,
};

fn viscoslide(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_viscoslide"))
        .args(args)
        .output()
        .unwrap()
}

const SLS: &str = "[material]\nmodel = \"sls\"\nrelaxed_modulus = 3.3333333333333335e6\nglassy_modulus = 1.0e7\ncreep_time = 0.01\n";

/// Plane slopes added to the scan, along x and y.
const TILT: (f64, f64) = (0.05, 0.03);

/// A non-periodic, tilted scan: a 96 x 80 window cut out of a 256^2
/// periodic self-affine surface (rms slope 0.02, 1 cm side; the window's
/// edges do not match), plus the plane `TILT`. Returns the scan and the
/// window before the tilt.
fn tilted_scan() -> (HeightMap, HeightMap) {
    let big = surface::generate(&GenerateParams {
        nx: 256,
        ny: 256,
        length: 0.01,
        hurst: 0.8,
        upper: UpperCutoff::Scales(64.0),
        normalisation: Normalisation::RmsSlope(0.02),
        seed: 11,
        ..GenerateParams::default()
    })
    .unwrap();
    let (nx, ny, a) = (96, 80, big.cell_size);
    let mut rough = Vec::with_capacity(nx * ny);
    let mut tilted = Vec::with_capacity(nx * ny);
    for i in 0..nx {
        for j in 0..ny {
            let h = big.at(i + 40, j + 70);
            rough.push(h);
            tilted.push(h + TILT.0 * i as f64 * a + TILT.1 * j as f64 * a);
        }
    }
    let lx = nx as f64 * a;
    (
        HeightMap::new(nx, ny, lx, tilted).unwrap(),
        HeightMap::new(nx, ny, lx, rough).unwrap(),
    )
}

fn problem(dir: &Path, surface_keys: &str) -> Problem {
    let (scan, _) = tilted_scan();
    surface::save_npy(&scan, &dir.join("scan.npy"), surface::NpyPrecision::F64).unwrap();
    let text = format!(
        "{SLS}[surface]\nfile = \"scan.npy\"\nlength = {:e}\n{surface_keys}[loading]\nmean_pressure = 3e4\nspeed = 0.01\n",
        scan.length_x()
    );
    let path = dir.join("c.toml");
    std::fs::write(&path, text).unwrap();
    Problem::from_config(&config::load(&path, &[]).unwrap()).unwrap()
}

/// Least-squares slopes `(dh/dx, dh/dy)` of a map's mean plane.
fn plane_slopes(m: &HeightMap) -> (f64, f64) {
    let (nx, ny, a) = (m.nx, m.ny, m.cell_size);
    let xm = (nx as f64 - 1.0) / 2.0;
    let ym = (ny as f64 - 1.0) / 2.0;
    let (mut sxh, mut sxx, mut syh, mut syy) = (0.0, 0.0, 0.0, 0.0);
    for i in 0..nx {
        for j in 0..ny {
            let (x, y, h) = ((i as f64 - xm) * a, (j as f64 - ym) * a, m.at(i, j));
            sxh += x * h;
            sxx += x * x;
            syh += y * h;
            syy += y * y;
        }
    }
    (sxh / sxx, syh / syy)
}

#[test]
fn a_tilted_scan_loses_its_plane_by_default_and_its_psd_agrees_with_real_space() {
    let tmp = tempfile::tempdir().unwrap();
    let p = problem(tmp.path(), "");
    assert_eq!(
        p.preprocessing,
        Some(Preprocessing {
            periodic: false,
            detrend: Detrend::Plane,
            window: Window::Hann,
        })
    );
    // The solver's map has no tilt left: its plane slopes are at round-off
    // against the 0.05 added (the x and y ramps are orthogonal on the grid).
    let (sx, sy) = plane_slopes(&p.surface);
    assert!(sx.abs() < 1e-12 && sy.abs() < 1e-12, "{sx:e} {sy:e}");
    // ... and it is the untilted window less its own plane: the added tilt
    // is gone exactly (to round-off of the 1 cm-scale heights).
    let (_, rough) = tilted_scan();
    let want = surface::detrend(
        &surface::Topography::from_height_map(&rough),
        Detrend::Plane,
    );
    let max = want.heights.iter().fold(0.0f64, |m, h| m.max(h.abs()));
    for (a, b) in p.surface.heights.iter().zip(&want.heights) {
        assert!((a - b).abs() <= 1e-9 * max, "{a:e} {b:e}");
    }
    // Persson's PSD: Hann-windowed radial average over the trusted band,
    // whose rms slope agrees with the real-space one within 20 % (the
    // warning's threshold), so no warning.
    let (psd, kind, report) = p.persson_psd_report().unwrap();
    let report = report.unwrap();
    assert_eq!(kind, "radial_average");
    assert_eq!(report.window, Window::Hann);
    assert_eq!(report.detrend, Some(Detrend::Plane));
    assert!(report.trusted_band);
    let (lo, hi) = (report.q_band_per_m[0], report.q_band_per_m[1]);
    let lmin = p.surface.length_x().min(p.surface.length_y());
    assert!((lo / (8.0 * std::f64::consts::PI / lmin) - 1.0).abs() < 1e-12);
    assert!((hi / (2.0 / 3.0 * std::f64::consts::PI / p.surface.cell_size) - 1.0).abs() < 1e-12);
    assert_eq!((psd.q_min(), psd.q_max()), (lo, hi));
    let ratio = report.rms_slope_psd / report.rms_slope_real;
    eprintln!(
        "plane + hann: PSD slope {:.4e}, real {:.4e}, ratio {ratio:.3}",
        report.rms_slope_psd, report.rms_slope_real
    );
    assert!((ratio - 1.0).abs() < 0.2, "{ratio}");
    assert!(report.warning.is_none(), "{:?}", report.warning);
}

#[test]
fn without_detrending_the_psd_slope_disagrees_and_is_warned_about() {
    let tmp = tempfile::tempdir().unwrap();
    let p = problem(tmp.path(), "detrend = \"none\"\n");
    // The tilt stays in the solver's map.
    let (sx, sy) = plane_slopes(&p.surface);
    assert!(
        (sx - TILT.0).abs() < 0.01 && (sy - TILT.1).abs() < 0.01,
        "{sx} {sy}"
    );
    let (_, _, report) = p.persson_psd_report().unwrap();
    let report = report.unwrap();
    eprintln!(
        "none + hann: PSD slope {:.4e}, real {:.4e}",
        report.rms_slope_psd, report.rms_slope_real
    );
    let w = report.warning.expect("a warning");
    assert!(w.contains("rms slope") && w.contains("detrend"), "{w}");
    assert!(!w.contains('\n'));
    // The solve carries it into its warnings and summary.json.
    let s = p
        .solve(
            &viscoslide::problem::Executor::Cpu,
            &mut viscoslide::internals::solver::Silent,
        )
        .unwrap();
    assert!(s.warnings.contains(&w), "{:?}", s.warnings);
    let doc = s.summary();
    assert_eq!(doc["surface_preprocessing"]["detrend"], "none");
    assert_eq!(doc["surface_preprocessing"]["window"], "hann");
    assert_eq!(doc["persson"]["map_psd"]["window"], "hann");
    assert!(doc["warnings"]
        .as_array()
        .unwrap()
        .iter()
        .any(|x| x.as_str() == Some(w.as_str())));
}

#[test]
fn surface_stats_defaults_to_plane_and_hann_for_npy_and_warns_without() {
    let tmp = tempfile::tempdir().unwrap();
    let (scan, _) = tilted_scan();
    let file = tmp.path().join("scan.npy");
    surface::save_npy(&scan, &file, surface::NpyPrecision::F64).unwrap();
    let length = format!("{:e}", scan.length_x());
    let stats = |extra: &[&str]| {
        let mut args = vec![
            "surface",
            "stats",
            file.to_str().unwrap(),
            "--length",
            &length,
            "--json",
        ];
        args.extend_from_slice(extra);
        let o = viscoslide(&args);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let j: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        (j, String::from_utf8_lossy(&o.stderr).to_string())
    };
    let (j, err) = stats(&[]);
    assert_eq!(j["stats"]["detrend"], "plane");
    assert_eq!(j["stats"]["window"], "hann");
    assert_eq!(j["preprocessing"]["detrend"], "plane");
    let (psd, real) = (
        j["stats"]["rms_slope_psd"].as_f64().unwrap(),
        j["stats"]["rms_slope_real"].as_f64().unwrap(),
    );
    eprintln!("stats plane + hann: PSD {psd:.4e}, real {real:.4e}");
    assert!((psd / real - 1.0).abs() < 0.2, "{psd} {real}");
    assert!(j["warnings"].as_array().unwrap().is_empty(), "{j}");
    assert!(!err.contains("warning"), "{err}");
    // The old default of .npy: no detrending, no window.
    let (j, err) = stats(&["--detrend", "none", "--window", "none"]);
    let (psd, real) = (
        j["stats"]["rms_slope_psd"].as_f64().unwrap(),
        j["stats"]["rms_slope_real"].as_f64().unwrap(),
    );
    eprintln!("stats none + none: PSD {psd:.4e}, real {real:.4e}");
    assert!(psd / real > 1.2, "{psd} {real}");
    assert_eq!(j["warnings"].as_array().unwrap().len(), 1, "{j}");
    assert!(err.contains("warning: the radial PSD of this map"), "{err}");
}

/// The periodic formulation takes a measured map as one period: a map that
/// is one period of a periodic surface, read from a file without
/// `periodic = true`, keeps its heights (before, its mean plane was
/// removed, which made it non-periodic: friction 4 % off on a full contact)
/// and is solved exactly as the same map marked periodic, with a warning
/// that states the step between its opposite edges; its PSDs take it as a
/// period too (no window). `detrend` given
/// explicitly is still applied; the non-periodic formulation still removes
/// the plane of a scan.
#[test]
fn the_periodic_formulation_takes_a_map_as_one_period() {
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    let map = surface::generate(&GenerateParams {
        nx: 64,
        ny: 64,
        length: 0.01,
        hurst: 0.8,
        upper: UpperCutoff::Scales(16.0),
        normalisation: Normalisation::RmsSlope(0.02),
        seed: 3,
        ..GenerateParams::default()
    })
    .unwrap();
    std::fs::write(
        d.join("map.npy"),
        surface::encode_npy(&map, surface::NpyPrecision::F64),
    )
    .unwrap();
    let solve = |name: &str, surface_keys: &str, formulation: &str| -> serde_json::Value {
        let cfg = d.join(format!("{name}.toml"));
        std::fs::write(
            &cfg,
            format!(
                "{SLS}[surface]\nfile = \"map.npy\"\nlength = 0.01\n{surface_keys}[loading]\nmean_pressure = 1e6\nspeed = 1.17\n[solver]\nformulation = \"{formulation}\"\n[analysis]\nenabled = false\n"
            ),
        )
        .unwrap();
        let out = d.join(name);
        let o = viscoslide(&[
            "solve",
            &cfg.display().to_string(),
            "--backend",
            "cpu",
            "--out",
            &out.display().to_string(),
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        serde_json::from_slice(&std::fs::read(out.join("summary.json")).unwrap()).unwrap()
    };
    let marked = solve("marked", "periodic = true\n", "periodic");
    let unmarked = solve("unmarked", "", "periodic");
    let mu = |s: &serde_json::Value| s["friction_coefficient"].as_f64().unwrap();
    let area = |s: &serde_json::Value| s["contact_area_fraction"].as_f64().unwrap();
    assert_eq!(unmarked["surface_preprocessing"]["detrend"], "none");
    assert_eq!(unmarked["surface_preprocessing"]["window"], "none");
    assert!((mu(&unmarked) / mu(&marked) - 1.0).abs() < 1e-12);
    assert_eq!(area(&unmarked), area(&marked));
    let warned = |s: &serde_json::Value| {
        s["warnings"]
            .as_array()
            .unwrap()
            .iter()
            .filter_map(|w| w.as_str())
            .find(|w| w.contains("not marked periodic"))
            .map(str::to_string)
    };
    assert!(warned(&marked).is_none(), "{}", marked["warnings"]);
    let w = warned(&unmarked).expect("the wrapped-edge warning");
    // A generated period: its opposite edges meet like neighbouring cells.
    assert!(
        w.contains("rms heights along x") && w.contains("detrend = \"none\""),
        "{w}"
    );
    // Asked for, the plane is removed (and the answer moves).
    let planed = solve("planed", "detrend = \"plane\"\n", "periodic");
    assert_eq!(planed["surface_preprocessing"]["detrend"], "plane");
    assert!(warned(&planed).unwrap().contains("detrend = \"plane\""));
    assert_ne!(mu(&planed), mu(&marked));
    // The non-periodic formulation: a scan loses its plane as before.
    let pad = solve("pad", "", "non_periodic");
    assert_eq!(pad["surface_preprocessing"]["detrend"], "plane");
    assert!(warned(&pad).is_none());
}
