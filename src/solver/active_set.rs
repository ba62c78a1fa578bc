//! The primal-dual active-set iteration (semismooth Newton) of
//! [`solve`], with its inner Krylov solves on the bordered contact-set
//! system (module docs of [`super`]).

use super::gmres::{gmres, AugOperator, AugVec, GmresWork};
use super::initial_guess::initial_guess;
use super::inner_mode::InnerMode;
use super::line_search::{update_set, Previous};
use super::{
    check_problem, tolerances, ContactProblem, ContactSolution, Control, Observer, SolveInfo,
    SolverError, SolverParams, WarmStart, FAST_FALL, FLOOR_TOGGLES, INNER_FLOOR,
    PRECONDITIONED_BUDGET, RESTART_GROWTH, ROUNDING_FLOOR, STAGNANT_ACCEPT, STAGNANT_ITERATIONS,
    STAGNATION, STALL_ABOVE, STALL_CYCLES, STALL_GAIN, STALL_ITERATIONS,
};
use crate::backend::Backend;

/// How far one outer iteration solves its contact-set system (inexact
/// Newton). Every solve stops at the sharp (final) tolerance; before that,
/// at a reduction of its starting residual that depends on how much the
/// contact set still moves: a rough solve decides the next set as well as
/// an exact one would while many cells change. The reduction is relative to
/// the warm start's residual, not to `|g_I|`, so that a good start (a
/// prolonged coarse solution) still makes progress each iteration.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Phase {
    /// More than a tenth of the set changed.
    Rough,
    /// Less than a tenth, more than 1 in 200 cells.
    Loose,
    /// A few cells; the set has almost settled.
    Sharp,
}

impl Phase {
    /// The phase after an iteration that changed `changes` of `cells`
    /// cells; a residual that did not fall (`stalled`: cells entering at
    /// `p = 0` leave again) moves it one step towards sharp.
    fn choose(changes: usize, cells: usize, stalled: bool) -> Self {
        let few = changes <= (cells / 200).max(1);
        let some = changes <= cells / 10;
        if few || (stalled && some) {
            Self::Sharp
        } else if some || stalled {
            Self::Loose
        } else {
            Self::Rough
        }
    }

    /// Reduction of the starting residual at which the solve stops (0: only
    /// the sharp tolerance); `settle` for a set that has settled (unchanged
    /// in the last iteration, or toggling at most one cell in
    /// [`FLOOR_TOGGLES`] while the residual fell by [`FAST_FALL`], or a
    /// stalled residual): solve to the end.
    fn reduction(self, settle: bool) -> f64 {
        match self {
            Self::Rough => 1e-2,
            Self::Loose => 1e-3,
            Self::Sharp if settle => 0.0,
            Self::Sharp => 1e-4,
        }
    }
}

/// The bordered operator on the contact set `I` (short vectors over `I`):
/// `y = (L_II x - delta_scale s 1, load_scale sum x)`.
///
/// With a backend preconditioner `K ~ L^-1` it is right-preconditioned by
/// the block inverse built on `K_II = R K R^T`: for `(r, t)`,
/// `s = (t / load_scale - 1.K_II r) / (delta_scale 1.K_II 1)` and
/// `x = K_II (r + delta_scale s 1)`, which is the exact inverse when
/// `K_II = L_II^-1` (the load row is met exactly, the approach follows the
/// Schur complement `1.K_II 1`).
pub(crate) struct Bordered<'a, B: Backend> {
    pub(crate) index: &'a B::Index,
    /// `delta = delta_scale * s`.
    pub(crate) delta_scale: f64,
    /// Load row scale.
    pub(crate) load_scale: f64,
    pub(crate) bordered: bool,
    pub(crate) matvecs: usize,
    /// Of `matvecs`, the exact (f64) products of mixed precision.
    pub(crate) exact_matvecs: usize,
    /// `K_II 1` and `1.K_II 1` when preconditioned.
    pub(crate) schur: Option<(B::Vector, f64)>,
    pub(crate) preconditioner_applications: usize,
}

