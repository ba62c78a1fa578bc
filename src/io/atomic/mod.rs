//! Atomic output: every file of one result set is first written into a
//! hidden staging folder beside the target directory, which also receives
//! (as hard links) the files of the target that this write keeps; `commit`
//! then swaps the two directories with one `renameat2(RENAME_EXCHANGE)`, so
//! a reader (or a crash at any instant) sees the whole old directory or the
//! whole new one, never a mixture. Where the file system cannot exchange,
//! the old directory is renamed aside and the new one into place; a crash
//! between the two renames is repaired by the next writer. A directory
//! holding sub-directories of other writers, or the working directory, is
//! not swapped: its files are staged inside it and renamed one by one, the
//! first-named file last. A study's report ([`StagedOutput::for_study`])
//! is swapped with the study's own sub-directories (`points/`), whose
//! files the staging folder receives as hard links: the report of a study
//! appears whole or not at all like any other output set.
//!
//! One writer per directory ([`DirLock`]): a second fails at once. Staging
//! folders and temporary files of dead processes are removed by the next
//! writer; a failed write (a full disk included) leaves nothing behind,
//! not even the directory if it made it.

use std::fs;
use std::path::{Path, PathBuf};

use super::dirlock::{remove_dead, remove_dead_temps, DirLock};
use super::fault::{crash_point, full_disk};

mod file;

use file::unique_suffix;
pub use file::write_atomic;
pub(crate) use file::write_new;

/// Errors writing output files; each names the path.
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    #[error("{path}: {source}")]
    Io {
        path: String,
        #[source]
        source: std::io::Error,
    },
    #[error("output file {0} was announced but never written")]
    Unwritten(String),
    #[error("{0} is not a file path")]
    NotAFile(String),
    #[error("{}", not_a_directory(.path, .dir))]
    NotADirectory { path: String, dir: String },
    #[error("{dir}: another process is writing output there now{}; wait for it to finish or choose another output directory", holder_text(.holder))]
    Busy { dir: String, holder: Option<u32> },
    #[error("{dir}: cannot write output there ({source})")]
    Unwritable {
        dir: String,
        #[source]
        source: std::io::Error,
    },
}

/// The message of [`OutputError::NotADirectory`]: the output directory
/// itself a file, or a file on its way.
fn not_a_directory(path: &str, dir: &str) -> String {
    if path == dir {
        format!("{dir} is a file, not a directory: choose another output directory")
    } else {
        format!("{path}: not a directory, so the output directory {dir} cannot be made under it")
    }
}

/// `" (pid N)"` for a known lock holder.
fn holder_text(holder: &Option<u32>) -> String {
    holder.map(|p| format!(" (pid {p})")).unwrap_or_default()
}

impl OutputError {
    /// An I/O error with the path that caused it.
    pub fn io(path: impl AsRef<Path>, source: std::io::Error) -> Self {
        OutputError::Io {
            path: path.as_ref().display().to_string(),
            source,
        }
    }
}

type Result<T, E = OutputError> = std::result::Result<T, E>;

/// Check, before long work, that output can be written to `dir`: its
/// nearest existing ancestor must be a directory that accepts a new file.
/// Creates nothing (a probe file is made and removed at once).
pub(crate) fn check_output_dir(dir: &Path) -> Result<()> {
    let existing = existing_ancestor(dir)?;
    let probe = existing.join(format!(
        ".viscoslide-probe-{}-{}",
        std::process::id(),
        unique_suffix()
    ));
    let unwritable = |source| OutputError::Unwritable {
        dir: dir.display().to_string(),
        source,
    };
    fs::File::create_new(&probe).map_err(unwritable)?;
    fs::remove_file(&probe).map_err(unwritable)
}

/// The nearest existing ancestor of `dir` (itself included; `.` where
/// none of its own exists), refused where it is not a directory.
fn existing_ancestor(dir: &Path) -> Result<&Path> {
    let mut p = dir;
    Ok(loop {
        match fs::metadata(p) {
            Ok(m) if m.is_dir() => break p,
            Ok(_) => {
                return Err(OutputError::NotADirectory {
                    path: p.display().to_string(),
                    dir: dir.display().to_string(),
                })
            }
            Err(_) => match p.parent() {
                Some(q) if !q.as_os_str().is_empty() => p = q,
                _ => break Path::new("."),
            },
        }
    })
}

