//! Dense direct reference solver for small grids (tests and checks only):
//! the same LCP solved by an active-set loop whose linear systems are
//! factorised exactly with faer's partial-pivoting LU.

use faer::linalg::solvers::Solve;
use faer::Mat;

use super::{Control, SolverError};

/// Solve the LCP with the dense matrix `l` (`N x N`); returns `(p, delta)`.
pub fn solve_dense(
    l: &Mat<f64>,
    g: &[f64],
    cell_area: f64,
    control: Control,
    max_iterations: usize,
) -> Result<(Vec<f64>, f64), SolverError> {
    let n = g.len();
    assert_eq!(l.nrows(), n);
    let mut active: Vec<bool> = {
        let gmin = g.iter().cloned().fold(f64::INFINITY, f64::min);
        g.iter().map(|&x| x <= gmin).collect()
    };
    for _ in 0..max_iterations {
        let idx: Vec<usize> = (0..n).filter(|&i| active[i]).collect();
        let m = idx.len();
        let bordered = matches!(control, Control::Load(_));
        let size = m + usize::from(bordered);
        let mut a = Mat::<f64>::zeros(size, size);
        let mut b = Mat::<f64>::zeros(size, 1);
        for (r, &i) in idx.iter().enumerate() {
            for (c, &k) in idx.iter().enumerate() {
                a[(r, c)] = l[(i, k)];
            }
            match control {
                Control::Load(_) => {
                    a[(r, m)] = -1.0;
                    b[(r, 0)] = -g[i];
                }
                Control::Approach(d) => b[(r, 0)] = d - g[i],
            }
        }
        if let Control::Load(f) = control {
            for c in 0..m {
                a[(m, c)] = cell_area;
            }
            b[(m, 0)] = f;
        }
        let lu = a.partial_piv_lu();
        lu.solve_in_place(b.as_mut());
        let mut p = vec![0.0; n];
        for (r, &i) in idx.iter().enumerate() {
            p[i] = b[(r, 0)];
        }
        let delta = match control {
            Control::Load(_) => b[(m, 0)],
            Control::Approach(d) => d,
        };
        let mut changed = false;
        for i in 0..n {
            let gap: f64 = g[i] - delta + (0..n).map(|k| l[(i, k)] * p[k]).sum::<f64>();
            let now = if active[i] { p[i] > 0.0 } else { gap < 0.0 };
            if now != active[i] {
                changed = true;
                active[i] = now;
            }
        }
        if !changed {
            return Ok((p, delta));
        }
    }
    Err(SolverError::NoConvergence {
        iterations: max_iterations,
        matvecs: 0,
        residual: f64::NAN,
        history: vec![],
        cause: String::new(),
    })
}
