//! The full-contact solve: one linear solve of the bordered system on the
//! whole grid, no sign constraint.

use super::active_set::Bordered;
use super::gmres::{gmres, AugVec, GmresWork};
use super::{
    check_problem, tolerances, ContactProblem, ContactSolution, Control, SolveInfo, SolverError,
    SolverParams,
};
use crate::backend::Backend;

/// Full contact: the pressure that keeps every cell in contact, from one
/// linear solve of the bordered system on the whole grid (no sign
/// constraint), right-preconditioned by the backend's preconditioner when
/// `params.precondition`. Physical when every pressure comes out positive; with
/// `Control::Load(0.0)` it gives the pure response to the profile `g`.
pub fn solve_full_contact<B: Backend>(
    backend: &mut B,
    problem: &ContactProblem<'_>,
    params: &SolverParams,
) -> Result<(ContactSolution, SolveInfo), SolverError> {
    let (g, cell_area, self_coefficient, control) = (
        &problem.gap[..],
        problem.cell_area,
        problem.self_coefficient,
        problem.control,
    );
    let n = backend.grid_len();
    check_problem(g, n, cell_area, self_coefficient, control)?;
    let mask = backend.mask_from(&vec![1.0; n]);
    let index = backend.index_of(&mask);
    drop(mask);
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
    let mut op = Bordered::new(
        backend,
        &index,
        self_coefficient,
        load_scale,
        bordered,
        params.precondition,
    );
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
        0.0,
        params.max_matvecs,
        &mut super::Silent,
    );
    let mut matvecs = op.matvecs;
    if !outcome.converged {
        return Err(SolverError::NoConvergence {
            iterations: 1,
            matvecs,
            residual: f64::NAN,
            history: vec![],
            cause: String::new(),
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
            preconditioner_applications: 0,
            exact_matvecs: 0,
            levels: Vec::new(),
            residual,
            load_error,
            history: vec![residual],
            contact_history: vec![n],
        },
    ))
}