/// How a [`StagedOutput`] reaches its directory.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Mode {
    /// Staging beside the directory, swapped in whole.
    Swap,
    /// Staging inside the directory, files renamed one by one.
    InPlace,
}

/// A set of output files written together, or not at all.
#[derive(Debug)]
pub struct StagedOutput {
    dir: PathBuf,
    staging: PathBuf,
    mode: Mode,
    names: Vec<String>,
    /// Names of the whole output set: those not written this time are
    /// removed from `dir` on commit.
    set: Vec<String>,
    committed: bool,
    /// The directory did not exist before: removed again (when empty) if
    /// the write fails.
    created: bool,
    /// Sub-directories carried into a swapped directory (hard links of
    /// their files) instead of keeping it from being swapped.
    owned: Vec<String>,
    _lock: DirLock,
}

impl StagedOutput {
    /// Prepare to write into `dir` (created if missing). Fails at once if
    /// another process is writing there.
    pub fn new(dir: impl AsRef<Path>) -> Result<Self> {
        Self::open(dir.as_ref(), &[])
    }

    /// [`StagedOutput::new`] for the report of a study in its directory:
    /// the sub-directories `owned` (the study's `points/`) belong to the
    /// study, whose writers all hold the directory's lock (shared by its
    /// shards), so while this output holds it alone nobody writes there.
    /// They are carried into the new directory as hard links of their
    /// files (copies where the file system has no links), so the directory
    /// is still swapped whole: the report's files appear together or not
    /// at all, a crash at any step included.
    pub fn for_study(dir: impl AsRef<Path>, owned: &[&str]) -> Result<Self> {
        Self::open(dir.as_ref(), owned)
    }

    fn open(dir: &Path, owned: &[&str]) -> Result<Self> {
        let owned: Vec<String> = owned.iter().map(|n| n.to_string()).collect();
        let dir = dir.to_path_buf();
        let name = dir_name(&dir);
        let parent = parent_of(&dir);
        if let Some(name) = &name {
            recover_aside(&parent, &dir, name);
        }
        existing_ancestor(&dir)?;
        let created = !dir.exists();
        fs::create_dir_all(&dir).map_err(|e| OutputError::io(&dir, e))?;
        let lock = match DirLock::acquire(&dir) {
            Ok(Some(l)) => l,
            // Busy: the directory is the lock holder's now, even if this
            // process created it (two writers starting at once both see it
            // missing); removing it would pull it from under the writer.
            Ok(None) => {
                return Err(OutputError::Busy {
                    dir: dir.display().to_string(),
                    holder: super::dirlock::holder(&dir),
                })
            }
            Err(e) => {
                if created {
                    let _ = fs::remove_dir(&dir);
                }
                return Err(OutputError::io(&dir, e));
            }
        };
        remove_dead(&dir, &[".staging-".to_string()]);
        remove_dead_temps(&dir);
        let mode = match &name {
            Some(name) if swappable(&dir, &owned) => {
                remove_dead(
                    &parent,
                    &[format!(".{name}.staging-"), format!(".{name}.aside-")],
                );
                Mode::Swap
            }
            _ => Mode::InPlace,
        };
        let suffix = format!("{}-{}", std::process::id(), unique_suffix());
        let staging = match (mode, &name) {
            (Mode::Swap, Some(name)) => parent.join(format!(".{name}.staging-{suffix}")),
            _ => dir.join(format!(".staging-{suffix}")),
        };
        let (staging, mode) = match fs::create_dir(&staging) {
            Ok(()) => (staging, mode),
            // A parent that takes no new entry (read-only, another
            // owner's): stage inside the directory instead.
            Err(_) if mode == Mode::Swap => {
                let inside = dir.join(format!(".staging-{suffix}"));
                fs::create_dir(&inside).map_err(|e| OutputError::io(&inside, e))?;
                (inside, Mode::InPlace)
            }
            Err(e) => return Err(OutputError::io(&staging, e)),
        };
        let out = Self {
            dir,
            staging,
            mode,
            names: Vec::new(),
            set: Vec::new(),
            committed: false,
            created,
            owned,
            _lock: lock,
        };
        Ok(out)
    }

