//! Time-temperature superposition of the isothermal model (physics.md
//! section 12): with every creep time scaled by the WLF factor `a_T`,
//! `mu(v, T) = mu(a_T v, T_ref)` exactly, for the boundary-element solve
//! (both formulations, friction by both routes and contact area), on the
//! GPU path, and for Persson's theory; and the refusals of a temperature
//! the material cannot take.

use std::path::Path;

use viscoslide::config;
use viscoslide::internals::solver::Silent;
use viscoslide::persson::{Persson, PerssonParams};
use viscoslide::problem::persson::theory_inputs;
use viscoslide::problem::{Executor, Problem};

/// An SLS rubber with WLF constants `C1 = 8.86`, `C2 = 101.6 K`, `T_ref =
/// 17 C` on a small generated surface; `FORMULATION`, `SPEED` and the
/// `[loading]` extras are filled in per test.
const BASE: &str = r#"
[material]
model = "sls"
relaxed_modulus = 3.3333333333333335e6
glassy_modulus = 1.0e7
creep_time = 0.01
wlf = [8.86, 101.6, 17.0]

[surface.generate]
n = 32
length = 0.01
hurst = 0.8
scales = 4
rms_slope = 0.02
seed = 3

[loading]
mean_pressure = 3000.0
speed = SPEED
EXTRA

[solver]
tolerance = 1e-10
formulation = "FORMULATION"

[analysis]
enabled = false
"#;

/// `log10 a_T = -C1 (T - T_ref) / (C2 + T - T_ref)`, written out here
/// independently of the library.
fn shift(t: f64) -> f64 {
    let dt = t - 17.0;
    10f64.powf(-8.86 * dt / (101.6 + dt))
}

fn write(dir: &Path, name: &str, text: &str) -> std::path::PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

fn config_text(formulation: &str, speed: f64, extra: &str) -> String {
    BASE.replace("FORMULATION", formulation)
        .replace("SPEED", &format!("{speed:e}"))
        .replace("EXTRA", extra)
}

fn problem(formulation: &str, speed: f64, extra: &str) -> Problem {
    let dir = tempfile::tempdir().unwrap();
    let p = write(
        dir.path(),
        "c.toml",
        &config_text(formulation, speed, extra),
    );
    Problem::from_config(&config::load(&p, &[]).unwrap()).unwrap()
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs().max(1e-300)
}

/// The BEM at `T` and speed `v` against `T_ref` and speed `a_T v`, both
/// formulations, friction by Eq. 9 and by dissipation, and the contact
/// area: 1e-9 relative. The two problems differ only in where the factor
/// `a_T` multiplies (the creep times or the speed): the operators agree
/// to rounding (1e-16), the iteration follows the same path, and the
/// solution is converged to 1e-10; 1e-9 leaves room for that and nothing
/// physical. The shift is large (a_T = 8.3 at 7 C, 0.14 at 27 C), so a
/// temperature that did not reach the kernel would fail by far.
#[test]
fn bem_friction_at_temperature_equals_the_shifted_speed_at_t_ref() {
    let v = 0.05;
    for formulation in ["non_periodic", "periodic"] {
        for t in [7.0, 27.0] {
            let a = shift(t);
            let hot = problem(formulation, v, &format!("temperature = {t}"));
            let reference = problem(formulation, a * v, "");
            let s1 = hot.solve(&Executor::Cpu, &mut Silent).unwrap();
            let s0 = reference.solve(&Executor::Cpu, &mut Silent).unwrap();
            let same = problem(formulation, v, "");
            let s2 = same.solve(&Executor::Cpu, &mut Silent).unwrap();
            println!(
                "{formulation} T = {t}: mu {:.12e} vs {:.12e} (unshifted {:.6e}); area {:.6e} vs {:.6e}",
                s1.friction_coefficient,
                s0.friction_coefficient,
                s2.friction_coefficient,
                s1.stats.contact_area_fraction,
                s0.stats.contact_area_fraction
            );
            assert!(rel(s1.friction_coefficient, s0.friction_coefficient) < 1e-9);
            assert!(
                rel(
                    s1.friction_coefficient_dissipation,
                    s0.friction_coefficient_dissipation
                ) < 1e-9
            );
            assert!(
                rel(
                    s1.stats.contact_area_fraction,
                    s0.stats.contact_area_fraction
                ) < 1e-9
            );
            // The shift matters: the same speed at T_ref is another answer.
            assert!(rel(s1.friction_coefficient, s2.friction_coefficient) > 1e-2);
            // summary.json states the temperature and a_T (Persson's too).
            let sum = s1.summary();
            assert_eq!(sum["temperature"], serde_json::json!(t));
            assert!(rel(sum["shift_factor"].as_f64().unwrap(), a) < 1e-13);
            assert_eq!(sum["reference_temperature"], serde_json::json!(17.0));
            assert!(rel(sum["persson"]["shift_factor"].as_f64().unwrap(), a) < 1e-13);
            // Persson beside the solve: the same identity.
            let (p1, p0) = (
                sum["persson_friction_coefficient"].as_f64().unwrap(),
                s0.summary()["persson_friction_coefficient"]
                    .as_f64()
                    .unwrap(),
            );
            assert!(rel(p1, p0) < 1e-9, "{p1} {p0}");
        }
    }
}

