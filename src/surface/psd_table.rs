//! A tabulated isotropic PSD `C(q)`: the `q, C` columns that `surface stats`
//! writes and that measured or stitched spectra come as (physics.md
//! section 11), log-log interpolated.
//!
//! Convention: the radial value of the 2-D PSD of [`super::psd`], so that
//! `<h^2> = 2 pi Int q C(q) dq` and `<|grad h|^2> = 2 pi Int q^3 C(q) dq`.
//! Between two rows `C` is the power law through both points (straight in
//! log-log axes); outside `[q_min, q_max]` the table says nothing and
//! [`TabulatedPsd::eval`] returns 0.

use std::path::Path;

use super::SurfaceError;

/// What a synthesis from a table gives the grid's modes below the table's
/// smallest wavenumber `q_min`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum BelowTable {
    /// The first row's `C` down to the lower edge of its bin
    /// ([`TabulatedPsd::first_bin_edge`]): every mode the table's first
    /// bin held keeps its power, nothing further down. The default.
    #[default]
    FirstBin,
    /// The power law of the first two rows continued down to the grid's
    /// longest mode: asks the table for power it does not hold.
    Extrapolate,
    /// Nothing below `q_min`.
    None,
}

impl BelowTable {
    /// The rule by its name in configs and on the command line.
    pub fn parse(s: &str) -> Result<Self, SurfaceError> {
        match s {
            "first_bin" | "first-bin" => Ok(Self::FirstBin),
            "extrapolate" => Ok(Self::Extrapolate),
            "none" => Ok(Self::None),
            _ => Err(SurfaceError::Invalid(format!(
                "below_table = {s:?}: expected \"first_bin\", \"extrapolate\" or \"none\""
            ))),
        }
    }
}

/// A PSD given at increasing wavenumbers, interpolated as a power law per
/// interval.
#[derive(Debug, Clone, PartialEq)]
pub struct TabulatedPsd {
    /// Wavenumbers \[1/m\], strictly increasing, positive.
    q: Vec<f64>,
    /// `C(q)` \[m^4\], positive.
    c: Vec<f64>,
}

impl TabulatedPsd {
    /// A table from its columns; `name` labels errors. Needs at least two
    /// rows, finite positive `q` strictly increasing and finite positive `C`.
    pub fn new(q: Vec<f64>, c: Vec<f64>, name: &str) -> Result<Self, SurfaceError> {
        if q.len() != c.len() {
            return Err(SurfaceError::Invalid(format!(
                "{name}: {} wavenumbers but {} PSD values",
                q.len(),
                c.len()
            )));
        }
        if q.len() < 2 {
            return Err(SurfaceError::Invalid(format!(
                "{name}: a tabulated PSD needs at least 2 rows, found {}",
                q.len()
            )));
        }
        for (row, (&qi, &ci)) in q.iter().zip(&c).enumerate() {
            if !(qi.is_finite() && qi > 0.0) {
                return Err(SurfaceError::Invalid(format!(
                    "{name}: row {}: wavenumber q = {qi} must be finite and positive",
                    row + 1
                )));
            }
            if !(ci.is_finite() && ci > 0.0) {
                return Err(SurfaceError::Invalid(format!(
                    "{name}: row {}: PSD value C = {ci} must be finite and positive",
                    row + 1
                )));
            }
            if row > 0 && qi <= q[row - 1] {
                return Err(SurfaceError::Invalid(format!(
                    "{name}: row {}: wavenumbers must increase strictly (q = {qi} after {})",
                    row + 1,
                    q[row - 1]
                )));
            }
        }
        Ok(Self { q, c })
    }

    /// Read a CSV whose first two columns are `q` \[1/m\] and `C` \[m^4\]
    /// (further columns are ignored). Blank lines, lines starting with `#`
    /// and a leading UTF-8 BOM are skipped; a first line that does not start
    /// with a number is a header, whose first two names must not state
    /// other units (`check_header`: viscoslide's `q_per_m,c_m4` and
    /// `q_per_m,c_radial_m4`, or names without units).
    pub fn from_csv(path: &Path) -> Result<Self, SurfaceError> {
        let text = std::fs::read_to_string(path).map_err(|source| SurfaceError::Io {
            path: path.display().to_string(),
            source,
        })?;
        Self::parse_csv(&text, &path.display().to_string())
    }

