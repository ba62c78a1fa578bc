//! Surface files of every supported format, chosen by extension with an
//! override: `.x3p` (ISO 25178-72, read/write), `.gwy` (Gwyddion, read),
//! `.npy` (read/write) and plain-text matrices (read/write, any other
//! extension). `.x3p` and `.gwy` carry their physical sizes; `.npy` and
//! text need the side along x (and optionally y) from the caller.

use std::path::Path;
use std::str::FromStr;

use serde::{Deserialize, Serialize};

use super::{npy_bytes_of, Axis, MissingData, NpyPrecision, SurfaceError, Topography, X3pType};
use crate::io::npy;

/// A surface file format.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SurfaceFormat {
    /// ISO 25178-72 XML 3D surface profile.
    X3p,
    /// Gwyddion native file (read only).
    Gwy,
    /// NumPy array, axis 0 = x.
    Npy,
    /// Text matrix, one row per x index.
    Text,
}

impl FromStr for SurfaceFormat {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s.to_ascii_lowercase().as_str() {
            "x3p" => Ok(Self::X3p),
            "gwy" => Ok(Self::Gwy),
            "npy" => Ok(Self::Npy),
            "text" | "txt" | "csv" | "asc" => Ok(Self::Text),
            _ => Err(format!(
                "unknown surface format '{s}' (use x3p, gwy, npy or text)"
            )),
        }
    }
}

impl SurfaceFormat {
    /// The format of `path` by its extension (case-insensitive); anything
    /// not `.x3p`, `.gwy` or `.npy` is text.
    pub fn from_path(path: &Path) -> Self {
        let ext = path
            .extension()
            .map(|e| e.to_string_lossy().to_ascii_lowercase())
            .unwrap_or_default();
        match ext.as_str() {
            "x3p" => Self::X3p,
            "gwy" => Self::Gwy,
            "npy" => Self::Npy,
            _ => Self::Text,
        }
    }

    /// Whether files of this format carry their physical size.
    pub fn has_size(self) -> bool {
        matches!(self, Self::X3p | Self::Gwy)
    }
}

/// How to read a surface file.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ReadOptions {
    /// Format; `None`: by extension.
    pub format: Option<SurfaceFormat>,
    /// Side along x \[m\]: required for `.npy` and text; for `.x3p`/`.gwy`
    /// it must agree with the file (to 1e-6).
    pub length: Option<f64>,
    /// Side along y \[m\]; default: square pixels.
    pub length_y: Option<f64>,
    /// What to do with missing points.
    pub missing: MissingData,
}

/// Read a surface file into a [`Topography`] (heights in metres, sizes,
/// missing points handled by `opts.missing`). Errors are one line and
/// name the file.
/// Instruments' formats this crate does not read, by extension.
const FOREIGN: &[(&str, &str)] = &[
    ("di", "a Bruker/Veeco Nanoscope (.di)"),
    ("opd", "a Wyko/Veeco Vision (.opd)"),
    ("datx", "a Zygo (.datx)"),
    ("sur", "a Digital Surf (.sur)"),
    ("plu", "a Sensofar (.plu)"),
    ("ibw", "an Igor binary wave (.ibw)"),
    ("mi", "an Agilent/Keysight (.mi)"),
    ("sdf", "a surface data (.sdf)"),
    ("spm", "a scanning probe (.spm)"),
];

/// The message for a file read as text that holds binary data: the
/// instrument format its extension names (if known) and how to read it.
fn not_text(path: &Path, name: &str) -> String {
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_lowercase())
        .unwrap_or_default();
    let what = FOREIGN
        .iter()
        .find(|(e, _)| *e == ext)
        .map_or("binary data, not a text matrix".to_string(), |(_, w)| {
            format!("{w} file, a format viscoslide does not read")
        });
    format!(
        "{name}: {what}; read it with SurfaceTopography in Python (`viscoslide.Surface.from_topography(SurfaceTopography.read_topography(path))`) or convert it to .x3p, .gwy, .npy or a text matrix"
    )
}

