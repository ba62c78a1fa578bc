//! A library `Problem` from a Python surface and material and the
//! `[loading]`, `[solver]` and `[layer]` sections (JSON, config key names),
//! with the configuration document that reproduces it (recorded in
//! `summary.json`; for a generated or file surface it is a valid config).

use viscoslide::config::{Formulation, LayerConfig, LoadingConfig, SolverConfig};
use viscoslide::problem::{check_memory, Problem};
use viscoslide::solver::Control;

use crate::errors::value_error;
use crate::material::{section_table, NativeMaterial};
use crate::surface::NativeSurface;
use pyo3::prelude::*;

/// `T` from a JSON section named `name` (unknown keys refused by name).
fn section<T: serde::de::DeserializeOwned>(name: &str, json: &str) -> PyResult<T> {
    serde_json::from_str(json).map_err(|e| value_error(format!("[{name}] {e}")))
}

/// A TOML table of a serialisable section.
fn table<T: serde::Serialize>(value: &T) -> toml::Value {
    toml::Value::Table(toml::Table::try_from(value).unwrap_or_default())
}

/// The problem of `surface` under `material` with the given sections.
pub fn build(
    surface: &NativeSurface,
    material: &NativeMaterial,
    loading_json: &str,
    solver_json: &str,
    layer_json: Option<&str>,
) -> PyResult<Problem> {
    let loading: LoadingConfig = section("loading", loading_json)?;
    let solver: SolverConfig = section("solver", solver_json)?;
    let layer: Option<LayerConfig> = layer_json.map(|j| section("layer", j)).transpose()?;
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
        .unwrap_or(viscoslide::solver::SolverParams::default().restart);
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
    .with_loading(&loading)
    .map_err(value_error)?
    .with_solver_config(&solver)
    .map_err(value_error)?;
    if let Some(l) = &layer {
        problem = problem.with_layer(l.build().map_err(value_error)?);
    }
    problem.source = surface.source.clone();
    problem.preprocessing = preprocessing;
    problem.seed = surface.seed;
    let mut document = toml::Table::new();
    document.insert(
        "material".into(),
        toml::Value::Table(section_table(&material.section)),
    );
    if let Some(s) = &surface.section {
        document.insert("surface".into(), table(s));
    }
    document.insert("loading".into(), table(&loading));
    document.insert("solver".into(), table(&solver));
    if let Some(l) = &layer {
        document.insert("layer".into(), table(l));
    }
    problem.document = document;
    problem.check().map_err(value_error)?;
    Ok(problem)
}
