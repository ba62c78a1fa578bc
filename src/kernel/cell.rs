//! Cell integrals of the layer's Green's function (paper Eq. 5; physics.md
//! section 3, "Finite thickness").
//!
//! The spatial factor of a layer coefficient is the integral of Eq. 5's
//! `Theta(r/h) / r` over the source cell, not `Theta` at the centre
//! distance times Love's integral (Eq. 6's collocation, kept as
//! [`ThetaRule::Collocation`]). With `Theta(rho) = 1 + rho psi(rho)`
//! ([`super::ThetaTable::psi`]):
//!
//! `M(d) = int_cell Theta(|d - x'|/h) / |d - x'| d2x' = L(d) + (1/h) int_cell psi(|d - x'|/h) d2x'`,
//!
//! `L` Love's closed form ([`super::love`]). The remainder's integrand is
//! even and analytic in each coordinate within `2h` of the real axis
//! (`psi` is analytic in `rho^2` for `|Im rho| < 2`), so tensor
//! Gauss-Legendre on sub-panels no longer than `2h` converges
//! geometrically: an `n`-point rule on a panel of length `b` leaves about
//! `r^-2n`, with `r = c + sqrt(1 + c^2)` the Bernstein parameter of an
//! ellipse reaching `1.5h` (`c = 3h/b`); `n` is chosen for
//! `r^-2n <= 1e-10` (10 nodes per side at `h <= a/2`, 7 at `h = a`, 2 for
//! `h >~ 50a`). Measured against independent polar-coordinate quadrature:
//! below 1e-9 of the self coefficient (tests/kernel/layer_cells.rs). Beyond the reach of
//! `Theta` (`|Theta| < 1e-13`, `r > rho_end h`), `M = 0` exactly.
//!
//! The tensor rule's cost grows like `(a/h)^2` (144,000 nodes per point at
//! `h = a/83`), so on layers thin against the cell (more than
//! `POLAR_ABOVE_NODES` nodes) `M` is evaluated whole in polar coordinates
//! around the target instead: along each ray the `1/r` cancels the
//! Jacobian, `M = int dphi [T_0(t1) - T_0(t0)]` with the tabulated radial
//! moment `T_0(t) = int_0^t Theta(s/h) ds` and `[t0, t1]` the ray's chord
//! through the cell, smooth in `phi` between the corner directions
//! (adaptive Gauss-Kronrod from there; a linear weight adds the moment
//! `T_1`). Its cost does not grow with `a/h`; it equals Love plus the
//! tensor rule to 6e-11 of the cell size (tests below) and made a 256^2
//! solve on a bonded layer of `h = 0.077 a` nine times faster.
//!
//! The friction stencil averages `M` across the target cell's width
//! (physics.md section 5): the width average and the source-cell integral
//! combine into one integral over the offset `u = t - eta` with the
//! triangular weight `(w - |u|)/w` on `[-w, w]`, integrated the same way
//! (split at `u = 0`, where the weight has its kink).

use super::quad::{adaptive, clean_breaks, gauss_legendre_unit};
use super::thickness::ThetaTable;
use super::Axis;

/// How `Theta(r/h)` enters the layer's coefficients.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ThetaRule {
    /// The cell integral of Eq. 5's Green's function `Theta(r/h) G(r)`
    /// over the source cell (the default; converges to the continuous
    /// layer as the cell shrinks, error O(a^2)).
    #[default]
    CellIntegral,
    /// The paper's Eq. 6: `Theta` at the centre-to-point distance times the
    /// half-space's cell integral. Reproduces the paper exactly; its error
    /// against the cell integral is O(a/h) at the self coefficient (15 % at
    /// `h = 3.8 a`, 91 % at `h = a` for a bonded incompressible layer).
    Collocation,
}

/// Relative size of the Gauss-Legendre truncation asked of the cell rules.
const RULE_TOL: f64 = 1e-10;