impl<'a, B: Backend> Bordered<'a, B> {
    /// The operator on `index`, preconditioned when `precondition` and the
    /// backend has a preconditioner (one application for `K_II 1`).
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn new(
        backend: &mut B,
        index: &'a B::Index,
        delta_scale: f64,
        load_scale: f64,
        bordered: bool,
        precondition: bool,
    ) -> Self {
        let mut op = Self {
            index,
            delta_scale,
            load_scale,
            bordered,
            matvecs: 0,
            exact_matvecs: 0,
            schur: None,
            preconditioner_applications: 0,
        };
        if precondition && backend.has_preconditioner() {
            let m = backend.index_len(index);
            let mut ones = backend.zeros(m);
            backend.add_scalar(1.0, &mut ones);
            let mut k1 = backend.zeros(m);
            op.restricted_stiffness(backend, &ones, &mut k1);
            let sigma = backend.sum(&k1);
            op.schur = Some((k1, sigma));
        }
        op
    }

    /// The approach column and the load row of the bordered product, added
    /// to `y.v = L_II x_v`.
    fn border(&self, backend: &mut B, x_v: &B::Vector, x_s: f64, y: &mut AugVec<B::Vector>) {
        if self.bordered {
            backend.add_scalar(-self.delta_scale * x_s, &mut y.v);
            y.s = self.load_scale * backend.sum(x_v);
        } else {
            y.s = 0.0;
        }
    }

    /// `y = K_II x` on short vectors.
    fn restricted_stiffness(&mut self, backend: &mut B, x: &B::Vector, y: &mut B::Vector) {
        backend.precondition_set(self.index, x, y);
        self.preconditioner_applications += 1;
    }
}

impl<B: Backend> AugOperator<B> for Bordered<'_, B> {
    fn apply(&mut self, backend: &mut B, x_v: &B::Vector, x_s: f64, y: &mut AugVec<B::Vector>) {
        backend.apply_set(self.index, x_v, &mut y.v);
        self.matvecs += 1;
        self.border(backend, x_v, x_s, y);
    }

    fn apply_exact(
        &mut self,
        backend: &mut B,
        x_v: &B::Vector,
        x_s: f64,
        y: &mut AugVec<B::Vector>,
    ) {
        if !backend.refines() {
            return self.apply(backend, x_v, x_s, y);
        }
        backend.apply_set_exact(self.index, x_v, &mut y.v);
        self.matvecs += 1;
        self.exact_matvecs += 1;
        self.border(backend, x_v, x_s, y);
    }

    fn bordered(&self) -> bool {
        self.bordered
    }

    fn preconditioned(&self) -> bool {
        self.schur.is_some()
    }

    fn precondition(
        &mut self,
        backend: &mut B,
        x_v: &B::Vector,
        x_s: f64,
        y: &mut AugVec<B::Vector>,
    ) {
        self.restricted_stiffness(backend, x_v, &mut y.v);
        let (k1, sigma) = self.schur.as_ref().expect("preconditioned");
        if self.bordered && *sigma > 0.0 {
            let s = (x_s / self.load_scale - backend.sum(&y.v)) / (self.delta_scale * sigma);
            backend.axpy(self.delta_scale * s, k1, &mut y.v);
            y.s = s;
        } else {
            y.s = 0.0;
        }
    }
}

