//! Dynamic mechanical analysis (DMA) data: CSV input and time-temperature
//! superposition by the WLF shift (physics.md section 2). The spectrum fit
//! to these data lives in [`super::fit`].

use std::path::Path;

use super::{columns, MaterialError, Wlf};

/// One DMA measurement.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DmaPoint {
    /// Angular frequency `w` [rad/s].
    pub omega: f64,
    /// Storage modulus `E1` \[Pa\].
    pub storage: f64,
    /// Loss modulus `E2` \[Pa\].
    pub loss: f64,
    /// Test temperature \[C\], when the file has a `temperature_c` column.
    pub temperature: Option<f64>,
}

/// A DMA data set read from CSV.
#[derive(Debug, Clone, PartialEq)]
pub struct DmaData {
    /// Where it came from (for messages and provenance).
    pub source: String,
    pub points: Vec<DmaPoint>,
    /// What reading them left out that may change the fit: each column
    /// the reader does not take (`material fit` warns of each).
    pub warnings: Vec<String>,
}

/// Accepted column names (lower case) and their meaning.
const FREQ_HZ: &[&str] = &["frequency_hz", "f_hz"];
const FREQ_RAD: &[&str] = &["omega_rad_s", "frequency_rad_s", "angular_frequency_rad_s"];
const STORAGE: &[&str] = &["e1_pa", "storage_modulus_pa"];
const LOSS: &[&str] = &["e2_pa", "loss_modulus_pa"];
const TEMP: &[&str] = &["temperature_c"];

impl DmaData {
    /// A data set of `points` given as values (`source` names it in
    /// messages), checked as a CSV's rows are: every angular frequency,
    /// `E1` and `E2` positive and finite, every temperature finite, at
    /// least 3 points. The error names the first bad point (from 0).
    pub fn from_points(source: &str, points: Vec<DmaPoint>) -> Result<Self, MaterialError> {
        let err = |message: String| MaterialError::Data {
            source_name: source.to_string(),
            message,
        };
        for (i, p) in points.iter().enumerate() {
            for (v, what) in [
                (p.omega, "angular frequency"),
                (p.storage, "E1"),
                (p.loss, "E2"),
            ] {
                if !(v.is_finite() && v > 0.0) {
                    return Err(err(format!(
                        "point {i}: {what} = {v} must be positive and finite"
                    )));
                }
            }
            if let Some(t) = p.temperature.filter(|t| !t.is_finite()) {
                return Err(err(format!("point {i}: temperature = {t} must be finite")));
            }
        }
        if points.len() < 3 {
            return Err(err(format!(
                "{} data points; at least 3 are needed",
                points.len()
            )));
        }
        Ok(Self {
            source: source.to_string(),
            points,
            warnings: Vec::new(),
        })
    }

    /// Read a CSV file (see [`DmaData::parse`]).
    pub fn read(path: &Path) -> Result<Self, MaterialError> {
        let text = std::fs::read_to_string(path).map_err(|e| MaterialError::Data {
            source_name: path.display().to_string(),
            message: e.to_string(),
        })?;
        Self::parse(&text, &path.display().to_string())
    }

