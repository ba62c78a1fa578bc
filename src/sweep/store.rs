//! The point store of a resumable study: `DIR/points/<id>.json`, one file
//! per finished point, each written atomically, beside a pinned description
//! of the study (`DIR/<pin file>`) that a rerun must match. Shared by
//! [`super::run_sweep`] and the magnification study, so that resuming and
//! sharding work the same way for every study made of independent points.
//!
//! The pin is written once (the first writer's stays; a writer that finds
//! another one is refused, unless it holds the directory alone and the
//! pinned study has no finished point: a run that failed or was stopped
//! before its first point does not keep the directory from a corrected
//! one), and every point file records the study it
//! belongs to (`"study"`, a hash of the pin): a point counts as done only
//! for the study it was solved for, and only in its own file (the point it
//! records, `"point"`, is the one its file name says: a file copied or
//! renamed onto another point's name is no result of that point).

use std::path::{Path, PathBuf};

use serde_json::Value;

use crate::error::{Error, Result};
use crate::io::atomic::{write_atomic, write_new};
use crate::io::LockMode;

/// Key of a point file naming its study.
pub const STUDY_KEY: &str = "study";

/// Key of a point file recording the point it holds (its `index` in the
/// plan, and its `id` where the study records one).
pub const POINT_KEY: &str = "point";

/// The file stem of the point at plan position `index`: `p0000`, `p0001`,
/// ... (more digits past 9999).
pub fn point_id(index: usize) -> String {
    format!("p{index:04}")
}

/// The plan position of the point whose file stem is `id`; `None` for a
/// name [`point_id`] does not make.
pub fn point_index(id: &str) -> Option<usize> {
    let index = id.strip_prefix('p')?.parse().ok()?;
    (point_id(index) == id).then_some(index)
}

/// Whether the `points/` folder `points` holds a point file (of any study:
/// only a folder without one leaves nothing to mix); a missing folder holds
/// none.
fn has_point_files(points: &Path) -> Result<bool> {
    let entries = match std::fs::read_dir(points) {
        Ok(entries) => entries,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(false),
        Err(e) => return Err(Error::io(points, e)),
    };
    for entry in entries {
        let path = entry.map_err(|e| Error::io(points, e))?.path();
        if path.extension().is_some_and(|x| x == "json") {
            return Ok(true);
        }
    }
    Ok(false)
}

/// Whether the point file `value`, found under the name `id`, records
/// that point: its `point.index` is the one `id` names, and so is its
/// `point.id` where it records one. `Err` says which point it records
/// instead (for a message).
pub fn records(value: &Value, id: &str) -> std::result::Result<(), String> {
    let point = value.get(POINT_KEY);
    let index = point
        .and_then(|p| p.get("index"))
        .and_then(Value::as_u64)
        .and_then(|i| usize::try_from(i).ok());
    let recorded = point.and_then(|p| p.get("id")).and_then(Value::as_str);
    match (index, recorded) {
        (None, _) => Err("no point".into()),
        (Some(i), Some(r)) if r != point_id(i) => Err(format!("{r} at index {i}")),
        (_, Some(r)) if r != id => Err(r.to_string()),
        (Some(i), _) if Some(i) != point_index(id) => Err(point_id(i)),
        _ => Ok(()),
    }
}

/// The `points/` folder of a study directory, its pin checked.
#[derive(Debug, Clone)]
pub struct PointStore {
    points: PathBuf,
    study: String,
}

/// The identity of the study pinned by `pin_text`: the MD5 of the text,
/// in hex.
pub(crate) fn study_id(pin_text: &str) -> String {
    crate::io::digest::md5_hex(pin_text.as_bytes())
}

