//! Warnings on a spectrum fit whose result may mislead
//! ([`fit_warnings`]): columns the reader left out, data of several
//! temperatures merged at one, a fit that misses its data, and data that
//! reach neither plateau, so that `E0` or `E_inf` is an extrapolation.
//! `material fit` prints each (stderr) and records them in `[fit]
//! warnings`; Python's `Material.fit_dma` warns of each and returns them.

use super::{DmaData, DmaPoint, SpectrumFit};

/// The rms relative error of `E1` or `E2` above which a fit is said to
/// miss its data: 10 %. The shipped data (`configs/data/sbr_like_dma.csv`,
/// all temperatures shifted by WLF) fit to 1.0 % and 0.97 % with the
/// default 34 times, and DMA instruments report moduli to a few percent;
/// ten times that is a spectrum that does not describe the data (too few
/// terms, or data that are not one material at one temperature).
pub(crate) const RMS_ERROR_WARN: f64 = 0.10;

/// The factor between moduli of one frequency at one temperature above
/// which the data are said to merge several temperatures: 2. Repeats of
/// one measurement scatter by percents; the shipped data's `E1` at 1 Hz
/// spans 5 MPa to 1 GPa over -20 to 100 C, so merged temperatures differ
/// by far more.
pub(crate) const REPEAT_FACTOR_WARN: f64 = 2.0;

/// The loss tangent of the fit at the data's lowest or highest frequency
/// above which the data are said not to reach the rubbery or the glassy
/// plateau: 0.05. The shipped master curve at 17 C has 0.024 at its
/// highest frequency (7.5e7 rad/s) and less at its lowest.
pub(crate) const PLATEAU_TAN_DELTA: f64 = 0.05;

/// The ratio of the fit's `E_inf` to its `E1` at the highest data
/// frequency above which `E_inf` is said to lie beyond the data: 2 (the
/// shipped master curve: 1.01).
pub(crate) const GLASSY_RATIO_WARN: f64 = 2.0;

/// Every warning on the fit `fit` of `data`, in the order: the data's own
/// ([`DmaData::warnings`]), merged temperatures, the fit's error, the
/// rubbery end, the glassy end.
pub fn fit_warnings(data: &DmaData, fit: &SpectrumFit) -> Vec<String> {
    let mut out = data.warnings.clone();
    out.extend(merged_temperatures(&data.points));
    let i = &fit.info;
    let worst = i.rms_relative_storage.max(i.rms_relative_loss);
    if worst > RMS_ERROR_WARN {
        out.push(format!(
            "the fit misses its data: rms relative error E1 {:.1} %, E2 {:.1} % (above {:.0} %); its moduli do not describe the data (more --terms, or data of one material at one temperature)",
            100.0 * i.rms_relative_storage,
            100.0 * i.rms_relative_loss,
            100.0 * RMS_ERROR_WARN
        ));
    }
    let [wmin, wmax] = i.frequency_range;
    if i.tan_delta_at_lowest_frequency > PLATEAU_TAN_DELTA {
        out.push(format!(
            "tan delta = {:.3} at the lowest data frequency {wmin:.3e} rad/s (above {PLATEAU_TAN_DELTA}): the data do not reach the rubbery plateau, so the fit's E0 = {:.3e} Pa and its moduli below the data are extrapolations",
            i.tan_delta_at_lowest_frequency,
            fit.creep.relaxed_modulus()
        ));
    }
    let einf = fit.creep.glassy_modulus;
    let ratio = einf / i.storage_at_highest_frequency;
    if i.tan_delta_at_highest_frequency > PLATEAU_TAN_DELTA || ratio > GLASSY_RATIO_WARN {
        let times = if ratio < 1e3 {
            format!("{ratio:.2}")
        } else {
            format!("{ratio:.2e}")
        };
        out.push(format!(
            "tan delta = {:.3} at the highest data frequency {wmax:.3e} rad/s, where the fit's E1 = {:.3e} Pa: the data do not reach the glassy plateau, so the fit's E_inf = {einf:.3e} Pa ({times} times that E1) and its moduli above the data are extrapolations",
            i.tan_delta_at_highest_frequency, i.storage_at_highest_frequency
        ));
    }
    out
}

/// Where one angular frequency at one temperature (or in data without
/// temperatures) carries moduli that differ by more than
/// [`REPEAT_FACTOR_WARN`], the warning naming the largest such spread:
/// data of several temperatures read as one.
pub fn merged_temperatures(points: &[DmaPoint]) -> Option<String> {
    let key = |p: &DmaPoint| (p.temperature.map(f64::to_bits), p.omega.to_bits());
    let mut sorted: Vec<&DmaPoint> = points.iter().collect();
    sorted.sort_by(|a, b| {
        let (ta, tb) = (a.temperature.unwrap_or(0.0), b.temperature.unwrap_or(0.0));
        ta.total_cmp(&tb).then(a.omega.total_cmp(&b.omega))
    });
    // The largest factor and its warning.
    let mut worst: Option<(f64, String)> = None;
    for run in sorted.chunk_by(|a, b| key(a) == key(b)) {
        for (which, value) in [
            ("E1", (|p: &DmaPoint| p.storage) as fn(&DmaPoint) -> f64),
            ("E2", |p: &DmaPoint| p.loss),
        ] {
            let lo = run.iter().map(|p| value(p)).fold(f64::INFINITY, f64::min);
            let hi = run.iter().map(|p| value(p)).fold(0.0, f64::max);
            let factor = hi / lo;
            if factor > REPEAT_FACTOR_WARN && worst.as_ref().is_none_or(|w| factor > w.0) {
                let at = run[0].temperature.map_or_else(
                    || "in data without a temperature_c column".to_string(),
                    |t| format!("at {t} C"),
                );
                let omega = run[0].omega;
                worst = Some((
                    factor,
                    format!(
                        "the frequency {omega:.4e} rad/s {at} carries {which} from {lo:.3e} to {hi:.3e} Pa ({factor:.0} times): data of several temperatures merged? give each point's temperature in C in a temperature_c column (with --wlf)"
                    ),
                ));
            }
        }
    }
    worst.map(|(_, warning)| warning)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn point(omega: f64, storage: f64, temperature: Option<f64>) -> DmaPoint {
        DmaPoint {
            omega,
            storage,
            loss: 0.1 * storage,
            temperature,
        }
    }

    #[test]
    fn repeats_that_differ_by_a_large_factor_are_merged_temperatures() {
        // Repeats within scatter, and different temperatures: nothing.
        let fine = [
            point(1.0, 1e7, Some(0.0)),
            point(1.0, 1.05e7, Some(0.0)),
            point(1.0, 1e9, Some(-20.0)),
        ];
        assert_eq!(merged_temperatures(&fine), None);
        let merged = [
            point(1.0, 5e6, None),
            point(10.0, 6e6, None),
            point(1.0, 1e9, None),
        ];
        let w = merged_temperatures(&merged).unwrap();
        assert!(
            w.contains("1.0000e0 rad/s in data without a temperature_c column")
                && w.contains("from 5.000e6 to 1.000e9 Pa (200 times)"),
            "{w}"
        );
    }
}
