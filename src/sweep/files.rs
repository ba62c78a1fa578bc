//! The content of the files a study's configuration reads, pinned with
//! it: a height map (`[surface] file`), a PSD table (`[surface.generate]
//! psd`), a material file (`[material] file`). A study directory holds
//! the points of one configuration *and* of one content of each of these
//! files, so that a file replaced between two runs (or two shards) is
//! refused by name instead of mixing results of two surfaces or
//! materials.
//!
//! The pin records, in a `[[pinned_files]]` array beside the
//! configuration, each file by the key that names it and the path as
//! written (relative paths are the configuration's), with the MD5 of its
//! bytes.

use std::path::{Path, PathBuf};

use crate::config::{Config, MaterialModel};
use crate::error::{Error, Result};
use crate::io::digest::md5_file_hex;

/// Key of the pin's array of files.
pub(crate) const FILES_KEY: &str = "pinned_files";

/// One file a configuration reads: the key naming it, its path as
/// written, the MD5 of its content (hex).
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct PinnedFile {
    pub key: &'static str,
    pub file: PathBuf,
    pub md5: String,
}

/// The files `config` reads, by key and path as written.
fn referenced(config: &Config) -> Vec<(&'static str, PathBuf)> {
    let mut out = Vec::new();
    if let Some(s) = &config.surface {
        if let Some(f) = &s.file {
            out.push(("surface.file", f.clone()));
        }
        if let Some(p) = s.generate.as_ref().and_then(|g| g.psd.as_ref()) {
            out.push(("surface.generate.psd", p.clone()));
        }
    }
    if let Some(m) = &config.material {
        if m.model == MaterialModel::File {
            if let Some(f) = &m.file {
                out.push(("material.file", f.clone()));
            }
        }
    }
    out
}

/// The files every configuration of `configs` reads (each once, in order
/// of first appearance), their content hashed; relative paths resolve
/// against `base_dir`.
pub(crate) fn pinned_files<'a>(
    configs: impl IntoIterator<Item = &'a Config>,
    base_dir: &Path,
) -> Result<Vec<PinnedFile>> {
    let mut out: Vec<PinnedFile> = Vec::new();
    for config in configs {
        for (key, file) in referenced(config) {
            if out.iter().any(|p| p.key == key && p.file == file) {
                continue;
            }
            let path = base_dir.join(&file);
            let md5 = md5_file_hex(&path).map_err(|e| Error::io(&path, e))?;
            out.push(PinnedFile { key, file, md5 });
        }
    }
    Ok(out)
}

/// `doc` with the array of `files` added (unchanged without files, so
/// that a study reading no file pins what it always pinned).
pub(crate) fn with_files(mut doc: toml::Table, files: &[PinnedFile]) -> toml::Table {
    if !files.is_empty() {
        let list = files
            .iter()
            .map(|f| {
                let mut t = toml::Table::new();
                t.insert("key".into(), toml::Value::String(f.key.into()));
                t.insert(
                    "file".into(),
                    toml::Value::String(f.file.display().to_string()),
                );
                t.insert("md5".into(), toml::Value::String(f.md5.clone()));
                toml::Value::Table(t)
            })
            .collect();
        doc.insert(FILES_KEY.into(), toml::Value::Array(list));
    }
    doc
}

/// The `(key, file, md5)` entries of a pin's array.
fn entries(value: Option<&toml::Value>) -> Vec<(String, String, String)> {
    let field = |t: &toml::Table, k: &str| {
        t.get(k)
            .and_then(toml::Value::as_str)
            .unwrap_or_default()
            .to_string()
    };
    value
        .and_then(toml::Value::as_array)
        .into_iter()
        .flatten()
        .filter_map(toml::Value::as_table)
        .map(|t| (field(t, "key"), field(t, "file"), field(t, "md5")))
        .collect()
}

/// Why a pin `old` differs from `new` when only the content of a file
/// differs: the file named, by its key and path. `None` when the pins
/// differ otherwise (another configuration), or agree.
pub(crate) fn changed_file(old: &str, new: &str, dir: &Path, what: &str) -> Option<String> {
    let mut old: toml::Table = old.parse().ok()?;
    let mut new: toml::Table = new.parse().ok()?;
    let (old_files, new_files) = (old.remove(FILES_KEY), new.remove(FILES_KEY));
    if old != new {
        return None;
    }
    let before = entries(old_files.as_ref());
    for (key, file, md5) in entries(new_files.as_ref()) {
        let named = format!("{key} = \"{file}\"");
        match before.iter().find(|(k, f, _)| *k == key && *f == file) {
            None if old_files.is_none() => {
                return Some(format!(
                    "{} holds a {what} started by an earlier version, which did not record the content of {named}; use another --out directory (or delete it)",
                    dir.display()
                ))
            }
            Some((_, _, was)) if *was != md5 => {
                return Some(format!(
                    "{named} has changed since the {what} in {} was started (its points were solved with other content); restore the file, or use another --out directory",
                    dir.display()
                ))
            }
            _ => {}
        }
    }
    None
}

/// Whether the files pinned in `pin` (a parsed pin) still have the
/// content recorded, relative paths against `base_dir`; `Err` names the
/// first that does not (or cannot be read).
pub(crate) fn check_unchanged(
    pin: &toml::Table,
    base_dir: &Path,
) -> std::result::Result<(), String> {
    for (key, file, md5) in entries(pin.get(FILES_KEY)) {
        let path = base_dir.join(&file);
        match md5_file_hex(&path) {
            Ok(now) if now == md5 => {}
            Ok(_) => {
                return Err(format!(
                    "{key} = \"{file}\" has changed since the study was pinned"
                ))
            }
            Err(e) => return Err(format!("{key} = \"{file}\": {}: {e}", path.display())),
        }
    }
    Ok(())
}
