//! Outputs keep "all files appear together or not at all" under faults: a
//! process killed at each step of the commit (injected with
//! `VISCOSLIDE_TEST_FAULT`, an abort as abrupt as `kill -9`), two writers
//! racing for one directory, and a full disk. The writer here is
//! `surface generate`, whose four files (heights, PSD table and chart,
//! summary) are one output set.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use viscoslide::io::dirlock::{process_alive, DirLock};

/// `surface generate` of seed `seed` into `out`, with an optional fault.
fn generate(out: &Path, seed: u64, fault: Option<&str>) -> Output {
    let mut c = Command::new(env!("CARGO_BIN_EXE_viscoslide"));
    c.args(["surface", "generate", "--n", "32", "--length", "0.01"])
        .args(["--hurst", "0.8", "--scales", "8", "--rms-height", "1e-5"])
        .args(["--seed", &seed.to_string(), "--out"])
        .arg(out);
    c.env_remove("VISCOSLIDE_TEST_FAULT");
    if let Some(f) = fault {
        c.env("VISCOSLIDE_TEST_FAULT", f);
    }
    c.output().unwrap()
}

/// Every entry of `dir` (hidden ones included) and its bytes.
fn snapshot(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| {
            let e = e.unwrap();
            let bytes = std::fs::read(e.path()).unwrap_or_default();
            (e.file_name().to_string_lossy().into_owned(), bytes)
        })
        .collect()
}

/// Names in `dir` (hidden ones included).
fn names(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

/// The result of seed `seed` written alone into a fresh directory.
fn reference(root: &Path, seed: u64) -> BTreeMap<String, Vec<u8>> {
    let dir = root.join(format!("ref{seed}"));
    let o = generate(&dir, seed, None);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let mut s = snapshot(&dir);
    // The summary records the output path and time; compare the maps.
    s.remove("surface.json");
    s
}

fn maps(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    let mut s = snapshot(dir);
    assert!(s.remove("surface.json").is_some(), "{:?}", names(dir));
    s
}

fn aborted(o: &Output) -> bool {
    use std::os::unix::process::ExitStatusExt;
    o.status.signal() == Some(libc_sigabrt())
}

fn libc_sigabrt() -> i32 {
    6
}

#[test]
fn a_crash_at_any_step_of_the_commit_leaves_old_or_new_whole() {
    let tmp = tempfile::tempdir().unwrap();
    let (old, new) = (reference(tmp.path(), 1), reference(tmp.path(), 2));
    assert_ne!(old, new);
    // (step, which result the directory must then hold whole)
    for (step, expect_new) in [("staged", false), ("swapped", true), ("aside", false)] {
        let out = tmp.path().join(format!("run-{step}"));
        assert!(generate(&out, 1, None).status.success());
        let o = generate(&out, 2, Some(step));
        assert!(aborted(&o), "{step}: {:?}", o.status);
        if step == "aside" {
            // Killed between the two renames: the old directory is aside.
            assert!(!out.exists(), "aside: the directory is renamed away");
        } else {
            let got = maps(&out);
            assert_eq!(&got, if expect_new { &new } else { &old }, "{step}");
        }
        // The next run (killed before its swap) repairs and cleans up: the
        // old directory is back whole and no leftover of the dead writer
        // remains beside it or in it.
        let o = generate(&out, 3, Some("staged"));
        assert!(aborted(&o), "{step}: {:?}", o.status);
        let got = maps(&out);
        assert_eq!(&got, if expect_new { &new } else { &old }, "{step}");
        // A clean run finishes and leaves only its own files.
        let o = generate(&out, 2, None);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        assert_eq!(maps(&out), new, "{step}");
        let beside: Vec<String> = names(tmp.path())
            .into_iter()
            .filter(|n| n.contains(&format!("run-{step}.")))
            .collect();
        assert!(beside.is_empty(), "{step}: leftovers {beside:?}");
        assert!(
            names(&out).iter().all(|n| !n.starts_with('.')),
            "{step}: {:?}",
            names(&out)
        );
    }
}

#[test]
fn files_of_other_writers_are_kept_and_stale_set_members_removed() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("run");
    assert!(generate(&out, 1, None).status.success());
    std::fs::write(out.join("notes.txt"), b"mine").unwrap();
    assert!(generate(&out, 2, None).status.success());
    assert_eq!(std::fs::read(out.join("notes.txt")).unwrap(), b"mine");
    assert_eq!(maps(&out).len(), 4, "{:?}", names(&out));
}

#[test]
fn a_second_writer_fails_at_once_with_one_line() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("run");
    assert!(generate(&out, 1, None).status.success());
    let before = snapshot(&out);
    let lock = DirLock::acquire(&out).unwrap().expect("free");
    let o = generate(&out, 2, None);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(err.contains("another process is writing"), "{err}");
    assert_eq!(snapshot(&out), before);
    drop(lock);
    assert!(generate(&out, 2, None).status.success());
}

