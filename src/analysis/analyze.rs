//! The contact analysis of one solved map: deformed-surface anisotropy
//! (Eq. 11-13), contact-area anisotropy from `C_chi` (Fig. 10), contact-spot
//! statistics, and the figures of Section IV (Fig. 8-10) plus pressure and
//! displacement maps (physics.md section 5).
//!
//! [`analyze_fields`] works on in-memory fields (the solve calls it);
//! [`write_analysis`] adds `analysis.json` and the figures to a staged
//! output; [`analyze_dir`] does both for the files of a finished solve.

use std::path::{Path, PathBuf};

use serde::Serialize;
use serde_json::Value;

use super::anisotropy::{deformed_anisotropy, AnisotropyTensor, ZetaBand};
use super::chi::{chi_spectrum, contour_level, ChiLevel};
use super::figures;
use super::spots::{find_spots, statistics_of, Connectivity, SpotStatistics};
use crate::io::npy::{self, NpyError};
use crate::io::StagedOutput;
use crate::plot::PlotError;
use crate::surface::{psd_2d, HeightMap, SurfaceError, Window};

/// Errors of the contact analysis; each message is one line and names what
/// to fix.
#[derive(Debug, thiserror::Error)]
pub enum AnalysisError {
    /// A required input file is absent.
    #[error("{path}: missing ({why})")]
    Missing { path: String, why: String },
    /// A field whose length or shape disagrees with the grid.
    #[error("{name}: shape {found:?} disagrees with the grid {expected:?}")]
    Shape {
        name: String,
        found: [usize; 2],
        expected: [usize; 2],
    },
    /// `summary.json` unreadable or lacking a key.
    #[error("{path}: {what}")]
    Summary { path: String, what: String },
    /// A parameter outside its range.
    #[error("analysis parameter `{name}` = {value}: {why}")]
    Parameter {
        name: &'static str,
        value: String,
        why: String,
    },
    /// A non-finite displacement (or a grid that cannot hold a map).
    #[error(transparent)]
    Surface(#[from] SurfaceError),
    #[error(transparent)]
    Npy(#[from] NpyError),
    #[error(transparent)]
    Plot(#[from] PlotError),
    /// Writing the outputs failed.
    #[error(transparent)]
    Output(#[from] crate::Error),
}

impl From<AnalysisError> for crate::Error {
    fn from(e: AnalysisError) -> Self {
        match e {
            AnalysisError::Surface(e) => crate::Error::Surface(e),
            AnalysisError::Npy(e) => crate::Error::Npy(e),
            AnalysisError::Plot(e) => crate::Error::Plot(e),
            AnalysisError::Output(e) => e,
            other => crate::Error::Invalid(other.to_string()),
        }
    }
}

fn param(name: &'static str, value: impl ToString, why: &str) -> AnalysisError {
    AnalysisError::Parameter {
        name,
        value: value.to_string(),
        why: why.into(),
    }
}

/// Parameters of [`analyze_fields`].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct AnalysisParams {
    /// Lower band factor `zeta1` of Eq. 11 (`|q| >= zeta1 q0`); the paper
    /// uses 1.
    pub zeta1: f64,
    /// Upper band factor `zeta2` (`|q| <= zeta2 q0`); `None`: the number of
    /// scales of the surface (`q1 / q0`, the paper's `N`), else `n/2`
    /// (the Nyquist wavenumber of the shorter side).
    pub zeta2: Option<f64>,
    /// Levels of `C_chi(q) / C_chi(0)` at which contours are fitted; the
    /// first one that gives an ellipse provides `lambda`.
    pub chi_levels: Vec<f64>,
    /// Taper of the displacement before its PSD. The deformed surface of a
    /// non-periodic solve is not periodic; its edge jumps leak power along
    /// the `q_x` and `q_y` axes and bias `M` towards the axes, so the default
    /// is [`Window::Hann`]. Use [`Window::None`] for periodic fields.
    pub window: Window,
    /// Window radius `r_c` of the `C_chi` estimator \[cells\]; `None`: from
    /// the spot sizes (see [`super::chi`]).
    pub chi_window_cells: Option<f64>,
    /// Rays over a half turn along which contours are sampled.
    pub rays: usize,
}

impl Default for AnalysisParams {
    fn default() -> Self {
        Self {
            zeta1: 1.0,
            zeta2: None,
            chi_levels: vec![0.5, 0.3],
            window: Window::Hann,
            chi_window_cells: None,
            rays: 180,
        }
    }
}

/// The fields of one solve, borrowed: `(nx, ny)` maps in C order with axis 0
/// = x = the sliding direction.
#[derive(Debug, Clone, Copy)]
pub struct AnalysisInputs<'a> {
    pub nx: usize,
    pub ny: usize,
    /// Side of a square cell \[m\].
    pub cell_size: f64,
    /// Surface displacement `u` of the solid \[m\].
    pub displacement: &'a [f64],
    /// 1 in contact, 0 elsewhere.
    pub contact: &'a [f64],
    /// Contact pressure \[Pa\].
    pub pressure: &'a [f64],
    /// Number of scales `N = q1 / q0` of the rough surface, when known.
    pub scales: Option<f64>,
    /// Dimensionless speed `xi`, when known (figure titles only).
    pub xi: Option<f64>,
}

/// Contact-area anisotropy from `C_chi` (Fig. 10).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ChiReport {
    /// Window radius `r_c` of the estimator \[cells\].
    pub window_radius_cells: f64,
    /// Flat part of the window \[cells\].
    pub flat_radius_cells: f64,
    /// Background subtracted from the autocorrelation \[cells\].
    pub background_cells: f64,
    /// `C_chi(0)` [m^4].
    pub c0: f64,
    /// `q0 = 2 pi / Lx` [1/m]: the unit of the contour coordinates.
    pub q0: f64,
    /// One entry per requested level.
    pub levels: Vec<ChiLevel>,
}

/// Everything [`analyze_fields`] finds; serialised as `analysis.json`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct AnalysisReport {
    /// `m20 = <u_x^2>` of the band-filtered displacement (Eq. 11).
    pub m20: f64,
    /// `m02 = <u_y^2>`.
    pub m02: f64,
    /// `m11 = <u_x u_y>`.
    pub m11: f64,
    /// Degree of isotropy `gamma = m2_min / m2_max` (Eq. 11).
    pub gamma: f64,
    /// Direction maximising `m2(theta)` (Eq. 13) [degrees, (-90, 90]] from
    /// the sliding direction +x.
    pub theta_p_deg: f64,
    /// The Eq. 11 tensor with its eigenvalues.
    pub tensor: AnisotropyTensor,
    /// The normalised tensor of Eq. 12.
    pub tensor_normalised: AnisotropyTensor,
    /// The band of Eq. 11.
    pub band: ZetaBand,
    /// `<u^2>` of the filtered displacement [m^2].
    pub filtered_mean_square: f64,
    /// Taper used before the PSD of `u`.
    pub window: Window,
    /// `minor / major` axis of the first fitted `C_chi` contour ellipse.
    pub lambda: Option<f64>,
    /// Major-axis direction of that ellipse [degrees, (-90, 90]] from +q_x.
    pub ellipse_angle_deg: Option<f64>,
    /// Level that gave `lambda`.
    pub lambda_level: Option<f64>,
    /// `C_chi` contours and ellipses; `None` without contact.
    pub chi: Option<ChiReport>,
    /// Contact-spot statistics.
    pub spots: SpotStatistics,
    /// Cells in contact / all cells.
    pub contact_area_fraction: f64,
    /// The parameters used.
    pub params: AnalysisParams,
    pub version: &'static str,
}

