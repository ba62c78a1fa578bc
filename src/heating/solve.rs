//! The heated solve (physics.md section 14, "Feedback (closure)"): the
//! effective temperature `T_eff = T0 + Theta(T_eff)`, where `Theta(T)` is
//! the dissipation-weighted rise `Int theta Q dV / Int Q dV` of the
//! contact solved isothermally at `T` (the material's creep times scaled
//! by `a_T(T)`, section 12) and heated by its own dissipation `Q`.
//!
//! Each evaluation of `Theta` is one isothermal solve, warm-started from
//! the previous evaluation's contact where the discretisation takes a
//! start, then the heat source of its pressure
//! ([`crate::heat::HeatSource::from_contact`]) and the rise under it
//! ([`crate::heat::HeatSolver::under`], planned once: the heat problem
//! does not depend on the temperature). The answer is the isothermal
//! solve at the chosen root itself, so `mu_heated(v, T0) = mu(v, T_eff)`
//! holds exactly.

use std::time::Instant;

use crate::error::{Error, Result};
use crate::heat::{
    profile_depths, scale_rises, DepthExtremes, DepthLadder, DepthRule, HeatSolver, HeatSource,
};
use crate::problem::{
    balance_warning, no_heat_note, Discretisation, Executor, Observer, Problem, Solution,
    SolverError,
};

use super::branches::{Branch, SearchFailure};
use super::coarse::coarse_problem;
use super::memory::check_heated_memory;
use super::no_heat::{solve_without_heat, NoHeat};
use super::params::{BranchChoice, HeatingParams};
use super::report::{
    peclet, persson_friction, scales_warning, DepthRow, HeatedSolution, HeatingReport, Rises,
};
use super::two_level::{Level, DISCREPANCY_WARNING};

/// One evaluation kept for the answer.
struct Solved {
    temperature: f64,
    solution: Solution,
    surface_rise: Vec<f64>,
    background: Option<f64>,
    rise: f64,
    heat: f64,
    /// Whether its source carries heat ([`HeatSource::carries_heat`]).
    carries: bool,
    /// Wall time of its heat source and rise \[s\].
    heat_time_s: f64,
    /// What the answer's depth profile and warnings take of its heat
    /// source.
    source: KeptSource,
    /// The volume source's layers: `(h_l sum theta Q, h_l sum Q)`.
    layers: Option<Vec<(f64, f64)>>,
}

/// What an evaluation keeps of its heat source: the volume source's
/// density maps (one per depth layer, together the largest arrays of the
/// heated solve) are reduced at once, so that the roots kept while the
/// search goes on hold no more than their fields.
enum KeptSource {
    /// The volume source: each layer's mean density \[W/m^3\], and the
    /// depth profile's rows (depth, mean and highest rise) from the sweep
    /// that gave the evaluation's rise (full-grid evaluations).
    Volume {
        means: Vec<f64>,
        rows: Option<DepthExtremes>,
    },
    /// The surface work flux (one map).
    Surface(HeatSource),
}

