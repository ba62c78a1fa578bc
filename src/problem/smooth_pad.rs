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
//! as the rough solve's coarse-to-fine cascade ([`crate::solver::solve_cascade`];
//! the flat gap is zero on every grid) from its bearing-area start (every
//! cell of the coarsest grid in contact at the mean pressure) on the
//! executor of the rough solve (the CPU: in f64 with the Toeplitz operator
//! and preconditioner, whatever the rough solve's precision; a GPU: in the
//! rough solve's precision, mixed (f32 products on the device, f64
//! residuals on the host: the f64 answer) or f32 on the device alone), and
//! its friction
//! from the same work-of-pressure route as the rough solve's (Eq. 9), with
//! the rough solve's derivative operators (built once for both).
//!
//! One linear solve of the bordered system in full contact
//! ([`crate::solver::solve_full_contact`]) is not used: its single Krylov
//! solve to the full tolerance converges slowly on the rim's singular
//! pressure, and the sliding pad's trailing rim lifts off, which the
//! constrained iteration then has to undo. Measured with `--backend cpu`
//! on the paper experiment at 512^2: 370 matvecs without converging, then
//! 101 constrained, against 101 constrained alone (the same friction to
//! 2e-14); `configs/default.toml` at 0.3 and 30 N: 86 against 52. The
//! cascade: at 2048^2, 145 fine-grid-equivalent matvecs against 367 on one
//! grid (BENCHMARKS.md, "Real GPU"); at 256^2 63 against 52.

use std::time::Instant;

use serde::Serialize;

use crate::error::Result;
use crate::solver::{self, Control, Silent};

use super::cascade::{cascade_of, CASCADE_COARSEST};
use super::executor::{CpuExecutor, DeviceTraffic, Executes};
use super::solve::UniformOperators;
use super::Problem;

/// A pad whose own part is above this share of the friction is warned
/// about.
pub(crate) const SMOOTH_PAD_SHARE_LIMIT: f64 = 0.1;

/// The smooth-pad solve's matvec budget is at least this.
const SMOOTH_PAD_MIN_MATVECS: usize = 300;

/// The smooth-pad solve's budget in the rough solve's matvecs, with a
/// preconditioner.
const SMOOTH_PAD_PER_ROUGH: usize = 3;

/// The same without one (the thin-layer law, or `solver.precondition =
/// false`): plain GMRES on the pad's full contact takes 1.7-7.1 times the
/// rough solve's matvecs on bonded 64^2 pads inside the thin-layer band
/// (214-498 against 37-136, h = a/10 to a/2, 0-45 deg), where the rough
/// solve's few contact cells need few; 3 left some of them unanswered.
const SMOOTH_PAD_PER_ROUGH_PLAIN: usize = 10;

/// The relative tolerance of the flat pad's solve with f32 vectors (a
/// device's f32 iteration):
/// its Krylov solves then aim at 1e-3 (0.01 of it). Tighter, the f32 inner
/// solves over a flat pad's (nearly full) contact set reach their rounding
/// floor before their target and burn the matvec budget: on the paper
/// experiment's pad at 256^2 (q1 = 1.5e6 1/m, lavapipe) 0.1 took 50 device
/// and 41 host matvecs, 1e-2 85 and 34, 1e-3 ran out at a residual of
/// 7.9e-6 (and the host solved the pad from scratch). Those measurements
/// were of the f32 stage that the host refined in f64; the mixed
/// iteration has f64 vectors and solves to the problem's tolerance.
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
    /// Operator applications (fine-grid equivalent) of the solve that gave
    /// the answer.
    pub matvecs: usize,
    /// Of its products, those in f64 beside `matvecs` (the residuals of a
    /// mixed-precision iteration, physics.md section 13; 0 in f64 or f32).
    pub exact_matvecs: usize,
    /// Of `matvecs`, those of a solve in f64 on the host where the
    /// device's did not converge (0 otherwise, and on the CPU).
    pub host_matvecs: usize,
    /// Wall time \[s\] of its solve, coefficient tables included (its Eq. 9
    /// friction is the rough solve's analysis's, which shares its
    /// operators).
    pub time_s: f64,
    /// Its products' device round trips (a GPU's mixed precision).
    pub device_traffic: Option<DeviceTraffic>,
}

/// The flat pad solved, its friction not yet taken.
pub(super) struct SolvedPad {
    /// Pressure on the grid \[Pa\].
    pub pressure: Vec<f64>,
    /// The load it carries \[N\] (its pressure times the cell area).
    loaded: f64,
    matvecs: usize,
    exact_matvecs: usize,
    host_matvecs: usize,
    time_s: f64,
    device_traffic: Option<DeviceTraffic>,
}