/// Solve `problem` on `backend` (paper Eq. 7 with the constraints of
/// physics.md section 4), from a warm start or (`None`) the bearing-area
/// guess. The start only changes the path, not the solution. The start's
/// host vectors are freed once uploaded, and an owned gap profile becomes
/// the iteration's vector (on the CPU without a copy; on the largest grids
/// each is hundreds of MB).
pub fn solve<B: Backend>(
    backend: &mut B,
    problem: ContactProblem<'_>,
    params: &SolverParams,
    start: Option<WarmStart>,
    observer: &mut dyn Observer,
) -> Result<(ContactSolution, SolveInfo), SolverError> {
    let ContactProblem {
        gap,
        cell_area,
        self_coefficient,
        control,
    } = problem;
    let g = gap.into_owned();
    let n = backend.grid_len();
    check_problem(&g, n, cell_area, self_coefficient, control)?;
    let stiffness = 1.0 / self_coefficient;
    let (tolerance, tight) = tolerances(params.tolerance, backend.epsilon());

    // Initial contact set.
    let (delta0, host_mask, host) = match start {
        Some(ws) if ws.contact.len() == n && ws.pressure.len() == n && ws.approach.is_finite() => {
            if ws.contact.iter().all(|&m| m <= 0.5) {
                return Err(SolverError::Invalid(
                    "the warm start has an empty contact set".into(),
                ));
            }
            (ws.approach, ws.contact, ws.pressure)
        }
        Some(_) => {
            return Err(SolverError::Invalid(format!(
                "the warm start does not match the {n} cells of the problem"
            )))
        }
        None => {
            let mut host_mask = vec![0.0; n];
            let (delta0, p0) =
                initial_guess(&g, cell_area, self_coefficient, control, &mut host_mask);
            let host = host_mask.iter().map(|m| p0 * m).collect();
            (delta0, host_mask, host)
        }
    };
    let mut contact_cells = host_mask.iter().filter(|&&m| m > 0.5).count();
    let mut mask = backend.mask_from(&host_mask);
    drop(host_mask);
    let gv = backend.adopt(g);
    let mut p_full = backend.adopt(host);

    let bordered = matches!(control, Control::Load(_));
    let delta_scale = self_coefficient;
    // Under approach control the approach is prescribed: the gap is
    // measured with it, whatever the start (the bearing-area guess's
    // threshold, a warm start's approach) held.
    let mut delta = match control {
        Control::Load(_) => delta0,
        Control::Approach(d) => d,
    };
    let mut restart = params.restart.max(1);
    let mut work = GmresWork::new(backend, restart, 0);
    let mut largest_set = 0usize;
    let mut rhs = AugVec {
        v: backend.zeros(0),
        s: 0.0,
    };
    let mut p = AugVec {
        v: backend.zeros(0),
        s: 0.0,
    };
    // The gap `g - delta + u`; each iteration's product `u = L p` is
    // written here and turned into the gap in place (the displacement is
    // recovered from it at the end).
    let mut gap = backend.zeros(n);

    let mut matvecs = 0usize;
    let mut preconditioner_applications = 0usize;
    let mut exact_matvecs = 0usize;
    let mut history = Vec::new();
    let mut contact_history = Vec::new();
    let mut last_changes = usize::MAX;
    let mut residual = f64::INFINITY;
    let mut stalled = false;
    // The inner tolerance is relative to |g_I|; where the complementarity
    // residual (relative to |p|) stalls above the target on an unchanged
    // set, the inner solves are sharpened towards the arithmetic's floor.
    let floor_inner = INNER_FLOOR * backend.epsilon();
    let mut sharp = tight;
    let mut stagnant = 0usize;
    let mut best_residual = f64::INFINITY;
    // Since the best residual last fell by STALL_GAIN: the outer
    // iterations, those among them whose inner solve ran out of its
    // budget, and that best residual.
    let mut stall = Stall {
        iterations: 0,
        at_budget: 0,
        best: f64::INFINITY,
        best_merit: f64::INFINITY,
    };
    let mut cause = String::new();
    // A preconditioner that does not help (an approximate inverse far from
    // the operator, e.g. the circulant of a layer much thinner than a cell)
    // is dropped after an inner solve that reaches neither its tolerance
    // nor its inexact-Newton reduction within PRECONDITIONED_BUDGET
    // restarts, and taken up again once plain solves cost more per decade.
    let mut mode = InnerMode::new(params.precondition && backend.has_preconditioner());
    // The previous iterate, for the line search along the Newton step.
    let mut previous = Previous::new(backend, n);
    for iteration in 1..=params.max_iterations {
        if observer.cancelled() {
            return Err(SolverError::Cancelled);
        }
        let phase = Phase::choose(last_changes, contact_cells, stalled);
        let index = backend.index_of(&mask);
        let m = backend.index_len(&index);
        if m == 0 {
            return Err(SolverError::Invalid(match control {
                Control::Approach(d) => format!(
                    "the contact set is empty: under approach control (approach {d:e} m) the surfaces do not touch"
                ),
                Control::Load(f) => format!(
                    "the contact set is empty: the normal load {f:e} N is too small to press any cell into contact in double precision"
                ),
            }));
        }
        let load_scale = self_coefficient / (m as f64).sqrt();
        // The short vectors (Krylov basis, its two work vectors, the
        // right-hand side and the solution) grow with the set: refuse a
        // growth that does not fit, in words, before allocating it.
        if m > largest_set {
            backend
                .reserve(restart + 5, m - largest_set)
                .map_err(|e| {
                    SolverError::Invalid(format!(
                        "the Krylov basis over a contact set of {m} cells (solver.restart = {}) does not fit: {e}",
                        params.restart
                    ))
                })?;
            largest_set = m;
        }
        work.resize(backend, m);
        backend.resize(&mut rhs.v, m);
        backend.resize(&mut p.v, m);
        // rhs = -g_I (+ delta under approach control); load row.
        backend.gather(&index, &gv, &mut rhs.v);
        backend.scale(-1.0, &mut rhs.v);
        match control {
            Control::Load(f) => rhs.s = load_scale * f / cell_area,
            Control::Approach(d) => {
                backend.add_scalar(d, &mut rhs.v);
                rhs.s = 0.0;
            }
        }
        // Warm start: the previous pressure on the new set, the previous approach.
        backend.gather(&index, &p_full, &mut p.v);
        p.s = delta / delta_scale;
        // The preconditioner fitting the set's size (near-full contact: the
        // optimal circulant of the whole grid).
        backend.set_contact_fraction(m as f64 / n as f64);
        let mut op = Bordered::new(
            backend,
            &index,
            delta_scale,
            load_scale,
            bordered,
            mode.precondition(),
        );
        let preconditioned = op.preconditioned();
        let mut budget = params.max_matvecs.saturating_sub(matvecs).max(1);
        if preconditioned {
            budget = budget.min(PRECONDITIONED_BUDGET * restart);
        }
        // Solve to the end once the set has settled: unchanged, or toggling
        // a few cells while the residual falls fast (the next set is likely
        // the last), or a stalled residual. A few cells still moving on a
        // slowly falling residual get the sharp phase's reduction only.
        let few_toggles = last_changes <= (contact_cells / FLOOR_TOGGLES).max(1);
        let before_last = match history.len() {
            n if n >= 2 => history[n - 2],
            _ => f64::INFINITY,
        };
        let settle =
            stalled || last_changes == 0 || (few_toggles && residual <= FAST_FALL * before_last);
        let reduction = phase.reduction(settle);
        let outcome = gmres(
            backend, &mut op, &rhs, &mut p, &mut work, sharp, reduction, budget, observer,
        );
        if outcome.cancelled {
            return Err(SolverError::Cancelled);
        }
        matvecs += op.matvecs;
        preconditioner_applications += op.preconditioner_applications;
        exact_matvecs += op.exact_matvecs;
        mode.record(op.matvecs, outcome.reduction, outcome.reached);
        // A preconditioned solve that missed its target within its budget
        // stagnated between restarts (restarted GMRES on an operator far
        // from normal: the periodic one near full contact with
        // `E_inf / E0 ~ 750` reduced its residual by 0.13 in 300 steps at
        // restart 30, and the plain solves that followed took up to 20,000
        // matvecs): the Krylov space is doubled, up to RESTART_GROWTH times
        // the configured length, where its memory fits.
        if preconditioned && !outcome.reached {
            let grown = (2 * restart).min(RESTART_GROWTH * params.restart.max(1));
            if grown > restart && backend.reserve(grown - restart, largest_set).is_ok() {
                restart = grown;
                work = GmresWork::new(backend, restart, m);
            }
        }
        if bordered {
            delta = p.s * delta_scale;
        }
        // Gap everywhere.
        backend.scatter(&index, &p.v, &mut p_full);
        backend.apply(&p_full, &mut gap);
        matvecs += 1;
        let u2 = backend.dot(&gap, &gap);
        backend.to_gap(&gv, delta, &mut gap);
        let merit = backend.complementarity(&p_full, &gap, stiffness);
        let step = previous.damp(backend, stiffness, &mut p_full, &mut gap, &mut delta, merit);
        let (r2, p2) = step.merit;
        residual = if p2 > 0.0 {
            (r2 / p2).sqrt()
        } else {
            f64::INFINITY
        };
        // Rounding floor of the residual: on a contact cell the gap is a
        // cancellation of terms of size |u|, so it carries an error of
        // about epsilon |u|, i.e. epsilon k |u| in pressure units (|u| of
        // the full Newton step; a damped step is far above the floor).
        let floor = if p2 > 0.0 {
            ROUNDING_FLOOR * backend.epsilon() * stiffness * (u2 / p2).sqrt()
        } else {
            0.0
        };
        let previous_residual = history.last().copied().unwrap_or(f64::INFINITY);
        stalled = residual >= previous_residual;
        let (changes, size) = update_set(backend, step.t, &p_full, &gap, stiffness, &mut mask);
        // A full inner solve that did not help (a stalled residual, or none
        // better than the best so far) or that left the residual above the
        // target on an unchanged set is limited by the inner tolerance:
        // sharpen it at once.
        let full_solve = phase == Phase::Sharp && reduction == 0.0;
        let short = residual > tolerance.max(floor);
        let no_gain = residual >= STAGNATION * best_residual;
        if full_solve && sharp > floor_inner && (stalled || no_gain || (changes == 0 && short)) {
            sharp = (0.01 * sharp).max(floor_inner);
        }
        history.push(residual);
        contact_history.push(size);
        observer.iteration(iteration, matvecs, residual, size);
        // At the arithmetic's floor the residual stops improving once the
        // inner solves cannot be sharpened further (f32 on large grids,
        // where the floor estimate above is optimistic). The set may then
        // keep toggling a few cells: one whose gap (full product) is below
        // zero enters, the inner solve (already within its tolerance) leaves
        // its pressure at zero or pushes it below, and it leaves again.
        let settled = changes == 0 && outcome.converged;
        let at_inner_floor = sharp <= floor_inner && outcome.converged;
        let few_changes = changes <= (size / FLOOR_TOGGLES).max(1);
        // Degenerate cells (both `p` and the gap at zero) may toggle in and
        // out of the set forever at a residual already below the target:
        // a converged solve whose set moves a few cells without improving
        // the residual is the answer too.
        let toggling = few_changes && stalled && outcome.converged;
        if residual < STAGNATION * best_residual {
            best_residual = residual;
            stagnant = 0;
        } else if at_inner_floor && few_changes {
            stagnant += 1;
        } else if !few_changes {
            stagnant = 0;
        }
        // (A few toggling cells after an inexact step that did not beat the
        // best residual neither count nor reset: at the floor such steps
        // alternate with the settled ones, which count.)
        let at_floor = stagnant >= STAGNANT_ITERATIONS && residual <= STAGNANT_ACCEPT;
        if ((settled || toggling) && residual <= tolerance.max(floor)) || at_floor {
            let load_error = match control {
                Control::Load(f) => (cell_area * backend.sum(&p_full) - f).abs() / f,
                Control::Approach(_) => 0.0,
            };
            // The work vectors go before the fields come to the host (on
            // the largest grids each is hundreds of MB), each field's
            // storage as soon as it is copied.
            drop((work, rhs, mask, index, previous));
            // The displacement from the gap: u = gap - g + delta.
            let mut u = backend.zeros(n);
            backend.copy(&gap, &mut u);
            backend.axpy(-1.0, &gv, &mut u);
            backend.add_scalar(delta, &mut u);
            drop(gv);
            let mut out = |v: B::Vector| backend.take_host(v);
            let pressure = out(p_full);
            // The cells carrying pressure: the set of this solve (the
            // updated mask differs by the toggling cells).
            let contact = pressure
                .iter()
                .map(|&p| if p > 0.0 { 1.0 } else { 0.0 })
                .collect();
            return Ok((
                ContactSolution {
                    pressure,
                    displacement: out(u),
                    gap: out(gap),
                    contact,
                    approach: delta,
                },
                SolveInfo {
                    iterations: iteration,
                    matvecs,
                    exact_matvecs,
                    preconditioner_applications,
                    levels: Vec::new(),
                    residual,
                    load_error,
                    history,
                    contact_history,
                },
            ));
        }
        last_changes = changes;
        contact_cells = size;
        stall.record(residual, r2.sqrt(), outcome.reached);
        if let Some(why) = stall.cause(residual, 100.0 * size as f64 / n as f64) {
            cause = why;
            break;
        }
        if matvecs >= params.max_matvecs {
            break;
        }
    }
    Err(SolverError::NoConvergence {
        iterations: history.len(),
        matvecs,
        residual,
        history,
        cause,
    })
}