    /// Parse CSV text. Lines starting with `#` and blank lines are skipped; the
    /// first other line is the header. Columns (case-insensitive): frequency as
    /// `frequency_hz` \[Hz\] or `omega_rad_s` [rad/s] (exactly one), `e1_pa` and
    /// `e2_pa` \[Pa\], optional `temperature_c` \[C\]; other columns are ignored,
    /// each named in [`DmaData::warnings`], but a temperature in kelvin or
    /// Fahrenheit (`temperature_k`, `temp_f`, ...) without `temperature_c`
    /// is refused. Every frequency, `E1` and `E2` must be positive and finite.
    pub fn parse(text: &str, source: &str) -> Result<Self, MaterialError> {
        let err = |line: usize, message: String| MaterialError::Data {
            source_name: if line > 0 {
                format!("{source} line {line}")
            } else {
                source.to_string()
            },
            message,
        };
        let mut lines = text
            .lines()
            .enumerate()
            .map(|(i, l)| (i + 1, l.trim()))
            .filter(|(_, l)| !l.is_empty() && !l.starts_with('#'));
        let (hline, header) = lines.next().ok_or_else(|| {
            err(
                0,
                "no header line (expected e.g. frequency_hz,e1_pa,e2_pa)".into(),
            )
        })?;
        // A spreadsheet's export with another separator is one column here.
        if !header.contains(',') {
            if let Some((_, name)) = [(';', "semicolons"), ('\t', "tabs")]
                .into_iter()
                .find(|(c, _)| header.contains(*c))
            {
                return Err(err(
                    hline,
                    format!("the columns are separated by {name}; the reader takes commas (export as CSV with ',' between columns and '.' as the decimal mark)"),
                ));
            }
        }
        let names: Vec<String> = header
            .split(',')
            .map(|s| s.trim().trim_matches('"').to_ascii_lowercase())
            .collect();
        let find = |aliases: &[&str]| -> Result<Option<usize>, MaterialError> {
            let hits: Vec<usize> = names
                .iter()
                .enumerate()
                .filter(|(_, n)| aliases.contains(&n.as_str()))
                .map(|(i, _)| i)
                .collect();
            match hits.len() {
                0 => Ok(None),
                1 => Ok(Some(hits[0])),
                _ => Err(err(
                    hline,
                    format!("more than one column named {}", aliases.join(" / ")),
                )),
            }
        };
        let hz = find(FREQ_HZ)?;
        let rad = find(FREQ_RAD)?;
        let (fcol, to_rad) = match (hz, rad) {
            (Some(c), None) => (c, 2.0 * std::f64::consts::PI),
            (None, Some(c)) => (c, 1.0),
            (Some(_), Some(_)) => {
                return Err(err(
                    hline,
                    "both frequency_hz and omega_rad_s columns given; keep one".into(),
                ))
            }
            (None, None) => {
                return Err(err(
                    hline,
                    "missing frequency column: frequency_hz (Hz) or omega_rad_s (rad/s)".into(),
                ))
            }
        };
        let e1col = find(STORAGE)?.ok_or_else(|| {
            err(
                hline,
                "missing column e1_pa (storage modulus E1, Pa)".into(),
            )
        })?;
        let e2col = find(LOSS)?
            .ok_or_else(|| err(hline, "missing column e2_pa (loss modulus E2, Pa)".into()))?;
        let tcol = find(TEMP)?;
        let mut warnings = Vec::new();
        for (c, name) in names.iter().enumerate() {
            if name.is_empty() || [Some(fcol), Some(e1col), Some(e2col), tcol].contains(&Some(c)) {
                continue;
            }
            let note = columns::unread_column(name, tcol.is_some()).map_err(|m| err(hline, m))?;
            warnings.push(note);
        }
        let mut points = Vec::new();
        for (ln, line) in lines {
            let cells: Vec<&str> = line.split(',').map(str::trim).collect();
            let cell = |c: usize| -> Result<f64, MaterialError> {
                let raw = cells.get(c).copied().ok_or_else(|| {
                    err(
                        ln,
                        format!("has {} cells, column {} is missing", cells.len(), names[c]),
                    )
                })?;
                let v: f64 = raw.trim_matches('"').parse().map_err(|_| {
                    err(ln, format!("column {}: '{raw}' is not a number", names[c]))
                })?;
                if !v.is_finite() {
                    return Err(err(
                        ln,
                        format!("column {}: '{raw}' is not finite", names[c]),
                    ));
                }
                Ok(v)
            };
            let f = cell(fcol)?;
            let e1 = cell(e1col)?;
            let e2 = cell(e2col)?;
            let t = tcol.map(cell).transpose()?;
            for (v, c, what) in [(f, fcol, "frequency"), (e1, e1col, "E1"), (e2, e2col, "E2")] {
                if v <= 0.0 {
                    return Err(err(
                        ln,
                        format!("column {}: {what} = {v} must be positive", names[c]),
                    ));
                }
            }
            points.push(DmaPoint {
                omega: f * to_rad,
                storage: e1,
                loss: e2,
                temperature: t,
            });
        }
        if points.len() < 3 {
            return Err(err(
                0,
                format!("{} data rows; at least 3 are needed", points.len()),
            ));
        }
        Ok(Self {
            source: source.to_string(),
            points,
            warnings,
        })
    }

    /// The distinct test temperatures, ascending (empty without a
    /// `temperature_c` column).
    pub fn temperatures(&self) -> Vec<f64> {
        let mut t: Vec<f64> = self.points.iter().filter_map(|p| p.temperature).collect();
        t.sort_by(f64::total_cmp);
        t.dedup();
        t
    }

    /// The lowest and highest test temperature \[C\] when the data span
    /// several: the range WLF constants that shift them onto one master
    /// curve were fitted over ([`Wlf::with_data_range`]).
    pub fn temperature_span(&self) -> Option<[f64; 2]> {
        match self.temperatures().as_slice() {
            [lo, .., hi] => Some([*lo, *hi]),
            _ => None,
        }
    }

