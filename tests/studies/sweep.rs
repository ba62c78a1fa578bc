//! Sweeps: resume after interruption without recomputation, exact shards,
//! deterministic order-independent merge, refusal of a changed config (but
//! not of a directory whose sweep finished no point).

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant, SystemTime};

const CONFIG: &str = r#"
[material]
model = "sls"
relaxed_modulus = 3.3333333333333335e6
glassy_modulus = 1.0e7
creep_time = 0.01

[surface.generate]
n = 32
length = 0.01
hurst = 0.8
scales = 4
rms_slope = 0.02
seed = 1

[loading]
normal_load = 0.30
xi = 1e-2

[sweep]
xi = [1e-3, 1e-2]
seeds = [1, 2]
"#;

fn viscoslide(args: &[&str]) -> (bool, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_viscoslide"))
        .args(args)
        .output()
        .unwrap();
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

fn write_config(dir: &Path, text: &str) -> String {
    let p = dir.join("sweep.toml.in");
    std::fs::write(&p, text).unwrap();
    p.display().to_string()
}

fn point_times(dir: &Path) -> Vec<(String, SystemTime)> {
    let mut v: Vec<_> = std::fs::read_dir(dir.join("points"))
        .unwrap()
        .map(|e| e.unwrap())
        .map(|e| {
            (
                e.file_name().to_string_lossy().into_owned(),
                e.metadata().unwrap().modified().unwrap(),
            )
        })
        .collect();
    v.sort();
    v
}

#[test]
fn interrupted_sweep_resumes_without_recomputing() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = write_config(tmp.path(), CONFIG);
    let out = tmp.path().join("run");
    let o = out.display().to_string();
    // Stop after 2 of 6 points (3 speeds incl. the static one x 2 seeds).
    let (ok, err) = viscoslide(&["sweep", &cfg, "--out", &o, "--limit", "2"]);
    assert!(ok, "{err}");
    let first = point_times(&out);
    assert_eq!(first.len(), 2);
    assert!(
        !out.join("sweep.csv").exists(),
        "no merge of an unfinished sweep"
    );
    std::thread::sleep(Duration::from_millis(20));
    let (ok, err) = viscoslide(&["sweep", &cfg, "--out", &o]);
    assert!(ok, "{err}");
    let second = point_times(&out);
    assert_eq!(second.len(), 6);
    for (name, t) in &first {
        let again = second.iter().find(|(n, _)| n == name).unwrap();
        assert_eq!(*t, again.1, "{name} was recomputed");
    }
    let csv = std::fs::read_to_string(out.join("sweep.csv")).unwrap();
    assert_eq!(csv.lines().count(), 1 + 3, "{csv}");
    assert!(out.join("friction_vs_xi.png").is_file());
    assert!(out.join("area_ratio_vs_xi.png").is_file());
}

#[test]
fn killed_sweep_loses_nothing() {
    let tmp = tempfile::tempdir().unwrap();
    // Bigger points so that the kill lands mid-sweep.
    let cfg = write_config(
        tmp.path(),
        &CONFIG
            .replace("n = 32", "n = 96")
            .replace("seeds = [1, 2]", "seeds = [1, 2, 3]"),
    );
    let out = tmp.path().join("run");
    let o = out.display().to_string();
    let mut child = Command::new(env!("CARGO_BIN_EXE_viscoslide"))
        .args(["sweep", &cfg, "--out", &o])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let t0 = Instant::now();
    loop {
        let n = std::fs::read_dir(out.join("points"))
            .map(|d| d.count())
            .unwrap_or(0);
        if n >= 1 || t0.elapsed() > Duration::from_secs(120) {
            break;
        }
        std::thread::sleep(Duration::from_millis(5));
    }
    child.kill().unwrap();
    child.wait().unwrap();
    // Every result present is complete (atomic writes); the one the kill
    // interrupted, if any, is still the writer's hidden temporary
    // (`.NAME.tmp-PID-*`), which the next run removes.
    let (before, temporaries): (Vec<_>, Vec<_>) = point_times(&out)
        .into_iter()
        .partition(|(name, _)| !name.starts_with('.'));
    assert!(
        temporaries.iter().all(|(name, _)| name.contains(".tmp-")),
        "{temporaries:?}"
    );
    for (name, _) in &before {
        let text = std::fs::read_to_string(out.join("points").join(name)).unwrap();
        let v: serde_json::Value =
            serde_json::from_str(&text).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!(v.get("friction_coefficient").is_some());
    }
    let (ok, err) = viscoslide(&["sweep", &cfg, "--out", &o]);
    assert!(ok, "{err}");
    let after = point_times(&out);
    assert_eq!(after.len(), 9, "{after:?}");
    assert!(after.iter().all(|(name, _)| !name.starts_with('.')));
    for (name, t) in &before {
        assert_eq!(
            *t,
            after.iter().find(|(n, _)| n == name).unwrap().1,
            "{name} recomputed"
        );
    }
}