    /// The final directory.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// Path in the staging folder to write the file `name` to; the file is
    /// moved to `dir/name` by [`StagedOutput::commit`].
    pub fn path(&mut self, name: &str) -> PathBuf {
        assert!(
            !name.contains('/') && !name.contains('\\'),
            "staged names are plain file names"
        );
        if !self.names.iter().any(|n| n == name) {
            self.names.push(name.to_string());
        }
        self.staging.join(name)
    }

    /// Write `bytes` as the file `name`.
    pub fn write(&mut self, name: &str, bytes: &[u8]) -> Result<()> {
        let p = self.path(name);
        full_disk()
            .and_then(|()| fs::write(&p, bytes))
            .map_err(|e| OutputError::io(&p, e))
    }

    /// Declare the names of the whole output set this write replaces: any
    /// of them left in the directory by an earlier write of the same kind
    /// and not written this time is removed on commit, so old and new
    /// outputs never mix. Other files are left alone.
    pub fn replaces(&mut self, names: &[&str]) {
        self.set = names.iter().map(|n| n.to_string()).collect();
    }

    /// Put every staged file into the target directory at once (see the
    /// module documentation), then remove the stale members of the output
    /// set (see [`StagedOutput::replaces`]).
    pub fn commit(mut self) -> Result<Vec<PathBuf>> {
        for name in &self.names {
            if !self.staging.join(name).exists() {
                return Err(OutputError::Unwritten(name.clone()));
            }
        }
        full_disk().map_err(|e| OutputError::io(&self.staging, e))?;
        let out: Vec<PathBuf> = self.names.iter().map(|n| self.dir.join(n)).collect();
        match self.mode {
            Mode::Swap => self.commit_swap()?,
            Mode::InPlace => self.commit_in_place()?,
        }
        Ok(out)
    }

    fn commit_swap(&mut self) -> Result<()> {
        // The files this write keeps: hard links (a copy where the file
        // system has none) of everything else in the directory.
        let entries = fs::read_dir(&self.dir).map_err(|e| OutputError::io(&self.dir, e))?;
        for e in entries {
            let e = e.map_err(|e| OutputError::io(&self.dir, e))?;
            let name = e.file_name();
            let keep = name.to_str().is_none_or(|n| {
                !self.names.iter().any(|m| m == n)
                    && !self.set.iter().any(|m| m == n)
                    && !n.starts_with(".staging-")
            });
            if !keep {
                continue;
            }
            let (from, to) = (e.path(), self.staging.join(&name));
            let ty = e.file_type().map_err(|err| OutputError::io(&from, err))?;
            let owned = name
                .to_str()
                .is_some_and(|n| self.owned.iter().any(|m| m == n));
            if ty.is_dir() && !owned {
                // A directory appeared since `new`: do not swap it away.
                return self.commit_in_place();
            }
            link_entry(&from, &to, ty)?;
        }
        crash_point("staged");
        let exchanged = if super::fault::no_exchange() {
            Err(std::io::Error::from_raw_os_error(libc::EINVAL))
        } else {
            exchange(&self.staging, &self.dir)
        };
        match exchanged {
            Ok(()) => {
                // The old directory is now at the staging path.
                self.committed = true;
                crash_point("swapped");
                let _ = fs::remove_dir_all(&self.staging);
                Ok(())
            }
            Err(e) if unsupported(&e) => self.commit_aside(),
            Err(e) => Err(OutputError::io(&self.dir, e)),
        }
    }

    /// Rename-aside-then-rename, for file systems without an exchange: a
    /// crash between the two renames leaves `.NAME.aside-PID-*` and no
    /// directory, which the next writer renames back ([`recover_aside`]).
    fn commit_aside(&mut self) -> Result<()> {
        let name = dir_name(&self.dir).expect("a swapped directory has a name");
        let aside = parent_of(&self.dir).join(format!(
            ".{name}.aside-{}-{}",
            std::process::id(),
            unique_suffix()
        ));
        fs::rename(&self.dir, &aside).map_err(|e| OutputError::io(&self.dir, e))?;
        crash_point("aside");
        if let Err(e) = fs::rename(&self.staging, &self.dir) {
            let _ = fs::rename(&aside, &self.dir);
            return Err(OutputError::io(&self.dir, e));
        }
        self.committed = true;
        let _ = fs::remove_dir_all(&aside);
        Ok(())
    }

