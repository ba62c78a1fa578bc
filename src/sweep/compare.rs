//! Computed viscoelastic friction against measurements (paper Fig. 6): the
//! measured coefficient minus the interfacial Coulomb part `mu_C` (measured
//! at vanishing speed), `mu_V = mu - mu_C`, plotted with its standard
//! deviation over the computed `mu` of a merged sweep, against the speed.

use std::path::Path;

use crate::error::{Error, Result};
use crate::io::StagedOutput;
use crate::plot::{xy_chart, Mark, Series, XyChart};

use super::row::MergedRow;

/// One measured point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Measured {
    /// Sliding speed [m/s].
    pub speed: f64,
    /// Measured friction coefficient (total).
    pub mu: f64,
    /// Its standard deviation (0 when not given).
    pub std: f64,
}

/// Read a measured CSV: header with `speed_m_s`, `mu` and optionally
/// `mu_std`; lines starting with `#` are comments.
pub(crate) fn read_measured(path: &Path) -> Result<Vec<Measured>> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
    let name = path.display().to_string();
    let mut lines = text
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty() && !l.trim_start().starts_with('#'));
    let (_, header) = lines
        .next()
        .ok_or_else(|| Error::Invalid(format!("{name}: empty file")))?;
    let cols: Vec<String> = header
        .split(',')
        .map(|c| c.trim().to_ascii_lowercase())
        .collect();
    let find = |key: &str| cols.iter().position(|c| c == key);
    let (iv, im) = match (find("speed_m_s"), find("mu")) {
        (Some(v), Some(m)) => (v, m),
        _ => {
            return Err(Error::Invalid(format!(
                "{name}: the header needs columns `speed_m_s` and `mu` (optional `mu_std`), found {header:?}"
            )))
        }
    };
    let is = find("mu_std");
    let mut out = Vec::new();
    for (k, line) in lines {
        let cells: Vec<&str> = line.split(',').map(str::trim).collect();
        let num = |i: usize, what: &str| -> Result<f64> {
            cells
                .get(i)
                .and_then(|c| c.parse::<f64>().ok())
                .filter(|v| v.is_finite())
                .ok_or_else(|| {
                    Error::Invalid(format!(
                        "{name}: line {}: `{what}` is not a finite number",
                        k + 1
                    ))
                })
        };
        let speed = num(iv, "speed_m_s")?;
        if speed <= 0.0 {
            return Err(Error::Invalid(format!(
                "{name}: line {}: speed must be positive",
                k + 1
            )));
        }
        out.push(Measured {
            speed,
            mu: num(im, "mu")?,
            std: match is.map(|i| num(i, "mu_std")).transpose()? {
                Some(s) if s < 0.0 => {
                    return Err(Error::Invalid(format!(
                        "{name}: line {}: `mu_std` = {s} is negative (a standard deviation)",
                        k + 1
                    )))
                }
                s => s.unwrap_or(0.0),
            },
        });
    }
    if out.is_empty() {
        return Err(Error::Invalid(format!("{name}: no data rows")));
    }
    Ok(out)
}

/// One computed curve of the sweep: its label and `(v, mean mu, std)` by
/// increasing speed.
type Curve = (String, Vec<(f64, f64, f64)>);

/// The computed curves of `rows` (one per load and `[sweep.vary]`
/// combination, in plan order), their points with `v > 0`.
fn curves(rows: &[MergedRow]) -> Vec<Curve> {
    let mut out: Vec<Curve> = Vec::new();
    for r in rows.iter().filter(|r| r.speed > 0.0) {
        let label = r.curve_label();
        let point = (r.speed, r.friction.0, r.friction.1);
        match out.iter_mut().find(|(l, _)| *l == label) {
            Some((_, points)) => points.push(point),
            None => out.push((label, vec![point])),
        }
    }
    for (_, points) in &mut out {
        points.sort_by(|a, b| a.0.total_cmp(&b.0));
    }
    out
}