#[test]
fn shards_merge_to_the_same_result_in_any_order() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = write_config(tmp.path(), CONFIG);
    let whole = tmp.path().join("whole");
    let (ok, err) = viscoslide(&["sweep", &cfg, "--out", &whole.display().to_string()]);
    assert!(ok, "{err}");
    let sharded = tmp.path().join("sharded");
    let s = sharded.display().to_string();
    for k in [2, 0, 1] {
        let (ok, err) = viscoslide(&["sweep", &cfg, "--out", &s, "--shard", &format!("{k}/3")]);
        assert!(ok, "{err}");
    }
    assert_eq!(point_times(&sharded).len(), 6);
    let (ok, err) = viscoslide(&["merge", &s]);
    assert!(ok, "{err}");
    let a = std::fs::read(whole.join("sweep.csv")).unwrap();
    let b = std::fs::read(sharded.join("sweep.csv")).unwrap();
    assert_eq!(
        a, b,
        "merge must not depend on the order points were made in"
    );
    let (ok, _) = viscoslide(&["merge", &s]);
    assert!(ok);
    assert_eq!(
        b,
        std::fs::read(sharded.join("sweep.csv")).unwrap(),
        "merge is deterministic"
    );
}

#[test]
fn changed_config_in_an_existing_directory_is_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = write_config(tmp.path(), CONFIG);
    let out = tmp.path().join("run").display().to_string();
    let (ok, err) = viscoslide(&["sweep", &cfg, "--out", &out, "--limit", "1"]);
    assert!(ok, "{err}");
    let (ok, err) = viscoslide(&[
        "sweep",
        &cfg,
        "--out",
        &out,
        "--limit",
        "1",
        "--set",
        "loading.normal_load=0.5",
    ]);
    assert!(!ok);
    assert!(err.contains("different configuration"), "{err}");
    assert_eq!(point_times(&tmp.path().join("run")).len(), 1);
}

/// A sweep whose first point fails leaves a pin and no finished point:
/// the corrected sweep takes the directory over (its pin replaced) when it
/// holds it alone; a shard, which cannot tell whether another shard of the
/// pinned sweep is at work, is refused; once a point exists another
/// configuration is refused again.
#[test]
fn a_sweep_that_finished_no_point_does_not_keep_its_directory() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = write_config(tmp.path(), CONFIG);
    let out = tmp.path().join("run");
    let o = out.display().to_string();
    let failing = ["sweep", &cfg, "--out", &o, "--set", "solver.max_matvecs=1"];
    let (ok, err) = viscoslide(&failing);
    assert!(!ok, "{err}");
    assert!(out.join("sweep.toml").is_file());
    assert!(point_times(&out).is_empty());
    let (ok, err) = viscoslide(&["sweep", &cfg, "--out", &o, "--shard", "0/2"]);
    assert!(!ok);
    assert!(err.contains("no finished point yet"), "{err}");
    let (ok, err) = viscoslide(&["sweep", &cfg, "--out", &o, "--limit", "1"]);
    assert!(ok, "{err}");
    assert_eq!(point_times(&out).len(), 1);
    let (ok, err) = viscoslide(&failing);
    assert!(!ok);
    assert!(err.contains("different configuration"), "{err}");
    let (ok, err) = viscoslide(&["sweep", &cfg, "--out", &o, "--shard", "1/2"]);
    assert!(ok, "{err}");
    let (ok, err) = viscoslide(&["sweep", &cfg, "--out", &o]);
    assert!(ok, "{err}");
    assert_eq!(point_times(&out).len(), 6);
    assert!(out.join("sweep.csv").is_file());
}