/// Tensor-rule nodes beyond which a cell integral takes the polar rule
/// ([`LayerCell::polar`]): the tensor rule's cost grows like `(a/h)^2`
/// (400 nodes at `h ~ a/4`, 144,000 at `h = a/83`), the polar rule's not.
const POLAR_ABOVE_NODES: usize = 400;

/// Relative size (of the cell's perimeter scale `ax + ay`) of the absolute
/// error asked of the polar rule: the tensor rule's `1e-10` of
/// `int |psi| / h ~ a`, with a margin.
const POLAR_TOL: f64 = 1e-12;

/// A rectangle `[x0, x1] x [y0, y1]` of source points with the weight
/// `alpha + bx x' + by y'` (the cell with weight 1, or one half of the
/// width average's triangular weight).
#[derive(Debug, Clone, Copy)]
struct Patch {
    x0: f64,
    x1: f64,
    y0: f64,
    y1: f64,
    alpha: f64,
    bx: f64,
    by: f64,
}

impl Patch {
    fn corners(&self) -> [(f64, f64); 4] {
        [
            (self.x0, self.y0),
            (self.x1, self.y0),
            (self.x0, self.y1),
            (self.x1, self.y1),
        ]
    }

    /// Where the ray `(x, y) + t (c, s)`, `t >= 0`, is inside: `[t0, t1]`,
    /// or `None`.
    #[inline]
    fn chord(&self, x: f64, y: f64, c: f64, s: f64) -> Option<(f64, f64)> {
        let mut t0 = 0.0f64;
        let mut t1 = f64::INFINITY;
        for (p, d, lo, hi) in [(x, c, self.x0, self.x1), (y, s, self.y0, self.y1)] {
            if d.abs() < 1e-300 {
                if p < lo || p > hi {
                    return None;
                }
            } else {
                let (ta, tb) = ((lo - p) / d, (hi - p) / d);
                t0 = t0.max(ta.min(tb));
                t1 = t1.min(ta.max(tb));
            }
        }
        (t1 > t0).then_some((t0, t1))
    }
}

/// Nodes `(position, weight)` for `int_{-len/2}^{len/2} f`, with `f` analytic
/// within `2h` of the real axis.
fn box_nodes(len: f64, h: f64) -> Vec<(f64, f64)> {
    panel_nodes(-0.5 * len, 0.5 * len, h, |_| 1.0)
}

/// Nodes for `(1/w) int_{-w}^{w} (w - |u|) f(u) du`: the width average of
/// a source-cell integral over a target of the same width `w`.
fn tri_nodes(w: f64, h: f64) -> Vec<(f64, f64)> {
    let weight = |u: f64| (w - u.abs()) / w;
    let mut n = panel_nodes(-w, 0.0, h, weight);
    n.extend(panel_nodes(0.0, w, h, weight));
    n
}

/// Gauss-Legendre on `[lo, hi]` split into panels no longer than `2h`, with
/// the node count from the Bernstein-ellipse bound (module docs), times
/// `weight` at the nodes.
fn panel_nodes(lo: f64, hi: f64, h: f64, weight: impl Fn(f64) -> f64) -> Vec<(f64, f64)> {
    let len = hi - lo;
    let panels = (len / (2.0 * h)).ceil().max(1.0) as usize;
    let b = len / panels as f64;
    // The singularities lie 2h from the real axis; the bound is taken at
    // 1.5h, where `psi` on the ellipse stays moderate.
    let c = 3.0 * h / b;
    let r = c + (1.0 + c * c).sqrt();
    let n = ((1.0 / RULE_TOL).ln() / (2.0 * r.ln()))
        .ceil()
        .clamp(2.0, 16.0) as usize;
    let (gx, gw) = gauss_legendre_unit(n);
    let mut out = Vec::with_capacity(panels * n);
    for p in 0..panels {
        let a = lo + p as f64 * b;
        for (t, wt) in gx.iter().zip(&gw) {
            let x = a + b * t;
            out.push((x, b * wt * weight(x)));
        }
    }
    out
}

