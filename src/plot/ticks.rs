//! The labelled ticks of a chart axis, chosen so that their labels never
//! run into each other: on a log axis the decades (every second, third,
//! fifth ... decade where they would crowd; 1, 2 and 5 times each decade
//! where only two decades are in range and those fit), or, on an axis
//! that spans less than two decades, the mantissas 1..9 or 1-2-5 of each
//! decade, or evenly stepped values where even those give fewer than two
//! labels; on
//! a linear axis evenly stepped values (steps of 1, 2 or 5 times a power
//! of ten). Every label is written with as few digits as tell the ticks
//! apart.

/// Pixels kept free between two neighbouring labels.
pub const LABEL_GAP: f64 = 8.0;

/// Most labels on one axis.
const MAX_LABELS: usize = 12;

/// The ticks of one axis: the labelled ones (`major`, with their labels)
/// and the unlabelled grid lines between them (`minor`).
#[derive(Debug, Clone, PartialEq)]
pub struct Ticks {
    pub major: Vec<f64>,
    pub labels: Vec<String>,
    pub minor: Vec<f64>,
}

impl Ticks {
    /// The label of tick `v` (one of `major`), else `v` written compactly.
    pub fn label(&self, v: f64) -> String {
        self.major
            .iter()
            .position(|&m| m == v)
            .map(|k| self.labels[k].clone())
            .unwrap_or_else(|| super::format_tick(v))
    }
}

/// Position of `v` on an axis from `lo` to `hi` that is `length` pixels
/// long.
pub fn pixel(v: f64, lo: f64, hi: f64, log: bool, length: f64) -> f64 {
    if log {
        (v / lo).ln() / (hi / lo).ln() * length
    } else {
        (v - lo) / (hi - lo) * length
    }
}

/// Whether labels at `ticks` fit on the axis: each pair of neighbours at
/// least half of both labels' extents plus [`LABEL_GAP`] apart.
/// `extent(label)` is the size of a label along the axis in pixels (its
/// width on a horizontal axis, its height on a vertical one).
pub fn labels_fit(
    ticks: &[f64],
    labels: &[String],
    lo: f64,
    hi: f64,
    log: bool,
    length: f64,
    extent: &dyn Fn(&str) -> f64,
) -> bool {
    ticks.len() <= MAX_LABELS
        && ticks.windows(2).zip(labels.windows(2)).all(|(t, l)| {
            let d = pixel(t[1], lo, hi, log, length) - pixel(t[0], lo, hi, log, length);
            d >= 0.5 * (extent(&l[0]) + extent(&l[1])) + LABEL_GAP
        })
}

/// The ticks of an axis from `lo` to `hi` (`0 < lo < hi` on a log axis)
/// that is `length` pixels long, whose labels take `extent(label)` pixels
/// along it. On a log axis that spans less than a decade there are at
/// least two labels whenever two fit at all.
pub fn axis_ticks(lo: f64, hi: f64, log: bool, length: f64, extent: &dyn Fn(&str) -> f64) -> Ticks {
    let fits = |t: &[f64], l: &[String]| labels_fit(t, l, lo, hi, log, length, extent);
    if !(lo.is_finite() && hi.is_finite() && hi > lo && (!log || lo > 0.0)) {
        return Ticks {
            major: Vec::new(),
            labels: Vec::new(),
            minor: Vec::new(),
        };
    }
    if log {
        let (k0, k1) = (
            (lo.log10() - 1e-9).ceil() as i32,
            (hi.log10() + 1e-9).floor() as i32,
        );
        let decades: Vec<i32> = (k0..=k1).collect();
        let in_range = |v: &f64| *v >= lo * (1.0 - 1e-12) && *v <= hi * (1.0 + 1e-12);
        let minor: Vec<f64> = if hi / lo < 1e8 {
            ((k0 - 1)..=k1)
                .flat_map(|k| (1..10).map(move |m| m as f64 * 10f64.powi(k)))
                .filter(in_range)
                .collect()
        } else {
            Vec::new()
        };
        let mantissa_ticks = |mantissas: &[i32]| -> (Vec<f64>, Vec<String>) {
            let major: Vec<f64> = ((k0 - 1)..=k1)
                .flat_map(|k| mantissas.iter().map(move |&m| f64::from(m) * 10f64.powi(k)))
                .filter(in_range)
                .collect();
            let labels = tick_labels(&major);
            (major, labels)
        };
        if decades.len() == 2 {
            // Two decades only: 1-2-5 between them where that fits.
            let (major, labels) = mantissa_ticks(&[1, 2, 5]);
            if fits(&major, &labels) {
                return Ticks {
                    major,
                    labels,
                    minor,
                };
            }
        }
        if decades.len() >= 2 {
            // Every s-th decade, aligned on multiples of s where that
            // leaves two labels.
            for s in [1, 2, 3, 5, 10, 20, 50, 100] {
                let mut pick: Vec<i32> = decades.iter().copied().filter(|k| k % s == 0).collect();
                if pick.len() < 2 {
                    pick = decades.iter().copied().step_by(s as usize).collect();
                }
                let major: Vec<f64> = pick.iter().map(|&k| 10f64.powi(k)).collect();
                let labels = tick_labels(&major);
                if fits(&major, &labels) || s == 100 {
                    let minor = if s == 1 {
                        minor
                    } else {
                        decade_minor(&pick, &decades)
                    };
                    return Ticks {
                        major,
                        labels,
                        minor,
                    };
                }
            }
        }
        // Less than two decades: the mantissas of each decade, densest
        // first, while they fit and give two labels.
        for mantissas in [&[1, 2, 3, 4, 5, 6, 7, 8, 9][..], &[1, 2, 5], &[1]] {
            let (major, labels) = mantissa_ticks(mantissas);
            if major.len() >= 2 && fits(&major, &labels) {
                return Ticks {
                    major,
                    labels,
                    minor,
                };
            }
        }
        // Narrower still: evenly stepped values, as on a linear axis.
        let mut t = linear_ticks(lo, hi, &fits);
        t.minor = minor;
        return t;
    }
    linear_ticks(lo, hi, &fits)
}