#[test]
fn compare_plots_measured_minus_coulomb_against_the_sweep() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = write_config(tmp.path(), CONFIG);
    let out = tmp.path().join("run");
    let o = out.display().to_string();
    let (ok, err) = viscoslide(&["sweep", &cfg, "--out", &o]);
    assert!(ok, "{err}");
    let measured = tmp.path().join("measured.csv");
    std::fs::write(
        &measured,
        "# test data\nspeed_m_s,mu,mu_std\n1e-3,0.51,0.01\n1e-2,0.52,0.02\n",
    )
    .unwrap();
    let m = measured.display().to_string();
    let (ok, err) = viscoslide(&["compare", &o, &m, "--coulomb", "0.5"]);
    assert!(ok, "{err}");
    let csv = std::fs::read_to_string(out.join("compare.csv")).unwrap();
    let second: Vec<f64> = csv
        .lines()
        .nth(2)
        .unwrap()
        .split(',')
        .map(|c| c.parse().unwrap())
        .collect();
    assert!(
        (second[1] - 0.02).abs() < 1e-12 && (second[2] - 0.02).abs() < 1e-12,
        "{csv}"
    );
    assert!(out.join("compare.png").is_file());
    // One curve: the computed friction at the measured speeds (here the
    // computed speeds themselves, v = xi L / tau with L = tau = 0.01), and
    // an empty field, with a note, for a measured speed beyond them.
    let merged = std::fs::read_to_string(out.join("sweep.csv")).unwrap();
    let header: Vec<&str> = merged.lines().next().unwrap().split(',').collect();
    let at = |name: &str| header.iter().position(|c| *c == name).unwrap();
    let computed: Vec<(f64, f64)> = merged
        .lines()
        .skip(1)
        .map(|l| {
            let f: Vec<f64> = l
                .split(',')
                .map(|c| c.parse().unwrap_or(f64::NAN))
                .collect();
            (
                f[at("speed_m_s")],
                f[at("friction_mean")],
                f[at("friction_std")],
            )
        })
        .filter(|r| r.0 > 0.0)
        .map(|r| (r.1, r.2))
        .collect();
    assert_eq!(computed.len(), 2, "{merged}");
    std::fs::write(
        &measured,
        "speed_m_s,mu,mu_std\n1e-3,0.51,0.01\n1e-2,0.52,0.02\n0.1,0.53,0.0\n",
    )
    .unwrap();
    let (ok, err) = viscoslide(&["compare", &o, &m, "--coulomb", "0.5"]);
    assert!(ok, "{err}");
    assert!(err.contains("1 of 3 measured speeds lie outside"), "{err}");
    let csv = std::fs::read_to_string(out.join("compare.csv")).unwrap();
    let lines: Vec<&str> = csv.lines().collect();
    assert!(lines[0].ends_with(",mu_computed,mu_computed_std"), "{csv}");
    for (line, (mu, std)) in lines[1..3].iter().zip(&computed) {
        let f: Vec<f64> = line.split(',').map(|c| c.parse().unwrap()).collect();
        assert!(
            (f[3] / mu - 1.0).abs() < 1e-8 && (f[4] - std).abs() <= 1e-8 * std,
            "{line}: {mu} {std}"
        );
    }
    assert!(lines[3].ends_with(",,"), "{csv}");
    // Between two computed speeds: linear in log v.
    std::fs::write(&measured, "speed_m_s,mu\n3.1622776601683795e-3,0.5\n").unwrap();
    let (ok, err) = viscoslide(&["compare", &o, &m, "--coulomb", "0.5"]);
    assert!(ok, "{err}");
    let csv = std::fs::read_to_string(out.join("compare.csv")).unwrap();
    let mid: f64 = csv
        .lines()
        .nth(1)
        .unwrap()
        .split(',')
        .nth(3)
        .unwrap()
        .parse()
        .unwrap();
    let half = 0.5 * (computed[0].0 + computed[1].0);
    assert!((mid / half - 1.0).abs() < 1e-8, "{mid} against {half}");
    // A negative standard deviation is refused.
    std::fs::write(&measured, "speed_m_s,mu,mu_std\n1e-3,0.51,-0.01\n").unwrap();
    let (ok, err) = viscoslide(&["compare", &o, &m, "--coulomb", "0.5"]);
    assert!(!ok && err.contains("negative"), "{err}");
    // A measured file without the speed column: one-line error, nothing new written.
    std::fs::remove_file(out.join("compare.csv")).unwrap();
    std::fs::write(&measured, "v,mu\n1e-3,0.5\n").unwrap();
    let (ok, err) = viscoslide(&["compare", &o, &m, "--coulomb", "0.5"]);
    assert!(!ok && err.contains("speed_m_s"), "{err}");
    assert!(!out.join("compare.csv").exists());
}

