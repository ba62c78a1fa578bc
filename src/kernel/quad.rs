//! Quadrature building blocks for the influence coefficients (physics.md
//! section 3): Gauss-Legendre rules, a globally adaptive Gauss-Kronrod
//! (G10/K21) integrator with user breakpoints, and Gauss rules for a
//! positive weight given by samples (discretised Stieltjes procedure followed
//! by Golub-Welsch), used for the exponential memory weights of Eq. 4.

use std::cmp::Ordering;
use std::collections::BinaryHeap;

pub use crate::gauss::gauss_legendre;

/// Gauss-Legendre rule mapped to `[0, 1]`.
pub fn gauss_legendre_unit(n: usize) -> (Vec<f64>, Vec<f64>) {
    let (x, w) = gauss_legendre(n);
    (
        x.iter().map(|t| 0.5 * (t + 1.0)).collect(),
        w.iter().map(|t| 0.5 * t).collect(),
    )
}

/// Kronrod abscissae of the 21-point rule (QUADPACK `qk21`), descending.
const XGK: [f64; 11] = [
    0.995_657_163_025_808_1,
    0.973_906_528_517_171_7,
    0.930_157_491_355_708_2,
    0.865_063_366_688_984_5,
    0.780_817_726_586_416_9,
    0.679_409_568_299_024_4,
    0.562_757_134_668_604_7,
    0.433_395_394_129_247_2,
    0.294_392_862_701_460_2,
    0.148_874_338_981_631_2,
    0.0,
];
const WGK: [f64; 11] = [
    0.011_694_638_867_371_874,
    0.032_558_162_307_964_73,
    0.054_755_896_574_351_996,
    0.075_039_674_810_919_95,
    0.093_125_454_583_697_6,
    0.109_387_158_802_297_64,
    0.123_491_976_262_065_85,
    0.134_709_217_311_473_33,
    0.142_775_938_577_060_08,
    0.147_739_104_901_338_5,
    0.149_445_554_002_916_9,
];
/// Weights of the embedded 10-point Gauss rule (at `XGK[1], XGK[3], ...`).
const WG: [f64; 5] = [
    0.066_671_344_308_688_14,
    0.149_451_349_150_580_6,
    0.219_086_362_515_982_04,
    0.269_266_719_309_996_36,
    0.295_524_224_714_752_9,
];

/// One G10/K21 panel: `(kronrod value, |kronrod - gauss|)`.
pub fn gk21(f: &mut impl FnMut(f64) -> f64, a: f64, b: f64) -> (f64, f64) {
    let c = 0.5 * (a + b);
    let h = 0.5 * (b - a);
    let fc = f(c);
    let mut k = WGK[10] * fc;
    let mut g = 0.0;
    for j in 0..10 {
        let dx = h * XGK[j];
        let s = f(c - dx) + f(c + dx);
        k += WGK[j] * s;
        if j % 2 == 1 {
            g += WG[j / 2] * s;
        }
    }
    (k * h, ((k - g) * h).abs())
}

struct Panel {
    a: f64,
    b: f64,
    value: f64,
    err: f64,
}