/// Persson's theory from a configuration (`viscoslide persson`, `merge`):
/// `mu(v, T) = mu(a_T v, T_ref)` and `A(v, T) = A(a_T v, T_ref)` over six
/// decades of speed, 1e-9 relative (the theory's quadrature is the same
/// for both: only where `a_T` multiplies differs). The SBR-like material
/// file carries its WLF constants in `[fit]`.
#[test]
fn persson_at_temperature_equals_the_shifted_speed_at_t_ref() {
    let dir = tempfile::tempdir().unwrap();
    let repo = Path::new(env!("CARGO_MANIFEST_DIR"));
    let file = repo.join("configs/data/sbr_like_material.toml");
    let text = |extra: &str| {
        config_text("periodic", 1e-3, extra).replace(
            "model = \"sls\"\nrelaxed_modulus = 3.3333333333333335e6\nglassy_modulus = 1.0e7\ncreep_time = 0.01\nwlf = [8.86, 101.6, 17.0]",
            &format!("model = \"file\"\nfile = \"{}\"", file.display()),
        )
    };
    let speeds: Vec<f64> = (0..13).map(|k| 1e-6 * 10f64.powf(k as f64 / 2.0)).collect();
    for t in [7.0, 37.0] {
        let a = shift(t);
        let hot = config::load(
            &write(dir.path(), "hot.toml", &text(&format!("temperature = {t}"))),
            &[],
        )
        .unwrap();
        let cold = config::load(&write(dir.path(), "ref.toml", &text("")), &[]).unwrap();
        let (hi, ri) = (
            theory_inputs(&hot, None, None).unwrap(),
            theory_inputs(&cold, None, None).unwrap(),
        );
        let th = Persson::new(
            &hi.material,
            &hi.psd,
            hi.nominal_pressure,
            PerssonParams::default(),
        )
        .unwrap();
        let tr = Persson::new(
            &ri.material,
            &ri.psd,
            ri.nominal_pressure,
            PerssonParams::default(),
        )
        .unwrap();
        let shifted: Vec<f64> = speeds.iter().map(|v| a * v).collect();
        let (c1, c0) = (th.curve(&speeds).unwrap(), tr.curve(&shifted).unwrap());
        let mut spread = 0.0f64;
        for (p1, p0) in c1.iter().zip(&c0) {
            assert!(rel(p1.friction_coefficient, p0.friction_coefficient) < 1e-9);
            assert!(rel(p1.contact_area_fraction, p0.contact_area_fraction) < 1e-9);
            spread = spread.max(rel(p1.friction_coefficient, c0[0].friction_coefficient));
        }
        assert!(spread > 0.1, "the curve varies over the range: {spread}");
        // Unshifted, the curves differ.
        let plain = tr.curve(&speeds).unwrap();
        assert!(rel(c1[6].friction_coefficient, plain[6].friction_coefficient) > 1e-2);
    }
}

