//! The bearing-area start of the active-set iteration: the cells with the
//! smallest gap, as many as the linear area-load law predicts.

use super::Control;

/// Initial contact set and pressure. Under load control: the cells with the
/// smallest gap, as many as the linear area-load law predicts (paper Eq. 10,
/// `A/A0 = kappa p0 / (E* m)` with `kappa = 2`, `m` the rms slope of the
/// gap profile and `E*` read off the self coefficient: for a square cell
/// `L_00 = (1 - nu^2) / (pi E) 4 a asinh(1)`, so `E* = 4 asinh(1) a / (pi L_00)`).
pub(crate) fn initial_guess(
    g: &[f64],
    cell_area: f64,
    l00: f64,
    control: Control,
    mask: &mut [f64],
) -> (f64, f64) {
    let n = g.len();
    let mut sorted: Vec<f64> = g.to_vec();
    sorted.sort_by(|a, b| a.total_cmp(b));
    let count = match control {
        Control::Load(f) => {
            let a = cell_area.sqrt();
            let e_star = 4.0 * 1f64.asinh() * a / (std::f64::consts::PI * l00);
            let mean_p = f / (cell_area * n as f64);
            let slope = rms_slope_along_rows(g, a);
            let fraction = if slope > 0.0 {
                2.0 * mean_p / (e_star * slope)
            } else {
                1.0
            };
            ((fraction * n as f64).ceil() as usize).clamp(1, n.div_ceil(2))
        }
        Control::Approach(d) => sorted.iter().filter(|&&x| x < d).count().max(1),
    };
    let threshold = sorted[count - 1];
    let mut m = 0usize;
    for (mk, &gi) in mask.iter_mut().zip(g) {
        if gi <= threshold && m < count {
            *mk = 1.0;
            m += 1;
        }
    }
    let p0 = match control {
        Control::Load(f) => f / (cell_area * m as f64),
        Control::Approach(_) => 0.0,
    };
    (threshold, p0)
}

/// rms of the finite-difference slope of `g` along the storage rows and
/// columns of a square grid (`sqrt(<|grad g|^2>)`); the grid shape is taken
/// as square when `n` is a perfect square, else as one row.
fn rms_slope_along_rows(g: &[f64], a: f64) -> f64 {
    let n = g.len();
    let side = (n as f64).sqrt().round() as usize;
    if side * side != n || side < 2 {
        return 0.0;
    }
    let mut s2 = 0.0;
    let mut count = 0usize;
    for i in 0..side {
        for j in 0..side - 1 {
            let d = g[i * side + j + 1] - g[i * side + j];
            s2 += d * d;
            count += 1;
        }
    }
    for i in 0..side - 1 {
        for j in 0..side {
            let d = g[(i + 1) * side + j] - g[i * side + j];
            s2 += d * d;
        }
    }
    (2.0 * s2 / (2 * count) as f64).sqrt() / a
}