impl PartialEq for Panel {
    fn eq(&self, other: &Self) -> bool {
        self.err.total_cmp(&other.err) == Ordering::Equal
    }
}
impl Eq for Panel {}
impl PartialOrd for Panel {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Panel {
    fn cmp(&self, other: &Self) -> Ordering {
        self.err.total_cmp(&other.err)
    }
}

/// Globally adaptive G10/K21 integration of `f` over `[breaks[0],
/// breaks.last()]`, starting from the panels between consecutive
/// breakpoints (kinks of the integrand and its natural length scales go
/// there) and always bisecting the panel with the largest error estimate,
/// until the summed estimate is below `max(abs_tol, rel_tol * |I|)` or
/// `max_panels` panels are in use. The error estimate `|K21 - G10|` is very
/// pessimistic for smooth integrands (the K21 value is far more accurate).
pub fn adaptive(
    mut f: impl FnMut(f64) -> f64,
    breaks: &[f64],
    abs_tol: f64,
    rel_tol: f64,
    max_panels: usize,
) -> f64 {
    let mut heap = BinaryHeap::new();
    let mut total = 0.0;
    let mut total_err = 0.0;
    for w in breaks.windows(2) {
        let (a, b) = (w[0], w[1]);
        if b <= a {
            continue;
        }
        let (value, err) = gk21(&mut f, a, b);
        total += value;
        total_err += err;
        heap.push(Panel { a, b, value, err });
    }
    while total_err > abs_tol.max(rel_tol * total.abs()) && heap.len() < max_panels {
        let Some(p) = heap.pop() else { break };
        let m = 0.5 * (p.a + p.b);
        if m <= p.a || m >= p.b {
            heap.push(Panel { err: 0.0, ..p });
            continue;
        }
        let (v1, e1) = gk21(&mut f, p.a, m);
        let (v2, e2) = gk21(&mut f, m, p.b);
        total += v1 + v2 - p.value;
        total_err += e1 + e2 - p.err;
        heap.push(Panel {
            a: p.a,
            b: m,
            value: v1,
            err: e1,
        });
        heap.push(Panel {
            a: m,
            b: p.b,
            value: v2,
            err: e2,
        });
    }
    // Re-sum to remove the drift of the running updates.
    heap.iter().map(|p| p.value).sum()
}

/// Sort, drop non-finite values and duplicates, and clip to `[lo, hi]`
/// (both included).
pub fn clean_breaks(mut b: Vec<f64>, lo: f64, hi: f64) -> Vec<f64> {
    b.retain(|x| x.is_finite() && *x > lo && *x < hi);
    b.push(lo);
    b.push(hi);
    b.sort_by(f64::total_cmp);
    b.dedup_by(|x, y| (*x - *y).abs() <= 1e-15 * y.abs().max(x.abs()));
    b
}

/// An `n`-point Gauss rule for the discrete positive measure
/// `sum_j w_j delta(x - x_j)` (a fine quadrature of a continuous weight):
/// recurrence coefficients by the discretised Stieltjes procedure, nodes and
/// weights by Golub-Welsch. Returns `(nodes, weights)`.
pub fn gauss_from_samples(x: &[f64], w: &[f64], n: usize) -> (Vec<f64>, Vec<f64>) {
    let m = x.len();
    let mu0: f64 = w.iter().sum();
    let mut diag = vec![0.0; n];
    let mut off = vec![0.0; n.saturating_sub(1)];
    // Orthonormal polynomials q_k evaluated at the sample points.
    let mut q_prev = vec![0.0; m];
    let mut q = vec![1.0 / mu0.sqrt(); m];
    let mut b_prev = 0.0;
    for k in 0..n {
        let alpha: f64 = (0..m).map(|j| w[j] * x[j] * q[j] * q[j]).sum();
        diag[k] = alpha;
        if k + 1 == n {
            break;
        }
        let r: Vec<f64> = (0..m)
            .map(|j| (x[j] - alpha) * q[j] - b_prev * q_prev[j])
            .collect();
        let b = (0..m).map(|j| w[j] * r[j] * r[j]).sum::<f64>().sqrt();
        off[k] = b;
        q_prev = q;
        q = r.iter().map(|v| v / b).collect();
        b_prev = b;
    }
    let (nodes, first) = symmetric_tridiagonal_eigen(&diag, &off);
    let mut pairs: Vec<(f64, f64)> = nodes
        .into_iter()
        .zip(first)
        .map(|(x, v)| (x, mu0 * v * v))
        .collect();
    pairs.sort_by(|a, b| a.0.total_cmp(&b.0));
    pairs.into_iter().unzip()
}

/// Eigenvalues and first eigenvector components of the symmetric tridiagonal
/// matrix with diagonal `d` and off-diagonal `e` (implicit QL with Wilkinson
/// shifts, as in EISPACK `tql2` restricted to the first row).
fn symmetric_tridiagonal_eigen(d: &[f64], e: &[f64]) -> (Vec<f64>, Vec<f64>) {
    let n = d.len();
    let mut d = d.to_vec();
    let mut e: Vec<f64> = e.iter().copied().chain(std::iter::once(0.0)).collect();
    let mut z = vec![0.0; n];
    z[0] = 1.0;
    for l in 0..n {
        let mut iter = 0;
        loop {
            let mut m = l;
            while m + 1 < n {
                let dd = d[m].abs() + d[m + 1].abs();
                if e[m].abs() <= f64::EPSILON * dd {
                    break;
                }
                m += 1;
            }
            if m == l {
                break;
            }
            iter += 1;
            if iter > 60 {
                break;
            }
            let mut g = (d[l + 1] - d[l]) / (2.0 * e[l]);
            let mut r = g.hypot(1.0);
            g = d[m] - d[l] + e[l] / (g + r.copysign(g));
            let (mut s, mut c, mut p) = (1.0, 1.0, 0.0);
            let mut i = m;
            let mut early = false;
            while i > l {
                i -= 1;
                let f = s * e[i];
                let b = c * e[i];
                r = f.hypot(g);
                e[i + 1] = r;
                if r == 0.0 {
                    d[i + 1] -= p;
                    e[m] = 0.0;
                    early = true;
                    break;
                }
                s = f / r;
                c = g / r;
                g = d[i + 1] - p;
                r = (d[i] - g) * s + 2.0 * c * b;
                p = s * r;
                d[i + 1] = g + p;
                g = c * r - b;
                let zf = z[i + 1];
                z[i + 1] = s * z[i] + c * zf;
                z[i] = c * z[i] - s * zf;
            }
            if early {
                continue;
            }
            d[l] -= p;
            e[l] = g;
            e[m] = 0.0;
        }
    }
    (d, z)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gauss_legendre_integrates_polynomials() {
        for n in [1, 2, 5, 8, 10, 20] {
            let (x, w) = gauss_legendre(n);
            for p in 0..(2 * n) {
                let got: f64 = x.iter().zip(&w).map(|(x, w)| w * x.powi(p as i32)).sum();
                let exact = if p % 2 == 1 {
                    0.0
                } else {
                    2.0 / (p as f64 + 1.0)
                };
                assert!((got - exact).abs() < 1e-14, "n={n} p={p} {got} {exact}");
            }
        }
    }

    #[test]
    fn adaptive_handles_kinks_and_peaks() {
        let v = adaptive(|x| (x - 0.3).abs(), &[0.0, 1.0], 1e-15, 1e-15, 200);
        assert!((v - (0.045 + 0.245)).abs() < 1e-13, "{v}");
        let br = [0.0, 1e-6, 1e-5, 1e-4, 1e-3, 1.0];
        let v = adaptive(|x| (-x / 1e-6).exp() / 1e-6, &br, 1e-15, 1e-15, 500);
        assert!((v - 1.0).abs() < 1e-12, "{v}");
    }

    #[test]
    fn stieltjes_golub_welsch_reproduces_laguerre_moments() {
        // Weight lambda e^{-lambda t} on [0, 1], lambda = 50: exact for degree <= 2n-1.
        let lam = 50.0;
        let (gx, gw) = gauss_legendre_unit(30);
        let mut xs = vec![];
        let mut ws = vec![];
        let edges: Vec<f64> = (0..=20).map(|k| (k as f64 / 20.0).powi(3)).collect();
        for e in edges.windows(2) {
            for (t, w) in gx.iter().zip(&gw) {
                let x = e[0] + (e[1] - e[0]) * t;
                xs.push(x);
                ws.push(w * (e[1] - e[0]) * lam * (-lam * x).exp());
            }
        }
        let (nx, nw) = gauss_from_samples(&xs, &ws, 8);
        for p in 0..16 {
            let exact: f64 = xs.iter().zip(&ws).map(|(x, w)| w * x.powi(p)).sum();
            let got: f64 = nx.iter().zip(&nw).map(|(x, w)| w * x.powi(p)).sum();
            assert!(
                (got - exact).abs() <= 1e-13 * exact.abs(),
                "p={p} {got} {exact}"
            );
        }
    }
}
