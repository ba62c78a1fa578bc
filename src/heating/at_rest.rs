//! The heated contact at rest (`v = 0`, a sweep's static point): nothing
//! slides, so nothing is dissipated (`mu F_N v = 0`, physics.md section
//! 14), `Theta = 0` at every temperature and the one self-consistent
//! temperature is `T0` itself. The answer is the isothermal solve at `T0`
//! with zero rises, reported as any heated answer is.

use std::time::Instant;

use crate::error::Result;
use crate::heat::AT_REST_NOTE;
use crate::problem::{Executor, Observer, Problem};

use super::branches::{Branch, Evaluation};
use super::params::HeatingParams;
use super::report::{persson_friction, DepthRow, HeatedSolution, HeatingReport, Rises};

/// What the answer at rest says of itself: the heat's own note
/// (`ContactHeating` at rest says the same) and what the answer is.
fn at_rest() -> String {
    format!("{AT_REST_NOTE}: the effective temperature is T0 and the answer is the isothermal solve there, without a search")
}

/// The heated answer of `problem` at rest (its material at `T0`).
pub(super) fn solve_at_rest(
    problem: &Problem,
    params: &HeatingParams,
    executor: &Executor,
    observer: &mut dyn Observer,
) -> Result<HeatedSolution> {
    let clock = Instant::now();
    let mut solution = problem.solve(executor, observer)?;
    let periodic = problem.grid()?.is_periodic();
    let t0 = params.ambient;
    let report = HeatingReport {
        ambient_temperature: t0,
        effective_temperature: t0,
        temperature_rise: Rises {
            effective: 0.0,
            peak_surface: 0.0,
            mean_contact: 0.0,
            background: periodic.then_some(0.0),
        },
        chosen_branch: params.branch.name(),
        branches: vec![Branch {
            temperature: t0,
            rise: 0.0,
            residual: 0.0,
            stable: true,
        }],
        bracket: [t0, t0 + params.max_rise],
        search: at_rest(),
        fixed_point_evaluations: 1,
        evaluations: vec![Evaluation {
            temperature: t0,
            rise: 0.0,
        }],
        coarse_evaluations: 0,
        coarse_grid: None,
        coarse_rises: Vec::new(),
        coarse_discrepancy: None,
        heat_total_w: 0.0,
        friction_power_w: 0.0,
        isothermal_friction_coefficient: solution.friction_coefficient,
        persson_friction_coefficient: persson_friction(&solution),
        source: params.source.name(),
        closure: "effective",
        scales: Vec::new(),
        conductivity: params.conduction.conductivity,
        diffusivity: params.conduction.diffusivity,
        block_length: params.block_length,
        peclet: 0.0,
        warnings: vec![at_rest()],
        wall_time_s: clock.elapsed().as_secs_f64(),
        solve_time_s: solution.timings.total_s,
        heat_time_s: 0.0,
    };
    solution.warnings.push(at_rest());
    let cells = solution.fields.contact.len();
    Ok(HeatedSolution {
        solution,
        surface_rise: vec![0.0; cells],
        // No heat at any depth: the profile is its surface row.
        depth_profile: periodic.then(|| {
            vec![DepthRow {
                depth: 0.0,
                mean_rise: 0.0,
                max_rise: 0.0,
                mean_source: 0.0,
            }]
        }),
        report,
    })
}
