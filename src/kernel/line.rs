//! The memory part of the steady-sliding Green's function (paper Eq. 4 and
//! Eq. 6; physics.md section 3) as ONE line integral along the sliding
//! direction:
//!
//! `sum_k C_k int_0^inf dz e^{-z} F(d + v tau_k z e_v) = int_0^inf ds phi(s) F(d + s e_v)`,
//! `phi(s) = sum_k (C_k / l_k) exp(-s / l_k)`, `l_k = v tau_k`.
//!
//! The integrand is evaluated once per node and shared by all terms, so the
//! cost grows only through the evaluation of `phi` (cheap), not through the
//! number of spatial evaluations. Extreme memory lengths are classified
//! first:
//! * `l_k < RELAXED * a_min` (or `v = 0`): the term acts as relaxed
//!   compliance, `C_k F(d)` (the neglected part is `~ l_k F'(d)`, a relative
//!   `1e-13`);
//! * `l_k = inf` (or `l_k > GLASSY * (|d| + a_max)`): the term acts as
//!   glassy: no memory contribution (what is dropped is at most
//!   `~ C_k (r/l_k) ln(l_k/r)`, below `1e-16` relative).
//!
//! The remaining terms are integrated by globally adaptive Gauss-Kronrod
//! with breakpoints at every crossing of a line on which the integrand has a
//! kink (source-cell edges), at the closest approach to the source, at the
//! memory lengths `l_k` and on a geometric grid (ratio 4) from below the
//! smallest scale to `46 l_max` (`e^{-46} ~ 1e-20`).

use super::quad::{adaptive, clean_breaks};

/// Memory lengths below `RELAXED * a_min` act as relaxed compliance.
pub const RELAXED: f64 = 1e-13;
/// Memory lengths above `GLASSY * (|d| + a_max)` act as glassy.
pub const GLASSY: f64 = 1e18;

/// A straight line on which the integrand may have a kink: `x = c` or `y = c`.
#[derive(Debug, Clone, Copy)]
pub enum KinkLine {
    X(f64),
    Y(f64),
}

/// Geometry of one line integral.
pub struct LineProblem<'a> {
    /// Start point `d` \[m\].
    pub d: (f64, f64),
    /// Unit sliding direction `e_v`.
    pub e: (f64, f64),
    /// Creep terms `(C_k [1/Pa], l_k = v tau_k \[m\])`.
    pub terms: &'a [(f64, f64)],
    /// Smallest and largest side of the source cell \[m\].
    pub a_min: f64,
    pub a_max: f64,
    pub kinks: &'a [KinkLine],
    /// Absolute tolerance of the adaptive integral (same units as the result).
    pub abs_tol: f64,
    /// Relative tolerance of the adaptive integral.
    pub rel_tol: f64,
}

/// Breakpoints of a memory integral along the trail: `l, 4l, 16l` for each
/// memory length `l`, and a geometric grid (ratio 4) from `smallest / 8` up
/// to `s_hi`.
pub(crate) fn memory_breaks(breaks: &mut Vec<f64>, lengths: &[f64], smallest: f64, s_hi: f64) {
    for &l in lengths {
        breaks.extend([l, 4.0 * l, 16.0 * l]);
    }
    let mut s = smallest / 8.0;
    while s < s_hi {
        breaks.push(s);
        s *= 4.0;
    }
}

/// `sum_k C_k int_0^inf dz e^{-z} F(d + l_k z e_v)` [F units / Pa].
pub fn memory_integral(p: &LineProblem, f: impl Fn(f64, f64) -> f64) -> f64 {
    let (dx, dy) = p.d;
    let (ex, ey) = p.e;
    let dist = dx.hypot(dy);
    let mut relaxed = 0.0;
    let mut active: Vec<(f64, f64)> = Vec::new();
    for &(c, l) in p.terms {
        if c == 0.0 {
            continue;
        }
        if l < RELAXED * p.a_min {
            relaxed += c;
        } else if l.is_finite() && l <= GLASSY * (dist + p.a_max) {
            active.push((c / l, 1.0 / l));
        }
    }
    let mut total = if relaxed != 0.0 {
        relaxed * f(dx, dy)
    } else {
        0.0
    };
    if active.is_empty() {
        return total;
    }
    let l_min = active
        .iter()
        .map(|t| 1.0 / t.1)
        .fold(f64::INFINITY, f64::min);
    let l_max = active.iter().map(|t| 1.0 / t.1).fold(0.0, f64::max);
    let s_hi = 46.0 * l_max;
    let mut breaks = Vec::new();
    for k in p.kinks {
        match *k {
            KinkLine::X(c) if ex != 0.0 => breaks.push((c - dx) / ex),
            KinkLine::Y(c) if ey != 0.0 => breaks.push((c - dy) / ey),
            _ => {}
        }
    }
    breaks.push(-(dx * ex + dy * ey));
    let lengths: Vec<f64> = active.iter().map(|t| 1.0 / t.1).collect();
    memory_breaks(&mut breaks, &lengths, l_min.min(p.a_min), s_hi);
    let breaks = clean_breaks(breaks, 0.0, s_hi);
    let phi = |s: f64| -> f64 { active.iter().map(|&(w, il)| w * (-s * il).exp()).sum() };
    total += adaptive(
        |s| {
            let w = phi(s);
            if w == 0.0 {
                0.0
            } else {
                w * f(dx + s * ex, dy + s * ey)
            }
        },
        &breaks,
        p.abs_tol,
        p.rel_tol,
        6000,
    );
    total
}
