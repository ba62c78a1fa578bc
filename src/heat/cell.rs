//! The moving point source integrated over one rectangular cell
//! (physics.md section 14, "Real space"; Carslaw & Jaeger, sec. 10.7).
//!
//! A source `P` \[W\] at `r'` on the surface of a half-space moving with
//! velocity `-v e_v` raises the surface at `r` by
//! `theta = P / (2 pi lam R) exp(-v (X + R) / (2 kappa))`,
//! `R = |s|`, `X = s . e_v`, `s = r - r'`. [`MovingSource::rect`] returns
//! `I = Int_rect exp(-v (X + R) / (2 kappa)) / R ds` over a rectangle of
//! `s` (the rise is `q I / (2 pi lam)` for a uniform flux `q` on the cell).
//!
//! Three rules, chosen per cell:
//! - **Polar** (the cell itself, its neighbours, and cells across which the
//!   exponential varies fast): around the target, `ds = rho drho dalpha`
//!   cancels `1 / R`, and the radial integral is analytic:
//!   `Int exp(-b rho) drho = exp(-b rho_in) (1 - exp(-b (rho_out - rho_in))) / b`,
//!   `b = v (1 + cos(alpha - phi)) / (2 kappa) = (v / kappa) sin^2(beta / 2)`
//!   with `beta` the angle from the wake direction `-e_v`. What remains is a
//!   1-D integral over `beta`, split at the corners' angles (where the
//!   entry and exit edges of the ray change) and at the wake (`beta = 0`),
//!   each piece integrated by adaptive Gauss-Legendre to a relative
//!   `1e-11`. The singular self cell needs nothing special (`rho_in = 0`).
//! - **Cartesian** tensor Gauss-Legendre on cells away from the target
//!   where the exponent `E = v (X + R) / (2 kappa)` is nearly linear, with
//!   the fewest points (3, 4 or 6 per axis) whose error estimate stays
//!   below about 1e-11 relative. The `n`-point rule's error on `[-1, 1]`
//!   is `K_n f^(2n)` (`K_3 = 6.4e-5`, `K_4 = 2.9e-7`, `K_6 = 1.5e-12`):
//!   for `1/R` at `d` from the centre of a half-width `w`, a Bernstein
//!   ellipse of parameter `2 d / w` gives `4 (2 d / w)^-2n`; for the
//!   exponent's change `g` across the half-diagonal by its gradient,
//!   `K_n g^2n e^g / 2`; for its change `c` by its curvature (`1/R`
//!   across `e_v`), `K_n c^n (2n)! / n! / 2`. So: 3 points from
//!   `d >= 68 w` with `g <= 0.08`, `c <= 1.4e-3`; 4 from `d >= 14 w` with
//!   `g <= 0.3`, `c <= 0.014`; 6 from `d >= 6 h` (`h` the half-diagonal)
//!   with `g <= 1`, `c <= 0.2` (the unit tests check every rule against the
//!   polar one).
//! - **Midpoint** on cells whose largest possible value is below 1e-20 of
//!   the self cell's scale (ahead of the source at high Peclet numbers):
//!   any value there is below the round-off of every sum with the near
//!   cells.

use crate::gauss::gauss_legendre;

/// A rectangle `[x0, x1] x [y0, y1]` of `s = r - r'` \[m\].
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Rect {
    pub x0: f64,
    pub x1: f64,
    pub y0: f64,
    pub y1: f64,
}

impl Rect {
    /// The cell of sides `dx x dy` centred at `(cx, cy)`.
    pub fn centred(cx: f64, cy: f64, dx: f64, dy: f64) -> Self {
        Self {
            x0: cx - 0.5 * dx,
            x1: cx + 0.5 * dx,
            y0: cy - 0.5 * dy,
            y1: cy + 0.5 * dy,
        }
    }

    fn centre(&self) -> (f64, f64) {
        (0.5 * (self.x0 + self.x1), 0.5 * (self.y0 + self.y1))
    }

    fn half_diagonal(&self) -> f64 {
        0.5 * (self.x1 - self.x0).hypot(self.y1 - self.y0)
    }

    fn corners(&self) -> [(f64, f64); 4] {
        [
            (self.x0, self.y0),
            (self.x1, self.y0),
            (self.x1, self.y1),
            (self.x0, self.y1),
        ]
    }

    fn contains_origin(&self) -> bool {
        self.x0 < 0.0 && 0.0 < self.x1 && self.y0 < 0.0 && 0.0 < self.y1
    }

