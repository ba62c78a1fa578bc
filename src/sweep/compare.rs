//! Computed viscoelastic friction against measurements (paper Fig. 6): the
//! measured coefficient minus the interfacial Coulomb part `mu_C` (measured
//! at vanishing speed), `mu_V = mu - mu_C`, plotted with its standard
//! deviation over the computed `mu` of a merged sweep, against the speed.

use std::path::Path;

use crate::error::{Error, Result};
use crate::io::StagedOutput;
use crate::plot::{xy_chart, Mark, Series, XyChart};

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
            std: is.map(|i| num(i, "mu_std")).transpose()?.unwrap_or(0.0),
        });
    }
    if out.is_empty() {
        return Err(Error::Invalid(format!("{name}: no data rows")));
    }
    Ok(out)
}

/// Write `compare.csv` and `compare.png` into the merged sweep `dir`.
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
    let computed: Vec<(f64, f64, f64)> = rows
        .iter()
        .filter(|r| r.speed > 0.0)
        .map(|r| (r.speed, r.friction.0, r.friction.1))
        .collect();
    if computed.is_empty() {
        return Err(Error::Invalid(format!(
            "{}: the sweep has no point with v > 0",
            dir.display()
        )));
    }
    let mut csv = String::from("speed_m_s,mu_measured_minus_coulomb,mu_measured_std\n");
    for m in &measured {
        csv.push_str(&format!(
            "{:.8e},{:.8e},{:.8e}\n",
            m.speed,
            m.mu - coulomb,
            m.std
        ));
    }
    let mut staged = StagedOutput::for_study(dir, &["points"])?;
    staged.write("compare.csv", csv.as_bytes())?;
    let mut model = Series::points(
        "computed mu_V",
        computed.iter().map(|c| (c.0, c.1)).collect(),
        2,
    );
    model.mark = Mark::LineAndPoints;
    model.errors = Some(computed.iter().map(|c| c.2).collect());
    let mut meas = Series::points(
        format!("measured mu - mu_C (mu_C = {coulomb})"),
        measured.iter().map(|m| (m.speed, m.mu - coulomb)).collect(),
        0,
    );
    meas.errors = Some(measured.iter().map(|m| m.std).collect());
    xy_chart(
        &staged.path("compare.png"),
        &XyChart {
            title: "Viscoelastic friction: computed and measured (paper Fig. 6)".into(),
            x_label: "v [m/s]".into(),
            y_label: "mu_V".into(),
            log_x: true,
            log_y: false,
            series: vec![model, meas],
        },
    )?;
    staged.commit()?;
    Ok(())
}
