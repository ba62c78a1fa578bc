//! Every check before anything is written: a study or a sweep whose plan
//! fails anywhere (a varied key's value in one combination, a solver
//! setting that only the solve would meet) is refused before its first
//! point, and leaves `--out` as it was: nothing made where there was
//! nothing, the corrected command accepted in the same directory.

use std::path::Path;
use std::process::Command;

/// A 64^2 generated surface on the adaptive mesh (non-periodic), a load
/// and a speed; `EXTRA` is replaced by a `[sweep]` or nothing.
const CONFIG: &str = r#"
[material]
model = "sls"
relaxed_modulus = 3.3333333333333335e6
glassy_modulus = 1.0e7
creep_time = 0.01

[surface.generate]
n = 64
length = 0.01
hurst = 0.8
scales = 8
rms_slope = 0.02
seed = 3

[loading]
normal_load = 0.3
speed = 0.01

[solver]
formulation = "non_periodic"
mesh = "adaptive"

[analysis]
enabled = false

EXTRA
"#;

fn viscoslide(args: &[&str]) -> (bool, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_viscoslide"))
        .args(args)
        .output()
        .unwrap();
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

fn write_config(dir: &Path, extra: &str) -> String {
    let p = dir.join("case.toml");
    std::fs::write(&p, CONFIG.replace("EXTRA", extra)).unwrap();
    p.display().to_string()
}

/// Every entry under `dir` with its contents (files) or `/` (folders).
pub(crate) fn snapshot(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            let name = p.strip_prefix(dir).unwrap().display().to_string();
            if p.is_dir() {
                out.push((format!("{name}/"), Vec::new()));
                stack.push(p);
            } else {
                out.push((name, std::fs::read(&p).unwrap()));
            }
        }
    }
    out.sort();
    out
}

/// The issue's magnification: mixed precision on the adaptive mesh is
/// refused before the pin and `points/` are made, and the corrected
/// command then runs in the same directory.
#[test]
fn a_refused_magnification_writes_nothing_and_the_corrected_one_runs() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = write_config(tmp.path(), "");
    let out = tmp.path().join("study");
    let o = out.display().to_string();
    let base = [
        "magnification",
        cfg.as_str(),
        "--scales",
        "4,8",
        "--set",
        "solver.mesh=\"adaptive\"",
        "--set",
        "solver.formulation=\"non_periodic\"",
        "--backend",
        "cpu",
        "--out",
        o.as_str(),
    ];
    let mut refused = base.to_vec();
    refused.extend(["--set", "solver.precision=\"mixed\""]);
    let (ok, _, err) = viscoslide(&refused);
    assert!(!ok, "accepted");
    assert!(err.contains("precision"), "{err}");
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(!out.exists(), "a refused study made {}", out.display());
    // Into a directory that exists and holds something: left as it was.
    std::fs::create_dir(&out).unwrap();
    std::fs::write(out.join("notes.txt"), b"mine").unwrap();
    let before = snapshot(&out);
    let (ok, _, err) = viscoslide(&refused);
    assert!(!ok, "accepted");
    assert_eq!(snapshot(&out), before, "{err}");
    let (ok, stdout, err) = viscoslide(&base);
    assert!(ok, "the corrected study: {err}");
    assert!(stdout.contains("0 already done, 2 solved now"), "{stdout}");
}

/// The issue's sweep: the adaptive mesh with `"solver.precision" = ["f64",
/// "mixed"]` is refused before its first point.
#[test]
fn a_sweep_refused_in_a_later_combination_solves_and_writes_nothing() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = write_config(
        tmp.path(),
        "[sweep]\nspeed = [0.01, 0.1]\ninclude_static = false\n\n[sweep.vary]\n\"solver.precision\" = [\"f64\", \"mixed\"]\n",
    );
    let out = tmp.path().join("run");
    let (ok, stdout, err) = viscoslide(&["sweep", &cfg, "--out", out.to_str().unwrap()]);
    assert!(!ok, "accepted: {stdout}");
    assert!(
        err.contains("\"solver.precision\"") || err.contains("precision"),
        "{err}"
    );
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(!out.exists(), "a refused sweep made {}", out.display());
}

/// A speed range of another length than `[from, to, points]` is refused
/// in one line, not read as its first three numbers.
#[test]
fn a_speed_range_of_another_length_is_refused() {
    let tmp = tempfile::tempdir().unwrap();
    for (key, range, n) in [
        ("speed_range", "[1e-3, 1e-1, 3, 7]", 4),
        ("speed_range", "[1e-3, 1e-1]", 2),
        ("xi_range", "[1e-3, 1e-1, 3, 7]", 4),
    ] {
        let cfg = write_config(
            tmp.path(),
            &format!("[sweep]\n{key} = {range}\ninclude_static = false\n"),
        );
        let out = tmp.path().join("run");
        let (ok, stdout, err) = viscoslide(&["sweep", &cfg, "--out", out.to_str().unwrap()]);
        assert!(!ok, "accepted: {stdout}");
        assert!(
            err.contains(key)
                && err.contains(&format!(
                    "invalid length {n}, expected an array of length 3"
                )),
            "{err}"
        );
        assert_eq!(err.trim().lines().count(), 1, "{err}");
        assert!(!out.exists(), "a refused sweep made {}", out.display());
    }
}

/// `sweep --backend` as `solve --backend`: the executor is named on
/// stderr and in every point; a bad name is refused before anything is
/// written.
#[test]
fn a_sweep_takes_a_backend_as_solve_does() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = write_config(
        tmp.path(),
        "[sweep]\nspeed = [0.01]\ninclude_static = false\n",
    );
    let text = std::fs::read_to_string(&cfg)
        .unwrap()
        .replace("mesh = \"adaptive\"", "mesh = \"uniform\"");
    std::fs::write(&cfg, text).unwrap();
    let out = tmp.path().join("run");
    let o = out.display().to_string();
    let (ok, _, err) = viscoslide(&["sweep", &cfg, "--out", &o, "--backend", "nope"]);
    assert!(!ok && err.contains("nope"), "{err}");
    assert!(!out.exists());
    let (ok, _, err) = viscoslide(&["sweep", &cfg, "--out", &o, "--backend", "cpu"]);
    assert!(ok, "{err}");
    assert!(err.lines().any(|l| l == "backend: cpu"), "{err}");
    let point: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("points/p0000.json")).unwrap())
            .unwrap();
    assert_eq!(point["backend"], "cpu", "{point}");
}

/// A magnification study at a speed whose frequencies `q1 v` leave double
/// precision is refused by Persson's theory before the pin and `points/`
/// are made (it made both, then failed at the first point's theory).
#[test]
fn a_magnification_beyond_persson_precision_writes_nothing() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = write_config(tmp.path(), "");
    let out = tmp.path().join("study");
    let (ok, _, err) = viscoslide(&[
        "magnification",
        cfg.as_str(),
        "--scales",
        "4,8",
        "--speed",
        "1e308",
        "--set",
        "solver.mesh=\"uniform\"",
        "--backend",
        "cpu",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(!ok, "accepted");
    assert!(err.contains("leave double precision"), "{err}");
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(!out.exists(), "a refused study made {}", out.display());
}