/// A sweep refused for bad input creates nothing: neither the pinned
/// configuration nor `points/`, so the corrected sweep runs in the same
/// directory.
#[test]
fn a_refused_sweep_leaves_its_directory_untouched() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("run");
    let o = out.display().to_string();
    // Seeds with a surface read from a file.
    let h: Vec<f64> = (0..64).map(|k| 1e-6 * (k as f64 * 0.7).sin()).collect();
    std::fs::write(
        tmp.path().join("h.npy"),
        viscoslide::io::npy::encode_f64(&[8, 8], &h),
    )
    .unwrap();
    let file_surface = CONFIG.replace(
        "[surface.generate]\nn = 32\nlength = 0.01\nhurst = 0.8\nscales = 4\nrms_slope = 0.02\nseed = 1\n",
        "[surface]\nfile = \"h.npy\"\nlength = 0.01\n",
    );
    assert!(file_surface.contains("h.npy"));
    // A negative modulus.
    let negative = CONFIG.replace(
        "relaxed_modulus = 3.3333333333333335e6",
        "relaxed_modulus = -1",
    );
    for (what, text) in [("seeds", file_surface), ("modulus", negative)] {
        let cfg = write_config(tmp.path(), &text);
        let (ok, err) = viscoslide(&["sweep", &cfg, "--out", &o, "--limit", "1"]);
        assert!(!ok, "{what}");
        assert_eq!(err.trim_end().lines().count(), 1, "{what}: {err}");
        assert!(
            !out.exists(),
            "{what}: a refused sweep made {}",
            out.display()
        );
    }
    let cfg = write_config(tmp.path(), CONFIG);
    let (ok, err) = viscoslide(&["sweep", &cfg, "--out", &o, "--limit", "1"]);
    assert!(ok, "{err}");
    assert_eq!(point_times(&out).len(), 1);
}

/// A merge of a sweep with a shard not run is refused, naming the missing
/// points, and writes nothing; `--partial` merges the finished ones and
/// says which are missing, on its line and in `merge.json`; once all are
/// there `merge.json` says the sweep is complete.
#[test]
fn merging_an_incomplete_sweep_is_refused_unless_partial() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = write_config(tmp.path(), CONFIG);
    let out = tmp.path().join("run");
    let o = out.display().to_string();
    let (ok, err) = viscoslide(&["sweep", &cfg, "--out", &o, "--shard", "0/2"]);
    assert!(ok, "{err}");
    let names = |d: &Path| {
        let mut v: Vec<String> = std::fs::read_dir(d)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    };
    let before = names(&out);
    let (ok, err) = viscoslide(&["merge", &o]);
    assert!(!ok);
    // Seed 2 is shard 1's: points 1, 3 and 5 (3 speeds x 2 seeds).
    assert!(
        err.contains("3 of the sweep's 6 points are missing: p0001 (xi = 0, seed 2), p0003 (xi = 0.001, seed 2), p0005 (xi = 0.01, seed 2)"),
        "{err}"
    );
    assert!(err.contains("merge --partial"), "{err}");
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert_eq!(names(&out), before, "a refused merge writes nothing");

    let merged = Command::new(env!("CARGO_BIN_EXE_viscoslide"))
        .args(["merge", &o, "--partial"])
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&merged.stdout);
    assert!(merged.status.success(), "{stdout}");
    assert!(
        stdout.contains("(partial: 3 of the sweep's 6 points missing: p0001 (xi = 0, seed 2)"),
        "{stdout}"
    );
    let record = |d: &Path| -> serde_json::Value {
        serde_json::from_str(&std::fs::read_to_string(d.join("merge.json")).unwrap()).unwrap()
    };
    let r = record(&out);
    assert_eq!(r["complete"], false, "{r}");
    assert_eq!(r["points_planned"], 6, "{r}");
    assert_eq!(r["points_merged"], 3, "{r}");
    assert_eq!(r["missing"].as_array().unwrap().len(), 3, "{r}");
    assert!(out.join("sweep.csv").exists());

    let (ok, err) = viscoslide(&["sweep", &cfg, "--out", &o, "--shard", "1/2"]);
    assert!(ok, "{err}");
    let (ok, err) = viscoslide(&["merge", &o]);
    assert!(ok, "{err}");
    let r = record(&out);
    assert_eq!(r["complete"], true, "{r}");
    assert_eq!(r["points_merged"], 6, "{r}");
    assert_eq!(r["missing"], serde_json::json!([]), "{r}");
}
