//! `viscoslide heat --from-run DIR`: the heat of a solved contact. Reads
//! the run's `summary.json` (grid, cells, speed, direction, formulation,
//! the material at the solve's temperature, the layer, the friction) and
//! `pressure.npy`, builds the heat source (`crate::problem::ContactHeating`:
//! the creep elements' dissipation on depth layers, or the surface work of
//! the pressure), solves the rise and writes `temperature.npy`,
//! `temperature.png` and `heat.json` (with the energy balance) into --out.

use std::path::Path;
use std::time::Instant;

use serde_json::{json, Value};

use super::heat::{write, HeatArgs, HEAT_FILES};
use crate::config::LayerConfig;
use crate::error::{Error, Result};
use crate::heat::{Conduction, DepthRule, HeatDomain, HeatSetup, SourceKind};
use crate::io::npy;
use crate::material::{CreepSpectrum, CreepTerm, Material};
use crate::problem::ContactHeating;
use crate::response::{Grid, SlidingResponse};

/// What the heat needs of a solve's `summary.json`.
struct Run {
    grid: Grid,
    response: SlidingResponse,
    direction_deg: f64,
    /// `mu` by the stencil (Eq. 9) and by the dissipation (Appendix A3).
    mu: (f64, f64),
    normal_load: f64,
}

fn bad(path: &Path, what: &str) -> Error {
    Error::Invalid(format!("{}: {what}", path.display()))
}

fn number(doc: &Value, key: &str, path: &Path) -> Result<f64> {
    doc[key]
        .as_f64()
        .ok_or_else(|| bad(path, &format!("needs the number `{key}`")))
}

fn read_run(dir: &Path) -> Result<Run> {
    let path = dir.join("summary.json");
    let bytes = std::fs::read(&path).map_err(|e| {
        bad(
            &path,
            &format!("{e}; --from-run takes the output directory of `viscoslide solve`"),
        )
    })?;
    let doc: Value =
        serde_json::from_slice(&bytes).map_err(|e| bad(&path, &format!("not valid JSON: {e}")))?;
    // `null` on a uniform grid, the mesh's report (an object) after an
    // adaptive solve; anything else is an edit, not a mesh.
    match &doc["mesh"] {
        Value::Null => {}
        Value::Object(_) => {
            return Err(bad(
                &path,
                "an adaptive-mesh solve: the heat source is computed on uniform grids only",
            ))
        }
        other => {
            return Err(bad(
                &path,
                &format!(
                "`mesh` = {other} is neither null (a uniform grid) nor an adaptive mesh's report"
            ),
            ))
        }
    }
    let size = doc["grid"]
        .as_array()
        .filter(|g| g.len() == 2)
        .and_then(|g| Some((g[0].as_u64()? as usize, g[1].as_u64()? as usize)))
        .ok_or_else(|| bad(&path, "needs `grid`: [nx, ny]"))?;
    let ax = number(&doc, "cell_size", &path)?;
    // Absent (or null) in a summary of square cells; anything else that is
    // not a number is not taken for them.
    let ay = match &doc["cell_size_y"] {
        Value::Null => ax,
        v => v.as_f64().ok_or_else(|| {
            bad(
                &path,
                &format!("`cell_size_y` = {v} is not a number (m; absent for square cells)"),
            )
        })?,
    };
    let grid = Grid::new(size.0, size.1, (ax, ay))?;
    let grid = match doc["formulation"].as_str() {
        Some("periodic") => grid.periodic(),
        Some("non_periodic") => grid,
        _ => return Err(bad(&path, "needs `formulation`: periodic or non_periodic")),
    };
    let m = &doc["material"];
    let terms = m["creep_spectrum"]
        .as_array()
        .and_then(|t| {
            t.iter()
                .map(|p| {
                    Some(CreepTerm {
                        compliance: p.get(0)?.as_f64()?,
                        time: p.get(1)?.as_f64()?,
                    })
                })
                .collect::<Option<Vec<_>>>()
        })
        .ok_or_else(|| bad(&path, "needs `material.creep_spectrum`: [[C, tau], ...]"))?;
    let spectrum = CreepSpectrum::new(number(m, "glassy_modulus", &path)?, terms)?;
    let material = Material::new(spectrum, number(m, "poisson", &path)?)?;
    let layer = match &doc["config"]["layer"] {
        Value::Null => None,
        v => Some(
            serde_json::from_value::<LayerConfig>(v.clone())
                .map_err(|e| bad(&path, &format!("config.layer: {e}")))?
                .build()?,
        ),
    };
    let direction_deg = number(&doc, "direction_deg", &path)?;
    let response = SlidingResponse::new(
        &material,
        number(&doc, "speed", &path)?,
        crate::response::direction_rad(direction_deg),
        layer,
    )?;
    Ok(Run {
        grid,
        response,
        direction_deg,
        mu: (
            number(&doc, "friction_coefficient", &path)?,
            number(&doc, "friction_coefficient_dissipation", &path)?,
        ),
        normal_load: number(&doc, "normal_load", &path)?,
    })
}

