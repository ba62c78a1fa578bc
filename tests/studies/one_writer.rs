//! One writer per study directory: a second sweep, study or merge started
//! into a directory another run is writing fails at once, naming the
//! directory and the process that holds it, and the first run's output is
//! that of a run alone; the shards of one sweep share the directory; a
//! point file counts as done only for the study it was solved for, and
//! only under the name of the point it holds.
//!
//! `VISCOSLIDE_TEST_FAULT=slow-point` slows every point's write by half a
//! second (a slow file system), so the second writer starts while the
//! first is at work.

use std::path::{Path, PathBuf};
use std::process::{Child, Output};
use std::time::{Duration, Instant};

use crate::support::{config, names, run, s, start_slow, text, STUDY, SWEEP};

/// Wait until `path` exists (the first writer holds its directory).
fn wait_for(path: &Path) {
    let t0 = Instant::now();
    while !path.exists() {
        assert!(
            t0.elapsed() < Duration::from_secs(60),
            "{} never came",
            path.display()
        );
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// The second writer's refusal: at once, one line, naming the directory
/// and (where `/proc/locks` is readable) the first writer's process.
fn assert_refused(second: &Output, took: Duration, dir: &Path, first: &Child) {
    let all = text(&second.stderr);
    assert!(!second.status.success(), "the second writer ran: {all}");
    // The error is one line, the last (a study names its executor first).
    let err = all.trim().lines().last().unwrap_or_default();
    assert_eq!(all.matches("error").count(), 1, "{all}");
    assert!(err.contains("another process is writing"), "{all}");
    assert!(err.contains(&dir.display().to_string()), "{all}");
    if std::fs::read_to_string("/proc/locks").is_ok_and(|t| t.contains("FLOCK")) {
        assert!(err.contains(&format!("(pid {})", first.id())), "{all}");
    }
    assert!(took < Duration::from_secs(10), "refused after {took:?}");
}

#[test]
fn a_second_sweep_and_a_merge_into_a_busy_directory_are_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = config(tmp.path(), SWEEP);
    let (out, alone) = (tmp.path().join("out"), tmp.path().join("alone"));
    let first = start_slow(&["sweep", &cfg, "--out", &s(&out)]);
    wait_for(&out.join("sweep.toml"));
    for args in [
        vec!["sweep", cfg.as_str(), "--out", &s(&out)],
        vec!["sweep", cfg.as_str(), "--out", &s(&out), "--shard", "1/2"],
        vec!["merge", &s(&out)],
    ] {
        let t0 = Instant::now();
        let second = run(&args);
        assert_refused(&second, t0.elapsed(), &out, &first);
    }
    let first = first.wait_with_output().unwrap();
    assert!(first.status.success(), "{}", text(&first.stderr));
    assert!(
        text(&first.stdout).contains("0 already done, 6 solved now"),
        "{}",
        text(&first.stdout)
    );
    let reference = run(&["sweep", &cfg, "--out", &s(&alone)]);
    assert!(reference.status.success(), "{}", text(&reference.stderr));
    assert_eq!(
        std::fs::read_to_string(out.join("sweep.csv")).unwrap(),
        std::fs::read_to_string(alone.join("sweep.csv")).unwrap()
    );
    assert_eq!(names(&out.join("points")), names(&alone.join("points")));
}

/// Two shards of one sweep at once share the directory and merge to the
/// whole run's table.
#[test]
fn shards_of_one_sweep_run_side_by_side() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = config(tmp.path(), SWEEP);
    let (out, alone) = (tmp.path().join("out"), tmp.path().join("alone"));
    let first = start_slow(&["sweep", &cfg, "--out", &s(&out), "--shard", "0/2"]);
    wait_for(&out.join("sweep.toml"));
    let second = run(&["sweep", &cfg, "--out", &s(&out), "--shard", "1/2"]);
    assert!(second.status.success(), "{}", text(&second.stderr));
    let first = first.wait_with_output().unwrap();
    assert!(first.status.success(), "{}", text(&first.stderr));
    assert!(run(&["merge", &s(&out)]).status.success());
    assert!(run(&["sweep", &cfg, "--out", &s(&alone)]).status.success());
    assert_eq!(
        std::fs::read_to_string(out.join("sweep.csv")).unwrap(),
        std::fs::read_to_string(alone.join("sweep.csv")).unwrap()
    );
}

#[test]
fn a_second_magnification_study_into_a_busy_directory_is_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = config(tmp.path(), STUDY);
    let (out, alone) = (tmp.path().join("out"), tmp.path().join("alone"));
    let args = |o: &PathBuf| {
        vec![
            "magnification".to_string(),
            cfg.clone(),
            "--scales".into(),
            "2,4,8".into(),
            "--backend".into(),
            "cpu".into(),
            "--out".into(),
            s(o),
        ]
    };
    let a = args(&out);
    let a: Vec<&str> = a.iter().map(String::as_str).collect();
    let first = start_slow(&a);
    wait_for(&out.join("magnification.toml"));
    let t0 = Instant::now();
    let second = run(&a);
    assert_refused(&second, t0.elapsed(), &out, &first);
    let first = first.wait_with_output().unwrap();
    assert!(first.status.success(), "{}", text(&first.stderr));
    assert!(
        text(&first.stdout).contains("0 already done, 3 solved now"),
        "{}",
        text(&first.stdout)
    );
    let b = args(&alone);
    let b: Vec<&str> = b.iter().map(String::as_str).collect();
    assert!(run(&b).status.success());
    // The table but its wall times (the last column).
    let table = |d: &Path| -> Vec<String> {
        std::fs::read_to_string(d.join("magnification.csv"))
            .unwrap()
            .lines()
            .map(|l| l.rsplit_once(',').unwrap().0.to_string())
            .collect()
    };
    assert_eq!(table(&out), table(&alone));
}

