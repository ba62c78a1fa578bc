//! The heated contact that dissipates nothing at any temperature: at
//! rest (`v = 0`, a sweep's static point), nothing slides (`mu F_N v = 0`,
//! physics.md section 14); an elastic rubber (no creep or relaxation
//! terms) stores and returns all the work done on it at every
//! temperature, whatever its WLF shift. Then `Theta = 0` at every
//! temperature and the one self-consistent temperature is `T0` itself.
//! The answer is the isothermal solve at `T0` with zero rises, reported as
//! any heated answer is, without a search (which for an elastic rubber
//! scanned the bracket with a dozen solves to find the same `T0`).

use std::time::Instant;

use crate::error::Result;
use crate::heat::AT_REST_NOTE;
use crate::problem::{Executor, Observer, Problem};

use super::branches::{Branch, Evaluation};
use super::params::HeatingParams;
use super::report::{peclet, persson_friction, DepthRow, HeatedSolution, HeatingReport, Rises};

/// Why a heated contact dissipates nothing at any temperature.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum NoHeat {
    /// The speed is 0.
    AtRest,
    /// The material has no creep or relaxation terms.
    Elastic,
}

impl NoHeat {
    /// Why `problem` dissipates nothing at any temperature, if it does not.
    pub fn of(problem: &Problem) -> Option<Self> {
        if problem.speed == 0.0 {
            Some(Self::AtRest)
        } else if problem.material.spectrum.terms.is_empty() {
            Some(Self::Elastic)
        } else {
            None
        }
    }

    /// What the answer says of itself: why nothing is dissipated (at
    /// rest, the heat's own note, which `ContactHeating` gives too) and
    /// what the answer is.
    fn note(self) -> String {
        let why = match self {
            Self::AtRest => AT_REST_NOTE.to_string(),
            Self::Elastic => "the rubber is elastic at every temperature (no creep or relaxation terms): it returns all the work done on it and dissipates nothing, whatever its WLF shift".to_string(),
        };
        format!("{why}: the effective temperature is T0 and the answer is the isothermal solve there, without a search")
    }
}

/// The heated answer of `problem` (its material at `T0`), which
/// dissipates nothing at any temperature for the reason `why`.
pub(super) fn solve_without_heat(
    why: NoHeat,
    problem: &Problem,
    params: &HeatingParams,
    executor: &Executor,
    observer: &mut dyn Observer,
) -> Result<HeatedSolution> {
    let clock = Instant::now();
    let mut solution = problem.solve(executor, observer)?;
    let periodic = problem.grid()?.is_periodic();
    let t0 = params.ambient;
    // The friction's power (`mu F_N v` at `v = 0` without the sign of
    // `mu`; an elastic solve's round-off by the route a heated answer
    // reports) and the Peclet number of the sliding.
    let (friction_power_w, peclet) = match why {
        NoHeat::AtRest => (0.0, 0.0),
        NoHeat::Elastic => (
            solution.friction_power_w(params.source, problem.speed),
            peclet(problem, params),
        ),
    };
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
        search: why.note(),
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
        friction_power_w,
        isothermal_friction_coefficient: solution.friction_coefficient,
        persson_friction_coefficient: persson_friction(&solution),
        source: params.source.name(),
        closure: "effective",
        scales: Vec::new(),
        conductivity: params.conduction.conductivity,
        diffusivity: params.conduction.diffusivity,
        block_length: params.block_length,
        peclet,
        warnings: vec![why.note()],
        wall_time_s: clock.elapsed().as_secs_f64(),
        solve_time_s: solution.timings.total_s,
        heat_time_s: 0.0,
    };
    solution.warnings.push(why.note());
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
