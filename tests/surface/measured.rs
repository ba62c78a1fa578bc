//! PSDs of measured (non-periodic) maps, Hurst exponents, PSD stitching and
//! surfaces synthesised from a tabulated PSD (physics.md section 11).

use std::f64::consts::PI;
use std::process::Command;

use viscoslide::surface::{
    analyse, detrend, generate, generate_from_table, psd_topography, radial_average, stitch,
    Detrend, GenerateParams, Normalisation, ScanPsd, SynthParams, TabulatedPsd, Topography,
    UpperCutoff, Window,
};

fn viscoslide(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_viscoslide"))
        .args(args)
        .output()
        .unwrap()
}

/// `A cos(q.x)` plus a tilt and a bow, on a non-periodic 256 x 200 map.
fn sinusoid_map(bow: bool) -> (Topography, f64, f64) {
    let (nx, ny, d) = (256, 200, 1e-6);
    let (lx, ly) = (nx as f64 * d, ny as f64 * d);
    let amp = 1e-7;
    let (qx, qy) = (2.0 * PI * 20.3 / lx, 2.0 * PI * 7.6 / ly);
    let mut h = vec![0.0; nx * ny];
    for i in 0..nx {
        for j in 0..ny {
            let (x, y) = ((i as f64 + 0.5) * d, (j as f64 + 0.5) * d);
            let mut v = amp * (qx * x + qy * y + 0.4).cos() + 3e-3 * x - 1e-3 * y + 5e-6;
            if bow {
                v += 30.0 * ((x - 1e-4).powi(2) + 0.5 * (y - 0.7e-4).powi(2));
            }
            h[i * ny + j] = v;
        }
    }
    let t = Topography::new(nx, ny, d, d, h, "sin").unwrap();
    (t, (qx * qx + qy * qy).sqrt(), amp * amp / 2.0)
}

#[test]
fn sinusoid_with_tilt_and_bow_peak_and_integral() {
    for (bow, trend) in [(false, Detrend::Plane), (true, Detrend::Quadratic)] {
        let (t, q_sin, msq) = sinusoid_map(bow);
        for window in [Window::Hann, Window::BlackmanHarris] {
            let psd = psd_topography(&detrend(&t, trend), window).unwrap();
            let integral = psd.mean_square();
            assert!(
                (integral / msq - 1.0).abs() < 0.02,
                "{trend:?} {window:?}: integral {integral:e} vs {msq:e}"
            );
            let radial = radial_average(&psd);
            let k = (0..radial.c.len())
                .max_by(|&a, &b| radial.c[a].total_cmp(&radial.c[b]))
                .unwrap();
            assert!(
                (radial.q[k] - q_sin).abs() <= radial.dq,
                "{trend:?} {window:?}: peak at {:e}, sinusoid at {q_sin:e}",
                radial.q[k]
            );
        }
        // Without detrending the tilt swamps the spectrum.
        let raw = psd_topography(&t, Window::Hann).unwrap().mean_square();
        assert!(raw > 2.0 * msq);
    }
}

#[test]
fn hurst_exponent_of_a_self_affine_crop() {
    let p = GenerateParams {
        nx: 1024,
        ny: 1024,
        length: 1e-3,
        hurst: 0.8,
        upper: UpperCutoff::Scales(256.0),
        normalisation: Normalisation::RmsHeight(1e-6),
        seed: 3,
        ..GenerateParams::default()
    };
    let map = generate(&p).unwrap();
    // A non-periodic 512 x 512 crop, with a tilt as a sample would have.
    let (n, a) = (512, map.cell_size);
    let mut h = vec![0.0; n * n];
    for i in 0..n {
        for j in 0..n {
            h[i * n + j] = map.at(i + 100, j + 300) + 1e-3 * i as f64 * a;
        }
    }
    let crop = Topography::new(n, n, a, a, h, "crop").unwrap();
    let q_l = 2.0 * PI / p.length;
    // From 16 wavelengths in the crop (the Hann window biases the steep
    // spectrum's few lowest modes upwards) to half the upper cut-off.
    let fit = (2.0 * PI / (n as f64 * a / 16.0), 0.5 * 256.0 * q_l);
    let an = analyse(&crop, Detrend::Plane, Window::Hann, Some(fit)).unwrap();
    let h_fit = an.hurst.unwrap().hurst;
    assert!((h_fit - 0.8).abs() < 0.05, "H = {h_fit}");
}

