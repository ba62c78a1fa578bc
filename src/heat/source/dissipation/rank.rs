//! The creep elements' stress-rate multipliers combined into fewer
//! (physics.md section 14, the dissipation density).
//!
//! `D` is the dissipation form of the vector `F(x)` of the elements' rate
//! fields, `F_k` the field of the multiplier `g_k(w) = sqrt(tau_k C_k) i w
//! / (1 + i w tau_k)`; being a sum of squares over the elements it is `|F|^2`
//! per component. For an orthonormal basis `V` (columns `v_j`) of a subspace
//! of the element space, the combined multipliers `h_j = sum_k V_kj g_k`
//! give `sum_j |v_j . F|^2 = |P F|^2`, `P = V V^T`: `D` minus `|(I - P) F|^2`,
//! never more than `D` at any point.
//!
//! `V` is the leading right singular vectors of the matrix whose rows are
//! the real and imaginary parts of `g(w) / |g(w)|` over every frequency
//! `|w|` the grid meets. Every row then loses at most `s^2` of its squared
//! norm to `I - P`, `s` the largest singular value dropped, so each
//! mode's power (its depth integral, hence the grid sum of `D` mode by
//! mode) changes by at most `2 s^2` relative, and `D` pointwise by at
//! most `2 s^2 (sum_q |g(w_q)| |A_q|)^2`, `A_q` the mode's stress
//! amplitude: second order in `s`. [`RANK_CUT`] keeps `2 s^2` at 2e-15,
//! round-off.

use faer::Mat;

use super::super::super::error::HeatError;
use num_complex::Complex64;

/// Singular values whose square lies below this are dropped (rows of unit
/// norm): each mode's power changes by at most twice this, relative.
pub(super) const RANK_CUT: f64 = 1e-15;

/// Rows per block of the running QR (bounds its memory on large grids).
const BLOCK_ROWS: usize = 4096;

/// A stress-rate multiplier `sum_k a_k i w / (1 + i w tau_k)` \[1/s\]
/// (`(a_k, tau_k)`): one element's rate times `sqrt(tau_k C_k)`, whose
/// dissipation form is the element's share of `D`.
#[derive(Clone, Debug)]
pub(crate) struct RateFn(pub Vec<(f64, f64)>);

impl RateFn {
    /// The multiplier at `w` \[rad/s\], term by term ([`rate_term`]).
    pub(super) fn at(&self, w: f64) -> Complex64 {
        self.0
            .iter()
            .map(|&(a, tau)| {
                let (re, im) = rate_term(a, tau, w);
                Complex64::new(re, im)
            })
            .sum()
    }
}

/// `a i w / (1 + i w tau)`: real and imaginary parts, as `(a / tau) (x^2,
/// x) / (1 + x^2)` with `x = w tau`, divided through by `x^2` where `|x| >
/// 1` so that no square overflows (frequencies up to f64's range: `v |q|`
/// of a very fast slide).
fn rate_term(a: f64, tau: f64, w: f64) -> (f64, f64) {
    let g = a / tau;
    let x = w * tau;
    if x.abs() > 1.0 {
        let y = 1.0 / x;
        let d = 1.0 + y * y;
        (g / d, g * y / d)
    } else {
        let d = 1.0 + x * x;
        (g * x * x / d, g * x / d)
    }
}

/// One element's multiplier `sqrt(tau C) i w / (1 + i w tau)`: real and
/// imaginary parts ([`rate_term`]).
fn element_rate(c: f64, tau: f64, w: f64) -> (f64, f64) {
    rate_term((tau * c).sqrt(), tau, w)
}

