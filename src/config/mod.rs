//! Run configuration: one TOML file in SI units, deserialised with
//! `deny_unknown_fields`, with `--set section.key=value` overrides applied to
//! the parsed document before it is typed. Errors name the key and its unit.
//!
//! One file per section; these types import nothing else of the crate (the
//! layers above build their objects from them: `MaterialConfig::build` in
//! `material`, `SurfaceConfig::load` in `surface`, `LayerConfig::build` in
//! `kernel`, the problem in `problem`, the sweep plan in `sweep`).

pub mod analysis;
mod exact;
pub mod heating;
pub mod layer;
pub mod loading;
pub mod material;
pub mod solver;
pub mod surface;
pub mod sweep;

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

pub use analysis::AnalysisConfig;
pub use heating::HeatingConfig;
pub use layer::{LayerBase, LayerConfig};
pub(crate) use loading::Pressing;
pub use loading::{LoadingConfig, Sliding, XiScale};
pub use material::{MaterialConfig, MaterialModel};
pub use solver::{AdaptiveConfig, Formulation, MeshKind, Precision, SolverConfig};
pub use surface::{AnisotropyConfig, GenerateConfig, SphereConfig, SurfaceConfig};
pub use sweep::SweepConfig;

/// Errors reading or checking a configuration.
#[derive(Debug, thiserror::Error)]
pub enum ConfigError {
    #[error("{path}: {source}")]
    Read {
        path: String,
        #[source]
        source: std::io::Error,
    },
    #[error("{path}: {message}")]
    Parse { path: String, message: String },
    #[error("--set {arg}: {message}")]
    Override { arg: String, message: String },
    #[error("{path}: section [{section}] is required here")]
    Missing { path: String, section: String },
}

/// A whole run configuration; every section is optional in the file and each
/// command asks for the sections it needs.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub struct Config {
    pub material: Option<MaterialConfig>,
    pub surface: Option<SurfaceConfig>,
    pub loading: Option<LoadingConfig>,
    pub solver: Option<SolverConfig>,
    pub layer: Option<LayerConfig>,
    pub sweep: Option<SweepConfig>,
    pub analysis: Option<AnalysisConfig>,
    pub heating: Option<HeatingConfig>,
}

/// A parsed config with the directory its relative paths refer to.
#[derive(Debug, Clone)]
pub struct LoadedConfig {
    pub config: Config,
    /// The file it came from.
    pub path: PathBuf,
    /// Directory relative paths inside the config are resolved against.
    pub base_dir: PathBuf,
    /// The merged document (after overrides), as recorded in reports.
    pub document: toml::Table,
}

impl LoadedConfig {
    /// Whether `[heating]` is present and not switched off.
    pub fn heated(&self) -> bool {
        self.config
            .heating
            .as_ref()
            .is_some_and(|h| h.enabled != Some(false))
    }

    /// Refuse an enabled `[heating]` for `study`, which solves
    /// isothermally (a heated contact would be reported as if it were
    /// not): one line naming the file, the study and the fix.
    pub fn refuse_heating(&self, study: &str) -> Result<(), ConfigError> {
        if !self.heated() {
            return Ok(());
        }
        Err(ConfigError::Parse {
            path: self.path.display().to_string(),
            message: format!(
                "{study} solves isothermally and does not take [heating]; set heating.enabled = false (--set heating.enabled=false; set={{\"heating.enabled\": False}} in Python) or remove the section for the solves at the ambient temperature"
            ),
        })
    }

    /// The `[material]` section, or an error saying it is needed.
    pub fn material(&self) -> Result<&MaterialConfig, ConfigError> {
        self.config
            .material
            .as_ref()
            .ok_or_else(|| self.missing("material"))
    }

    /// The `[surface]` section, or an error saying it is needed.
    pub fn surface(&self) -> Result<&SurfaceConfig, ConfigError> {
        self.config
            .surface
            .as_ref()
            .ok_or_else(|| self.missing("surface"))
    }

    fn missing(&self, section: &str) -> ConfigError {
        ConfigError::Missing {
            path: self.path.display().to_string(),
            section: section.into(),
        }
    }
}