    /// `[rho_in, rho_out]` of the ray `rho u`, `rho >= 0`, inside the
    /// rectangle (slabs), or `None`.
    fn chord(&self, (ux, uy): (f64, f64)) -> Option<(f64, f64)> {
        let (mut lo, mut hi) = (0.0f64, f64::INFINITY);
        for (u, a, b) in [(ux, self.x0, self.x1), (uy, self.y0, self.y1)] {
            if u != 0.0 {
                let (t1, t2) = (a / u, b / u);
                lo = lo.max(t1.min(t2));
                hi = hi.min(t1.max(t2));
            } else if !(a <= 0.0 && 0.0 <= b) {
                return None;
            }
        }
        (hi > lo).then_some((lo, hi))
    }
}

/// Gauss-Legendre points of the adaptive polar rule.
const POLAR_POINTS: usize = 8;
/// Relative tolerance of each polar piece.
const POLAR_TOLERANCE: f64 = 1e-11;
/// Bisections at most per piece.
const POLAR_DEPTH: u32 = 40;
/// The Cartesian rules: points per axis, and the least distance of the
/// cell's centre in per-axis half-widths, the largest change of the
/// exponent by its gradient and by its curvature across a half-diagonal
/// each accepts (module docs).
const CARTESIAN: [(usize, f64, f64, f64); 3] = [
    (3, 68.0, 0.08, 1.4e-3),
    (4, 14.0, 0.3, 0.014),
    (6, 0.0, 1.0, 0.2),
];
/// Distance of the cell's centre, in half-diagonals, from which the
/// Cartesian rules may serve.
const FAR_HALF_DIAGONALS: f64 = 6.0;
/// Bound, relative to the self cell's scale, below which a cell is
/// negligible.
const NEGLIGIBLE: f64 = 1e-20;

/// The moving point source of one speed, diffusivity and direction, with
/// its quadrature rules.
#[derive(Debug, Clone)]
pub(crate) struct MovingSource {
    /// `-e_v`: the direction in which heat trails behind.
    wake: (f64, f64),
    /// `v / kappa` \[1/m\].
    rate: f64,
    polar: (Vec<f64>, Vec<f64>),
    /// The rules of [`CARTESIAN`], in its order.
    cartesian: [(Vec<f64>, Vec<f64>); 3],
}

/// Which rule [`MovingSource::rect`] picked.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Rule {
    Polar,
    /// The Cartesian rule of index `k` in [`CARTESIAN`].
    Cartesian(usize),
    Midpoint,
}

impl MovingSource {
    /// The source sliding at `speed` along `e_v = direction` (a unit
    /// vector) in a solid of diffusivity `kappa`.
    pub fn new(speed: f64, kappa: f64, direction: (f64, f64)) -> Self {
        Self {
            wake: (-direction.0, -direction.1),
            rate: speed / kappa,
            polar: gauss_legendre(POLAR_POINTS),
            cartesian: CARTESIAN.map(|(n, ..)| gauss_legendre(n)),
        }
    }

    /// `Int_rect exp(-v (X + R) / (2 kappa)) / R ds` \[m\], by the rule
    /// [`MovingSource::rule`] picks.
    pub fn rect(&self, r: Rect) -> f64 {
        match self.rule(r) {
            Rule::Polar => self.polar(r),
            Rule::Cartesian(k) => self.cartesian(r, k),
            Rule::Midpoint => self.midpoint(r),
        }
    }

    /// The rule for cell `r` (module docs).
    pub fn rule(&self, r: Rect) -> Rule {
        let (cx, cy) = r.centre();
        let h = r.half_diagonal();
        let d = cx.hypot(cy);
        if d < FAR_HALF_DIAGONALS * h {
            return Rule::Polar;
        }
        let sum = self.lead((cx, cy), d);
        // X + R is 2-Lipschitz in s: its least value on the cell is at
        // least `sum - 2h`, and 1/R at most 1/(d - h).
        let bound =
            (-0.5 * self.rate * (sum - 2.0 * h)).exp() * ((r.x1 - r.x0) * (r.y1 - r.y0) / (d - h));
        if bound < NEGLIGIBLE * h {
            return Rule::Midpoint;
        }
        // |grad (X + R)| = |e_v + s/R| = sqrt(2 (X + R) / R); the
        // curvature of R is at most 1/R, a change h^2 / (2 R).
        let gradient = 0.5 * self.rate * (2.0 * sum / d).sqrt() * h;
        let curvature = 0.25 * self.rate * h * h / (d - h);
        let width = 0.5 * (r.x1 - r.x0).max(r.y1 - r.y0);
        CARTESIAN
            .iter()
            .position(|&(_, far, g, c)| d >= far * width && gradient <= g && curvature <= c)
            .map_or(Rule::Polar, Rule::Cartesian)
    }