/// The GPU path sees the shifted material: a GPU solve at `T` agrees with
/// the CPU solve at `T` (f32 coefficients: 1e-4 relative, as the other
/// GPU conformance tests) and with the CPU solve at `a_T v` at `T_ref`,
/// while the unshifted problem is 10 % away. Skips without an adapter.
#[test]
fn gpu_solve_at_temperature_matches_the_cpu() {
    let Some(ctx) = crate::common::gpu_context() else {
        return;
    };
    let t = 7.0;
    let v = 0.05;
    let mut hot = problem("non_periodic", v, &format!("temperature = {t}"));
    // The device's own answer: the mixed iteration's f64 residuals would
    // take it to the host operator's answer whatever material the device
    // used.
    hot.gpu_refine = false;
    let cpu = hot.solve(&Executor::Cpu, &mut Silent).unwrap();
    let gpu = hot.solve(&Executor::Gpu(ctx), &mut Silent).unwrap();
    let plain = problem("non_periodic", v, "")
        .solve(&Executor::Cpu, &mut Silent)
        .unwrap();
    let e = rel(gpu.friction_coefficient, cpu.friction_coefficient);
    println!(
        "{}: gpu {:.7e} cpu {:.7e} ({e:.1e}); unshifted {:.7e}",
        gpu.backend, gpu.friction_coefficient, cpu.friction_coefficient, plain.friction_coefficient
    );
    assert!(gpu.backend.starts_with("gpu"), "{}", gpu.backend);
    assert!(e < 1e-4, "{e:.2e}");
    assert!(rel(gpu.friction_coefficient, plain.friction_coefficient) > 1e-2);
}

/// Refusals are one line and name the remedy or the bound: a temperature
/// for a material without WLF constants, at or below `T_ref - C2`, and
/// malformed constants.
#[test]
fn temperatures_the_material_cannot_take_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let no_wlf = config_text("periodic", 0.05, "temperature = 20.0")
        .replace("wlf = [8.86, 101.6, 17.0]\n", "");
    let p = write(dir.path(), "a.toml", &no_wlf);
    let e = Problem::from_config(&config::load(&p, &[]).unwrap())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("WLF") && e.contains("wlf") && !e.contains('\n'),
        "{e}"
    );
    for t in ["-84.6", "-100.0"] {
        let p = write(
            dir.path(),
            "b.toml",
            &config_text("periodic", 0.05, &format!("temperature = {t}")),
        );
        let e = Problem::from_config(&config::load(&p, &[]).unwrap())
            .unwrap_err()
            .to_string();
        assert!(e.contains("T_ref - C2 = -84.6") && !e.contains('\n'), "{e}");
    }
    let p = write(
        dir.path(),
        "c.toml",
        &config_text("periodic", 0.05, "").replace("[8.86, 101.6, 17.0]", "[8.86, -1.0, 17.0]"),
    );
    let e = Problem::from_config(&config::load(&p, &[]).unwrap())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("wlf") && e.contains("C2") && !e.contains('\n'),
        "{e}"
    );
    // A negative speed is the speed's error at any temperature (it was
    // blamed on the temperature: "give a temperature nearer T_ref").
    let p = write(
        dir.path(),
        "e.toml",
        &config_text("periodic", -0.1, "temperature = 17.0"),
    );
    let e = Problem::from_config(&config::load(&p, &[]).unwrap())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("speed must be >= 0") && !e.contains("temperature"),
        "{e}"
    );
    // Persson's inputs refuse the same way.
    let p = write(dir.path(), "d.toml", &no_wlf);
    let e = theory_inputs(&config::load(&p, &[]).unwrap(), None, None)
        .unwrap_err()
        .to_string();
    assert!(e.contains("WLF"), "{e}");
}

