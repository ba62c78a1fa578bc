//! Plain-text height matrices: rows of numbers separated by whitespace
//! and/or commas, `#` starts a comment, blank lines and a leading UTF-8 BOM
//! are skipped. Two layouts:
//!
//! - viscoslide's own (no size header): row `i` is the x index, heights in
//!   m, the sides from the caller (`--length`, `[surface] length`);
//! - a header of `# Width: <number> <unit>`, `# Height: <number> <unit>` and
//!   `# Value units: <unit>` before the first row (SurfaceTopography's
//!   `Topography.to_matrix`, Gwyddion's ASCII export): each row is a line
//!   along x at one y, and the sides and the height unit are the header's.
//!   A side without a unit takes that of the heights, as SurfaceTopography
//!   reads it; a unit that is not a length, or no unit at all, is refused.
//!
//! Refused as not a height matrix: an `x y z` point list (three columns,
//! the first two grid coordinates), and numbers with decimal commas
//! (`0,25 1,5`), which commas-as-separators would split into columns.

use super::length_unit::metres_per;
use super::SurfaceError;

/// A text matrix as read: heights in metres with axis 0 = x.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct TextMatrix {
    /// Points along x and y.
    pub nx: usize,
    pub ny: usize,
    /// `heights[i * ny + j]` \[m\], `i` along x.
    pub heights: Vec<f64>,
    /// The sides along x and y \[m\] where the header states them.
    pub length_x: Option<f64>,
    pub length_y: Option<f64>,
}

/// A side or unit the header states: `(value, unit)` as written.
type Side<'a> = (f64, Option<&'a str>);

/// The header keys read (case-insensitive), as SurfaceTopography's
/// `to_matrix` and Gwyddion write them.
#[derive(Debug, Default)]
struct Header<'a> {
    width: Option<Side<'a>>,
    height: Option<Side<'a>>,
    value_units: Option<&'a str>,
}

impl<'a> Header<'a> {
    fn is_empty(&self) -> bool {
        self.width.is_none() && self.height.is_none() && self.value_units.is_none()
    }

    /// Read `# Key: value` from one comment line (the text after `#`);
    /// other comments are left alone.
    fn take(&mut self, comment: &'a str, name: &str, line: usize) -> Result<(), SurfaceError> {
        let Some((key, value)) = comment.split_once(':') else {
            return Ok(());
        };
        let (key, value) = (key.trim().to_ascii_lowercase(), value.trim());
        let side = || -> Result<Side<'a>, SurfaceError> {
            let split = value.find(char::is_whitespace).unwrap_or(value.len());
            let (num, unit) = (&value[..split], value[split..].trim());
            let v: f64 = num.parse().map_err(|_| {
                SurfaceError::Invalid(format!(
                    "{name}: line {line}: cannot read the header's size '{value}' as a number and a unit"
                ))
            })?;
            if !(v.is_finite() && v > 0.0) {
                return Err(SurfaceError::Invalid(format!(
                    "{name}: line {line}: the header's size '{value}' must be finite and > 0"
                )));
            }
            Ok((v, (!unit.is_empty()).then_some(unit)))
        };
        match key.as_str() {
            "width" => self.width = Some(side()?),
            "height" => self.height = Some(side()?),
            "value units" => self.value_units = Some(value).filter(|v| !v.is_empty()),
            _ => {}
        }
        Ok(())
    }
}

/// The units of length a header may state: those SurfaceTopography and
/// Gwyddion write (`µm` as micro sign or Greek mu, `um`; `Å` or `A`).
const HEADER_UNITS: &[&str] = &[
    "km", "m", "cm", "mm", "µm", "μm", "um", "nm", "Å", "A", "pm",
];

fn unit_factor(unit: &str, what: &str, name: &str) -> Result<f64, SurfaceError> {
    let known = metres_per(unit).filter(|_| HEADER_UNITS.contains(&unit));
    known.ok_or_else(|| {
        SurfaceError::Invalid(format!(
            "{name}: the header gives the {what} in '{unit}', not a unit of length viscoslide knows (km, m, cm, mm, um, nm, A, pm)"
        ))
    })
}

