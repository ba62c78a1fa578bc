//! The self-consistent effective temperatures of a heated contact: every
//! root of `g(T) = T0 + Theta(T) - T` in a stated bracket (physics.md
//! section 14, "Feedback (closure)"), where `Theta(T)` is the
//! dissipation-weighted temperature rise of the contact solved
//! isothermally at `T`.
//!
//! `g(T0) = Theta(T0) >= 0`, so a root exists in `[T0, T0 + max_rise]`
//! whenever `Theta(T0 + max_rise) <= max_rise`. Friction that rises with
//! temperature (above the friction peak, where warming brings `a_T v` back
//! towards it) makes `g` fold: a cold and a hot branch, stable where
//! `g' < 0`, with an unstable root between them (the hysteresis of the hot
//! branch).
//!
//! Each evaluation of `Theta` is a whole contact solve, so the search is
//! frugal: `Theta(T0)` sets the scale of the rise, a geometric scan of
//! rises `Theta(T0) r^i` (ratio `r`, default 3) up to `max_rise` finds the
//! sign changes, and each is closed to `|g| <= tolerance` by the Illinois
//! variant of regula falsi, with quadratic (Muller) steps through the last
//! three evaluations where they fall inside the bracket: near a fold `g`
//! bends across the bracket and regula falsi alone converges from one
//! side. Roots closer together than one scan step, or a
//! tangent root (`g` touching zero without changing sign), can be missed;
//! the report says how the bracket was scanned.

use serde::Serialize;

/// How the bracket is searched.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct BranchSearch {
    /// Ambient temperature `T0` \[C\]: the bracket's lower end.
    pub t0: f64,
    /// The bracket's upper end is `T0 + max_rise` \[K\].
    pub max_rise: f64,
    /// Ratio of consecutive scanned rises (> 1).
    pub scan_ratio: f64,
    /// A root is accepted where `|g| <= tolerance` \[K\].
    pub tolerance: f64,
    /// At most this many evaluations of `Theta` in all.
    pub max_evaluations: usize,
}

/// `Theta` at one temperature.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Evaluation {
    /// Temperature of the isothermal solve \[C\].
    pub temperature: f64,
    /// Its dissipation-weighted temperature rise `Theta(T)` \[K\].
    pub rise: f64,
}

impl Evaluation {
    /// `g(T) = T0 + Theta(T) - T`.
    pub(super) fn residual(&self, t0: f64) -> f64 {
        t0 + self.rise - self.temperature
    }
}

/// One self-consistent effective temperature.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Branch {
    /// `T_eff` \[C\].
    pub temperature: f64,
    /// `T_eff - T0` \[K\].
    pub rise: f64,
    /// `g(T_eff)` \[K\], at most the tolerance.
    pub residual: f64,
    /// Whether `g` falls through zero here (`g' < 0`: a perturbed
    /// temperature returns to it); the unstable root between a cold and a
    /// hot branch has `g' > 0`.
    pub stable: bool,
}

/// Every root found and the evaluations spent.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub(crate) struct Branches {
    /// The roots, coldest first.
    pub branches: Vec<Branch>,
    /// Every evaluation, in the order made.
    pub evaluations: Vec<Evaluation>,
    /// The first this many of `evaluations` are the scan (`T0` first),
    /// the rest the closing of its sign changes.
    pub scanned: usize,
    /// The bracket searched \[C\].
    pub bracket: [f64; 2],
    /// How the bracket was searched, for the report.
    pub method: String,
}

/// Why the search gave no root.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum SearchFailure<E> {
    /// An evaluation failed.
    Evaluation(E),
    /// `g` stays positive up to the bracket's end: the rise exceeds
    /// `max_rise`.
    AboveBracket { rise_at_end: f64 },
    /// The evaluation budget ran out before a root was closed.
    Budget { evaluations: usize },
    /// The scan itself, from `start` \[K\] (`Theta(T0)`, or the tolerance
    /// where larger) by the scan ratio up to `max_rise`, would take more
    /// than the budget's `evaluations`: refused before it starts.
    ScanTooLong { start: f64, evaluations: usize },
}