/// The heated solve of `problem` (its material at `T0 =
/// params.ambient`) on `executor` (module docs); `observer` sees every
/// isothermal solve's iterations.
pub fn solve_heated(
    problem: &Problem,
    params: &HeatingParams,
    executor: &Executor,
    observer: &mut dyn Observer,
) -> Result<HeatedSolution> {
    let clock = Instant::now();
    problem.check()?;
    let search = params.search();
    search.check().map_err(Error::Invalid)?;
    if let Some(why) = NoHeat::of(problem) {
        return solve_without_heat(why, problem, params, executor, observer);
    }
    let periodic = problem.grid()?.is_periodic();
    let rule = DepthRule::default();
    // The coarse grid that scans the bracket (`two_level.rs`), with its
    // own heat problem; none on small grids.
    let coarse = coarse_problem(problem).filter(|_| params.coarse_scan);
    check_heated_memory(problem, coarse.as_ref(), params.source, &rule)?;
    let mut heat = HeatSolver::new(params.heat_setup(problem)?).map_err(heat_error)?;
    let warm_starts = problem.discretisation() != Discretisation::Adaptive;
    // The coarse cells are 2 to 4 times the full grid's: on a pad their
    // Peclet number may pass the limit the full grid's is under, and the
    // full grid then scans alone (any other refusal is the full grid's
    // too, and came above).
    let coarse = match coarse {
        Some(c) => HeatSolver::new(params.heat_setup(&c)?).ok().map(|h| (c, h)),
        None => None,
    };
    let coarse_grid = coarse.as_ref().map(|(c, _)| [c.surface.nx, c.surface.ny]);
    let mut coarse = coarse;
    let mut last: Option<Solution> = None;
    let mut last_coarse: Option<Solution> = None;
    let mut coarse_evaluations = 0;
    let mut kept: Vec<Solved> = Vec::new();
    let mut isothermal: Option<f64> = None;
    let tolerance = params.tolerance;
    let (mut solve_time_s, mut heat_time_s) = (0.0, 0.0);

    let mut full_evaluations = 0;
    let mut evaluate = |level: Level, t: f64| -> Result<f64> {
        if level == Level::Coarse {
            let (cp, ch) = coarse.as_mut().expect("a coarse level is searched");
            let label = format!(
                "heated: coarse {} x {} grid, evaluation {} at {t:.4} C",
                cp.surface.nx,
                cp.surface.ny,
                coarse_evaluations + 1
            );
            let solved = solve_at(
                &label,
                cp,
                params,
                ch,
                &rule,
                t,
                last_coarse.as_ref().filter(|_| warm_starts),
                None,
                executor,
                observer,
            )?;
            coarse_evaluations += 1;
            solve_time_s += solved.solution.timings.total_s;
            heat_time_s += solved.heat_time_s;
            last_coarse = Some(solved.solution);
            return Ok(solved.rise);
        }
        full_evaluations += 1;
        let label = format!("heated: evaluation {full_evaluations} at {t:.4} C");
        // An evaluation that closes the fixed point may be the answer,
        // whose depth profile is reported; the others need none.
        let closes = |rise: f64| (params.ambient + rise - t).abs() <= tolerance;
        let solved = solve_at(
            &label,
            problem,
            params,
            &mut heat,
            &rule,
            t,
            last.as_ref().filter(|_| warm_starts),
            periodic.then_some(&closes),
            executor,
            observer,
        )?;
        if isothermal.is_none() {
            isothermal = Some(solved.solution.friction_coefficient);
        }
        solve_time_s += solved.solution.timings.total_s;
        heat_time_s += solved.heat_time_s;
        let rise = solved.rise;
        if closes(rise) {
            last = Some(solved.solution.clone());
            kept.push(solved);
        } else {
            last = Some(solved.solution);
        }
        Ok(rise)
    };
    let searched = if coarse_grid.is_some() {
        search.find_two_level(&mut evaluate).map(|two| {
            let rises = two.coarse.clone();
            (two.found, Some((rises, two.discrepancy)))
        })
    } else {
        search
            .find(|t| evaluate(Level::Full, t))
            .map(|found| (found, None))
    };
    let (found, coarse_found) = match searched {
        Ok(found) => found,
        Err(SearchFailure::Evaluation(e)) => return Err(e),
        Err(SearchFailure::AboveBracket { rise_at_end }) => {
            return Err(Error::Invalid(format!(
                "[heating] the rise at T0 + max_rise = {} C is {rise_at_end:.4e} K, above max_rise = {} K: no self-consistent temperature in the bracket; raise [heating] max_rise, or check the conductivity and the speed",
                params.ambient + params.max_rise,
                params.max_rise
            )))
        }
        Err(SearchFailure::ScanTooLong { start, evaluations }) => {
            let from = if start > params.tolerance {
                format!("Theta(T0) = {start:.4e} K")
            } else {
                format!("the tolerance, {start:e} K (Theta(T0) is below it)")
            };
            return Err(Error::Invalid(format!(
                "[heating] max_rise = {:e} K: scanning the rises from {from} by factors of {} up to it takes more than {evaluations} isothermal solves, the most one heated solve makes; lower [heating] max_rise",
                params.max_rise,
                search.scan_ratio
            )));
        }
        Err(SearchFailure::Budget { evaluations }) => {
            return Err(Error::Invalid(format!(
                "[heating] no self-consistent temperature closed within {evaluations} isothermal solves; loosen [heating] tolerance (now {} K)",
                params.tolerance
            )))
        }
    };

    // g(T0) = Theta(T0) > 0: where the hottest root found is unstable (g
    // rising through zero), g is still positive at the bracket's end, and
    // a hotter branch, if any, lies above it.
    let above = found
        .branches
        .last()
        .filter(|b| !b.stable)
        .map(|b| b.temperature);
    if let (Some(t), BranchChoice::Hot) = (above, params.branch) {
        return Err(Error::Invalid(format!(
            "[heating] branch = \"hot\": the hottest self-consistent temperature in [{}, {}] C, {t:.4} C, is unstable and the rise at the bracket's end exceeds max_rise, so the hot branch lies above {} C; raise [heating] max_rise (now {} K)",
            found.bracket[0], found.bracket[1], found.bracket[1], params.max_rise
        )));
    }
    let stable: Vec<&Branch> = found.branches.iter().filter(|b| b.stable).collect();
    let chosen = match params.branch {
        BranchChoice::Cold => stable.first().copied(),
        BranchChoice::Hot => stable.last().copied(),
    }
    .or(found.branches.first())
    .copied()
    .expect("the search returns at least one root");
    let mut evaluations = found.evaluations.len();
    let answer = match kept
        .into_iter()
        .find(|s| s.temperature == chosen.temperature)
    {
        Some(s) => s,
        None => {
            evaluations += 1;
            solve_at(
                &format!("heated: the answer at {:.4} C", chosen.temperature),
                problem,
                params,
                &mut heat,
                &rule,
                chosen.temperature,
                last.as_ref().filter(|_| warm_starts),
                periodic.then_some(&|_| true),
                executor,
                observer,
            )?
        }
    };

    let scales_clock = Instant::now();
    let scales = match &answer.layers {
        Some(layers) => {
            let at = problem_at(problem, answer.temperature)?;
            scale_rises(
                &answer.solution.fields.pressure,
                &at.grid()?,
                &at.response()?,
                &rule,
                layers,
            )
            .map_err(heat_error)?
        }
        None => Vec::new(),
    };
    heat_time_s += scales_clock.elapsed().as_secs_f64();
    let solution = answer.solution;
    let friction_power = solution.friction_power_w(params.source, problem.speed);
    let contact: Vec<f64> = answer
        .surface_rise
        .iter()
        .zip(&solution.fields.contact)
        .filter(|(_, &c)| c > 0.5)
        .map(|(&r, _)| r)
        .collect();
    let mean_contact = if contact.is_empty() {
        0.0
    } else {
        contact.iter().sum::<f64>() / contact.len() as f64
    };
    let peak = answer
        .surface_rise
        .iter()
        .copied()
        .fold(f64::NEG_INFINITY, f64::max);
    let mut warnings = Vec::new();
    if found.branches.len() > 1 {
        let list: Vec<String> = found
            .branches
            .iter()
            .map(|b| {
                format!(
                    "{:.4} C ({})",
                    b.temperature,
                    if b.stable { "stable" } else { "unstable" }
                )
            })
            .collect();
        warnings.push(format!(
            "{} self-consistent temperatures in [{}, {}] C: {}; the answer is the {} branch ([heating] branch = \"cold\" or \"hot\" chooses)",
            found.branches.len(),
            found.bracket[0],
            found.bracket[1],
            list.join(", "),
            params.branch.name()
        ));
    }
    // The answer's own temperature is the solve's, which warns of it.
    if let Some(wlf) = problem.material.wlf {
        let beyond: Vec<String> = found
            .branches
            .iter()
            .filter(|b| b.temperature != chosen.temperature)
            .filter_map(|b| wlf.extrapolation(b.temperature))
            .collect();
        if !beyond.is_empty() {
            warnings.push(format!(
                "another self-consistent temperature rests on an extrapolated WLF shift: {}",
                beyond.join("; ")
            ));
        }
    }
    if let Some(t) = above {
        warnings.push(format!(
            "the hottest self-consistent temperature found, {t:.4} C, is unstable: the rise at the bracket's end exceeds max_rise, so a hotter branch (or runaway heating) lies above {} C; raise [heating] max_rise to find it",
            found.bracket[1]
        ));
    }
    if let Some((_, d)) = &coarse_found {
        if *d > DISCREPANCY_WARNING {
            warnings.push(format!(
                "the coarse grid's rise that scanned the bracket differs from the full grid's by {:.1} % where both were solved: a branch away from the roots found may be misplaced or missed by the scan",
                100.0 * d
            ));
        }
    }
    if answer.carries {
        warnings.extend(balance_warning(answer.heat, friction_power));
        if let KeptSource::Surface(flux) = &answer.source {
            warnings.extend(flux.returned_share_warning());
        }
    } else {
        // The balance and the share returned would weigh round-off.
        warnings.push(no_heat_note(answer.heat));
    }
    let isothermal = isothermal.expect("T0 is evaluated first");
    warnings.extend(scales_warning(
        &scales,
        answer.temperature - params.ambient,
        isothermal,
        solution.friction_coefficient,
    ));
    if params.block_length.is_some() {
        warnings.extend(heat.setup().notes());
    }
    warnings.extend(
        problem
            .layer
            .as_ref()
            .and_then(|l| heat.setup().layer_note(l.thickness)),
    );
    let report = HeatingReport {
        ambient_temperature: params.ambient,
        effective_temperature: answer.temperature,
        temperature_rise: Rises {
            effective: answer.rise,
            peak_surface: peak,
            mean_contact,
            background: answer.background,
        },
        chosen_branch: params.branch.name(),
        branches: found.branches.clone(),
        bracket: found.bracket,
        search: found.method.clone(),
        fixed_point_evaluations: evaluations,
        evaluations: found.evaluations.clone(),
        coarse_evaluations,
        coarse_grid,
        coarse_rises: coarse_found
            .as_ref()
            .map_or_else(Vec::new, |(r, _)| r.clone()),
        coarse_discrepancy: coarse_found.as_ref().map(|(_, d)| *d),
        heat_total_w: answer.heat,
        friction_power_w: friction_power,
        isothermal_friction_coefficient: isothermal,
        persson_friction_coefficient: persson_friction(&solution),
        source: params.source.name(),
        closure: "effective",
        scales,
        conductivity: params.conduction.conductivity,
        diffusivity: params.conduction.diffusivity,
        block_length: params.block_length,
        peclet: peclet(problem, params),
        warnings,
        wall_time_s: 0.0,
        solve_time_s,
        heat_time_s,
    };
    let profile_clock = Instant::now();
    let depth_profile = if periodic {
        observer.stage("heated: depth profile");
        Some(depth_profile(problem, &mut heat, &answer.source)?)
    } else {
        None
    };
    let mut report = report;
    report.heat_time_s += profile_clock.elapsed().as_secs_f64();
    report.wall_time_s = clock.elapsed().as_secs_f64();
    let mut solution = solution;
    solution.warnings.extend(report.warnings.iter().cloned());
    Ok(HeatedSolution {
        solution,
        surface_rise: answer.surface_rise,
        depth_profile,
        report,
    })
}

