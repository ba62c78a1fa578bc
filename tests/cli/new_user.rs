//! What a new user runs into: unwritable outputs, bad `--set` values,
//! directories that are not sweeps (or do not exist), unphysical loads,
//! surfaces too large for memory, stale outputs from an earlier solve, empty
//! sweep axes, and friction routes that disagree. Each is refused or
//! reported in one line.

use std::path::Path;
use std::process::Command;

use viscoslide::config::{self, AnalysisConfig, SweepConfig};
use viscoslide::internals::solver::{Control, Silent};
use viscoslide::material::{CreepSpectrum, Material};
use viscoslide::problem::{Executor, Problem};
use viscoslide::surface::{GenerateParams, UpperCutoff};
use viscoslide::sweep::SweepPlan;

const CONFIG: &str = r#"
[material]
model = "sls"
relaxed_modulus = 3.3333333333333335e6
glassy_modulus = 1.0e7
creep_time = 0.01
poisson = 0.5

[surface.generate]
n = 32
length = 0.01
hurst = 0.8
scales = 4
rms_slope = 0.02
seed = 3

[loading]
normal_load = 0.30
xi = 1.17e-2
"#;

fn viscoslide(args: &[&str]) -> (bool, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_viscoslide"))
        .args(args)
        .env("VISCOSLIDE_BACKEND", "cpu")
        .output()
        .unwrap();
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

fn write_config(dir: &Path) -> String {
    let p = dir.join("c.toml");
    std::fs::write(&p, CONFIG).unwrap();
    p.display().to_string()
}

/// The paper's single-relaxation material.
fn material() -> Material {
    Material::new(
        CreepSpectrum::standard_linear_solid(3.3333333333333335e6, 1e7, 0.01).unwrap(),
        0.5,
    )
    .unwrap()
}

fn surface(n: usize) -> GenerateParams {
    GenerateParams {
        nx: n,
        ny: n,
        upper: UpperCutoff::Scales(4.0),
        seed: 3,
        ..Default::default()
    }
}

/// An output directory that cannot be written is refused before the solve
/// starts, naming the path.
#[test]
fn an_unwritable_output_is_refused_before_solving() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = write_config(tmp.path());
    let (ok, _, err) = viscoslide(&["solve", &cfg, "--out", "/proc/viscoslide-out"]);
    assert!(!ok);
    assert!(err.contains("/proc/viscoslide-out"), "{err}");
    assert!(!err.contains("solving"), "the solve must not start: {err}");
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    // Under a regular file.
    let file = tmp.path().join("f");
    std::fs::write(&file, "x").unwrap();
    let under = file.join("out").display().to_string();
    let (ok, _, err) = viscoslide(&["solve", &cfg, "--out", &under]);
    assert!(!ok);
    assert!(err.contains("not a directory"), "{err}");
    assert!(!err.contains("solving"), "{err}");
}

/// A bad value given with `--set` is reported against the flag, not
/// against a line of the file it did not come from.
#[test]
fn a_bad_set_value_names_the_flag() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = write_config(tmp.path());
    let e = config::load(
        Path::new(&cfg),
        &["solver.formulation=\"sideways\"".to_string()],
    )
    .unwrap_err()
    .to_string();
    assert!(e.starts_with("--set solver.formulation="), "{e}");
    assert!(e.contains("sideways"), "{e}");
    assert!(!e.contains("line "), "{e}");
    assert!(!e.contains("c.toml"), "{e}");
    // A good override beside it does not take the blame.
    let e = config::load(
        Path::new(&cfg),
        &[
            "material.poisson=0.4".to_string(),
            "loading.normal_load=\"heavy\"".to_string(),
        ],
    )
    .unwrap_err()
    .to_string();
    assert!(e.starts_with("--set loading.normal_load="), "{e}");
    assert!(e.contains("normal_load: N"), "the unit is named: {e}");
}

/// `merge` of a directory that is not a sweep says so.
#[test]
fn merging_a_directory_that_is_not_a_sweep_says_so() {
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path().display().to_string();
    let (ok, _, err) = viscoslide(&["merge", &d]);
    assert!(!ok);
    assert!(err.contains("not a sweep directory"), "{err}");
    assert!(!err.contains("No such file"), "{err}");
}

/// `merge` of a directory that does not exist says that, and makes nothing.
#[test]
fn merging_a_directory_that_does_not_exist_says_so() {
    let tmp = tempfile::tempdir().unwrap();
    let missing = tmp.path().join("no_such_dir");
    let d = missing.display().to_string();
    let (ok, _, err) = viscoslide(&["merge", &d]);
    assert!(!ok);
    assert!(err.contains("no such directory"), "{err}");
    assert!(!err.contains("not a sweep directory"), "{err}");
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(!missing.exists(), "a refused merge made {d}");
    // A file where the directory should be is named as such.
    std::fs::write(&missing, "").unwrap();
    let (ok, _, err) = viscoslide(&["merge", &d]);
    assert!(!ok);
    assert!(err.contains("not a directory"), "{err}");
}

