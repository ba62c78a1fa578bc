//! Layers much thinner than a cell (paper Eq. 5; physics.md section 3,
//! "Finite thickness"): the local limit of the layer's Green's function.
//!
//! `G(r) = Theta(r/h) / r` vanishes beyond `R h` (`R = rho_end`, where
//! `|Theta| < 1e-13`, [`super::ThetaTable::rho_end`]). When `R h` is at
//! most half the shorter cell side, every point that matters (a cell
//! centre, the start of a trail, a cell edge's middle) sees at most one
//! straight edge of the source cell within reach, and the cell integral
//! `M` of `G` is exact in closed form from two numbers of the curve:
//!
//! * `m0 = 2 pi int_0^R Theta(rho) drho`, the integral of `G` over the
//!   plane in units of `h`: the layer's local compliance
//!   `prefactor * m0 h = 2 (1 - nu^2) S'(0) h` (`S'(0) = 1/2` frictionless:
//!   `w = p h (1 - nu^2)/E`; bonded `(1-2nu) / (2 (1-nu)^2)`: the
//!   oedometric `w = p h (1+nu)(1-2nu)/((1-nu)E)`; zero for a bonded
//!   incompressible layer, whose thin limit `w = -(h^3/E) lap p` has no
//!   response at the centre of a uniformly loaded cell: such layers take
//!   the law of [`super::thin_law`] on the cell grid);
//! * the edge profile: within `R h` of one straight edge,
//!   `M = m0 h F(t)`, `t` the signed distance into the cell over `h` and
//!   `F` the cumulative line projection of `G`,
//!   `1 - F(t) = (2/m0) int_t^R Theta(rho) acos(t/rho) drho` (`F(0) = 1/2`).
//!
//! The sliding trail then crosses smooth steps: the memory integral of
//! Eq. 4 is the step's exponential integral plus one correction per edge
//! reached, an integral of `1 - F` against the memory weight (exact to
//! the quadrature). The friction stencil's width average across the target
//! adds `c2 = 4 int_0^R rho Theta(rho) drho`: the strip of the source
//! cell averaged over a target of the same width `a_t` carries
//! `a_t m0 h - c2 h^2`, each neighbouring strip `c2 h^2 / 2`; the edge
//! profile of these averages is taken as `F` (its change of shape is
//! `O(h / a_t)` and matters only where `v tau ~ h`).

use std::sync::{Arc, Mutex, OnceLock};

use super::quad::gauss_legendre_unit;
use super::thickness::ThetaTable;
use super::{Axis, Cell, Coefficient, KernelError, SlidingKernel, ThetaRule};
use crate::response::LayerBase;

/// The numbers of the local limit for one (base, nu), computed once per
/// process.
#[derive(Debug)]
pub(crate) struct ThinProfile {
    /// `2 pi int Theta`.
    pub m0: f64,
    /// `4 int rho Theta`.
    pub c2: f64,
    /// `R = rho_end`.
    pub reach: f64,
    /// Quadrature nodes `t` on `[0, R]` (graded towards 0, where `F` has a
    /// `t log t` kink), weights, and `1 - F(t)` there.
    nodes: Vec<(f64, f64, f64)>,
    /// Start of the first panel.
    pub t_min: f64,
}

/// Integrals of `Theta` over `[lo, hi]` (16-point Gauss-Legendre on panels
/// of at most 0.5: `Theta` is a degree-14 polynomial on each Chebyshev
/// piece, so panels aligned with the pieces are exact).
fn integral(theta: &ThetaTable, lo: f64, hi: f64, weight: impl Fn(f64) -> f64) -> f64 {
    let gl = gauss_legendre_unit(16);
    let n = ((hi - lo) / 0.5).ceil().max(1.0) as usize;
    let b = (hi - lo) / n as f64;
    let mut s = 0.0;
    for p in 0..n {
        let a = lo + p as f64 * b;
        for (x, w) in gl.0.iter().zip(&gl.1) {
            let r = a + b * x;
            s += w * b * theta.eval(r) * weight(r);
        }
    }
    s
}

/// `1 - F(t) = (2/m0) int_t^R Theta(rho) acos(t/rho) drho`: the square-root
/// start `rho = t` by `rho = t + d s^2` on `[t, t + d]`, then panels.
fn one_minus_f(theta: &ThetaTable, m0: f64, t: f64, reach: f64) -> f64 {
    if t >= reach {
        return 0.0;
    }
    if t <= 0.0 {
        return 0.5;
    }
    let gl = gauss_legendre_unit(16);
    let d = t.min(0.5).min(reach - t);
    let mut s = 0.0;
    for (x, w) in gl.0.iter().zip(&gl.1) {
        let r = t + d * x * x;
        s += w * 2.0 * d * x * theta.eval(r) * (t / r).min(1.0).acos();
    }
    if t + d < reach {
        s += integral(theta, t + d, reach, |r| (t / r).min(1.0).acos());
    }
    2.0 * s / m0
}