/// The command line: a refused temperature writes nothing; an accepted
/// one is stated in summary.json.
#[test]
fn cli_solve_states_the_temperature_and_refuses_without_writing() {
    let dir = tempfile::tempdir().unwrap();
    let bin = env!("CARGO_BIN_EXE_viscoslide");
    let p = write(
        dir.path(),
        "c.toml",
        &config_text("periodic", 0.05, "temperature = 7.0"),
    );
    let out = dir.path().join("bad");
    let o = std::process::Command::new(bin)
        .args(["solve"])
        .arg(&p)
        .args(["--set", "loading.temperature=-90", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success());
    assert!(
        err.contains("T_ref - C2") && err.trim().lines().count() == 1,
        "{err}"
    );
    assert!(!out.exists(), "nothing written");
    let good = dir.path().join("good");
    let o = std::process::Command::new(bin)
        .args(["solve"])
        .arg(&p)
        .arg("--out")
        .arg(&good)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(good.join("summary.json")).unwrap()).unwrap();
    assert_eq!(s["temperature"], serde_json::json!(7.0));
    assert!(rel(s["shift_factor"].as_f64().unwrap(), shift(7.0)) < 1e-13);
    // `viscoslide persson` states them too, and its curve at T is the
    // curve at T_ref at the shifted speeds.
    let run = |extra: &[&str], dir: &str| -> serde_json::Value {
        let out = p.parent().unwrap().join(dir);
        let o = std::process::Command::new(bin)
            .arg("persson")
            .arg(&p)
            .args(extra)
            .arg("--out")
            .arg(&out)
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        serde_json::from_str(&std::fs::read_to_string(out.join("persson.json")).unwrap()).unwrap()
    };
    let a = shift(7.0);
    let hot = run(&["--speeds", "1e-3,1e-1,3"], "p_hot");
    let speeds = format!("{:e},{:e},3", a * 1e-3, a * 1e-1);
    let reference = run(
        &["--set", "loading.temperature=17.0", "--speeds", &speeds],
        "p_ref",
    );
    assert_eq!(hot["temperature"], serde_json::json!(7.0));
    assert!(rel(hot["shift_factor"].as_f64().unwrap(), a) < 1e-13);
    assert_eq!(reference["shift_factor"], serde_json::json!(1.0));
    for k in 0..3 {
        let (m1, m0) = (
            hot["friction_coefficient"][k].as_f64().unwrap(),
            reference["friction_coefficient"][k].as_f64().unwrap(),
        );
        // The speeds of the reference pass through a decimal string: 1e-9.
        assert!(rel(m1, m0) < 1e-9, "{m1} {m0}");
    }
}

/// Run the command-line tool with `args`.
fn cli<S: AsRef<std::ffi::OsStr>>(args: &[S]) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_viscoslide"))
        .args(args)
        .output()
        .unwrap()
}

/// A refusal: a nonzero exit, one `error:` line on stderr holding every
/// `needle`, and nothing at `out`.
fn refused(o: &std::process::Output, needles: &[&str], out: &Path) {
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success(), "accepted: {err}");
    assert!(
        err.starts_with("error:") && err.trim_end().lines().count() == 1,
        "{err}"
    );
    for needle in needles {
        assert!(err.contains(needle), "{needle} not in {err}");
    }
    assert!(!out.exists(), "{} written", out.display());
}