/// A mean pressure above the material's modulus is solved, with a warning
/// on the console and in summary.json; an ordinary load gets none.
#[test]
fn a_load_beyond_small_strain_is_warned_about() {
    let heavy = Problem::generated(material(), surface(32), Control::Load(1e9), 1e-3)
        .unwrap()
        .solve(&Executor::Cpu, &mut Silent)
        .unwrap();
    let w = heavy.warnings.join("\n");
    assert!(w.contains("small-strain"), "{w}");
    assert!(w.contains("exceeds the relaxed modulus"), "{w}");
    let summary = heavy.summary();
    assert!(summary["warnings"]
        .as_array()
        .unwrap()
        .iter()
        .any(|s| s.as_str().unwrap().contains("small-strain")));
    let light = Problem::generated(material(), surface(32), Control::Load(0.3), 1e-3)
        .unwrap()
        .solve(&Executor::Cpu, &mut Silent)
        .unwrap();
    assert!(
        !light.warnings.iter().any(|w| w.contains("small-strain")),
        "{:?}",
        light.warnings
    );
    // And on the console.
    let tmp = tempfile::tempdir().unwrap();
    let cfg = write_config(tmp.path());
    let out = tmp.path().join("out").display().to_string();
    let (ok, _, err) = viscoslide(&[
        "solve",
        &cfg,
        "--set",
        "loading.normal_load=1e9",
        "--set",
        "analysis.enabled=false",
        "--out",
        &out,
    ]);
    assert!(ok, "{err}");
    assert!(
        err.contains("warning: ") && err.contains("small-strain"),
        "{err}"
    );
}

/// `surface generate` refuses a grid that cannot fit in memory, with the
/// estimate, instead of aborting.
#[test]
fn generating_a_surface_too_large_for_memory_is_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("s").display().to_string();
    let (ok, _, err) = viscoslide(&[
        "surface",
        "generate",
        "--n",
        "1000000",
        "--length",
        "0.01",
        "--hurst",
        "0.8",
        "--scales",
        "32",
        "--rms-height",
        "1e-6",
        "--out",
        &out,
    ]);
    assert!(!ok);
    assert!(err.contains("needs about") && err.contains("GiB"), "{err}");
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(!Path::new(&out).exists());
}

/// Solving again into a directory replaces the whole output set: no
/// analysis files of an earlier solve survive beside the new summary.
#[test]
fn resolving_into_a_directory_replaces_the_earlier_outputs() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("out");
    let problem = Problem::generated(material(), surface(32), Control::Load(0.3), 1e-3).unwrap();
    let first = problem.solve(&Executor::Cpu, &mut Silent).unwrap();
    first.write(&dir).unwrap();
    assert!(dir.join("analysis.json").exists());
    assert!(dir.join("analysis_contact.png").exists());
    std::fs::write(dir.join("notes.txt"), "mine").unwrap();
    let second = problem
        .with_analysis(AnalysisConfig {
            enabled: Some(false),
            ..Default::default()
        })
        .solve(&Executor::Cpu, &mut Silent)
        .unwrap();
    second.write(&dir).unwrap();
    assert!(dir.join("summary.json").exists());
    assert!(!dir.join("analysis.json").exists());
    assert!(!dir.join("analysis_contact.png").exists());
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    assert!(summary["analysis"].is_null());
    // Files that are not outputs of a solve are left alone.
    assert_eq!(
        std::fs::read_to_string(dir.join("notes.txt")).unwrap(),
        "mine"
    );
}

/// A sweep with an empty axis is refused instead of running only the
/// static point.
#[test]
fn an_empty_sweep_axis_is_refused() {
    for cfg in [
        SweepConfig {
            xi: Some(vec![]),
            ..Default::default()
        },
        SweepConfig {
            speed: Some(vec![]),
            ..Default::default()
        },
        SweepConfig {
            xi: Some(vec![0.1]),
            normal_load: Some(vec![]),
            ..Default::default()
        },
    ] {
        let e = SweepPlan::new(&cfg).unwrap_err().to_string();
        assert!(e.contains("is empty"), "{e}");
    }
}

/// When the two friction routes differ by more than 2 %, the solution says
/// so and names the likely cause; when they agree, it says nothing.
#[test]
fn disagreeing_friction_routes_are_warned_about() {
    // xi = 6.8 on a 1 cm pad: v tau = 6.8 cm, longer than the pad.
    let fast = Problem::generated(material(), surface(64), Control::Load(2.2), 6.8)
        .unwrap()
        .solve(&Executor::Cpu, &mut Silent)
        .unwrap();
    let d = fast.friction_relative_difference();
    assert!(d > 0.02, "the case must disagree: {d}");
    let w = fast.warnings.join("\n");
    assert!(w.contains("friction routes differ"), "{w}");
    assert!(w.contains("longer than the pad"), "{w}");
    // A resolved case: agreement within 2 % and no warning.
    let slow = Problem::generated(material(), surface(64), Control::Load(0.3), 1e-3)
        .unwrap()
        .solve(&Executor::Cpu, &mut Silent)
        .unwrap();
    let d = slow.friction_relative_difference();
    let warned = slow.warnings.iter().any(|w| w.contains("friction routes"));
    assert_eq!(warned, d > 0.02, "{d}: {:?}", slow.warnings);
}

/// Help texts print units as written: no Markdown escapes (`\[m\]`) from
/// the doc comments clap shows.
#[test]
fn help_texts_show_no_markdown_escapes() {
    for cmd in [
        &["kernel"][..],
        &["heat"],
        &["material", "fit"],
        &["material", "show"],
        &["surface", "generate"],
        &["surface", "stats"],
        &["surface", "convert"],
        &["surface", "resample"],
        &["surface", "psd-stitch"],
        &["persson"],
        &["refine"],
        &["magnification"],
        &["solve"],
    ] {
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_viscoslide"))
            .args(cmd)
            .arg("--help")
            .output()
            .unwrap();
        assert!(o.status.success(), "{cmd:?}");
        let help = String::from_utf8_lossy(&o.stdout);
        assert!(!help.contains('\\'), "{cmd:?} --help:\n{help}");
    }
}
