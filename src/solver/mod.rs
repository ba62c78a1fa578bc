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
//! The iteration is globalised (module `line_search`): where a full step does not
//! lower the complementarity merit `|min(p, k gap)|^2`, the step is damped
//! by backtracking (the undamped iteration cycled near full contact on the
//! periodic operator far from symmetric, `E_inf / E0 ~ 80`).
//!
//! Three things keep the work nearly independent of the grid:
//! - the inner solves are right-preconditioned, where the backend has one,
//!   with the restriction to `I` of an approximate inverse of `L` (the
//!   spectral stiffness; operator preconditioning of a first-kind integral
//!   equation), bordered by its Schur complement for the load row
//!   ([`solve`]); their iteration counts then barely grow with the
//!   resolution of the contact spots;
//! - inexact Newton: each outer iteration reduces its inner residual by a
//!   fixed factor relative to its warm start (1e-2 while the set moves a
//!   lot, down to the full tolerance once it settles), not relative to
//!   `|g_I|`, so a good start still progresses every iteration;
//! - nested iteration ([`cascade`]): the same problem solved on coarser
//!   grids first gives the fine grid a start a few outer iterations from
//!   its solution (instead of a bearing-area guess some 70 times too large
//!   on many-scale surfaces).
//!
//! Written once against [`crate::backend::Backend`]: every vector stays in backend storage;
//! the host sees only scalars and, once per outer iteration, two counts.

mod active_set;
pub mod cascade;
mod full_contact;
mod gmres;
mod initial_guess;
mod inner_mode;
mod line_search;
pub mod reference;

pub use active_set::solve;
pub use cascade::{solve_cascade, CascadeLevel, LevelInfo};
pub use full_contact::solve_full_contact;

use std::borrow::Cow;

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
    /// to what the backend's arithmetic reaches ([`crate::backend::Backend::epsilon`]): in
    /// f32 the outer test accepts about `16 eps k |u| / |p|` (2.5e-5 on a
    /// 128 x 128 patch) and the inner solves stop at `16 eps`.
    pub tolerance: f64,
    /// Active-set (outer) iterations allowed.
    pub max_iterations: usize,
    /// Operator applications allowed in total.
    pub max_matvecs: usize,
    /// GMRES restart length.
    pub restart: usize,
    /// Right-precondition the inner solves with the backend's approximate
    /// inverse of the operator where it has one ([`crate::backend::Backend::precondition`]).
    pub precondition: bool,
}

impl Default for SolverParams {
    fn default() -> Self {
        Self {
            tolerance: 1e-8,
            max_iterations: 200,
            max_matvecs: 50_000,
            restart: 30,
            precondition: true,
        }
    }
}

/// Convergence report of a solve.
#[derive(Debug, Clone, PartialEq, Default, serde::Serialize)]
pub struct SolveInfo {
    /// Active-set iterations (on the finest grid of a cascade).
    pub iterations: usize,
    /// Applications of the influence operator; for a cascade
    /// ([`solve_cascade`]) the fine-grid equivalent (an application on a
    /// grid of a quarter of the cells counts 1/4), rounded up.
    pub matvecs: usize,
    /// Of `matvecs`, the f64 products of the GMRES restarts of mixed
    /// precision (iterative refinement, [`crate::backend::Backend::refines`]; 0 in f64),
    /// counted like `matvecs`.
    pub exact_matvecs: usize,
    /// Applications of the preconditioner (an approximate inverse of the
    /// operator, [`crate::backend::Backend::precondition`]), counted like `matvecs`.
    pub preconditioner_applications: usize,
    /// Per grid of a cascade, coarse to fine (empty for a single grid).
    pub levels: Vec<LevelInfo>,
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
    #[error("no convergence after {iterations} iterations and {matvecs} matvecs: residual {residual:.3e}{cause} (history: {history:?})")]
    NoConvergence {
        iterations: usize,
        matvecs: usize,
        residual: f64,
        history: Vec<f64>,
        /// Why, where known (`""` otherwise): `"; ..."`.
        cause: String,
    },
    #[error("invalid problem: {0}")]
    Invalid(String),
    /// The observer asked to stop ([`Observer::cancelled`]); nothing of the
    /// solve is kept.
    #[error("the solve was cancelled")]
    Cancelled,
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

/// Something that wants to hear about progress, and may stop a solve.
pub trait Observer {
    /// After every outer (active-set) iteration.
    fn iteration(
        &mut self,
        _iteration: usize,
        _matvecs: usize,
        _residual: f64,
        _contact_cells: usize,
    ) {
    }