impl BranchSearch {
    /// Check the controls; a one-line message naming the bad one.
    pub(crate) fn check(&self) -> Result<(), String> {
        if !self.t0.is_finite() {
            return Err(format!("ambient temperature {} C must be finite", self.t0));
        }
        if !(self.max_rise.is_finite() && self.max_rise > 0.0) {
            return Err(format!(
                "[heating] max_rise = {} K must be positive and finite",
                self.max_rise
            ));
        }
        if !(self.scan_ratio.is_finite() && self.scan_ratio > 1.0) {
            return Err(format!(
                "scan ratio {} must be finite and above 1",
                self.scan_ratio
            ));
        }
        if !(self.tolerance.is_finite() && self.tolerance > 0.0) {
            return Err(format!(
                "[heating] tolerance = {} K must be positive and finite",
                self.tolerance
            ));
        }
        if self.max_evaluations < 3 {
            return Err(format!(
                "at least 3 evaluations are needed, {} given",
                self.max_evaluations
            ));
        }
        Ok(())
    }

    /// Every root of `g(T) = T0 + theta(T) - T` in `[T0, T0 + max_rise]`
    /// (module docs). `theta(T)` is called with temperatures in the
    /// bracket, nearest ones in succession where the scan allows (a caller
    /// warm-starts each solve from the last).
    pub(crate) fn find<E>(
        &self,
        mut theta: impl FnMut(f64) -> Result<f64, E>,
    ) -> Result<Branches, SearchFailure<E>> {
        let t0 = self.t0;
        let end = t0 + self.max_rise;
        let mut evaluations: Vec<Evaluation> = Vec::new();
        let mut eval = |t: f64, evaluations: &mut Vec<Evaluation>| {
            if evaluations.len() >= self.max_evaluations {
                return Err(SearchFailure::Budget {
                    evaluations: evaluations.len(),
                });
            }
            let rise = theta(t).map_err(SearchFailure::Evaluation)?;
            let e = Evaluation {
                temperature: t,
                rise,
            };
            evaluations.push(e);
            Ok(e)
        };

        // The scan: T0, then rises Theta(T0) r^i up to max_rise (the
        // bracket's end always included).
        let first = eval(t0, &mut evaluations)?;
        let mut scan = vec![first];
        let start = first.rise.max(self.tolerance).min(self.max_rise);
        let rises = self.scan_rises(start);
        if 1 + rises.len() > self.max_evaluations {
            return Err(SearchFailure::ScanTooLong {
                start,
                evaluations: self.max_evaluations,
            });
        }
        for rise in rises {
            scan.push(eval(t0 + rise, &mut evaluations)?);
        }

        let mut branches = Vec::new();
        for pair in scan.windows(2) {
            let (a, b) = (pair[0], pair[1]);
            let (ga, gb) = (a.residual(t0), b.residual(t0));
            if ga.abs() <= self.tolerance
                && !branches
                    .iter()
                    .any(|r: &Branch| r.temperature == a.temperature)
            {
                branches.push(self.branch(a, gb - ga, b.temperature - a.temperature));
                continue;
            }
            if gb.abs() <= self.tolerance || ga.signum() == gb.signum() {
                continue;
            }
            let root = self.close_bracket(a, b, &mut |t| eval(t, &mut evaluations))?;
            branches.push(root);
        }
        if let Some(last) = scan.last() {
            let g = last.residual(t0);
            if g.abs() <= self.tolerance {
                let prev = scan[scan.len() - 2];
                branches.push(self.branch(
                    *last,
                    g - prev.residual(t0),
                    last.temperature - prev.temperature,
                ));
            }
        }
        if branches.is_empty() {
            let last = scan.last().copied().unwrap_or(first);
            return Err(SearchFailure::AboveBracket {
                rise_at_end: last.rise,
            });
        }
        branches.sort_by(|a, b| a.temperature.total_cmp(&b.temperature));
        // One root met at two neighbouring evaluations (`|g| <= tolerance`
        // at both, e.g. `T0` and `T0 + tolerance` without heating) is one
        // branch: the one nearer zero is kept.
        branches.dedup_by(|later, earlier| {
            let same = later.temperature - earlier.temperature <= 2.0 * self.tolerance;
            if same && later.residual.abs() < earlier.residual.abs() {
                std::mem::swap(later, earlier);
            }
            same
        });
        Ok(Branches {
            branches,
            evaluations,
            scanned: scan.len(),
            bracket: [t0, end],
            method: format!(
                "rises Theta(T0) x {}^i scanned up to {} K, sign changes closed by regula falsi (Illinois) with quadratic steps to |g| <= {} K",
                self.scan_ratio, self.max_rise, self.tolerance
            ),
        })
    }

