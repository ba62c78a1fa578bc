//! The constrained iteration for the contact area and pressure (physics.md
//! section 4): find `p >= 0` and the approach `delta` with
//! `gap = g - delta + L p >= 0`, `p gap = 0`, and the normal load
//! `a^2 sum p = F_N` (or `delta` prescribed).
//!
//! Method: a primal-dual active-set iteration (the semismooth Newton method
//! for `min(p, gap) = 0`; Hintermueller, Ito & Kunisch, SIAM J. Optim. 13,
//! 865, 2003). On the current contact set `I` it solves the bordered system
//! `(L p)_I - delta = -g_I`, `a^2 sum_I p = F_N` with restarted GMRES (the
//! operator is not symmetric for `v != 0`), then moves cells with `p <= 0`
//! out of `I` and cells with `gap < 0` into it, until the set no longer
//! changes and the final solve met the tolerance. For a P-matrix (the
//! symmetric part of `L` is positive definite) the LCP has a unique solution;
//! convergence of this iteration on the viscoelastic operator is demonstrated
//! by the tests against the dense direct solver.
//!
//! Written once against [`Backend`]: every vector stays in backend storage;
//! the host sees only scalars and, once per outer iteration, two counts.

mod gmres;
pub mod reference;

use crate::backend::Backend;
use gmres::{gmres, AugOperator, AugVec, GmresWork};

/// What is prescribed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Control {
    /// Normal load `F_N` \[N\].
    Load(f64),
    /// Rigid approach `delta` \[m\].
    Approach(f64),
}

/// Parameters of [`solve`].
#[derive(Debug, Clone, PartialEq)]
pub struct SolverParams {
    /// Relative complementarity residual to reach (default 1e-8). Clamped
    /// to what the backend's arithmetic reaches ([`Backend::epsilon`]): in
    /// f32 the outer test accepts about `16 eps k |u| / |p|` (2.5e-5 on a
    /// 128 x 128 patch) and the inner solves stop at `16 eps`.
    pub tolerance: f64,
    /// Active-set (outer) iterations allowed.
    pub max_iterations: usize,
    /// Operator applications allowed in total.
    pub max_matvecs: usize,
    /// GMRES restart length.
    pub restart: usize,
}

impl Default for SolverParams {
    fn default() -> Self {
        Self {
            tolerance: 1e-8,
            max_iterations: 200,
            max_matvecs: 50_000,
            restart: 30,
        }
    }
}

/// Convergence report of a solve.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct SolveInfo {
    /// Active-set iterations.
    pub iterations: usize,
    /// Applications of the influence operator.
    pub matvecs: usize,
    /// `|min(p, k gap)| / |p|` with `k = 1 / L_00` (a gap turned into the
    /// pressure that closes it on one cell).
    pub residual: f64,
    /// `|a^2 sum p - F_N| / F_N` (0 under approach control).
    pub load_error: f64,
    /// Residual after each outer iteration.
    pub history: Vec<f64>,
    /// Contact-set size after each outer iteration.
    pub contact_history: Vec<usize>,
}

/// Why a solve failed.
#[derive(Debug, thiserror::Error)]
pub enum SolverError {
    #[error("no convergence after {iterations} iterations and {matvecs} matvecs: residual {residual:.3e} (history: {history:?})")]
    NoConvergence {
        iterations: usize,
        matvecs: usize,
        residual: f64,
        history: Vec<f64>,
    },
    #[error("invalid problem: {0}")]
    Invalid(String),
}

/// The solution fields, on the host.
#[derive(Debug, Clone)]
pub struct ContactSolution {
    /// Pressure \[Pa\] per cell.
    pub pressure: Vec<f64>,
    /// Surface displacement `u = L p` \[m\].
    pub displacement: Vec<f64>,
    /// `g - delta + u` \[m\].
    pub gap: Vec<f64>,
    /// 1 in contact, 0 elsewhere.
    pub contact: Vec<f64>,
    /// Rigid approach `delta` \[m\].
    pub approach: f64,
}

/// Something that wants to hear about progress.
pub trait Observer {
    fn iteration(
        &mut self,
        _iteration: usize,
        _matvecs: usize,
        _residual: f64,
        _contact_cells: usize,
    ) {
    }
}

/// An observer that ignores everything.
pub struct Silent;
impl Observer for Silent {}

/// The bordered operator on the contact set `I` (short vectors over `I`):
/// `y = (L_II x - delta_scale s 1, load_scale sum x)`.
struct Bordered<'a, B: Backend> {
    index: &'a B::Index,
    full_in: &'a mut B::Vector,
    full_out: &'a mut B::Vector,
    /// `delta = delta_scale * s`.
    delta_scale: f64,
    /// Load row scale.
    load_scale: f64,
    bordered: bool,
    matvecs: usize,
}

