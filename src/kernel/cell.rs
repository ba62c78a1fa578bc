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
//! The friction stencil averages `M` across the target cell's width
//! (physics.md section 5): the width average and the source-cell integral
//! combine into one integral over the offset `u = t - eta` with the
//! triangular weight `(w - |u|)/w` on `[-w, w]`, integrated the same way
//! (split at `u = 0`, where the weight has its kink).

use super::quad::gauss_legendre_unit;
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
}

impl LayerCell {
    /// Rules for an `ax x ay` source cell on the layer of `theta`.
    pub(crate) fn new(theta: &ThetaTable, ax: f64, ay: f64) -> Self {
        let h = theta.layer.thickness;
        Self {
            theta: theta.clone(),
            inv_h: 1.0 / h,
            reach: theta.reach(),
            hx: 0.5 * ax,
            hy: 0.5 * ay,
            box_x: box_nodes(ax, h),
            box_y: box_nodes(ay, h),
            tri_x: tri_nodes(ax, h),
            tri_y: tri_nodes(ay, h),
        }
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
