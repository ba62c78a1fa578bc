//! Whether an inner solve of the active-set iteration is preconditioned.
//!
//! The backend's approximate inverse (a circulant's) is excellent on most
//! contact sets but may be poor on some: on a layer much thinner than a
//! cell it barely helps at all, and on the periodic viscoelastic operator
//! far from symmetric (`E_inf / E0 ~ 80`) it reduced a solve on 79 % of the
//! grid only to 0.15 in 300 steps, while the same operator on the nearly
//! full set that follows takes 5-15 preconditioned steps against 1,500
//! plain ones (BENCHMARKS.md, "Stalled solves and sub-cell layers"). So
//! the choice is measured, not fixed: each solve's cost, matvecs per decade
//! of residual reduction, is recorded for its mode; a solve that misses its
//! target within its budget, or costs more than the other mode's last
//! measurement, hands the next solve to the other mode.

/// Cost measurements of the two modes and the current choice.
#[derive(Debug, Clone)]
pub(crate) struct InnerMode {
    /// Whether preconditioning is available (asked for, and the backend
    /// has a preconditioner).
    available: bool,
    precondition: bool,
    /// Matvecs per decade of the last preconditioned and plain solves.
    cost: [Option<f64>; 2],
}

impl InnerMode {
    /// Preconditioned first where `available`.
    pub(crate) fn new(available: bool) -> Self {
        Self {
            available,
            precondition: available,
            cost: [None, None],
        }
    }

    /// Whether the next solve is preconditioned.
    pub(crate) fn precondition(&self) -> bool {
        self.precondition
    }

    /// Record a solve in the current mode that took `matvecs` products
    /// and reduced its residual by `reduction`, `reached` telling whether
    /// it met its target; choose the next mode.
    pub(crate) fn record(&mut self, matvecs: usize, reduction: f64, reached: bool) {
        let this = usize::from(!self.precondition);
        // A solve that ended at its first residual (already within its
        // tolerance) measures nothing.
        if matvecs > 1 && reduction.is_finite() {
            let decades = (-reduction.log10()).max(1e-3);
            self.cost[this] = Some(matvecs as f64 / decades);
        }
        let other = 1 - this;
        let dearer = matches!((self.cost[this], self.cost[other]), (Some(a), Some(b)) if a > b);
        if self.available && (!reached || dearer) {
            self.precondition = !self.precondition;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_failing_preconditioner_is_dropped_and_retried_when_plain_solves_cost_more() {
        let mut m = InnerMode::new(true);
        assert!(m.precondition());
        // Preconditioned: 300 matvecs for a reduction of 0.15 (360 per
        // decade), target missed: plain next.
        m.record(300, 0.15, false);
        assert!(!m.precondition());
        // Plain, 100 matvecs for two decades: cheaper, stays plain.
        m.record(100, 1e-2, true);
        assert!(!m.precondition());
        // Plain, 1500 matvecs for three decades: dearer than 360, back.
        m.record(1500, 1e-3, true);
        assert!(m.precondition());
        // Preconditioned, 10 for three decades: stays.
        m.record(10, 1e-3, true);
        assert!(m.precondition());
        // A solve that was already converged measures nothing.
        m.record(1, 1.0, true);
        assert!(m.precondition());
    }

    #[test]
    fn without_a_preconditioner_every_solve_is_plain() {
        let mut m = InnerMode::new(false);
        assert!(!m.precondition());
        m.record(500, 0.5, false);
        assert!(!m.precondition());
    }

    #[test]
    fn a_preconditioner_that_never_fails_is_kept() {
        let mut m = InnerMode::new(true);
        for _ in 0..5 {
            m.record(40, 1e-2, true);
            assert!(m.precondition());
        }
    }
}
