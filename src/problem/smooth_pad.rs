//! The finite pad's own friction: the same pad without roughness, pressed
//! by the same load at the same speed (docs/periodic-vs-nonperiodic.md,
//! "A finite pad's own edge").
//!
//! A rigid pad of finite size sliding on a viscoelastic half-space
//! dissipates at its own edges even when it is perfectly flat: the
//! pressure under a flat punch is singular at its rim (paper Eq. 6-7 with
//! `g = 0`), and the rim's hysteresis gives a friction that does not
//! depend on the roughness. A rubber block on a large rough plate has no
//! such rim. The flat pad is in full contact, so its pressure comes from
//! one linear solve of the bordered system on the whole grid
//! ([`crate::solver::solve_full_contact`]) in f64 on the host (the CPU
//! path's Toeplitz operator and preconditioner), and its friction from the
//! same work-of-pressure route as the rough solve's (Eq. 9).

use std::time::Instant;

use serde::Serialize;

use crate::error::Result;
use crate::solver::{self, Control, Silent};

use crate::operator::OperatorDescription;

use super::executor::{CpuExecutor, Executes};
use super::Problem;

/// A pad whose own part is above this share of the friction is warned
/// about.
pub const SMOOTH_PAD_SHARE_LIMIT: f64 = 0.1;

/// The smooth-pad solve's matvec budget is at least this.
const SMOOTH_PAD_MIN_MATVECS: usize = 300;

/// The flat pad's solve and friction.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SmoothPad {
    /// `mu` of the flat pad at the rough solve's load and speed (Eq. 9).
    pub friction_coefficient: f64,
    /// The rough solve's `mu` less the flat pad's: the roughness part.
    pub roughness_friction_coefficient: f64,
    /// The flat pad's share of the rough solve's `mu`.
    pub share: f64,
    /// Operator applications (both solves when the full-contact one handed
    /// over).
    pub matvecs: usize,
    /// `"full_contact"` (one linear solve) or `"constrained"` (the
    /// constrained iteration took over).
    pub method: &'static str,
    /// Wall time \[s\], coefficient tables included.
    pub time_s: f64,
}

impl Problem {
    /// The flat pad of this non-periodic problem under the normal load
    /// `load` \[N\], and the split of the rough solve's friction `mu` into
    /// the pad's part and the roughness part. At most
    /// `max(SMOOTH_PAD_MIN_MATVECS, 3 rough_matvecs)` operator applications,
    /// so that a flat pad the iteration struggles with (a layer on the
    /// thin-layer law takes no preconditioner) costs at most a few rough
    /// solves; an error then, which the caller reports instead of failing.
    pub(super) fn smooth_pad(&self, load: f64, mu: f64, rough_matvecs: usize) -> Result<SmoothPad> {
        let t = Instant::now();
        let (nx, ny, (ax, ay)) = (self.surface.nx, self.surface.ny, self.surface.cell());
        let kernel = self.sliding_kernel()?;
        let description = OperatorDescription::Toeplitz {
            kernel: &kernel,
            grid: self.grid()?,
        };
        let (mut backend, l00) = CpuExecutor::<f64>::new().build(&description, None)?;
        let flat = vec![0.0; nx * ny];
        let params = solver::SolverParams {
            max_matvecs: SMOOTH_PAD_MIN_MATVECS.max(3 * rough_matvecs),
            ..self.solver_params()
        };
        // One linear solve in full contact; a pressure negative somewhere
        // (a rim lifting off), or no convergence within the budget (an
        // unpreconditioned operator), hands over to the constrained
        // iteration, whose inexact Newton steps converge where one Krylov
        // solve at the full tolerance stalls.
        let full = solver::solve_full_contact(
            &mut backend,
            &solver::ContactProblem::new(&flat, ax * ay, l00, Control::Load(load)),
            &params,
        );
        let spent = match &full {
            Ok((_, i)) => i.matvecs,
            Err(solver::SolverError::NoConvergence { matvecs, .. }) => *matvecs,
            Err(_) => 0,
        };
        let (solution, matvecs, method) = match full {
            Ok((s, i)) if s.pressure.iter().all(|&p| p >= 0.0) => (s, i.matvecs, "full_contact"),
            _ => {
                let (s, i) = solver::solve(
                    &mut backend,
                    solver::ContactProblem::new(&flat, ax * ay, l00, Control::Load(load)),
                    &params,
                    None,
                    &mut Silent,
                )?;
                (s, spent + i.matvecs, "constrained")
            }
        };
        drop(backend);
        let force = self.friction_force_eq9(&kernel, &solution.pressure)?;
        let loaded: f64 = solution.pressure.iter().sum::<f64>() * ax * ay;
        let smooth = -force / loaded;
        Ok(SmoothPad {
            friction_coefficient: smooth,
            roughness_friction_coefficient: mu - smooth,
            share: if mu != 0.0 { smooth / mu } else { 0.0 },
            matvecs,
            method,
            time_s: t.elapsed().as_secs_f64(),
        })
    }
}