pub fn read_topography(path: &Path, opts: &ReadOptions) -> Result<Topography, SurfaceError> {
    let name = path.display().to_string();
    if opts.format.is_none() && has_extension(path, "xyz") {
        return Err(SurfaceError::Invalid(super::text::point_list_refusal(
            &name,
        )));
    }
    let format = opts
        .format
        .unwrap_or_else(|| SurfaceFormat::from_path(path));
    let mut topo = match format {
        SurfaceFormat::X3p => super::x3p::read_x3p(path)?,
        SurfaceFormat::Gwy => super::gwy::read_gwy(path)?,
        SurfaceFormat::Npy | SurfaceFormat::Text => {
            let (shape, data, sides) = if format == SurfaceFormat::Npy {
                let a = npy::read(path)?;
                (a.shape, a.data, (None, None))
            } else {
                let text = std::fs::read_to_string(path).map_err(|source| {
                    if source.kind() == std::io::ErrorKind::InvalidData {
                        SurfaceError::Invalid(not_text(path, &name))
                    } else {
                        SurfaceError::Io {
                            path: name.clone(),
                            source,
                        }
                    }
                })?;
                let m = super::text::text_matrix(&text, &name)?;
                (vec![m.nx, m.ny], m.heights, (m.length_x, m.length_y))
            };
            if shape.len() != 2 || shape[0] < 2 || shape[1] < 2 {
                return Err(SurfaceError::Shape { path: name, shape });
            }
            let lx = match sides.0 {
                Some(file) => {
                    check_side(&name, opts.length, file, Axis::X)?;
                    file
                }
                None => opts.length.ok_or_else(|| {
                    SurfaceError::Invalid(format!(
                        "{name}: a {format:?} file carries no physical size; give the side along x \
                         (--length, or `length` in [surface]), in m"
                    ))
                })?,
            };
            if !(lx.is_finite() && lx > 0.0) {
                return Err(SurfaceError::param(
                    "length",
                    lx,
                    "the side of the map along x must be a finite length > 0 (m)",
                ));
            }
            let (nx, ny) = (shape[0], shape[1]);
            let dx = lx / nx as f64;
            let dy = match (sides.1, opts.length_y) {
                (Some(file), given) => {
                    check_side(&name, given, file, Axis::Y)?;
                    file / ny as f64
                }
                (None, None) => dx,
                (None, Some(ly)) if ly.is_finite() && ly > 0.0 => ly / ny as f64,
                (None, Some(ly)) => {
                    return Err(SurfaceError::param(
                        "length_y",
                        ly,
                        "the side of the map along y must be a finite length > 0 (m)",
                    ))
                }
            };
            return finish(Topography::new(nx, ny, dx, dy, data, &name)?, opts, &name);
        }
    };
    check_side(&name, opts.length, topo.length_x(), Axis::X)?;
    check_side(&name, opts.length_y, topo.length_y(), Axis::Y)?;
    topo.filled = 0;
    finish(topo, opts, &name)
}

fn has_extension(path: &Path, ext: &str) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case(ext))
}

/// A side given (`--length`/`length` along x, `--length-y`/`length_y`
/// along y) must agree with the side the file states, to 1e-6; the error
/// names both and the option to drop.
pub(super) fn check_side(
    name: &str,
    given: Option<f64>,
    file: f64,
    axis: Axis,
) -> Result<(), SurfaceError> {
    let (what, option) = match axis {
        Axis::X => ("x", "`--length` (`length` in [surface])"),
        Axis::Y => ("y", "`--length-y` (`length_y` in [surface])"),
    };
    match given {
        Some(g) if ((g - file) / file).abs() > 1e-6 || g.is_nan() => Err(SurfaceError::Invalid(format!(
            "{name}: the file gives a side of {file:.6e} m along {what}, but {g:.6e} m was given; drop {option}"
        ))),
        _ => Ok(()),
    }
}

fn finish(
    mut topo: Topography,
    opts: &ReadOptions,
    name: &str,
) -> Result<Topography, SurfaceError> {
    topo.handle_missing(opts.missing, name)?;
    Ok(topo)
}

/// How to write a surface file.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct WriteOptions {
    /// Format; `None`: by extension.
    pub format: Option<SurfaceFormat>,
    /// z data type of an `.x3p`.
    pub x3p_type: X3pType,
    /// Precision of a `.npy`.
    pub npy_precision: NpyPrecision,
    /// Note for the file (x3p `Record2/Comment`, text header comment).
    pub comment: Option<String>,
}

/// The bytes of `topo` in a format; `.gwy` cannot be written.
pub fn encode_topography(
    topo: &Topography,
    format: SurfaceFormat,
    opts: &WriteOptions,
) -> Result<Vec<u8>, SurfaceError> {
    match format {
        SurfaceFormat::X3p => super::x3p::encode_x3p(topo, opts.x3p_type, opts.comment.as_deref()),
        SurfaceFormat::Gwy => Err(SurfaceError::Invalid(
            "writing .gwy is not supported; write .x3p, .npy or text".into(),
        )),
        SurfaceFormat::Npy => Ok(npy_bytes_of(
            topo.nx,
            topo.ny,
            &topo.heights,
            opts.npy_precision,
        )),
        SurfaceFormat::Text => {
            let mut s = String::new();
            s.push_str(&format!(
                "# heights in m, {} rows (x) x {} columns (y), pixel {:e} m x {:e} m\n",
                topo.nx, topo.ny, topo.dx, topo.dy
            ));
            if let Some(c) = &opts.comment {
                for line in c.lines() {
                    s.push_str(&format!("# {line}\n"));
                }
            }
            for row in topo.heights.chunks(topo.ny) {
                let cells: Vec<String> = row.iter().map(|v| format!("{v:e}")).collect();
                s.push_str(&cells.join(" "));
                s.push('\n');
            }
            Ok(s.into_bytes())
        }
    }
}

/// Write `topo` to `path` atomically (format by extension unless given).
pub fn write_topography(
    topo: &Topography,
    path: &Path,
    opts: &WriteOptions,
) -> Result<(), SurfaceError> {
    let format = opts
        .format
        .unwrap_or_else(|| SurfaceFormat::from_path(path));
    let bytes = encode_topography(topo, format, opts)?;
    crate::io::atomic::write_atomic(path, &bytes).map_err(|e| match e {
        crate::io::OutputError::Io { source, .. } => SurfaceError::Io {
            path: path.display().to_string(),
            source,
        },
        other => SurfaceError::Invalid(other.to_string()),
    })
}