impl<B: Backend> AugOperator<B> for Bordered<'_, B> {
    fn apply(&mut self, backend: &mut B, x_v: &B::Vector, x_s: f64, y: &mut AugVec<B::Vector>) {
        backend.scatter(self.index, x_v, self.full_in);
        backend.apply_rows(self.full_in, self.index, self.full_out, &mut y.v);
        self.matvecs += 1;
        if self.bordered {
            backend.add_scalar(-self.delta_scale * x_s, &mut y.v);
            y.s = self.load_scale * backend.sum(x_v);
        } else {
            y.s = 0.0;
        }
    }

    fn bordered(&self) -> bool {
        self.bordered
    }
}

/// Solve the contact problem for the gap profile `g` (>= 0, one value per
/// cell) on a grid of square cells of area `cell_area`.
///
/// `self_coefficient` is `L_00` (the displacement of a cell under unit
/// pressure on itself), used to scale gaps into pressures.
pub fn solve<B: Backend>(
    backend: &mut B,
    g: &[f64],
    cell_area: f64,
    self_coefficient: f64,
    control: Control,
    params: &SolverParams,
    observer: &mut dyn Observer,
) -> Result<(ContactSolution, SolveInfo), SolverError> {
    solve_from(
        backend,
        g,
        cell_area,
        self_coefficient,
        control,
        params,
        None,
        observer,
    )
}

/// A starting point for [`solve_from`]: a previous solution's contact set,
/// pressure and approach (e.g. on a refined mesh).
#[derive(Debug, Clone, PartialEq)]
pub struct WarmStart {
    /// 1 in contact, 0 elsewhere, one value per cell.
    pub contact: Vec<f64>,
    /// Pressure per cell \[Pa\].
    pub pressure: Vec<f64>,
    /// Rigid approach \[m\].
    pub approach: f64,
}