    /// [`Self::from_csv`] on text already read; `name` labels errors.
    pub fn parse_csv(text: &str, name: &str) -> Result<Self, SurfaceError> {
        let mut q = Vec::new();
        let mut c = Vec::new();
        let mut first = true;
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
        for (n, line) in text.lines().enumerate() {
            let line = line.trim();
            if line.is_empty() || line.starts_with('#') {
                continue;
            }
            let mut cols = line.split([',', ';', '\t', ' ']).filter(|s| !s.is_empty());
            let (a, b) = (cols.next().unwrap_or(""), cols.next());
            if first && a.parse::<f64>().is_err() {
                first = false;
                // Names may hold spaces (`q [1/m]`) where a separator is.
                let mut names: Vec<&str> = if line.contains([',', ';', '\t']) {
                    line.split([',', ';', '\t']).collect()
                } else {
                    line.split_whitespace().collect()
                };
                names.resize(2, "");
                check_header(names[0], names[1], name)?;
                continue;
            }
            first = false;
            let number = |s: &str| {
                s.trim().parse::<f64>().map_err(|_| {
                    SurfaceError::Invalid(format!(
                        "{name}: line {}: cannot read '{s}' as a number",
                        n + 1
                    ))
                })
            };
            let Some(b) = b else {
                return Err(SurfaceError::Invalid(format!(
                    "{name}: line {}: expected two columns q, C",
                    n + 1
                )));
            };
            q.push(number(a)?);
            c.push(number(b)?);
        }
        Self::new(q, c, name)
    }

    /// The table as CSV, `q_per_m,c_m4`, the header [`Self::parse_csv`]
    /// skips.
    pub fn to_csv(&self) -> String {
        let mut s = String::from("q_per_m,c_m4\n");
        for (q, c) in self.q.iter().zip(&self.c) {
            s.push_str(&format!("{q:.10e},{c:.10e}\n"));
        }
        s
    }

    /// Smallest tabulated wavenumber \[1/m\].
    pub fn q_min(&self) -> f64 {
        self.q[0]
    }

    /// Largest tabulated wavenumber \[1/m\].
    pub fn q_max(&self) -> f64 {
        self.q[self.q.len() - 1]
    }

    /// The tabulated wavenumbers \[1/m\].
    pub fn q(&self) -> &[f64] {
        &self.q
    }

    /// The tabulated values \[m^4\].
    pub fn c(&self) -> &[f64] {
        &self.c
    }

    /// The table over `[lo, hi]` only (its rows inside, and the
    /// interpolated values at `lo` and `hi` where the table reaches them):
    /// the PSD of a surface synthesised from the table on a grid that
    /// resolves that band. An error when fewer than two rows remain.
    pub fn within(&self, lo: f64, hi: f64, name: &str) -> Result<Self, SurfaceError> {
        let lo = lo.max(self.q_min());
        let hi = hi.min(self.q_max());
        let mut q = vec![];
        let mut c = vec![];
        if lo < hi {
            q.push(lo);
            c.push(self.eval(lo));
            for (&qi, &ci) in self.q.iter().zip(&self.c) {
                if qi > lo && qi < hi {
                    q.push(qi);
                    c.push(ci);
                }
            }
            q.push(hi);
            c.push(self.eval(hi));
        }
        if q.len() < 2 {
            return Err(SurfaceError::Invalid(format!(
                "{name}: the table ({:.4e} to {:.4e} 1/m) does not overlap the band {lo:.4e} to {hi:.4e} 1/m",
                self.q_min(),
                self.q_max()
            )));
        }
        Self::new(q, c, name)
    }

    /// The lower edge of the table's first bin \[1/m\]: a row stands for
    /// the bin around it, so the first bin reaches below `q_min`.
    ///
    /// - Rows evenly spaced at the start (the first three spacings within
    ///   a factor 1.5 of each other) are linear bins of width `dq`, the
    ///   mean spacing. `surface stats` writes the mean `|q|` of the modes
    ///   of annuli centred on multiples of `dq` ([`super::radial_average`]):
    ///   when `q_0 / dq` is within 0.35 of an integer `k >= 1` the edge is
    ///   `(k - 1/2) dq`, else `q_0 - dq / 2`.
    /// - Other tables (log-spaced bins): the geometric half-spacing
    ///   `q_0 sqrt(q_0 / q_1)`.
    pub fn first_bin_edge(&self) -> f64 {
        let (q0, q1) = (self.q[0], self.q[1]);
        let spacings: Vec<f64> = self.q.windows(2).take(3).map(|w| w[1] - w[0]).collect();
        let (lo, hi) = spacings
            .iter()
            .fold((f64::INFINITY, 0.0f64), |(lo, hi), &d| {
                (lo.min(d), hi.max(d))
            });
        let dq = spacings.iter().sum::<f64>() / spacings.len() as f64;
        if hi <= 1.5 * lo && q0 - 0.5 * dq > 0.0 {
            let k = (q0 / dq).round();
            if k >= 1.0 && (q0 / dq - k).abs() < 0.35 {
                (k - 0.5) * dq
            } else {
                q0 - 0.5 * dq
            }
        } else {
            q0 * (q0 / q1).sqrt()
        }
    }

