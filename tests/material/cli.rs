//! `viscoslide material fit` and `material show`, end to end through the
//! built binary.

use std::path::Path;
use std::process::Command;

const BIN: &str = env!("CARGO_BIN_EXE_viscoslide");

fn data() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("configs/data/sbr_like_dma.csv")
}

#[test]
fn fit_writes_three_files_loadable_by_file_model() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("fit");
    let run = Command::new(BIN)
        .args(["material", "fit"])
        .arg(data())
        .args(["--wlf", "8.86,101.6,17", "--temperature", "25", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    for name in ["material.toml", "fit.csv", "fit.png"] {
        let p = out.join(name);
        assert!(
            p.metadata().map(|m| m.len() > 100).unwrap_or(false),
            "{name}"
        );
    }
    // Nothing else (no staging folder) is left behind.
    assert_eq!(std::fs::read_dir(&out).unwrap().count(), 3);
    let png = std::fs::read(out.join("fit.png")).unwrap();
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
    let csv = std::fs::read_to_string(out.join("fit.csv")).unwrap();
    // Header plus one row per data point (160).
    assert_eq!(csv.lines().count(), 161);
    let toml_text = std::fs::read_to_string(out.join("material.toml")).unwrap();
    assert!(toml_text.contains("[fit]") && toml_text.contains("temperature = 25.0"));

    // A config in another directory loads it with model = "file".
    let cfg = dir.path().join("run.toml");
    std::fs::write(
        &cfg,
        "[material]\nmodel = \"file\"\nfile = \"fit/material.toml\"\n",
    )
    .unwrap();
    let show = Command::new(BIN)
        .args(["material", "show"])
        .arg(&cfg)
        .args(["--points", "7"])
        .output()
        .unwrap();
    assert!(
        show.status.success(),
        "{}",
        String::from_utf8_lossy(&show.stderr)
    );
    let text = String::from_utf8(show.stdout).unwrap();
    assert!(
        text.contains("relaxed modulus E0") && text.contains("tan delta"),
        "{text}"
    );
    // 7 table rows after the table header.
    let rows = text
        .lines()
        .skip_while(|l| !l.contains("tan delta"))
        .count();
    assert_eq!(rows, 8, "{text}");
    // Fitted with --wlf at 25 C: the shift and the temperature are shown.
    assert!(
        text.contains("spectrum at T = 25 C") && text.contains("T_ref = 17 C"),
        "{text}"
    );
}

/// `material show` prints the WLF constants of a material that carries
/// them (the shipped SBR-like fit, C1 = 8.86, C2 = 101.6 K, T_ref = 17 C)
/// and its shift factors, checked against the WLF form evaluated here.
#[test]
fn show_prints_the_wlf_shift() {
    let show = Command::new(BIN)
        .args(["material", "show"])
        .arg(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/configs/paper_experiment.toml"
        ))
        .args(["--points", "3"])
        .output()
        .unwrap();
    let text = String::from_utf8(show.stdout).unwrap();
    assert!(show.status.success(), "{text}");
    assert!(
        text.contains("C1 = 8.86, C2 = 101.6 K, T_ref = 17 C"),
        "{text}"
    );
    let a_t = |t: f64| 10f64.powf(-8.86 * (t - 17.0) / (101.6 + t - 17.0));
    for t in [-3.0, 7.0, 27.0, 37.0, 57.0] {
        let want = format!("{t} C: {:.4e}", a_t(t));
        assert!(text.contains(&want), "{want} in {text}");
    }
    // A material without WLF constants shows no shift.
    let show = Command::new(BIN)
        .args(["material", "show"])
        .arg(concat!(env!("CARGO_MANIFEST_DIR"), "/configs/default.toml"))
        .output()
        .unwrap();
    let text = String::from_utf8(show.stdout).unwrap();
    assert!(show.status.success() && !text.contains("WLF"), "{text}");
}

/// `material show` of the file `material fit` writes shows it as a config
/// loading it (`[material] model = "file"`) does, to the byte (before:
/// "unknown field `fit`"); `--set` beside it is refused in one line.
#[test]
fn show_takes_the_file_material_fit_writes() {
    let show = |path: &str, extra: &[&str]| {
        Command::new(BIN)
            .args(["material", "show"])
            .arg(format!("{}/{path}", env!("CARGO_MANIFEST_DIR")))
            .args(extra)
            .output()
            .unwrap()
    };
    let file = show("configs/data/sbr_like_material.toml", &[]);
    let config = show("configs/material_sbr_like.toml", &[]);
    assert!(
        file.status.success(),
        "{}",
        String::from_utf8_lossy(&file.stderr)
    );
    assert!(config.status.success());
    assert_eq!(file.stdout, config.stdout);
    let set = show(
        "configs/data/sbr_like_material.toml",
        &["--set", "material.poisson=0.49"],
    );
    let err = String::from_utf8_lossy(&set.stderr);
    assert!(
        !set.status.success() && err.contains("is a material file"),
        "{err}"
    );
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
}

