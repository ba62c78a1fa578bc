//! Quadrature rules of Persson's theory: Gauss-Legendre rules with their
//! running-integral matrices, and piecewise Chebyshev interpolation.
//! The Gauss-Legendre nodes come from [`crate::gauss`], the crate's one
//! generator, which imports nothing: `persson` still needs no grid, kernel
//! or solver.

use std::f64::consts::PI;

use crate::gauss::gauss_legendre;

/// An `n`-point Gauss-Legendre rule on `[-1, 1]` with the matrix of running
/// integrals `S[i][j] = Int_{-1}^{t_i} l_j(t) dt` (`l_j` the Lagrange basis of
/// the nodes), so that `Int_{-1}^{t_i} f ~ sum_j S[i][j] f(t_j)` with the
/// accuracy of the rule's interpolant.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct GaussRule {
    /// Nodes, ascending.
    pub nodes: Vec<f64>,
    /// Weights (sum 2).
    pub weights: Vec<f64>,
    /// Running-integral matrix, row-major `n x n`.
    pub running: Vec<f64>,
}

impl GaussRule {
    pub fn new(n: usize) -> Self {
        let (nodes, weights) = gauss_legendre(n);
        let mut running = vec![0.0; n * n];
        // Int_{-1}^{t_i} l_j exactly: l_j has degree n - 1, the n-point rule
        // mapped onto [-1, t_i] integrates it exactly.
        for i in 0..n {
            let half = 0.5 * (nodes[i] + 1.0);
            for k in 0..n {
                let tau = -1.0 + half * (nodes[k] + 1.0);
                for j in 0..n {
                    running[i * n + j] += half * weights[k] * lagrange(&nodes, j, tau);
                }
            }
        }
        Self {
            nodes,
            weights,
            running,
        }
    }

    pub fn len(&self) -> usize {
        self.nodes.len()
    }
}

/// `l_j(t) = prod_{m != j} (t - t_m) / (t_j - t_m)`.
fn lagrange(nodes: &[f64], j: usize, t: f64) -> f64 {
    let mut p = 1.0;
    for (m, &tm) in nodes.iter().enumerate() {
        if m != j {
            p *= (t - tm) / (nodes[j] - tm);
        }
    }
    p
}

/// Piecewise Chebyshev interpolation of several functions of one variable on
/// `[lo, hi]`: equal panels, each with the `m` Chebyshev points of the second
/// kind (end points included, shared by neighbouring panels), evaluated with
/// the barycentric formula. For a function analytic in a strip
/// `|Im x| < d` the error falls like `rho^-m` with
/// `rho = 2d/h + sqrt((2d/h)^2 + 1)` on panels of width `h`.
#[derive(Debug, Clone)]
pub(crate) struct ChebTable<const K: usize> {
    lo: f64,
    width: f64,
    panels: usize,
    /// Points per panel.
    m: usize,
    /// Chebyshev points on `[-1, 1]`, ascending.
    points: Vec<f64>,
    /// Barycentric weights `(-1)^j delta_j`.
    bary: Vec<f64>,
    /// Values `[panel * m + j][k]`.
    values: Vec<[f64; K]>,
}

