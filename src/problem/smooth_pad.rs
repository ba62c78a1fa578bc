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

use super::executor::toeplitz_backend;
use super::Problem;

/// A pad whose own part is above this share of the friction is warned
/// about.
pub const SMOOTH_PAD_SHARE_LIMIT: f64 = 0.1;

/// The flat pad's solve and friction.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SmoothPad {
    /// `mu` of the flat pad at the rough solve's load and speed (Eq. 9).
    pub friction_coefficient: f64,
    /// The rough solve's `mu` less the flat pad's: the roughness part.
    pub roughness_friction_coefficient: f64,
    /// The flat pad's share of the rough solve's `mu`.
    pub share: f64,
    /// Operator applications of the full-contact solve.
    pub matvecs: usize,
    /// Wall time \[s\], coefficient tables included.
    pub time_s: f64,
}

impl Problem {
    /// The flat pad of this non-periodic problem under the normal load
    /// `load` \[N\], and the split of the rough solve's friction `mu` into
    /// the pad's part and the roughness part.
    pub(super) fn smooth_pad(&self, load: f64, mu: f64) -> Result<SmoothPad> {
        let t = Instant::now();
        let (nx, ny, (ax, ay)) = (self.surface.nx, self.surface.ny, self.surface.cell());
        let kernel = self.sliding_kernel()?;
        let table = kernel.table_rect(nx, ny, ax, ay);
        let (mut backend, l00) = toeplitz_backend::<f64>(nx, ny, &table.values);
        drop(table);
        let flat = vec![0.0; nx * ny];
        let params = self.solver_params();
        let (mut solution, mut info) = solver::solve_full_contact(
            &mut backend,
            &flat,
            ax * ay,
            l00,
            Control::Load(load),
            &params,
        )?;
        // A flat pad whose pressure comes out negative somewhere (a rim
        // lifting off) takes the constrained iteration instead.
        if solution.pressure.iter().any(|&p| p < 0.0) {
            let (s, i) = solver::solve(
                &mut backend,
                &flat,
                ax * ay,
                l00,
                Control::Load(load),
                &params,
                &mut Silent,
            )?;
            info.matvecs += i.matvecs;
            solution = s;
        }
        drop(backend);
        let force = self.friction_force_eq9(&kernel, &solution.pressure);
        let loaded: f64 = solution.pressure.iter().sum::<f64>() * ax * ay;
        let smooth = -force / loaded;
        Ok(SmoothPad {
            friction_coefficient: smooth,
            roughness_friction_coefficient: mu - smooth,
            share: if mu != 0.0 { smooth / mu } else { 0.0 },
            matvecs: info.matvecs,
            time_s: t.elapsed().as_secs_f64(),
        })
    }
}
