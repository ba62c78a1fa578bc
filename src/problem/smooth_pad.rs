//! The finite pad's own friction: the same pad without roughness, pressed
//! by the same load at the same speed (docs/periodic-vs-nonperiodic.md,
//! "A finite pad's own edge").
//!
//! A rigid pad of finite size sliding on a viscoelastic half-space
//! dissipates at its own edges even when it is perfectly flat: the
//! pressure under a flat punch is singular at its rim (paper Eq. 6-7 with
//! `g = 0`), and the rim's hysteresis gives a friction that does not
//! depend on the roughness. A rubber block on a large rough plate has no
//! such rim. The flat pad's pressure comes from the constrained iteration
//! ([`crate::solver::solve`]) from its bearing-area start (every cell in
//! contact at the mean pressure) on the executor of the rough solve (the
//! CPU: in f64 with the Toeplitz operator and preconditioner, whatever the
//! rough solve's precision; the GPU: in f32 on the device, refined in f64
//! on the host from the device's answer where the rough solve is,
//! [`super::gpu_refine`]), and its friction from the same work-of-pressure
//! route as the rough solve's (Eq. 9).
//!
//! One linear solve of the bordered system in full contact
//! ([`crate::solver::solve_full_contact`]) is not used: its single Krylov
//! solve to the full tolerance converges slowly on the rim's singular
//! pressure, and the sliding pad's trailing rim lifts off, which the
//! constrained iteration then has to undo. Measured with `--backend cpu`
//! on the paper experiment at 512^2: 370 matvecs without converging, then
//! 101 constrained, against 101 constrained alone (the same friction to
//! 2e-14); `configs/default.toml` at 0.3 and 30 N: 86 against 52;
//! `configs/sphere_sliding.toml`: 149 against 59.

use std::time::Instant;

use serde::Serialize;

use crate::backend::Backend;
use crate::error::Result;
use crate::solver::{self, Control, Silent};

use crate::operator::OperatorDescription;

use super::executor::{CpuExecutor, Executes};
use super::Problem;

/// A pad whose own part is above this share of the friction is warned
/// about.
pub(crate) const SMOOTH_PAD_SHARE_LIMIT: f64 = 0.1;

/// The smooth-pad solve's matvec budget is at least this.
const SMOOTH_PAD_MIN_MATVECS: usize = 300;

/// The relative tolerance of the flat pad's solve in f32 (on a device):
/// its Krylov solves then aim at 1e-3 (0.01 of it). The f32 GMRES over a
/// flat pad's (nearly full) contact set stalls far above the rough solve's inner floor (16
/// epsilon, 1.9e-6): at 1e-5 it burnt the 300-matvec budget without
/// converging on `configs/default.toml` at 128^2 on lavapipe (it reached
/// it at 64^2), and its floor grows with the grid side. The device's
/// answer is then a start: the host refinement, where it follows, takes it
/// to the problem's tolerance; without one it is the f32 answer.
const F32_TOLERANCE: f64 = 0.1;

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
    /// over; the host refinement's included).
    pub matvecs: usize,
    /// Of `matvecs`, those in f64 on the host after a device's stage: its
    /// refinement, or the whole solve where the device's did not converge
    /// (0 on the CPU, where the whole solve is the host's own).
    pub host_refinement_matvecs: usize,
    /// Wall time \[s\], coefficient tables included.
    pub time_s: f64,
}

impl Problem {
    /// The flat pad of this non-periodic problem under the normal load
    /// `load` \[N\] on `executor` (then refined in f64 on the host where
    /// its precision is ([`Executes::refined_on_host`])), and the split of the rough solve's friction `mu` into
    /// the pad's part and the roughness part. At most
    /// `max(SMOOTH_PAD_MIN_MATVECS, 3 rough_matvecs)` operator applications
    /// per stage, so that a flat pad the iteration struggles with (a layer
    /// on the thin-layer law takes no preconditioner) costs at most a few
    /// rough solves; an error then, which the caller reports instead of
    /// failing.
    pub(super) fn smooth_pad<X: Executes>(
        &self,
        executor: &mut X,
        load: f64,
        mu: f64,
        rough_matvecs: usize,
    ) -> Result<SmoothPad> {
        let t = Instant::now();
        let (nx, ny, (ax, ay)) = (self.surface.nx, self.surface.ny, self.surface.cell());
        let kernel = self.sliding_kernel()?;
        let description = OperatorDescription::Toeplitz {
            kernel: &kernel,
            grid: self.grid()?,
        };
        let params = solver::SolverParams {
            max_matvecs: SMOOTH_PAD_MIN_MATVECS.max(3 * rough_matvecs),
            ..self.solver_params()
        };
        let (mut backend, l00) = executor.build(&description, None)?;
        let flat = vec![0.0; nx * ny];
        let problem = solver::ContactProblem::new(&flat, ax * ay, l00, Control::Load(load));
        // A backend whose vectors are f32 (`Backend::epsilon` above f64's:
        // a device) solves to `F32_TOLERANCE`.
        let device = backend.epsilon() > f64::EPSILON;
        let stage_params = solver::SolverParams {
            tolerance: if device {
                params.tolerance.max(F32_TOLERANCE)
            } else {
                params.tolerance
            },
            ..params.clone()
        };
        let pad = flat_pad(&mut backend, &problem, &stage_params);
        executor.release(backend);
        let refine = executor.refined_on_host();
        // The host's f64 Toeplitz backend: for the refinement of a
        // device's answer, or the whole solve where the device's did not
        // converge.
        let host = || CpuExecutor::<f64>::new().build(&description, None);
        let (solution, matvecs, host_refinement_matvecs) = match pad {
            Ok((solution, matvecs)) if refine => {
                // The device's f32 answer starts the f64 constrained
                // iteration on the host.
                let (mut host, l00) = host()?;
                let low = solver::SolveInfo {
                    matvecs,
                    ..Default::default()
                };
                let refined = solver::refine(
                    &mut host,
                    solver::ContactProblem {
                        self_coefficient: l00,
                        ..problem
                    },
                    &params,
                    (solution, low),
                    &mut Silent,
                )?;
                (
                    refined.solution,
                    refined.info.matvecs,
                    refined.stage.matvecs,
                )
            }
            Ok((solution, matvecs)) => (solution, matvecs, 0),
            Err(_) if device => {
                let (mut host, l00) = host()?;
                let problem = solver::ContactProblem {
                    self_coefficient: l00,
                    ..problem
                };
                let (s, m) = flat_pad(&mut host, &problem, &params)?;
                (s, m, m)
            }
            Err(e) => return Err(e),
        };
        let force = self.friction_force_eq9(&kernel, &solution.pressure)?;
        let loaded: f64 = solution.pressure.iter().sum::<f64>() * ax * ay;
        let smooth = -force / loaded;
        Ok(SmoothPad {
            friction_coefficient: smooth,
            roughness_friction_coefficient: mu - smooth,
            share: if mu != 0.0 { smooth / mu } else { 0.0 },
            matvecs,
            host_refinement_matvecs,
            time_s: t.elapsed().as_secs_f64(),
        })
    }
}

/// The flat pad's pressure on `backend` by the constrained iteration from
/// its bearing-area start, and its matvecs.
fn flat_pad<B: Backend>(
    backend: &mut B,
    problem: &solver::ContactProblem<'_>,
    params: &solver::SolverParams,
) -> Result<(solver::ContactSolution, usize)> {
    let (s, i) = solver::solve(backend, problem.clone(), params, None, &mut Silent)?;
    Ok((s, i.matvecs))
}