/// Decades between the labelled ones, as grid lines.
fn decade_minor(picked: &[i32], decades: &[i32]) -> Vec<f64> {
    decades
        .iter()
        .filter(|k| !picked.contains(k))
        .map(|&k| 10f64.powi(k))
        .collect()
}

/// Evenly stepped ticks (steps of 1, 2, 2.5 or 5 times a power of ten),
/// the densest whose labels fit and that has at least two; grid lines at
/// a fifth of the step.
fn linear_ticks(lo: f64, hi: f64, fits: &dyn Fn(&[f64], &[String]) -> bool) -> Ticks {
    let span = hi - lo;
    let p = 10f64.powf((span / MAX_LABELS as f64).log10().floor() - 1.0);
    let mut best = None;
    'steps: for decade in 0..6 {
        for m in [1.0, 2.0, 2.5, 5.0] {
            let step = m * p * 10f64.powi(decade);
            let first = (lo / step - 1e-9).ceil() as i64;
            let last = (hi / step + 1e-9).floor() as i64;
            if last - first + 1 > MAX_LABELS as i64 {
                continue;
            }
            let major: Vec<f64> = (first..=last)
                .map(|k| snap(k as f64 * step, step))
                .collect();
            let labels = tick_labels(&major);
            if major.len() >= 2 && fits(&major, &labels) {
                let fine = step / 5.0;
                let minor = ((lo / fine).ceil() as i64..=(hi / fine).floor() as i64)
                    .map(|k| k as f64 * fine)
                    .collect();
                best = Some(Ticks {
                    major,
                    labels,
                    minor,
                });
                break 'steps;
            }
            if major.len() < 2 {
                break 'steps;
            }
        }
    }
    best.unwrap_or_else(|| {
        // Not even two labels fit: the ends of the axis if they do, else
        // its middle alone.
        let ends = vec![lo, hi];
        let labels = tick_labels(&ends);
        let major = if fits(&ends, &labels) {
            ends
        } else {
            vec![0.5 * (lo + hi)]
        };
        Ticks {
            labels: tick_labels(&major),
            major,
            minor: Vec::new(),
        }
    })
}

/// `v` with the round-off of `k * step` removed (zero stays zero).
fn snap(v: f64, step: f64) -> f64 {
    if v.abs() < 1e-9 * step {
        0.0
    } else {
        v
    }
}

/// Labels for `ticks`: the fewest significant digits (1 to 15) with which
/// the labels differ and each reads back as its tick.
pub fn tick_labels(ticks: &[f64]) -> Vec<String> {
    let scale = ticks.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    for digits in 1..=15 {
        let labels: Vec<String> = ticks.iter().map(|&v| format_digits(v, digits)).collect();
        let distinct = labels
            .iter()
            .enumerate()
            .all(|(k, l)| !labels[..k].contains(l));
        let exact = ticks.iter().zip(&labels).all(|(&v, l)| {
            l.parse::<f64>()
                .is_ok_and(|r| (r - v).abs() <= 1e-9 * v.abs().max(1e-6 * scale))
        });
        if distinct && exact {
            return labels;
        }
    }
    ticks.iter().map(|&v| format_digits(v, 17)).collect()
}

