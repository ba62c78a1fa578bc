//! One writer per output directory, and the leftovers of dead writers.
//!
//! A writer holds an exclusive `flock` on the output directory itself (no
//! lock file is left behind); a second writer fails at once with one line.
//! The shards of one study share the lock ([`LockMode::Shared`]). A writer
//! nested in another on the same directory and thread (a study's report
//! inside the study's run) shares the outer one's lock instead of refusing
//! itself. Staging folders and temporary files carry the id of the process
//! that made them (`.staging-PID-*`, `.NAME.staging-PID-*`,
//! `.NAME.tmp-PID-*`); those of processes no longer running (killed, or
//! out of disk) are removed by the next writer of the same place.

use std::cell::RefCell;
use std::fs;
use std::os::unix::fs::MetadataExt;
use std::os::unix::io::AsRawFd;
use std::path::Path;
use std::sync::{Arc, Weak};

/// How a directory is held.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LockMode {
    /// One writer; every other is refused.
    Exclusive,
    /// Writers of disjoint files of one study (its shards): refused only
    /// by, and to, an exclusive writer.
    Shared,
}

/// A lock this thread holds: the directory's device and inode, its mode.
struct Held {
    dev: u64,
    ino: u64,
    mode: LockMode,
    file: Weak<fs::File>,
}

thread_local! {
    static HELD: RefCell<Vec<Held>> = const { RefCell::new(Vec::new()) };
}

/// The lock this thread holds on directory `(dev, ino)` that covers
/// `mode` (an exclusive lock covers both modes), if any.
fn held_here(dev: u64, ino: u64, mode: LockMode) -> Option<Arc<fs::File>> {
    HELD.with(|h| {
        let mut h = h.borrow_mut();
        h.retain(|l| l.file.strong_count() > 0);
        h.iter()
            .filter(|l| l.dev == dev && l.ino == ino)
            .filter(|l| l.mode == LockMode::Exclusive || mode == LockMode::Shared)
            .find_map(|l| l.file.upgrade())
    })
}

/// A lock on a directory, held until dropped (or the process ends: the
/// kernel releases it, so a killed writer never blocks the next).
#[derive(Debug)]
pub struct DirLock {
    _file: Arc<fs::File>,
}

impl DirLock {
    /// Lock `dir` (which exists) for one writer; `None` at once if
    /// another process holds it.
    pub fn acquire(dir: &Path) -> std::io::Result<Option<Self>> {
        Self::acquire_as(dir, LockMode::Exclusive)
    }

    /// Lock `dir` (which exists) in `mode`; `None` at once if another
    /// writer holds it in a mode that excludes this one. A lock this
    /// thread already holds on `dir` is shared. The directory is re-checked
    /// after locking: a writer that swapped in a new directory meanwhile
    /// leaves the lock on the old one, so the new one is locked instead.
    pub fn acquire_as(dir: &Path, mode: LockMode) -> std::io::Result<Option<Self>> {
        for _ in 0..8 {
            let file = fs::File::open(dir)?;
            let held = file.metadata()?;
            if let Some(file) = held_here(held.dev(), held.ino(), mode) {
                return Ok(Some(Self { _file: file }));
            }
            let op = match mode {
                LockMode::Exclusive => libc::LOCK_EX,
                LockMode::Shared => libc::LOCK_SH,
            };
            // SAFETY: flock on a descriptor this function owns.
            let rc = unsafe { libc::flock(file.as_raw_fd(), op | libc::LOCK_NB) };
            if rc != 0 {
                let e = std::io::Error::last_os_error();
                if e.raw_os_error() == Some(libc::EWOULDBLOCK) {
                    return Ok(None);
                }
                return Err(e);
            }
            match fs::metadata(dir) {
                Ok(now) if now.dev() == held.dev() && now.ino() == held.ino() => {
                    let file = Arc::new(file);
                    HELD.with(|h| {
                        h.borrow_mut().push(Held {
                            dev: held.dev(),
                            ino: held.ino(),
                            mode,
                            file: Arc::downgrade(&file),
                        })
                    });
                    return Ok(Some(Self { _file: file }));
                }
                _ => continue,
            }
        }
        Ok(None)
    }
}