/// The numbers of `line` when it has a decimal comma: a whitespace-separated
/// token such as `0,25` (digits on both sides of one comma, no point) on a
/// line whose tokens do not start or end with a comma (not `1.0, 2.0`).
fn decimal_comma(line: &str) -> Option<&str> {
    let tokens: Vec<&str> = line.split_whitespace().collect();
    if tokens.len() < 2
        || tokens
            .iter()
            .any(|t| t.starts_with(',') || t.ends_with(','))
    {
        return None;
    }
    tokens.into_iter().find(|t| {
        let mantissa = t.split(['e', 'E']).next().unwrap_or("");
        let digits = mantissa.trim_start_matches(['-', '+']);
        let (a, b) = digits.split_once(',').unwrap_or(("", ""));
        !digits.contains('.')
            && !a.is_empty()
            && !b.is_empty()
            && a.bytes().chain(b.bytes()).all(|c| c.is_ascii_digit())
    })
}

/// Whether a column holds grid coordinates: fewer distinct values than
/// rows (each repeats) and at least two.
fn repeats(col: &[f64]) -> bool {
    let mut v = col.to_vec();
    v.sort_by(f64::total_cmp);
    v.dedup();
    v.len() >= 2 && v.len() < col.len()
}

fn monotone(col: &[f64]) -> bool {
    col.windows(2).all(|w| w[0] <= w[1]) || col.windows(2).all(|w| w[0] >= w[1])
}

/// Whether `rows x 3` values are an `x y z` point list: one of the first two
/// columns runs monotonically through repeated values (the slow axis) and
/// the other repeats (the fast axis).
fn is_point_list(rows: usize, values: &[f64]) -> bool {
    if rows < 4 {
        return false;
    }
    let col = |k: usize| -> Vec<f64> { values.iter().skip(k).step_by(3).copied().collect() };
    let (a, b) = (col(0), col(1));
    repeats(&a) && repeats(&b) && (monotone(&a) || monotone(&b))
}

/// The message for a point list (by content or by a `.xyz` extension).
pub(super) fn point_list_refusal(name: &str) -> String {
    format!(
        "{name}: an x, y, z point list, not a height matrix; a map must be a matrix of heights (one row per x, or one row per y under a `# Width:`/`# Height:` header): convert it, or read it with SurfaceTopography in Python (`viscoslide.Surface.from_topography(SurfaceTopography.read_topography(path))`)"
    )
}

/// Read a text matrix (module doc); `name` labels errors. The heights are
/// not validated (a NaN marks a missing point); the shape is the caller's
/// to check.
pub(super) fn text_matrix(text: &str, name: &str) -> Result<TextMatrix, SurfaceError> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut header = Header::default();
    let mut values = Vec::new();
    let mut ncols: Option<usize> = None;
    let mut nrows = 0;
    for (lineno, raw) in text.lines().enumerate() {
        let (line, comment) = raw.split_once('#').unwrap_or((raw, ""));
        if nrows == 0 && line.trim().is_empty() {
            header.take(comment, name, lineno + 1)?;
        }
        if let Some(token) = decimal_comma(line) {
            return Err(SurfaceError::Invalid(format!(
                "{name}: line {}: '{token}' has a decimal comma; write the numbers with decimal points (commas separate columns)",
                lineno + 1
            )));
        }
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
            values.push(v);
        }
        nrows += 1;
    }
    let ncols = ncols.unwrap_or(0);
    if header.is_empty() {
        if ncols == 3 && is_point_list(nrows, &values) {
            return Err(SurfaceError::Invalid(point_list_refusal(name)));
        }
        return Ok(TextMatrix {
            nx: nrows,
            ny: ncols,
            heights: values,
            length_x: None,
            length_y: None,
        });
    }
    oriented(header, nrows, ncols, values, name)
}