fn check_inputs(inp: &AnalysisInputs<'_>) -> Result<(), AnalysisError> {
    let n = inp.nx * inp.ny;
    for (name, f) in [
        ("displacement", inp.displacement),
        ("contact", inp.contact),
        ("pressure", inp.pressure),
    ] {
        if f.len() != n {
            return Err(AnalysisError::Shape {
                name: name.into(),
                found: [f.len(), 1],
                expected: [inp.nx, inp.ny],
            });
        }
    }
    if !(inp.cell_size.is_finite() && inp.cell_size > 0.0) {
        return Err(param(
            "cell_size",
            inp.cell_size,
            "must be a length > 0 (m)",
        ));
    }
    Ok(())
}

fn check_params(p: &AnalysisParams) -> Result<(), AnalysisError> {
    if !(p.zeta1.is_finite() && p.zeta1 >= 0.0) {
        return Err(param("zeta1", p.zeta1, "must be finite and >= 0"));
    }
    if let Some(z2) = p.zeta2 {
        if !(z2.is_finite() && z2 > p.zeta1) {
            return Err(param("zeta2", z2, "must be finite and exceed zeta1"));
        }
    }
    if p.chi_levels.is_empty() {
        return Err(param("levels", "[]", "give at least one level in (0, 1)"));
    }
    for &l in &p.chi_levels {
        if !(l > 0.0 && l < 1.0) {
            return Err(param("levels", l, "levels of C_chi/C_chi(0) lie in (0, 1)"));
        }
    }
    if let Some(r) = p.chi_window_cells {
        if !(r.is_finite() && r >= 2.0) {
            return Err(param("chi_window_cells", r, "must be at least 2 cells"));
        }
    }
    if p.rays < 3 {
        return Err(param("rays", p.rays, "need at least 3 rays"));
    }
    Ok(())
}