    /// `C(q)` with the rule `below` for wavenumbers under `q_min` (see
    /// [`BelowTable`]); [`Self::eval`] above.
    pub fn eval_with(&self, q: f64, below: BelowTable) -> f64 {
        if q >= self.q_min() || q.is_nan() || q <= 0.0 {
            return self.eval(q);
        }
        match below {
            BelowTable::None => 0.0,
            BelowTable::FirstBin if q >= self.first_bin_edge() => self.c[0],
            BelowTable::FirstBin => 0.0,
            BelowTable::Extrapolate => {
                let slope = (self.c[1] / self.c[0]).ln() / (self.q[1] / self.q[0]).ln();
                self.c[0] * (q / self.q[0]).powf(slope)
            }
        }
    }

    /// `C(q)` by log-log interpolation; 0 outside `[q_min, q_max]`.
    pub fn eval(&self, q: f64) -> f64 {
        if !(q >= self.q_min() && q <= self.q_max()) {
            return 0.0;
        }
        // First row with q_i >= q; the interval is [i - 1, i].
        let i = self.q.partition_point(|&qi| qi < q).max(1);
        let (q0, q1) = (self.q[i - 1], self.q[i]);
        let (c0, c1) = (self.c[i - 1], self.c[i]);
        let slope = (c1 / c0).ln() / (q1 / q0).ln();
        c0 * (q / q0).powf(slope)
    }

    /// [`Self::moment`] with the first row's value continued down to the
    /// lower edge of its bin ([`Self::first_bin_edge`],
    /// [`BelowTable::FirstBin`]): `+ 2 pi C_0 (q_0^(2+k) - e^(2+k)) / (2+k)`.
    pub fn moment_first_bin(&self, k: u32) -> f64 {
        let (q0, e) = (self.q[0], self.first_bin_edge());
        let p = 2 + k as i32;
        self.moment(k)
            + 2.0 * std::f64::consts::PI * self.c[0] * (q0.powi(p) - e.powi(p)) / p as f64
    }

    /// `2 pi Int q^(1 + k) C(q) dq` over the whole table, exact for the
    /// piecewise power law: `k = 0` is the mean square height `<h^2>`,
    /// `k = 2` the mean square slope `<|grad h|^2>`, `k = 4` the mean
    /// square Laplacian (curvature).
    pub fn moment(&self, k: u32) -> f64 {
        let mut sum = 0.0;
        for i in 1..self.q.len() {
            let (q0, q1) = (self.q[i - 1], self.q[i]);
            let (c0, c1) = (self.c[i - 1], self.c[i]);
            let slope = (c1 / c0).ln() / (q1 / q0).ln();
            // Int_{q0}^{q1} c0 (q/q0)^s q^(1+k) dq with e = s + 2 + k.
            let e = slope + 2.0 + k as f64;
            let f0 = c0 * q0.powi(2 + k as i32);
            let r = (q1 / q0).ln();
            let part = if (e * r).abs() < 1e-12 {
                f0 * r
            } else {
                f0 * ((e * r).exp_m1()) / e
            };
            sum += part;
        }
        2.0 * std::f64::consts::PI * sum
    }
}

