//! Love's integral of `1/r` over a uniformly loaded rectangle (Love 1929;
//! Johnson, Contact Mechanics, sec. 3.7): the spatial factor `L(d)` of the
//! paper's Eq. 6 and of physics.md section 3.
//!
//! `L(x, y) = int_{-ax/2}^{ax/2} int_{-ay/2}^{ay/2} dxi deta / |(x - xi, y - eta)|`.
//!
//! Near the rectangle the closed form (sum over corners of
//! `F(X, Y) = X asinh(Y/|X|) + Y asinh(X/|Y|)`) is used. It cancels
//! catastrophically far away (relative error ~ `eps (r/a)^2`), so beyond
//! `r >= SWITCH * rho` (`rho` the half-diagonal) the multipole expansion
//! `1/|d - x'| = sum_l |x'|^l P_l(cos g) / r^(l+1)`, averaged over the
//! rectangle, is summed through degree [`MAX_DEGREE`]; odd degrees vanish by
//! symmetry. Truncation error <= `SWITCH^-(MAX_DEGREE+2) / (1 - SWITCH^-2)`
//! ~ 1e-14; the closed form at the switch radius loses about
//! `eps (SWITCH rho / a)^2` ~ 1e-14 too, so the two agree there.
//! The same construction gives the `y`-antiderivative used for cell
//! averages of the friction stencil (physics.md section 5).

/// Highest multipole degree kept (even).
pub const MAX_DEGREE: usize = 16;
/// Switch radius in units of the half-diagonal.
pub const SWITCH: f64 = 6.0;
const NDEG: usize = MAX_DEGREE / 2 + 1;

/// Precomputed Love integral for one rectangle size: closed form near,
/// multipole expansion far.
#[derive(Debug, Clone)]
pub struct LoveRect {
    pub ax: f64,
    pub ay: f64,
    area: f64,
    switch_r2: f64,
    /// Squared half-diagonal.
    rho2: f64,
    /// `poly[k][p]`: coefficient of `U^p` (`U = (x/r)^2`) in the averaged
    /// Legendre term of degree `2k`, in units of the half-diagonal: the
    /// term is `poly[k](U) (rho^2 / r^2)^k`. No power of a side is formed,
    /// so the expansion holds for cells of any size f64 represents (a
    /// power `a^16` would leave f64's range for cells beyond 1e+-19 m).
    poly: [[f64; NDEG]; NDEG],
}

fn binom(n: usize, k: usize) -> f64 {
    let mut r = 1.0;
    for i in 0..k {
        r = r * (n - i) as f64 / (i + 1) as f64;
    }
    r
}

fn fact(n: usize) -> f64 {
    (1..=n).map(|k| k as f64).product()
}

impl LoveRect {
    /// Precompute the far-field coefficients for an `ax x ay` rectangle.
    pub fn new(ax: f64, ay: f64) -> Self {
        // The half-sides in units of the half-diagonal (`hypot`: no
        // square of a side either).
        let rho = (0.5 * ax).hypot(0.5 * ay);
        let hx = 0.5 * ax / rho;
        let hy = 0.5 * ay / rho;
        // Moments of the uniform distribution on [-h, h]: <xi^p>.
        let mom = |h: f64, p: usize| {
            if p % 2 == 1 {
                0.0
            } else {
                h.powi(p as i32) / (p as f64 + 1.0)
            }
        };
        let mut poly = [[0.0; NDEG]; NDEG];
        for (kk, row) in poly.iter_mut().enumerate() {
            let l = 2 * kk;
            // <Q_l> as a polynomial in (u, w): coef[i][j] of u^i w^j.
            let mut coef = vec![vec![0.0; l + 1]; l + 1];
            for m in 0..=l / 2 {
                let c_lm = if m % 2 == 0 { 1.0 } else { -1.0 } * fact(2 * l - 2 * m)
                    / (2f64.powi(l as i32) * fact(m) * fact(l - m) * fact(l - 2 * m));
                let a = l - 2 * m;
                for i in (0..=a).step_by(2) {
                    let mut s = 0.0;
                    for j in 0..=m {
                        s += binom(m, j) * mom(hx, i + 2 * j) * mom(hy, a - i + 2 * m - 2 * j);
                    }
                    coef[i][a - i] += c_lm * binom(a, i) * s;
                }
            }
            // Substitute w^2 = 1 - U, u^2 = U.
            for (i, ci) in coef.iter().enumerate() {
                for (j, &c) in ci.iter().enumerate() {
                    if c == 0.0 {
                        continue;
                    }
                    let (pi, pj) = (i / 2, j / 2);
                    for t in 0..=pj {
                        let sgn = if t % 2 == 0 { 1.0 } else { -1.0 };
                        row[pi + t] += c * binom(pj, t) * sgn;
                    }
                }
            }
        }
        let rho2 = rho * rho;
        Self {
            ax,
            ay,
            area: ax * ay,
            switch_r2: SWITCH * SWITCH * rho2,
            rho2,
            poly,
        }
    }

    /// Squared switch radius between closed form and multipole expansion.
    pub fn switch_radius_sq(&self) -> f64 {
        self.switch_r2
    }

    /// `L(x, y)` \[m\]: closed form near, multipole far.
    #[inline]
    pub fn eval(&self, x: f64, y: f64) -> f64 {
        let r2 = x * x + y * y;
        if r2 >= self.switch_r2 {
            self.far(x, y, r2)
        } else {
            self.near(x, y)
        }
    }

