//! A fitted material holds where its data were taken. WLF constants hold
//! over the temperatures of the data (`[material] wlf_range`, or `[fit]
//! wlf_range` written by `material fit --wlf` on data at several
//! temperatures), the spectrum over the data's frequencies (`[material]
//! frequency_range`, `[fit] frequency_range`). A solve beyond them is
//! answered with a warning that names the value, by how much and beyond
//! which end; inside them nothing warns; a range that cannot be one is
//! refused in one line naming the key, with nothing written.

use std::path::Path;

use viscoslide::config;
use viscoslide::internals::solver::Silent;
use viscoslide::problem::persson::theory_inputs;
use viscoslide::problem::{Executor, Problem};

/// An SLS rubber with WLF constants `8.86, 101.6 K, 17 C` fitted over
/// `RANGE`, on a small periodic cell at `T` C.
const BASE: &str = r#"
[material]
model = "sls"
relaxed_modulus = 3.3333333333333335e6
glassy_modulus = 1.0e7
creep_time = 0.01
wlf = [8.86, 101.6, 17.0]
RANGE

[surface.generate]
n = 16
length = 0.01
hurst = 0.8
scales = 3
rms_slope = 0.02
seed = 3

[loading]
mean_pressure = 3000.0
speed = 0.05
temperature = T

[solver]
formulation = "periodic"

[analysis]
enabled = false
"#;

fn text(range: &str, t: f64) -> String {
    BASE.replace("RANGE", range)
        .replace("T\n", &format!("{t:?}\n"))
}

/// Config `text` with its `[material]` the `material.toml` at `file`, with
/// the `extra` keys beside it.
fn on_file(file: &Path, extra: &str, text: &str) -> String {
    format!(
        "[material]\nmodel = \"file\"\nfile = \"{}\"\n{extra}\n\n{}",
        file.display(),
        &text[text.find("[surface.generate]").unwrap()..]
    )
}

/// The problem of config `text`, or its error (reading or building).
fn problem(dir: &Path, text: &str) -> Result<Problem, String> {
    let p = dir.join("c.toml");
    std::fs::write(&p, text).unwrap();
    let cfg = config::load(&p, &[]).map_err(|e| e.to_string())?;
    Problem::from_config(&cfg).map_err(|e| e.to_string())
}

