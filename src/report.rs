//! Outputs of a solve: `summary.json` (every scalar result, convergence,
//! seed, configuration, version, backend, wall time), maps as `.npy`
//! (axis 0 = x = sliding direction) and PNG figures. All files of one solve
//! are written atomically (see [`crate::io::StagedOutput`]).

use std::path::{Path, PathBuf};

use serde_json::{json, Value};

use crate::error::Result;
use crate::io::{npy, StagedOutput};
use crate::plot;
use crate::run::{SolveOutcome, SolveSetup};

/// The `summary.json` document. Key names are fixed: scripts read them.
pub fn summary(setup: &SolveSetup, out: &SolveOutcome) -> Value {
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
        "unknowns": nx * ny,
        "iterations": out.info.iterations,
        "matvecs": out.info.matvecs,
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
    })
}

/// Write every output of a solve into `dir`; returns the written paths.
pub fn write_solve(dir: &Path, setup: &SolveSetup, out: &SolveOutcome) -> Result<Vec<PathBuf>> {
    let (nx, ny, a) = (setup.surface.nx, setup.surface.ny, setup.surface.cell_size);
    let mut staged = StagedOutput::new(dir)?;
    let doc = summary(setup, out);
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
    staged.commit()
}
