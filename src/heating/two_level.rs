//! The roots of `g(T) = T0 + Theta(T) - T` (physics.md section 14,
//! "Feedback (closure)") searched on two grids: the bracket scanned on a
//! coarse grid, each root closed on the full grid.
//!
//! The full-grid scan ([`BranchSearch::find`]) spends most of its
//! isothermal solves on the scan: rises `Theta(T0) r^i` up to `max_rise`,
//! 8-13 solves where one or three roots lie. Here:
//!
//! 1. `Theta(T0)` on the full grid (the report's isothermal friction).
//! 2. The same scan and closing on the coarse grid, its `Theta`
//!    calibrated to the full grid's at `T0` (`Theta_c(T) Theta(T0) /
//!    Theta_c(T0)`), so that the scanned temperatures are the ones the
//!    full-grid scan would take.
//! 3. Each coarse root closed on the full grid inside its window (from the
//!    midpoint to the neighbouring roots, or the bracket's end): an
//!    evaluation at the coarse root, then secant steps (the coarse `g`'s
//!    slope for the first) until `|g| <= tolerance`, or the bracket's
//!    closing of `branches.rs` once two full-grid evaluations in the
//!    window bracket the root with the coarse root's orientation. Usually
//!    one or two solves a root.
//! 4. The honesty rule. The full and coarse `Theta` differ by the
//!    relative discrepancy `delta = max |Theta / Theta_c - 1|`, measured
//!    at every temperature solved on both grids besides `T0` (the roots;
//!    if none, the scan's first rise above `T0` is solved on the full grid
//!    for it). A scan temperature decides the number of roots when its
//!    neighbours' `g` have the same sign (or it is the bracket's end): a
//!    change of its own sign adds or removes roots. Every such temperature
//!    with `|g_c| <= DISCREPANCY_MARGIN delta Theta_c + tolerance` is
//!    solved on the full grid too. The coarse search is accepted when all
//!    of these have the coarse sign, every sign change among the full-grid
//!    evaluations holds a found root, and each root closed in its window;
//!    otherwise the full-grid scan runs (re-using the full-grid solves
//!    made), and the report says why. A discrepancy that grows away from
//!    the roots by more than `DISCREPANCY_MARGIN` times is not detected:
//!    the report states `delta`, and a warning is given above
//!    [`DISCREPANCY_WARNING`].

use super::branches::{Branch, BranchSearch, Branches, Evaluation, SearchFailure};

/// A deciding scan temperature is solved on the full grid when a
/// discrepancy this many times the measured one could flip its sign.
pub(crate) const DISCREPANCY_MARGIN: f64 = 3.0;

/// Relative discrepancy between the coarse and full-grid `Theta` at the
/// roots above which the report warns that the coarse scan may misplace or
/// miss a branch away from them.
pub(crate) const DISCREPANCY_WARNING: f64 = 0.1;

/// Full-grid evaluations per root at most before the full-grid scan takes
/// over.
const CLOSE_STEPS: usize = 8;

/// The grid an evaluation is solved on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Level {
    Coarse,
    Full,
}

/// The roots, as [`BranchSearch::find`] gives them on the full grid, and
/// how they were found.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct TwoLevel {
    /// The full-grid roots; `evaluations` holds the full-grid evaluations
    /// only.
    pub found: Branches,
    /// The coarse grid's `Theta` (uncalibrated), in the order solved.
    pub coarse: Vec<Evaluation>,
    /// The calibration factor `Theta(T0) / Theta_c(T0)`.
    pub scale: f64,
    /// `delta`, the largest relative discrepancy measured (module docs).
    pub discrepancy: f64,
    /// Why the full-grid scan ran, if it did.
    pub fallback: Option<String>,
}

/// The full-grid evaluations, each temperature solved once.
struct Full<'a, E> {
    theta: &'a mut dyn FnMut(Level, f64) -> Result<f64, E>,
    done: Vec<Evaluation>,
    budget: usize,
}

impl<E> Full<'_, E> {
    fn eval(&mut self, t: f64) -> Result<Evaluation, SearchFailure<E>> {
        if let Some(e) = self.done.iter().find(|e| e.temperature == t) {
            return Ok(*e);
        }
        if self.done.len() >= self.budget {
            return Err(SearchFailure::Budget {
                evaluations: self.done.len(),
            });
        }
        let rise = (self.theta)(Level::Full, t).map_err(SearchFailure::Evaluation)?;
        let e = Evaluation {
            temperature: t,
            rise,
        };
        self.done.push(e);
        Ok(e)
    }

    /// The full-grid evaluations in `[lo, hi]`, coldest first.
    fn within(&self, lo: f64, hi: f64) -> Vec<Evaluation> {
        let mut v: Vec<Evaluation> = self
            .done
            .iter()
            .filter(|e| e.temperature >= lo && e.temperature <= hi)
            .copied()
            .collect();
        v.sort_by(|a, b| a.temperature.total_cmp(&b.temperature));
        v
    }
}