/// `material fit DATA --wlf 8.86,101.6,17 --terms 8` on the DMA table
/// `csv`, written in `dir` as `name.csv`: the `material.toml` it writes.
fn fitted(dir: &Path, csv: &str, name: &str) -> toml::Value {
    let data = dir.join(format!("{name}.csv"));
    std::fs::write(&data, csv).unwrap();
    let out = dir.join(name);
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_viscoslide"))
        .args(["material", "fit", data.to_str().unwrap()])
        .args(["--wlf", "8.86,101.6,17", "--terms", "8", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    toml::from_str(&std::fs::read_to_string(out.join("material.toml")).unwrap()).unwrap()
}

/// The warnings of a solve of `text` that hold `needle`.
fn warnings_with(dir: &Path, text: &str, needle: &str) -> Vec<String> {
    let s = problem(dir, text)
        .unwrap()
        .solve(&Executor::Cpu, &mut Silent)
        .unwrap();
    s.warnings
        .into_iter()
        .filter(|w| w.contains(needle))
        .collect()
}

/// The warnings of a solve of `text` that mention the WLF constants' data.
fn data_warnings(dir: &Path, text: &str) -> Vec<String> {
    warnings_with(dir, text, "that the WLF constants were fitted to")
}

#[test]
fn a_temperature_beyond_the_fitted_range_is_warned_of() {
    let dir = tempfile::tempdir().unwrap();
    let range = "wlf_range = [0.0, 40.0]";
    for t in [0.0, 7.0, 40.0] {
        assert!(data_warnings(dir.path(), &text(range, t)).is_empty(), "{t}");
    }
    let above = data_warnings(dir.path(), &text(range, 45.0));
    assert_eq!(above.len(), 1, "{above:?}");
    assert!(
        above[0].contains("45.0000 C lies 5.000 K above the DMA data (0 to 40 C)")
            && above[0].contains("extrapolated")
            && !above[0].contains('\n'),
        "{}",
        above[0]
    );
    let below = data_warnings(dir.path(), &text(range, -10.0));
    assert!(
        below.len() == 1 && below[0].contains("-10.0000 C lies 10.000 K below"),
        "{below:?}"
    );
    // Persson's theory at the same temperature (`viscoslide persson`)
    // says the same.
    let p = dir.path().join("c.toml");
    std::fs::write(&p, text(range, 45.0)).unwrap();
    let inputs = theory_inputs(&config::load(&p, &[]).unwrap(), None, None).unwrap();
    assert!(
        inputs
            .warnings
            .iter()
            .filter(|w| w.contains("5.000 K above the DMA data"))
            .count()
            == 1,
        "{:?}",
        inputs.warnings
    );
    // Without a recorded range nothing can be said, and nothing is.
    assert!(data_warnings(dir.path(), &text("", 90.0)).is_empty());
    // summary.json states the range (null without one).
    let s = problem(dir.path(), &text(range, 45.0))
        .unwrap()
        .solve(&Executor::Cpu, &mut Silent)
        .unwrap()
        .summary();
    assert_eq!(s["wlf_range"], serde_json::json!([0.0, 40.0]));
    assert!(s["warnings"]
        .as_array()
        .unwrap()
        .iter()
        .any(|w| w.as_str().unwrap().contains("5.000 K above")));
    let s = problem(dir.path(), &text("", 20.0))
        .unwrap()
        .solve(&Executor::Cpu, &mut Silent)
        .unwrap()
        .summary();
    assert_eq!(s["wlf_range"], serde_json::Value::Null);
}

#[test]
fn a_range_that_cannot_be_one_is_refused_naming_the_key() {
    let dir = tempfile::tempdir().unwrap();
    let cases: [(&str, &str, &[&str]); 5] = [
        ("[40.0, 0.0]", BASE, &["wlf_range", "lowest first"]),
        ("[0.0, nan]", BASE, &["wlf_range", "finite"]),
        (
            "[-90.0, 40.0]",
            BASE,
            &["wlf_range", "-90 C", "T >= -69.3 C"],
        ),
        (
            "[0.0, 40.0, 80.0]",
            BASE,
            &["wlf_range", "length 3", "length 2"],
        ),
        (
            "[0.0, 40.0]",
            &BASE.replace("wlf = [8.86, 101.6, 17.0]\n", ""),
            &["wlf_range", "give the constants too"],
        ),
    ];
    for (range, base, needles) in cases {
        let t = base
            .replace("RANGE", &format!("wlf_range = {range}"))
            .replace("T\n", "20.0\n");
        let e = match problem(dir.path(), &t) {
            Ok(_) => panic!("{range} accepted"),
            Err(e) => e,
        };
        for n in needles {
            assert!(e.contains(n) && !e.contains('\n'), "{n} not in {e}");
        }
    }
    // From the command line: one line, nothing written.
    let p = dir.path().join("c.toml");
    std::fs::write(&p, text("wlf_range = [40.0, 0.0]", 20.0)).unwrap();
    let out = dir.path().join("out");
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_viscoslide"))
        .args(["solve", p.to_str().unwrap(), "--out", out.to_str().unwrap()])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        !o.status.success() && err.trim_end().lines().count() == 1,
        "{err}"
    );
    assert!(err.contains("wlf_range"), "{err}");
    assert!(!out.exists());
}

/// `material fit --wlf` records the data's temperatures when there are
/// several (none for data at one temperature); the shipped SBR-like file
/// carries `[-20, 100]` and a config's `wlf_range` replaces it.
#[test]
fn the_fit_records_its_data_range_and_a_config_may_replace_it() {
    let dir = tempfile::tempdir().unwrap();
    let fit = |csv: &str, name: &str| fitted(dir.path(), csv, name);
    let mut several = String::from("temperature_c,omega_rad_s,e1_pa,e2_pa\n");
    let mut one = several.clone();
    for (k, t) in [-5.0, 17.0, 35.5].iter().enumerate() {
        for w in [1.0, 10.0, 100.0] {
            let e1 = 2e6 * (1.0 + 0.1 * k as f64) * (1.0 + 0.05 * f64::log10(w));
            several.push_str(&format!("{t},{w},{e1},{}\n", 0.1 * e1));
            one.push_str(&format!(
                "17,{},{e1},{}\n",
                w * 10f64.powi(k as i32),
                0.1 * e1
            ));
        }
    }
    let f = fit(&several, "several");
    assert_eq!(
        f["fit"]["wlf_range"],
        toml::Value::try_from([-5.0, 35.5]).unwrap()
    );
    let f = fit(&one, "one");
    assert!(f["fit"].get("wlf_range").is_none(), "{f}");

    let shipped = Path::new(env!("CARGO_MANIFEST_DIR")).join("configs/data/sbr_like_material.toml");
    let material = |range: &str, t: f64| on_file(&shipped, range, &text("", t));
    let w = data_warnings(dir.path(), &material("", 110.0));
    assert!(
        w.len() == 1 && w[0].contains("110.0000 C lies 10.000 K above the DMA data (-20 to 100 C)"),
        "{w:?}"
    );
    assert!(data_warnings(dir.path(), &material("", 90.0)).is_empty());
    assert!(data_warnings(dir.path(), &material("wlf_range = [-20.0, 120.0]", 110.0)).is_empty());
}

/// The warnings of a solve of `text` that mention the data's frequencies.
fn frequency_warnings(dir: &Path, text: &str) -> Vec<String> {
    warnings_with(dir, text, "the sliding excites frequencies")
}

/// The cell of [`BASE`] excites `v q` from `v q_L` (`q_L = 2 pi / 0.01
/// m`) to `v q1` (`q1 = 3 q_L`, three scales). With data from 1 to 1e3
/// rad/s at 17 C: 20 m/s reaches 3.77e4 rad/s, 1.6 decades above (warned);
/// at 27 C the data's frequencies are `1 / a_T` times higher (`a_T(27) /
/// a_T(17) = 0.1417`: up to 7.06e3 rad/s), and 3.77e4 lies within a decade
/// of them (not warned); 1e-4 m/s reaches down to 0.0628 rad/s, 1.2
/// decades below 1 rad/s.
#[test]
fn frequencies_beyond_the_fitted_data_are_warned_of() {
    let dir = tempfile::tempdir().unwrap();
    let data = "frequency_range = [1.0, 1.0e3]";
    let at = |t: f64, v: f64| text(data, t).replace("speed = 0.05", &format!("speed = {v:e}"));
    let above = frequency_warnings(dir.path(), &at(17.0, 20.0));
    assert!(
        above.len() == 1
            && above[0].contains("up to 3.770e4 rad/s, 1.6 decades above")
            && above[0].contains("(1.000e3 rad/s at this temperature)"),
        "{above:?}"
    );
    assert!(frequency_warnings(dir.path(), &at(27.0, 20.0)).is_empty());
    // summary.json states the range at the solve's temperature.
    let s = problem(dir.path(), &at(27.0, 20.0))
        .unwrap()
        .solve(&Executor::Cpu, &mut Silent)
        .unwrap()
        .summary();
    let a = 10f64.powf(-8.86 * 10.0 / 111.6);
    let hi = s["frequency_range"][1].as_f64().unwrap();
    assert!((hi * a / 1e3 - 1.0).abs() < 1e-12, "{hi}");
    let below = frequency_warnings(dir.path(), &at(17.0, 1e-4));
    assert!(
        below.len() == 1 && below[0].contains("down to 6.283e-2 rad/s, 1.2 decades below"),
        "{below:?}"
    );
    assert!(frequency_warnings(dir.path(), &at(17.0, 0.05)).is_empty());
    // `viscoslide persson` over speeds from 1 mm/s to 20 m/s: the same
    // upper end (its PSD is the band q_L .. q1 of the cell).
    let p = dir.path().join("p.toml");
    std::fs::write(&p, at(17.0, 0.05)).unwrap();
    let out = dir.path().join("persson");
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_viscoslide"))
        .args([
            "persson",
            p.to_str().unwrap(),
            "--speeds",
            "1e-3,20,5",
            "--out",
        ])
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let doc: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("persson.json")).unwrap()).unwrap();
    let w: Vec<&str> = doc["warnings"]
        .as_array()
        .unwrap()
        .iter()
        .filter_map(|w| w.as_str())
        .filter(|w| w.starts_with("the sliding excites"))
        .collect();
    assert!(
        w.len() == 1 && w[0].contains("up to 3.770e4 rad/s"),
        "{w:?}"
    );
    for (range, needle) in [
        ("[0.0, 1.0e3]", "positive"),
        ("[1.0e3, 1.0]", "lowest first"),
        ("[1.0, 2.0, 3.0]", "length 2"),
    ] {
        let t = text(&format!("frequency_range = {range}"), 17.0);
        let e = problem(dir.path(), &t).expect_err(range);
        assert!(
            e.contains("frequency_range") && e.contains(needle) && !e.contains('\n'),
            "{e}"
        );
    }
}