    /// The scan's rises \[K\] above `T0`: from `start` by the scan ratio
    /// up to `max_rise` (the bracket's end always included), listed up to
    /// as many as the budget holds (with `T0`'s evaluation, one more than
    /// it: a scan that long is refused).
    fn scan_rises(&self, start: f64) -> Vec<f64> {
        let mut rises = vec![start];
        let mut rise = start;
        while rise < self.max_rise && rises.len() < self.max_evaluations {
            rise = (rise * self.scan_ratio).min(self.max_rise);
            rises.push(rise);
        }
        rises
    }

    /// A root at evaluation `e`, with `g`'s change `dg` over `dt` for its
    /// stability.
    pub(super) fn branch(&self, e: Evaluation, dg: f64, dt: f64) -> Branch {
        Branch {
            temperature: e.temperature,
            rise: e.temperature - self.t0,
            residual: e.residual(self.t0),
            stable: dg / dt < 0.0,
        }
    }

    /// The root between `a` and `b` (residuals of opposite signs): regula
    /// falsi with the Illinois halving of the retained end's residual,
    /// where a quadratic through the last three evaluations does not
    /// offer a better step ([`quadratic_root`]: taken where it lies inside
    /// the bracket, unless the last quadratic step did not halve `|g|`).
    pub(super) fn close_bracket<E>(
        &self,
        a: Evaluation,
        b: Evaluation,
        eval: &mut dyn FnMut(f64) -> Result<Evaluation, SearchFailure<E>>,
    ) -> Result<Branch, SearchFailure<E>> {
        let t0 = self.t0;
        let falling = b.residual(t0) < a.residual(t0);
        let (mut x0, mut g0) = (a.temperature, a.residual(t0));
        let (mut x1, mut g1) = (b.temperature, b.residual(t0));
        let mut side = 0i8;
        // The evaluations so far, newest last (true residuals).
        let mut last: Vec<(f64, f64)> = vec![(x0, g0), (x1, g1)];
        let mut halved = true;
        loop {
            let (lo, hi) = (x0.min(x1), x0.max(x1));
            let quadratic = match last.as_slice() {
                [.., p, q, r] if halved => {
                    quadratic_root(*p, *q, *r).filter(|x| *x > lo && *x < hi)
                }
                _ => None,
            };
            let x = quadratic.unwrap_or((x0 * g1 - x1 * g0) / (g1 - g0));
            let g_before = last[last.len() - 1].1.abs();
            let e = eval(x)?;
            let g = e.residual(t0);
            if g.abs() <= self.tolerance || (x1 - x0).abs() <= f64::EPSILON * x.abs().max(1.0) {
                return Ok(Branch {
                    temperature: e.temperature,
                    rise: e.temperature - t0,
                    residual: g,
                    stable: falling,
                });
            }
            halved = quadratic.is_none() || g.abs() <= 0.5 * g_before;
            last.push((x, g));
            if g.signum() == g1.signum() {
                (x1, g1) = (x, g);
                if side == -1 {
                    g0 /= 2.0;
                }
                side = -1;
            } else {
                (x0, g0) = (x, g);
                if side == 1 {
                    g1 /= 2.0;
                }
                side = 1;
            }
        }
    }
}