/// The layer part of one source cell's coefficients: `psi` integrals and
/// the reach of `Theta`.
#[derive(Debug, Clone)]
pub(crate) struct LayerCell {
    theta: ThetaTable,
    /// `1/h` \[1/m\].
    inv_h: f64,
    /// Distance beyond which `Theta = 0` \[m\].
    reach: f64,
    hx: f64,
    hy: f64,
    box_x: Vec<(f64, f64)>,
    box_y: Vec<(f64, f64)>,
    tri_x: Vec<(f64, f64)>,
    tri_y: Vec<(f64, f64)>,
    /// Whether the cell integrals take the polar rule.
    polar: bool,
}

impl LayerCell {
    /// Rules for an `ax x ay` source cell on the layer of `theta`.
    pub(crate) fn new(theta: &ThetaTable, ax: f64, ay: f64) -> Self {
        let h = theta.layer.thickness;
        let (box_x, box_y) = (box_nodes(ax, h), box_nodes(ay, h));
        let polar = box_x.len() * box_y.len() > POLAR_ABOVE_NODES;
        Self {
            theta: theta.clone(),
            inv_h: 1.0 / h,
            reach: theta.reach(),
            hx: 0.5 * ax,
            hy: 0.5 * ay,
            box_x,
            box_y,
            tri_x: tri_nodes(ax, h),
            tri_y: tri_nodes(ay, h),
            polar,
        }
    }

    /// Whether [`Self::cell_integral`] and [`Self::cell_integral_average`]
    /// take the polar rule (the layer is thin against the cell) rather than
    /// Love's closed form plus the tensor rule for the `psi` part.
    pub(crate) fn is_polar(&self) -> bool {
        self.polar
    }

    /// `M(x, y)` \[m\], the whole cell integral of `Theta(r/h) / r`, by the
    /// polar rule (only where [`Self::is_polar`]; otherwise Love's `L` plus
    /// [`Self::psi_part`]).
    pub(crate) fn cell_integral(&self, x: f64, y: f64) -> f64 {
        let (hx, hy) = (self.hx, self.hy);
        self.polar(
            x,
            y,
            &[Patch {
                x0: -hx,
                x1: hx,
                y0: -hy,
                y1: hy,
                alpha: 1.0,
                bx: 0.0,
                by: 0.0,
            }],
        )
    }

    /// `M` averaged across a target of the cell's width transverse to
    /// `axis`, at `(x, y)`, by the polar rule: the source cell and the
    /// target segment combine into a rectangle twice the width with the
    /// triangular weight `(w - |u|)/w` (module docs), two patches of linear
    /// weight.
    pub(crate) fn cell_integral_average(&self, x: f64, y: f64, axis: Axis) -> f64 {
        let (hx, hy) = (self.hx, self.hy);
        let patches = match axis {
            Axis::X => {
                let w = 2.0 * hy;
                [
                    Patch {
                        x0: -hx,
                        x1: hx,
                        y0: 0.0,
                        y1: w,
                        alpha: 1.0,
                        bx: 0.0,
                        by: -1.0 / w,
                    },
                    Patch {
                        x0: -hx,
                        x1: hx,
                        y0: -w,
                        y1: 0.0,
                        alpha: 1.0,
                        bx: 0.0,
                        by: 1.0 / w,
                    },
                ]
            }
            Axis::Y => {
                let w = 2.0 * hx;
                [
                    Patch {
                        x0: 0.0,
                        x1: w,
                        y0: -hy,
                        y1: hy,
                        alpha: 1.0,
                        bx: -1.0 / w,
                        by: 0.0,
                    },
                    Patch {
                        x0: -w,
                        x1: 0.0,
                        y0: -hy,
                        y1: hy,
                        alpha: 1.0,
                        bx: 1.0 / w,
                        by: 0.0,
                    },
                ]
            }
        };
        self.polar(x, y, &patches)
    }

