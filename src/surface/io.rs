//! Height-map files: NumPy `.npy` (float64 or float32, C or Fortran order;
//! axis 0 = x) and plain-text matrices (one row per x index, numbers separated
//! by whitespace or commas, `#` starts a comment). Every loaded map is
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

/// Parse a plain-text matrix: rows of numbers separated by whitespace and/or
/// commas; `#` starts a comment; blank lines are skipped. Row `i` is the x
/// index. `name` is used in error messages.
pub fn parse_text(text: &str, name: &str, length: f64) -> Result<HeightMap, SurfaceError> {
    let (shape, heights) = text_matrix(text, name)?;
    build(name, shape, heights, length)
}

/// The rows of numbers of a plain-text matrix (see [`parse_text`]): its
/// shape `[rows, columns]` and the values in row order, not yet validated.
pub(super) fn text_matrix(text: &str, name: &str) -> Result<(Vec<usize>, Vec<f64>), SurfaceError> {
    let mut heights = Vec::new();
    let mut ncols: Option<usize> = None;
    let mut nrows = 0;
    for (lineno, raw) in text.lines().enumerate() {
        let line = raw.split('#').next().unwrap_or("");
        let tokens: Vec<&str> = line
            .split(|c: char| c == ',' || c.is_whitespace())
            .filter(|t| !t.is_empty())
            .collect();
        if tokens.is_empty() {
            continue;
        }
        match ncols {
            None => ncols = Some(tokens.len()),
            Some(n) if n != tokens.len() => {
                return Err(SurfaceError::Ragged {
                    path: name.to_string(),
                    line: lineno + 1,
                    expected: n,
                    found: tokens.len(),
                })
            }
            _ => {}
        }
        for t in tokens {
            let v: f64 = t.parse().map_err(|_| SurfaceError::TextNumber {
                path: name.to_string(),
                line: lineno + 1,
                token: t.to_string(),
            })?;
            heights.push(v);
        }
        nrows += 1;
    }
    Ok((vec![nrows, ncols.unwrap_or(0)], heights))
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