    /// The integrand at the cell's centre times its area.
    fn midpoint(&self, r: Rect) -> f64 {
        let c = r.centre();
        let d = c.0.hypot(c.1);
        (-0.5 * self.rate * self.lead(c, d)).exp() / d * (r.x1 - r.x0) * (r.y1 - r.y0)
    }

    /// `X + R` at `s` (`R = |s|` given), without cancellation behind the
    /// source (`X ~ -R`): there `X + R = Y^2 / (R - X)`.
    fn lead(&self, (sx, sy): (f64, f64), r: f64) -> f64 {
        // X = s . e_v = -(s . wake); Y = the component across e_v.
        let x = -(sx * self.wake.0 + sy * self.wake.1);
        if x < 0.0 {
            let y = sx * self.wake.1 - sy * self.wake.0;
            y * y / (r - x)
        } else {
            x + r
        }
    }

    /// The Cartesian tensor Gauss rule of index `k` in [`CARTESIAN`].
    pub fn cartesian(&self, r: Rect, k: usize) -> f64 {
        let (nodes, weights) = &self.cartesian[k];
        let (hx, hy) = (0.5 * (r.x1 - r.x0), 0.5 * (r.y1 - r.y0));
        let (cx, cy) = r.centre();
        let mut sum = 0.0;
        for (xi, wi) in nodes.iter().zip(weights) {
            let sx = cx + hx * xi;
            let mut row = 0.0;
            for (yj, wj) in nodes.iter().zip(weights) {
                let sy = cy + hy * yj;
                let rr = sx.hypot(sy);
                row += wj * (-0.5 * self.rate * self.lead((sx, sy), rr)).exp() / rr;
            }
            sum += wi * row;
        }
        sum * hx * hy
    }

    /// The polar rule: the analytic radial integral along each ray, the
    /// angle by adaptive Gauss-Legendre between the corners' angles and the
    /// wake.
    pub fn polar(&self, r: Rect) -> f64 {
        let w = self.wake;
        // Angle of a vector from the wake direction, in (-pi, pi].
        let angle = |(x, y): (f64, f64)| (w.0 * y - w.1 * x).atan2(w.0 * x + w.1 * y);
        let mut breaks: Vec<f64> = Vec::with_capacity(6);
        let (start, end);
        if r.contains_origin() {
            breaks.extend(r.corners().map(angle));
            breaks.sort_by(f64::total_cmp);
            start = breaks[0];
            end = start + std::f64::consts::TAU;
            breaks.push(end);
        } else {
            // All corners lie within less than pi of the centre's angle.
            let c = r.centre();
            let base = angle(c);
            let rel = |(x, y): (f64, f64)| (c.0 * y - c.1 * x).atan2(c.0 * x + c.1 * y);
            breaks.extend(r.corners().map(|p| base + rel(p)));
            breaks.sort_by(f64::total_cmp);
            start = breaks[0];
            end = breaks[3];
        }
        // The wake (beta = 0 modulo 2 pi), where the integrand peaks.
        for wake in [-std::f64::consts::TAU, 0.0, std::f64::consts::TAU] {
            if start < wake && wake < end {
                breaks.push(wake);
            }
        }
        breaks.sort_by(f64::total_cmp);
        let floor = 1e-16 * r.half_diagonal();
        let f = |beta: f64| self.ray(r, beta);
        breaks
            .windows(2)
            .filter(|p| p[1] > p[0])
            .map(|p| {
                let whole = self.gauss(&f, p[0], p[1]);
                self.adapt(&f, p[0], p[1], whole, floor, POLAR_DEPTH)
            })
            .sum()
    }

    /// `Int exp(-b rho) drho` over the ray at angle `beta` from the wake.
    fn ray(&self, r: Rect, beta: f64) -> f64 {
        let (s, c) = beta.sin_cos();
        let u = (
            self.wake.0 * c - self.wake.1 * s,
            self.wake.0 * s + self.wake.1 * c,
        );
        let Some((rho_in, rho_out)) = r.chord(u) else {
            return 0.0;
        };
        let half = (0.5 * beta).sin();
        let b = self.rate * half * half;
        let len = rho_out - rho_in;
        let x = b * len;
        let phi = if x > 0.0 { -(-x).exp_m1() / x } else { 1.0 };
        (-b * rho_in).exp() * len * phi
    }