    /// `int_patches w(x') Theta(|x' - d|/h) / |x' - d| d2x'` in polar
    /// coordinates around `d = (x, y)`: along the ray of direction `phi`
    /// the `1/r` cancels the Jacobian and a linear weight gives
    /// `(alpha + bx x + by y) [T_0]_{t0}^{t1} + (bx cos phi + by sin phi) [T_1]_{t0}^{t1}`
    /// with the tabulated radial moments `T_k(t) = int_0^t s^k Theta(s/h) ds`
    /// ([`ThetaTable::radial_moments`]), `[t0, t1]` where the ray crosses
    /// the patch. The angular integrand is smooth between the directions
    /// of the patches' corners (where the exit side changes), so adaptive
    /// Gauss-Kronrod from those breaks converges fast, at a cost that does
    /// not grow with `a/h`.
    fn polar(&self, x: f64, y: f64, patches: &[Patch]) -> f64 {
        use std::f64::consts::PI;
        let mut breaks: Vec<f64> = patches
            .iter()
            .flat_map(|p| p.corners())
            .map(|(cx, cy)| (cy - y).atan2(cx - x))
            .collect();
        breaks.extend([-PI, PI]);
        let breaks = clean_breaks(breaks, -PI, PI);
        let reach = self.reach;
        let ray = |phi: f64| {
            let (s, c) = phi.sin_cos();
            let mut v = 0.0;
            for p in patches {
                let Some((t0, t1)) = p.chord(x, y, c, s) else {
                    continue;
                };
                if t0 >= reach {
                    continue;
                }
                let (a0, a1) = self.theta.radial_moments(t0);
                let (b0, b1) = self.theta.radial_moments(t1);
                v +=
                    (p.alpha + p.bx * x + p.by * y) * (b0 - a0) + (p.bx * c + p.by * s) * (b1 - a1);
            }
            v
        };
        let abs_tol = POLAR_TOL * 2.0 * (self.hx + self.hy);
        adaptive(ray, &breaks, abs_tol, 1e-13, 2000)
    }

    /// Distance \[m\] beyond which `Theta = 0`.
    pub(crate) fn reach(&self) -> f64 {
        self.reach
    }

    /// Whether every point of the `[x - gx, x + gx] x [y - gy, y + gy]` box
    /// is beyond the reach of `Theta` from every point of the cell.
    #[inline]
    pub(crate) fn beyond(&self, x: f64, y: f64, gx: f64, gy: f64) -> bool {
        let dx = (x.abs() - self.hx - gx).max(0.0);
        let dy = (y.abs() - self.hy - gy).max(0.0);
        dx * dx + dy * dy > self.reach * self.reach
    }

    /// `(1/h) sum_ij wx_i wy_j psi(|(x - x_i, y - y_j)| / h)`.
    #[inline]
    fn psi_sum(&self, x: f64, y: f64, xs: &[(f64, f64)], ys: &[(f64, f64)]) -> f64 {
        let ih = self.inv_h;
        let mut s = 0.0;
        for &(xi, wi) in xs {
            let dx = (x - xi) * ih;
            let dx2 = dx * dx;
            let mut row = 0.0;
            for &(yj, wj) in ys {
                let dy = (y - yj) * ih;
                row += wj * self.theta.psi((dx2 + dy * dy).sqrt());
            }
            s += wi * row;
        }
        s * ih
    }

    /// `M(x, y) - L(x, y)` \[m\]: the `psi` part of the cell integral.
    #[inline]
    pub(crate) fn psi_part(&self, x: f64, y: f64) -> f64 {
        self.psi_sum(x, y, &self.box_x, &self.box_y)
    }

