//! One file written whole: atomically replaced ([`write_atomic`]: a
//! temporary file renamed over the target) or made once ([`write_new`]: a
//! temporary file hard-linked to a name that does not exist yet). Temporary
//! files of dead writers are removed first; a failed write (a full disk)
//! leaves none.

use std::fs;
use std::path::Path;

use super::super::dirlock::remove_dead_temps;
use super::super::fault::full_disk;
use super::{OutputError, Result};

/// Write one file atomically: a temporary file in the same directory, then a
/// rename over the target. Temporary files of dead writers of the same
/// target are removed first; a failed write (a full disk) leaves none.
pub fn write_atomic(path: impl AsRef<Path>, bytes: &[u8]) -> Result<()> {
    let path = path.as_ref();
    let dir = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let existed = dir.exists();
    fs::create_dir_all(dir).map_err(|e| OutputError::io(dir, e))?;
    let file_name = path
        .file_name()
        .ok_or_else(|| OutputError::NotAFile(path.display().to_string()))?;
    let prefix = format!(".{}.tmp-", file_name.to_string_lossy());
    remove_dead_temps(dir);
    let tmp = dir.join(format!(
        "{prefix}{}-{}",
        std::process::id(),
        unique_suffix()
    ));
    let written = full_disk()
        .and_then(|()| fs::write(&tmp, bytes))
        .and_then(|()| fs::rename(&tmp, path));
    written.map_err(|e| {
        let _ = fs::remove_file(&tmp);
        if !existed {
            let _ = fs::remove_dir(dir);
        }
        OutputError::io(path, e)
    })
}

/// Write `path` once: `bytes` appear there whole unless the file exists
/// already, in which case it is left alone and `false` returned (two
/// writers racing to make it: exactly one wins, the other reads its file).
pub(crate) fn write_new(path: impl AsRef<Path>, bytes: &[u8]) -> Result<bool> {
    let path = path.as_ref();
    let dir = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let file_name = path
        .file_name()
        .ok_or_else(|| OutputError::NotAFile(path.display().to_string()))?;
    remove_dead_temps(dir);
    let tmp = dir.join(format!(
        ".{}.tmp-{}-{}",
        file_name.to_string_lossy(),
        std::process::id(),
        unique_suffix()
    ));
    let written = full_disk()
        .and_then(|()| fs::write(&tmp, bytes))
        .and_then(|()| fs::hard_link(&tmp, path));
    let _ = fs::remove_file(&tmp);
    match written {
        Ok(()) => Ok(true),
        Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => Ok(false),
        Err(e) => Err(OutputError::io(path, e)),
    }
}

/// A suffix that two temporary files of one process never share.
pub(super) fn unique_suffix() -> u64 {
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
    fn write_new_writes_once() {
        let tmp = tempfile::tempdir().unwrap();
        let p = tmp.path().join("pin.toml");
        assert!(write_new(&p, b"first").unwrap());
        assert!(!write_new(&p, b"second").unwrap());
        assert_eq!(fs::read(&p).unwrap(), b"first");
        assert_eq!(fs::read_dir(tmp.path()).unwrap().count(), 1);
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
