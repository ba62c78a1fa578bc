//! Refinement studies: the same physical problem (surface seed, material,
//! load, speed) solved on a sequence of grids, coarse to fine, each level
//! by the solver's own coarse-to-fine cascade (default) or started from the
//! previous level's solution prolonged to its grid ([`Problem::prolong`];
//! the cascade needs about half the matvecs on the experiment), with a Richardson estimate of the grid-converged
//! friction and contact area and a verdict on whether the sequence is in its
//! asymptotic range ([`richardson()`]). [`RefineReport::write`] puts
//! `refine.json` and `refine.png` into a directory, both or neither.

mod richardson;

pub use richardson::{observed_order, richardson, Richardson, RichardsonParams, Verdict};

use std::path::{Path, PathBuf};
use std::time::Instant;

use serde::Serialize;
use serde_json::{json, Value};

use crate::error::{Error, Result};
use crate::io::StagedOutput;
use crate::plot::{self, Mark, Series, XyChart};
use crate::problem::{check_memory, Discretisation, Executor, Problem, ShortestWavelength};
use crate::solver::Observer;

fn invalid(msg: impl Into<String>) -> Error {
    Error::Invalid(msg.into())
}

/// Controls of a refinement study.
#[derive(Debug, Clone, PartialEq)]
pub struct RefineParams {
    /// Cells along x of each level, strictly increasing (see
    /// `check_levels`).
    pub levels: Vec<usize>,
    /// Start each level from the previous one's solution; off (default),
    /// each level runs the solver's own coarse-to-fine cascade.
    pub warm_start: bool,
    pub richardson: RichardsonParams,
}

impl RefineParams {
    /// `levels`, cold-started (the solver's cascade), default Richardson
    /// controls.
    pub fn new(levels: Vec<usize>) -> Self {
        Self {
            levels,
            warm_start: false,
            richardson: RichardsonParams::default(),
        }
    }
}

/// Parse `512,1024,2048` into grid sizes (any order; [`check_levels`]
/// judges it).
pub(crate) fn parse_levels(text: &str) -> Result<Vec<usize>> {
    text.split(',')
        .map(|s| {
            let s = s.trim();
            s.parse::<usize>().map_err(|_| {
                invalid(format!(
                    "--levels: `{s}` is not a grid size; give cells along x, comma-separated, coarse to fine, e.g. 512,1024,2048"
                ))
            })
        })
        .collect()
}

/// Check a level list: at least two levels, strictly increasing (no
/// duplicates), each at least 8 cells. Any sizes are accepted (ratio-2
/// grids make the Richardson order the plain `log2`).
pub(crate) fn check_levels(levels: &[usize]) -> Result<()> {
    if levels.len() < 2 {
        return Err(invalid(format!(
            "--levels needs at least two grids (three to observe the order of convergence), got {levels:?}"
        )));
    }
    if let Some(&n) = levels.iter().find(|&&n| n < 8) {
        return Err(invalid(format!(
            "--levels: {n} is too small, a grid needs at least 8 cells"
        )));
    }
    for w in levels.windows(2) {
        if w[1] == w[0] {
            return Err(invalid(format!(
                "--levels lists {} twice: give each grid once",
                w[0]
            )));
        }
        if w[1] < w[0] {
            return Err(invalid(format!(
                "--levels must go from coarse to fine (strictly increasing), but {} comes before {}",
                w[0], w[1]
            )));
        }
    }
    Ok(())
}

/// Check every level of `problem` against the memory estimate
/// ([`crate::problem::memory_estimate`]) before anything is solved.
pub(crate) fn check_level_memory(problem: &Problem, levels: &[usize]) -> Result<()> {
    for &n in levels {
        let within = |e: crate::error::Error| e.within(&format!("--levels {n}"));
        let ny_n = problem.grid_y(n).map_err(within)?;
        check_memory(
            n,
            ny_n,
            problem.params.restart,
            problem.formulation,
            problem.precision.unwrap_or_default(),
        )
        .map_err(within)?;
    }
    Ok(())
}

/// One level of a study.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Level {
    /// Cells along x.
    pub n: usize,
    /// Cells along y.
    pub ny: usize,
    /// Cell size \[m\].
    pub cell_size: f64,
    /// See [`Problem::cells_per_shortest_wavelength`]; `None` for a sphere.
    pub cells_per_shortest_wavelength: Option<f64>,
    pub friction_coefficient: f64,
    pub friction_coefficient_dissipation: f64,
    pub contact_area_fraction: f64,
    /// Operator applications of this level's solve.
    pub matvecs: usize,
    /// Active-set iterations.
    pub iterations: usize,
    /// Final relative complementarity residual.
    pub residual: f64,
    /// Wall time of the level, the set-up and the prolongation included
    /// \[s\].
    pub wall_time_s: f64,
    /// Whether the level started from the previous level's solution.
    pub warm_started: bool,
    /// The solve's warnings (resolution).
    pub warnings: Vec<String>,
}