/// Depths of the surface source's profile: 8 per octave (27 per decade,
/// [`DepthLadder::octaves`]) from a tenth of the smaller cell side to the
/// map's side.
const PROFILE_PER_OCTAVE: u64 = 8;

/// The rise against depth of the answer (a periodic cell) under its heat
/// `source`: at the volume source's layer middles (the rows swept with
/// its rise), or at depths spaced geometrically below a surface flux.
fn depth_profile(
    problem: &Problem,
    heat: &mut HeatSolver,
    source: &KeptSource,
) -> Result<Vec<DepthRow>> {
    match source {
        KeptSource::Volume { means, rows } => {
            let rows = rows.as_ref().ok_or_else(|| {
                Error::Invalid(
                    "the volume source's depth profile comes from a full-grid evaluation".into(),
                )
            })?;
            Ok(rows
                .iter()
                .enumerate()
                .map(|(i, &(z, mean_rise, max_rise))| DepthRow {
                    depth: z,
                    mean_rise,
                    max_rise,
                    mean_source: if i == 0 { 0.0 } else { means[i - 1] },
                })
                .collect())
        }
        KeptSource::Surface(HeatSource::Surface { flux }) => {
            let s = &problem.surface;
            let shallow = 0.1 * s.cell_size.min(s.cell_size_y);
            let deep = (s.nx as f64 * s.cell_size).max(s.ny as f64 * s.cell_size_y);
            let ladder =
                DepthLadder::octaves(shallow, deep, PROFILE_PER_OCTAVE).map_err(heat_error)?;
            let rows = heat.surface_extremes(flux, &ladder).map_err(heat_error)?;
            Ok(rows
                .iter()
                .zip(ladder.depths())
                .map(|(&(mean_rise, max_rise), depth)| DepthRow {
                    depth,
                    mean_rise,
                    max_rise,
                    mean_source: 0.0,
                })
                .collect())
        }
        KeptSource::Surface(HeatSource::Volume { .. }) => {
            unreachable!("a volume source is kept as its layers' means")
        }
    }
}