impl<const K: usize> ChebTable<K> {
    /// Tabulate `f` on `[lo, hi]` with panels no wider than `max_width` and
    /// `m >= 2` points each; `f` is called once per distinct point (in
    /// parallel).
    pub fn new(
        lo: f64,
        hi: f64,
        max_width: f64,
        m: usize,
        f: impl Fn(f64) -> [f64; K] + Sync,
    ) -> Self {
        use rayon::prelude::*;
        assert!(m >= 2 && hi > lo && max_width > 0.0);
        let panels = ((hi - lo) / max_width).ceil().max(1.0) as usize;
        let width = (hi - lo) / panels as f64;
        let points: Vec<f64> = (0..m)
            .map(|j| -(PI * j as f64 / (m - 1) as f64).cos())
            .collect();
        let bary: Vec<f64> = (0..m)
            .map(|j| {
                let s = if j % 2 == 0 { 1.0 } else { -1.0 };
                if j == 0 || j == m - 1 {
                    0.5 * s
                } else {
                    s
                }
            })
            .collect();
        // Distinct abscissae: panel p, point j (j = 0 of panel p > 0 is the
        // last point of panel p - 1).
        let xs: Vec<f64> = (0..panels * (m - 1) + 1)
            .map(|i| {
                let (p, j) = if i == panels * (m - 1) {
                    (panels - 1, m - 1)
                } else {
                    (i / (m - 1), i % (m - 1))
                };
                lo + width * (p as f64 + 0.5 * (points[j] + 1.0))
            })
            .collect();
        let distinct: Vec<[f64; K]> = xs.par_iter().map(|&x| f(x)).collect();
        let mut values = Vec::with_capacity(panels * m);
        for p in 0..panels {
            for j in 0..m {
                values.push(distinct[p * (m - 1) + j]);
            }
        }
        Self {
            lo,
            width,
            panels,
            m,
            points,
            bary,
            values,
        }
    }

    /// Interpolated values at `x` (clamped to `[lo, hi]`).
    pub fn eval(&self, x: f64) -> [f64; K] {
        let s = ((x - self.lo) / self.width).clamp(0.0, self.panels as f64);
        let p = (s.floor() as usize).min(self.panels - 1);
        let t = 2.0 * (s - p as f64) - 1.0;
        let vals = &self.values[p * self.m..(p + 1) * self.m];
        let mut num = [0.0; K];
        let mut den = 0.0;
        for ((&x, &b), v) in self.points.iter().zip(&self.bary).zip(vals) {
            let d = t - x;
            if d == 0.0 {
                return *v;
            }
            let c = b / d;
            den += c;
            for (n, y) in num.iter_mut().zip(v) {
                *n += c * y;
            }
        }
        num.map(|v| v / den)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gauss_rule_integrates_polynomials_and_running_integrals() {
        for n in [1usize, 2, 5, 8, 12] {
            let r = GaussRule::new(n);
            for deg in 0..(2 * n) {
                let q: f64 = r
                    .nodes
                    .iter()
                    .zip(&r.weights)
                    .map(|(t, w)| w * t.powi(deg as i32))
                    .sum();
                let exact = if deg % 2 == 0 {
                    2.0 / (deg as f64 + 1.0)
                } else {
                    0.0
                };
                assert!((q - exact).abs() < 1e-14, "n = {n}, degree {deg}");
            }
            // Running integrals are exact up to degree n - 1.
            for deg in 0..n {
                for i in 0..n {
                    let s: f64 = (0..n)
                        .map(|j| r.running[i * n + j] * r.nodes[j].powi(deg as i32))
                        .sum();
                    let e = (r.nodes[i].powi(deg as i32 + 1) - (-1f64).powi(deg as i32 + 1))
                        / (deg as f64 + 1.0);
                    assert!((s - e).abs() < 1e-13, "n = {n}, degree {deg}, node {i}");
                }
            }
        }
    }

    #[test]
    fn chebyshev_table_is_spectrally_accurate_and_exact_on_constants() {
        // 1 / (1 + x^2) has poles at +-i: rho = 2 + sqrt(5) on unit panels,
        // rho^-16 = 1e-10.
        let f = |x: f64| [x.sin() * x.exp(), 1.0 / (1.0 + x * x), 3.5];
        let t = ChebTable::new(-3.0, 4.0, 1.0, 16, f);
        for i in 0..=1000 {
            let x = -3.0 + 7.0 * i as f64 / 1000.0;
            let (a, b) = (t.eval(x), f(x));
            for k in 0..3 {
                assert!((a[k] - b[k]).abs() < 1e-9, "x = {x}, k = {k}");
            }
            assert!((a[2] - 3.5).abs() < 1e-14);
        }
    }
}