    fn commit_in_place(&mut self) -> Result<()> {
        // The first-named file (the one a reader looks for: a report's
        // json) last, so that it never stands without the others of a
        // first write.
        let order = self.names.iter().skip(1).chain(self.names.iter().take(1));
        for (k, name) in order.enumerate() {
            let (from, to) = (self.staging.join(name), self.dir.join(name));
            if k > 0 {
                crash_point("renaming");
            }
            fs::rename(&from, &to).map_err(|e| OutputError::io(&to, e))?;
        }
        self.committed = true;
        let _ = fs::remove_dir_all(&self.staging);
        for name in self.set.iter().filter(|n| !self.names.contains(n)) {
            let stale = self.dir.join(name);
            match fs::remove_file(&stale) {
                Err(e) if e.kind() != std::io::ErrorKind::NotFound => {
                    return Err(OutputError::io(&stale, e))
                }
                _ => {}
            }
        }
        Ok(())
    }
}

impl Drop for StagedOutput {
    fn drop(&mut self) {
        if !self.committed {
            let _ = fs::remove_dir_all(&self.staging);
            if self.created {
                // Only if empty: never remove what someone else put there.
                let _ = fs::remove_dir(&self.dir);
            }
        }
    }
}

/// The last component of `dir` as text, if it has a plain one.
fn dir_name(dir: &Path) -> Option<String> {
    match dir.components().next_back()? {
        std::path::Component::Normal(n) => n.to_str().map(str::to_string),
        _ => None,
    }
}

/// The directory holding `dir` (`.` for a bare name).
fn parent_of(dir: &Path) -> PathBuf {
    dir.parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."))
        .to_path_buf()
}

/// `from` at `to`: a hard link of a file (a copy where links fail), a
/// symbolic link re-made, a directory made and filled alike.
fn link_entry(from: &Path, to: &Path, ty: fs::FileType) -> Result<()> {
    let linked = if ty.is_symlink() {
        fs::read_link(from).and_then(|t| std::os::unix::fs::symlink(t, to))
    } else if ty.is_dir() {
        fs::create_dir(to).map_err(|e| OutputError::io(to, e))?;
        for e in fs::read_dir(from).map_err(|e| OutputError::io(from, e))? {
            let e = e.map_err(|e| OutputError::io(from, e))?;
            let ty = e
                .file_type()
                .map_err(|err| OutputError::io(e.path(), err))?;
            link_entry(&e.path(), &to.join(e.file_name()), ty)?;
        }
        Ok(())
    } else {
        fs::hard_link(from, to).or_else(|_| fs::copy(from, to).map(|_| ()))
    };
    linked.map_err(|err| OutputError::io(to, err))
}

/// Whether `dir` may be swapped whole: it holds no sub-directory but the
/// `owned` ones (the writers of others hold no lock on `dir`), it is not
/// the working directory or one of its ancestors, and it is on the same
/// file system as its parent.
fn swappable(dir: &Path, owned: &[String]) -> bool {
    use std::os::unix::fs::MetadataExt;
    let Ok(entries) = fs::read_dir(dir) else {
        return false;
    };
    for e in entries.flatten() {
        let name = e.file_name();
        let skip = name
            .to_str()
            .is_some_and(|n| n.starts_with(".staging-") || owned.iter().any(|m| m == n));
        if !skip && e.file_type().is_ok_and(|t| t.is_dir()) {
            return false;
        }
    }
    let (Ok(d), Ok(cwd)) = (fs::canonicalize(dir), std::env::current_dir()) else {
        return false;
    };
    if cwd.starts_with(&d) {
        return false;
    }
    match (fs::metadata(&d), fs::metadata(parent_of(&d))) {
        (Ok(a), Ok(b)) => a.dev() == b.dev(),
        _ => false,
    }
}

