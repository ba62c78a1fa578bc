//! The contact analysis on disk: [`write_analysis`] adds `analysis.json`
//! and the figures (paper Fig. 8-10, pressure and displacement maps) to a
//! staged output; [`analyze_dir`] analyses the files of a finished solve.

use std::path::{Path, PathBuf};

use serde_json::Value;

use super::fields::{analyze, check_inputs};
use super::figures;
use super::report::{AnalysisError, AnalysisInputs, AnalysisParams, AnalysisReport};
use crate::config::{AnalysisConfig, Formulation};
use crate::io::npy;
use crate::io::StagedOutput;
use crate::surface::Window;

/// Add `analysis.json` and the figures ([`super::ANALYSIS_FILES`]) to `staged`.
pub fn write_analysis(
    staged: &mut StagedOutput,
    inputs: &AnalysisInputs<'_>,
    report: &AnalysisReport,
) -> Result<(), AnalysisError> {
    check_inputs(inputs)?;
    let json = serde_json::to_string_pretty(report).map_err(|e| AnalysisError::Summary {
        path: "analysis.json".into(),
        what: e.to_string(),
    })?;
    staged.write("analysis.json", json.as_bytes())?;
    figures::contact_map(&staged.path("analysis_contact.png"), inputs, report)?;
    figures::m2_polar(&staged.path("analysis_m2_polar.png"), inputs, report)?;
    figures::chi_contours(&staged.path("analysis_chi_contours.png"), inputs, report)?;
    figures::field_map(
        &staged.path("analysis_pressure.png"),
        inputs,
        "Contact pressure",
        inputs.pressure,
        "p [Pa]",
    )?;
    figures::field_map(
        &staged.path("analysis_displacement.png"),
        inputs,
        "Surface displacement u",
        inputs.displacement,
        "u [m]",
    )?;
    figures::spot_areas(&staged.path("analysis_spot_areas.png"), report)?;
    Ok(())
}

/// Number of scales `N = q1 / q0` of a generated surface from a solve's
/// configuration (as JSON): `scales` (with `ql` when set) or `q1`;
/// `None` for a surface read from a file.
pub fn scales_from_config(config: &serde_json::Value, q0: f64) -> Option<f64> {
    let g = &config["surface"]["generate"];
    let ql = g["ql"].as_f64().unwrap_or(q0);
    match (g["scales"].as_f64(), g["q1"].as_f64()) {
        (Some(n), _) => Some(n * ql / q0),
        (None, Some(q1)) => Some(q1 / q0),
        _ => None,
    }
}

/// What [`analyze_dir`] reads from `summary.json`.
#[derive(Debug, Clone, PartialEq)]
pub struct SolveSummary {
    pub nx: usize,
    pub ny: usize,
    pub cell_size: f64,
    /// Cell side along y \[m\]: `cell_size_y` of the summary, `cell_size`
    /// where it is absent (square cells).
    pub cell_size_y: f64,
    /// `q1 / q0` of a generated surface, if the config says.
    pub scales: Option<f64>,
    pub xi: Option<f64>,
    /// The solve's formulation: `formulation` of the summary, else
    /// `config.solver.formulation`; `None` where neither says.
    pub formulation: Option<Formulation>,
    /// The solve's `[analysis]` section (`config.analysis`; empty where
    /// absent).
    pub analysis: AnalysisConfig,
}

/// What `analyze DIR` asks for beyond the solve's own analysis: each
/// `None` takes the solve's setting ([`SolveSummary::analysis_params`]),
/// so that no setting reproduces its `analysis.json`.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct AnalysisOverrides {
    pub zeta1: Option<f64>,
    pub zeta2: Option<f64>,
    pub chi_levels: Option<Vec<f64>>,
    /// Radius of the `C_chi` estimator window \[cells\] (the solve's is
    /// always from the spot sizes).
    pub chi_window_cells: Option<f64>,
    /// The taper; one against the run's formulation is warned of.
    pub window: Option<Window>,
}

impl SolveSummary {
    /// The settings of the solve's own analysis: its `[analysis]` band and
    /// levels, and the taper of its formulation: none for a periodic solve,
    /// whose fields are one period; Hann otherwise (and where the summary
    /// does not name its formulation, as the solve's default is
    /// non-periodic).
    pub fn analysis_params(&self) -> AnalysisParams {
        AnalysisParams::configured(
            &self.analysis,
            self.formulation == Some(Formulation::Periodic),
        )
    }
}