/// The stall rule: outer iterations that lower neither the best relative
/// residual `|min(p, k gap)| / |p|` nor the best merit `|min(p, k gap)|`
/// by [`STALL_GAIN`], counted since one of them last did.
///
/// The merit is what the line search lowers (module `line_search`); the
/// relative residual alone missed the progress of a set shrinking from
/// half the grid to 1 % of it, where `|p|` falls with the merit: the
/// layer case of issue #41 was stopped as stalled after 19 iterations at a
/// flat relative residual of 0.7 and converges in 30.
struct Stall {
    iterations: usize,
    /// Of `iterations`, those whose inner solve ran out of its budget
    /// (neither converged nor reached its inexact-Newton reduction).
    at_budget: usize,
    best: f64,
    best_merit: f64,
}

impl Stall {
    fn record(&mut self, residual: f64, merit: f64, inner_reached: bool) {
        let gain = residual < STALL_GAIN * self.best || merit < STALL_GAIN * self.best_merit;
        if gain {
            *self = Stall {
                iterations: 0,
                at_budget: 0,
                best: residual.min(self.best),
                best_merit: merit.min(self.best_merit),
            };
        } else {
            self.iterations += 1;
            self.at_budget += usize::from(!inner_reached);
        }
    }

    /// The error's cause once the iteration counts as stalled (above
    /// [`STALL_ABOVE`]: [`STALL_ITERATIONS`] iterations without gain whose
    /// inner solves ran out of their budget, or [`STALL_CYCLES`] without
    /// gain at all), with the contact percentage `percent`.
    fn cause(&self, residual: f64, percent: f64) -> Option<String> {
        if residual <= STALL_ABOVE {
            return None;
        }
        if self.at_budget >= STALL_ITERATIONS {
            Some(format!(
                "; stalled: the residual has not fallen below {:.3e} for {} iterations, {} of them with the inner solve at its budget, with {percent:.1} % of the cells in contact (the constrained iteration cycles on a strongly non-symmetric operator)",
                self.best, self.iterations, self.at_budget
            ))
        } else if self.iterations >= STALL_CYCLES {
            Some(format!(
                "; stalled: the residual has not fallen below {:.3e} for {} iterations, {} of them with a converged inner solve, with {percent:.1} % of the cells in contact (the contact set cycles: cells enter and leave in turn)",
                self.best,
                self.iterations,
                self.iterations - self.at_budget
            ))
        } else {
            None
        }
    }
}
