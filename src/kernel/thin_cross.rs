//! The friction stencil's derivative across the sliding direction for a
//! layer much thinner than a cell (physics.md sections 3 and 5; the local
//! limit of [`super::thin`]).
//!
//! Sliding along a grid axis, `D_c(d) = (1/a_c) [Kbar(c + a_c/2) - Kbar(c - a_c/2)]`
//! with `c` the offset across `e_v` and `Kbar` the average of `K` over the
//! target's width `a` along `e_v`. The points `c +- a_c/2` of a table lie on
//! a source edge (step value 1/2) or beyond the reach `R h`, so only the
//! along profile matters, and there it is exact: the width average and the
//! source's extent along `e_v` correlate into the triangle
//! `tri(Y) = (a - |Y|)_+` of the along offset `Y`, seen through the line
//! projection `f = F'` of the layer's Green's function (normalised to one),
//!
//! `Kbar = prefactor m0 h P_c / a [glassy B_0(Y) + sum_k C_k B_k(Y)]`,
//! `B_k(Y) = int f(t) T_k(Y - t h) dt`, `T_k(Y) = int_0^inf phi_k(s) tri(Y + s) ds`,
//!
//! `phi_k(s) = e^{-s/l_k} / l_k` (`T_0 = tri`). `T_k` is closed form (the
//! ramps `(z)_+` of `tri = (Y + a)_+ - 2 (Y)_+ + (Y - a)_+` smoothed by the
//! exponential), and by parts with `1 - F` (even `f`)
//!
//! `B_k(Y) = T_k(Y) + h int_0^R (1 - F(t)) [T_k'(Y + t h) - T_k'(Y - t h)] dt`,
//!
//! whose integrand is smooth for `t > 0` when `Y` lies on a kink of `tri`
//! (`0, +-a`) or farther than `R h` from all of them (every table offset):
//! the edge profile's graded nodes integrate it; `[0, t_min]`, where
//! `1 - F = 1/2`, in closed form. At rest this gives the strip values of
//! [`super::thin`]: `B_0(0) = a - c2 h / m0`, `B_0(+-a) = c2 h / (2 m0)`.

use super::thin::{step_value, ThinProfile};
use super::{Axis, Cell, SlidingKernel};

/// `int_0^inf phi(s) (z + s)_+ ds - l` for a memory length `l` (`(z)_+`
/// at `l = 0`); the `- l` cancels in `tri`'s weights `1, -2, 1` and keeps
/// long memories free of cancellation.
fn ramp(z: f64, l: f64) -> f64 {
    if z >= 0.0 {
        z
    } else if l == 0.0 {
        0.0
    } else {
        l * (z / l).exp_m1()
    }
}

/// The derivative of [`ramp`] in `z`.
fn ramp_slope(z: f64, l: f64) -> f64 {
    if z >= 0.0 {
        1.0
    } else if l == 0.0 {
        0.0
    } else {
        (z / l).exp()
    }
}

/// `B(Y)` of the module docs for memory length `l` (`0`: no memory), given
/// the offsets `z = [Y + a, Y, Y - a]` of `Y` from the kinks of `tri`.
fn smoothed_triangle(p: &ThinProfile, h: f64, l: f64, z: &[f64; 3]) -> f64 {
    const W: [f64; 3] = [1.0, -2.0, 1.0];
    let t_of = |d: f64| -> f64 { z.iter().zip(W).map(|(z, w)| w * ramp(z + d, l)).sum() };
    let slope = |d: f64| -> f64 { z.iter().zip(W).map(|(z, w)| w * ramp_slope(z + d, l)).sum() };
    let e = p.t_min * h;
    let sliver = 0.5 * (t_of(e) + t_of(-e) - 2.0 * t_of(0.0));
    t_of(0.0) + sliver + h * p.profile_sum(|t| slope(t * h) - slope(-t * h))
}

impl SlidingKernel {
    /// `glassy B_0(Y) + sum_k C_k B_k(Y)` at the along offset `x` for cells
    /// `aa` long along `e_v`; `None` where `x` lies within the reach of a
    /// kink of `tri` but off it.
    fn cross_bracket(&self, p: &ThinProfile, h: f64, x: f64, aa: f64) -> Option<f64> {
        let reach = p.reach * h;
        let mut z = [x + aa, x, x - aa];
        for zi in &mut z {
            if zi.abs() <= 1e-9 * aa {
                *zi = 0.0;
            } else if zi.abs() < reach {
                return None;
            }
        }
        let mut s = self.glassy * smoothed_triangle(p, h, 0.0, &z);
        for &(c, l) in &self.terms {
            if c != 0.0 && l.is_finite() {
                s += c * smoothed_triangle(p, h, l, &z);
            }
        }
        Some(s)
    }

    /// `D` along `axis`, transverse to `e_v` (which lies along the other
    /// grid axis), in the local limit (module docs); NaN where a point of
    /// the stencil lies within the reach of an edge but off it.
    pub(crate) fn thin_cross_derivative(
        &self,
        p: &ThinProfile,
        cell: &Cell,
        dx: f64,
        dy: f64,
        axis: Axis,
    ) -> f64 {
        let (ax, ay) = (cell.love.ax, cell.love.ay);
        let Some((x, c, aa, at)) = self.frame(dx, dy, ax, ay) else {
            return f64::NAN;
        };
        // `frame` puts the other axis across: `axis` must be that one.
        let across_is_x = self.e.1 != 0.0;
        if across_is_x != (axis == Axis::X) {
            return f64::NAN;
        }
        let h = self.theta.as_ref().map_or(0.0, |t| t.layer.thickness);
        let reach = p.reach * h;
        let kbar = |cc: f64| -> Option<f64> {
            let v = step_value(cc, 0.5 * at, reach)?;
            if v == 0.0 {
                return Some(0.0);
            }
            let b = self.cross_bracket(p, h, x, aa)?;
            Some(self.prefactor * p.m0 * h * v * b / aa)
        };
        match (kbar(c + 0.5 * at), kbar(c - 0.5 * at)) {
            (Some(hi), Some(lo)) => (hi - lo) / at,
            _ => f64::NAN,
        }
    }
}
