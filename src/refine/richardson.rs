//! Richardson extrapolation of a quantity computed on a sequence of grids,
//! with the observed order of convergence and a verdict on whether the
//! sequence is in its asymptotic range.
//!
//! Model: `f(h) = f* + C h^p` for cell sizes `h` small enough (the
//! asymptotic range). Three levels `h1 > h2 > h3` determine `p` from
//! `(f1 - f2) / (f2 - f3) = (h1^p - h2^p) / (h2^p - h3^p)`; for grids of
//! ratio `r = h1/h2 = h2/h3` this is `p = log_r(|f1 - f2| / |f2 - f3|)`
//! (`log2` for ratio-2 grids), for other ratios the equation is solved for
//! `p` by bisection (its right-hand side increases with `p`). Then
//! `f* = f3 + (f3 - f2) / ((h2/h3)^p - 1)` and the error estimate of the
//! finest level is `|f* - f3|` (Richardson's estimate, the quantity Roache's
//! grid convergence index multiplies by a safety factor).

use serde::Serialize;

/// Controls of [`richardson`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RichardsonParams {
    /// Observed orders outside `[low, high]` mean the sequence is not in
    /// its asymptotic range (default 0.5..4: a discretisation of at most
    /// fourth order that converges at all).
    pub order_band: (f64, f64),
    /// Order assumed with only two levels (default 1: the slowest order in
    /// the band that piecewise-constant pressures on rough surfaces show,
    /// so the error estimate errs on the large side).
    pub assumed_order: f64,
    /// Relative changes below this (of the largest `|f|`) are at the
    /// precision of the solves (default 1e-6, two orders above what the
    /// default solver tolerance 1e-8 leaves in friction and area): a
    /// sequence whose last changes are all below it has converged.
    pub noise: f64,
}

impl Default for RichardsonParams {
    fn default() -> Self {
        Self {
            order_band: (0.5, 4.0),
            assumed_order: 1.0,
            noise: 1e-6,
        }
    }
}

/// What a refinement sequence says about its limit.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Verdict {
    /// Monotone differences, an observed order inside the band: the
    /// extrapolation and its error estimate can be trusted.
    Asymptotic,
    /// Not in the asymptotic range (non-monotone or growing differences,
    /// an order outside the band): no extrapolation; the error estimate is
    /// only the spread of the last levels.
    NotAsymptotic,
    /// The last levels agree to the precision of the solves.
    Converged,
    /// Two levels: the extrapolation uses an assumed order, not checked.
    AssumedOrder,
}

/// Richardson estimate of one quantity over the levels.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Richardson {
    pub verdict: Verdict,
    /// `true` for [`Verdict::Asymptotic`] and [`Verdict::Converged`],
    /// `false` for [`Verdict::NotAsymptotic`], `None` (unknown) with two
    /// levels.
    pub asymptotic: Option<bool>,
    /// Order observed on the finest three levels, where it exists.
    pub observed_order: Option<f64>,
    /// Order the extrapolation used (observed, or assumed with two levels).
    pub order_used: Option<f64>,
    /// Estimate of the grid-converged value; `None` when not asymptotic.
    pub extrapolated: Option<f64>,
    /// Value on the finest level.
    pub finest: f64,
    /// Estimated `|finest - limit|` (with [`Verdict::NotAsymptotic`]: the
    /// largest change over the last three levels, no bound).
    pub error_estimate: f64,
    /// `error_estimate / |extrapolated or finest|`.
    pub relative_error_estimate: f64,
    /// Observed order of each three consecutive levels, coarse to fine
    /// (`None` where the differences change sign or do not shrink).
    pub orders: Vec<Option<f64>>,
    /// The verdict in words, for the console and the report.
    pub message: String,
}