/// Read `path`, apply `overrides` (`section.key=value`, TOML values; a bare
/// word is taken as a string), and type-check the result.
pub fn load(path: &Path, overrides: &[String]) -> Result<LoadedConfig, ConfigError> {
    let text = std::fs::read_to_string(path).map_err(|source| ConfigError::Read {
        path: path.display().to_string(),
        source,
    })?;
    let name = path.display().to_string();
    let mut document: toml::Table = toml::from_str(&text).map_err(|e| ConfigError::Parse {
        path: name.clone(),
        message: one_line(&e, &text),
    })?;
    let mut given = Vec::new();
    for arg in overrides {
        apply_override(&mut document, arg, &mut given)?;
    }
    // Without overrides, type-check the file's own text so that line numbers
    // in errors are the user's.
    let config = if overrides.is_empty() {
        toml::from_str(&text).map_err(|e| ConfigError::Parse {
            path: name.clone(),
            message: one_line(&e, &text),
        })?
    } else {
        parse_document(&document, &name).map_err(|e| blame_override(&text, &name, overrides, e))?
    };
    let base_dir = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .map(Path::to_path_buf)
        .unwrap_or_else(|| PathBuf::from("."));
    Ok(LoadedConfig {
        config,
        path: path.to_path_buf(),
        base_dir,
        document,
    })
}

/// The error of a file with overrides, put where it belongs: the file's own
/// error (with its line numbers) when the file alone is wrong, else the
/// first `--set` that breaks it, named by its flag (a line of the merged
/// document would point into a file the value did not come from).
fn blame_override(text: &str, name: &str, overrides: &[String], err: ConfigError) -> ConfigError {
    if let Err(e) = toml::from_str::<Config>(text) {
        return ConfigError::Parse {
            path: name.into(),
            message: one_line(&e, text),
        };
    }
    let Ok(mut document) = toml::from_str::<toml::Table>(text) else {
        return err;
    };
    // A section that a `--set` starts may be completed by a later one
    // (`layer.thickness`, then `layer.base`): a missing field is blamed
    // only when no later `--set` breaks the document otherwise.
    let mut incomplete: Option<ConfigError> = None;
    let mut given = Vec::new();
    for arg in overrides {
        if apply_override(&mut document, arg, &mut given).is_err() {
            return err;
        }
        if let Err(ConfigError::Parse { message, .. }) = parse_document(&document, name) {
            // "line N, key `k`: ..." names a line of the merged document.
            let missing = message.contains("missing field `");
            let message = match message.split_once(", ") {
                Some((head, rest)) if head.starts_with("line ") => rest.to_string(),
                _ => message,
            };
            let blamed = ConfigError::Override {
                arg: arg.clone(),
                message,
            };
            if !missing {
                return blamed;
            }
            incomplete.get_or_insert(blamed);
        }
    }
    incomplete.unwrap_or(err)
}

/// Type-check a TOML document as a [`Config`].
pub fn parse_document(document: &toml::Table, name: &str) -> Result<Config, ConfigError> {
    // Re-serialise so that toml reports errors with the key path.
    let text = toml::to_string(document).map_err(|e| ConfigError::Parse {
        path: name.into(),
        message: e.to_string(),
    })?;
    toml::from_str(&text).map_err(|e| ConfigError::Parse {
        path: name.into(),
        message: one_line(&e, &text),
    })
}

/// Keys of which a configuration gives one: the speed (m/s or `xi`), the
/// load (a force, a pressure or an approach), a generated surface's upper
/// cut-off and its amplitude.
const ALTERNATIVES: [&[&str]; 4] = [
    &["loading.speed", "loading.xi"],
    &[
        "loading.normal_load",
        "loading.mean_pressure",
        "loading.approach",
    ],
    &["surface.generate.scales", "surface.generate.q1"],
    &["surface.generate.rms_height", "surface.generate.rms_slope"],
];

/// Set the dotted `key` to `value` as `--set` sets it ([`set_value`]),
/// then remove the alternatives of the key that the document gave
/// (`--set loading.speed=0.01` on a config with `xi` replaces it, as a flag
/// of `surface generate` replaces its config's exclusive key, and so does
/// a `[sweep.vary]` value); alternatives set before through `given`
/// (which gains this key) stay, so two of them are refused as in a file.
pub(crate) fn set_replacing(
    document: &mut toml::Table,
    key: &str,
    value: toml::Value,
    given: &mut Vec<String>,
) -> Result<(), String> {
    set_value(document, key, value)?;
    let key: String = key.split('.').map(str::trim).collect::<Vec<_>>().join(".");
    if let Some(group) = ALTERNATIVES.iter().find(|g| g.contains(&key.as_str())) {
        for other in group
            .iter()
            .filter(|k| **k != key && !given.iter().any(|g| g == *k))
        {
            let (path, last) = other.rsplit_once('.').expect("dotted");
            let mut table = Some(&mut *document);
            for part in path.split('.') {
                table = table
                    .and_then(|t| t.get_mut(part))
                    .and_then(|v| v.as_table_mut());
            }
            if let Some(t) = table {
                t.remove(last);
            }
        }
    }
    given.push(key);
    Ok(())
}

