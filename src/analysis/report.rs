//! The data of the contact analysis: its parameters, the borrowed fields it
//! reads, the report it produces and its errors. Plain types, shared by the
//! analysis ([`super::fields`]), its figures ([`super::figures`]) and its
//! files ([`super::files`]).

use serde::Serialize;

use super::anisotropy::{AnisotropyTensor, ZetaBand};
use super::chi::ChiLevel;
use super::spots::SpotStatistics;
use crate::config::AnalysisConfig;
use crate::io::npy::NpyError;
use crate::io::OutputError;
use crate::plot::PlotError;
use crate::surface::{SurfaceError, Window};

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
    /// A grid whose default band (`zeta1 <= |q|/q0 <= min(nx, ny) / 2`)
    /// is empty: fewer than `min` cells along a side.
    #[error("a {nx} x {ny} grid is too small for the anisotropy analysis run after the solve: its band zeta1 = {zeta1} <= |q|/q0 <= min(nx, ny) / 2 needs at least {min} cells per side; give a larger map, a zeta2 above zeta1 ([analysis] zeta2), or [analysis] enabled = false")]
    SmallGrid {
        nx: usize,
        ny: usize,
        zeta1: f64,
        min: usize,
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
    Output(#[from] OutputError),
}

pub(super) fn param(name: &'static str, value: impl ToString, why: &str) -> AnalysisError {
    AnalysisError::Parameter {
        name,
        value: value.to_string(),
        why: why.into(),
    }
}

/// Parameters of [`super::analyze`].
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

impl AnalysisParams {
    /// The analysis a solve's `[analysis]` section asks for (its band and
    /// levels, the defaults where it is silent), with the taper of its
    /// formulation: none for a `periodic` solve, whose fields are one
    /// period, Hann otherwise. `enabled` is not read here.
    pub fn configured(cfg: &AnalysisConfig, periodic: bool) -> Self {
        let defaults = Self::default();
        Self {
            zeta1: cfg.zeta1.unwrap_or(defaults.zeta1),
            zeta2: cfg.zeta2,
            chi_levels: cfg
                .chi_levels
                .clone()
                .unwrap_or(defaults.chi_levels.clone()),
            window: if periodic {
                Window::None
            } else {
                defaults.window
            },
            ..defaults
        }
    }
}

/// The fields of one solve, borrowed: `(nx, ny)` maps in C order with axis 0
/// = x = the sliding direction.
#[derive(Debug, Clone, Copy)]
pub struct AnalysisInputs<'a> {
    pub nx: usize,
    pub ny: usize,
    /// Side of a cell along x \[m\].
    pub cell_size: f64,
    /// Side of a cell along y \[m\] (equal to `cell_size` for square cells).
    pub cell_size_y: f64,
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

/// Everything [`super::analyze`] finds; serialised as `analysis.json`.
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
    /// Settings or fields under which a number above may mislead, one line
    /// each: a band reaching beyond the grid's Nyquist wavenumber, a band
    /// that samples directions unevenly on an elongated map
    /// ([`ZetaBand::grid_gamma`]), a taper asked for against the solve's
    /// formulation, a `C_chi` window asked beyond the largest the map
    /// allows, a contact that covers most of the map.
    pub warnings: Vec<String>,
    pub version: &'static str,
}

/// Names of the files [`super::write_analysis`] adds.
pub const ANALYSIS_FILES: [&str; 7] = [
    "analysis.json",
    "analysis_contact.png",
    "analysis_m2_polar.png",
    "analysis_chi_contours.png",
    "analysis_pressure.png",
    "analysis_displacement.png",
    "analysis_spot_areas.png",
];
