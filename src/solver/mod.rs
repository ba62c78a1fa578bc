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
    /// Normal load `F_N` [N].
    Load(f64),
    /// Rigid approach `delta` [m].
    Approach(f64),
}

/// Parameters of [`solve`].
#[derive(Debug, Clone, PartialEq)]
pub struct SolverParams {
    /// Relative complementarity residual to reach (default 1e-8).
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
    /// Pressure [Pa] per cell.
    pub pressure: Vec<f64>,
    /// Surface displacement `u = L p` [m].
    pub displacement: Vec<f64>,
    /// `g - delta + u` [m].
    pub gap: Vec<f64>,
    /// 1 in contact, 0 elsewhere.
    pub contact: Vec<f64>,
    /// Rigid approach `delta` [m].
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

/// The bordered operator on the contact set.
struct Bordered<'a, V> {
    mask: &'a V,
    tmp_in: V,
    tmp_out: V,
    /// `delta = delta_scale * s`.
    delta_scale: f64,
    /// Load row scale.
    load_scale: f64,
    bordered: bool,
    matvecs: usize,
}

impl<B: Backend> AugOperator<B> for Bordered<'_, B::Vector> {
    fn apply(&mut self, backend: &mut B, x_v: &B::Vector, x_s: f64, y: &mut AugVec<B::Vector>) {
        backend.masked(self.mask, x_v, &mut self.tmp_in);
        backend.apply(&self.tmp_in, &mut self.tmp_out);
        self.matvecs += 1;
        backend.masked(self.mask, &self.tmp_out, &mut y.v);
        if self.bordered {
            backend.axpy(-self.delta_scale * x_s, self.mask, &mut y.v);
            y.s = self.load_scale * backend.sum(&self.tmp_in);
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
    let n = backend.len();
    if g.len() != n {
        return Err(SolverError::Invalid(format!(
            "gap has {} cells, grid has {n}",
            g.len()
        )));
    }
    if !(cell_area > 0.0 && self_coefficient > 0.0) {
        return Err(SolverError::Invalid(
            "cell area and self coefficient must be positive".into(),
        ));
    }
    match control {
        Control::Load(f) if !(f.is_finite() && f > 0.0) => {
            return Err(SolverError::Invalid(format!(
                "normal load {f} N must be positive"
            )))
        }
        Control::Approach(d) if !d.is_finite() => {
            return Err(SolverError::Invalid(format!(
                "approach {d} m must be finite"
            )))
        }
        _ => {}
    }
    let stiffness = 1.0 / self_coefficient;
    let tight = 0.01 * params.tolerance;
    let loose = 1e-4_f64.max(tight);

    // Initial contact set.
    let mut host_mask = vec![0.0; n];
    let (delta0, p0) = initial_guess(g, cell_area, self_coefficient, control, &mut host_mask);
    let mut mask = backend.zeros();
    backend.upload(&host_mask, &mut mask);
    let mut gv = backend.zeros();
    backend.upload(g, &mut gv);
    let mut p = AugVec {
        v: backend.zeros(),
        s: 0.0,
    };
    let mut host = vec![0.0; n];
    for (h, m) in host.iter_mut().zip(&host_mask) {
        *h = p0 * m;
    }
    backend.upload(&host, &mut p.v);

    let bordered = matches!(control, Control::Load(_));
    let delta_scale = self_coefficient;
    p.s = delta0 / delta_scale;
    let mut work = GmresWork::new(backend, params.restart);
    let mut rhs = AugVec {
        v: backend.zeros(),
        s: 0.0,
    };
    let mut u = backend.zeros();
    let mut gap = backend.zeros();
    let mut tmp_in = backend.zeros();
    let mut tmp_out = backend.zeros();

    let mut matvecs = 0usize;
    let mut history = Vec::new();
    let mut contact_history = Vec::new();
    let mut contact_cells = host_mask.iter().filter(|&&m| m > 0.5).count();
    let mut last_changes = usize::MAX;
    let mut residual = f64::INFINITY;
    for iteration in 1..=params.max_iterations {
        let inner_tol = if last_changes <= (contact_cells / 200).max(1) {
            tight
        } else {
            loose
        };
        let m = contact_cells.max(1) as f64;
        let load_scale = self_coefficient / m.sqrt();
        // rhs = (mask * (delta - g) or -mask*g, load row)
        backend.masked(&mask, &gv, &mut rhs.v);
        backend.scale(-1.0, &mut rhs.v);
        match control {
            Control::Load(f) => rhs.s = load_scale * f / cell_area,
            Control::Approach(d) => {
                backend.axpy(d, &mask, &mut rhs.v);
                rhs.s = 0.0;
            }
        }
        let mut op = Bordered {
            mask: &mask,
            tmp_in,
            tmp_out,
            delta_scale,
            load_scale,
            bordered,
            matvecs: 0,
        };
        // Warm start: restrict the previous pressure to the new set.
        backend.masked(&mask, &p.v, &mut u);
        backend.copy(&u, &mut p.v);
        let budget = params.max_matvecs.saturating_sub(matvecs).max(1);
        let outcome = gmres(backend, &mut op, &rhs, &mut p, &mut work, inner_tol, budget);
        matvecs += op.matvecs;
        tmp_in = op.tmp_in;
        tmp_out = op.tmp_out;
        let delta = match control {
            Control::Load(_) => p.s * delta_scale,
            Control::Approach(d) => d,
        };
        // Gap everywhere.
        backend.masked(&mask, &p.v, &mut tmp_in);
        backend.copy(&tmp_in, &mut p.v);
        backend.apply(&p.v, &mut u);
        matvecs += 1;
        backend.gap(&gv, &u, delta, &mut gap);
        let (r2, p2) = backend.complementarity(&p.v, &gap, stiffness);
        residual = if p2 > 0.0 {
            (r2 / p2).sqrt()
        } else {
            f64::INFINITY
        };
        let (changes, size) = backend.update_active_set(&p.v, &gap, &mut mask);
        history.push(residual);
        contact_history.push(size);
        observer.iteration(iteration, matvecs, residual, size);
        if changes == 0 && inner_tol == tight && outcome.converged && residual <= params.tolerance {
            let load_error = match control {
                Control::Load(f) => (cell_area * backend.sum(&p.v) - f).abs() / f,
                Control::Approach(_) => 0.0,
            };
            let mut pressure = vec![0.0; n];
            backend.download(&p.v, &mut pressure);
            let mut displacement = vec![0.0; n];
            backend.download(&u, &mut displacement);
            let mut gap_h = vec![0.0; n];
            backend.download(&gap, &mut gap_h);
            let mut contact = vec![0.0; n];
            backend.download(&mask, &mut contact);
            return Ok((
                ContactSolution {
                    pressure,
                    displacement,
                    gap: gap_h,
                    contact,
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
        if size == 0 {
            return Err(SolverError::Invalid(
                "the contact set became empty: under approach control the surfaces do not touch"
                    .into(),
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
    let n = backend.len();
    if g.len() != n {
        return Err(SolverError::Invalid(format!(
            "gap has {} cells, grid has {n}",
            g.len()
        )));
    }
    let mut mask = backend.zeros();
    backend.upload(&vec![1.0; n], &mut mask);
    let mut gv = backend.zeros();
    backend.upload(g, &mut gv);
    let bordered = matches!(control, Control::Load(_));
    let load_scale = self_coefficient / (n as f64).sqrt();
    let mut rhs = AugVec {
        v: backend.zeros(),
        s: 0.0,
    };
    backend.copy(&gv, &mut rhs.v);
    backend.scale(-1.0, &mut rhs.v);
    match control {
        Control::Load(f) => rhs.s = load_scale * f / cell_area,
        Control::Approach(d) => backend.axpy(d, &mask, &mut rhs.v),
    }
    let mut op = Bordered {
        mask: &mask,
        tmp_in: backend.zeros(),
        tmp_out: backend.zeros(),
        delta_scale: self_coefficient,
        load_scale,
        bordered,
        matvecs: 0,
    };
    let mut p = AugVec {
        v: backend.zeros(),
        s: 0.0,
    };
    let mut work = GmresWork::new(backend, params.restart);
    let outcome = gmres(
        backend,
        &mut op,
        &rhs,
        &mut p,
        &mut work,
        0.01 * params.tolerance,
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
    let mut u = backend.zeros();
    backend.apply(&p.v, &mut u);
    matvecs += 1;
    let mut gap = backend.zeros();
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

/// Initial contact set and pressure: the cells with the smallest gap, as
/// many as the linear area-load law (paper Eq. 10, `A/A0 ~ 2 p0 / (E* m)`,
/// here with the cell stiffness standing in for `E*/m`) suggests.
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
            // Pressure that closes the typical gap spread on one cell.
            let spread = (sorted[n / 2] - sorted[0]).max(f64::MIN_POSITIVE);
            let p_close = spread / l00;
            let mean_p = f / (cell_area * n as f64);
            ((2.0 * mean_p / p_close * n as f64).ceil() as usize).clamp(1, n.div_ceil(2))
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