#[test]
fn real_space_and_spectral_rms_agree_on_a_smooth_periodic_map() {
    let (nx, ny, d) = (128, 96, 1e-6);
    let (lx, ly) = (nx as f64 * d, ny as f64 * d);
    let mut h = vec![0.0; nx * ny];
    for i in 0..nx {
        for j in 0..ny {
            let (x, y) = (i as f64 * d, j as f64 * d);
            h[i * ny + j] = 1e-7 * (2.0 * PI * 3.0 * x / lx).sin()
                + 5e-8 * (2.0 * PI * (2.0 * x / lx + 4.0 * y / ly)).cos();
        }
    }
    let t = Topography::new(nx, ny, d, d, h, "s").unwrap();
    let s = analyse(&t, Detrend::None, Window::None, None)
        .unwrap()
        .stats;
    for (a, b, what) in [
        (s.rms_height_real, s.rms_height_psd, "height"),
        (s.rms_slope_real, s.rms_slope_psd, "slope"),
        (s.rms_curvature_real, s.rms_curvature_psd, "curvature"),
    ] {
        assert!((a / b - 1.0).abs() < 0.02, "{what}: {a:e} vs {b:e}");
    }
}

/// Plateau below `qr`, then `q^-3.6` (H = 0.8) up to beyond Nyquist.
fn table(l: f64, n: usize) -> TabulatedPsd {
    let dq = 2.0 * PI / l;
    let qr = 8.0 * dq;
    let qmax = 1.5 * PI * n as f64 / l;
    let c0 = 1e-24;
    TabulatedPsd::new(
        vec![0.5 * dq, qr, qmax],
        vec![c0, c0, c0 * (qmax / qr).powf(-3.6)],
        "table",
    )
    .unwrap()
}

fn log_bins(
    q: &[f64],
    c: &[f64],
    w: &[f64],
    q0: f64,
    bpd: usize,
    range: (f64, f64),
) -> Vec<(usize, f64)> {
    let mut acc = std::collections::BTreeMap::<usize, (f64, f64)>::new();
    for i in 0..q.len() {
        if q[i] < range.0 || q[i] > range.1 {
            continue;
        }
        let b = ((q[i] / q0).log10() * bpd as f64).floor() as usize;
        let e = acc.entry(b).or_default();
        e.0 += w[i] * c[i];
        e.1 += w[i];
    }
    acc.into_iter().map(|(b, (s, n))| (b, s / n)).collect()
}

#[test]
fn stitching_a_crop_and_a_decimation_matches_the_large_surface() {
    let (n, l) = (1024, 1e-3);
    let t = table(l, n);
    let big = generate_from_table(
        &t,
        &SynthParams {
            nx: n,
            ny: n,
            length: l,
            seed: 11,
            q1: None,
            below: Default::default(),
        },
    )
    .unwrap();
    let a = big.cell_size;
    // Coarse scan: the same surface at a quarter of the resolution (the
    // synthesis is resolution-consistent: same seed, same long waves),
    // periodic, so analysed without detrending or window.
    let coarse = generate_from_table(
        &t,
        &SynthParams {
            nx: n / 4,
            ny: n / 4,
            length: l,
            seed: 11,
            q1: None,
            below: Default::default(),
        },
    )
    .unwrap();
    let coarse = Topography::from_height_map(&coarse);
    // Fine scan: a non-periodic 512 x 512 crop at full resolution (a
    // windowed crop's PSD fluctuates by ~15 % per radial bin from the
    // window's correlation of neighbouring modes; the log bins average that
    // down to a few per cent).
    let m = 512;
    let mut h = vec![0.0; m * m];
    for i in 0..m {
        for j in 0..m {
            h[i * m + j] = big.at(i + 300, j + 100);
        }
    }
    let fine = Topography::new(m, m, a, a, h, "fine").unwrap();
    let scans = vec![
        ScanPsd::from_topography("coarse", &coarse, Detrend::None, Window::None).unwrap(),
        ScanPsd::from_topography("fine", &fine, Detrend::Plane, Window::Hann).unwrap(),
    ];
    let bpd = 10;
    let st = stitch(&scans, bpd).unwrap();
    let q0 = scans[0].q_lo.min(scans[1].q_lo);
    let q1 = scans[0].q_hi.max(scans[1].q_hi);
    assert!((st.q[0] / q0) < 1.3 && st.q[st.q.len() - 1] / q1 > 0.8);
    // The large surface's radial PSD at the stitched wavenumbers (each
    // stitched bin's q is the mode-weighted mean of what went into it).
    let refr = radial_average(&viscoslide::surface::psd_2d(&big, Window::None).unwrap());
    let reference = TabulatedPsd::new(refr.q.clone(), refr.c.clone(), "reference").unwrap();
    let mut worst = 0.0f64;
    for (q, c) in st.q.iter().zip(&st.c) {
        let r = reference.eval(*q);
        let err = (c / r - 1.0).abs();
        worst = worst.max(err);
        assert!(
            err < 0.15,
            "bin at q = {q:.3e}: stitched {c:.3e} vs {r:.3e}"
        );
    }
    assert!(st.q.len() >= 15, "{} bins", st.q.len());
    eprintln!("worst bin {:.1} %", 100.0 * worst);
}