    /// Closed form (exact in exact arithmetic; use only near the rectangle).
    pub fn near(&self, x: f64, y: f64) -> f64 {
        let (hx, hy) = (0.5 * self.ax, 0.5 * self.ay);
        let (x1, x2) = (x + hx, x - hx);
        let (y1, y2) = (y + hy, y - hy);
        corner(x1, y1) - corner(x2, y1) - corner(x1, y2) + corner(x2, y2)
    }

    /// Multipole expansion (valid for `r` beyond the half-diagonal; accurate
    /// to ~1e-14 beyond the switch radius).
    #[inline]
    pub fn far(&self, x: f64, _y: f64, r2: f64) -> f64 {
        let inv_r2 = 1.0 / r2;
        let u2 = x * x * inv_r2;
        let ratio = self.rho2 * inv_r2;
        let mut sum = 0.0;
        // The term of degree 2k is scaled by ratio^k, which also bounds it
        // (|P_l| <= 1, |x'| <= rho): stop once that is below 1e-17.
        let mut scale = 1.0;
        for (k, row) in self.poly.iter().enumerate() {
            if scale < 1e-17 {
                break;
            }
            let mut t = 0.0;
            for &c in row[..=k].iter().rev() {
                t = t * u2 + c;
            }
            sum += t * scale;
            scale *= ratio;
        }
        self.area * sum / r2.sqrt()
    }

    /// `int_{y0}^{y1} L(x, y) dy` in closed form (sum over corners of
    /// `G(X, Y) = X Y asinh(Y/|X|) + (Y^2/2) asinh(X/|Y|) - X r / 2`, the
    /// `Y`-antiderivative of `F`). Cancels like `eps (r/a)^3` far away: use only
    /// near the rectangle.
    pub fn near_y_integral(&self, x: f64, y0: f64, y1: f64) -> f64 {
        let (hx, hy) = (0.5 * self.ax, 0.5 * self.ay);
        let cols = [(x + hx, 1.0), (x - hx, -1.0)];
        let rows = [(hy, 1.0), (-hy, -1.0)];
        let mut s = 0.0;
        for (xx, sx) in cols {
            for (eta, sy) in rows {
                // L = sum sx * sy' F(X, y - eta) with sy' = +1 for eta = -hy.
                let g = g_corner(xx, y1 - eta) - g_corner(xx, y0 - eta);
                s += sx * (-sy) * g;
            }
        }
        s
    }
}

/// `F(X, Y) = X asinh(Y/|X|) + Y asinh(X/|Y|)` (`= X ln(Y + r) + Y ln(X + r)`
/// up to single-variable terms that cancel in the corner sum), with its
/// limits on the axes.
#[inline]
fn corner(x: f64, y: f64) -> f64 {
    let mut v = 0.0;
    if x.abs() > 1e-300 * y.abs() && x != 0.0 {
        v += x * (y / x.abs()).asinh();
    }
    if y.abs() > 1e-300 * x.abs() && y != 0.0 {
        v += y * (x / y.abs()).asinh();
    }
    v
}

/// `G(X, Y) = X Y asinh(Y/|X|) + (Y^2/2) asinh(X/|Y|) - X r / 2`, `dG/dY = F`.
#[inline]
fn g_corner(x: f64, y: f64) -> f64 {
    let r = x.hypot(y);
    let mut v = -0.5 * x * r;
    if x.abs() > 1e-300 * y.abs() && x != 0.0 {
        v += x * y * (y / x.abs()).asinh();
    }
    if y.abs() > 1e-300 * x.abs() && y != 0.0 {
        v += 0.5 * y * y * (x / y.abs()).asinh();
    }
    v
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kernel::quad::adaptive;

    fn quad_l(x: f64, y: f64, ax: f64, ay: f64) -> f64 {
        // Inner integral in xi analytically: int dxi / sqrt(X^2 + Y^2) = asinh.
        let inner = |eta: f64| {
            let yy = y - eta;
            let a = x + 0.5 * ax;
            let b = x - 0.5 * ax;
            if yy == 0.0 {
                f64::NAN
            } else {
                (a / yy.abs()).asinh() - (b / yy.abs()).asinh()
            }
        };
        let mut br = vec![-0.5 * ay, 0.5 * ay];
        if y.abs() < 0.5 * ay {
            br.insert(1, y);
        }
        adaptive(inner, &br, 1e-15, 1e-15, 2000)
    }

    #[test]
    fn closed_form_matches_quadrature_in_all_quadrants() {
        for &(ax, ay) in &[(1.0, 1.0), (2.0, 0.5), (0.3, 3.0)] {
            let r = LoveRect::new(ax, ay);
            for &(x, y) in &[
                (0.0, 0.0),
                (0.1, -0.2),
                (-0.7, 0.3),
                (1.3, -2.1),
                (-3.0, -0.01),
                (0.5 * ax, 0.1),
                (2.0, 0.5 * ay),
            ] {
                let a = r.near(x, y);
                let b = quad_l(x, y, ax, ay);
                assert!((a - b).abs() < 1e-12 * b, "{ax} {ay} ({x},{y}) {a} {b}");
            }
        }
    }

    #[test]
    fn y_antiderivative_matches_quadrature() {
        let r = LoveRect::new(1.0, 0.7);
        for &(x, y0, y1) in &[(0.2, -0.3, 0.9), (-1.4, 0.35, 1.35), (2.0, -3.0, -2.0)] {
            let a = r.near_y_integral(x, y0, y1);
            let br = crate::kernel::quad::clean_breaks(vec![-0.35, 0.35], y0, y1);
            let b = adaptive(|y| r.near(x, y), &br, 1e-15, 1e-15, 2000);
            assert!((a - b).abs() < 1e-12 * b.abs(), "{a} {b}");
        }
    }
}