/// [`solve`] from a warm start (`None`: the bearing-area guess of
/// [`solve`]). The start only changes the path, not the solution.
#[allow(clippy::too_many_arguments)]
pub fn solve_from<B: Backend>(
    backend: &mut B,
    g: &[f64],
    cell_area: f64,
    self_coefficient: f64,
    control: Control,
    params: &SolverParams,
    start: Option<&WarmStart>,
    observer: &mut dyn Observer,
) -> Result<(ContactSolution, SolveInfo), SolverError> {
    let n = backend.grid_len();
    check_problem(g, n, cell_area, self_coefficient, control)?;
    let stiffness = 1.0 / self_coefficient;
    let (tolerance, tight) = tolerances(params.tolerance, backend.epsilon());
    let loose = 1e-4_f64.max(tight);
    let rough = 1e-2_f64.max(loose);

    // Initial contact set.
    let mut host_mask = vec![0.0; n];
    let (delta0, host) = match start {
        Some(ws) if ws.contact.len() == n && ws.pressure.len() == n && ws.approach.is_finite() => {
            host_mask.copy_from_slice(&ws.contact);
            if host_mask.iter().all(|&m| m <= 0.5) {
                return Err(SolverError::Invalid(
                    "the warm start has an empty contact set".into(),
                ));
            }
            (ws.approach, ws.pressure.clone())
        }
        Some(_) => {
            return Err(SolverError::Invalid(format!(
                "the warm start does not match the {n} cells of the problem"
            )))
        }
        None => {
            let (delta0, p0) =
                initial_guess(g, cell_area, self_coefficient, control, &mut host_mask);
            (delta0, host_mask.iter().map(|m| p0 * m).collect())
        }
    };
    let mut mask = backend.zeros(n);
    backend.upload(&host_mask, &mut mask);
    let mut gv = backend.zeros(n);
    backend.upload(g, &mut gv);
    let mut p_full = backend.zeros(n);
    backend.upload(&host, &mut p_full);

    let bordered = matches!(control, Control::Load(_));
    let delta_scale = self_coefficient;
    let mut delta = delta0;
    let mut work = GmresWork::new(backend, params.restart, 0);
    let mut rhs = AugVec {
        v: backend.zeros(0),
        s: 0.0,
    };
    let mut p = AugVec {
        v: backend.zeros(0),
        s: 0.0,
    };
    let mut u = backend.zeros(n);
    let mut gap = backend.zeros(n);
    let mut full_in = backend.zeros(n);
    let mut full_out = backend.zeros(n);

    let mut matvecs = 0usize;
    let mut history = Vec::new();
    let mut contact_history = Vec::new();
    let mut contact_cells = host_mask.iter().filter(|&&m| m > 0.5).count();
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
    for iteration in 1..=params.max_iterations {
        // Inexact Newton: while the contact set still moves a lot, a rough
        // solve decides the next set as well as an exact one would.
        // A residual that did not fall means the rough solves no longer
        // move the pressure (cells entering at p = 0 would leave again).
        let inner_tol = if stalled || last_changes <= (contact_cells / 200).max(1) {
            sharp
        } else if last_changes <= contact_cells / 10 {
            loose
        } else {
            rough
        };
        let index = backend.index_of(&mask);
        let m = backend.index_len(&index);
        if m == 0 {
            return Err(SolverError::Invalid(
                "the contact set is empty: under approach control the surfaces do not touch".into(),
            ));
        }
        let load_scale = self_coefficient / (m as f64).sqrt();
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
        let mut op = Bordered::<B> {
            index: &index,
            full_in: &mut full_in,
            full_out: &mut full_out,
            delta_scale,
            load_scale,
            bordered,
            matvecs: 0,
        };
        let budget = params.max_matvecs.saturating_sub(matvecs).max(1);
        let outcome = gmres(backend, &mut op, &rhs, &mut p, &mut work, inner_tol, budget);
        matvecs += op.matvecs;
        if bordered {
            delta = p.s * delta_scale;
        }
        // Gap everywhere.
        backend.scatter(&index, &p.v, &mut p_full);
        backend.apply(&p_full, &mut u);
        matvecs += 1;
        backend.gap(&gv, &u, delta, &mut gap);
        let (r2, p2) = backend.complementarity(&p_full, &gap, stiffness);
        residual = if p2 > 0.0 {
            (r2 / p2).sqrt()
        } else {
            f64::INFINITY
        };
        // Rounding floor of the residual: on a contact cell the gap is a
        // cancellation of terms of size |u|, so it carries an error of
        // about epsilon |u|, i.e. epsilon k |u| in pressure units.
        let floor = if p2 > 0.0 {
            ROUNDING_FLOOR * backend.epsilon() * stiffness * (backend.dot(&u, &u) / p2).sqrt()
        } else {
            0.0
        };
        let previous_residual = history.last().copied().unwrap_or(f64::INFINITY);
        stalled = residual >= previous_residual;
        if stalled && inner_tol == sharp && sharp > floor_inner {
            sharp = (0.01 * sharp).max(floor_inner);
        }
        let (changes, size) = backend.update_active_set(&p_full, &gap, &mut mask);
        history.push(residual);
        contact_history.push(size);
        observer.iteration(iteration, matvecs, residual, size);
        // At the arithmetic's floor the residual stops improving once the
        // inner solves cannot be sharpened further (f32 on large grids,
        // where the floor estimate above is optimistic). The set may then
        // keep toggling a few cells: one whose gap (full product) is below
        // zero enters, the inner solve (already within its tolerance) leaves
        // its pressure at zero or pushes it below, and it leaves again.
        let settled = changes == 0 && inner_tol == sharp && outcome.converged;
        let at_inner_floor = inner_tol <= floor_inner && outcome.converged;
        let few_changes = changes <= (size / FLOOR_TOGGLES).max(1);
        if residual < STAGNATION * best_residual {
            best_residual = residual;
            stagnant = 0;
        } else if at_inner_floor && few_changes {
            stagnant += 1;
        } else {
            stagnant = 0;
        }
        let at_floor = stagnant >= STAGNANT_ITERATIONS && residual <= STAGNANT_ACCEPT;
        if (settled && residual <= tolerance.max(floor)) || at_floor {
            let load_error = match control {
                Control::Load(f) => (cell_area * backend.sum(&p_full) - f).abs() / f,
                Control::Approach(_) => 0.0,
            };
            let mut out = |v: &B::Vector| {
                let mut h = vec![0.0; n];
                backend.download(v, &mut h);
                h
            };
            return Ok((
                ContactSolution {
                    pressure: out(&p_full),
                    displacement: out(&u),
                    gap: out(&gap),
                    contact: out(&mask),
                    approach: delta,
                },
                SolveInfo {
                    iterations: iteration,
                    matvecs,
                    residual,
                    load_error,
                    history,
                    contact_history,
                },
            ));
        }
        last_changes = changes;
        contact_cells = size;
        if matvecs >= params.max_matvecs {
            break;
        }
    }
    Err(SolverError::NoConvergence {
        iterations: history.len(),
        matvecs,
        residual,
        history,
    })
}