    /// The data as a master curve at temperature `target` \[C\]:
    /// each frequency is shifted by `a_T(T) / a_T(target)` (WLF). Without WLF
    /// constants the data must be at one temperature, which must equal
    /// `target` if one is given. Returns the points and the temperature they
    /// now describe (None if unknown).
    pub fn reduced(
        &self,
        wlf: Option<&Wlf>,
        target: Option<f64>,
    ) -> Result<(Vec<DmaPoint>, Option<f64>), MaterialError> {
        let temps = self.temperatures();
        let src = || self.source.clone();
        match wlf {
            None => {
                if temps.len() > 1 {
                    return Err(MaterialError::Data {
                        source_name: src(),
                        message: format!(
                            "data at {} temperatures need WLF constants (--wlf C1,C2,TREF) to build a master curve",
                            temps.len()
                        ),
                    });
                }
                let data_t = temps.first().copied();
                match (target, data_t) {
                    (Some(t), Some(d)) if t != d => Err(MaterialError::Data {
                        source_name: src(),
                        message: format!(
                            "data are at {d} C; shifting to {t} C needs WLF constants (--wlf C1,C2,TREF)"
                        ),
                    }),
                    (Some(t), None) => Err(MaterialError::Data {
                        source_name: src(),
                        message: format!(
                            "no temperature_c column: cannot shift to {t} C"
                        ),
                    }),
                    _ => Ok((self.points.clone(), data_t)),
                }
            }
            Some(w) => {
                if self.points.iter().any(|p| p.temperature.is_none()) {
                    return Err(MaterialError::Data {
                        source_name: src(),
                        message: "WLF shift needs a temperature_c column".into(),
                    });
                }
                let to = target.unwrap_or(w.reference_temperature);
                let mut out = Vec::with_capacity(self.points.len());
                for p in &self.points {
                    let from = p.temperature.unwrap_or(to);
                    let omega = w.shift_frequency(p.omega, from, to)?;
                    if !(omega.is_finite() && omega > 0.0) {
                        return Err(MaterialError::Data {
                            source_name: src(),
                            message: format!(
                                "the frequency {} rad/s at {from} C shifts to {omega} rad/s at {to} C, outside the range of double precision",
                                p.omega
                            ),
                        });
                    }
                    out.push(DmaPoint { omega, ..*p });
                }
                Ok((out, Some(to)))
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A header separated by semicolons or tabs is named as such, not as a
    /// missing frequency column.
    #[test]
    fn other_separators_are_named() {
        for (text, needle) in [
            ("frequency_hz;e1_pa;e2_pa\n1;2e6;1e5\n", "semicolons"),
            ("frequency_hz\te1_pa\te2_pa\n1\t2e6\t1e5\n", "tabs"),
        ] {
            let e = DmaData::parse(text, "t").unwrap_err().to_string();
            assert!(e.starts_with("t line 1: ") && e.contains(needle), "{e}");
        }
    }

    #[test]
    fn csv_units_and_comments() {
        let text = "# comment\nomega_rad_s, E1_Pa ,e2_pa\n1,2,3\n\n# x\n10,20,30\n100,200,300\n";
        let d = DmaData::parse(text, "t").unwrap();
        assert_eq!(d.points.len(), 3);
        assert_eq!(d.points[1].omega, 10.0);
        let hz = DmaData::parse("frequency_hz,e1_pa,e2_pa\n1,2,3\n2,2,3\n3,2,3\n", "t").unwrap();
        assert!((hz.points[0].omega - 2.0 * std::f64::consts::PI).abs() < 1e-15);
    }

    /// A temperature column the reader does not take is refused in kelvin
    /// (it was ignored, and the temperatures merged) and named in a
    /// warning otherwise; so is any other unread column.
    #[test]
    fn unread_columns_are_refused_or_named() {
        let rows = "1,2e6,1e5,250\n10,3e6,2e5,250\n100,4e6,3e5,300\n";
        let e = DmaData::parse(
            &format!("omega_rad_s,e1_pa,e2_pa,temperature_k\n{rows}"),
            "t",
        )
        .unwrap_err()
        .to_string();
        assert!(
            e.starts_with("t line 1: column temperature_k") && e.contains("temperature_c"),
            "{e}"
        );
        let d = DmaData::parse(&format!("omega_rad_s,e1_pa,e2_pa,temp\n{rows}"), "t").unwrap();
        assert_eq!(d.warnings.len(), 1);
        assert!(
            d.warnings[0].contains("column temp is ignored"),
            "{:?}",
            d.warnings
        );
        let d = DmaData::parse(
            &format!(
                "omega_rad_s,e1_pa,e2_pa,temperature_c,tan_d\n{}",
                rows.replace('\n', ",0.1\n")
            ),
            "t",
        )
        .unwrap();
        assert_eq!(d.warnings.len(), 1, "{:?}", d.warnings);
        assert!(d.warnings[0].contains("tan_d"));
        let clean = DmaData::parse(
            &format!("omega_rad_s,e1_pa,e2_pa,temperature_c\n{rows}"),
            "t",
        )
        .unwrap();
        assert!(clean.warnings.is_empty());
    }
}