/// Hears about a study's progress.
pub trait RefineObserver {
    /// Level `index` (0-based) of `count` starts on `problem`.
    fn level_started(&mut self, _index: usize, _count: usize, _problem: &Problem, _warm: bool) {}
    /// Level `index` of `count` is done.
    fn level_finished(&mut self, _index: usize, _count: usize, _level: &Level) {}
    /// The observer of each solve's iterations.
    fn solver(&mut self) -> &mut dyn Observer;
}

/// A [`RefineObserver`] that ignores everything.
#[derive(Debug, Default, Clone, Copy)]
pub struct Quiet;

impl Observer for Quiet {}

impl RefineObserver for Quiet {
    fn solver(&mut self) -> &mut dyn Observer {
        self
    }
}

/// The result of a study.
#[derive(Debug, Clone)]
pub struct RefineReport {
    pub levels: Vec<Level>,
    pub friction: Richardson,
    pub friction_dissipation: Richardson,
    pub area: Richardson,
    pub warm_start: bool,
    pub backend: String,
    /// The shortest roughness wavelength (of the coarsest level; `None`
    /// for a sphere).
    pub shortest_wavelength: Option<ShortestWavelength>,
    pub seed: Option<u64>,
    pub speed: f64,
    pub xi: Option<f64>,
    pub document: toml::Table,
    pub total_wall_time_s: f64,
}

/// The study of `problem` on `params.levels` (each level
/// [`Problem::with_grid`]): the grids are checked against the memory
/// estimate before anything is solved.
pub fn refine(
    problem: &Problem,
    executor: &Executor,
    params: &RefineParams,
    observer: &mut dyn RefineObserver,
) -> Result<RefineReport> {
    check_levels(&params.levels)?;
    check_level_memory(problem, &params.levels)?;
    let count = params.levels.len();
    run(
        count,
        |k| problem.with_grid(params.levels[k]),
        executor,
        params,
        observer,
    )
}

/// The study over given problems, the same physical problem on grids from
/// coarse to fine (for surfaces [`Problem::with_grid`] cannot re-discretise,
/// e.g. given as values); `params.levels` is ignored.
pub fn refine_problems(
    problems: &[Problem],
    executor: &Executor,
    params: &RefineParams,
    observer: &mut dyn RefineObserver,
) -> Result<RefineReport> {
    let levels: Vec<usize> = problems.iter().map(|p| p.surface.nx).collect();
    check_levels(&levels)?;
    run(
        problems.len(),
        |k| Ok(problems[k].clone()),
        executor,
        params,
        observer,
    )
}

fn run(
    count: usize,
    mut make: impl FnMut(usize) -> Result<Problem>,
    executor: &Executor,
    params: &RefineParams,
    observer: &mut dyn RefineObserver,
) -> Result<RefineReport> {
    let t_all = Instant::now();
    let mut levels: Vec<Level> = Vec::with_capacity(count);
    let mut previous: Option<(Problem, crate::problem::Solution)> = None;
    let mut backend = String::new();
    let mut first: Option<Problem> = None;
    for k in 0..count {
        let t0 = Instant::now();
        // Without a warm start the coarser level goes before the next one
        // is built (its fields are a quarter of the next level's grid
        // vectors, and the next level's memory check sees what is free).
        if !params.warm_start {
            previous = None;
        }
        let problem = make(k).map_err(|e| e.within(&format!("level {}", k + 1)))?;
        let warm = params.warm_start && problem.discretisation() != Discretisation::Adaptive;
        // The coarser level goes once its solution is prolonged, the start
        // once the iteration holds it: on the finest grid neither stays.
        let start = match (previous.take(), warm) {
            (Some((cp, cs)), true) => Some(problem.prolong(&cp, &cs)?),
            _ => None,
        };
        let warm_started = start.is_some();
        observer.level_started(k, count, &problem, warm_started);
        let solution = problem.solve_warm(executor, start, observer.solver())?;
        let (n, ny) = solution.grid();
        let level = Level {
            n,
            ny,
            cell_size: problem.surface.cell_size,
            cells_per_shortest_wavelength: solution.cells_per_shortest_wavelength(),
            friction_coefficient: solution.friction_coefficient,
            friction_coefficient_dissipation: solution.friction_coefficient_dissipation,
            contact_area_fraction: solution.stats.contact_area_fraction,
            matvecs: solution.info.matvecs,
            iterations: solution.info.iterations,
            residual: solution.info.residual,
            wall_time_s: t0.elapsed().as_secs_f64(),
            warm_started,
            warnings: solution.warnings.clone(),
        };
        observer.level_finished(k, count, &level);
        levels.push(level);
        backend = solution.backend.clone();
        if first.is_none() {
            first = Some(problem.clone());
        }
        previous = Some((problem, solution));
    }
    let base = first.ok_or_else(|| invalid("a refinement study needs levels"))?;
    let h: Vec<f64> = levels.iter().map(|l| l.cell_size).collect();
    let est = |f: fn(&Level) -> f64| {
        let v: Vec<f64> = levels.iter().map(f).collect();
        richardson(&h, &v, &params.richardson)
    };
    Ok(RefineReport {
        friction: est(|l| l.friction_coefficient),
        friction_dissipation: est(|l| l.friction_coefficient_dissipation),
        area: est(|l| l.contact_area_fraction),
        levels,
        warm_start: params.warm_start,
        backend,
        shortest_wavelength: base.shortest_wavelength(),
        seed: base.seed,
        speed: base.speed,
        xi: base.xi(),
        document: base.document.clone(),
        total_wall_time_s: t_all.elapsed().as_secs_f64(),
    })
}

