//! Height-map files: NumPy `.npy` (float64 or float32, C or Fortran order;
//! axis 0 = x) and plain-text matrices ([`super::text`]: one row per x
//! index, or per y index under a size header; numbers separated by
//! whitespace or commas, `#` starts a comment). Every loaded map is
//! validated: 2-D, at least 2 x 2 cells, finite heights, side `length > 0`.

use std::path::Path;

use crate::io::npy;

use super::{HeightMap, SurfaceError};

/// Precision of a written `.npy` file.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum NpyPrecision {
    /// float64 (`<f8`), bit-exact.
    #[default]
    F64,
    /// float32 (`<f4`), heights rounded to the nearest f32.
    F32,
}

/// Check that every height is finite; the error names the first bad index
/// `[row, col]` (row = x index) of an array with `ny` columns.
pub(crate) fn validate_heights(name: &str, ny: usize, heights: &[f64]) -> Result<(), SurfaceError> {
    match heights.iter().position(|h| !h.is_finite()) {
        None => Ok(()),
        Some(k) => Err(SurfaceError::NonFinite {
            path: name.to_string(),
            row: k / ny.max(1),
            col: k % ny.max(1),
            value: heights[k],
        }),
    }
}

fn build(
    name: &str,
    shape: Vec<usize>,
    heights: Vec<f64>,
    length: f64,
) -> Result<HeightMap, SurfaceError> {
    if shape.len() != 2 || shape[0] < 2 || shape[1] < 2 {
        return Err(SurfaceError::Shape {
            path: name.to_string(),
            shape,
        });
    }
    if !(length.is_finite() && length > 0.0) {
        return Err(SurfaceError::param(
            "length",
            length,
            "the side of the map along x must be a finite length > 0 (m)",
        ));
    }
    let (nx, ny) = (shape[0], shape[1]);
    validate_heights(name, ny, &heights)?;
    Ok(HeightMap {
        nx,
        ny,
        cell_size: length / nx as f64,
        cell_size_y: length / nx as f64,
        heights,
    })
}

/// Read a `.npy` height map (2-D float64/float32) of side `length` \[m\] along x.
pub fn load_npy(path: &Path, length: f64) -> Result<HeightMap, SurfaceError> {
    let a = npy::read(path)?;
    build(&path.display().to_string(), a.shape, a.data, length)
}

/// Parse a plain-text matrix (see `surface/text.rs`): rows of numbers
/// separated by whitespace and/or commas, `#` starts a comment, blank lines
/// are skipped; row `i` is the x index, or, under a `# Width:`/`# Height:`
/// header (SurfaceTopography's `to_matrix`), row `j` the y index with the
/// sides and the height unit of the header. `length` \[m\] is the side
/// along x and must agree with the header's. `name` is used in error
/// messages.
pub fn parse_text(text: &str, name: &str, length: f64) -> Result<HeightMap, SurfaceError> {
    let m = super::text::text_matrix(text, name)?;
    if let Some(lx) = m.length_x {
        super::format::check_side(name, Some(length), lx, super::Axis::X)?;
    }
    let mut map = build(name, vec![m.nx, m.ny], m.heights, length)?;
    if let Some(ly) = m.length_y {
        map.cell_size_y = ly / m.ny as f64;
    }
    Ok(map)
}

/// Read a plain-text height map (see [`parse_text`]).
pub fn load_text(path: &Path, length: f64) -> Result<HeightMap, SurfaceError> {
    let text = std::fs::read_to_string(path).map_err(|source| SurfaceError::Io {
        path: path.display().to_string(),
        source,
    })?;
    parse_text(&text, &path.display().to_string(), length)
}

/// Read a height map: `.npy` by extension, anything else as a text matrix.
pub fn read_height_map(path: &Path, length: f64) -> Result<HeightMap, SurfaceError> {
    let is_npy = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("npy"));
    if is_npy {
        load_npy(path, length)
    } else {
        load_text(path, length)
    }
}

/// The `.npy` bytes of a height map, shape `(nx, ny)`, C order.
pub fn encode_npy(map: &HeightMap, precision: NpyPrecision) -> Vec<u8> {
    npy_bytes_of(map.nx, map.ny, &map.heights, precision)
}

/// The `.npy` bytes of `nx x ny` heights in C order.
pub(crate) fn npy_bytes_of(
    nx: usize,
    ny: usize,
    heights: &[f64],
    precision: NpyPrecision,
) -> Vec<u8> {
    let shape = [nx, ny];
    match precision {
        NpyPrecision::F64 => npy::encode_f64(&shape, heights),
        NpyPrecision::F32 => {
            let h: Vec<f32> = heights.iter().map(|&v| v as f32).collect();
            npy::encode_f32(&shape, &h)
        }
    }
}

/// Write a height map as `.npy` (atomically: temporary file, then rename).
pub fn save_npy(map: &HeightMap, path: &Path, precision: NpyPrecision) -> Result<(), SurfaceError> {
    crate::io::atomic::write_atomic(path, &encode_npy(map, precision)).map_err(|e| match e {
        crate::io::OutputError::Io { source, .. } => SurfaceError::Io {
            path: path.display().to_string(),
            source,
        },
        other => SurfaceError::Invalid(other.to_string()),
    })
}
