//! Studies under faults, one test per study type (sweep, magnification,
//! refinement): a run killed (`kill -9`) at random moments, then its
//! resumed run killed again, a run aborted at each step of its report's
//! commit (`VISCOSLIDE_TEST_FAULT`, as abrupt as `kill -9`), and two runs
//! racing into one directory leave either none of the report's files or
//! all of them, and only complete point files; the run that follows ends
//! with the output of one uninterrupted run, every value read back equal
//! (the timings aside), without solving again a point that was stored.
//!
//! The moments of the kills are drawn from a seed printed with every
//! failure (`VISCOSLIDE_FAULT_SEED=N` repeats a draw).

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Child, Output, Stdio};
use std::time::{Duration, Instant};

use serde_json::Value;

use crate::support::{bin, config, text, STUDY, SWEEP};

/// Kills at random moments per study (each of a run and of its resume).
const KILLS: usize = 3;

/// The steps of an output commit where a fault aborts the process.
const STEPS: [&str; 4] = ["staged", "swapped", "aside", "renaming"];

/// A small deterministic generator (xorshift) of the kill moments.
struct Draws(u64);

impl Draws {
    fn new() -> Self {
        let seed = std::env::var("VISCOSLIDE_FAULT_SEED")
            .ok()
            .and_then(|v| v.parse().ok())
            .unwrap_or_else(|| {
                std::time::SystemTime::now()
                    .duration_since(std::time::UNIX_EPOCH)
                    .map(|d| d.as_nanos() as u64)
                    .unwrap_or(1)
            });
        Self(seed.max(1))
    }

    /// Uniform in `[0, 1)`.
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// A study as the command line runs it: its arguments before `--out`, and
/// whether it stores its points (a sweep, a magnification study) or
/// solves every level again when rerun (a refinement study).
struct Case<'a> {
    args: Vec<&'a str>,
    resumable: bool,
}

impl Case<'_> {
    fn command(&self, out: &Path, fault: Option<&str>) -> std::process::Command {
        let mut c = bin();
        c.args(&self.args).arg("--out").arg(out);
        if let Some(f) = fault {
            c.env("VISCOSLIDE_TEST_FAULT", f);
        }
        c.stdout(Stdio::piped()).stderr(Stdio::piped());
        c
    }

    fn start(&self, out: &Path) -> Child {
        self.command(out, None).spawn().unwrap()
    }

    fn run(&self, out: &Path, fault: Option<&str>) -> Output {
        self.command(out, fault).output().unwrap()
    }
}

/// A JSON value without what differs between two runs of the same study:
/// wall and stage times and the peak memory.
fn timeless(v: &mut Value) {
    match v {
        Value::Object(map) => {
            map.retain(|k, _| {
                !(k.ends_with("time_s") || k == "timings" || k == "peak_memory_bytes")
            });
            map.values_mut().for_each(timeless);
        }
        Value::Array(items) => items.iter_mut().for_each(timeless),
        _ => {}
    }
}

/// A file of a study directory as read back: JSON as values (timings
/// aside), CSV as rows of numbers (time columns aside), PNG and the rest
/// as their bytes.
fn read_back(path: &Path) -> Value {
    let bytes = std::fs::read(path).unwrap();
    let name = path.to_string_lossy();
    if name.ends_with(".json") {
        let mut v: Value = serde_json::from_slice(&bytes)
            .unwrap_or_else(|e| panic!("{name} is not whole JSON: {e}"));
        timeless(&mut v);
        v
    } else if name.ends_with(".csv") {
        let t = String::from_utf8(bytes).unwrap();
        let mut lines = t.lines();
        let header: Vec<&str> = lines.next().unwrap_or_default().split(',').collect();
        let keep: Vec<bool> = header.iter().map(|h| !h.ends_with("time_s")).collect();
        let cell = |c: &str| {
            c.parse::<f64>()
                .map(Value::from)
                .unwrap_or_else(|_| Value::from(c))
        };
        Value::Array(
            std::iter::once(header.iter().map(|h| Value::from(*h)).collect::<Vec<_>>())
                .chain(lines.map(|l| l.split(',').map(cell).collect()))
                .map(|row: Vec<Value>| {
                    Value::Array(
                        row.into_iter()
                            .zip(&keep)
                            .filter(|(_, k)| **k)
                            .map(|(c, _)| c)
                            .collect(),
                    )
                })
                .collect(),
        )
    } else {
        Value::Array(bytes.into_iter().map(Value::from).collect())
    }
}