    fn gauss(&self, f: &impl Fn(f64) -> f64, a: f64, b: f64) -> f64 {
        let (nodes, weights) = &self.polar;
        let (m, h) = (0.5 * (a + b), 0.5 * (b - a));
        h * nodes
            .iter()
            .zip(weights)
            .map(|(x, w)| w * f(m + h * x))
            .sum::<f64>()
    }

    /// Bisect until the halves agree with the whole to the tolerance.
    fn adapt(
        &self,
        f: &impl Fn(f64) -> f64,
        a: f64,
        b: f64,
        whole: f64,
        floor: f64,
        depth: u32,
    ) -> f64 {
        let m = 0.5 * (a + b);
        let (left, right) = (self.gauss(f, a, m), self.gauss(f, m, b));
        let halves = left + right;
        if depth == 0 || (halves - whole).abs() <= POLAR_TOLERANCE * halves.abs() + floor {
            return halves;
        }
        self.adapt(f, a, m, left, 0.5 * floor, depth - 1)
            + self.adapt(f, m, b, right, 0.5 * floor, depth - 1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// At rest the self cell of a square of side `a` has the closed form
    /// `4 a ln(1 + sqrt 2)` (`Int 1/R` over the square, the target at its
    /// centre); an off-centre rectangle has Love's form.
    #[test]
    fn stationary_cells_match_the_closed_forms() {
        let love = |x: f64, y: f64| {
            let r = x.hypot(y);
            x * (y + r).ln() + y * (x + r).ln()
        };
        let rect_integral =
            |r: Rect| love(r.x1, r.y1) - love(r.x0, r.y1) - love(r.x1, r.y0) + love(r.x0, r.y0);
        let src = MovingSource::new(1e-12, 1.0, (1.0, 0.0));
        let a = 2e-3;
        let own = src.polar(Rect::centred(0.0, 0.0, a, a));
        let exact = 4.0 * a * (1.0 + 2f64.sqrt()).ln();
        assert!((own / exact - 1.0).abs() < 1e-10, "{own} vs {exact}");
        for (cx, cy) in [(0.3e-3, -0.2e-3), (3e-3, 1e-3), (-2e-3, 5e-3)] {
            let r = Rect::centred(cx, cy, a, 0.5 * a);
            let (p, e) = (src.polar(r), rect_integral(r));
            assert!((p / e - 1.0).abs() < 1e-10, "({cx}, {cy}): {p} vs {e}");
        }
    }

    /// Where a Cartesian rule serves it agrees with the polar rule to
    /// 1e-9 relative (measured: ~1e-11), over cell Peclet numbers from
    /// 1e-3 to 1e3, directions, aspect ratios and distances; every rule is
    /// met.
    #[test]
    fn the_cartesian_rules_agree_with_the_polar_where_chosen() {
        let (mut checked, mut worst) = ([0usize; 3], 0.0f64);
        for pe in [1e-3, 0.1, 1.0, 3.0, 10.0, 30.0, 1e3] {
            for deg in [0.0f64, 30.0, 90.0, 200.0] {
                let t = deg.to_radians();
                let src = MovingSource::new(pe, 1.0, (t.cos(), t.sin()));
                for (dx, dy) in [(1.0, 1.0), (1.0, 0.3)] {
                    for i in (-300..=300).step_by(7) {
                        for j in (-200..=200).step_by(5) {
                            let r = Rect::centred(i as f64 * dx, j as f64 * dy, dx, dy);
                            let Rule::Cartesian(k) = src.rule(r) else {
                                continue;
                            };
                            let (c, p) = (src.cartesian(r, k), src.polar(r));
                            assert!(
                                (c - p).abs() <= 1e-9 * p.abs(),
                                "Pe {pe}, {deg} deg, cell ({i}, {j}), rule {k}: {c} vs {p}"
                            );
                            worst = worst.max((c / p - 1.0).abs());
                            checked[k] += 1;
                        }
                    }
                }
            }
        }
        eprintln!("{checked:?} cells per rule, largest relative difference {worst:.2e}");
        assert!(checked.iter().all(|&c| c > 100), "{checked:?}");
    }
}
