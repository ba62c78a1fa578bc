//! One writer per study directory: a sweep, a magnification study, a
//! refinement study or a merge holds the directory's lock ([`DirLock`],
//! the one `solve` takes) from its first write to its last, so a second
//! writer fails at once, naming the directory and the process that holds
//! it. The shards of one study (`--shard K/N`, each writing its own point
//! files) share the lock; a whole run, a merge and a report take it alone,
//! so the report's commit may swap the directory with its `points/`
//! ([`super::StagedOutput::for_study`]).

use std::fs;
use std::path::{Path, PathBuf};

use super::atomic::{check_output_dir, recover, OutputError};
use super::dirlock::{holder, DirLock, LockMode};

/// A study directory held by this process until dropped.
#[derive(Debug)]
pub struct StudyLock {
    dir: PathBuf,
    /// The directory was made here: removed again on drop while empty,
    /// so that a run that ends before its first file leaves nothing.
    created: bool,
    _lock: DirLock,
}

impl StudyLock {
    /// Make `dir` if missing (call this after every check of the study:
    /// it is the study's first write) and lock it in `mode`; fails at once
    /// if another writer holds it.
    pub fn acquire(dir: &Path, mode: LockMode) -> Result<Self, OutputError> {
        // A study directory a report's commit left renamed aside (a writer
        // killed between its two renames) is the study: put it back
        // rather than start an empty one.
        recover(dir);
        check_output_dir(dir)?;
        let created = !dir.exists();
        fs::create_dir_all(dir).map_err(|e| OutputError::io(dir, e))?;
        match DirLock::acquire_as(dir, mode) {
            Ok(Some(lock)) => Ok(Self {
                dir: dir.to_path_buf(),
                created,
                _lock: lock,
            }),
            // The directory is the holder's now, even if this process made
            // it (two writers starting at once both see it missing).
            Ok(None) => Err(OutputError::Busy {
                dir: dir.display().to_string(),
                holder: holder(dir),
            }),
            Err(e) => {
                if created {
                    let _ = fs::remove_dir(dir);
                }
                Err(OutputError::io(dir, e))
            }
        }
    }

    /// The directory held.
    pub fn dir(&self) -> &Path {
        &self.dir
    }
}

impl Drop for StudyLock {
    fn drop(&mut self) {
        if self.created {
            // Only if empty: never what a writer put there.
            let _ = fs::remove_dir(&self.dir);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exclusive_refuses_all_shared_refuses_exclusive_only() {
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path().join("study");
        let a = StudyLock::acquire(&dir, LockMode::Shared).unwrap();
        // Another thread: the lock is not this thread's to share.
        let d = dir.clone();
        std::thread::spawn(move || {
            let b = StudyLock::acquire(&d, LockMode::Shared).unwrap();
            let e = StudyLock::acquire(&d, LockMode::Exclusive).unwrap_err();
            assert!(matches!(e, OutputError::Busy { .. }), "{e}");
            drop(b);
        })
        .join()
        .unwrap();
        drop(a);
        let a = StudyLock::acquire(&dir, LockMode::Exclusive).unwrap();
        // A writer nested in this one, on this thread, shares its lock.
        let nested = StudyLock::acquire(&dir, LockMode::Exclusive).unwrap();
        drop(nested);
        let d = dir.clone();
        std::thread::spawn(move || {
            let e = StudyLock::acquire(&d, LockMode::Shared).unwrap_err();
            assert!(e.to_string().contains("another process is writing"), "{e}");
            assert_eq!(e.to_string().lines().count(), 1);
        })
        .join()
        .unwrap();
        drop(a);
        // Made here and left empty: gone with the lock.
        assert!(!dir.exists());
    }
}