impl ThinProfile {
    fn new(theta: &ThetaTable) -> Self {
        use rayon::prelude::*;
        let reach = theta.rho_end();
        let m0 = 2.0 * std::f64::consts::PI * integral(theta, 0.0, reach, |_| 1.0);
        let c2 = 4.0 * integral(theta, 0.0, reach, |r| r);
        // Panels: geometric (ratio 2) from R 2^-40 to 1, then at most 0.5.
        let t_min = reach.min(1.0) * 2f64.powi(-40);
        let mut breaks = vec![];
        let mut b = t_min;
        while b < reach.min(1.0) {
            breaks.push(b);
            b *= 2.0;
        }
        let n = ((reach - reach.min(1.0)) / 0.5).ceil() as usize;
        for k in 0..=n {
            breaks.push(reach.min(1.0) + (reach - reach.min(1.0)) * k as f64 / n.max(1) as f64);
        }
        breaks.dedup();
        let gl = gauss_legendre_unit(8);
        let pts: Vec<(f64, f64)> = breaks
            .windows(2)
            .flat_map(|w| {
                let (a, len) = (w[0], w[1] - w[0]);
                gl.0.iter()
                    .zip(&gl.1)
                    .map(move |(x, wt)| (a + len * x, len * wt))
                    .collect::<Vec<_>>()
            })
            .collect();
        let nodes = pts
            .par_iter()
            .map(|&(t, w)| (t, w, one_minus_f(theta, m0, t, reach)))
            .collect();
        Self {
            m0,
            c2,
            reach,
            nodes,
            t_min,
        }
    }

    /// `(h/l) int_0^R exp(-(s0 - t h)/l) (1 - F(t)) dt` for `sign = +1`
    /// (`exp(-(s0 + t h)/l)` for `sign = -1`): one half of an edge's
    /// correction for a memory term of length `l`, `s0 >= 0` the distance
    /// along the trail to the edge. `l = 0` gives the limit `(1/2)` at
    /// `s0 = 0`, zero beyond.
    pub(crate) fn edge_half(&self, h: f64, l: f64, s0: f64, sign: f64) -> f64 {
        if l == 0.0 {
            return if s0 == 0.0 && sign < 0.0 { 0.5 } else { 0.0 };
        }
        if !l.is_finite() {
            return 0.0;
        }
        // The first node's panel starts at `t_min`; below it `1 - F = 1/2`
        // to `O(t_min log t_min)`, integrated in closed form.
        let x = self.t_min * h / l;
        let sliver = 0.5 * (-s0 / l).exp() * (sign * x).exp_m1() / sign;
        let mut s = 0.0;
        for &(t, w, g) in &self.nodes {
            s += w * g * (-(s0 - sign * t * h) / l).exp();
        }
        s * h / l + sliver
    }
}

impl ThinProfile {
    /// `sum_n w_n (1 - F(t_n)) g(t_n)`: the integral of `(1 - F) g` over
    /// `[t_min, R]` (the nodes of the edge profile).
    pub(crate) fn profile_sum(&self, mut g: impl FnMut(f64) -> f64) -> f64 {
        self.nodes.iter().map(|&(t, w, f)| w * f * g(t)).sum()
    }
}

type ProfileCache = Mutex<Vec<((LayerBase, u64), Arc<ThinProfile>)>>;

/// The profile of `theta`'s (base, nu), computed once per process.
pub(crate) fn profile(theta: &ThetaTable) -> Arc<ThinProfile> {
    static CACHE: OnceLock<ProfileCache> = OnceLock::new();
    let cache = CACHE.get_or_init(|| Mutex::new(Vec::new()));
    let key = (theta.layer.base, theta.poisson.to_bits());
    if let Some((_, p)) = cache
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .iter()
        .find(|(k, _)| *k == key)
    {
        return p.clone();
    }
    let p = Arc::new(ThinProfile::new(theta));
    cache
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .push((key, p.clone()));
    p
}

/// Where a point lies against one pair of the source cell's edges at
/// `+-half`: the value of the smooth step there (1 inside, 0 outside,
/// 1/2 on an edge), or `None` within the reach of an edge but off it.
pub(super) fn step_value(x: f64, half: f64, reach: f64) -> Option<f64> {
    let d = half - x.abs();
    if d.abs() <= 1e-9 * half {
        Some(0.5)
    } else if d >= reach {
        Some(1.0)
    } else if d <= -reach {
        Some(0.0)
    } else {
        None
    }
}