/// The order `p` with `(f1 - f2) / (f2 - f3) = (h1^p - h2^p) / (h2^p - h3^p)`
/// for cell sizes `h1 > h2 > h3`: `None` when the differences change sign
/// or vanish or do not shrink (no `p > 0`); `Some(p)` otherwise, with `p`
/// capped at 64.
pub fn observed_order(h: [f64; 3], f: [f64; 3]) -> Option<f64> {
    let (d1, d2) = (f[1] - f[0], f[2] - f[1]);
    if d1 == 0.0 || d2 == 0.0 || d1.signum() != d2.signum() {
        return None;
    }
    let q = d1 / d2;
    let (r21, r32) = (h[0] / h[1], h[1] / h[2]);
    if (r21 - r32).abs() <= 1e-12 * r32 {
        let p = q.ln() / r32.ln();
        return (p > 0.0).then_some(p.min(64.0));
    }
    // (x^p - y^p) / (y^p - 1) with x = h1/h3, y = h2/h3, increasing in p
    // from ln(x/y) / ln(y) at p -> 0.
    let (x, y) = (h[0] / h[2], h[1] / h[2]);
    let g = |p: f64| (x.powf(p) - y.powf(p)) / (y.powf(p) - 1.0);
    if q <= (x / y).ln() / y.ln() {
        return None;
    }
    let (mut lo, mut hi) = (1e-9, 64.0);
    if q >= g(hi) {
        return Some(hi);
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if g(mid) < q {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Some(0.5 * (lo + hi))
}

/// Richardson estimate of the quantity `values[k]` computed with cell size
/// `cell_sizes[k]` (strictly decreasing, at least two levels). The verdict
/// uses the finest three levels:
/// - both last changes below `noise` (relative): [`Verdict::Converged`];
/// - the changes change sign (non-monotone), do not shrink, only the last
///   one is below `noise`, or the observed order lies outside
///   `order_band`: [`Verdict::NotAsymptotic`], no extrapolation;
/// - otherwise [`Verdict::Asymptotic`], extrapolated with the observed order.
///
/// With two levels the order is assumed ([`RichardsonParams::assumed_order`]).
pub fn richardson(cell_sizes: &[f64], values: &[f64], params: &RichardsonParams) -> Richardson {
    assert!(
        cell_sizes.len() == values.len() && values.len() >= 2,
        "Richardson needs at least two levels"
    );
    let n = values.len();
    let finest = values[n - 1];
    let scale = values.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    let noise = params.noise * scale;
    let orders: Vec<Option<f64>> = (0..n.saturating_sub(2))
        .map(|k| {
            observed_order(
                [cell_sizes[k], cell_sizes[k + 1], cell_sizes[k + 2]],
                [values[k], values[k + 1], values[k + 2]],
            )
        })
        .collect();
    // Relative to `v` (the limit or the finest value); against a limit
    // smaller than the error itself (a contact area that shrinks with the
    // cells, one cell on every grid: a limit of zero), relative to the
    // finest value, whose whole size is then the error.
    let relative = |e: f64, v: f64| {
        let d = if v.abs() > e {
            v.abs()
        } else {
            v.abs().max(finest.abs())
        };
        if d > 0.0 {
            e / d
        } else {
            e
        }
    };
    let converged = |spread: f64, levels: usize| {
        Richardson {
        verdict: Verdict::Converged,
        asymptotic: Some(true),
        observed_order: None,
        order_used: None,
        extrapolated: Some(finest),
        finest,
        error_estimate: spread,
        relative_error_estimate: relative(spread, finest),
        orders: orders.clone(),
        message: format!(
            "converged: the last {levels} levels agree to {:.1e} (below the solve precision {:.0e} relative)",
            relative(spread, finest),
            params.noise
        ),
    }
    };
    if n == 2 {
        let d = values[1] - values[0];
        if d.abs() <= noise {
            return converged(d.abs(), 2);
        }
        let p = params.assumed_order;
        let r = cell_sizes[0] / cell_sizes[1];
        let e = d / (r.powf(p) - 1.0);
        let limit = finest + e;
        return Richardson {
            verdict: Verdict::AssumedOrder,
            asymptotic: None,
            observed_order: None,
            order_used: Some(p),
            extrapolated: Some(limit),
            finest,
            error_estimate: e.abs(),
            relative_error_estimate: relative(e.abs(), limit),
            orders,
            message: format!(
                "two levels only: order {p} assumed, not observed; whether the sequence is in its asymptotic range is unknown (a third level tells)"
            ),
        };
    }
    let (f1, f2, f3) = (values[n - 3], values[n - 2], values[n - 1]);
    let (d1, d2) = (f2 - f1, f3 - f2);
    if d1.abs() <= noise && d2.abs() <= noise {
        return converged(d1.abs().max(d2.abs()), 3);
    }
    let p = orders[n - 3];
    let (lo, hi) = params.order_band;
    let reason = if d2.abs() <= noise {
        Some("the last change is at the solve precision but the one before is not: a crossing cannot be told from convergence".to_string())
    } else if d1.signum() != d2.signum() {
        Some(format!(
            "non-monotone: the changes over the last three levels are {d1:+.3e} then {d2:+.3e}"
        ))
    } else if d2.abs() >= d1.abs() && p.is_none() {
        Some(format!(
            "the changes do not shrink: {d1:+.3e} then {d2:+.3e}"
        ))
    } else {
        match p {
            Some(p) if p < lo || p > hi => {
                Some(format!("observed order {p:.2} outside the band {lo}..{hi}"))
            }
            Some(_) => None,
            None => Some(format!(
                "no positive order fits the changes {d1:+.3e} then {d2:+.3e}"
            )),
        }
    };
    if let Some(reason) = reason {
        let spread = d1.abs().max(d2.abs());
        return Richardson {
            verdict: Verdict::NotAsymptotic,
            asymptotic: Some(false),
            observed_order: p,
            order_used: None,
            extrapolated: None,
            finest,
            error_estimate: spread,
            relative_error_estimate: relative(spread, finest),
            orders,
            message: format!(
                "NOT in the asymptotic range ({reason}); no extrapolation: the finest value is uncertain by at least the last changes (spread {spread:.3e}); refine further"
            ),
        };
    }
    let p = p.expect("an order exists when there is no reason against it");
    let r32 = cell_sizes[n - 2] / cell_sizes[n - 1];
    let e = d2 / (r32.powf(p) - 1.0);
    let limit = f3 + e;
    Richardson {
        verdict: Verdict::Asymptotic,
        asymptotic: Some(true),
        observed_order: Some(p),
        order_used: Some(p),
        extrapolated: Some(limit),
        finest,
        error_estimate: e.abs(),
        relative_error_estimate: relative(e.abs(), limit),
        orders,
        message: format!(
            "asymptotic: observed order {p:.2} (band {lo}..{hi}), monotone changes {d1:+.3e} then {d2:+.3e}"
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn seq(h: &[f64], limit: f64, c: f64, p: f64) -> Vec<f64> {
        h.iter().map(|h| limit + c * h.powf(p)).collect()
    }

    #[test]
    fn ratio_two_recovers_order_and_limit() {
        let h = [1.0 / 32.0, 1.0 / 64.0, 1.0 / 128.0];
        let f = seq(&h, 0.3, 5.0, 1.5);
        let r = richardson(&h, &f, &RichardsonParams::default());
        assert_eq!(r.verdict, Verdict::Asymptotic);
        assert!((r.observed_order.unwrap() - 1.5).abs() < 1e-10, "{r:?}");
        assert!((r.extrapolated.unwrap() - 0.3).abs() < 1e-12, "{r:?}");
    }

    #[test]
    fn other_ratios_recover_order_and_limit() {
        let h = [1.0 / 48.0, 1.0 / 64.0, 1.0 / 160.0, 1.0 / 256.0];
        for p in [0.7, 1.0, 2.0, 3.5] {
            // C h1^p = -2: every change well above the noise floor.
            let f = seq(&h, -0.1, -2.0 * 48f64.powf(p), p);
            let r = richardson(&h, &f, &RichardsonParams::default());
            assert_eq!(r.verdict, Verdict::Asymptotic, "{r:?}");
            assert!((r.observed_order.unwrap() - p).abs() < 1e-9, "{p}: {r:?}");
            assert!((r.extrapolated.unwrap() + 0.1).abs() < 1e-12, "{p}: {r:?}");
            for o in &r.orders {
                assert!((o.unwrap() - p).abs() < 1e-9);
            }
        }
    }

    /// One cell in contact on every grid: the area fraction is `h^2`, its
    /// limit 0, and the finest value is all error (it was reported as
    /// 0.01 %: the absolute error of 6.1e-5 taken for a relative one).
    #[test]
    fn a_limit_of_zero_has_the_finest_value_as_its_error() {
        let h = [1.0 / 32.0, 1.0 / 64.0, 1.0 / 128.0];
        let f: Vec<f64> = h.iter().map(|h| h * h).collect();
        let r = richardson(&h, &f, &RichardsonParams::default());
        assert!(r.extrapolated.unwrap().abs() < 1e-18, "{r:?}");
        assert!((r.relative_error_estimate - 1.0).abs() < 1e-9, "{r:?}");
    }

    #[test]
    fn non_monotone_and_out_of_band_are_flagged() {
        let h = [4.0, 2.0, 1.0];
        let r = richardson(&h, &[0.206, 0.238, 0.227], &RichardsonParams::default());
        assert_eq!(r.verdict, Verdict::NotAsymptotic);
        assert_eq!(r.asymptotic, Some(false));
        assert!(r.extrapolated.is_none());
        assert!(r.message.contains("non-monotone"), "{}", r.message);
        // Order 6: too fast to be this discretisation's.
        let f = seq(&h, 1.0, 1e-3, 6.0);
        let r = richardson(&h, &f, &RichardsonParams::default());
        assert_eq!(r.verdict, Verdict::NotAsymptotic);
        assert!((r.observed_order.unwrap() - 6.0).abs() < 1e-9);
        // Growing changes.
        let r = richardson(&h, &[1.0, 1.1, 1.3], &RichardsonParams::default());
        assert_eq!(r.verdict, Verdict::NotAsymptotic, "{r:?}");
    }

    #[test]
    fn two_levels_assume_the_order_and_equal_levels_converge() {
        let r = richardson(&[2.0, 1.0], &[1.2, 1.1], &RichardsonParams::default());
        assert_eq!(r.verdict, Verdict::AssumedOrder);
        assert_eq!(r.asymptotic, None);
        assert!((r.extrapolated.unwrap() - 1.0).abs() < 1e-12);
        let r = richardson(
            &[4.0, 2.0, 1.0],
            &[0.5, 0.5 + 1e-9, 0.5 - 1e-9],
            &RichardsonParams::default(),
        );
        assert_eq!(r.verdict, Verdict::Converged);
        assert_eq!(r.extrapolated, Some(0.5 - 1e-9));
    }
}