    /// When work above the solver enters a new stage (a heated solve's
    /// evaluation: its isothermal solve, its heat source, its rise):
    /// `label` says which, in words, for a progress line. The iterations
    /// that follow belong to it. Default: nothing.
    fn stage(&mut self, _label: &str) {}

    /// Polled before every application of the operator (each inner Krylov
    /// step) and every outer iteration: `true` stops the solve with
    /// [`SolverError::Cancelled`]. Called often (milliseconds apart on large
    /// grids), so it must be cheap: look at a flag or a clock. Default:
    /// never.
    fn cancelled(&mut self) -> bool {
        false
    }
}

/// An observer that ignores everything.
pub struct Silent;
impl Observer for Silent {}

/// One contact problem as the solver takes it (physics.md section 4): the
/// gap profile `g >= 0` \[m\] (one value per cell, in the backend's cell
/// order; borrowed, or owned to become the iteration's vector without a
/// copy), the cell area \[m^2\] of the load constraint, `L_00` (the
/// displacement of a cell under unit pressure on itself \[m/Pa\], which
/// scales gaps into pressures) and what is prescribed.
#[derive(Debug, Clone, PartialEq)]
pub struct ContactProblem<'a> {
    pub gap: Cow<'a, [f64]>,
    pub cell_area: f64,
    pub self_coefficient: f64,
    pub control: Control,
}

impl<'a> ContactProblem<'a> {
    /// The problem of `gap` on cells of area `cell_area` with `L_00 =
    /// self_coefficient`, under `control`.
    pub fn new(
        gap: impl Into<Cow<'a, [f64]>>,
        cell_area: f64,
        self_coefficient: f64,
        control: Control,
    ) -> Self {
        Self {
            gap: gap.into(),
            cell_area,
            self_coefficient,
            control,
        }
    }
}

/// A starting point for [`solve`]: a previous solution's contact set,
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

/// Smallest inner (GMRES) tolerance, in units of the backend's epsilon.
pub(crate) const INNER_FLOOR: f64 = 16.0;
/// Smallest outer (complementarity) tolerance, in units of the backend's
/// epsilon.
pub(crate) const OUTER_FLOOR: f64 = 128.0;
/// The outer test accepts a residual below this multiple of its rounding
/// floor `epsilon k |u| / |p|` (which grows with the grid side: the
/// displacement integrates the pressure over the patch, `k = 1 / L_00`
/// only over one cell). Far below the default tolerance in f64; in f32 it
/// is what can be reached (measured: 2.5e-5 on a 128 x 128 patch, where
/// `epsilon k |u| / |p|` is 3.2e-6).
pub(crate) const ROUNDING_FLOOR: f64 = 16.0;
/// A residual less than 1 % below the best so far counts as stagnant.
pub(crate) const STAGNATION: f64 = 0.99;

/// An outer iteration that lowers neither the best relative residual nor
/// the best merit `|min(p, k gap)|` by this factor counts towards a stall.
pub(crate) const STALL_GAIN: f64 = 0.9;
/// Consecutive such iterations after which the solve stops as stalled
/// (before the line search, the undamped iteration cycled on the periodic
/// formulation near full contact with `E_inf / E0 ~ 80`, residual flat at
/// 0.3-0.4 for 100,000 matvecs; kept as a guard against cycles it does not
/// break).
pub(crate) const STALL_ITERATIONS: usize = 15;
/// Outer iterations without gain (as for [`STALL_ITERATIONS`]) after which
/// the solve stops as stalled even though its inner solves converge: the
/// set cycles (cells entering and leaving in turn at a flat residual, each
/// inner solve exact on its set). Longer than [`STALL_ITERATIONS`], since a
/// converging iteration whose set is still far from the answer may keep a
/// flat residual for a few iterations while cells enter.
pub(crate) const STALL_CYCLES: usize = 40;
/// A stall is only declared above this residual (below, the floor logic
/// of the iteration takes over).
pub(crate) const STALL_ABOVE: f64 = 1e-3;
/// At the floor, the set may toggle at most one cell in this many (at least
/// one cell) per iteration.
pub(crate) const FLOOR_TOGGLES: usize = 1000;
/// A residual that fell by this factor or more in one outer iteration
/// while only a few cells moved: the set has (nearly) settled and the next
/// inner solve runs to the sharp tolerance.
pub(crate) const FAST_FALL: f64 = 0.1;
/// Stagnant outer iterations (inner solves at the floor, the set unchanged
/// or toggling a few cells) after which the residual is the arithmetic's
/// floor.
pub(crate) const STAGNANT_ITERATIONS: usize = 3;
/// Largest residual accepted at the floor (measured f32 floors: 5.8e-5 at
/// 512^2, 1.3e-4 at 1024^2); above it a stagnant solve is an error.
pub(crate) const STAGNANT_ACCEPT: f64 = 1e-3;
/// The Krylov space of the inner solves may grow to this many times
/// `SolverParams::restart` (doubling after each preconditioned solve that
/// misses its target within its budget; module `active_set`).
pub(crate) const RESTART_GROWTH: usize = 4;
/// GMRES restart cycles one preconditioned inner solve may take before the
/// next solve runs without the preconditioner (preconditioned inner solves
/// on the experiment take one or two cycles; module `inner_mode`).
pub(crate) const PRECONDITIONED_BUDGET: usize = 10;