/// A matrix under a size header: rows along y, sides and heights in the
/// header's units, turned to axis 0 = x in metres.
fn oriented(
    header: Header,
    nrows: usize,
    ncols: usize,
    values: Vec<f64>,
    name: &str,
) -> Result<TextMatrix, SurfaceError> {
    let z_unit = header.value_units.ok_or_else(|| {
        SurfaceError::Invalid(format!(
            "{name}: the header gives the map's sizes but no `# Value units:`; add the unit of the heights (e.g. `# Value units: m`)"
        ))
    })?;
    let z = unit_factor(z_unit, "heights", name)?;
    let side = |s: Option<Side>, fallback: &str, what: &str| -> Result<Option<f64>, SurfaceError> {
        s.map(|(v, unit)| Ok(v * unit_factor(unit.unwrap_or(fallback), what, name)?))
            .transpose()
    };
    let x_unit = header.width.and_then(|w| w.1).unwrap_or(z_unit);
    let length_x = side(header.width, z_unit, "width (x)")?;
    let length_y = side(header.height, x_unit, "height (y)")?;
    let (nx, ny) = (ncols, nrows);
    let mut heights = vec![0.0; values.len()];
    for (r, row) in values.chunks(ncols.max(1)).enumerate() {
        for (c, v) in row.iter().enumerate() {
            heights[c * ny + r] = if z == 1.0 { *v } else { v * z };
        }
    }
    Ok(TextMatrix {
        nx,
        ny,
        heights,
        length_x,
        length_y,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_are_x_without_a_header() {
        let t = text_matrix("\u{feff}1e-7 2e-7\n3e-7 4e-7\n5e-7 6e-7\n", "t").unwrap();
        assert_eq!((t.nx, t.ny), (3, 2));
        assert_eq!(t.heights, [1e-7, 2e-7, 3e-7, 4e-7, 5e-7, 6e-7]);
        assert_eq!((t.length_x, t.length_y), (None, None));
    }

    /// SurfaceTopography's `to_matrix`: rows along y, sizes and heights in
    /// the header's unit.
    #[test]
    fn a_size_header_gives_rows_along_y_in_its_units() {
        let text = "# Width: 3.0 um\n# Height: 2.0 um\n# Value units: um\n1 2 3\n4 5 6\n";
        let t = text_matrix(text, "t").unwrap();
        assert_eq!((t.nx, t.ny), (3, 2));
        // h(x, y): row y, column x.
        let want = [1.0, 4.0, 2.0, 5.0, 3.0, 6.0].map(|v: f64| v * 1e-6);
        assert_eq!(t.heights, want);
        assert_eq!(t.length_x, Some(3.0 * 1e-6));
        assert_eq!(t.length_y, Some(2.0 * 1e-6));
        // Gwyddion: sides in µm, heights in m; a side without a unit takes
        // that of the heights.
        let gwy =
            "# Channel: Height\n# Width: 1.500 µm\n# Height: 4 nm\n# Value units: m\n1 2\n3 4\n";
        let t = text_matrix(gwy, "g").unwrap();
        assert_eq!(t.heights, [1.0, 3.0, 2.0, 4.0]);
        assert!((t.length_x.unwrap() / 1.5e-6 - 1.0).abs() < 1e-15);
        assert_eq!(t.length_y, Some(4e-9));
        let bare = "# Width: 2\n# Value units: nm\n1 2\n3 4\n";
        assert_eq!(text_matrix(bare, "b").unwrap().length_x, Some(2e-9));
    }

    #[test]
    fn unknown_or_missing_units_are_refused_naming_them() {
        let cases = [
            (
                "# Width: 3 furlong\n# Value units: m\n1 2\n3 4\n",
                "'furlong'",
            ),
            ("# Width: 3 um\n# Value units: V\n1 2\n3 4\n", "'V'"),
            ("# Width: 3 um\n# Height: 3 um\n1 2\n3 4\n", "Value units"),
            ("# Width: wide\n1 2\n3 4\n", "'wide'"),
            ("# Height: -2 m\n# Value units: m\n1 2\n3 4\n", "> 0"),
        ];
        for (text, want) in cases {
            let e = text_matrix(text, "u.txt").unwrap_err().to_string();
            assert!(
                e.starts_with("u.txt: ") && e.contains(want),
                "{text:?}: {e}"
            );
            assert!(!e.contains('\n'), "{e}");
        }
    }

    #[test]
    fn point_lists_and_decimal_commas_are_refused() {
        let mut xyz = String::new();
        for y in 0..4 {
            for x in 0..5 {
                xyz.push_str(&format!(
                    "{} {} {}\n",
                    x as f64 * 1e-6,
                    y as f64 * 1e-6,
                    0.1 * x as f64
                ));
            }
        }
        let e = text_matrix(&xyz, "p.txt").unwrap_err().to_string();
        assert!(
            e.contains("point list") && e.contains("height matrix"),
            "{e}"
        );
        let e = text_matrix("0,000125730 -0,000132105\n1,5 2,5\n", "c.txt")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("line 1") && e.contains("'0,000125730'") && e.contains("decimal comma"),
            "{e}"
        );
        // CSV reads, with or without spaces; a 3-column map of heights too.
        for csv in ["1.0, 2.0\n3.0, 4.0\n", "1.0,2.0\n3.0,4.0\n", "1,2\n3,4\n"] {
            let t = text_matrix(csv, "ok.csv").unwrap();
            assert_eq!(t.heights, [1.0, 2.0, 3.0, 4.0], "{csv:?}");
        }
        let map = "0.3 0.1 0.2\n0.5 0.9 0.4\n0.2 0.7 0.8\n0.6 0.3 0.1\n";
        assert_eq!(text_matrix(map, "m.txt").unwrap().ny, 3);
    }
}