/// The combined multipliers of the elements `(C_k, tau_k)` over the
/// frequencies `|w|` of `freqs` \[rad/s\] (module docs), in decreasing
/// singular value; none where no frequency is positive.
pub(super) fn combined_rates(
    elements: &[(f64, f64)],
    freqs: &[f64],
) -> Result<Vec<RateFn>, HeatError> {
    let n = elements.len();
    let freqs: Vec<f64> = freqs.iter().copied().filter(|w| *w > 0.0).collect();
    if n == 0 || freqs.is_empty() {
        return Ok(Vec::new());
    }
    // A running QR: `R` of the rows seen so far stacked over each block.
    let mut r = Mat::<f64>::zeros(0, n);
    for block in freqs.chunks(BLOCK_ROWS / 2) {
        let top = r.nrows();
        let mut m = Mat::<f64>::zeros(top + 2 * block.len(), n);
        for i in 0..top {
            for k in 0..n {
                m[(i, k)] = r[(i, k)];
            }
        }
        for (b, &w) in block.iter().enumerate() {
            let g: Vec<(f64, f64)> = elements
                .iter()
                .map(|&(c, tau)| element_rate(c, tau, w))
                .collect();
            let norm = g.iter().map(|(a, b)| a * a + b * b).sum::<f64>().sqrt();
            for (k, (re, im)) in g.iter().enumerate() {
                m[(top + 2 * b, k)] = re / norm;
                m[(top + 2 * b + 1, k)] = im / norm;
            }
        }
        r = m.qr().thin_R().to_owned();
    }
    let svd = r.thin_svd().map_err(|e| {
        HeatError::OutOfRange(format!(
            "the creep elements' rates over the grid's frequencies (up to {:e} rad/s) could not be combined ({e:?}): a frequency or an element beyond the range of f64's arithmetic",
            freqs.iter().copied().fold(0.0, f64::max)
        ))
    })?;
    let (s, v) = (svd.S().column_vector(), svd.V());
    let mut order: Vec<usize> = (0..s.nrows()).collect();
    order.sort_by(|&a, &b| s[b].total_cmp(&s[a]));
    Ok(order
        .into_iter()
        .filter(|&j| s[j] * s[j] > RANK_CUT)
        .map(|j| {
            RateFn(
                elements
                    .iter()
                    .enumerate()
                    .map(|(k, &(c, tau))| (v[(k, j)] * (tau * c).sqrt(), tau))
                    .collect(),
            )
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// At every frequency given (and between them on the SBR-like
    /// spectrum's range), the combined multipliers' squared norm is the
    /// elements' to `2 RANK_CUT` relative plus round-off, and never above
    /// it beyond round-off; fewer multipliers than elements when the
    /// elements' responses overlap.
    #[test]
    fn combined_rates_keep_every_frequency_s_power() {
        // 24 elements, two per decade from 1e-8 s to 1e4 s.
        let elements: Vec<(f64, f64)> = (0..24)
            .map(|k| {
                (
                    1e-9 * (1.0 + (k % 5) as f64),
                    1e-8 * 10f64.powf(k as f64 / 2.0),
                )
            })
            .collect();
        let freqs: Vec<f64> = (1..=512).map(|k| 2.5 * k as f64).collect();
        let combined = combined_rates(&elements, &freqs).unwrap();
        assert!(combined.len() < elements.len(), "{}", combined.len());
        let singles: Vec<RateFn> = elements
            .iter()
            .map(|&(c, tau)| RateFn(vec![((tau * c).sqrt(), tau)]))
            .collect();
        let power =
            |rates: &[RateFn], w: f64| -> f64 { rates.iter().map(|r| r.at(w).norm_sqr()).sum() };
        for &w in &freqs {
            let (want, got) = (power(&singles, w), power(&combined, w));
            assert!(
                (got / want - 1.0).abs() < 2.0 * RANK_CUT + 1e-14,
                "{w}: {got} {want}"
            );
            assert!(got <= want * (1.0 + 1e-14));
        }
        // The combined multipliers are odd in w like the elements'.
        let r = &combined[0];
        assert!((r.at(-3.0) - r.at(3.0).conj()).norm() <= 1e-15 * r.at(3.0).norm());
        assert_eq!(
            combined_rates(&elements, &[0.0]).unwrap().len(),
            0,
            "no frequency, no rate"
        );
    }

    /// Frequencies whose squares leave f64 (`v |q|` of a slide at 1e150
    /// m/s, which panicked the SVD): every rate finite, the elements'
    /// glassy limit `sqrt(C / tau)` on the real axis.
    #[test]
    fn rates_hold_at_frequencies_beyond_their_squares() {
        let elements = [(1e-8, 1e-3), (2e-8, 1e-1)];
        for (c, tau) in elements {
            let (re, im) = element_rate(c, tau, 1e160);
            assert!((re / (c / tau).sqrt() - 1.0).abs() < 1e-15 && im > 0.0 && im.is_finite());
        }
        let combined = combined_rates(&elements, &[1e3, 1e157, 1e160]).unwrap();
        assert!(!combined.is_empty());
        for rate in &combined {
            let m = rate.at(1e160);
            assert!(m.re.is_finite() && m.im.is_finite(), "{m}");
        }
    }
}
