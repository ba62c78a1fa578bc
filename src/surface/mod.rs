//! Rigid rough surfaces: height maps, self-affine generation, PSD and
//! statistics, file input (physics.md section 8); measured topographies:
//! `.x3p`/`.gwy`/`.npy`/text files with physical sizes, missing data,
//! detrended and windowed PSDs, PSD stitching and surfaces synthesised
//! from a tabulated PSD (section 11).
//!
//! Heights are stored in C order with axis 0 = x, the sliding direction:
//! `heights[i * ny + j]` is the height at the centre of cell `(i, j)`.

mod config;
mod format;
mod generate;
mod gwy;
pub(crate) mod height_fft;
mod io;
mod length_unit;
mod measured;
mod preprocess;
mod psd;
mod psd_table;
mod resample;
mod stitch;
mod synth;
mod text;
mod topography;
mod x3p;

pub use crate::config::{AnisotropyConfig, GenerateConfig, SphereConfig, SurfaceConfig};
pub use format::{
    encode_topography, read_topography, write_topography, ReadOptions, SurfaceFormat, WriteOptions,
};
pub(crate) use generate::LENGTH_RANGE;
pub use generate::{
    anisotropy_warning, generate, generate_with_target, lattice_moments, Anisotropy,
    GenerateParams, Normalisation, SelfAffinePsd, UpperCutoff,
};
pub(crate) use generate::{lattice_slope_ratio, slope_ratio_warning};
pub use gwy::{decode_gwy, read_gwy};
pub(crate) use io::npy_bytes_of;
pub(crate) use io::validate_heights;
pub use io::{
    encode_npy, load_npy, load_text, parse_text, read_height_map, save_npy, NpyPrecision,
};
pub(crate) use measured::empty_band_reason;
pub use measured::{
    analyse, detrend, line_psd, psd_topography, trusted_band, Analysis, Axis, Detrend, LinePsd,
    MeasuredStats,
};
pub(crate) use preprocess::{edge_steps, filled_note, EdgeSteps};
pub use preprocess::{
    parse_detrend, parse_window, prepare, rms_slope_real, slope_warning, Preprocessing,
    SLOPE_TOLERANCE,
};
pub(crate) use psd::overflow;
pub use psd::{
    fit_hurst, psd_2d, radial_average, stats, stats_with_window, HurstFit, Psd2d, RadialPsd,
    SurfaceStats, Window,
};
pub use psd_table::{BelowTable, TabulatedPsd};
pub(crate) use resample::fourier_edge_warning;
pub use resample::{
    resample, resample_grid, ResampleGrid, ResampleMethod, ResampleTarget, MAX_RESAMPLE_CELLS,
};
pub use stitch::{stitch, ScanPsd, StitchedPsd};
pub use synth::{below_table_modes, generate_from_table, table_lattice_moments, SynthParams};
pub use topography::{MissingData, Topography};
pub use x3p::{decode_x3p, encode_x3p, read_x3p, X3pType};

use crate::io::npy::NpyError;

/// Errors reading, generating or validating a surface. Each message is one
/// line and says what to fix.
#[derive(Debug, thiserror::Error)]
pub enum SurfaceError {
    /// A configuration or argument that cannot be used as given.
    #[error("{0}")]
    Invalid(String),
    /// A generator or analysis parameter outside its range.
    #[error("surface parameter `{name}` = {value}: {why}")]
    Parameter {
        name: &'static str,
        value: String,
        why: String,
    },
    /// A height map whose shape cannot be used (not 2-D, or fewer than 2 x 2 cells).
    #[error(
        "{path}: height map must be a 2-D array of at least 2 x 2 cells, found shape {shape:?}"
    )]
    Shape { path: String, shape: Vec<usize> },
    /// A NaN or infinite height; `row` is the x index (axis 0), `col` the y index.
    #[error("{path}: non-finite height {value} at index [{row}, {col}] (first bad value; heights must be finite)")]
    NonFinite {
        path: String,
        row: usize,
        col: usize,
        value: f64,
    },
    /// A text matrix whose rows have different lengths.
    #[error("{path}: line {line}: ragged text matrix, row has {found} values but the first row has {expected}")]
    Ragged {
        path: String,
        line: usize,
        expected: usize,
        found: usize,
    },
    /// A token in a text matrix that is not a number.
    #[error("{path}: line {line}: cannot read '{token}' as a number")]
    TextNumber {
        path: String,
        line: usize,
        token: String,
    },
    /// A surface file (x3p, gwy) that cannot be decoded: corrupted,
    /// truncated, or using a feature that is not supported.
    #[error("{path}: {why}")]
    File { path: String, why: String },
    /// A `.npy` file that cannot be decoded.
    #[error(transparent)]
    Npy(#[from] NpyError),
    /// A file that cannot be read or written.
    #[error("{path}: {source}")]
    Io {
        path: String,
        #[source]
        source: std::io::Error,
    },
}

