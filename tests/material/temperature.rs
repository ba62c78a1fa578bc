//! Time-temperature superposition of the isothermal model (physics.md
//! section 12): with every creep time scaled by the WLF factor `a_T`,
//! `mu(v, T) = mu(a_T v, T_ref)` exactly, for the boundary-element solve
//! (both formulations, friction by both routes and contact area), on the
//! GPU path, and for Persson's theory; and the refusals of a temperature
//! the material cannot take.

use std::path::Path;

use viscoslide::config;
use viscoslide::persson::{Persson, PerssonParams};
use viscoslide::problem::persson::theory_inputs;
use viscoslide::problem::{Executor, Problem};
use viscoslide::solver::Silent;

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
    let Some(ctx) = viscoslide::backend::gpu::context_for_tests() else {
        return;
    };
    let t = 7.0;
    let v = 0.05;
    let mut hot = problem("non_periodic", v, &format!("temperature = {t}"));
    // The device's own answer: the host refinement would converge to the
    // host operator's answer whatever material the device used.
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