/// Smallest inner (GMRES) tolerance, in units of the backend's epsilon.
const INNER_FLOOR: f64 = 16.0;
/// Smallest outer (complementarity) tolerance, in units of the backend's
/// epsilon.
const OUTER_FLOOR: f64 = 128.0;
/// The outer test accepts a residual below this multiple of its rounding
/// floor `epsilon k |u| / |p|` (which grows with the grid side: the
/// displacement integrates the pressure over the patch, `k = 1 / L_00`
/// only over one cell). Far below the default tolerance in f64; in f32 it
/// is what can be reached (measured: 2.5e-5 on a 128 x 128 patch, where
/// `epsilon k |u| / |p|` is 3.2e-6).
const ROUNDING_FLOOR: f64 = 16.0;
/// A residual less than 1 % below the best so far counts as stagnant.
const STAGNATION: f64 = 0.99;
/// At the floor, the set may toggle at most one cell in this many (at least
/// one cell) per iteration.
const FLOOR_TOGGLES: usize = 1000;
/// Stagnant outer iterations (inner solves at the floor, the set unchanged
/// or toggling a few cells) after which the residual is the arithmetic's
/// floor.
const STAGNANT_ITERATIONS: usize = 3;
/// Largest residual accepted at the floor (measured f32 floors: 5.8e-5 at
/// 512^2, 1.3e-4 at 1024^2); above it a stagnant solve is an error.
const STAGNANT_ACCEPT: f64 = 1e-3;

/// `(outer, inner)` tolerances: the requested outer tolerance and
/// `0.01` of it for the inner solves, each clamped to what the backend's
/// arithmetic can reach (for f64 the defaults are far above the floors; f32
/// storage gives about `1.5e-5` and `1.9e-6`).
fn tolerances(tolerance: f64, epsilon: f64) -> (f64, f64) {
    let outer = tolerance.max(OUTER_FLOOR * epsilon);
    (outer, (0.01 * outer).max(INNER_FLOOR * epsilon))
}

fn check_problem(
    g: &[f64],
    n: usize,
    cell_area: f64,
    self_coefficient: f64,
    control: Control,
) -> Result<(), SolverError> {
    if g.len() != n {
        return Err(SolverError::Invalid(format!(
            "gap has {} cells, grid has {n}",
            g.len()
        )));
    }
    if let Some(i) = g.iter().position(|v| !v.is_finite()) {
        return Err(SolverError::Invalid(format!(
            "gap profile is not finite at cell {i}"
        )));
    }
    if !(cell_area > 0.0 && self_coefficient > 0.0) {
        return Err(SolverError::Invalid(
            "cell area and self coefficient must be positive".into(),
        ));
    }
    match control {
        Control::Load(f) if !(f.is_finite() && f >= 0.0) => Err(SolverError::Invalid(format!(
            "normal load {f} N must be positive"
        ))),
        Control::Approach(d) if !d.is_finite() => Err(SolverError::Invalid(format!(
            "approach {d} m must be finite"
        ))),
        _ => Ok(()),
    }
}