/// Apply one `section.key=value` override to a TOML document
/// ([`set_replacing`], `given` the keys of the overrides before it).
pub(crate) fn apply_override(
    document: &mut toml::Table,
    arg: &str,
    given: &mut Vec<String>,
) -> Result<(), ConfigError> {
    let err = |message: String| ConfigError::Override {
        arg: arg.into(),
        message,
    };
    let (key, value) = arg
        .split_once('=')
        .ok_or_else(|| err("expected section.key=value".into()))?;
    let last = key.rsplit('.').next().unwrap_or(key).trim();
    let value = parse_value(value.trim()).map_err(|why| err(format!("key `{last}`: {why}")))?;
    set_replacing(document, key, value, given).map_err(err)
}

/// Set the dotted `key` (`section.key`, `surface.generate.q1`) of a TOML
/// document to `value`, creating the sections on the way: the one path of
/// `--set` and of a sweep's `[sweep.vary]` values (both through
/// [`set_replacing`]). `Err` says why not.
pub(crate) fn set_value(
    document: &mut toml::Table,
    key: &str,
    value: toml::Value,
) -> Result<(), String> {
    let parts: Vec<&str> = key.trim().split('.').map(str::trim).collect();
    if parts.iter().any(|p| p.is_empty()) {
        return Err(format!("bad key '{key}'"));
    }
    let mut table = document;
    for part in &parts[..parts.len() - 1] {
        let entry = table
            .entry(part.to_string())
            .or_insert_with(|| toml::Value::Table(toml::Table::new()));
        table = match entry {
            toml::Value::Table(t) => t,
            _ => return Err(format!("'{part}' is a value, not a section")),
        };
    }
    table.insert(parts[parts.len() - 1].to_string(), value);
    Ok(())
}

/// `raw` as a TOML value; what TOML does not read is taken as a string (a
/// bare word). A number that TOML does not read because it is beyond the
/// range of its type (`1e400`, an integer beyond 64 bits), or a nonzero
/// one that it reads as 0 (`1e-400`), is refused saying so, not passed on
/// as the string it is not.
fn parse_value(raw: &str) -> Result<toml::Value, String> {
    let numeric = !raw.is_empty()
        && raw.contains(|c: char| c.is_ascii_digit())
        && raw
            .chars()
            .all(|c| c.is_ascii_digit() || "+-._eE".contains(c));
    let digits = raw.replace('_', "");
    match toml::from_str::<toml::Table>(&format!("v = {raw}")) {
        Ok(mut t) => {
            let value = t.remove("v").unwrap_or(toml::Value::String(raw.into()));
            let mantissa = digits.split(['e', 'E']).next().unwrap_or("");
            if value.as_float() == Some(0.0)
                && mantissa.contains(|c: char| ('1'..='9').contains(&c))
            {
                return Err(format!(
                    "{raw} is below the range of a double (nonzero magnitudes from about 4.9e-324) and would be read as 0"
                ));
            }
            Ok(value)
        }
        Err(_) if numeric && digits.parse::<f64>().is_ok_and(f64::is_infinite) => Err(format!(
            "{raw} is out of the range of a double (magnitudes up to about 1.8e308)"
        )),
        Err(_)
            if numeric
                && digits
                    .trim_start_matches(['+', '-'])
                    .chars()
                    .all(|c| c.is_ascii_digit()) =>
        {
            Err(format!(
                "{raw} is out of the range of a 64-bit integer (magnitudes up to {})",
                i64::MAX
            ))
        }
        Err(_) => Ok(toml::Value::String(raw.into())),
    }
}

