//! The least-squares centred ellipse `A x^2 + B x y + C y^2 = 1` through
//! a set of points (the contours of `C_chi`, physics.md section 5; Carbone
//! & Putignano 2014, Fig. 10): linear least squares on the conic
//! coefficients, accepted when `4AC - B^2 > 0` and `A > 0`; the semi-axes
//! from the conic's eigenvalues, the major axis's direction from +x in
//! (-90, 90].

use serde::Serialize;

use super::anisotropy::wrap_axis_deg;

/// A centred ellipse `A x^2 + B x y + C y^2 = 1` fitted to contour points.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct EllipseFit {
    /// Conic coefficients `[A, B, C]` (points in units of `q0`).
    pub conic: [f64; 3],
    /// Semi-major axis [in units of `q0`].
    pub semi_major: f64,
    /// Semi-minor axis [in units of `q0`].
    pub semi_minor: f64,
    /// `semi_minor / semi_major`.
    pub lambda: f64,
    /// Direction of the major axis from +x [degrees, (-90, 90]].
    pub angle_deg: f64,
    /// rms of `|p| / r_ellipse(direction of p) - 1` over the points.
    pub rms_radial_residual: f64,
}

/// Why no ellipse came out of a set of points.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum FitFailure {
    /// Fewer than 6 points (or all along one line).
    TooFewPoints,
    /// The least-squares conic is a hyperbola or parabola.
    NotAnEllipse,
    /// `C_chi(0) <= 0` after the background subtraction (densely packed
    /// spots whose neighbour shell fills the taper ring): no contours.
    NonPositiveC0,
}

/// Least-squares centred ellipse through `points` (see the module doc).
pub fn fit_centred_ellipse(points: &[[f64; 2]]) -> Result<EllipseFit, FitFailure> {
    if points.len() < 6 {
        return Err(FitFailure::TooFewPoints);
    }
    // Normal equations of sum (A x^2 + B x y + C y^2 - 1)^2.
    let mut n = [[0.0f64; 3]; 3];
    let mut rhs = [0.0f64; 3];
    for p in points {
        let f = [p[0] * p[0], p[0] * p[1], p[1] * p[1]];
        for i in 0..3 {
            rhs[i] += f[i];
            for j in 0..3 {
                n[i][j] += f[i] * f[j];
            }
        }
    }
    let sol = solve3(n, rhs).ok_or(FitFailure::TooFewPoints)?;
    let [a, b, c] = sol;
    if !(4.0 * a * c - b * b > 0.0 && a > 0.0) {
        return Err(FitFailure::NotAnEllipse);
    }
    let mean = 0.5 * (a + c);
    let r = (0.5 * (a - c)).hypot(0.5 * b);
    let (mu_min, mu_max) = (mean - r, mean + r);
    let semi_major = 1.0 / mu_min.sqrt();
    let semi_minor = 1.0 / mu_max.sqrt();
    // Q(theta) = mean + (A-C)/2 cos 2theta + B/2 sin 2theta is smallest
    // (longest radius) at 2 theta = atan2(B, A - C) + pi.
    let angle_deg = wrap_axis_deg(0.5 * b.atan2(a - c).to_degrees() + 90.0);
    let mut ss = 0.0;
    for p in points {
        let rp = p[0].hypot(p[1]);
        let th = p[1].atan2(p[0]);
        let (s, co) = th.sin_cos();
        let q = a * co * co + b * s * co + c * s * s;
        let re = 1.0 / q.sqrt();
        ss += (rp / re - 1.0).powi(2);
    }
    Ok(EllipseFit {
        conic: sol,
        semi_major,
        semi_minor,
        lambda: semi_minor / semi_major,
        angle_deg,
        rms_radial_residual: (ss / points.len() as f64).sqrt(),
    })
}

/// Gaussian elimination with partial pivoting on a 3 x 3 system.
fn solve3(mut m: [[f64; 3]; 3], mut b: [f64; 3]) -> Option<[f64; 3]> {
    let scale = m
        .iter()
        .flat_map(|r| r.iter())
        .fold(0.0f64, |s, v| s.max(v.abs()));
    if scale == 0.0 {
        return None;
    }
    for col in 0..3 {
        let piv = (col..3)
            .max_by(|&i, &j| m[i][col].abs().total_cmp(&m[j][col].abs()))
            .unwrap_or(col);
        if m[piv][col].abs() <= 1e-13 * scale {
            return None;
        }
        m.swap(col, piv);
        b.swap(col, piv);
        for row in col + 1..3 {
            let f = m[row][col] / m[col][col];
            let pivot_row = m[col];
            for (v, p) in m[row].iter_mut().zip(pivot_row).skip(col) {
                *v -= f * p;
            }
            b[row] -= f * b[col];
        }
    }
    let mut x = [0.0; 3];
    for row in (0..3).rev() {
        let s: f64 = (row + 1..3).map(|k| m[row][k] * x[k]).sum();
        x[row] = (b[row] - s) / m[row][row];
    }
    Some(x)
}

#[cfg(test)]
mod tests {
    use std::f64::consts::PI;

    use super::*;

    #[test]
    fn ellipse_fit_recovers_exact_points() {
        let (a, b, phi) = (3.0, 1.2, 25f64.to_radians());
        let pts: Vec<[f64; 2]> = (0..40)
            .map(|k| {
                let t = 2.0 * PI * k as f64 / 40.0;
                let (x, y) = (a * t.cos(), b * t.sin());
                [x * phi.cos() - y * phi.sin(), x * phi.sin() + y * phi.cos()]
            })
            .collect();
        let f = fit_centred_ellipse(&pts).unwrap();
        assert!((f.semi_major - a).abs() < 1e-9 && (f.semi_minor - b).abs() < 1e-9);
        assert!((f.angle_deg - 25.0).abs() < 1e-7, "{}", f.angle_deg);
        assert!(f.rms_radial_residual < 1e-12);
    }

    #[test]
    fn too_few_points_is_reported() {
        assert_eq!(
            fit_centred_ellipse(&[[1.0, 0.0], [0.0, 1.0]]),
            Err(FitFailure::TooFewPoints)
        );
    }
}
