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
    /// (further columns are ignored). Blank lines and lines starting with
    /// `#` are skipped; a first line that does not start with a number is a
    /// header.
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
        for (n, line) in text.lines().enumerate() {
            let line = line.trim();
            if line.is_empty() || line.starts_with('#') {
                continue;
            }
            let mut cols = line.split([',', ';', '\t', ' ']).filter(|s| !s.is_empty());
            let (a, b) = (cols.next().unwrap_or(""), cols.next());
            if first && a.parse::<f64>().is_err() {
                first = false;
                continue; // header
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