impl SurfaceError {
    pub(crate) fn param(name: &'static str, value: impl ToString, why: impl Into<String>) -> Self {
        SurfaceError::Parameter {
            name,
            value: value.to_string(),
            why: why.into(),
        }
    }
}

/// A height map on a uniform grid of `cell_size x cell_size_y` cells
/// (rectangular cells: physics.md section 11).
#[derive(Debug, Clone, PartialEq)]
pub struct HeightMap {
    /// Cells along x (axis 0, sliding direction).
    pub nx: usize,
    /// Cells along y (axis 1).
    pub ny: usize,
    /// Side of one cell along x \[m\].
    pub cell_size: f64,
    /// Side of one cell along y \[m\] (equal to `cell_size` for square cells).
    pub cell_size_y: f64,
    /// Heights \[m\], `heights[i * ny + j]`.
    pub heights: Vec<f64>,
}

/// Aspect ratio of a cell (longer side over shorter) beyond which results
/// get a warning: the longer direction is resolved that much worse
/// (physics.md section 11).
pub(crate) const CELL_ASPECT_WARNING: f64 = 4.0;

/// The warning for `ax x ay` cells whose aspect ratio exceeds
/// [`CELL_ASPECT_WARNING`], `None` otherwise.
pub(crate) fn cell_aspect_warning(ax: f64, ay: f64) -> Option<String> {
    let r = ax.max(ay) / ax.min(ay);
    (r > CELL_ASPECT_WARNING).then(|| {
        format!(
            "cells of {ax:.4e} m x {ay:.4e} m have an aspect ratio of {r:.2} (beyond \
             {CELL_ASPECT_WARNING}): the {} direction is resolved {r:.1} times worse than the \
             other; consider resampling the map to squarer cells",
            if ax > ay { "x" } else { "y" }
        )
    })
}

impl HeightMap {
    /// A validated height map: at least 2 x 2 cells, `heights.len() == nx * ny`,
    /// finite heights, `length_x > 0` (the side along x, m; cells are square).
    pub fn new(
        nx: usize,
        ny: usize,
        length_x: f64,
        heights: Vec<f64>,
    ) -> Result<Self, SurfaceError> {
        if !(length_x.is_finite() && length_x > 0.0) {
            return Err(SurfaceError::param(
                "length",
                length_x,
                "the side along x must be a finite length > 0 (m)",
            ));
        }
        if nx < 2 || ny < 2 || heights.len() != nx * ny {
            return Err(SurfaceError::Shape {
                path: "height map".into(),
                shape: vec![nx, ny],
            });
        }
        validate_heights("height map", ny, &heights)?;
        let a = length_x / nx as f64;
        Ok(Self {
            nx,
            ny,
            cell_size: a,
            cell_size_y: a,
            heights,
        })
    }

    /// A validated height map of `nx x ny` cells of side `dx` along x and
    /// `dy` along y \[m\] (both finite and > 0).
    pub fn with_cells(
        nx: usize,
        ny: usize,
        dx: f64,
        dy: f64,
        heights: Vec<f64>,
    ) -> Result<Self, SurfaceError> {
        if !(dy.is_finite() && dy > 0.0) {
            return Err(SurfaceError::param(
                "cell_size_y",
                dy,
                "the cell side along y must be a finite length > 0 (m)",
            ));
        }
        let mut map = Self::new(nx, ny, dx * nx as f64, heights)?;
        map.cell_size = dx;
        map.cell_size_y = dy;
        Ok(map)
    }

    /// Side of the map along x \[m\].
    pub fn length_x(&self) -> f64 {
        self.nx as f64 * self.cell_size
    }
    /// Side of the map along y \[m\].
    pub fn length_y(&self) -> f64 {
        self.ny as f64 * self.cell_size_y
    }
    /// Cell sides `(a_x, a_y)` \[m\].
    pub fn cell(&self) -> (f64, f64) {
        (self.cell_size, self.cell_size_y)
    }
    /// Area of one cell `a_x a_y` \[m^2\].
    pub fn cell_area(&self) -> f64 {
        self.cell_size * self.cell_size_y
    }
    /// Whether the cells are square (sides equal to 1e-9 relative).
    pub fn square_cells(&self) -> bool {
        ((self.cell_size - self.cell_size_y) / self.cell_size).abs() <= 1e-9
    }
    /// Height of cell `(i, j)` \[m\].
    pub fn at(&self, i: usize, j: usize) -> f64 {
        self.heights[i * self.ny + j]
    }
}