/// The powers of length a column name states, as (unit, power): `per_um`,
/// `1/nm`, `m^-1` (power -1), `um4`, `m^4` (power 4), `m3` (a line PSD's
/// m^3); `None` when the name states no unit of length.
fn stated_unit(column: &str) -> Option<(String, i32)> {
    const LENGTHS: &[&str] = &[
        "km", "m", "cm", "mm", "um", "µm", "μm", "nm", "pm", "a", "å",
    ];
    let lower = column.trim().trim_matches('"').to_lowercase();
    let tokens: Vec<&str> = lower
        .split(['_', ' ', '[', ']', '(', ')', '{', '}'])
        .filter(|t| !t.is_empty())
        .collect();
    for (k, t) in tokens.iter().enumerate() {
        // `per_X`, `1_per_X`.
        if *t == "per" {
            if let Some(u) = tokens.get(k + 1).filter(|u| LENGTHS.contains(u)) {
                return Some((u.to_string(), -1));
            }
        }
        // `1/X`, `/X`.
        if let Some(u) = t.strip_prefix("1/").or_else(|| t.strip_prefix('/')) {
            if LENGTHS.contains(&u) {
                return Some((u.to_string(), -1));
            }
        }
        // `X^p`, `X**p`, `Xp` with p an integer (`m^-1`, `um4`, `m3`).
        let unit_end = t
            .find(|c: char| c == '^' || c == '*' || c == '-' || c.is_ascii_digit())
            .unwrap_or(t.len());
        let (unit, rest) = t.split_at(unit_end);
        let power = rest.trim_start_matches(['^', '*']);
        if LENGTHS.contains(&unit) && (k > 0 || !rest.is_empty()) {
            match power.parse::<i32>() {
                Ok(p) => return Some((unit.to_string(), p)),
                Err(_) if power.is_empty() => return Some((unit.to_string(), 1)),
                Err(_) => {}
            }
        }
    }
    None
}