pub(super) fn run(args: &HeatArgs, dir: &Path) -> Result<()> {
    let run = read_run(dir)?;
    let (nx, ny) = run.grid.size();
    let (px, py, pressure) = npy::read_2d(dir.join("pressure.npy"))?;
    if (px, py) != (nx, ny) {
        return Err(Error::Invalid(format!(
            "{}: the pressure is {px} x {py}, the run's grid {nx} x {ny}",
            dir.join("pressure.npy").display()
        )));
    }
    let periodic = run.grid.is_periodic();
    if args.block_length.is_some() && !periodic {
        return Err(Error::Invalid(
            "--block-length is for a periodic cell; this run is a pad, whose steady rise needs none"
                .into(),
        ));
    }
    let layered = run.response.layer().is_some();
    let kind = args
        .source
        .unwrap_or(SourceKind::default_for(periodic, layered));
    if let Some(why) = kind.unsupported(periodic, layered) {
        return Err(Error::Invalid(format!(
            "--source {}: {why}; give --source surface (the default on a pad or a layer)",
            kind.name()
        )));
    }
    if args.refined_layers && kind == SourceKind::Surface {
        return Err(Error::Invalid(
            "--refined-layers refines the volume source's depth layers; the surface source has none: drop it or give --source volume (periodic runs)".into(),
        ));
    }
    let rule = if args.refined_layers {
        DepthRule::refined()
    } else {
        DepthRule::default()
    };
    let mu = match kind {
        SourceKind::Volume => run.mu.1,
        SourceKind::Surface => run.mu.0,
    };
    let speed = run.response.speed();
    let conduction = Conduction {
        conductivity: args.conductivity,
        diffusivity: args.diffusivity,
    };
    let t0 = Instant::now();
    // Seconds to minutes for a volume source on the largest grids.
    let spinner = super::spinner::Spinner::start(format!(
        "the {} heat source of {nx} x {ny} cells and its rise",
        kind.name()
    ));
    let heat = ContactHeating::new(
        &pressure,
        &run.grid,
        &run.response,
        conduction,
        args.block_length,
        kind,
        &rule,
        mu * run.normal_load * speed,
        &mut || false,
    );
    spinner.bar.finish_and_clear();
    let heat = heat?;
    let wall = t0.elapsed().as_secs_f64();
    let setup = HeatSetup {
        grid: run.grid,
        conduction,
        speed,
        direction_rad: run.response.direction_rad(),
        domain: if periodic {
            HeatDomain::Periodic {
                block_length: args.block_length,
            }
        } else {
            HeatDomain::Pad
        },
    };
    let mut doc = heat.report();
    let extra = json!({
        "version": crate::version::VERSION,
        "run": dir.display().to_string(),
        "grid": [nx, ny],
        "cell_size_m": [run.grid.cell().0, run.grid.cell().1],
        "speed_m_per_s": speed,
        "direction_deg": run.direction_deg,
        "conductivity_w_per_m_k": args.conductivity,
        "diffusivity_m2_per_s": args.diffusivity,
        "formulation": if periodic { "periodic" } else { "non-periodic" },
        "block_length_m": args.block_length,
        "contact_time_s": setup.contact_time(),
        "total_power_w": heat.heat_power_w,
        "mean_flux_w_per_m2": heat.heat_power_w / (run.grid.cells() as f64 * run.grid.cell_area()),
        "peclet_number": setup.peclet(),
        "peclet_definition": "v a / kappa, a a cell's length along the sliding direction (its chord through the centre along e_v)",
        "friction_route": match kind {
            SourceKind::Volume => "dissipation (Appendix A3-A4)",
            SourceKind::Surface => "stencil (paper Eq. 9)",
        },
        "depth_rule": matches!(kind, SourceKind::Volume).then(|| json!({
            "first_fraction_of_cell": rule.first_fraction,
            "ratio": rule.ratio,
            "gauss_points": rule.points,
            "depth_periods": rule.depth_periods,
        })),
        "wall_time_s": wall,
        "files": HEAT_FILES,
        "conventions": {
            "temperature": "surface rise T - T0 [K] at the cell centres, axis 0 = x",
            "effective_rise_k": "Int theta Q dV / Int Q dV: the rise where the heat is released",
            "energy_balance": "heat_total_w / friction_power_w - 1",
            "model": "physics.md section 14: steady moving heat source on a half-space; the source from the solved contact",
        },
    });
    if let (Value::Object(d), Value::Object(e)) = (&mut doc, extra) {
        d.extend(e);
    }
    let out = write(
        &args.out,
        &setup,
        run.direction_deg,
        &heat.temperature,
        &doc,
    )?;
    for n in &heat.notes {
        eprintln!("note: {n}");
    }
    println!(
        "heat ({} source): {nx} x {ny} cells, max rise {:.4e} K, effective {:.4e} K, heat {:.6e} W vs mu F_N v {:.6e} W ({:+.2e}), {:.3} s: {}",
        kind.name(),
        heat.temperature.max(),
        heat.effective_rise,
        heat.heat_power_w,
        heat.friction_power_w,
        heat.balance(),
        wall,
        out.display()
    );
    Ok(())
}