/// The process that holds a lock on `dir`, as `/proc/locks` names it
/// (Linux; `None` where it cannot be read or names no other process).
pub fn holder(dir: &Path) -> Option<u32> {
    let meta = fs::metadata(dir).ok()?;
    let (major, minor) = (libc::major(meta.dev()), libc::minor(meta.dev()));
    let text = fs::read_to_string("/proc/locks").ok()?;
    text.lines().find_map(|line| {
        // "1: FLOCK  ADVISORY  WRITE 1234 08:01:5678 0 EOF"; a waiting
        // request ("1: -> FLOCK ...") holds nothing.
        let f: Vec<&str> = line.split_whitespace().collect();
        if f.get(1) != Some(&"FLOCK") {
            return None;
        }
        let pid: u32 = f.get(4)?.parse().ok()?;
        let mut id = f.get(5)?.split(':');
        let maj = u32::from_str_radix(id.next()?, 16).ok()?;
        let min = u32::from_str_radix(id.next()?, 16).ok()?;
        let ino: u64 = id.next()?.parse().ok()?;
        let this = maj == major && min == minor && ino == meta.ino();
        (this && pid != 0 && pid != std::process::id()).then_some(pid)
    })
}

/// Whether process `pid` is running (signal 0 reaches it, or exists but
/// belongs to someone else).
pub fn process_alive(pid: u32) -> bool {
    let Ok(pid) = libc::pid_t::try_from(pid) else {
        return false;
    };
    if pid <= 0 {
        return false;
    }
    // SAFETY: signal 0 only checks that the process exists.
    let rc = unsafe { libc::kill(pid, 0) };
    rc == 0 || std::io::Error::last_os_error().raw_os_error() == Some(libc::EPERM)
}

/// The process id in a leftover name `PREFIX<pid>-<suffix>`, if `name`
/// starts with `prefix`.
pub(crate) fn owner(name: &str, prefix: &str) -> Option<u32> {
    let rest = name.strip_prefix(prefix)?;
    let (pid, suffix) = rest.split_once('-')?;
    if suffix.is_empty() || !suffix.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    pid.parse().ok()
}

/// The writer of a temporary file `.NAME.tmp-<pid>-<suffix>` of any `NAME`.
fn temp_owner(name: &str) -> Option<u32> {
    let at = name.rfind(".tmp-")?;
    if !name.starts_with('.') || at == 0 {
        return None;
    }
    owner(&name[at..], ".tmp-")
}

/// Remove the temporary files (`.NAME.tmp-PID-*`) of dead writers in `dir`.
pub(crate) fn remove_dead_temps(dir: &Path) {
    remove_matching(dir, temp_owner);
}

/// Remove the entries of `dir` whose names start with one of `prefixes`
/// followed by the id of a process no longer running. Errors are ignored:
/// cleaning is a courtesy, never a reason to fail a write.
pub(crate) fn remove_dead(dir: &Path, prefixes: &[String]) {
    remove_matching(dir, |name| prefixes.iter().find_map(|p| owner(name, p)));
}

fn remove_matching(dir: &Path, owner_of: impl Fn(&str) -> Option<u32>) {
    let Ok(entries) = fs::read_dir(dir) else {
        return;
    };
    for e in entries.flatten() {
        let name = e.file_name();
        let Some(name) = name.to_str() else {
            continue;
        };
        let dead =
            owner_of(name).is_some_and(|pid| pid != std::process::id() && !process_alive(pid));
        if dead {
            let p = e.path();
            match e.file_type() {
                Ok(t) if t.is_dir() => {
                    let _ = fs::remove_dir_all(&p);
                }
                _ => {
                    let _ = fs::remove_file(&p);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn owners_are_read_from_names() {
        assert_eq!(owner(".staging-123-456", ".staging-"), Some(123));
        assert_eq!(owner(".a.tmp-9-1", ".a.tmp-"), Some(9));
        assert_eq!(owner(".staging-123-x", ".staging-"), None);
        assert_eq!(owner("summary.json", ".staging-"), None);
        assert_eq!(temp_owner(".heights.npy.tmp-77-1"), Some(77));
        assert_eq!(temp_owner("heights.npy.tmp-77-1"), None);
        assert!(process_alive(std::process::id()));
        assert!(!process_alive(0));
    }

    #[test]
    fn a_second_lock_fails_at_once_and_the_first_releases() {
        let tmp = tempfile::tempdir().unwrap();
        let a = DirLock::acquire(tmp.path()).unwrap().unwrap();
        // Another thread (as another process) is refused ...
        let dir = tmp.path().to_path_buf();
        let other = move || DirLock::acquire(&dir).unwrap().is_some();
        assert!(!std::thread::spawn(other.clone()).join().unwrap());
        // ... a writer nested on this thread shares the lock.
        assert!(DirLock::acquire(tmp.path()).unwrap().is_some());
        drop(a);
        assert!(std::thread::spawn(other).join().unwrap());
    }
}