/// Every visible file of a study directory and of its `points/`, read
/// back.
fn outcome(dir: &Path) -> BTreeMap<String, Value> {
    let mut files = BTreeMap::new();
    for sub in ["", "points"] {
        let Ok(entries) = std::fs::read_dir(dir.join(sub)) else {
            continue;
        };
        for e in entries.map(|e| e.unwrap()) {
            let name = e.file_name().to_string_lossy().into_owned();
            if name.starts_with('.') || e.file_type().unwrap().is_dir() {
                continue;
            }
            let key = if sub.is_empty() {
                name
            } else {
                format!("{sub}/{name}")
            };
            files.insert(key, read_back(&e.path()));
        }
    }
    files
}

/// What a run left in `dir` after being stopped: the report files all or
/// none, every point file whole, no visible file of another kind.
fn assert_whole(dir: &Path, report: &[String], pins: &[String], at: &str) {
    let got = outcome(dir);
    let present: Vec<&String> = report.iter().filter(|f| got.contains_key(*f)).collect();
    assert!(
        present.is_empty() || present.len() == report.len(),
        "{at}: part of the report: {present:?} of {report:?}"
    );
    for (name, v) in &got {
        if name.starts_with("points/") {
            assert!(v.get("friction_coefficient").is_some(), "{at}: {name}: {v}");
        } else {
            assert!(
                report.contains(name) || pins.contains(name),
                "{at}: unexpected {name}"
            );
        }
    }
}

/// Run `case` to its end in `dir` (after a fault) and check it ends with
/// `want`; `stored` points that must not be solved again ("N already
/// done" with N at least that).
fn finish(case: &Case<'_>, dir: &Path, want: &BTreeMap<String, Value>, stored: usize, at: &str) {
    let o = case.run(dir, None);
    assert!(o.status.success(), "{at}: {}", text(&o.stderr));
    if case.resumable {
        let out = text(&o.stdout);
        let done: usize = out
            .split(" already done")
            .next()
            .and_then(|h| h.rsplit(' ').next())
            .and_then(|n| n.parse().ok())
            .unwrap_or_else(|| panic!("{at}: {out}"));
        assert!(done >= stored, "{at}: {stored} points stored, {out}");
    }
    let got = outcome(dir);
    assert_eq!(
        got.keys().collect::<Vec<_>>(),
        want.keys().collect::<Vec<_>>(),
        "{at}"
    );
    for (name, v) in want {
        assert!(
            got[name] == *v,
            "{at}: {name} differs from the uninterrupted run's"
        );
    }
}

/// Point files in `dir/points`.
fn stored(dir: &Path) -> usize {
    std::fs::read_dir(dir.join("points"))
        .map(|d| {
            d.filter(|e| {
                e.as_ref()
                    .is_ok_and(|e| !e.file_name().to_string_lossy().starts_with('.'))
            })
            .count()
        })
        .unwrap_or(0)
}

/// Start `case` into `dir`, kill it after `delay`, and check what it left.
fn kill_after(
    case: &Case<'_>,
    dir: &Path,
    delay: Duration,
    report: &[String],
    pins: &[String],
    at: &str,
) {
    let mut child = case.start(dir);
    std::thread::sleep(delay);
    // SIGKILL: no destructor runs, as with `kill -9`.
    let _ = child.kill();
    let _ = child.wait();
    assert_whole(dir, report, pins, at);
}