impl PointStore {
    /// Open the store in `dir` for the study described by `pin_text`:
    /// records `pin_text` in `dir/pin_file` if no study is pinned there
    /// (once: of two writers racing, one pin stays) or checks that the one
    /// recorded is the same (a directory holds the points of one study;
    /// `what` names the study in the error), and creates `dir/points/`.
    /// The caller holds the directory's lock ([`crate::io::StudyLock`]) in
    /// `mode`: holding it alone, it replaces the pin of another study that
    /// has no point file (no other writer can be at work on that study).
    pub fn open(
        dir: &Path,
        pin_file: &str,
        pin_text: &str,
        what: &str,
        mode: LockMode,
    ) -> Result<Self> {
        let pinned = dir.join(pin_file);
        let mut ours = match std::fs::read_to_string(&pinned) {
            Ok(old) => old == pin_text,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
                write_new(&pinned, pin_text.as_bytes())?
                    || std::fs::read_to_string(&pinned).is_ok_and(|old| old == pin_text)
            }
            Err(e) => return Err(Error::io(&pinned, e)),
        };
        let points = dir.join("points");
        if !ours && !has_point_files(&points)? {
            if mode == LockMode::Exclusive {
                write_atomic(&pinned, pin_text.as_bytes())?;
                ours = true;
            } else {
                // Sharing the directory, this writer cannot tell whether a
                // shard of the pinned study is at work on its first point.
                return Err(Error::Invalid(format!(
                    "{} holds a {what} made with a different configuration and no finished point yet (a shard of it may be at work); a run without --shard replaces it, or use another --out directory",
                    dir.display()
                )));
            }
        }
        if !ours {
            // A file the configuration reads, changed, is named.
            let changed = std::fs::read_to_string(&pinned)
                .ok()
                .and_then(|old| super::files::changed_file(&old, pin_text, dir, what));
            return Err(Error::Invalid(changed.unwrap_or_else(|| {
                format!(
                    "{} holds a {what} made with a different configuration; use another --out directory (or delete it) instead of mixing results",
                    dir.display()
                )
            })));
        }
        std::fs::create_dir_all(&points).map_err(|e| Error::io(&points, e))?;
        Ok(Self {
            points,
            study: study_id(pin_text),
        })
    }

    /// The file of point `id`.
    pub fn path(&self, id: &str) -> PathBuf {
        self.points.join(format!("{id}.json"))
    }

    /// The finished point `id` of this study: its file parses, has `key`
    /// (a point cut off mid-write never has a file at all; the key guards
    /// against files of another kind), names this study and records point
    /// `id` (`records`). Any other file is solved again, and replaced.
    pub fn read(&self, id: &str, key: &str) -> Option<Value> {
        std::fs::read_to_string(self.path(id))
            .ok()
            .and_then(|t| serde_json::from_str::<Value>(&t).ok())
            .filter(|v| v.get(key).is_some() && self.owns(v) && records(v, id).is_ok())
    }

    /// Whether point `id` is finished (see [`PointStore::read`]).
    pub fn done(&self, id: &str, key: &str) -> bool {
        self.read(id, key).is_some()
    }

    /// Whether the point file `value` belongs to this study.
    pub fn owns(&self, value: &Value) -> bool {
        value.get(STUDY_KEY).and_then(Value::as_str) == Some(self.study.as_str())
    }

    /// Write point `id` atomically, marked as this study's.
    pub fn write(&self, id: &str, value: &Value) -> Result<()> {
        let mut value = value.clone();
        if let Value::Object(map) = &mut value {
            map.insert(STUDY_KEY.into(), Value::String(self.study.clone()));
        }
        crate::io::fault::slow_point("point");
        write_atomic(
            self.path(id),
            serde_json::to_string_pretty(&value)
                .expect("serialisable")
                .as_bytes(),
        )?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn ids_and_indices_are_one_naming() {
        assert_eq!(point_id(5), "p0005");
        assert_eq!(point_id(12345), "p12345");
        assert_eq!(point_index("p0005"), Some(5));
        assert_eq!(point_index("p12345"), Some(12345));
        for bad in ["p5", "p00005", "q0005", "p", "p-001", "p0005.json"] {
            assert_eq!(point_index(bad), None, "{bad}");
        }
    }

    #[test]
    fn a_file_records_the_point_its_name_says_or_not() {
        let sweep = json!({ "point": { "index": 5, "id": "p0005" } });
        assert_eq!(records(&sweep, "p0005"), Ok(()));
        assert_eq!(records(&sweep, "p0004"), Err("p0005".into()));
        // A study that records the index alone (magnification).
        let level = json!({ "point": { "index": 4, "level": 1 } });
        assert_eq!(records(&level, "p0004"), Ok(()));
        assert_eq!(records(&level, "p0005"), Err("p0004".into()));
        // An id that disagrees with its own index.
        let odd = json!({ "point": { "index": 4, "id": "p0005" } });
        assert_eq!(records(&odd, "p0005"), Err("p0005 at index 4".into()));
        assert!(records(&json!({}), "p0000").is_err());
    }
}