#[test]
fn synthesis_follows_the_table_and_its_rms() {
    let (n, l) = (256, 1e-3);
    let t = table(l, n);
    let bpd = 10;
    let seeds = 4;
    let mut sums: std::collections::BTreeMap<usize, (f64, f64)> = Default::default();
    let dq = 2.0 * PI / l;
    let mut expected = std::collections::BTreeMap::new();
    for seed in 0..seeds {
        let map = generate_from_table(
            &t,
            &SynthParams {
                nx: n,
                ny: n,
                length: l,
                seed,
                q1: None,
                below: Default::default(),
            },
        )
        .unwrap();
        // rms: the table's mean square over the grid's band.
        let band = TabulatedPsd::new(
            vec![0.5 * dq, 8.0 * dq, PI / map.cell_size],
            vec![
                t.eval(0.5 * dq),
                t.eval(8.0 * dq),
                t.eval(PI / map.cell_size),
            ],
            "band",
        )
        .unwrap();
        let rms = (map.heights.iter().map(|h| h * h).sum::<f64>() / (n * n) as f64).sqrt();
        let want = band.moment(0).sqrt();
        assert!((rms / want - 1.0).abs() < 0.01, "rms {rms:e} vs {want:e}");
        let r = radial_average(&viscoslide::surface::psd_2d(&map, Window::None).unwrap());
        // What the table says at the same wavenumbers, with the same weights.
        let w: Vec<f64> = r.count.iter().map(|&c| c as f64).collect();
        let tab: Vec<f64> = r.q.iter().map(|&q| t.eval(q)).collect();
        expected = log_bins(&r.q, &tab, &w, dq, bpd, (dq, PI / map.cell_size))
            .into_iter()
            .collect();
        for (b, c) in log_bins(&r.q, &r.c, &w, dq, bpd, (dq, PI / map.cell_size)) {
            let e = sums.entry(b).or_default();
            e.0 += c;
            e.1 += 1.0;
        }
    }
    for (b, (s, k)) in sums {
        let measured = s / k;
        let want = expected[&b];
        assert!(
            (measured / want - 1.0).abs() < 0.1,
            "bin {b}: {measured:.3e} vs {want:.3e}"
        );
    }
}