/// What closing one coarse root gave.
enum Closed {
    Root(Branch),
    Fallback(String),
}

impl BranchSearch {
    /// Every root of `g` in `[T0, T0 + max_rise]`, `theta(level, T)`
    /// solving `Theta(T)` on the coarse or the full grid (module docs).
    /// Errors are those of [`BranchSearch::find`] on the full grid; a
    /// coarse search that fails falls back to the full-grid scan.
    pub(crate) fn find_two_level<E: std::fmt::Display>(
        &self,
        theta: &mut dyn FnMut(Level, f64) -> Result<f64, E>,
    ) -> Result<TwoLevel, SearchFailure<E>> {
        let t0 = self.t0;
        let mut full = Full {
            theta,
            done: Vec::new(),
            budget: self.max_evaluations,
        };
        let first = full.eval(t0)?;

        // 2. The coarse search, calibrated at T0.
        let mut coarse: Vec<Evaluation> = Vec::new();
        let mut scale = 1.0;
        let coarse_found = {
            let theta = &mut *full.theta;
            self.find(|t| {
                let rise = theta(Level::Coarse, t)?;
                if coarse.is_empty() && rise > 0.0 && first.rise > 0.0 {
                    scale = first.rise / rise;
                }
                coarse.push(Evaluation {
                    temperature: t,
                    rise,
                });
                Ok::<f64, E>(scale * rise)
            })
        };
        let mut out = TwoLevel {
            found: Branches {
                branches: Vec::new(),
                evaluations: Vec::new(),
                scanned: 0,
                bracket: [t0, t0 + self.max_rise],
                method: String::new(),
            },
            coarse,
            scale,
            discrepancy: 0.0,
            fallback: None,
        };
        let reason = match coarse_found {
            Ok(c) => match self.close_all(&c, &mut full, scale, &out.coarse)? {
                Ok((branches, discrepancy)) => {
                    out.discrepancy = discrepancy;
                    out.found.branches = branches;
                    out.found.scanned = c.scanned;
                    out.found.method = format!(
                        "rises Theta(T0) x {}^i scanned up to {} K on the coarse grid (its Theta x {scale:.6} to meet the full grid's at T0) and closed there by regula falsi (Illinois) with quadratic steps; each of its {} roots closed on the full grid by secant, regula falsi and quadratic steps to |g| <= {} K; the grids' Theta differ by {discrepancy:.3e} (relative) where both were solved, and every scanned temperature whose sign decides the number of roots has |g| above {DISCREPANCY_MARGIN} times that or was solved on the full grid",
                        self.scan_ratio,
                        self.max_rise,
                        out.found.branches.len(),
                        self.tolerance
                    );
                    None
                }
                Err(why) => Some(why),
            },
            Err(SearchFailure::Evaluation(e)) => Some(format!("the coarse solve failed ({e})")),
            Err(SearchFailure::AboveBracket { rise_at_end }) => Some(format!(
                "the coarse grid's rise at the bracket's end is {:.4e} K, above max_rise",
                scale * rise_at_end
            )),
            Err(SearchFailure::Budget { evaluations }) => Some(format!(
                "the coarse search closed no root within {evaluations} solves"
            )),
            Err(SearchFailure::ScanTooLong { evaluations, .. }) => Some(format!(
                "the coarse scan would take more than {evaluations} solves"
            )),
        };
        if let Some(why) = reason {
            // The full-grid scan, re-using the full-grid solves made.
            let f = self
                .find(|t| full.eval(t).map(|e| e.rise))
                .map_err(flatten)?;
            out.found = Branches {
                method: format!("{} (on the full grid: {why})", f.method),
                ..f
            };
            out.fallback = Some(why);
        }
        out.found.evaluations = full.done;
        Ok(out)
    }