impl RefineReport {
    /// The `refine.json` document. Key names are fixed: scripts read them.
    pub fn to_json(&self) -> Value {
        let (source, wavelength) = match self.shortest_wavelength {
            Some(ShortestWavelength::UpperCutoff(l)) => (Some("upper_cutoff"), Some(l)),
            Some(ShortestWavelength::Nyquist(_)) => (Some("nyquist"), None),
            None => (None, None),
        };
        let mut warnings: Vec<String> = Vec::new();
        for (name, r) in [("friction", &self.friction), ("contact area", &self.area)] {
            if r.verdict == Verdict::NotAsymptotic {
                warnings.push(format!("{name}: {}", r.message));
            }
        }
        json!({
            "levels": self.levels,
            "richardson": {
                "friction_coefficient": self.friction,
                "friction_coefficient_dissipation": self.friction_dissipation,
                "contact_area_fraction": self.area,
            },
            "shortest_wavelength": {
                "source": source,
                "length_m": wavelength,
            },
            "warm_start": self.warm_start,
            "matvecs_total": self.levels.iter().map(|l| l.matvecs).sum::<usize>(),
            "wall_time_s": self.total_wall_time_s,
            "backend": self.backend,
            "seed": self.seed,
            "speed": self.speed,
            "xi": self.xi,
            "version": crate::version::VERSION,
            "config": self.document,
            "warnings": warnings,
        })
    }

    /// Write `refine.json` and `refine.png` into `dir`: both or neither.
    pub fn write(&self, dir: &Path) -> Result<Vec<PathBuf>> {
        let mut staged = StagedOutput::new(dir)?;
        staged.write(
            "refine.json",
            serde_json::to_string_pretty(&self.to_json())
                .expect("the report is serialisable")
                .as_bytes(),
        )?;
        let png = staged.path("refine.png");
        plot::xy_charts_stacked(&png, &self.charts())?;
        Ok(staged.commit()?)
    }

    /// Friction and area against cells per shortest wavelength (grid cells
    /// along x for a sphere), log x, with the Richardson limit where the
    /// sequence is asymptotic.
    fn charts(&self) -> Vec<XyChart> {
        let by_cells = self
            .levels
            .iter()
            .all(|l| l.cells_per_shortest_wavelength.is_some());
        let x = |l: &Level| {
            if by_cells {
                l.cells_per_shortest_wavelength.unwrap_or(f64::NAN)
            } else {
                l.n as f64
            }
        };
        let x_label = if by_cells {
            "cells per shortest wavelength"
        } else {
            "cells along x"
        };
        let (x0, x1) = (
            self.levels.first().map(x).unwrap_or(1.0),
            self.levels.last().map(x).unwrap_or(1.0),
        );
        let chart = |title: &str, y_label: &str, r: &Richardson, f: fn(&Level) -> f64| {
            let pts: Vec<(f64, f64)> = self.levels.iter().map(|l| (x(l), f(l))).collect();
            let mut series = vec![Series {
                label: "levels".into(),
                points: pts,
                mark: Mark::LineAndPoints,
                color: 2,
                errors: None,
            }];
            if let (Some(limit), true) = (r.extrapolated, r.asymptotic == Some(true)) {
                series.push(Series {
                    label: format!("Richardson limit {limit:.4e} +- {:.1e}", r.error_estimate),
                    points: vec![(x0, limit), (x1, limit)],
                    mark: Mark::Line,
                    color: 0,
                    errors: None,
                });
            }
            let verdict = match r.verdict {
                Verdict::Asymptotic => format!(
                    "asymptotic, order {:.2}",
                    r.observed_order.unwrap_or(f64::NAN)
                ),
                Verdict::NotAsymptotic => "NOT asymptotic".into(),
                Verdict::Converged => "converged".into(),
                Verdict::AssumedOrder => "2 levels, order assumed".into(),
            };
            XyChart {
                title: format!("{title} under refinement ({verdict})"),
                x_label: x_label.into(),
                y_label: y_label.into(),
                log_x: true,
                log_y: false,
                series,
            }
        };
        vec![
            chart("Friction", "friction coefficient", &self.friction, |l| {
                l.friction_coefficient
            }),
            chart(
                "Contact area",
                "contact area fraction A/A0",
                &self.area,
                |l| l.contact_area_fraction,
            ),
        ]
    }
}