    /// The `psi` part of `M` averaged across a target of the cell's width
    /// transverse to `axis`, at `(x, y)`.
    pub(crate) fn psi_part_average(&self, x: f64, y: f64, axis: Axis) -> f64 {
        match axis {
            Axis::X => self.psi_sum(x, y, &self.box_x, &self.tri_y),
            Axis::Y => self.psi_sum(x, y, &self.tri_x, &self.box_y),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kernel::love::LoveRect;
    use crate::response::{Layer, LayerBase};

    const A: f64 = 1e-4;

    fn cell(base: LayerBase, h_cells: f64, ax: f64, ay: f64) -> LayerCell {
        let theta = ThetaTable::new(
            Layer {
                thickness: h_cells * A,
                base,
            },
            0.5,
        )
        .unwrap();
        LayerCell::new(&theta, ax, ay)
    }

    /// Target points inside, on and near the edges, outside near a corner
    /// and farther away, in units of `A`.
    const POINTS: [(f64, f64); 9] = [
        (0.0, 0.0),
        (0.3, 0.1),
        (0.5, 0.0),
        (0.5003, 0.2),
        (-0.45, 0.49),
        (0.7, 0.6),
        (1.2, 0.1),
        (2.0, 1.0),
        (0.0, -1.1),
    ];

    /// The polar rule against Love's closed form plus the tensor rule of
    /// the `psi` part (two independent evaluations of the same integral;
    /// the tensor rule asks 1e-10 of its panels), on square and
    /// rectangular cells, where both are affordable: below 1e-10 of the
    /// larger of the value and the cell size (the tensor rule's own
    /// accuracy).
    #[test]
    fn polar_rule_equals_love_plus_the_tensor_rule() {
        let mut worst = 0.0f64;
        for base in [LayerBase::Bonded, LayerBase::Frictionless] {
            for h_cells in [0.06, 0.12, 0.25, 0.5, 1.0, 3.0] {
                for (ax, ay) in [(A, A), (A, 0.6 * A)] {
                    let lc = cell(base, h_cells, ax, ay);
                    let love = LoveRect::new(ax, ay);
                    for (i, j) in POINTS {
                        let (x, y) = (i * A, j * A);
                        let tensor = love.eval(x, y) + lc.psi_part(x, y);
                        let polar = lc.cell_integral(x, y);
                        let err = (polar - tensor).abs() / tensor.abs().max(A);
                        worst = worst.max(err);
                        assert!(
                            err < 1e-10,
                            "{base:?} h = {h_cells} a, cell {ax:e} x {ay:e}, ({i}, {j}): polar {polar:e}, tensor {tensor:e}"
                        );
                    }
                }
            }
        }
        eprintln!("worst |polar - tensor| / max(|M|, a) = {worst:e}");
    }

    /// The width average: the polar rule's triangular patches against the
    /// tensor rule's `psi` part plus Love's `L` averaged over the target
    /// segment by adaptive quadrature.
    #[test]
    fn polar_average_equals_love_plus_the_tensor_rule() {
        let mut worst = 0.0f64;
        for base in [LayerBase::Bonded, LayerBase::Frictionless] {
            for h_cells in [0.06, 0.25, 1.0] {
                let (ax, ay) = (A, 0.8 * A);
                let lc = cell(base, h_cells, ax, ay);
                let love = LoveRect::new(ax, ay);
                for axis in [Axis::X, Axis::Y] {
                    for (i, j) in POINTS {
                        let (x, y) = (i * A, j * A);
                        let w = match axis {
                            Axis::X => ay,
                            Axis::Y => ax,
                        };
                        let along = |t: f64| match axis {
                            Axis::X => love.eval(x, y + t),
                            Axis::Y => love.eval(x + t, y),
                        };
                        // L has kinks where the segment crosses the cell's
                        // edge lines.
                        let edge = match axis {
                            Axis::X => [-0.5 * ay - y, 0.5 * ay - y],
                            Axis::Y => [-0.5 * ax - x, 0.5 * ax - x],
                        };
                        let breaks = clean_breaks(edge.to_vec(), -0.5 * w, 0.5 * w);
                        let love_avg = adaptive(along, &breaks, 1e-16 * A, 1e-15, 4000) / w;
                        let tensor = love_avg + lc.psi_part_average(x, y, axis);
                        let polar = lc.cell_integral_average(x, y, axis);
                        let err = (polar - tensor).abs() / A;
                        worst = worst.max(err);
                        assert!(
                            err < 1e-10,
                            "{base:?} h = {h_cells} a, {axis:?}, ({i}, {j}): polar {polar:e}, tensor {tensor:e}"
                        );
                    }
                }
            }
        }
        eprintln!("worst |polar - tensor| / a = {worst:e}");
    }
}