    /// Steps 3 and 4 of the module docs on the coarse search `c`:
    /// `Ok(Ok((roots, delta)))`, or `Ok(Err(why))` where the full-grid
    /// scan must take over.
    #[allow(clippy::type_complexity)]
    fn close_all<E>(
        &self,
        c: &Branches,
        full: &mut Full<'_, E>,
        scale: f64,
        coarse: &[Evaluation],
    ) -> Result<Result<(Vec<Branch>, f64), String>, SearchFailure<E>> {
        let t0 = self.t0;
        let end = t0 + self.max_rise;
        // The calibrated coarse evaluations.
        let calibrated: Vec<Evaluation> = coarse
            .iter()
            .map(|e| Evaluation {
                temperature: e.temperature,
                rise: scale * e.rise,
            })
            .collect();
        let roots = &c.branches;
        let mut branches = Vec::with_capacity(roots.len());
        for (i, root) in roots.iter().enumerate() {
            let lo = if i == 0 {
                t0
            } else {
                0.5 * (roots[i - 1].temperature + root.temperature)
            };
            let hi = match roots.get(i + 1) {
                Some(next) => 0.5 * (root.temperature + next.temperature),
                None => end,
            };
            match self.close(root, (lo, hi), full, &calibrated)? {
                Closed::Root(b) => branches.push(b),
                Closed::Fallback(why) => return Ok(Err(why)),
            }
        }
        for w in branches.windows(2) {
            if w[1].temperature - w[0].temperature <= 2.0 * self.tolerance {
                return Ok(Err(format!(
                    "two coarse roots closed on one full-grid root at {} C",
                    w[0].temperature
                )));
            }
        }

        // 4. The discrepancy and the deciding scan temperatures.
        let scan = &calibrated[..c.scanned];
        let discrepancy = |full: &Full<'_, E>| {
            full.done
                .iter()
                .filter(|f| f.temperature != t0)
                .filter_map(|f| {
                    calibrated
                        .iter()
                        .find(|e| e.temperature == f.temperature)
                        .map(|e| relative(f.rise, e.rise))
                })
                .fold(None, |m: Option<f64>, d| Some(m.map_or(d, |m| m.max(d))))
        };
        if discrepancy(full).is_none() {
            if let Some(e) = scan.get(1) {
                full.eval(e.temperature)?;
            }
        }
        let g = |e: &Evaluation| e.residual(t0);
        loop {
            let delta = discrepancy(full).unwrap_or(0.0);
            let mut checked_all = true;
            for i in 1..scan.len() {
                let deciding = match (scan.get(i - 1), scan.get(i + 1)) {
                    (Some(a), Some(b)) => (g(a) > 0.0) == (g(b) > 0.0),
                    _ => true,
                };
                let e = scan[i];
                let near =
                    g(&e).abs() <= DISCREPANCY_MARGIN * delta * e.rise.abs() + self.tolerance;
                if !(deciding && near) {
                    continue;
                }
                let f = full.eval(e.temperature)?;
                if f.residual(t0).abs() > self.tolerance && (g(&f) > 0.0) != (g(&e) > 0.0) {
                    return Ok(Err(format!(
                        "g changes sign at {} C between the grids ({:.4e} K coarse, {:.4e} K full), which changes the number of roots",
                        e.temperature,
                        g(&e),
                        g(&f)
                    )));
                }
                if discrepancy(full).unwrap_or(0.0) > delta {
                    checked_all = false;
                    break;
                }
            }
            if checked_all {
                break;
            }
        }
        // Every sign change among the full-grid evaluations holds a root.
        let done = full.within(t0, end);
        for w in done.windows(2) {
            let (a, b) = (w[0], w[1]);
            let (ga, gb) = (g(&a), g(&b));
            if ga.abs() <= self.tolerance || gb.abs() <= self.tolerance || (ga > 0.0) == (gb > 0.0)
            {
                continue;
            }
            if !branches
                .iter()
                .any(|r| r.temperature >= a.temperature && r.temperature <= b.temperature)
            {
                return Ok(Err(format!(
                    "the full grid's g changes sign between {} and {} C, where the coarse grid has no root",
                    a.temperature, b.temperature
                )));
            }
        }
        Ok(Ok((branches, discrepancy(full).unwrap_or(0.0))))
    }

    /// The full-grid root near the coarse `root`, inside `(lo, hi)`
    /// (module docs, step 3).
    fn close<E>(
        &self,
        root: &Branch,
        (lo, hi): (f64, f64),
        full: &mut Full<'_, E>,
        calibrated: &[Evaluation],
    ) -> Result<Closed, SearchFailure<E>> {
        let t0 = self.t0;
        let tol = self.tolerance;
        // The sign of g just below the root.
        let below = if root.stable { 1.0 } else { -1.0 };
        // A full-grid evaluation of the window already on a root.
        if let Some(e) = full
            .within(lo, hi)
            .into_iter()
            .filter(|e| e.residual(t0).abs() <= tol)
            .min_by(|a, b| {
                (a.temperature - root.temperature)
                    .abs()
                    .total_cmp(&(b.temperature - root.temperature).abs())
            })
        {
            return Ok(Closed::Root(self.oriented(e, root.stable)));
        }
        let slope_c = coarse_slope(calibrated, root.temperature, t0);
        if slope_c * below >= 0.0 || !slope_c.is_finite() {
            return Ok(Closed::Fallback(format!(
                "the coarse g has no usable slope at its root {} C",
                root.temperature
            )));
        }
        let mut x = root.temperature;
        for _ in 0..CLOSE_STEPS {
            let e = full.eval(x)?;
            let ge = e.residual(t0);
            if ge.abs() <= tol {
                return Ok(Closed::Root(self.oriented(e, root.stable)));
            }
            let window = full.within(lo, hi);
            let at = window
                .iter()
                .position(|w| w.temperature == e.temperature)
                .expect("the evaluation lies in its window");
            // The root lies above e where g has the sign it has below the
            // root.
            let up = ge * below > 0.0;
            let neighbour = if up {
                window.get(at + 1)
            } else {
                at.checked_sub(1).map(|k| &window[k])
            };
            if let Some(&n) = neighbour {
                if n.residual(t0) * ge < 0.0 {
                    let (a, b) = if up { (e, n) } else { (n, e) };
                    let mut step = |t: f64| full.eval(t);
                    let r = self.close_bracket(a, b, &mut step)?;
                    return Ok(if r.residual.abs() <= tol {
                        Closed::Root(r)
                    } else {
                        Closed::Fallback(format!(
                            "the full grid's root between {} and {} C did not close",
                            a.temperature, b.temperature
                        ))
                    });
                }
            }
            // A secant step from the nearest full-grid evaluation whose
            // slope has the root's orientation, else the coarse slope.
            let secant = window
                .iter()
                .filter(|w| w.temperature != e.temperature)
                .map(|w| (w, (ge - w.residual(t0)) / (e.temperature - w.temperature)))
                .filter(|(_, s)| s.is_finite() && s * below < 0.0)
                .min_by(|(a, _), (b, _)| {
                    (a.temperature - x)
                        .abs()
                        .total_cmp(&(b.temperature - x).abs())
                })
                .map(|(_, s)| s);
            let slope = secant.unwrap_or(slope_c);
            let mut next = x - ge / slope;
            if next <= lo || next >= hi {
                // Out of the window: its end, unless solved already.
                let edge = if next <= lo { lo } else { hi };
                if window.iter().any(|w| w.temperature == edge) {
                    return Ok(Closed::Fallback(format!(
                        "the full grid's g has no root in ({lo}, {hi}) C, the window of the coarse root {} C",
                        root.temperature
                    )));
                }
                next = edge;
            }
            x = next;
        }
        Ok(Closed::Fallback(format!(
            "the coarse root {} C did not close on the full grid within {CLOSE_STEPS} solves",
            root.temperature
        )))
    }

    /// A root found at the evaluation `e` whose orientation is the coarse
    /// root's.
    fn oriented(&self, e: Evaluation, stable: bool) -> Branch {
        Branch {
            temperature: e.temperature,
            rise: e.temperature - self.t0,
            residual: e.residual(self.t0),
            stable,
        }
    }
}