/// Full contact: the pressure that keeps every cell in contact, from one
/// linear solve of the bordered system on the whole grid (no sign
/// constraint). Physical when every pressure comes out positive; with
/// `Control::Load(0.0)` it gives the pure response to the profile `g`.
pub fn solve_full_contact<B: Backend>(
    backend: &mut B,
    g: &[f64],
    cell_area: f64,
    self_coefficient: f64,
    control: Control,
    params: &SolverParams,
) -> Result<(ContactSolution, SolveInfo), SolverError> {
    let n = backend.grid_len();
    check_problem(g, n, cell_area, self_coefficient, control)?;
    let mut mask = backend.zeros(n);
    backend.upload(&vec![1.0; n], &mut mask);
    let index = backend.index_of(&mask);
    let mut gv = backend.zeros(n);
    backend.upload(g, &mut gv);
    let bordered = matches!(control, Control::Load(_));
    let load_scale = self_coefficient / (n as f64).sqrt();
    let mut rhs = AugVec {
        v: backend.zeros(n),
        s: 0.0,
    };
    backend.copy(&gv, &mut rhs.v);
    backend.scale(-1.0, &mut rhs.v);
    match control {
        Control::Load(f) => rhs.s = load_scale * f / cell_area,
        Control::Approach(d) => backend.add_scalar(d, &mut rhs.v),
    }
    let mut full_in = backend.zeros(n);
    let mut full_out = backend.zeros(n);
    let mut op = Bordered::<B> {
        index: &index,
        full_in: &mut full_in,
        full_out: &mut full_out,
        delta_scale: self_coefficient,
        load_scale,
        bordered,
        matvecs: 0,
    };
    let mut p = AugVec {
        v: backend.zeros(n),
        s: 0.0,
    };
    let mut work = GmresWork::new(backend, params.restart, n);
    let outcome = gmres(
        backend,
        &mut op,
        &rhs,
        &mut p,
        &mut work,
        tolerances(params.tolerance, backend.epsilon()).1,
        params.max_matvecs,
    );
    let mut matvecs = op.matvecs;
    if !outcome.converged {
        return Err(SolverError::NoConvergence {
            iterations: 1,
            matvecs,
            residual: f64::NAN,
            history: vec![],
        });
    }
    let delta = match control {
        Control::Load(_) => p.s * self_coefficient,
        Control::Approach(d) => d,
    };
    let mut u = backend.zeros(n);
    backend.apply(&p.v, &mut u);
    matvecs += 1;
    let mut gap = backend.zeros(n);
    backend.gap(&gv, &u, delta, &mut gap);
    let (r2, p2) = backend.complementarity(&p.v, &gap, 1.0 / self_coefficient);
    let load_error = match control {
        Control::Load(f) if f > 0.0 => (cell_area * backend.sum(&p.v) - f).abs() / f,
        _ => 0.0,
    };
    let mut out = |v: &B::Vector| {
        let mut h = vec![0.0; n];
        backend.download(v, &mut h);
        h
    };
    let solution = ContactSolution {
        pressure: out(&p.v),
        displacement: out(&u),
        gap: out(&gap),
        contact: vec![1.0; n],
        approach: delta,
    };
    let residual = if p2 > 0.0 { (r2 / p2).sqrt() } else { 0.0 };
    Ok((
        solution,
        SolveInfo {
            iterations: 1,
            matvecs,
            residual,
            load_error,
            history: vec![residual],
            contact_history: vec![n],
        },
    ))
}

/// Initial contact set and pressure. Under load control: the cells with the
/// smallest gap, as many as the linear area-load law predicts (paper Eq. 10,
/// `A/A0 = kappa p0 / (E* m)` with `kappa = 2`, `m` the rms slope of the
/// gap profile and `E*` read off the self coefficient: for a square cell
/// `L_00 = (1 - nu^2) / (pi E) 4 a asinh(1)`, so `E* = 4 asinh(1) a / (pi L_00)`).
fn initial_guess(
    g: &[f64],
    cell_area: f64,
    l00: f64,
    control: Control,
    mask: &mut [f64],
) -> (f64, f64) {
    let n = g.len();
    let mut sorted: Vec<f64> = g.to_vec();
    sorted.sort_by(|a, b| a.total_cmp(b));
    let count = match control {
        Control::Load(f) => {
            let a = cell_area.sqrt();
            let e_star = 4.0 * 1f64.asinh() * a / (std::f64::consts::PI * l00);
            let mean_p = f / (cell_area * n as f64);
            let slope = rms_slope_along_rows(g, a);
            let fraction = if slope > 0.0 {
                2.0 * mean_p / (e_star * slope)
            } else {
                1.0
            };
            ((fraction * n as f64).ceil() as usize).clamp(1, n.div_ceil(2))
        }
        Control::Approach(d) => sorted.iter().filter(|&&x| x < d).count().max(1),
    };
    let threshold = sorted[count - 1];
    let mut m = 0usize;
    for (mk, &gi) in mask.iter_mut().zip(g) {
        if gi <= threshold && m < count {
            *mk = 1.0;
            m += 1;
        }
    }
    let p0 = match control {
        Control::Load(f) => f / (cell_area * m as f64),
        Control::Approach(_) => 0.0,
    };
    (threshold, p0)
}

/// rms of the finite-difference slope of `g` along the storage rows and
/// columns of a square grid (`sqrt(<|grad g|^2>)`); the grid shape is taken
/// as square when `n` is a perfect square, else as one row.
fn rms_slope_along_rows(g: &[f64], a: f64) -> f64 {
    let n = g.len();
    let side = (n as f64).sqrt().round() as usize;
    if side * side != n || side < 2 {
        return 0.0;
    }
    let mut s2 = 0.0;
    let mut count = 0usize;
    for i in 0..side {
        for j in 0..side - 1 {
            let d = g[i * side + j + 1] - g[i * side + j];
            s2 += d * d;
            count += 1;
        }
    }
    for i in 0..side - 1 {
        for j in 0..side {
            let d = g[(i + 1) * side + j] - g[i * side + j];
            s2 += d * d;
        }
    }
    (2.0 * s2 / (2 * count) as f64).sqrt() / a
}
