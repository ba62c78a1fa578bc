//! Non-negative least squares, `min ||A x - b||_2` subject to `x >= 0`, by the
//! active-set algorithm of Lawson & Hanson (Solving Least Squares Problems,
//! 1974, ch. 23). Used to fit DMA data with non-negative spectrum weights
//! (physics.md section 2). The unconstrained sub-problems on the passive set
//! are solved by Householder QR with column pivoting, which stays accurate for
//! the strongly overlapping columns of a dense relaxation-time grid.

/// Options for [`nnls`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NnlsParams {
    /// Maximum number of outer (column-adding) iterations; `0` means `3 n`.
    pub max_iter: usize,
    /// Dual-feasibility tolerance relative to `||A||_1 ||b||_2`; `0` means the
    /// default `10 eps max(m, n)`.
    pub tolerance: f64,
}

impl Default for NnlsParams {
    fn default() -> Self {
        Self {
            max_iter: 0,
            tolerance: 0.0,
        }
    }
}

/// What [`nnls`] did.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NnlsInfo {
    /// Outer iterations (columns moved into the passive set).
    pub iterations: usize,
    /// Final residual norm `||A x - b||_2`.
    pub residual_norm: f64,
    /// Number of strictly positive unknowns.
    pub passive: usize,
}

/// [`nnls`] failures.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum NnlsError {
    #[error("nnls: matrix is {rows} x {cols} in a buffer of {len} values")]
    Shape {
        rows: usize,
        cols: usize,
        len: usize,
    },
    #[error("nnls: non-finite entry in the matrix or right-hand side")]
    NonFinite,
    #[error("nnls: no convergence after {0} iterations")]
    NoConvergence(usize),
}

/// A dense column-major matrix view for [`nnls`].
#[derive(Debug, Clone, Copy)]
pub struct ColMajor<'a> {
    pub rows: usize,
    pub cols: usize,
    /// `data[i + j * rows]` is `A[i][j]`.
    pub data: &'a [f64],
}

impl ColMajor<'_> {
    fn col(&self, j: usize) -> &[f64] {
        &self.data[j * self.rows..(j + 1) * self.rows]
    }
}

/// Solve `min ||A x - b||` with `x >= 0` (Lawson-Hanson active set).
pub fn nnls(
    a: ColMajor<'_>,
    b: &[f64],
    params: NnlsParams,
) -> Result<(Vec<f64>, NnlsInfo), NnlsError> {
    let (m, n) = (a.rows, a.cols);
    if a.data.len() != m * n || b.len() != m {
        return Err(NnlsError::Shape {
            rows: m,
            cols: n,
            len: a.data.len(),
        });
    }
    if a.data.iter().chain(b).any(|v| !v.is_finite()) {
        return Err(NnlsError::NonFinite);
    }
    let max_iter = if params.max_iter == 0 {
        3 * n.max(1)
    } else {
        params.max_iter
    };
    let norm1 = (0..n)
        .map(|j| a.col(j).iter().map(|v| v.abs()).sum::<f64>())
        .fold(0.0, f64::max);
    let bnorm = b.iter().map(|v| v * v).sum::<f64>().sqrt();
    let rel = if params.tolerance > 0.0 {
        params.tolerance
    } else {
        10.0 * f64::EPSILON * m.max(n) as f64
    };
    let tol = rel * norm1 * bnorm.max(f64::MIN_POSITIVE);

    let mut x = vec![0.0; n];
    let mut passive = vec![false; n];
    let mut iterations = 0;
    let residual = |x: &[f64]| -> Vec<f64> {
        let mut r = b.to_vec();
        for (j, &xj) in x.iter().enumerate() {
            if xj != 0.0 {
                for (ri, aij) in r.iter_mut().zip(a.col(j)) {
                    *ri -= aij * xj;
                }
            }
        }
        r
    };
    // Columns refused in this outer step because their least-squares value
    // came out non-positive (round-off); reset once x changes.
    let mut refused = vec![false; n];
    loop {
        let r = residual(&x);
        let w: Vec<f64> = (0..n)
            .map(|j| a.col(j).iter().zip(&r).map(|(p, q)| p * q).sum())
            .collect();
        let pick = (0..n)
            .filter(|&j| !passive[j] && !refused[j] && w[j] > tol)
            .max_by(|&i, &j| w[i].total_cmp(&w[j]));
        let Some(t) = pick else { break };
        if iterations >= max_iter {
            return Err(NnlsError::NoConvergence(iterations));
        }
        iterations += 1;
        passive[t] = true;
        let mut first = true;
        loop {
            let set: Vec<usize> = (0..n).filter(|&j| passive[j]).collect();
            let z = lstsq_subset(a, b, &set);
            if first && z[set.iter().position(|&j| j == t).unwrap_or(0)] <= 0.0 {
                // The new column does not help in exact arithmetic terms.
                passive[t] = false;
                refused[t] = true;
                break;
            }
            first = false;
            if z.iter().all(|&v| v > 0.0) {
                for (&j, &v) in set.iter().zip(&z) {
                    x[j] = v;
                }
                refused.iter_mut().for_each(|f| *f = false);
                break;
            }
            // Step from x toward z until the first passive variable hits 0.
            let mut alpha = f64::INFINITY;
            let mut blocking = usize::MAX;
            for (&j, &v) in set.iter().zip(&z) {
                if v <= 0.0 {
                    let s = x[j] / (x[j] - v);
                    if s < alpha {
                        alpha = s;
                        blocking = j;
                    }
                }
            }
            for (&j, &v) in set.iter().zip(&z) {
                x[j] += alpha * (v - x[j]);
            }
            for &j in &set {
                if j == blocking || x[j] <= 0.0 {
                    x[j] = 0.0;
                    passive[j] = false;
                }
            }
            refused.iter_mut().for_each(|f| *f = false);
            if !passive.iter().any(|&p| p) {
                break;
            }
        }
    }
    let r = residual(&x);
    let info = NnlsInfo {
        iterations,
        residual_norm: r.iter().map(|v| v * v).sum::<f64>().sqrt(),
        passive: x.iter().filter(|&&v| v > 0.0).count(),
    };
    Ok((x, info))
}