#[test]
fn racing_writers_never_mix_their_files() {
    let tmp = tempfile::tempdir().unwrap();
    let refs: Vec<_> = (10..12).map(|s| reference(tmp.path(), s)).collect();
    let out = tmp.path().join("race");
    for round in 0..6 {
        let spawn = |seed: u64| {
            Command::new(env!("CARGO_BIN_EXE_viscoslide"))
                .args(["surface", "generate", "--n", "32", "--length", "0.01"])
                .args(["--hurst", "0.8", "--scales", "8", "--rms-height", "1e-5"])
                .args(["--seed", &seed.to_string(), "--out"])
                .arg(&out)
                .env_remove("VISCOSLIDE_TEST_FAULT")
                .stderr(std::process::Stdio::piped())
                .spawn()
                .unwrap()
        };
        let (a, b) = (spawn(10), spawn(11));
        let (a, b) = (a.wait_with_output().unwrap(), b.wait_with_output().unwrap());
        for o in [&a, &b] {
            let err = String::from_utf8_lossy(&o.stderr);
            assert!(
                o.status.success() || err.contains("another process is writing"),
                "round {round}: {err}"
            );
        }
        assert!(a.status.success() || b.status.success());
        let got = maps(&out);
        assert!(
            refs.contains(&got),
            "round {round}: a mixture {:?}",
            names(&out)
        );
        let json: serde_json::Value =
            serde_json::from_slice(&std::fs::read(out.join("surface.json")).unwrap()).unwrap();
        let seed = json.to_string();
        let which = refs.iter().position(|r| *r == got).unwrap();
        assert!(
            seed.contains(&format!("\"seed\":{}", 10 + which)),
            "round {round}: summary of the other writer"
        );
        assert!(names(&out).iter().all(|n| !n.starts_with('.')));
    }
}

#[test]
fn a_full_disk_leaves_nothing_behind() {
    let tmp = tempfile::tempdir().unwrap();
    // A new directory: not even the directory remains.
    let out = tmp.path().join("new");
    let o = generate(&out, 1, Some("enospc"));
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(err.contains("No space left on device"), "{err}");
    assert!(names(tmp.path()).is_empty(), "{:?}", names(tmp.path()));
    // An existing directory: unchanged, no staging folder beside or in it.
    assert!(generate(&out, 1, None).status.success());
    let before = snapshot(&out);
    let o = generate(&out, 2, Some("enospc"));
    assert_eq!(o.status.code(), Some(1));
    assert_eq!(snapshot(&out), before);
    assert_eq!(names(tmp.path()), ["new"]);
    // A single file written atomically (convert): no temporary file.
    let conv = tmp.path().join("conv");
    std::fs::create_dir(&conv).unwrap();
    let mut c = Command::new(env!("CARGO_BIN_EXE_viscoslide"));
    c.args(["surface", "convert"])
        .arg(out.join("heights.npy"))
        .arg(conv.join("h.x3p"))
        .args(["--length", "0.01"])
        .env("VISCOSLIDE_TEST_FAULT", "enospc");
    let o = c.output().unwrap();
    assert_eq!(o.status.code(), Some(1));
    assert!(names(&conv).is_empty(), "{:?}", names(&conv));
}

/// A process id that is not running.
fn dead_pid() -> u32 {
    (4_000_000..).find(|&p| !process_alive(p)).unwrap()
}

#[test]
fn leftovers_of_dead_writers_are_removed_by_the_next_run() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("run");
    assert!(generate(&out, 1, None).status.success());
    let pid = dead_pid();
    let beside: PathBuf = tmp.path().join(format!(".run.staging-{pid}-17"));
    let inside = out.join(format!(".staging-{pid}-18"));
    let temp = out.join(format!(".heights.npy.tmp-{pid}-19"));
    std::fs::create_dir(&beside).unwrap();
    std::fs::write(beside.join("heights.npy"), b"half").unwrap();
    std::fs::create_dir(&inside).unwrap();
    std::fs::write(&temp, b"half").unwrap();
    // A live writer's staging folder is left alone.
    let live = tmp
        .path()
        .join(format!(".run.staging-{}-20", std::process::id()));
    std::fs::create_dir(&live).unwrap();
    assert!(generate(&out, 2, None).status.success());
    assert!(!beside.exists() && !inside.exists());
    assert!(live.exists());
    // write_atomic cleans the temporary files of dead writers beside it.
    let conv = tmp.path().join("c.npy");
    let stale = tmp.path().join(format!(".c.npy.tmp-{pid}-21"));
    std::fs::write(&stale, b"half").unwrap();
    let o = Command::new(env!("CARGO_BIN_EXE_viscoslide"))
        .args(["surface", "convert"])
        .arg(out.join("heights.npy"))
        .arg(&conv)
        .args(["--length", "0.01"])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(!stale.exists() && conv.exists());
    assert!(!temp.exists());
}