impl SlidingKernel {
    /// The local limit's numbers when the layer's reach `R h` is at most
    /// half the shorter side of `ax x ay` cells (cell-integral rule only).
    pub(crate) fn thin_profile(&self, ax: f64, ay: f64) -> Option<Arc<ThinProfile>> {
        match (&self.theta, self.rule) {
            (Some(t), ThetaRule::CellIntegral) if self.local && t.reach() <= 0.5 * ax.min(ay) => {
                Some(profile(t))
            }
            _ => None,
        }
    }

    /// `(along, across, a_along, a_across)` of the offset `(dx, dy)` in the
    /// frame of `e_v` (along a grid axis; `None` otherwise).
    pub(super) fn frame(&self, dx: f64, dy: f64, ax: f64, ay: f64) -> Option<(f64, f64, f64, f64)> {
        match self.e {
            (x, 0.0) if x.abs() == 1.0 => Some((x * dx, dy, ax, ay)),
            (0.0, y) if y.abs() == 1.0 => Some((y * dy, dx, ay, ax)),
            _ => None,
        }
    }

    /// `(1/C) int_0^inf phi_k(s) P(x + s) ds` for one memory term of length
    /// `l` along a trail starting at `x` (module docs), `P` the smooth step
    /// of the source's `[-aa/2, aa/2]`; `None` where the trail starts
    /// within the reach of an edge but off it.
    fn thin_memory(p: &ThinProfile, h: f64, l: f64, x: f64, aa: f64) -> Option<f64> {
        let reach = p.reach * h;
        let pv = step_value(x, 0.5 * aa, reach)?;
        if l == 0.0 {
            return Some(pv);
        }
        if !l.is_finite() {
            return Some(0.0);
        }
        let s1 = (-0.5 * aa - x).max(0.0);
        let s2 = (0.5 * aa - x).max(0.0);
        let mut m = (-s1 / l).exp() - (-s2 / l).exp();
        // Entering at the left edge (+1), leaving at the right (-1).
        for (xe, dir) in [(-0.5 * aa, 1.0), (0.5 * aa, -1.0)] {
            let se = xe - x;
            if se.abs() <= 1e-9 * aa {
                m -= dir * p.edge_half(h, l, 0.0, -1.0);
            } else if se > 0.0 && (se - reach) / l < 700.0 {
                m += dir * (p.edge_half(h, l, se, 1.0) - p.edge_half(h, l, se, -1.0));
            }
        }
        Some(m)
    }

    /// `[glassy P(x) + sum_k C_k (1/C_k) int phi_k P]`: the bracket shared
    /// by `K` and `Kbar` in the local limit.
    fn thin_bracket(&self, p: &ThinProfile, x: f64, aa: f64) -> f64 {
        let h = self.theta.as_ref().map_or(0.0, |t| t.layer.thickness);
        let Some(pv) = step_value(x, 0.5 * aa, p.reach * h) else {
            return f64::NAN;
        };
        let mut s = self.glassy * pv;
        for &(c, l) in &self.terms {
            match Self::thin_memory(p, h, l, x, aa) {
                Some(m) => s += c * m,
                None => return f64::NAN,
            }
        }
        s
    }

    /// `K(d)` in the local limit (module docs): nonzero only on the row of
    /// the source along `e_v`; NaN off a grid-axis direction or where a
    /// point lies within the reach of an edge but off it.
    pub(crate) fn thin_coefficient(
        &self,
        p: &ThinProfile,
        cell: &Cell,
        dx: f64,
        dy: f64,
    ) -> Coefficient {
        if self.thin_law(p, cell.love.ax, cell.love.ay) {
            return self.law_coefficient(cell.love.ax, cell.love.ay, dx, dy);
        }
        let Some((x, c, aa, at)) = self.frame(dx, dy, cell.love.ax, cell.love.ay) else {
            return Coefficient::NAN;
        };
        let h = self.theta.as_ref().map_or(0.0, |t| t.layer.thickness);
        let across = match step_value(c, 0.5 * at, p.reach * h) {
            Some(v) if v != 0.5 => v,
            _ => return Coefficient::NAN,
        };
        if across == 0.0 {
            return Coefficient::default();
        }
        let scale = self.prefactor * p.m0 * h;
        let Some(pv) = step_value(x, 0.5 * aa, p.reach * h) else {
            return Coefficient::NAN;
        };
        let total = self.thin_bracket(p, x, aa);
        Coefficient {
            elastic: scale * self.glassy * pv,
            viscoelastic: scale * (total - self.glassy * pv),
        }
    }