/// A point file of another study (another configuration's, copied or left
/// by an earlier version) is solved again, and left out of the merge.
#[test]
fn a_point_of_another_study_is_not_counted_as_done() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = config(tmp.path(), SWEEP);
    let out = tmp.path().join("out");
    let first = run(&["sweep", &cfg, "--out", &s(&out)]);
    assert!(first.status.success(), "{}", text(&first.stderr));
    let csv = std::fs::read_to_string(out.join("sweep.csv")).unwrap();
    let p = out.join("points").join("p0001.json");
    let mut v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&p).unwrap()).unwrap();
    assert!(v["study"].is_string(), "{v}");
    v["study"] = "another".into();
    v["friction_coefficient"] = 1.0.into();
    std::fs::write(&p, v.to_string()).unwrap();
    // The point left out is missing: a merge of the others is partial.
    let refused = run(&["merge", &s(&out)]);
    assert!(!refused.status.success());
    assert!(
        text(&refused.stderr).contains("1 of the sweep's 6 points are missing: p0001"),
        "{}",
        text(&refused.stderr)
    );
    let merged = run(&["merge", &s(&out), "--partial"]);
    assert!(merged.status.success(), "{}", text(&merged.stderr));
    assert!(
        text(&merged.stderr).contains("another study"),
        "{}",
        text(&merged.stderr)
    );
    assert_ne!(std::fs::read_to_string(out.join("sweep.csv")).unwrap(), csv);
    let again = run(&["sweep", &cfg, "--out", &s(&out)]);
    assert!(again.status.success(), "{}", text(&again.stderr));
    assert!(
        text(&again.stdout).contains("5 already done, 1 solved now"),
        "{}",
        text(&again.stdout)
    );
    assert_eq!(std::fs::read_to_string(out.join("sweep.csv")).unwrap(), csv);
}

/// A point file copied onto another point's name is no result of that
/// point: a merge leaves it out and names it (never counting the point it
/// holds twice), and a rerun solves the named point again, replacing it.
#[test]
fn a_point_file_under_another_points_name_is_solved_again() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = config(tmp.path(), SWEEP);
    let out = tmp.path().join("out");
    let first = run(&["sweep", &cfg, "--out", &s(&out)]);
    assert!(first.status.success(), "{}", text(&first.stderr));
    let csv = std::fs::read_to_string(out.join("sweep.csv")).unwrap();
    // p0004 and p0005 are xi = 0.01 with seeds 1 and 2.
    let points = out.join("points");
    std::fs::copy(points.join("p0004.json"), points.join("p0005.json")).unwrap();
    let refused = run(&["merge", &s(&out)]);
    assert!(!refused.status.success());
    let err = text(&refused.stderr);
    assert!(
        err.contains("1 of the sweep's 6 points are missing: p0005"),
        "{err}"
    );
    assert!(err.contains("p0005.json holds p0004"), "{err}");
    let merged = run(&["merge", &s(&out), "--partial"]);
    assert!(merged.status.success(), "{}", text(&merged.stderr));
    let partial = std::fs::read_to_string(out.join("sweep.csv")).unwrap();
    let last: Vec<&str> = partial.lines().last().unwrap().split(',').collect();
    assert_eq!(last[3], "1", "one realisation of xi = 0.01: {partial}");
    let record: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("merge.json")).unwrap()).unwrap();
    assert_eq!(record["points_merged"], 5, "{record}");
    let again = run(&["sweep", &cfg, "--out", &s(&out)]);
    assert!(again.status.success(), "{}", text(&again.stderr));
    assert!(
        text(&again.stdout).contains("5 already done, 1 solved now"),
        "{}",
        text(&again.stdout)
    );
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(points.join("p0005.json")).unwrap()).unwrap();
    assert_eq!(v["point"]["id"], "p0005", "{v}");
    assert_eq!(std::fs::read_to_string(out.join("sweep.csv")).unwrap(), csv);
}

/// A refinement study into a directory another writer holds is refused
/// before its first level, naming the holder; once the directory is free
/// it runs there.
#[test]
fn a_refinement_study_into_a_busy_directory_is_refused_before_solving() {
    use viscoslide::io::{LockMode, StudyLock};
    let tmp = tempfile::tempdir().unwrap();
    let cfg = config(tmp.path(), STUDY);
    let out = tmp.path().join("out");
    let args = [
        "refine",
        cfg.as_str(),
        "--levels",
        "16,32",
        "--backend",
        "cpu",
        "--out",
        &s(&out),
    ];
    // This test's own process holds the directory, as a second process
    // would (a lock is not shared across processes).
    let held = StudyLock::acquire(&out, LockMode::Exclusive).unwrap();
    let t0 = Instant::now();
    let second = run(&args);
    let all = text(&second.stderr);
    assert!(!second.status.success(), "{all}");
    assert!(!all.contains("level 1/"), "solved before refusing: {all}");
    let err = all.trim().lines().last().unwrap_or_default();
    assert!(err.contains("another process is writing"), "{all}");
    if std::fs::read_to_string("/proc/locks").is_ok_and(|t| t.contains("FLOCK")) {
        assert!(
            err.contains(&format!("(pid {})", std::process::id())),
            "{all}"
        );
    }
    assert!(t0.elapsed() < Duration::from_secs(10));
    drop(held);
    let again = run(&args);
    assert!(again.status.success(), "{}", text(&again.stderr));
    assert!(out.join("refine.json").is_file());
}
