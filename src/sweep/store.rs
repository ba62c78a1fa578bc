//! The point store of a resumable study: `DIR/points/<id>.json`, one file
//! per finished point, each written atomically, beside a pinned description
//! of the study (`DIR/<pin file>`) that a rerun must match. Shared by
//! [`super::run_sweep`] and the magnification study, so that resuming and
//! sharding work the same way for every study made of independent points.

use std::path::{Path, PathBuf};

use serde_json::Value;

use crate::error::{Error, Result};
use crate::io::atomic::write_atomic;

/// The `points/` folder of a study directory, its pin checked.
#[derive(Debug, Clone)]
pub struct PointStore {
    points: PathBuf,
}

impl PointStore {
    /// Open the store in `dir` for the study described by `pin_text`:
    /// checks that `dir` can take output, records `pin_text` in
    /// `dir/pin_file` (or checks that the one recorded there is the same:
    /// a directory holds the points of one study; `what` names the study
    /// in the error) and creates `dir/points/`.
    pub fn open(dir: &Path, pin_file: &str, pin_text: &str, what: &str) -> Result<Self> {
        crate::io::check_output_dir(dir)?;
        let pinned = dir.join(pin_file);
        match std::fs::read_to_string(&pinned) {
            Ok(old) if old == pin_text => {}
            Ok(_) => {
                return Err(Error::Invalid(format!(
                    "{} holds a {what} made with a different configuration; use another --out directory (or delete it) instead of mixing results",
                    dir.display()
                )))
            }
            Err(_) => write_atomic(&pinned, pin_text.as_bytes())?,
        }
        let points = dir.join("points");
        std::fs::create_dir_all(&points).map_err(|e| Error::io(&points, e))?;
        Ok(Self { points })
    }

    /// The file of point `id`.
    pub fn path(&self, id: &str) -> PathBuf {
        self.points.join(format!("{id}.json"))
    }

    /// The finished point `id`: its file parses and has `key` (a point
    /// cut off mid-write never has a file at all; the key guards against
    /// files of another kind).
    pub fn read(&self, id: &str, key: &str) -> Option<Value> {
        std::fs::read_to_string(self.path(id))
            .ok()
            .and_then(|t| serde_json::from_str::<Value>(&t).ok())
            .filter(|v| v.get(key).is_some())
    }

    /// Whether point `id` is finished (see [`PointStore::read`]).
    pub fn done(&self, id: &str, key: &str) -> bool {
        self.read(id, key).is_some()
    }

    /// Write point `id` atomically.
    pub fn write(&self, id: &str, value: &Value) -> Result<()> {
        write_atomic(
            self.path(id),
            serde_json::to_string_pretty(value)
                .expect("serialisable")
                .as_bytes(),
        )?;
        Ok(())
    }
}