impl SolvedPad {
    /// The split of the rough solve's friction `mu` with the pad's Eq. 9
    /// friction force `force` \[N\].
    pub(super) fn with_force(self, force: f64, mu: f64) -> SmoothPad {
        let smooth = -force / self.loaded;
        SmoothPad {
            friction_coefficient: smooth,
            roughness_friction_coefficient: mu - smooth,
            share: if mu != 0.0 { smooth / mu } else { 0.0 },
            matvecs: self.matvecs,
            exact_matvecs: self.exact_matvecs,
            host_matvecs: self.host_matvecs,
            time_s: self.time_s,
            device_traffic: self.device_traffic,
        }
    }
}

impl Problem {
    /// The flat pad of this non-periodic problem under the normal load
    /// `load` \[N\] on `executor` (in its precision; solved again in f64
    /// on the host where a device's solve does not converge,
    /// [`Executes::on_device`]). At most
    /// `max(SMOOTH_PAD_MIN_MATVECS, k rough_matvecs)` operator applications
    /// per solve (`k` = [`SMOOTH_PAD_PER_ROUGH`], or
    /// [`SMOOTH_PAD_PER_ROUGH_PLAIN`] without a preconditioner), so that a
    /// flat pad the iteration struggles with costs at most a few rough
    /// solves; an error then, which the caller reports instead of failing.
    pub(super) fn smooth_pad<X: Executes>(
        &self,
        executor: &mut X,
        load: f64,
        rough_matvecs: usize,
    ) -> Result<SolvedPad> {
        let t = Instant::now();
        let traffic_before = executor.device_traffic();
        let (nx, ny, (ax, ay)) = (self.surface.nx, self.surface.ny, self.surface.cell());
        let kernel = self.sliding_kernel()?;
        let operators = UniformOperators::Toeplitz(kernel);
        let base = self.solver_params();
        let per_rough = if base.precondition {
            SMOOTH_PAD_PER_ROUGH
        } else {
            SMOOTH_PAD_PER_ROUGH_PLAIN
        };
        let params = solver::SolverParams {
            max_matvecs: SMOOTH_PAD_MIN_MATVECS.max(per_rough * rough_matvecs),
            ..base
        };
        // An executor whose vectors are f32 (a device's f32 iteration)
        // solves to `F32_TOLERANCE`.
        let device = executor.epsilon() > f64::EPSILON;
        let stage_params = solver::SolverParams {
            tolerance: if device {
                params.tolerance.max(F32_TOLERANCE)
            } else {
                params.tolerance
            },
            ..params.clone()
        };
        let shapes = solver::cascade::cascade_shapes(nx, ny, CASCADE_COARSEST, self.cascade_levels);
        let pad = flat_cascade(executor, &operators, &shapes, (ax, ay), load, &stage_params);
        let (solution, info, host_matvecs) = match pad {
            Ok((solution, info)) => (solution, info, 0),
            Err(_) if executor.on_device() => {
                // The device's solve did not converge: the host's, in f64.
                let mut host = CpuExecutor::<f64>::new();
                let (s, info) =
                    flat_cascade(&mut host, &operators, &shapes, (ax, ay), load, &params)?;
                let matvecs = info.matvecs;
                (s, info, matvecs)
            }
            Err(e) => return Err(e),
        };
        Ok(SolvedPad {
            loaded: solution.pressure.iter().sum::<f64>() * ax * ay,
            pressure: solution.pressure,
            matvecs: info.matvecs,
            exact_matvecs: info.exact_matvecs,
            host_matvecs,
            time_s: t.elapsed().as_secs_f64(),
            device_traffic: executor
                .device_traffic()
                .zip(traffic_before)
                .map(|(now, before)| now.since(&before)),
        })
    }
}

/// The flat pad's pressure on `executor`'s backends by the constrained
/// iteration as the rough solve's coarse-to-fine cascade over `shapes`
/// ([`cascade_of`], the gap zero on every grid), from the coarsest grid's
/// bearing-area start; returns the fine grid's solution and the report
/// (fine-grid-equivalent matvecs).
fn flat_cascade<X: Executes>(
    executor: &mut X,
    operators: &UniformOperators,
    shapes: &[(usize, usize)],
    cell: (f64, f64),
    load: f64,
    params: &solver::SolverParams,
) -> Result<(solver::ContactSolution, solver::SolveInfo)> {
    let &(nx, ny) = shapes.last().expect("the fine grid");
    Ok(cascade_of(
        shapes,
        cell,
        vec![0.0; nx * ny],
        Control::Load(load),
        params,
        &mut Silent,
        |lx, ly, cell| executor.build(&operators.on(lx, ly, cell)?, None),
    )??)
}
