//! The reference of the closed-form tests, computed without the heat
//! room's routines: the moving point source (Carslaw & Jaeger sec. 10.7)
//! integrated over a rectangular patch in Cartesian coordinates by adaptive
//! tensor Gauss-Legendre (the heat room integrates each cell in polar
//! coordinates with the radial integral in closed form). A target inside
//! the patch splits it into four rectangles with a corner at the target,
//! each mapped by Duffy's transform (two triangles onto the unit square,
//! whose Jacobian cancels the `1/R` singularity).

use viscoslide::internals::gauss::gauss_legendre;

/// A moving source: `e_v` and `v / kappa` [1/m].
#[derive(Debug, Clone, Copy)]
pub struct Motion {
    pub e: (f64, f64),
    pub rate: f64,
}

impl Motion {
    /// `v (X + R) / (2 kappa)` at `s = r - r'`, where `X = s . e_v`;
    /// behind the source (`X < 0`) written as `Y^2 / (R - X)`.
    fn exponent(&self, (sx, sy): (f64, f64)) -> f64 {
        let r = sx.hypot(sy);
        let x = sx * self.e.0 + sy * self.e.1;
        let y = -sx * self.e.1 + sy * self.e.0;
        let lead = if x < 0.0 { y * y / (r - x) } else { x + r };
        0.5 * self.rate * lead
    }

    /// `exp(-v (X + R) / (2 kappa)) / R` [1/m].
    fn kernel(&self, s: (f64, f64)) -> f64 {
        (-self.exponent(s)).exp() / s.0.hypot(s.1)
    }
}

/// A rectangle `(x0, x1, y0, y1)`.
pub type Rect = (f64, f64, f64, f64);

/// `Int_patch exp(-v (X + R) / (2 kappa)) / R dr'` [m] for the target
/// `t`, `R = |t - r'|`: the surface rise under a unit flux on the patch is
/// this over `2 pi lam`.
pub fn patch_integral(m: Motion, t: (f64, f64), patch: Rect) -> f64 {
    let (sx0, sx1) = (t.0 - patch.1, t.0 - patch.0);
    let (sy0, sy1) = (t.1 - patch.3, t.1 - patch.2);
    if sx0 < 0.0 && 0.0 < sx1 && sy0 < 0.0 && 0.0 < sy1 {
        [(sx1, sy1), (sx0, sy1), (sx1, sy0), (sx0, sy0)]
            .into_iter()
            .map(|(x, y)| corner(m, x, y))
            .sum()
    } else {
        adaptive(&|x, y| m.kernel((x, y)), (sx0, sx1, sy0, sy1))
    }
}

/// The integral over the rectangle with corners `(0, 0)` and `(x, y)`:
/// triangle A `s = (x u, y u w)`, triangle B `s = (x u w, y u)`, `ds =
/// |x y| u du dw`; the kernel is homogeneous (`1/R` of degree -1, the
/// exponent of degree 1), so the factor `u` cancels.
fn corner(m: Motion, x: f64, y: f64) -> f64 {
    let area = (x * y).abs();
    let a = |u: f64, w: f64| {
        let s = (x, y * w);
        area * (-u * m.exponent(s)).exp() / s.0.hypot(s.1)
    };
    let b = |u: f64, w: f64| {
        let s = (x * w, y);
        area * (-u * m.exponent(s)).exp() / s.0.hypot(s.1)
    };
    adaptive(&a, (0.0, 1.0, 0.0, 1.0)) + adaptive(&b, (0.0, 1.0, 0.0, 1.0))
}

/// Panels per side of the first pass: fine enough that no feature of the
/// integrand (the wake, `sqrt(kappa R / v)` wide, a few hundredths of the
/// patch at the highest Peclet number) falls between the nodes.
const PANELS: usize = 64;
/// Gauss-Legendre points per axis and panel.
const POINTS: usize = 6;
/// Each panel is bisected until its four quarters agree with it to this
/// fraction of the first pass's total, in proportion to its area, or to
/// [`RELATIVE`] of its own value (where the integrand concentrates in a
/// corner of the domain, rounding would otherwise stop the area's share
/// from ever being met).
const TOLERANCE: f64 = 1e-11;
/// The panel's own relative tolerance.
const RELATIVE: f64 = 1e-13;

/// `Int_rect f` by adaptive tensor Gauss-Legendre.
pub fn adaptive(f: &impl Fn(f64, f64) -> f64, r: Rect) -> f64 {
    let (x, w) = gauss_legendre(POINTS);
    let rule = |r: Rect| -> f64 {
        let (cx, hx) = (0.5 * (r.0 + r.1), 0.5 * (r.1 - r.0));
        let (cy, hy) = (0.5 * (r.2 + r.3), 0.5 * (r.3 - r.2));
        let mut sum = 0.0;
        for (xi, wi) in x.iter().zip(&w) {
            for (yj, wj) in x.iter().zip(&w) {
                sum += wi * wj * f(cx + hx * xi, cy + hy * yj);
            }
        }
        sum * hx * hy
    };
    let (dx, dy) = ((r.1 - r.0) / PANELS as f64, (r.3 - r.2) / PANELS as f64);
    let mut panels = Vec::with_capacity(PANELS * PANELS);
    for i in 0..PANELS {
        for j in 0..PANELS {
            let p = (
                r.0 + i as f64 * dx,
                r.0 + (i + 1) as f64 * dx,
                r.2 + j as f64 * dy,
                r.2 + (j + 1) as f64 * dy,
            );
            panels.push((p, rule(p)));
        }
    }
    let total: f64 = panels.iter().map(|p| p.1).sum();
    let density = TOLERANCE * total.abs() / ((r.1 - r.0) * (r.3 - r.2)).abs();
    panels
        .into_iter()
        .map(|(p, whole)| refine(&rule, p, whole, density, 30))
        .sum()
}

fn refine(rule: &impl Fn(Rect) -> f64, r: Rect, whole: f64, density: f64, depth: u32) -> f64 {
    let (mx, my) = (0.5 * (r.0 + r.1), 0.5 * (r.2 + r.3));
    let quarters = [
        (r.0, mx, r.2, my),
        (mx, r.1, r.2, my),
        (r.0, mx, my, r.3),
        (mx, r.1, my, r.3),
    ];
    let parts = quarters.map(rule);
    let sum: f64 = parts.iter().sum();
    let area = ((r.1 - r.0) * (r.3 - r.2)).abs();
    let diff = (sum - whole).abs();
    if depth == 0 || diff <= density * area || diff <= RELATIVE * sum.abs() {
        return sum;
    }
    quarters
        .into_iter()
        .zip(parts)
        .map(|(q, p)| refine(rule, q, p, density, depth - 1))
        .sum()
}

/// `Int 1/R` over a rectangle of `s`, in closed form (the source at
/// rest): `F(x, y) = x ln(y + R) + y ln(x + R)` at the corners.
pub fn stationary(t: (f64, f64), patch: Rect) -> f64 {
    let f = |x: f64, y: f64| {
        let r = x.hypot(y);
        x * (y + r).ln() + y * (x + r).ln()
    };
    let (sx0, sx1) = (t.0 - patch.1, t.0 - patch.0);
    let (sy0, sy1) = (t.1 - patch.3, t.1 - patch.2);
    f(sx1, sy1) - f(sx0, sy1) - f(sx1, sy0) + f(sx0, sy0)
}