/// The curve's mean and standard deviation at speed `v`, linear in
/// `log v` between the computed speeds around it; `None` outside them.
fn at_speed(points: &[(f64, f64, f64)], v: f64) -> Option<(f64, f64)> {
    let k = points.iter().position(|p| p.0 >= v)?;
    let hi = points[k];
    if hi.0 == v {
        return Some((hi.1, hi.2));
    }
    let lo = points[k.checked_sub(1)?];
    let t = (v / lo.0).ln() / (hi.0 / lo.0).ln();
    Some((lo.1 + t * (hi.1 - lo.1), lo.2 + t * (hi.2 - lo.2)))
}

/// Write `compare.csv` and `compare.png` into the merged sweep `dir`: the
/// measured friction minus `coulomb` against every computed curve (one per
/// load and `[sweep.vary]` combination); with one curve, `compare.csv`
/// also gives the computed friction at the measured speeds.
pub fn compare(
    dir: &Path,
    measured_csv: &Path,
    coulomb: f64,
    observer: &mut dyn super::SweepObserver,
) -> Result<()> {
    if !(coulomb.is_finite() && coulomb >= 0.0) {
        return Err(Error::Invalid(format!(
            "--coulomb {coulomb} must be finite and >= 0 (the Coulomb friction coefficient subtracted from the measured one)"
        )));
    }
    let measured = read_measured(measured_csv)?;
    let (rows, _) = super::merge::aggregate(dir, observer)?;
    let curves = curves(&rows);
    if curves.is_empty() {
        return Err(Error::Invalid(format!(
            "{}: the sweep has no point with v > 0",
            dir.display()
        )));
    }
    let single = match curves.as_slice() {
        [(_, points)] => Some(points),
        _ => {
            observer.note(&format!(
                "the sweep has {} curves ({}): compare.png draws each; compare.csv gives the computed friction at the measured speeds only for a sweep of one load without [sweep.vary]",
                curves.len(),
                curves.iter().map(|c| c.0.as_str()).collect::<Vec<_>>().join("; ")
            ));
            None
        }
    };
    let mut csv = String::from("speed_m_s,mu_measured_minus_coulomb,mu_measured_std");
    if single.is_some() {
        csv.push_str(",mu_computed,mu_computed_std");
    }
    csv.push('\n');
    let mut outside = 0;
    for m in &measured {
        csv.push_str(&format!(
            "{:.8e},{:.8e},{:.8e}",
            m.speed,
            m.mu - coulomb,
            m.std
        ));
        if let Some(points) = single {
            match at_speed(points, m.speed) {
                Some((mu, std)) => csv.push_str(&format!(",{mu:.8e},{std:.8e}")),
                None => {
                    outside += 1;
                    csv.push_str(",,");
                }
            }
        }
        csv.push('\n');
    }
    if outside > 0 {
        let points = single.expect("counted with one curve");
        observer.note(&format!(
            "{outside} of {} measured speeds lie outside the computed ones ({:.4e} to {:.4e} m/s): their mu_computed is left empty",
            measured.len(),
            points[0].0,
            points[points.len() - 1].0
        ));
    }
    let mut staged = StagedOutput::for_study(dir, &["points"])?;
    staged.write("compare.csv", csv.as_bytes())?;
    let mut series = Vec::new();
    for (c, (label, points)) in curves.iter().enumerate() {
        let name = if single.is_some() {
            "computed mu_V".to_string()
        } else {
            format!("computed mu_V, {label}")
        };
        let mut model = Series::points(name, points.iter().map(|p| (p.0, p.1)).collect(), c + 2);
        model.mark = Mark::LineAndPoints;
        model.errors = Some(points.iter().map(|p| p.2).collect());
        series.push(model);
    }
    let mut meas = Series::points(
        format!("measured mu - mu_C (mu_C = {coulomb})"),
        measured.iter().map(|m| (m.speed, m.mu - coulomb)).collect(),
        0,
    );
    meas.errors = Some(measured.iter().map(|m| m.std).collect());
    series.push(meas);
    xy_chart(
        &staged.path("compare.png"),
        &XyChart {
            title: "Viscoelastic friction: computed and measured (paper Fig. 6)".into(),
            x_label: "v [m/s]".into(),
            y_label: "mu_V".into(),
            log_x: true,
            log_y: false,
            series,
        },
    )?;
    staged.commit()?;
    Ok(())
}
