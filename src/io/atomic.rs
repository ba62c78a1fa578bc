//! Atomic output: every file of one result set is first written into a
//! hidden staging folder inside the target directory and moved into place only
//! when all of them are complete. A failure before `commit` leaves the target
//! directory as it was (the staging folder is removed on drop).

use std::fs;
use std::path::{Path, PathBuf};

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
    #[error("{path}: not a directory, so the output directory {dir} cannot be made under it")]
    NotADirectory { path: String, dir: String },
    #[error("{dir}: cannot write output there ({source})")]
    Unwritable {
        dir: String,
        #[source]
        source: std::io::Error,
    },
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
pub fn check_output_dir(dir: &Path) -> Result<()> {
    let mut p = dir;
    let existing = loop {
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
    };
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

/// A set of output files written together, or not at all.
#[derive(Debug)]
pub struct StagedOutput {
    dir: PathBuf,
    staging: PathBuf,
    names: Vec<String>,
    /// Names of the whole output set: those not written this time are
    /// removed from `dir` on commit.
    set: Vec<String>,
    committed: bool,
}

impl StagedOutput {
    /// Prepare to write into `dir` (created if missing).
    pub fn new(dir: impl AsRef<Path>) -> Result<Self> {
        let dir = dir.as_ref().to_path_buf();
        fs::create_dir_all(&dir).map_err(|e| OutputError::io(&dir, e))?;
        let staging = dir.join(format!(
            ".staging-{}-{}",
            std::process::id(),
            unique_suffix()
        ));
        fs::create_dir_all(&staging).map_err(|e| OutputError::io(&staging, e))?;
        Ok(Self {
            dir,
            staging,
            names: Vec::new(),
            set: Vec::new(),
            committed: false,
        })
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
        fs::write(&p, bytes).map_err(|e| OutputError::io(&p, e))
    }

    /// Declare the names of the whole output set this write replaces: any
    /// of them left in the directory by an earlier write of the same kind
    /// and not written this time is removed on commit, so old and new
    /// outputs never mix. Other files are left alone.
    pub fn replaces(&mut self, names: &[&str]) {
        self.set = names.iter().map(|n| n.to_string()).collect();
    }

    /// Move every staged file into the target directory, then remove the
    /// stale members of the output set (see [`StagedOutput::replaces`]).
    pub fn commit(mut self) -> Result<Vec<PathBuf>> {
        let mut out = Vec::with_capacity(self.names.len());
        for name in &self.names {
            let from = self.staging.join(name);
            if !from.exists() {
                return Err(OutputError::Unwritten(name.clone()));
            }
        }
        for name in &self.names {
            let from = self.staging.join(name);
            let to = self.dir.join(name);
            fs::rename(&from, &to).map_err(|e| OutputError::io(&to, e))?;
            out.push(to);
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
        Ok(out)
    }
}

impl Drop for StagedOutput {
    fn drop(&mut self) {
        if !self.committed {
            let _ = fs::remove_dir_all(&self.staging);
        }
    }
}

/// Write one file atomically: a temporary file in the same directory, then a
/// rename over the target.
pub fn write_atomic(path: impl AsRef<Path>, bytes: &[u8]) -> Result<()> {
    let path = path.as_ref();
    let dir = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    fs::create_dir_all(dir).map_err(|e| OutputError::io(dir, e))?;
    let file_name = path
        .file_name()
        .ok_or_else(|| OutputError::NotAFile(path.display().to_string()))?;
    let tmp = dir.join(format!(
        ".{}.tmp-{}-{}",
        file_name.to_string_lossy(),
        std::process::id(),
        unique_suffix()
    ));
    fs::write(&tmp, bytes).map_err(|e| OutputError::io(&tmp, e))?;
    fs::rename(&tmp, path).map_err(|e| {
        let _ = fs::remove_file(&tmp);
        OutputError::io(path, e)
    })
}

fn unique_suffix() -> u64 {
    use std::sync::atomic::{AtomicU64, Ordering};
    static COUNTER: AtomicU64 = AtomicU64::new(0);
    let t = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map(|d| d.subsec_nanos() as u64)
        .unwrap_or(0);
    t ^ (COUNTER.fetch_add(1, Ordering::Relaxed) << 32)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn failed_set_leaves_nothing() {
        let tmp = tempfile::tempdir().unwrap();
        let out = tmp.path().join("run");
        {
            let mut s = StagedOutput::new(&out).unwrap();
            s.write("a.txt", b"x").unwrap();
            // dropped without commit
        }
        let left: Vec<_> = fs::read_dir(&out).unwrap().collect();
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

    #[test]
    fn write_atomic_replaces() {
        let tmp = tempfile::tempdir().unwrap();
        let p = tmp.path().join("f.json");
        write_atomic(&p, b"old").unwrap();
        write_atomic(&p, b"new").unwrap();
        assert_eq!(fs::read(&p).unwrap(), b"new");
        assert_eq!(fs::read_dir(tmp.path()).unwrap().count(), 1);
    }
}