/// `|a / b - 1|`, 0 where both vanish.
fn relative(a: f64, b: f64) -> f64 {
    if a == b {
        0.0
    } else {
        ((a - b) / b).abs()
    }
}

/// The slope of the calibrated coarse `g` across its root at `t`: between
/// the nearest coarse evaluations below and above it.
fn coarse_slope(calibrated: &[Evaluation], t: f64, t0: f64) -> f64 {
    let nearest = |above: bool| {
        calibrated
            .iter()
            .filter(|e| {
                if above {
                    e.temperature > t
                } else {
                    e.temperature < t
                }
            })
            .min_by(|a, b| {
                (a.temperature - t)
                    .abs()
                    .total_cmp(&(b.temperature - t).abs())
            })
            .copied()
    };
    match (nearest(false), nearest(true)) {
        (Some(a), Some(b)) => (b.residual(t0) - a.residual(t0)) / (b.temperature - a.temperature),
        (Some(a), None) | (None, Some(a)) => {
            let r = calibrated
                .iter()
                .find(|e| e.temperature == t)
                .copied()
                .unwrap_or(a);
            (r.residual(t0) - a.residual(t0)) / (r.temperature - a.temperature)
        }
        (None, None) => f64::NAN,
    }
}

/// The full-grid scan's failure, its evaluations' own failures (a solve's
/// error, or [`Full`]'s budget) unwrapped.
fn flatten<E>(e: SearchFailure<SearchFailure<E>>) -> SearchFailure<E> {
    match e {
        SearchFailure::Evaluation(inner) => inner,
        SearchFailure::AboveBracket { rise_at_end } => SearchFailure::AboveBracket { rise_at_end },
        SearchFailure::Budget { evaluations } => SearchFailure::Budget { evaluations },
        SearchFailure::ScanTooLong { start, evaluations } => {
            SearchFailure::ScanTooLong { start, evaluations }
        }
    }
}

#[cfg(test)]
mod tests;