/// Check the first two names of a PSD table's header: a unit stated must
/// be 1/m for `q` and m^4 for `C` (a line PSD's m^3 or another length unit
/// is refused, naming the column), so that a table in other units is not
/// read as SI. Names without a unit are taken as `q` \[1/m\], `C` \[m^4\].
fn check_header(q: &str, c: &str, name: &str) -> Result<(), SurfaceError> {
    for (column, power, want, which) in [(q, -1, "1/m", "first (q)"), (c, 4, "m^4", "second (C)")] {
        let Some((unit, p)) = stated_unit(column) else {
            continue;
        };
        if unit != "m" || p != power {
            let stated = match p {
                -1 => format!("1/{unit}"),
                1 => unit.clone(),
                _ => format!("{unit}^{p}"),
            };
            return Err(SurfaceError::Invalid(format!(
                "{name}: the header's {which} column '{}' is in {stated}, not {want}: a PSD table holds q in 1/m and the radial C(q) in m^4 (header `q_per_m,c_m4`); convert the columns",
                column.trim()
            )));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn power_law_is_reproduced_between_and_at_rows() {
        // C = 1e-30 (q / 1e4)^-3.6 sampled at three points.
        let f = |q: f64| 1e-30 * (q / 1e4).powf(-3.6);
        let q = vec![1e4, 1e5, 1e6];
        let t = TabulatedPsd::new(q.clone(), q.iter().map(|&x| f(x)).collect(), "t").unwrap();
        for x in [1e4, 2.5e4, 1e5, 3.3e5, 1e6] {
            assert!((t.eval(x) / f(x) - 1.0).abs() < 1e-12, "q = {x}");
        }
        assert_eq!(t.eval(9e3), 0.0);
        assert_eq!(t.eval(1.1e6), 0.0);
        // Moments against the closed form of the single power law.
        for k in [0u32, 2, 4] {
            let e = -3.6 + 2.0 + k as f64;
            let exact = 2.0 * std::f64::consts::PI * 1e-30 * 1e4f64.powf(3.6) / e
                * (1e6f64.powf(e) - 1e4f64.powf(e));
            assert!((t.moment(k) / exact - 1.0).abs() < 1e-10, "k = {k}");
        }
    }

    #[test]
    fn csv_round_trip_with_header_and_extra_columns() {
        let text =
            "q_per_m,c_radial_m4,c_target_m4\n# comment\n1e3,2e-20,\n2e3,1e-21,5\n\n4e3,3e-23,\n";
        let t = TabulatedPsd::parse_csv(text, "psd.csv").unwrap();
        assert_eq!(t.q(), &[1e3, 2e3, 4e3]);
        assert_eq!(t.c(), &[2e-20, 1e-21, 3e-23]);
        let back = TabulatedPsd::parse_csv(&t.to_csv(), "back").unwrap();
        assert_eq!(back, t);
    }

    #[test]
    fn the_first_bin_reaches_half_a_bin_below_the_first_row() {
        // Linear bins of width 10 centred on 10, 20, 30, ...; rows at the
        // mean |q| of each annulus, a little above the centre.
        let lin =
            TabulatedPsd::new(vec![10.6, 20.3, 30.2, 40.1], vec![4.0, 2.0, 1.0, 0.5], "t").unwrap();
        let dq = (40.1 - 10.6) / 3.0;
        assert!((lin.first_bin_edge() - 0.5 * dq).abs() < 1e-12);
        // Log-spaced rows: the geometric half-spacing.
        let log = TabulatedPsd::new(vec![100.0, 200.0, 400.0, 800.0], vec![1.0; 4], "t").unwrap();
        assert!((log.first_bin_edge() - 100.0 / 2f64.sqrt()).abs() < 1e-12);
        // Below q_min: the first row's C down to the edge, nothing under
        // it; zero everywhere below for `None`; the first interval's power
        // law for `Extrapolate`.
        let e = lin.first_bin_edge();
        assert_eq!(lin.eval_with(e * 1.01, BelowTable::FirstBin), 4.0);
        assert_eq!(lin.eval_with(e * 0.99, BelowTable::FirstBin), 0.0);
        assert_eq!(lin.eval_with(e * 1.01, BelowTable::None), 0.0);
        let slope = (2.0f64 / 4.0).ln() / (20.3f64 / 10.6).ln();
        let x = lin.eval_with(2.0, BelowTable::Extrapolate);
        assert!((x - 4.0 * (2.0f64 / 10.6).powf(slope)).abs() < 1e-12 * x);
        // Above q_min every rule is the table.
        for b in [
            BelowTable::FirstBin,
            BelowTable::None,
            BelowTable::Extrapolate,
        ] {
            assert_eq!(lin.eval_with(25.0, b), lin.eval(25.0));
        }
        // The first bin's lower part adds pi C_0 (q_0^2 - e^2) to <h^2>.
        let extra = lin.moment_first_bin(0) - lin.moment(0);
        let want = std::f64::consts::PI * 4.0 * (10.6f64.powi(2) - e * e);
        assert!((extra - want).abs() < 1e-12 * want);
        assert!(BelowTable::parse("sideways").is_err());
        assert_eq!(
            BelowTable::parse("first_bin").unwrap(),
            BelowTable::FirstBin
        );
    }

    #[test]
    fn header_units_other_than_si_are_refused() {
        let rows = "1e3,2e-20\n2e3,1e-21\n";
        for header in [
            "q_per_m,c_radial_m4",
            "q_per_m,c_m4,modes,scans",
            "q_per_m,c_radial_m4,c_target_m4",
            "q,C",
            "wavenumber,psd",
            "q [1/m],C [m^4]",
            "q (m^-1);C (m4)",
            "\u{feff}q_per_m,c_m4",
        ] {
            let t = TabulatedPsd::parse_csv(&format!("{header}\n{rows}"), "psd.csv");
            assert_eq!(t.unwrap().q(), &[1e3, 2e3], "{header}");
        }
        for (header, want) in [
            ("q_1_per_um,C_um4", "'q_1_per_um' is in 1/um"),
            ("q [1/nm],C [nm^4]", "'q [1/nm]' is in 1/nm"),
            ("q_per_m,C_um4", "'C_um4' is in um^4"),
            ("q_per_m,c1_m3", "'c1_m3' is in m^3"),
            ("q (m^-1),C (m^2)", "'C (m^2)' is in m^2"),
        ] {
            let e = TabulatedPsd::parse_csv(&format!("{header}\n{rows}"), "psd.csv")
                .unwrap_err()
                .to_string();
            assert!(
                e.starts_with("psd.csv: ") && e.contains(want),
                "{header}: {e}"
            );
            assert!(!e.contains('\n'), "{e}");
        }
        // A BOM before a headerless table is not part of the first number.
        let t = TabulatedPsd::parse_csv(&format!("\u{feff}{rows}"), "psd.csv").unwrap();
        assert_eq!(t.c(), &[2e-20, 1e-21]);
    }

    #[test]
    fn bad_tables_are_one_line_errors() {
        let cases = [
            ("q,C\n1e3,1e-20\n", "at least 2 rows"),
            ("1e3,1e-20\n0,1e-21\n", "finite and positive"),
            ("1e3,1e-20\n2e3,-1e-21\n", "finite and positive"),
            ("1e3,1e-20\n2e3,NaN\n", "finite and positive"),
            ("2e3,1e-20\n1e3,1e-21\n", "increase strictly"),
            ("1e3,1e-20\n2e3,abc\n", "cannot read 'abc'"),
            ("1e3,1e-20\n2e3\n", "two columns"),
        ];
        for (text, want) in cases {
            let e = TabulatedPsd::parse_csv(text, "psd.csv")
                .unwrap_err()
                .to_string();
            assert!(
                e.contains(want) && e.starts_with("psd.csv"),
                "{text:?}: {e}"
            );
            assert!(!e.contains('\n'), "{e}");
        }
    }
}
