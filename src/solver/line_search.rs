//! Globalisation of the active-set iteration: a backtracking line search on
//! the complementarity merit along the semismooth Newton step.
//!
//! The active-set iteration is Newton's method for `F(p) = min(p, k gap(p))
//! = 0` (`k = 1 / L_00`): at a point `p`, the cells with `p > k gap` get the
//! row `gap = 0`, the others `p = 0`, and with the load row this is the
//! contact-set system the inner solve answers (Hintermueller, Ito & Kunisch,
//! SIAM J. Optim. 13, 865, 2003). Undamped, it converges for M-matrices; on
//! an operator far from symmetric (the periodic viscoelastic one near full
//! contact with `E_inf / E0 ~ 80`, where a mode's compliance has a phase of
//! up to 77 degrees) the full step overshoots: hundreds of cells enter and
//! leave every iteration and the residual cycles at 0.2-0.4 (BENCHMARKS.md,
//! "Stalled solves and sub-cell layers").
//!
//! The remedy is the classical damped Newton method: where the full step
//! does not lower the merit `theta = |min(p, k gap)|^2` by the Armijo
//! condition `theta(t) <= (1 - 2 sigma t) theta(0)` (the directional
//! derivative of `theta` along the Newton step is `-2 theta(0)`), the step
//! is halved. Along the step `p(t) = p0 + t (p1 - p0)` the gap is linear in
//! `t` too (`u = L p`, `delta` likewise), so each trial costs vector
//! operations only, no product with the operator. The next contact set is
//! then the Newton rule's `{p > k gap}` at the damped point (at an undamped
//! point, where `gap = 0` on the set and `p = 0` off it up to the inner
//! tolerance, it is the usual rule: cells with `p <= 0` leave, cells with
//! `gap < 0` enter). Steps from an iterate whose relative residual is
//! already below 1e-3 are taken in full (`DAMP_ABOVE`).

use crate::backend::Backend;

/// Armijo constant `sigma`.
const ARMIJO: f64 = 1e-4;
/// Smallest step tried; if none down to it satisfies the Armijo condition,
/// the trial with the smallest merit is taken.
const SMALLEST_STEP: f64 = 1.0 / 64.0;
/// Steps from an iterate whose relative residual `|min(p, k gap)| / |p|`
/// is at or below this are taken in full: near the solution the Newton
/// method converges fast undamped, and at the arithmetic's floor a rising
/// residual is rounding, which the floor rules of the iteration judge
/// (the threshold of its stall rule, `STALL_ABOVE`).
const DAMP_ABOVE: f64 = super::STALL_ABOVE;

/// The previous iterate of the active-set iteration: pressure, its gap
/// `g - delta + L p`, the approach and the merit `|min(p, k gap)|^2`.
pub(crate) struct Previous<V> {
    p: V,
    gap: V,
    delta: f64,
    merit: f64,
    /// Its relative residual `|min(p, k gap)| / |p|`.
    residual: f64,
    /// Whether `p`, `u` hold an iterate (not before the first step).
    valid: bool,
}

/// A step accepted by [`Previous::damp`].
#[derive(Debug, Clone, Copy)]
pub(crate) struct Step {
    /// Step length (1: the full Newton step).
    pub(crate) t: f64,
    /// `(|min(p, k gap)|^2, |p|^2)` at the accepted point.
    pub(crate) merit: (f64, f64),
}

impl<V> Previous<V> {
    /// No previous iterate yet (grid vectors of `n` cells).
    pub(crate) fn new<B: Backend<Vector = V>>(backend: &mut B, n: usize) -> Self {
        Self {
            p: backend.zeros(n),
            gap: backend.zeros(n),
            delta: 0.0,
            merit: f64::INFINITY,
            residual: f64::INFINITY,
            valid: false,
        }
    }

    /// Damp the Newton step from the previous iterate to `(p, gap, delta)`
    /// whose merit is `merit` (as [`Backend::complementarity`] returns it):
    /// on return `p`, `gap` and `delta` hold the accepted point, which
    /// becomes the previous iterate. The trials move `p` and `gap` along the
    /// step in place (`x(t') = x0 + (t' / t) (x(t) - x0)`), so the search
    /// holds no vector of its own beyond the previous iterate.
    pub(crate) fn damp<B: Backend<Vector = V>>(
        &mut self,
        backend: &mut B,
        stiffness: f64,
        p: &mut V,
        gap: &mut V,
        delta: &mut f64,
        merit: (f64, f64),
    ) -> Step {
        let mut step = Step { t: 1.0, merit };
        let rises = merit.0 > (1.0 - 2.0 * ARMIJO) * self.merit;
        if self.valid && self.residual > DAMP_ABOVE && rises {
            let full = *delta;
            let mut best = (merit.0, 1.0);
            let mut at = 1.0;
            let mut t = 0.5;
            while t >= SMALLEST_STEP {
                self.move_to(backend, t / at, p, gap);
                at = t;
                let (r2, _) = backend.complementarity(p, gap, stiffness);
                if r2 < best.0 {
                    best = (r2, t);
                }
                if r2 <= (1.0 - 2.0 * ARMIJO * t) * self.merit {
                    break;
                }
                t *= 0.5;
            }
            let t = best.1;
            if t != at {
                self.move_to(backend, t / at, p, gap);
            }
            if t < 1.0 {
                *delta = self.delta + t * (full - self.delta);
            }
            step = Step {
                t,
                merit: backend.complementarity(p, gap, stiffness),
            };
        }
        backend.copy(p, &mut self.p);
        backend.copy(gap, &mut self.gap);
        self.delta = *delta;
        self.merit = step.merit.0;
        self.residual = if step.merit.1 > 0.0 {
            (step.merit.0 / step.merit.1).sqrt()
        } else {
            f64::INFINITY
        };
        self.valid = true;
        step
    }

    /// `x = x0 + s (x - x0)` for `x = p, gap` (`x0` the previous iterate):
    /// a point at `t` on the step moves to `s t`.
    fn move_to<B: Backend<Vector = V>>(&self, backend: &mut B, s: f64, p: &mut V, gap: &mut V) {
        for (x, x0) in [(p, &self.p), (gap, &self.gap)] {
            backend.scale(s, x);
            backend.axpy(1.0 - s, x0, x);
        }
    }
}

/// The next contact set from the point `(p, gap)` reached by a step of
/// length `t`: the usual update for a full step, the Newton rule
/// `{p > k gap}` for a damped one (module docs). Returns the number of
/// cells that changed and the new set's size, as
/// [`Backend::update_active_set`].
pub(crate) fn update_set<B: Backend>(
    backend: &mut B,
    t: f64,
    p: &B::Vector,
    gap: &B::Vector,
    stiffness: f64,
    mask: &mut B::Mask,
) -> (usize, usize) {
    if t >= 1.0 {
        backend.update_active_set(p, gap, mask)
    } else {
        backend.newton_set(p, gap, stiffness, mask)
    }
}