/// Just above the pole `T_ref - C2 = -84.6 C` of `wlf = [8.86, 101.6,
/// 17.0]` (-84.4 C: `log10 a_T` = 4492, `a_T` overflows; -80 C: `a_T` =
/// 6.8e186) the solve is refused by both formulations, in one line naming
/// the temperature and the validity range `T >= T_ref - C2 * 50 / (C1 +
/// 50)` = -69.306 C (`|log10 a_T| <= 50`, quoted rounded up to -69.3 C),
/// with nothing written.
#[test]
fn cli_refuses_temperatures_near_the_wlf_pole() {
    let dir = tempfile::tempdir().unwrap();
    for formulation in ["non_periodic", "periodic"] {
        let p = write(
            dir.path(),
            "c.toml",
            &config_text(formulation, 0.05, "temperature = 7.0"),
        );
        for t in ["-84.4", "-80", "-69.31"] {
            let out = dir.path().join(format!("{formulation}{t}"));
            let set = format!("loading.temperature={t}");
            let o = cli(&[
                "solve",
                p.to_str().unwrap(),
                "--set",
                set.as_str(),
                "--out",
                out.to_str().unwrap(),
            ]);
            refused(
                &o,
                &[
                    &format!("temperature {t} C"),
                    "T >= -69.3 C",
                    "T_ref - C2 = -84.6 C",
                ],
                &out,
            );
        }
    }
    // Inside the range, but with a speed that the shift takes out of
    // double precision: xi = v a_T tau / L overflows.
    let p = write(
        dir.path(),
        "fast.toml",
        &config_text("non_periodic", 1e280, "temperature = -69.3"),
    );
    let out = dir.path().join("fast");
    let o = cli(&["solve", p.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    refused(&o, &["temperature = -69.3 C", "xi"], &out);
}

/// Absurd WLF constants are refused in one line naming the key, from a
/// config file (`solve`, at 27 C where `C1 = 1e300` gave `a_T = 0`, and
/// without a temperature), by `material show`, and by `material fit
/// --wlf`: `C1` beyond 50 (`log10 a_T` tends to `-C1` at high
/// temperature), non-finite values, `C2 <= 0`, and any count but three.
#[test]
fn absurd_wlf_constants_are_refused_naming_the_key() {
    let dir = tempfile::tempdir().unwrap();
    let p = write(
        dir.path(),
        "c.toml",
        &config_text("non_periodic", 0.05, "temperature = 27.0"),
    );
    let cases: [(&str, &[&str]); 9] = [
        ("[1e300, 101.6, 17.0]", &["wlf", "C1 = 1e300", "50"]),
        ("[60.0, 101.6, 17.0]", &["wlf", "C1 = 6e1", "50"]),
        ("[-51.0, 101.6, 17.0]", &["wlf", "C1 = -5.1e1"]),
        ("[nan, 101.6, 17.0]", &["wlf", "finite"]),
        ("[8.86, inf, 17.0]", &["wlf", "finite"]),
        ("[8.86, 0.0, 17.0]", &["wlf", "C2 > 0"]),
        ("[8.86, -101.6, 17.0]", &["wlf", "C2 > 0"]),
        ("[8.86, 101.6, 17.0, 4.0]", &["wlf", "length 4", "length 3"]),
        ("[8.86, 101.6]", &["wlf", "length 2", "length 3"]),
    ];
    for (k, (wlf, needles)) in cases.iter().enumerate() {
        let set = format!("material.wlf={wlf}");
        for extra in [None, Some("loading.temperature=17.0")] {
            let out = dir.path().join(format!("solve{k}"));
            let mut args: Vec<&str> = vec!["solve", p.to_str().unwrap(), "--set", set.as_str()];
            if let Some(e) = extra {
                args.extend(["--set", e]);
            }
            args.extend(["--out", out.to_str().unwrap()]);
            refused(&cli(&args), needles, &out);
        }
        let o = cli(&[
            "material",
            "show",
            p.to_str().unwrap(),
            "--set",
            set.as_str(),
        ]);
        refused(&o, needles, &dir.path().join("none"));
        assert!(o.stdout.is_empty());
    }
    // The same values in a config file, not through --set.
    let q = write(
        dir.path(),
        "d.toml",
        &config_text("non_periodic", 0.05, "temperature = 27.0")
            .replace("[8.86, 101.6, 17.0]", "[8.86, 101.6, 17.0, 4.0]"),
    );
    let out = dir.path().join("four");
    let o = cli(&["solve", q.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    refused(&o, &["wlf", "length 4"], &out);
    // `material fit --wlf`: the constants, and a target temperature or a
    // data temperature outside the validity range.
    let csv = Path::new(env!("CARGO_MANIFEST_DIR")).join("configs/data/sbr_like_dma.csv");
    for (wlf, t, needles) in [
        ("1e300,101.6,17", "17", &["--wlf", "C1 = 1e300"][..]),
        ("8.86,0,17", "17", &["--wlf", "C2 > 0"][..]),
        (
            "8.86,101.6,17",
            "-80",
            &["temperature -80 C", "T >= -69.3 C"][..],
        ),
    ] {
        let out = dir.path().join("fit");
        let o = cli(&[
            "material",
            "fit",
            csv.to_str().unwrap(),
            "--wlf",
            wlf,
            &format!("--temperature={t}"),
            "--out",
            out.to_str().unwrap(),
        ]);
        refused(&o, needles, &out);
    }
    let data = write(
        dir.path(),
        "cold.csv",
        "temperature_c,omega_rad_s,e1_pa,e2_pa\n-80,1,2e6,1e5\n17,10,2e6,2e5\n17,100,3e6,3e5\n",
    );
    let out = dir.path().join("fit_cold");
    let o = cli(&[
        "material",
        "fit",
        data.to_str().unwrap(),
        "--wlf",
        "8.86,101.6,17",
        "--out",
        out.to_str().unwrap(),
    ]);
    refused(&o, &["temperature -80 C", "T >= -69.3 C"], &out);
}

/// `a_T` at ordinary temperatures is the WLF form evaluated as
/// `10^(log10 a_T)`, to the last bit, in the library and in
/// `summary.json`; and within 1e-15 relative of the product form
/// `exp(ln 10 log10 a_T)` near `T_ref`, where that form's own rounding
/// (`|ln a_T|` ulps) is below it.
#[test]
fn shift_factor_at_ordinary_temperatures_is_unchanged() {
    use viscoslide::material::Wlf;
    let wlf = Wlf::new(8.86, 101.6, 17.0).unwrap();
    for t in [-40.0, -3.0, 7.0, 16.0, 17.0, 18.0, 27.0, 57.0, 150.0] {
        assert_eq!(
            wlf.shift_factor(t).unwrap().to_bits(),
            shift(t).to_bits(),
            "{t}"
        );
    }
    for t in [16.9, 17.0, 17.1] {
        let dt: f64 = t - 17.0;
        let product = (std::f64::consts::LN_10 * (-8.86 * dt / (101.6 + dt))).exp();
        assert!(rel(wlf.shift_factor(t).unwrap(), product) <= 1e-15, "{t}");
    }
    let dir = tempfile::tempdir().unwrap();
    let p = write(
        dir.path(),
        "c.toml",
        &config_text("periodic", 0.05, "temperature = 7.0"),
    );
    let out = dir.path().join("o");
    let o = cli(&["solve", p.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(
        s["shift_factor"].as_f64().unwrap().to_bits(),
        shift(7.0).to_bits()
    );
}

/// Every number of a JSON document finite; the paths of its nulls
/// collected (serde_json writes a NaN or an infinity as null).
fn walk(v: &serde_json::Value, path: &str, nulls: &mut Vec<String>) {
    match v {
        serde_json::Value::Null => nulls.push(path.to_string()),
        serde_json::Value::Number(n) => {
            assert!(n.as_f64().is_some_and(f64::is_finite), "{path} = {n}")
        }
        serde_json::Value::Array(a) => {
            for (i, x) in a.iter().enumerate() {
                walk(x, &format!("{path}[{i}]"), nulls);
            }
        }
        serde_json::Value::Object(o) => {
            for (k, x) in o {
                walk(x, &format!("{path}.{k}"), nulls);
            }
        }
        _ => {}
    }
}

/// No NaN reaches an output with exit code 0: near the pole (-84.4 C,
/// where `a_T` overflowed and `summary.json` held nulls for the
/// dissipation friction, `shift_factor` and `xi`) the solve is refused;
/// just inside the validity range (-69.3 C, `a_T` = 9.3e49) every number
/// of `summary.json` and of `persson.json` is finite and their nulls are
/// exactly those of the same run at `T_ref`, and the pressure, gap and
/// displacement maps are finite; both formulations.
#[test]
fn outputs_near_the_bound_are_finite_in_every_field() {
    let dir = tempfile::tempdir().unwrap();
    for formulation in ["non_periodic", "periodic"] {
        let p = write(
            dir.path(),
            &format!("{formulation}.toml"),
            &config_text(formulation, 0.05, ""),
        );
        let run = |cmd: &str, t: &str, file: &str| -> Option<(serde_json::Value, Vec<String>)> {
            let out = dir.path().join(format!("{cmd}{formulation}{t}"));
            let set = format!("loading.temperature={t}");
            let o = cli(&[
                cmd,
                p.to_str().unwrap(),
                "--set",
                set.as_str(),
                "--out",
                out.to_str().unwrap(),
            ]);
            if !o.status.success() {
                refused(&o, &["T >= -69.3 C"], &out);
                return None;
            }
            let doc: serde_json::Value =
                serde_json::from_str(&std::fs::read_to_string(out.join(file)).unwrap()).unwrap();
            let mut nulls = Vec::new();
            walk(&doc, "", &mut nulls);
            if cmd == "solve" {
                for map in ["pressure", "gap", "displacement"] {
                    let (_, _, data) =
                        viscoslide::io::npy::read_2d(out.join(format!("{map}.npy"))).unwrap();
                    assert!(data.iter().all(|x| x.is_finite()), "{map}.npy at {t} C");
                }
            }
            Some((doc, nulls))
        };
        for (cmd, file) in [("solve", "summary.json"), ("persson", "persson.json")] {
            let (_, reference) = run(cmd, "17.0", file).unwrap();
            assert!(run(cmd, "-84.4", file).is_none(), "{cmd} at -84.4 C");
            let (doc, nulls) = run(cmd, "-69.3", file).expect("inside the range");
            assert_eq!(nulls, reference, "{cmd} {formulation}");
            assert!(doc["shift_factor"].as_f64().unwrap() > 1e49);
            if cmd == "solve" {
                for key in [
                    "xi",
                    "friction_coefficient",
                    "friction_coefficient_dissipation",
                ] {
                    assert!(doc[key].is_number(), "{key}");
                }
            }
        }
    }
}
