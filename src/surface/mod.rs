//! Rigid rough surfaces: height maps, self-affine generation, PSD and
//! statistics, file input (physics.md section 8).
//!
//! Heights are stored in C order with axis 0 = x, the sliding direction:
//! `heights[i * ny + j]` is the height at the centre of cell `(i, j)`.

mod config;

pub use config::SurfaceConfig;

/// Errors reading, generating or validating a surface.
#[derive(Debug, thiserror::Error)]
pub enum SurfaceError {
    #[error("{0}")]
    Invalid(String),
}

/// A height map on a uniform grid of square cells.
#[derive(Debug, Clone, PartialEq)]
pub struct HeightMap {
    /// Cells along x (axis 0, sliding direction).
    pub nx: usize,
    /// Cells along y (axis 1).
    pub ny: usize,
    /// Side of one square cell [m].
    pub cell_size: f64,
    /// Heights [m], `heights[i * ny + j]`.
    pub heights: Vec<f64>,
}

impl HeightMap {
    /// Side of the map along x [m].
    pub fn length_x(&self) -> f64 {
        self.nx as f64 * self.cell_size
    }
    /// Side of the map along y [m].
    pub fn length_y(&self) -> f64 {
        self.ny as f64 * self.cell_size
    }
}