/// Exchange two directories atomically (`renameat2(RENAME_EXCHANGE)`).
fn exchange(a: &Path, b: &Path) -> std::io::Result<()> {
    use std::ffi::CString;
    use std::os::unix::ffi::OsStrExt;
    let c = |p: &Path| {
        CString::new(p.as_os_str().as_bytes())
            .map_err(|_| std::io::Error::from(std::io::ErrorKind::InvalidInput))
    };
    let (ca, cb) = (c(a)?, c(b)?);
    // SAFETY: two NUL-terminated paths that live across the call.
    let rc = unsafe {
        libc::renameat2(
            libc::AT_FDCWD,
            ca.as_ptr(),
            libc::AT_FDCWD,
            cb.as_ptr(),
            libc::RENAME_EXCHANGE,
        )
    };
    if rc == 0 {
        Ok(())
    } else {
        Err(std::io::Error::last_os_error())
    }
}

/// An exchange the file system or kernel does not offer.
fn unsupported(e: &std::io::Error) -> bool {
    matches!(
        e.raw_os_error(),
        Some(libc::EINVAL) | Some(libc::ENOSYS) | Some(libc::EOPNOTSUPP)
    )
}

/// Repair what a writer of `dir` killed mid-commit left: where `dir` is
/// missing and a dead writer's `.NAME.aside-PID-*` holds the old directory
/// (a crash between the two renames of a commit on a file system without
/// an exchange), it is renamed back. Call before making `dir` or reading
/// it, so that the directory is found again instead of being made anew.
pub(crate) fn recover(dir: &Path) {
    if let Some(name) = dir_name(dir) {
        recover_aside(&parent_of(dir), dir, &name);
    }
}

/// Repair a crash between the two renames of [`StagedOutput::commit_aside`]:
/// the directory is missing and a dead writer's `.NAME.aside-PID-*` holds
/// the old one, which is renamed back.
fn recover_aside(parent: &Path, dir: &Path, name: &str) {
    if dir.exists() {
        return;
    }
    let prefix = format!(".{name}.aside-");
    let Ok(entries) = fs::read_dir(parent) else {
        return;
    };
    for e in entries.flatten() {
        let n = e.file_name();
        let dead = n
            .to_str()
            .and_then(|n| super::dirlock::owner(n, &prefix))
            .is_some_and(|pid| !super::dirlock::process_alive(pid));
        if dead && fs::rename(e.path(), dir).is_ok() {
            return;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_file_in_the_way_is_named_and_kept() {
        let tmp = tempfile::tempdir().unwrap();
        let file = tmp.path().join("taken");
        fs::write(&file, "keep").unwrap();
        let e = StagedOutput::new(&file).unwrap_err().to_string();
        assert_eq!(
            e,
            format!(
                "{} is a file, not a directory: choose another output directory",
                file.display()
            )
        );
        let under = file.join("out");
        let e = StagedOutput::new(&under).unwrap_err().to_string();
        assert!(
            e.starts_with(&format!("{}: not a directory", file.display())),
            "{e}"
        );
        assert_eq!(fs::read_to_string(&file).unwrap(), "keep");
    }

    #[test]
    fn failed_set_leaves_nothing() {
        let tmp = tempfile::tempdir().unwrap();
        let out = tmp.path().join("run");
        {
            let mut s = StagedOutput::new(&out).unwrap();
            s.write("a.txt", b"x").unwrap();
            // dropped without commit
        }
        // The directory was made by the write: it goes with it.
        assert!(!out.exists(), "the failed write's directory must vanish");
        let left: Vec<_> = fs::read_dir(tmp.path()).unwrap().collect();
        assert!(left.is_empty(), "staging must vanish: {left:?}");
    }

    #[test]
    fn commit_moves_all_files() {
        let tmp = tempfile::tempdir().unwrap();
        let mut s = StagedOutput::new(tmp.path()).unwrap();
        s.write("a.txt", b"1").unwrap();
        s.write("b.txt", b"2").unwrap();
        s.commit().unwrap();
        assert_eq!(fs::read(tmp.path().join("a.txt")).unwrap(), b"1");
        assert_eq!(fs::read(tmp.path().join("b.txt")).unwrap(), b"2");
        assert_eq!(fs::read_dir(tmp.path()).unwrap().count(), 2);
    }
}