/// A failing `fit` prints exactly one `error:` line and writes nothing.
fn fails_cleanly(csv: &str, needle: &str) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("bad.csv");
    std::fs::write(&path, csv).unwrap();
    let out = dir.path().join("out");
    let run = Command::new(BIN)
        .args(["material", "fit"])
        .arg(&path)
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    assert!(!run.status.success());
    let err = String::from_utf8(run.stderr).unwrap();
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(err.starts_with("error:") && err.contains(needle), "{err}");
    assert!(!out.exists(), "output directory must not be created");
}

#[test]
fn bad_csv_gives_one_line_error_and_writes_nothing() {
    fails_cleanly("frequency_hz,e1_pa\n1,2\n2,3\n3,4\n", "e2_pa");
    fails_cleanly("e1_pa,e2_pa\n1,2\n2,3\n3,4\n", "frequency_hz");
    fails_cleanly(
        "# note\nomega_rad_s,e1_pa,e2_pa\n1,2e6,1e5\n10,abc,2e5\n100,3e6,3e5\n",
        "line 4",
    );
    fails_cleanly(
        "omega_rad_s,e1_pa,e2_pa\n1,2e6,1e5\n10,-2e6,2e5\n100,3e6,3e5\n",
        "positive",
    );
    // Several temperatures and no WLF constants.
    fails_cleanly(
        "temperature_c,omega_rad_s,e1_pa,e2_pa\n0,1,2e6,1e5\n20,10,2e6,2e5\n20,100,3e6,3e5\n",
        "--wlf",
    );
}

/// A fit at a temperature beyond its data's (the shipped DMA data span -20
/// to 100 C) warns that every modulus of the file is the WLF shift's
/// extrapolation; a fit inside them does not.
#[test]
fn a_fit_beyond_its_datas_temperatures_is_warned() {
    let dir = tempfile::tempdir().unwrap();
    for (t, warned) in [("300", true), ("17", false)] {
        let o = Command::new(BIN)
            .args(["material", "fit"])
            .arg(concat!(
                env!("CARGO_MANIFEST_DIR"),
                "/configs/data/sbr_like_dma.csv"
            ))
            .args([
                "--wlf",
                "8.86,101.6,17",
                "--terms",
                "8",
                "--temperature",
                t,
                "--out",
            ])
            .arg(dir.path().join(t))
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(o.status.success(), "{err}");
        assert_eq!(
            err.contains("warning: the fit's temperature 300.0000 C lies 200.000 K above the DMA data (-20 to 100 C)"),
            warned,
            "{t}: {err}"
        );
    }
}

/// A creep-time grid that leaves double precision (`--terms 1000` with the
/// default ratio e spans 434 decades; `--ratio 1e300`) is refused naming
/// both, before the fit (it was "nnls: non-finite entry in the matrix").
#[test]
fn a_time_grid_beyond_double_precision_is_refused() {
    let data = concat!(env!("CARGO_MANIFEST_DIR"), "/configs/data/sbr_like_dma.csv");
    for (flag, value, needle) in [
        (
            "--terms",
            "1000",
            "terms = 1000 with ratio = 2.718281828459045 spans 434 decades",
        ),
        ("--ratio", "1e300", "ratio = 1e300 spans"),
    ] {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("out");
        let o = Command::new(BIN)
            .args([
                "material",
                "fit",
                data,
                "--wlf",
                "8.86,101.6,17",
                flag,
                value,
                "--out",
            ])
            .arg(&out)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success() && err.contains(needle), "{err}");
        assert_eq!(err.trim_end().lines().count(), 1, "{err}");
        assert!(!out.exists());
    }
}

/// The shipped DMA data without their comment lines, with the header's
/// `temperature_c` renamed `header` and only the rows `keep` accepts.
fn shipped_as(dir: &Path, header: &str, keep: impl Fn(&str) -> bool) -> std::path::PathBuf {
    let text = std::fs::read_to_string(data()).unwrap();
    let mut lines = text.lines().filter(|l| !l.starts_with('#'));
    let mut out = lines.next().unwrap().replace("temperature_c", header) + "\n";
    for l in lines.filter(|l| keep(l)) {
        out += l;
        out += "\n";
    }
    let path = dir.join(format!("{header}.csv"));
    std::fs::write(&path, out).unwrap();
    path
}