/// The root nearest `r` of the quadratic through the points `(x, g)` `p`,
/// `q` and `r` (Muller's step); `None` where the three do not fix a
/// quadratic with a real root.
fn quadratic_root(p: (f64, f64), q: (f64, f64), r: (f64, f64)) -> Option<f64> {
    let (d_qr, d_pq) = (r.0 - q.0, q.0 - p.0);
    let (s_qr, s_pq) = ((r.1 - q.1) / d_qr, (q.1 - p.1) / d_pq);
    let a = (s_qr - s_pq) / (r.0 - p.0);
    let b = s_qr + a * d_qr;
    let disc = b * b - 4.0 * a * r.1;
    if disc.is_nan() || disc < 0.0 {
        return None;
    }
    let sq = disc.sqrt();
    let den = if b >= 0.0 { b + sq } else { b - sq };
    let x = r.0 - 2.0 * r.1 / den;
    x.is_finite().then_some(x)
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;

    /// The search of these tests and the two-grid search's, from `t0`.
    pub(in crate::heating) fn search(t0: f64) -> BranchSearch {
        BranchSearch {
            t0,
            max_rise: 200.0,
            scan_ratio: 3.0,
            tolerance: 1e-9,
            max_evaluations: 200,
        }
    }

    #[test]
    fn one_root_of_a_falling_rise_is_the_fixed_point() {
        // Theta(T) = 5 exp(-(T - 20) / 30): g is decreasing, one stable
        // root, checked by substitution.
        let s = search(20.0);
        let r = s
            .find(|t| Ok::<_, ()>(5.0 * (-(t - 20.0) / 30.0).exp()))
            .unwrap();
        assert_eq!(r.branches.len(), 1, "{r:?}");
        let b = r.branches[0];
        let theta = 5.0 * (-(b.temperature - 20.0) / 30.0).exp();
        assert!((20.0 + theta - b.temperature).abs() <= 1e-9, "{b:?}");
        assert!(b.stable);
        assert!(
            r.evaluations.len() < 30,
            "{} evaluations",
            r.evaluations.len()
        );
    }

    #[test]
    fn an_s_curve_gives_cold_unstable_and_hot_roots() {
        // A constructed fold: Theta(T) = 2 + 80 / (1 + exp(-(T - 60) / 4))
        // with T0 = 20: g = 22 + 80 s - T has roots near 22, between, and
        // near 102. Each is checked by substitution; the stabilities
        // alternate.
        let theta = |t: f64| 2.0 + 80.0 / (1.0 + (-(t - 60.0) / 4.0).exp());
        let s = search(20.0);
        let r = s.find(|t| Ok::<_, ()>(theta(t))).unwrap();
        assert_eq!(r.branches.len(), 3, "{r:?}");
        for b in &r.branches {
            assert!(
                (20.0 + theta(b.temperature) - b.temperature).abs() <= 1e-9,
                "{b:?}"
            );
        }
        let stable: Vec<bool> = r.branches.iter().map(|b| b.stable).collect();
        assert_eq!(stable, [true, false, true]);
        assert!(
            r.branches[0].rise < 5.0 && r.branches[2].rise > 70.0,
            "{r:?}"
        );
    }

    #[test]
    fn the_quadratic_step_is_the_root_of_the_parabola_nearest_the_last_point() {
        // g = 0.3 (x - 2) (x + 5): roots 2 and -5.
        let g = |x: f64| 0.3 * (x - 2.0) * (x + 5.0);
        let p = |x: f64| (x, g(x));
        let r = quadratic_root(p(0.0), p(4.0), p(1.5)).unwrap();
        assert!((r - 2.0).abs() < 1e-12, "{r}");
        let r = quadratic_root(p(0.0), p(4.0), p(-4.0)).unwrap();
        assert!((r + 5.0).abs() < 1e-12, "{r}");
        // A straight line: the secant's root.
        let r = quadratic_root((0.0, 2.0), (1.0, 1.0), (3.0, -1.0)).unwrap();
        assert!((r - 2.0).abs() < 1e-12, "{r}");
        // No real root.
        assert!(quadratic_root((-1.0, 2.0), (0.0, 1.0), (1.0, 2.0)).is_none());
    }

    #[test]
    fn a_curved_g_closes_in_fewer_steps_than_regula_falsi() {
        // Near a fold (the shape of the paper experiment heated at 10
        // m/s): g = 17 + Theta - T falls through zero near 66.47 C with a
        // slope of about -0.3 and bends strongly across the bracket.
        let theta = |t: f64| -11.0 + 76.0 / (1.0 + (-(t - 42.0) / 18.0).exp());
        let s = BranchSearch {
            tolerance: 1e-3,
            ..search(17.0)
        };
        let at = |t: f64| Evaluation {
            temperature: t,
            rise: theta(t),
        };
        let (a, b) = (at(47.0), at(80.0));
        let mut made = 0;
        let root = s
            .close_bracket::<()>(a, b, &mut |t| {
                made += 1;
                Ok(at(t))
            })
            .unwrap();
        assert!(root.residual.abs() <= 1e-3 && root.stable, "{root:?}");
        assert!((17.0 + theta(root.temperature) - root.temperature).abs() <= 1e-3);
        // The same bracket by regula falsi with the Illinois halving
        // alone, written out here.
        let g = |t: f64| 17.0 + theta(t) - t;
        let (mut x0, mut g0, mut x1, mut g1) = (a.temperature, g(47.0), b.temperature, g(80.0));
        let (mut plain, mut side) = (0, 0i8);
        loop {
            let x = (x0 * g1 - x1 * g0) / (g1 - g0);
            let gx = g(x);
            plain += 1;
            if gx.abs() <= 1e-3 {
                break;
            }
            if gx.signum() == g1.signum() {
                (x1, g1) = (x, gx);
                if side == -1 {
                    g0 /= 2.0;
                }
                side = -1;
            } else {
                (x0, g0) = (x, gx);
                if side == 1 {
                    g1 /= 2.0;
                }
                side = 1;
            }
        }
        assert!(made < plain, "{made} steps against regula falsi's {plain}");
    }

    #[test]
    fn a_rise_beyond_the_bracket_is_reported_not_a_root() {
        let s = BranchSearch {
            max_rise: 10.0,
            ..search(0.0)
        };
        match s.find(|_| Ok::<_, ()>(50.0)) {
            Err(SearchFailure::AboveBracket { rise_at_end }) => assert_eq!(rise_at_end, 50.0),
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn no_heating_is_the_ambient_temperature() {
        let r = search(25.0).find(|_| Ok::<_, ()>(0.0)).unwrap();
        assert_eq!(r.branches.len(), 1);
        assert!((r.branches[0].temperature - 25.0).abs() <= 1e-9, "{r:?}");
        // A rise below the tolerance: T0 and T0 + tolerance both satisfy
        // |g| <= tolerance, one branch.
        let coarse = BranchSearch {
            tolerance: 1e-3,
            ..search(25.0)
        };
        let r = coarse.find(|_| Ok::<_, ()>(1e-8)).unwrap();
        assert_eq!(r.branches.len(), 1, "{r:?}");
        assert!(r.branches[0].residual.abs() <= 1e-3, "{r:?}");
    }

    #[test]
    fn the_budget_and_evaluation_errors_stop_the_search() {
        // Theta(T0) = 5 K scanned by 3 up to 200 K: T0, 5, 15, 45, 135 and
        // 200 K. Seven solves hold the scan, not the closing of its root;
        // three do not hold the scan, refused before it starts.
        let theta = |t: f64| Ok::<_, ()>(5.0 * (-t / 30.0).exp());
        let s = BranchSearch {
            max_evaluations: 7,
            ..search(0.0)
        };
        assert!(matches!(
            s.find(theta),
            Err(SearchFailure::Budget { evaluations: 7 })
        ));
        let s = BranchSearch {
            max_evaluations: 3,
            ..search(0.0)
        };
        let mut calls = 0;
        let e = s.find(|t| {
            calls += 1;
            theta(t)
        });
        assert!(
            matches!(
                e,
                Err(SearchFailure::ScanTooLong {
                    start: 5.0,
                    evaluations: 3
                })
            ),
            "{e:?}"
        );
        assert_eq!(calls, 1);
        // Six hold it exactly.
        let s = BranchSearch {
            max_evaluations: 6,
            ..search(0.0)
        };
        assert!(matches!(
            s.find(theta),
            Err(SearchFailure::Budget { evaluations: 6 })
        ));
        assert!(matches!(
            search(0.0).find(|_| Err::<f64, _>("solve failed")),
            Err(SearchFailure::Evaluation("solve failed"))
        ));
    }

    #[test]
    fn bad_controls_are_refused_in_one_line() {
        for s in [
            BranchSearch {
                max_rise: 0.0,
                ..search(0.0)
            },
            BranchSearch {
                scan_ratio: 1.0,
                ..search(0.0)
            },
            BranchSearch {
                tolerance: f64::NAN,
                ..search(0.0)
            },
            BranchSearch {
                t0: f64::INFINITY,
                ..search(0.0)
            },
        ] {
            let e = s.check().unwrap_err();
            assert!(!e.contains('\n'), "{e}");
        }
        search(0.0).check().unwrap();
    }
}