/// Unconstrained least squares on the columns `set` of `a`, by Householder QR
/// with column pivoting; rank-deficient trailing columns get zero.
fn lstsq_subset(a: ColMajor<'_>, b: &[f64], set: &[usize]) -> Vec<f64> {
    let m = a.rows;
    let k = set.len();
    let mut q: Vec<Vec<f64>> = set.iter().map(|&j| a.col(j).to_vec()).collect();
    let mut rhs = b.to_vec();
    let mut perm: Vec<usize> = (0..k).collect();
    let mut norms: Vec<f64> = q.iter().map(|c| c.iter().map(|v| v * v).sum()).collect();
    let max_norm = norms.iter().copied().fold(0.0, f64::max).sqrt();
    let mut rank = 0;
    for col in 0..k.min(m) {
        // Pivot: the remaining column with the largest norm below row `col`.
        let (p, _) = (col..k)
            .map(|c| (c, norms[c]))
            .max_by(|x, y| x.1.total_cmp(&y.1))
            .unwrap_or((col, 0.0));
        q.swap(col, p);
        norms.swap(col, p);
        perm.swap(col, p);
        let v = &mut q[col];
        let alpha = v[col..].iter().map(|x| x * x).sum::<f64>().sqrt();
        if alpha <= 1e-14 * max_norm {
            break;
        }
        let beta = if v[col] > 0.0 { -alpha } else { alpha };
        v[col] -= beta;
        let vnorm2 = v[col..].iter().map(|x| x * x).sum::<f64>();
        let h: Vec<f64> = v[col..].to_vec();
        v[col] = beta;
        for x in v[col + 1..].iter_mut() {
            *x = 0.0;
        }
        let reflect = |y: &mut [f64]| {
            let d: f64 = h.iter().zip(&y[col..]).map(|(p, q)| p * q).sum();
            let s = 2.0 * d / vnorm2;
            for (yi, hi) in y[col..].iter_mut().zip(&h) {
                *yi -= s * hi;
            }
        };
        for c in q.iter_mut().skip(col + 1) {
            reflect(c);
        }
        reflect(&mut rhs);
        for c in col + 1..k {
            norms[c] = q[c][col + 1..].iter().map(|x| x * x).sum();
        }
        rank = col + 1;
    }
    // Back substitution on the leading `rank` columns.
    let mut y = vec![0.0; k];
    for i in (0..rank).rev() {
        let mut s = rhs[i];
        for (c, yc) in y.iter().enumerate().take(rank).skip(i + 1) {
            s -= q[c][i] * yc;
        }
        y[i] = s / q[i][i];
    }
    let mut out = vec![0.0; k];
    for (i, &p) in perm.iter().enumerate() {
        out[p] = y[i];
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matches_unconstrained_solution_when_it_is_positive() {
        // A = [[1,0],[0,2],[1,1]], b = A [1, 2] exactly.
        let data = [1.0, 0.0, 1.0, 0.0, 2.0, 1.0];
        let b = [1.0, 4.0, 3.0];
        let a = ColMajor {
            rows: 3,
            cols: 2,
            data: &data,
        };
        let (x, info) = nnls(a, &b, NnlsParams::default()).unwrap();
        assert!((x[0] - 1.0).abs() < 1e-14 && (x[1] - 2.0).abs() < 1e-14);
        assert!(info.residual_norm < 1e-13);
    }

    /// Karush-Kuhn-Tucker conditions of `min ||Ax - b||, x >= 0`:
    /// `x >= 0`, gradient `g = A^T (b - A x) <= 0` where `x = 0` and `g = 0`
    /// where `x > 0` (to `tol` relative to `||A|| ||b||`).
    fn assert_kkt(m: usize, n: usize, data: &[f64], b: &[f64], x: &[f64], tol: f64) {
        let r: Vec<f64> = (0..m)
            .map(|i| b[i] - (0..n).map(|j| data[j * m + i] * x[j]).sum::<f64>())
            .collect();
        let scale = data.iter().map(|v| v * v).sum::<f64>().sqrt()
            * b.iter().map(|v| v * v).sum::<f64>().sqrt();
        for j in 0..n {
            assert!(x[j] >= 0.0);
            let g: f64 = (0..m).map(|i| data[j * m + i] * r[i]).sum();
            if x[j] > 0.0 {
                assert!(g.abs() <= tol * scale, "g[{j}] = {g}, x = {}", x[j]);
            } else {
                assert!(g <= tol * scale, "g[{j}] = {g}");
            }
        }
    }

    #[test]
    fn kkt_holds_on_seeded_random_problems() {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        for &(m, n) in &[(5, 3), (20, 8), (50, 20), (8, 12), (100, 35)] {
            for _ in 0..5 {
                let data: Vec<f64> = (0..m * n).map(|_| rng.random::<f64>() - 0.3).collect();
                let b: Vec<f64> = (0..m).map(|_| rng.random::<f64>() - 0.5).collect();
                let a = ColMajor {
                    rows: m,
                    cols: n,
                    data: &data,
                };
                let (x, _) = nnls(a, &b, NnlsParams::default()).unwrap();
                // Well-conditioned random matrices: 1e-10 of the scale is
                // far above round-off and far below any real violation.
                assert_kkt(m, n, &data, &b, &x, 1e-10);
            }
        }
    }

    #[test]
    fn clamps_negative_component_and_satisfies_kkt() {
        // Unconstrained solution of this system has x1 < 0.
        let data = [1.0, 1.0, 0.0, 1.0, 2.0, 1.0];
        let b = [1.0, -1.0, -2.0];
        let a = ColMajor {
            rows: 3,
            cols: 2,
            data: &data,
        };
        let (x, _) = nnls(a, &b, NnlsParams::default()).unwrap();
        assert!(x.iter().all(|&v| v >= 0.0));
        // KKT: gradient A^T (b - A x) <= 0 on zero components, = 0 on positive.
        let r: Vec<f64> = (0..3)
            .map(|i| b[i] - data[i] * x[0] - data[3 + i] * x[1])
            .collect();
        for j in 0..2 {
            let g: f64 = (0..3).map(|i| data[j * 3 + i] * r[i]).sum();
            if x[j] > 0.0 {
                assert!(g.abs() < 1e-12, "g[{j}] = {g}");
            } else {
                assert!(g <= 1e-12, "g[{j}] = {g}");
            }
        }
    }
}