/// `material fit` of `csv` with `extra` arguments: its status, stderr and
/// (when written) material.toml.
fn fit_of(csv: &Path, extra: &[&str]) -> (bool, String, Option<String>) {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let o = Command::new(BIN)
        .args(["material", "fit"])
        .arg(csv)
        .args(extra)
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    let toml_text = std::fs::read_to_string(out.join("material.toml")).ok();
    (
        o.status.success(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
        toml_text,
    )
}

/// A temperature column in kelvin was ignored and the ten temperatures
/// fitted as one (rms 70 % / 90 %, exit 0, no word): it is refused naming
/// the column the reader takes. A temperature column of another name is
/// named in a warning, with the merged frequencies and the fit's error,
/// on stderr and in `[fit] warnings`.
#[test]
fn a_temperature_column_the_reader_does_not_take_is_named() {
    let dir = tempfile::tempdir().unwrap();
    let kelvin = shipped_as(dir.path(), "temperature_k", |_| true);
    let (ok, err, toml_text) = fit_of(&kelvin, &[]);
    assert!(!ok && toml_text.is_none(), "{err}");
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(
        err.contains("column temperature_k looks like a temperature in K")
            && err.contains("a column named temperature_c"),
        "{err}"
    );
    let temp = shipped_as(dir.path(), "temp", |_| true);
    let (ok, err, toml_text) = fit_of(&temp, &[]);
    assert!(ok, "{err}");
    let toml_text = toml_text.unwrap();
    for needle in [
        "column temp is ignored",
        "the frequency 6.2832e-1 rad/s in data without a temperature_c column carries E2 from 1.780e3 to 1.840e8 Pa",
        "the fit misses its data: rms relative error E1 69.7 %, E2 90.2 %",
    ] {
        assert!(err.contains(&format!("warning: {needle}")), "{err}");
        assert!(toml_text.contains(needle), "{toml_text}");
    }
}

/// Data at 60 C stop below the glassy plateau (tan delta 0.55 at their
/// highest frequency) and the fit's E_inf came out 1.08e12 Pa, a thousand
/// times the generating spectrum's, without a word: it is warned with the
/// numbers. One time for 160 points misses them (48 % / 84 %): warned.
/// The shipped data at all temperatures, shifted by WLF, warn of nothing.
#[test]
fn a_fit_beyond_the_glassy_plateau_or_missing_its_data_is_warned() {
    let dir = tempfile::tempdir().unwrap();
    let hot = shipped_as(dir.path(), "temperature_c", |l| l.starts_with("60,"));
    let (ok, err, toml_text) = fit_of(&hot, &[]);
    assert!(ok, "{err}");
    let glassy = "tan delta = 0.546 at the highest data frequency 6.283e2 rad/s, where the fit's E1 = 1.262e7 Pa: the data do not reach the glassy plateau, so the fit's E_inf = 1.084e12 Pa (8.58e4 times that E1)";
    assert!(err.contains(&format!("warning: {glassy}")), "{err}");
    assert!(toml_text.unwrap().contains(glassy));
    let wlf = ["--wlf", "8.86,101.6,17", "--temperature", "17"];
    let (ok, err, toml_text) = fit_of(&data(), &wlf);
    assert!(ok && !err.contains("warning"), "{err}");
    assert!(!toml_text.unwrap().contains("warnings"));
    let (ok, err, _) = fit_of(&data(), &[&wlf[..], &["--terms", "1"]].concat());
    assert!(ok, "{err}");
    assert!(
        err.contains("warning: the fit misses its data: rms relative error E1 48.3 %, E2 84.1 %"),
        "{err}"
    );
}

/// A config's `[loading] temperature` is the temperature `material show`
/// describes, as a solve sees the material: every creep time times `a_T`,
/// the table at that temperature; a temperature beyond the WLF range is
/// refused as the solve refuses it.
#[test]
fn show_takes_the_config_temperature() {
    let dir = tempfile::tempdir().unwrap();
    let cfg = dir.path().join("c.toml");
    std::fs::write(
        &cfg,
        "[material]\nmodel = \"sls\"\nrelaxed_modulus = 2e6\nglassy_modulus = 1e7\ncreep_time = 0.01\nwlf = [8.86, 101.6, 17.0]\n",
    )
    .unwrap();
    let show = |set: &[&str]| {
        let mut c = Command::new(BIN);
        c.args(["material", "show"])
            .arg(&cfg)
            .args(["--points", "3"]);
        for s in set {
            c.args(["--set", s]);
        }
        c.output().unwrap()
    };
    let o = show(&["loading.temperature=37"]);
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let a_t = 10f64.powf(-8.86 * 20.0 / (101.6 + 20.0));
    assert!(text.contains("spectrum at T = 37 C"), "{text}");
    assert!(text.contains(&format!("{:>14.6e}", 0.01 * a_t)), "{text}");
    let o = show(&["loading.temperature=-200"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success() && o.stdout.is_empty(), "{err}");
    assert!(
        err.contains("-200") && err.trim().lines().count() == 1,
        "{err}"
    );
}