/// Analyse one solved contact (physics.md section 5; paper Section IV).
///
/// 1. Eq. 11-13 on the displacement, band `zeta1 q0 <= |q| <= zeta2 q0`
///    (see [`super::anisotropy`]).
/// 2. `C_chi` contours and centred least-squares ellipses (see [`super::chi`]).
/// 3. Spots under 4-connectivity (see [`super::spots`]).
pub fn analyze_fields(
    inputs: &AnalysisInputs<'_>,
    params: &AnalysisParams,
) -> Result<AnalysisReport, AnalysisError> {
    check_inputs(inputs)?;
    check_params(params)?;
    let (nx, ny, a) = (inputs.nx, inputs.ny, inputs.cell_size);
    let map = HeightMap::new(nx, ny, nx as f64 * a, inputs.displacement.to_vec())?;
    let psd = psd_2d(&map, params.window)?;
    let zeta2 = match (params.zeta2, inputs.scales) {
        (Some(z), _) => z,
        (None, Some(s)) if s.is_finite() && s > params.zeta1 => s,
        _ => (nx.min(ny) / 2) as f64,
    };
    if zeta2 <= params.zeta1 {
        return Err(param("zeta2", zeta2, "must exceed zeta1"));
    }
    let def = deformed_anisotropy(&psd, params.zeta1, zeta2);

    let spots = find_spots(inputs.contact, nx, ny, Connectivity::Four);
    let count_8 = find_spots(inputs.contact, nx, ny, Connectivity::Eight).len();
    let spot_stats = statistics_of(&spots, count_8, a);
    let contact_cells = inputs.contact.iter().filter(|&&c| c > 0.5).count();

    let chi = if contact_cells == 0 {
        None
    } else {
        let radius = params.chi_window_cells.unwrap_or_else(|| {
            let (mut sw, mut sv) = (0.0, 0.0);
            for s in &spots {
                let w = s.cells as f64;
                sw += w;
                sv += w * s.major_variance();
            }
            1.5 * (4.0 * (sv / sw).sqrt()).max(2.0)
        });
        let spec = chi_spectrum(inputs.contact, nx, ny, a, radius);
        let levels: Vec<ChiLevel> = params
            .chi_levels
            .iter()
            .map(|&l| contour_level(&spec, l, params.rays))
            .collect();
        Some(ChiReport {
            window_radius_cells: spec.window_radius_cells,
            flat_radius_cells: spec.flat_radius_cells,
            background_cells: spec.background_cells,
            c0: spec.c0,
            q0: spec.dqx,
            levels,
        })
    };
    let first = chi
        .as_ref()
        .and_then(|c| c.levels.iter().find(|l| l.ellipse.is_some()));
    let t = def.tensor;
    Ok(AnalysisReport {
        m20: t.m20,
        m02: t.m02,
        m11: t.m11,
        gamma: t.gamma,
        theta_p_deg: t.theta_p_deg,
        tensor: t,
        tensor_normalised: def.normalised,
        band: def.band,
        filtered_mean_square: def.mean_square,
        window: params.window,
        lambda: first.and_then(|l| l.ellipse.map(|e| e.lambda)),
        ellipse_angle_deg: first.and_then(|l| l.ellipse.map(|e| e.angle_deg)),
        lambda_level: first.map(|l| l.level),
        chi,
        spots: spot_stats,
        contact_area_fraction: contact_cells as f64 / (nx * ny) as f64,
        params: params.clone(),
        version: crate::VERSION,
    })
}

/// Names of the files [`write_analysis`] adds.
pub const ANALYSIS_FILES: [&str; 7] = [
    "analysis.json",
    "analysis_contact.png",
    "analysis_m2_polar.png",
    "analysis_chi_contours.png",
    "analysis_pressure.png",
    "analysis_displacement.png",
    "analysis_spot_areas.png",
];

/// Add `analysis.json` and the figures ([`ANALYSIS_FILES`]) to `staged`.
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
    /// `q1 / q0` of a generated surface, if the config says.
    pub scales: Option<f64>,
    pub xi: Option<f64>,
}

/// Read the grid, cell size and number of scales from a solve's
/// `summary.json`: `grid`, `cell_size`, `xi` and, for generated surfaces,
/// `config.surface.generate` (`scales` with `ql`, or `q1`; `q0 = 2 pi / L`).
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
    let lx = grid[0] as f64 * cell_size;
    let q0 = 2.0 * std::f64::consts::PI / lx;
    let scales = scales_from_config(&doc["config"], q0);
    Ok(SolveSummary {
        nx: grid[0],
        ny: grid[1],
        cell_size,
        scales,
        xi: doc["xi"].as_f64(),
    })
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
/// figures ([`ANALYSIS_FILES`]) there, all or nothing. Every input is read
/// and checked before anything is written.
pub fn analyze_dir(dir: &Path, params: &AnalysisParams) -> Result<AnalysisReport, AnalysisError> {
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
        displacement: &displacement,
        contact: &contact,
        pressure: &pressure,
        scales: summary.scales,
        xi: summary.xi,
    };
    let report = analyze_fields(&inputs, params)?;
    let mut staged = StagedOutput::new(dir)?;
    write_analysis(&mut staged, &inputs, &report)?;
    staged.commit()?;
    Ok(report)
}
