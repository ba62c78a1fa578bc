//! Outputs of a solve: `summary.json` (every scalar result, convergence,
//! seed, configuration, version, backend, wall time), maps as `.npy`
//! (axis 0 = x = sliding direction) and PNG figures. All files of one solve
//! are written atomically (see [`crate::io::StagedOutput`]).

use std::path::{Path, PathBuf};

use serde_json::{json, Value};

use crate::analysis::{self, AnalysisInputs, AnalysisParams, AnalysisReport};
use crate::config::Formulation;
use crate::error::Result;
use crate::io::{npy, StagedOutput};
use crate::plot;
use crate::run::{SolveOutcome, SolveSetup};
use crate::surface::Window;

/// The fields of a solve as the analysis sees them.
pub fn analysis_inputs<'a>(setup: &SolveSetup, out: &'a SolveOutcome) -> AnalysisInputs<'a> {
    let lx = setup.surface.length_x();
    let config = serde_json::to_value(&setup.document).unwrap_or(Value::Null);
    AnalysisInputs {
        nx: setup.surface.nx,
        ny: setup.surface.ny,
        cell_size: setup.surface.cell_size,
        displacement: &out.solution.displacement,
        contact: &out.solution.contact,
        pressure: &out.solution.pressure,
        scales: analysis::scales_from_config(&config, 2.0 * std::f64::consts::PI / lx),
        xi: setup.xi(),
    }
}

/// Run the anisotropy analysis of a solve as `[analysis]` asks (`None`
/// when disabled). Periodic solves have periodic fields: no taper.
pub fn analyze(setup: &SolveSetup, out: &SolveOutcome) -> Result<Option<AnalysisReport>> {
    let cfg = setup.analysis.clone().unwrap_or_default();
    if !cfg.enabled.unwrap_or(true) {
        return Ok(None);
    }
    let defaults = AnalysisParams::default();
    let params = AnalysisParams {
        zeta1: cfg.zeta1.unwrap_or(defaults.zeta1),
        zeta2: cfg.zeta2,
        chi_levels: cfg.chi_levels.unwrap_or(defaults.chi_levels),
        window: if setup.formulation == Formulation::Periodic {
            Window::None
        } else {
            defaults.window
        },
        ..defaults
    };
    Ok(Some(analysis::analyze_fields(
        &analysis_inputs(setup, out),
        &params,
    )?))
}

/// The `summary.json` document. Key names are fixed: scripts read them.
/// With an analysis, its headline numbers appear under `analysis`.
pub fn summary(setup: &SolveSetup, out: &SolveOutcome, analysis: Option<&AnalysisReport>) -> Value {
    let s = &out.stats;
    let (nx, ny) = (setup.surface.nx, setup.surface.ny);
    let rel_diff = if out.friction_coefficient_dissipation != 0.0 {
        (out.friction_coefficient - out.friction_coefficient_dissipation).abs()
            / out.friction_coefficient_dissipation.abs()
    } else {
        (out.friction_coefficient - out.friction_coefficient_dissipation).abs()
    };
    let spec = &setup.material.spectrum;
    json!({
        "friction_coefficient": out.friction_coefficient,
        "friction_coefficient_dissipation": out.friction_coefficient_dissipation,
        "friction_relative_difference": rel_diff,
        "contact_area_fraction": s.contact_area_fraction,
        "contact_area": s.contact_area,
        "contact_cells": s.contact_cells,
        "approach": out.solution.approach,
        "max_pressure": s.max_pressure,
        "mean_pressure": s.mean_pressure,
        "normal_load": s.normal_load,
        "pressure_centroid": s.pressure_centroid,
        "speed": setup.speed,
        "xi": setup.xi(),
        "direction_deg": setup.direction_rad.to_degrees(),
        "grid": [nx, ny],
        "cell_size": setup.surface.cell_size,
        "length": [setup.surface.length_x(), setup.surface.length_y()],
        "unknowns": out.unknowns,
        "mesh": out.mesh,
        "iterations": out.info.iterations,
        "matvecs": out.info.matvecs,
        "preconditioner_applications": out.info.preconditioner_applications,
        "matvecs_by_level": out.info.levels,
        "residual": out.info.residual,
        "load_error": out.info.load_error,
        "residual_history": out.info.history,
        "contact_history": out.info.contact_history,
        "backend": out.backend,
        "wall_time_s": out.timings.total_s,
        "timings": out.timings,
        "seed": setup.seed,
        "version": crate::VERSION,
        "formulation": setup.formulation,
        "material": {
            "relaxed_modulus": spec.relaxed_modulus(),
            "glassy_modulus": spec.glassy_modulus,
            "poisson": setup.material.poisson,
            "creep_spectrum": spec.terms.iter().map(|t| [t.compliance, t.time]).collect::<Vec<_>>(),
        },
        "config": setup.document,
        "analysis": analysis.map(analysis_headline),
    })
}

/// The headline numbers of an analysis, as recorded in `summary.json`.
fn analysis_headline(r: &AnalysisReport) -> Value {
    json!({
        "gamma": r.gamma,
        "theta_p_deg": r.theta_p_deg,
        "m20": r.m20,
        "m02": r.m02,
        "m11": r.m11,
        "lambda": r.lambda,
        "ellipse_angle_deg": r.ellipse_angle_deg,
        "spots": r.spots.count,
    })
}

/// Write every output of a solve into `dir`; returns the written paths.
pub fn write_solve(dir: &Path, setup: &SolveSetup, out: &SolveOutcome) -> Result<Vec<PathBuf>> {
    let (nx, ny, a) = (setup.surface.nx, setup.surface.ny, setup.surface.cell_size);
    let report = analyze(setup, out)?;
    let mut staged = StagedOutput::new(dir)?;
    let doc = summary(setup, out, report.as_ref());
    staged.write(
        "summary.json",
        serde_json::to_string_pretty(&doc)
            .expect("summary is serialisable")
            .as_bytes(),
    )?;
    let sol = &out.solution;
    for (name, field) in [
        ("pressure.npy", &sol.pressure),
        ("displacement.npy", &sol.displacement),
        ("gap.npy", &sol.gap),
        ("contact.npy", &sol.contact),
    ] {
        staged.write(name, &npy::encode_f64(&[nx, ny], field))?;
    }
    let extent = (0.0, nx as f64 * a, 0.0, ny as f64 * a);
    let title_suffix = match setup.xi() {
        Some(xi) => format!("xi = {xi:.3e}"),
        None => format!("v = {:.3e} m/s", setup.speed),
    };
    let p = staged.path("pressure.png");
    plot::heatmap(
        &p,
        &format!("Contact pressure, {title_suffix}"),
        &plot::Field {
            nx,
            ny,
            values: &sol.pressure,
            extent,
        },
        "p [Pa]",
        None,
    )?;
    let c = staged.path("contact.png");
    plot::heatmap(
        &c,
        &format!(
            "Contact area (A/A0 = {:.4}), {title_suffix}",
            out.stats.contact_area_fraction
        ),
        &plot::Field {
            nx,
            ny,
            values: &sol.contact,
            extent,
        },
        "in contact",
        None,
    )?;
    if let Some(r) = &report {
        analysis::write_analysis(&mut staged, &analysis_inputs(setup, out), r)?;
    }
    staged.commit()
}
