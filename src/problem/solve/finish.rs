//! A raw solution of any route made into a [`Solution`]: the friction by
//! both routes (physics.md section 4), the contact statistics, the finite
//! pad's own friction and the warnings of a solve, and the timings.

use std::time::Instant;

use crate::config::{Formulation, Precision};
use crate::error::Result;

use super::super::executor::Executes;
use super::super::smooth_pad::SMOOTH_PAD_SHARE_LIMIT;
use super::super::warnings::FRICTION_ROUND_OFF;
use super::super::{Problem, Solution, SurfaceSource, Timings};
use super::Raw;

impl Problem {
    /// Friction by both routes, contact statistics and timings of any path
    /// (solved in `precision`); a finite pad's own friction on `executor`
    /// (in its precision, as the rough solve).
    pub(super) fn finish<X: Executes>(
        &self,
        raw: Raw,
        t0: Instant,
        executor: &mut X,
        precision: Precision,
    ) -> Result<Solution> {
        let t2 = Instant::now();
        let unknowns = raw
            .mesh
            .as_ref()
            .map_or(self.surface.nx * self.surface.ny, |m| m.unknowns);
        // A finite pad's own part of the friction (the same pad, flat): on
        // the uniform grid of the non-periodic formulation, solved before
        // the friction so that both take Eq. 9 from the same operators. A
        // sphere is an indenter, not a rough pad: a flat pad's rim says
        // nothing of its friction.
        let stats = self.contact_stats(&raw.solution);
        let load = stats.normal_load;
        // The rough solve's device round trips, before the pad's add to them.
        let device_traffic = executor.device_traffic();
        let mut pad_error = None;
        let sphere = matches!(self.source, SurfaceSource::Sphere(_));
        let pad = if self.formulation == Formulation::NonPeriodic
            && raw.mesh.is_none()
            && load > 0.0
            && !sphere
        {
            self.smooth_pad(executor, load, raw.info.matvecs)
                .map_err(|e| pad_error = Some(e))
                .ok()
        } else {
            None
        };
        let (mu, mu_d, pad_force) = self.friction_with(
            &raw.solution,
            &stats,
            pad.as_ref().map(|p| p.pressure.as_slice()),
        )?;
        let mut warnings = self.warnings(&stats, mu, mu_d);
        // The iteration stops at the arithmetic's floor when the tolerance
        // asked lies below it (a tolerance of 1e-16 ended at 2e-14): say
        // so. The f32 iteration alone stops there by choice.
        let residual = raw.info.residual;
        if precision != Precision::F32 && residual > self.params.tolerance {
            warnings.push(format!(
                "the residual {residual:.3e} stayed above the tolerance {:.1e} asked ([solver] tolerance): the iteration stopped at the arithmetic's floor for this grid, so the answer is as accurate as double precision allows here, not as the tolerance asks; a tolerance above the residual states it",
                self.params.tolerance
            ));
        }
        if let Some(e) = pad_error {
            warnings.push(format!("the finite pad's own friction (the same pad without roughness) was not computed: {e}"));
        }
        let smooth_pad = pad.zip(pad_force).map(|(p, force)| p.with_force(force, mu));
        if let Some(pad) = &smooth_pad {
            // No friction to share at rest or on an elastic solid: both
            // zero to round-off, whose ratio means nothing.
            let zero = mu.abs().max(pad.friction_coefficient.abs()) < FRICTION_ROUND_OFF;
            if pad.share.abs() > SMOOTH_PAD_SHARE_LIMIT && !zero {
                warnings.push(format!(
                    "{:.0} % of the friction is the finite pad's own: the same pad without roughness gives mu = {:.4e} at this load and speed (its rim's hysteresis), the roughness part is {:.4e}; a rubber block on a large rough plate has no such rim: compare the roughness part (smooth_pad in summary.json) with experiments and Persson, or use formulation = \"periodic\" or a larger pad",
                    100.0 * pad.share,
                    pad.friction_coefficient,
                    pad.roughness_friction_coefficient
                ));
            }
        }
        let t_an = t2.elapsed().as_secs_f64();
        let t_pad = smooth_pad.as_ref().map_or(0.0, |p| p.time_s);
        let total = t0.elapsed().as_secs_f64();
        let timings = Timings {
            coefficients_s: raw.t_coeff,
            operator_setup_s: raw
                .t_setup
                .unwrap_or(total - raw.t_coeff - raw.t_iter - t_an),
            iteration_s: raw.t_iter,
            analysis_s: (t_an - t_pad).max(0.0),
            smooth_pad_s: t_pad,
            total_s: total,
        };
        let mut solution = Solution::new(
            self,
            raw.solution,
            raw.info,
            stats,
            (mu, mu_d),
            raw.backend,
            timings,
            unknowns,
            raw.mesh,
            warnings,
        );
        solution.record_precision(precision);
        solution.smooth_pad = smooth_pad;
        solution.device_traffic = device_traffic;
        Ok(solution)
    }
}
