//! A library `Problem` from a Python surface and material and the
//! `[loading]`, `[solver]`, `[layer]` and `[heating]` sections (JSON,
//! config key names), typed by the configuration's parser (the command
//! line's: a bad key or value is named with its unit), with the
//! configuration document that reproduces it (recorded in `summary.json`;
//! for a generated or file surface it is a valid config), and the heated
//! solve's parameters checked by the library
//! (`viscoslide::heating::HeatingParams`, physics.md section 14).

use viscoslide::config::{
    self, Config, ConfigError, Formulation, HeatingConfig, LayerConfig, LoadingConfig, SolverConfig,
};
use viscoslide::heating::HeatingParams;
use viscoslide::problem::Control;
use viscoslide::problem::{check_memory, Problem};

use crate::errors::value_error;
use crate::material::{section_table, NativeMaterial};
use crate::surface::NativeSurface;
use pyo3::prelude::*;

/// A section given as JSON, as a TOML value.
pub fn json_section(name: &str, json: &str) -> PyResult<toml::Value> {
    let value: serde_json::Value =
        serde_json::from_str(json).map_err(|e| value_error(format!("[{name}] {e}")))?;
    toml::Value::try_from(value).map_err(|e| value_error(format!("[{name}] {e}")))
}

/// The sections of a solve given as JSON: `[loading]`, `[solver]` and the
/// optional `[layer]` and `[heating]`.
#[derive(Clone, Copy)]
pub struct Sections<'a> {
    pub loading: &'a str,
    pub solver: &'a str,
    pub layer: Option<&'a str>,
    pub heating: Option<&'a str>,
}

/// The sections (JSON) as a configuration document.
pub fn document(sections: Sections<'_>) -> PyResult<toml::Table> {
    let mut document = toml::Table::new();
    for (name, json) in [
        ("loading", Some(sections.loading)),
        ("solver", Some(sections.solver)),
        ("layer", sections.layer),
        ("heating", sections.heating),
    ] {
        if let Some(json) = json {
            document.insert(name.into(), json_section(name, json)?);
        }
    }
    if let Some(heating) = document.get("heating") {
        // Typed alone first, so that a bad key or value is named as the
        // argument `heating` (the whole document's parser names no section).
        let mut alone = toml::Table::new();
        alone.insert("heating".into(), heating.clone());
        parse(&alone, "heating")?;
    }
    Ok(document)
}

/// `document` typed as a configuration, by the parser of configuration
/// files; errors are named `name: key ...` in one line.
pub fn parse(document: &toml::Table, name: &str) -> PyResult<Config> {
    config::parse_document(document, name).map_err(|e| value_error(config_message(e)))
}

/// A configuration error without the line of the document it names (a
/// document built from arguments: its lines are nobody's).
pub fn config_message(e: ConfigError) -> String {
    match e {
        ConfigError::Parse { path, message } => format!("{path}: {}", without_line(&message)),
        other => load_message(other),
    }
}

/// An error loading a configuration file with overrides, an override
/// named as Python's `set=` argument gives it (not as the command line's
/// flag).
pub fn load_message(e: ConfigError) -> String {
    match e {
        ConfigError::Override { arg, message } => format!("set '{arg}': {message}"),
        other => other.to_string(),
    }
}

/// `message` without a leading `line N, ` or `line N: `.
fn without_line(message: &str) -> &str {
    let Some(rest) = message.strip_prefix("line ") else {
        return message;
    };
    let digits = rest.len() - rest.trim_start_matches(|c: char| c.is_ascii_digit()).len();
    if digits == 0 {
        return message;
    }
    let rest = &rest[digits..];
    rest.strip_prefix(", ")
        .or_else(|| rest.strip_prefix(": "))
        .unwrap_or(message)
}

/// A TOML table of a serialisable section.
fn table<T: serde::Serialize>(value: &T) -> toml::Value {
    toml::Value::Table(toml::Table::try_from(value).unwrap_or_default())
}

/// The problem of `surface` under `material` with the given sections, and
/// its heated solve's parameters when `[heating]` is given and enabled:
/// everything checked before anything is solved.
pub fn build(
    surface: &NativeSurface,
    material: &NativeMaterial,
    sections: Sections<'_>,
) -> PyResult<(Problem, Option<HeatingParams>)> {
    let config = parse(&document(sections)?, "solve")?;
    let loading = config.loading.unwrap_or_default();
    let problem = from_sections(
        surface,
        material,
        &loading,
        &config.solver.unwrap_or_default(),
        config.layer.as_ref(),
        config.heating.as_ref(),
    )?;
    let heating = heating_params(config.heating.as_ref(), &problem, loading.temperature)?;
    Ok((problem, heating))
}

/// `[heating]` checked against `problem` by the library (the command
/// line's checks and messages); `None` without the section or with
/// `enabled = false`. `ambient` is `[loading] temperature`.
pub fn heating_params(
    heating: Option<&HeatingConfig>,
    problem: &Problem,
    ambient: Option<f64>,
) -> PyResult<Option<HeatingParams>> {
    match heating {
        Some(h) => HeatingParams::from_config(h, problem, ambient).map_err(value_error),
        None => Ok(None),
    }
}

/// The problem of `surface` under `material` with typed sections
/// (`heating` is only recorded in the problem's configuration document).
pub fn from_sections(
    surface: &NativeSurface,
    material: &NativeMaterial,
    loading: &LoadingConfig,
    solver: &SolverConfig,
    layer: Option<&LayerConfig>,
    heating: Option<&HeatingConfig>,
) -> PyResult<Problem> {
    // The periodic formulation takes a measured map as one period.
    let period = match solver.formulation.unwrap_or_default() {
        Formulation::Periodic => surface.as_period()?,
        Formulation::NonPeriodic => None,
    };
    let (map, preprocessing) = match &period {
        Some((m, p)) => (m.as_ref(), Some(*p)),
        None => (&surface.map, surface.preprocessing),
    };
    let restart = solver
        .restart
        .unwrap_or(viscoslide::problem::SolverParams::default().restart);
    check_memory(
        map.nx,
        map.ny,
        restart,
        solver.formulation.unwrap_or_default(),
        solver.precision.unwrap_or_default(),
    )
    .map_err(value_error)?;
    let mut problem = Problem::new(
        material.material.clone(),
        map.clone(),
        Control::Load(0.0),
        0.0,
    )
    .with_loading(loading)
    .map_err(value_error)?
    .with_solver_config(solver)
    .map_err(value_error)?;
    if let Some(l) = layer {
        problem = problem.with_layer(l.build().map_err(value_error)?);
    }
    problem.source = surface.source.clone();
    problem.preprocessing = preprocessing;
    problem.filled_points = surface.filled;
    problem.seed = surface.seed;
    let mut document = toml::Table::new();
    document.insert(
        "material".into(),
        toml::Value::Table(section_table(&material.section)),
    );
    if let Some(s) = &surface.section {
        document.insert("surface".into(), table(s));
    }
    document.insert("loading".into(), table(loading));
    document.insert("solver".into(), table(solver));
    if let Some(l) = layer {
        document.insert("layer".into(), table(l));
    }
    if let Some(h) = heating {
        document.insert("heating".into(), table(h));
    }
    problem.document = document;
    problem.check().map_err(value_error)?;
    Ok(problem)
}