/// Keys and their units, appended to error messages that mention them.
const UNITS: &[(&str, &str)] = &[
    ("relaxed_modulus", "relaxed (zero-frequency) modulus E0, Pa"),
    ("glassy_modulus", "glassy modulus E_inf, Pa"),
    ("creep_time", "creep (retardation) time, s"),
    ("relaxation_time", "stress-relaxation time, s"),
    ("creep_spectrum", "[[C_k in 1/Pa, tau_k in s], ...]"),
    ("prony", "[[E_j in Pa, theta_j in s], ...]"),
    ("poisson", "Poisson ratio, dimensionless"),
    ("length", "side of the map along x, m"),
    ("rms_height", "m"),
    ("rms_slope", "dimensionless"),
    ("hurst", "Hurst exponent H, 0 < H <= 1"),
    ("normal_load", "N"),
    ("mean_pressure", "Pa"),
    ("speed", "m/s"),
    ("xi", "v tau / L, dimensionless"),
    (
        "temperature",
        "C, where |log10 a_T| <= 50: T >= T_ref - C2 * 50 / (|C1| + 50) for the material's WLF constants",
    ),
    ("wlf", "[C1, C2 in K, T_ref in C]"),
    ("thickness", "m"),
    (
        "base",
        "[layer] base = \"bonded\" or \"frictionless\", how the layer rests on its rigid base",
    ),
    ("cell_size", "m"),
];

fn one_line(e: &toml::de::Error, text: &str) -> String {
    let mut msg = e.message().trim().replace('\n', " ");
    // The key the message is about: named by serde ("unknown field `k`",
    // "missing field `k`") or the key on the line the error points at.
    let mut key = ["unknown field `", "missing field `"]
        .iter()
        .find_map(|pat| {
            let rest = &msg[msg.find(pat)? + pat.len()..];
            Some(rest[..rest.find('`')?].to_string())
        });
    if let Some(span) = e.span() {
        let start = span.start.min(text.len());
        let line = text[..start].matches('\n').count() + 1;
        let line_text = text.lines().nth(line - 1).unwrap_or("");
        match (&key, line_text.split_once('=')) {
            (None, Some((k, _))) => {
                let k = k.trim().trim_matches('"').to_string();
                msg = format!("line {line}, key `{k}`: {msg}");
                key = Some(k);
            }
            (None, None) => msg = format!("line {line}: {msg}"),
            // serde named the key; its span covers the whole table.
            (Some(_), _) => {}
        }
    }
    if let Some(key) = key {
        if let Some((_, unit)) = UNITS.iter().find(|(k, _)| *k == key) {
            msg.push_str(&format!(" ({key}: {unit})"));
        }
    }
    msg
}

#[cfg(test)]
mod tests {
    use super::*;

    fn write(dir: &Path, text: &str) -> PathBuf {
        let p = dir.join("c.toml");
        std::fs::write(&p, text).unwrap();
        p
    }

    const SLS: &str = "[material]\nmodel = \"sls\"\nrelaxed_modulus = 3.3e6\nglassy_modulus = 1e7\ncreep_time = 0.01\n";

    #[test]
    fn overrides_replace_and_add_keys() {
        let tmp = tempfile::tempdir().unwrap();
        let p = write(tmp.path(), SLS);
        let c = load(
            &p,
            &[
                "material.poisson=0.4".into(),
                "material.glassy_modulus=2e7".into(),
            ],
        )
        .unwrap();
        let m = c.material().unwrap();
        assert_eq!(m.poisson, Some(0.4));
        assert_eq!(m.glassy_modulus, Some(2e7));
    }

    #[test]
    fn unknown_keys_are_named() {
        let tmp = tempfile::tempdir().unwrap();
        let p = write(tmp.path(), &format!("{SLS}colour = 3\n"));
        let e = load(&p, &[]).unwrap_err().to_string();
        assert!(e.contains("colour"), "{e}");
        assert!(!e.contains('\n'), "one line: {e}");
        let p = write(tmp.path(), SLS);
        let e = load(&p, &["material.glasy_modulus=1".into()])
            .unwrap_err()
            .to_string();
        assert!(e.contains("glasy_modulus"), "{e}");
    }

    #[test]
    fn type_errors_name_the_unit() {
        let tmp = tempfile::tempdir().unwrap();
        let p = write(tmp.path(), SLS);
        let e = load(&p, &["material.relaxed_modulus=\"soft\"".into()])
            .unwrap_err()
            .to_string();
        assert!(e.contains("Pa"), "{e}");
        // The range the generator's check accepts, H = 1 included.
        let e = load(&p, &["surface.generate.hurst=\"rough\"".into()])
            .unwrap_err()
            .to_string();
        assert!(e.contains("(hurst: Hurst exponent H, 0 < H <= 1)"), "{e}");
    }

    #[test]
    fn bad_override_syntax() {
        let tmp = tempfile::tempdir().unwrap();
        let p = write(tmp.path(), SLS);
        assert!(matches!(
            load(&p, &["material".into()]),
            Err(ConfigError::Override { .. })
        ));
        assert!(matches!(
            load(&p, &["material.model.x=1".into()]),
            Err(ConfigError::Override { .. })
        ));
    }
}