/// `v` with `digits` significant digits, trailing zeros dropped: plain for
/// magnitudes in `[1e-2, 1e4)`, else scientific (`2.5e6`, `1e-4`).
pub fn format_digits(v: f64, digits: usize) -> String {
    let a = v.abs();
    if v == 0.0 {
        return "0".into();
    }
    let digits = digits.max(1);
    if (1e-2..1e4).contains(&a) {
        let exponent = a.log10().floor() as i32;
        let decimals = (digits as i32 - 1 - exponent).max(0) as usize;
        let s = format!("{v:.decimals$}");
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    } else {
        let s = format!("{v:.prec$e}", prec = digits - 1);
        match s.split_once('e') {
            Some((m, e)) if m.contains('.') => {
                format!("{}e{e}", m.trim_end_matches('0').trim_end_matches('.'))
            }
            _ => s,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Label widths of the 14-pixel DejaVu Sans of the charts, measured.
    fn width(label: &str) -> f64 {
        super::super::label_extent(label, 14.0).0
    }

    fn check(lo: f64, hi: f64, log: bool, length: f64) -> Ticks {
        let t = axis_ticks(lo, hi, log, length, &width);
        assert_eq!(t.major.len(), t.labels.len());
        for w in t.major.windows(2) {
            assert!(w[1] > w[0], "{lo}..{hi}: {:?}", t.major);
        }
        for (k, w) in t.labels.windows(2).enumerate() {
            let d =
                pixel(t.major[k + 1], lo, hi, log, length) - pixel(t.major[k], lo, hi, log, length);
            assert!(
                d >= 0.5 * (width(&w[0]) + width(&w[1])),
                "{lo}..{hi} on {length} px: {:?} at {d} px",
                t.labels
            );
        }
        for &m in &t.major {
            let slack = if log { 1e-9 * lo } else { 1e-9 * (hi - lo) };
            assert!(m >= lo - slack && m <= hi + slack, "{m} outside {lo}..{hi}");
        }
        t
    }

    #[test]
    fn log_axes_label_decades_without_overlap() {
        // The magnification chart of issue 42: q1 from 5e6 to 9e6 with
        // the chart's margins, where "5.0e66.0e7.0e8.0e6" ran together.
        let t = check(5e6 / 1.3, 9e6 * 1.3, true, 690.0);
        assert!(t.major.len() >= 2, "{:?}", t.labels);
        assert!(
            t.major.iter().any(|&v| v < 1e7),
            "the lower decade has a label: {:?}",
            t.labels
        );
        // Spans of a few to many decades, wide and narrow axes.
        for (lo, hi) in [
            (1e-4, 1.0),
            (7.7e-5, 1.3),
            (700.0, 2.6e4),
            (1e-30, 1e30),
            (3.3e-3, 4.2e-1),
            (1e-12, 1e-11),
            (4.6e3, 2.6e4),
        ] {
            for length in [80.0, 300.0, 690.0] {
                check(lo, hi, true, length);
            }
        }
        // Every span under a decade keeps two labels on a chart-sized axis.
        let mut lo = 1.0;
        while lo < 100.0 {
            for ratio in [1.05, 1.3, 1.69, 2.5, 4.0, 9.9] {
                let t = check(lo, lo * ratio, true, 690.0);
                assert!(t.major.len() >= 2, "{lo} x {ratio}: {:?}", t.labels);
                let t = check(lo, lo * ratio, true, 340.0);
                assert!(t.major.len() >= 2, "{lo} x {ratio}: {:?}", t.labels);
            }
            lo *= 1.37;
        }
    }

    #[test]
    fn linear_axes_label_without_overlap_and_with_enough_digits() {
        for (lo, hi) in [
            (0.0, 1.0),
            (-0.05, 1.05),
            (2.5e-3, 7.5e-3),
            (0.0755, 0.1205),
            (1.0e5, 1.0000001e5),
            (-3.0e-7, 2.0e-7),
        ] {
            for length in [120.0, 340.0, 690.0] {
                let t = check(lo, hi, false, length);
                assert!(
                    t.major.len() >= 2 || length < 300.0,
                    "{lo}..{hi}: {:?}",
                    t.labels
                );
                let mut sorted = t.labels.clone();
                sorted.dedup();
                assert_eq!(sorted.len(), t.labels.len(), "{:?}", t.labels);
            }
        }
    }

    #[test]
    fn labels_read_back_as_their_ticks() {
        assert_eq!(tick_labels(&[1e6, 1e7]), vec!["1e6", "1e7"]);
        assert_eq!(tick_labels(&[5e6, 6e6, 7e6]), vec!["5e6", "6e6", "7e6"]);
        assert_eq!(
            tick_labels(&[0.1, 0.125, 0.15]),
            vec!["0.1", "0.125", "0.15"]
        );
        assert_eq!(
            tick_labels(&[0.0, 2.5e-3, 5e-3]),
            vec!["0", "2.5e-3", "5e-3"]
        );
        assert_eq!(tick_labels(&[1000.0, 1e4]), vec!["1000", "1e4"]);
    }
}