#[test]
fn cli_stats_stitch_and_generate_from_psd() {
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    let p = |s: &str| d.join(s).display().to_string();
    let (n, l) = (256, 1e-3);
    let t = table(l, n);
    std::fs::write(d.join("table.csv"), t.to_csv()).unwrap();
    let big = generate_from_table(
        &t,
        &SynthParams {
            nx: n,
            ny: n,
            length: l,
            seed: 2,
            q1: None,
            below: Default::default(),
        },
    )
    .unwrap();
    let topo = Topography::from_height_map(&big);
    std::fs::write(
        d.join("a.x3p"),
        viscoslide::surface::encode_x3p(&topo, Default::default(), None).unwrap(),
    )
    .unwrap();
    let o = viscoslide(&[
        "surface",
        "stats",
        &p("a.x3p"),
        "--json",
        "--out",
        &p("stats"),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let s: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(s["stats"]["detrend"], "plane");
    assert_eq!(s["stats"]["window"], "hann");
    for f in [
        "stats.json",
        "psd.csv",
        "psd_line_x.csv",
        "psd_line_y.csv",
        "psd.png",
        "psd_lines.png",
    ] {
        assert!(d.join("stats").join(f).exists(), "{f}");
    }
    let o = viscoslide(&[
        "surface",
        "psd-stitch",
        &p("a.x3p"),
        &p("stats/psd.csv"),
        "--out",
        &p("st"),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let stitched = TabulatedPsd::from_csv(&d.join("st/psd.csv")).unwrap();
    assert!(stitched.q().len() > 5);
    assert!(d.join("st/psd.png").exists() && d.join("st/stitch.json").exists());

    let o = viscoslide(&[
        "surface",
        "generate",
        "--psd",
        &p("st/psd.csv"),
        "--n",
        "128",
        "--length",
        "1e-3",
        "--seed",
        "4",
        "--out",
        &p("gen"),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let j: serde_json::Value =
        serde_json::from_slice(&std::fs::read(d.join("gen/surface.json")).unwrap()).unwrap();
    assert_eq!(j["seed"], 4);
    // From a config, relative to the config's directory.
    std::fs::write(
        d.join("g.toml"),
        "[surface.generate]\nn = 64\nlength = 1e-3\nseed = 1\npsd = \"st/psd.csv\"\n",
    )
    .unwrap();
    // `surface generate` from a config, into an output directory.
    let generate_from = |config: &str, out: &str| {
        viscoslide(&[
            "surface",
            "generate",
            "--config",
            &p(config),
            "--out",
            &p(out),
        ])
    };
    let o = generate_from("g.toml", "gen2");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    // psd and self-affine keys together: refused, nothing written.
    std::fs::write(
        d.join("bad.toml"),
        "[surface.generate]\nn = 64\nlength = 1e-3\nhurst = 0.8\npsd = \"st/psd.csv\"\n",
    )
    .unwrap();
    let o = generate_from("bad.toml", "gen3");
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success() && err.contains("remove hurst"), "{err}");
    assert!(!d.join("gen3").exists());

    // --q1 cuts the table as the config key does: the same heights as
    // `q1 = ...` in the config, others than without the cut.
    let q_max = *stitched.q().last().unwrap();
    let q1 = format!("{:e}", 0.3 * q_max);
    let o = viscoslide(&[
        "surface",
        "generate",
        "--psd",
        &p("st/psd.csv"),
        "--n",
        "64",
        "--length",
        "1e-3",
        "--seed",
        "1",
        "--q1",
        &q1,
        "--out",
        &p("gen_q1_flag"),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    std::fs::write(
        d.join("q1.toml"),
        format!("[surface.generate]\nn = 64\nlength = 1e-3\nseed = 1\nq1 = {q1}\npsd = \"st/psd.csv\"\n"),
    )
    .unwrap();
    let o = generate_from("q1.toml", "gen_q1_key");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let heights = |dir: &str| std::fs::read(d.join(dir).join("heights.npy")).unwrap();
    assert_eq!(heights("gen_q1_flag"), heights("gen_q1_key"));
    assert_ne!(heights("gen_q1_flag"), heights("gen2"));
}

/// `surface generate --psd` keeps the grid modes in the table's first bin
/// (issue: a table measured by `surface stats` lost its longest modes, so
/// the synthesis had 18 % less rms height than the table itself). A
/// 256 x 192 map over 1e-4 m, its table, and surfaces synthesised from it
/// at 256^2 under each rule for the modes below the first row.
#[test]
fn a_synthesis_from_a_measured_table_keeps_the_first_bin() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let p = |s: &str| d.join(s).display().to_string();
    let ok = |o: std::process::Output| {
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    };
    ok(viscoslide(&[
        "surface",
        "generate",
        "--n",
        "256",
        "--ny",
        "192",
        "--length",
        "1e-4",
        "--hurst",
        "0.8",
        "--scales",
        "128",
        "--rms-height",
        "1e-7",
        "--seed",
        "3",
        "--out",
        &p("map"),
    ]));
    ok(viscoslide(&[
        "surface",
        "stats",
        &p("map/heights.npy"),
        "--length",
        "1e-4",
        "--detrend",
        "none",
        "--window",
        "none",
        "--out",
        &p("stats"),
    ]));
    let json = |f: &str| -> serde_json::Value {
        serde_json::from_slice(&std::fs::read(d.join(f)).unwrap()).unwrap()
    };
    let map_rms = json("stats/stats.json")["stats"]["rms_height_psd"]
        .as_f64()
        .unwrap();
    let generate = |rule: Option<&str>, out: &str| {
        let mut args = vec![
            "surface",
            "generate",
            "--psd",
            "stats/psd.csv",
            "--n",
            "256",
            "--length",
            "1e-4",
            "--seed",
            "1",
            "--out",
            out,
        ];
        if let Some(r) = rule {
            args.extend(["--below-table", r]);
        }
        Command::new(env!("CARGO_BIN_EXE_viscoslide"))
            .args(&args)
            .current_dir(d)
            .output()
            .unwrap()
    };
    let mut rms = std::collections::HashMap::new();
    for (rule, out) in [
        (None, "default"),
        (Some("first_bin"), "first_bin"),
        (Some("none"), "none"),
        (Some("extrapolate"), "extrapolate"),
    ] {
        ok(generate(rule, out));
        let doc = json(&format!("{out}/surface.json"));
        rms.insert(out, doc["stats"]["rms_height"].as_f64().unwrap());
        let below = &doc["below_table"];
        assert_eq!(below["rule"], rule.unwrap_or("first_bin"), "{doc}");
        // (+-1, 0), (0, +-1) at 6.3e4 1/m and (+-1, +-1) at 8.89e4 1/m lie
        // in the first bin, below its row at 8.90e4 1/m.
        let modes = below["modes"].as_u64().unwrap();
        assert_eq!(modes, if rule == Some("none") { 0 } else { 8 }, "{below}");
        if out == "first_bin" {
            let edge = below["first_bin_edge_per_m"].as_f64().unwrap();
            assert!(
                edge < 2.0 * PI / 1e-4 && edge > 0.5 * 2.0 * PI / 1e-4,
                "{edge}"
            );
            let binned = doc["table_rms_height_first_bin"].as_f64().unwrap();
            assert!(
                (rms[out] / binned - 1.0).abs() < 0.05,
                "{} vs {binned}",
                rms[out]
            );
        }
    }
    assert_eq!(rms["default"], rms["first_bin"]);
    // The map's rms within 5 % with the first bin; 40 % short without
    // it; more than the map with the power law continued down.
    assert!(
        (rms["first_bin"] / map_rms - 1.0).abs() < 0.05,
        "{rms:?} {map_rms}"
    );
    assert!(rms["none"] < 0.7 * map_rms, "{rms:?} {map_rms}");
    assert!(rms["extrapolate"] > rms["first_bin"], "{rms:?}");

    // The config key gives the flag's surface; a rule without a table and
    // an unknown rule are one-line errors that write nothing.
    std::fs::write(
        d.join("g.toml"),
        "[surface.generate]\nn = 256\nlength = 1e-4\nseed = 1\npsd = \"stats/psd.csv\"\nbelow_table = \"none\"\n",
    )
    .unwrap();
    ok(viscoslide(&[
        "surface",
        "generate",
        "--config",
        &p("g.toml"),
        "--out",
        &p("key"),
    ]));
    let heights = |dir: &str| std::fs::read(d.join(dir).join("heights.npy")).unwrap();
    assert_eq!(heights("key"), heights("none"));
    let o = generate(Some("sideways"), "bad");
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success() && err.contains("sideways"), "{err}");
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(!d.join("bad").exists());
    let o = viscoslide(&[
        "surface",
        "generate",
        "--n",
        "64",
        "--length",
        "1e-4",
        "--hurst",
        "0.8",
        "--scales",
        "8",
        "--rms-height",
        "1e-7",
        "--below-table",
        "none",
        "--out",
        &p("no_table"),
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success() && err.contains("below_table"), "{err}");
    assert!(!d.join("no_table").exists());
}