/// Read the grid, cell size and number of scales from a solve's
/// `summary.json`: `grid`, `cell_size`, `xi`, `formulation` and, for
/// generated surfaces, `config.surface.generate` (`scales` with `ql`, or
/// `q1`; `q0 = 2 pi / L`).
pub fn read_summary(path: &Path) -> Result<SolveSummary, AnalysisError> {
    let p = path.display().to_string();
    let bytes = std::fs::read(path).map_err(|e| {
        if e.kind() == std::io::ErrorKind::NotFound {
            AnalysisError::Missing {
                path: p.clone(),
                why: "analyze needs the summary.json of a solve".into(),
            }
        } else {
            AnalysisError::Summary {
                path: p.clone(),
                what: e.to_string(),
            }
        }
    })?;
    let doc: Value = serde_json::from_slice(&bytes).map_err(|e| AnalysisError::Summary {
        path: p.clone(),
        what: format!("not valid JSON: {e}"),
    })?;
    let bad = |what: &str| AnalysisError::Summary {
        path: p.clone(),
        what: what.into(),
    };
    let grid = doc["grid"]
        .as_array()
        .filter(|g| g.len() == 2)
        .and_then(|g| Some([g[0].as_u64()? as usize, g[1].as_u64()? as usize]))
        .ok_or_else(|| bad("needs `grid`: [nx, ny]"))?;
    let cell_size = doc["cell_size"]
        .as_f64()
        .filter(|a| a.is_finite() && *a > 0.0)
        .ok_or_else(|| bad("needs `cell_size` > 0 (m)"))?;
    let cell_size_y = match &doc["cell_size_y"] {
        Value::Null => cell_size,
        v => v
            .as_f64()
            .filter(|a| a.is_finite() && *a > 0.0)
            .ok_or_else(|| bad("`cell_size_y` must be > 0 (m)"))?,
    };
    let lx = grid[0] as f64 * cell_size;
    let q0 = 2.0 * std::f64::consts::PI / lx;
    let scales = scales_from_config(&doc["config"], q0);
    let formulation = match (&doc["formulation"], &doc["config"]["solver"]["formulation"]) {
        (Value::Null, Value::Null) => None,
        (Value::Null, v) | (v, _) => Some(
            serde_json::from_value::<Formulation>(v.clone())
                .map_err(|_| bad("`formulation` must be \"periodic\" or \"non_periodic\""))?,
        ),
    };
    let analysis = match &doc["config"]["analysis"] {
        Value::Null => AnalysisConfig::default(),
        v => serde_json::from_value(v.clone()).map_err(|e| {
            bad(&format!(
                "`config.analysis` is not an [analysis] section: {e}"
            ))
        })?,
    };
    Ok(SolveSummary {
        analysis,
        nx: grid[0],
        ny: grid[1],
        cell_size,
        cell_size_y,
        scales,
        xi: doc["xi"].as_f64(),
        formulation,
    })
}

/// The warning for a taper `window` asked for against the run's
/// formulation, `None` where they agree (or the formulation is unknown).
fn window_warning(window: Window, formulation: Option<Formulation>) -> Option<String> {
    match (formulation?, window) {
        (Formulation::Periodic, Window::None) | (Formulation::NonPeriodic, Window::Hann | Window::BlackmanHarris) => None,
        (Formulation::Periodic, w) => Some(format!(
            "the solve is periodic (summary.json formulation), its fields are one period and need no taper: the {} window asked for reweights the map, so gamma and theta_P differ from the solve's own analysis (window none)",
            w.name()
        )),
        (Formulation::NonPeriodic, _) => Some(
            "the solve is non-periodic (summary.json formulation) and no taper was asked for: the displacement's edge jumps leak power along the q_x and q_y axes and bias gamma and theta_P towards the axes (the solve's own analysis uses the Hann window)".into(),
        ),
    }
}

fn read_field(dir: &Path, name: &str, nx: usize, ny: usize) -> Result<Vec<f64>, AnalysisError> {
    let path: PathBuf = dir.join(name);
    if !path.exists() {
        return Err(AnalysisError::Missing {
            path: path.display().to_string(),
            why: "analyze needs summary.json, displacement.npy, contact.npy and pressure.npy of a solve".into(),
        });
    }
    let (r, c, data) = npy::read_2d(&path)?;
    if (r, c) != (nx, ny) {
        return Err(AnalysisError::Shape {
            name: path.display().to_string(),
            found: [r, c],
            expected: [nx, ny],
        });
    }
    Ok(data)
}

/// Analyse the solve written in `dir` and write `analysis.json` and the
/// figures ([`super::ANALYSIS_FILES`]) there, all or nothing. Every input is read
/// and checked before anything is written.
///
/// The settings are the solve's own analysis ([`SolveSummary::analysis_params`]:
/// its `[analysis]` band and levels, the taper of its formulation) with
/// `overrides` in their place, so that none reproduces its `analysis.json`.
/// A taper asked for against the run's formulation is used and named in
/// the report's warnings.
pub fn analyze_dir(
    dir: &Path,
    overrides: &AnalysisOverrides,
) -> Result<AnalysisReport, AnalysisError> {
    if !dir.is_dir() {
        return Err(AnalysisError::Missing {
            path: dir.display().to_string(),
            why: "not a directory; give the output directory of a solve".into(),
        });
    }
    let summary = read_summary(&dir.join("summary.json"))?;
    let (nx, ny) = (summary.nx, summary.ny);
    let displacement = read_field(dir, "displacement.npy", nx, ny)?;
    let contact = read_field(dir, "contact.npy", nx, ny)?;
    let pressure = read_field(dir, "pressure.npy", nx, ny)?;
    let inputs = AnalysisInputs {
        nx,
        ny,
        cell_size: summary.cell_size,
        cell_size_y: summary.cell_size_y,
        displacement: &displacement,
        contact: &contact,
        pressure: &pressure,
        scales: summary.scales,
        xi: summary.xi,
    };
    let own = summary.analysis_params();
    let o = overrides;
    let params = AnalysisParams {
        zeta1: o.zeta1.unwrap_or(own.zeta1),
        zeta2: o.zeta2.or(own.zeta2),
        chi_levels: o.chi_levels.clone().unwrap_or(own.chi_levels),
        chi_window_cells: o.chi_window_cells.or(own.chi_window_cells),
        window: o.window.unwrap_or(own.window),
        ..own
    };
    let mut report = analyze(&inputs, &params)?;
    if let Some(w) = o
        .window
        .and_then(|w| window_warning(w, summary.formulation))
    {
        report.warnings.push(w);
    }
    let mut staged = StagedOutput::new(dir)?;
    write_analysis(&mut staged, &inputs, &report)?;
    staged.commit()?;
    Ok(report)
}