/// A heat problem's refusal in one line; its cancellation is the solve's.
fn heat_error(e: crate::heat::HeatError) -> Error {
    match e {
        e @ crate::heat::HeatError::Cancelled => e.into(),
        e => Error::Invalid(e.to_string()),
    }
}

/// `problem` with its material at `t` \[C\] (the isothermal problem of one
/// evaluation).
fn problem_at(problem: &Problem, t: f64) -> Result<Problem> {
    let mut at = problem.clone();
    at.material = problem
        .material
        .at_temperature(t)
        .map_err(|e| Error::Invalid(format!("[heating] the effective temperature {t} C: {e}")))?;
    Ok(at)
}

/// The isothermal solve at `t` \[C\] and its dissipation-weighted rise;
/// where `profile` holds for the rise \[K\], a volume source's depth
/// profile from the same sweep (full-grid evaluations that close the
/// fixed point: one of them is the answer, whose profile is reported).
/// `observer` hears each stage under `label` and may stop the heat
/// source between its depth nodes.
#[allow(clippy::too_many_arguments)]
fn solve_at(
    label: &str,
    problem: &Problem,
    params: &HeatingParams,
    heat: &mut HeatSolver,
    rule: &DepthRule,
    t: f64,
    start: Option<&Solution>,
    profile: Option<&dyn Fn(f64) -> bool>,
    executor: &Executor,
    observer: &mut dyn Observer,
) -> Result<Solved> {
    let at = problem_at(problem, t)?;
    observer.stage(&format!("{label}: isothermal solve"));
    let solution = at.solve_warm(executor, start.map(Solution::warm_start), observer)?;
    let clock = Instant::now();
    observer.stage(&format!("{label}: heat source"));
    let source = HeatSource::from_contact_until(
        params.source,
        &solution.fields.pressure,
        &at.grid()?,
        &at.response()?,
        rule,
        &mut || observer.cancelled(),
    )
    .map_err(heat_error)?;
    if observer.cancelled() {
        return Err(SolverError::Cancelled.into());
    }
    observer.stage(&format!("{label}: rise"));
    let heat_w = source.power(at.grid()?.cell_area());
    let carries = source.carries_heat(at.grid()?.cell_area());
    let (temperature, rise, swept, layers) = if carries {
        let under = heat.under_with(&source, profile).map_err(heat_error)?;
        (
            under.temperature,
            under.weighted,
            under.profile,
            under.layers,
        )
    } else {
        // No dissipation (no contact, or a purely elastic response, whose
        // work flux nets round-off): no rise anywhere.
        (
            crate::heat::Temperature {
                rise: vec![0.0; solution.fields.pressure.len()],
                background: None,
            },
            0.0,
            None,
            None,
        )
    };
    let source = match source {
        HeatSource::Volume { layers: l, density } => {
            // Without heat the profile is zero at every depth.
            let still = || profile_depths(&l).map(|z| (z, 0.0, 0.0)).collect();
            KeptSource::Volume {
                means: density.layer_means(),
                rows: swept.or_else(|| {
                    let zero_rise = profile.is_some_and(|wanted| wanted(0.0));
                    (zero_rise && !carries).then(still)
                }),
            }
        }
        flux @ HeatSource::Surface { .. } => KeptSource::Surface(flux),
    };
    Ok(Solved {
        temperature: t,
        background: temperature.background,
        surface_rise: temperature.rise,
        rise,
        heat: heat_w,
        carries,
        heat_time_s: clock.elapsed().as_secs_f64(),
        solution,
        source,
        layers,
    })
}