    /// The cell-averaged derivative along `e_v`'s axis in the local limit:
    /// `Kbar` of the strip (`a_t m0 h - c2 h^2`) and of its two neighbours
    /// (`c2 h^2 / 2`); the transverse axis by [`super::thin_cross`].
    pub(crate) fn thin_derivative(
        &self,
        p: &ThinProfile,
        cell: &Cell,
        dx: f64,
        dy: f64,
        axis: Axis,
    ) -> f64 {
        let (ax, ay) = (cell.love.ax, cell.love.ay);
        if self.thin_law(p, ax, ay) {
            return self.law_derivative(ax, ay, dx, dy, axis);
        }
        let along_axis = match self.e {
            (x, _) if x.abs() == 1.0 => Axis::X,
            _ => Axis::Y,
        };
        if axis != along_axis {
            return self.thin_cross_derivative(p, cell, dx, dy, axis);
        }
        let (ex, ey, a) = match axis {
            Axis::X => (0.5 * ax, 0.0, ax),
            Axis::Y => (0.0, 0.5 * ay, ay),
        };
        let kbar = |px: f64, py: f64| -> f64 {
            let Some((x, c, aa, at)) = self.frame(px, py, ax, ay) else {
                return f64::NAN;
            };
            let h = self.theta.as_ref().map_or(0.0, |t| t.layer.thickness);
            let j = (c / at).round();
            if (c - j * at).abs() > 1e-9 * at {
                return f64::NAN;
            }
            let y = match j.abs() as u64 {
                0 => at * p.m0 * h - p.c2 * h * h,
                1 => 0.5 * p.c2 * h * h,
                _ => return 0.0,
            };
            self.prefactor * y / at * self.thin_bracket(p, x, aa)
        };
        (kbar(dx + ex, dy + ey) - kbar(dx - ex, dy - ey)) / a
    }
}

/// The thinnest layer accepted, in cells (`thickness / cell`): the local
/// limit is checked down to this ratio (tests/kernel/thin_layer.rs).
pub const THIN_RATIO_MIN: f64 = 1e-3;

impl SlidingKernel {
    /// Whether `ax x ay` cells are in the local limit of this kernel's
    /// layer, or take its thin-layer law's continuation above it
    /// (`kernel/thin_band.rs`): either way the layer is not resolved by
    /// the cells.
    pub fn is_thin(&self, ax: f64, ay: f64) -> bool {
        self.thin_profile(ax, ay).is_some() || self.is_band(ax, ay)
    }

    /// The checks of `ax x ay` cells \[m\] for coefficients asked for by
    /// themselves (`viscoslide kernel`, Python's `kernel_table`), as a
    /// solve on a pad checks them: positive, finite sides within the range
    /// the kernel's arithmetic holds (1.5e-154 m to 1.3e154 m: squares of
    /// lengths normal f64 numbers), and a layer the cells can discretise
    /// ([`Self::check_layer_cells`]). Returns the
    /// warning of a layer thinner than a cell
    /// ([`crate::response::Layer::resolution_warning`]).
    pub fn check_cells(&self, ax: f64, ay: f64) -> Result<Option<String>, KernelError> {
        crate::response::Grid::new(1, 1, (ax, ay))?;
        super::check_cell_range((ax, ay))?;
        self.check_layer_cells(ax, ay)?;
        Ok(self
            .theta
            .as_ref()
            .and_then(|t| t.layer.resolution_warning(ax.min(ay))))
    }

    /// Whether this kernel's layer can be discretised on `ax x ay` cells:
    /// at least [`THIN_RATIO_MIN`] of the longer side; in the local limit
    /// (reach below half the shorter side) a sliding direction along a grid
    /// axis (a layer whose local compliance is swamped by its edge term, a
    /// bonded incompressible one, takes the thin-layer law of
    /// `super::thin_law`).
    pub fn check_layer_cells(&self, ax: f64, ay: f64) -> Result<(), KernelError> {
        let Some(t) = &self.theta else { return Ok(()) };
        let h = t.layer.thickness;
        let a = ax.max(ay);
        if h < THIN_RATIO_MIN * a {
            return Err(KernelError::Invalid(format!(
                "[layer] thickness = {h:e} m is {:.3e} of a cell ({a:e} m), below the bound of {THIN_RATIO_MIN:e} of a cell; use cells of at most {:e} m or a thicker layer",
                h / a,
                h / THIN_RATIO_MIN
            )));
        }
        let Some(p) = self.thin_profile(ax, ay) else {
            return Ok(());
        };
        if self.frame(0.0, 0.0, ax, ay).is_none() {
            return Err(KernelError::Invalid(format!(
                "[layer] thickness = {h:e} m is {:.3e} of a cell, below {:.3e} (half a cell over the layer's reach of {:.1} thicknesses): the thin-layer kernel needs a sliding direction along a grid axis",
                h / a,
                0.5 / p.reach,
                p.reach
            )));
        }
        Ok(())
    }
}