/// The whole exercise of one study type in `root`.
fn exercise(root: &Path, case: &Case<'_>) {
    let mut draws = Draws::new();
    let seed = draws.0;
    // The uninterrupted run, and how long it takes.
    let reference = root.join("reference");
    let t0 = Instant::now();
    let o = case.run(&reference, None);
    let took = t0.elapsed();
    assert!(o.status.success(), "{}", text(&o.stderr));
    let want = outcome(&reference);
    let pins: Vec<String> = ["sweep.toml", "sweep.config_dir", "magnification.toml"]
        .iter()
        .map(|p| p.to_string())
        .filter(|p| want.contains_key(p))
        .collect();
    let report: Vec<String> = want
        .keys()
        .filter(|k| !k.starts_with("points/") && !pins.contains(k))
        .cloned()
        .collect();
    assert!(!report.is_empty());

    // kill -9 at random moments of a run and of its resumed run.
    for k in 0..KILLS {
        let dir = root.join(format!("killed-{k}"));
        for stage in ["run", "resumed run"] {
            let delay = took.mul_f64(1.2 * draws.next());
            let at = format!("seed {seed}, kill {k} of the {stage} after {delay:?}");
            kill_after(case, &dir, delay, &report, &pins, &at);
        }
        let at = format!("seed {seed}, kill {k}: the run after");
        finish(case, &dir, &want, stored(&dir), &at);
    }

    // An abort at each step of the report's commit (every point stored).
    for step in STEPS {
        let dir = root.join(format!("fault-{step}"));
        let o = case.run(&dir, Some(step));
        let at = format!("fault at {step}");
        // A step the commit does not take lets the run finish.
        assert!(
            o.status.success() || o.status.code().is_none(),
            "{at}: {}",
            text(&o.stderr)
        );
        if dir.exists() {
            assert_whole(&dir, &report, &pins, &at);
        }
        let points = if case.resumable {
            want.keys().filter(|k| k.starts_with("points/")).count()
        } else {
            0
        };
        finish(case, &dir, &want, points, &at);
    }

    // Two runs racing into one directory: one may be refused, at once
    // and by name; none mixes its files with the other's.
    let dir = root.join("race");
    let (a, b) = (case.start(&dir), case.start(&dir));
    let (a, b) = (a.wait_with_output().unwrap(), b.wait_with_output().unwrap());
    for o in [&a, &b] {
        assert!(
            o.status.success() || text(&o.stderr).contains("another process is writing"),
            "race: {}",
            text(&o.stderr)
        );
    }
    assert!(
        a.status.success() || b.status.success(),
        "race: both refused"
    );
    assert_whole(&dir, &report, &pins, "race");
    finish(case, &dir, &want, stored(&dir), "race: the run after");
}

fn case_dir(name: &str) -> (tempfile::TempDir, PathBuf) {
    let tmp = tempfile::tempdir().unwrap();
    let root = tmp.path().join(name);
    std::fs::create_dir_all(&root).unwrap();
    (tmp, root)
}

#[test]
fn a_sweep_killed_at_any_moment_ends_as_one_run() {
    let (_tmp, root) = case_dir("sweep");
    let cfg = config(&root, SWEEP);
    let case = Case {
        args: vec!["sweep", &cfg, "--backend", "cpu"],
        resumable: true,
    };
    exercise(&root, &case);
}

#[test]
fn a_magnification_study_killed_at_any_moment_ends_as_one_run() {
    let (_tmp, root) = case_dir("magnification");
    let cfg = config(&root, STUDY);
    let case = Case {
        args: vec![
            "magnification",
            &cfg,
            "--scales",
            "2,4,8",
            "--backend",
            "cpu",
        ],
        resumable: true,
    };
    exercise(&root, &case);
}

#[test]
fn a_refinement_study_killed_at_any_moment_ends_as_one_run() {
    let (_tmp, root) = case_dir("refine");
    let cfg = config(&root, STUDY);
    let case = Case {
        args: vec!["refine", &cfg, "--levels", "16,32", "--backend", "cpu"],
        resumable: false,
    };
    exercise(&root, &case);
}