/// `material fit` records the data's angular frequencies, shifted to the
/// fit's temperature, in `[fit] frequency_range`; the shipped SBR-like
/// file carries them (7.46e7 rad/s at most at 17 C), and sliding it at
/// 1 km/s at -10 C excites 1.9e6 rad/s, beyond its data's 4.6e4 there
/// (`a_T(-10) / a_T(17) = 10^(8.86 27 / 74.6)`).
#[test]
fn the_fit_records_its_frequencies() {
    let dir = tempfile::tempdir().unwrap();
    let f = fitted(
        dir.path(),
        "temperature_c,omega_rad_s,e1_pa,e2_pa\n-5,1,2e6,2e5\n-5,100,3e6,3e5\n17,10,2.5e6,2.5e5\n35.5,1,2e6,2e5\n35.5,1000,4e6,4e5\n",
        "d",
    );
    let shift = |t: f64| 10f64.powf(-8.86 * (t - 17.0) / (101.6 + t - 17.0));
    let range = f["fit"]["frequency_range"].as_array().unwrap();
    let (lo, hi) = (range[0].as_float().unwrap(), range[1].as_float().unwrap());
    assert!((lo / shift(35.5) - 1.0).abs() < 1e-12, "{lo}");
    assert!((hi / (100.0 * shift(-5.0)) - 1.0).abs() < 1e-12, "{hi}");

    // A recorded range that cannot be one is refused as the config's is.
    let shipped_text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("configs/data/sbr_like_material.toml"),
    )
    .unwrap();
    let line = shipped_text
        .lines()
        .find(|l| l.starts_with("frequency_range"))
        .unwrap();
    let bad = dir.path().join("bad.toml");
    std::fs::write(
        &bad,
        shipped_text.replace(line, "frequency_range = [0.0, 1.0]"),
    )
    .unwrap();
    let e = problem(dir.path(), &on_file(&bad, "", &text("", 17.0)))
        .expect_err("a frequency range of zero");
    assert!(
        e.contains("[fit] frequency_range") && e.contains("positive") && !e.contains('\n'),
        "{e}"
    );

    let shipped = Path::new(env!("CARGO_MANIFEST_DIR")).join("configs/data/sbr_like_material.toml");
    let config = on_file(
        &shipped,
        "",
        &text("", -10.0).replace("speed = 0.05", "speed = 1e3"),
    );
    let w = frequency_warnings(dir.path(), &config);
    let hi = 74_609_283.866_236_85 / 10f64.powf(8.86 * 27.0 / 74.6);
    assert!(
        w.len() == 1 && w[0].contains(&format!("({hi:.3e} rad/s at this temperature)")),
        "{w:?}"
    );
}
