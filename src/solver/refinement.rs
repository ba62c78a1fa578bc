//! Iterative refinement by a second iteration (physics.md section 13): a
//! low-precision answer (an f32 iteration on a device, at its rounding floor)
//! warm-starts the same constrained problem on a backend with f64 products,
//! which reaches the requested tolerance in a few outer iterations from its
//! contact set, pressure and approach. The CPU's mixed precision refines
//! within one iteration instead (every GMRES restart's residual in f64,
//! [`crate::backend::Backend::refines`]); this is the form for an executor
//! without f64 products of its own.

use crate::backend::Backend;

use super::{
    solve, ContactProblem, ContactSolution, Observer, SolveInfo, SolverError, SolverParams,
    WarmStart,
};

/// A refined answer: the f64 solution, the report of both stages combined
/// ([`SolveInfo::followed_by`]) and the f64 stage's own.
#[derive(Debug, Clone)]
pub(crate) struct Refined {
    pub(crate) solution: ContactSolution,
    pub(crate) info: SolveInfo,
    pub(crate) stage: SolveInfo,
}

/// Refine the low-precision answer `low` (its solution and report) of
/// `problem` on `backend`, whose products are f64 ([`Backend::epsilon`]; a
/// backend in a lower precision is refused), to the tolerance of `params`.
pub(crate) fn refine<B: Backend>(
    backend: &mut B,
    problem: ContactProblem<'_>,
    params: &SolverParams,
    low: (ContactSolution, SolveInfo),
    observer: &mut dyn Observer,
) -> Result<Refined, SolverError> {
    if backend.epsilon() > f64::EPSILON {
        return Err(SolverError::Invalid(format!(
            "the refinement needs f64 products, {} rounds to {:.1e}",
            backend.name(),
            backend.epsilon()
        )));
    }
    let (solution, info) = low;
    let start = WarmStart {
        contact: solution.contact,
        pressure: solution.pressure,
        approach: solution.approach,
    };
    let (solution, stage) = solve(backend, problem, params, Some(start), observer)?;
    Ok(Refined {
        solution,
        info: info.followed_by(&stage),
        stage,
    })
}

impl SolveInfo {
    /// This report followed by the refinement stage `next`: iterations and
    /// every product count summed, the residual and load error of `next`,
    /// the histories one after the other, this report's cascade levels.
    pub(crate) fn followed_by(self, next: &SolveInfo) -> SolveInfo {
        SolveInfo {
            iterations: self.iterations + next.iterations,
            matvecs: self.matvecs + next.matvecs,
            preconditioner_applications: self.preconditioner_applications
                + next.preconditioner_applications,
            exact_matvecs: self.exact_matvecs + next.exact_matvecs,
            levels: self.levels,
            residual: next.residual,
            load_error: next.load_error,
            history: self
                .history
                .into_iter()
                .chain(next.history.iter().copied())
                .collect(),
            contact_history: self
                .contact_history
                .into_iter()
                .chain(next.contact_history.iter().copied())
                .collect(),
        }
    }
}
