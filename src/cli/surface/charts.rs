//! The PSD charts of the surface commands: log-log axes drawn in units of
//! `10^k` with the largest value in [1, 10) (plotters places no ticks on
//! log axes over very small values).

use std::path::Path;

use crate::error::Result;
use crate::plot::{self, Series, XyChart};
use crate::surface::{RadialPsd, SelfAffinePsd};

/// `(x, y)` points of two columns.
pub(super) fn pairs(x: &[f64], y: &[f64]) -> Vec<(f64, f64)> {
    x.iter().zip(y).map(|(a, b)| (*a, *b)).collect()
}

/// The exponent `k` with `peak` in `[10^k, 10^(k+1))` (0 for no positive
/// peak) and `10^k`.
fn decade(peak: f64) -> (f64, f64) {
    let k = if peak > 0.0 {
        peak.log10().floor()
    } else {
        0.0
    };
    (k, 10f64.powf(k))
}

/// The y label of a PSD axis in units of `10^k unit`.
fn c_label(k: f64, unit: &str) -> String {
    if k == 0.0 {
        format!("C(q) [{unit}]")
    } else {
        format!("C(q) [1e{k} {unit}]")
    }
}

/// A log-log chart of positive values, drawn in units of 10^k `unit` with
/// the largest value in [1, 10) (plotters places no ticks on log axes over
/// very small values).
pub(super) fn log_plot(
    path: &Path,
    title: &str,
    unit: &str,
    mut series: Vec<Series>,
) -> Result<()> {
    let peak = series
        .iter()
        .flat_map(|s| s.points.iter().map(|p| p.1))
        .fold(0.0, f64::max);
    let floor = peak * 1e-14;
    let (k, scale) = decade(peak);
    for s in &mut series {
        s.points.retain(|p| p.1 > floor && p.0 > 0.0);
        for p in &mut s.points {
            p.1 /= scale;
        }
    }
    series.retain(|s| !s.points.is_empty());
    let chart = XyChart {
        title: title.into(),
        x_label: "q [1/m]".into(),
        y_label: c_label(k, unit),
        log_x: true,
        log_y: true,
        series,
    };
    plot::xy_chart(path, &chart)?;
    Ok(())
}

/// The radial average of a PSD and, if given, the self-affine target.
pub(super) fn psd_plot(
    path: &Path,
    radial: &RadialPsd,
    target: Option<&SelfAffinePsd>,
    title: &str,
) -> Result<()> {
    // Modes outside the band hold FFT round-off (~1e-30 of the peak); keep
    // them off the log axis.
    let peak = radial.c.iter().copied().fold(0.0, f64::max);
    let floor = peak * 1e-12;
    // The log axis is drawn in units of 10^k m^4 with the peak in [1, 10):
    // plotters places no ticks on log axes over very small values.
    let (k, unit) = decade(peak);
    let measured: Vec<(f64, f64)> = radial
        .q
        .iter()
        .zip(&radial.c)
        .filter(|(_, c)| **c > floor)
        .map(|(q, c)| (*q, *c / unit))
        .collect();
    let mut series = vec![Series::points("radial average", measured, 2)];
    if let Some(t) = target {
        let line: Vec<(f64, f64)> = radial
            .q
            .iter()
            .map(|&q| (q, t.eval_radial(q) / unit))
            .filter(|p| p.1 > 0.0)
            .collect();
        series.push(Series::line(format!("target, H = {}", t.hurst), line, 0));
    }
    let chart = XyChart {
        title: title.into(),
        x_label: "q [1/m]".into(),
        y_label: c_label(k, "m^4"),
        log_x: true,
        log_y: true,
        series,
    };
    plot::xy_chart(path, &chart)?;
    Ok(())
}