/// `(outer, inner)` tolerances: the requested outer tolerance and
/// `0.01` of it for the inner solves, each clamped to what the backend's
/// arithmetic can reach (for f64 the defaults are far above the floors; f32
/// storage gives about `1.5e-5` and `1.9e-6`).
pub(crate) fn tolerances(tolerance: f64, epsilon: f64) -> (f64, f64) {
    let outer = tolerance.max(OUTER_FLOOR * epsilon);
    (outer, (0.01 * outer).max(INNER_FLOOR * epsilon))
}

pub(crate) fn check_problem(
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
        _ => check_scale(n, cell_area, self_coefficient, control),
    }
}

/// Sums of squares (and of products) of pressures and displacements over
/// the grid stay below this.
const SCALE_LIMIT: f64 = 1e300;
/// Squares of the largest pressure and displacement a cell can carry stay
/// above this: the mirror of [`SCALE_LIMIT`], as far inside f64's normal
/// range (from 2.2e-308) as that is inside its largest value.
const SCALE_FLOOR: f64 = 1.0 / SCALE_LIMIT;

/// Refuse a load or approach whose pressures and displacements, squared and
/// summed over the grid, leave double precision: the whole load on one
/// cell (`f / A`, its displacement `f K_00 / A`) or the whole approach on
/// one cell (`d`, its pressure `d / K_00`). Beyond it the iteration's norms
/// overflow: a NaN friction with exit 0, a residual NaN after the whole
/// matvec budget, or an empty contact set reported for a huge approach.
/// A positive load or approach so small that even those largest one-cell
/// values square below [`SCALE_FLOOR`] is refused too: there the squares
/// underflow, and the solve found no contact or reported friction and
/// loads rounded to zero.
fn check_scale(
    n: usize,
    cell_area: f64,
    self_coefficient: f64,
    control: Control,
) -> Result<(), SolverError> {
    let (p, w) = match control {
        Control::Load(f) => (f / cell_area, f / cell_area * self_coefficient),
        Control::Approach(d) => (d / self_coefficient, d),
    };
    let big = p.abs().max(w.abs());
    let small = p.abs().min(w.abs());
    let what = match control {
        Control::Load(f) => format!(
            "the normal load {f:e} N (a mean pressure of {:e} Pa)",
            f / (cell_area * n.max(1) as f64)
        ),
        Control::Approach(d) => format!("the approach {d:e} m"),
    };
    if big * big * n.max(1) as f64 > SCALE_LIMIT {
        return Err(SolverError::Invalid(format!(
            "{what} is beyond double precision on this grid: one cell would carry {p:.3e} Pa and move {w:.3e} m, whose squares summed over {n} cells overflow; lower it"
        )));
    }
    if small > 0.0 && small * small < SCALE_FLOOR {
        return Err(SolverError::Invalid(format!(
            "{what} is below double precision on this grid: even all of it on one cell would carry {p:.3e} Pa and move {w:.3e} m, whose squares underflow (below {SCALE_FLOOR:e}); raise it"
        )));
    }
    Ok(())
}
