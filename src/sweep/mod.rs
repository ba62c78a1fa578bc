//! Sweeps over speed, load, surface realisation and any other config key
//! (`[sweep.vary]`) that survive interruption
//! and scale out: every point is solved independently and written atomically
//! to `DIR/points/<id>.json`; a rerun skips finished points; `--shard K/N`
//! runs a deterministic subset; [`merge`] aggregates the points into
//! `DIR/sweep.csv` (mean and standard deviation over realisations) and plots.

mod compare;
pub(crate) mod files;
mod heated;
mod master;
mod merge;
mod plan;
mod points;
mod row;
pub(crate) mod store;
mod theory;

pub use crate::config::SweepConfig;
pub use compare::{compare, Measured};
pub(crate) use merge::MERGE_FILE;
pub use merge::{merge, Merged};
pub use plan::{Point, Shard, SweepPlan};
pub use row::{HeatedRow, MergedRow};
pub use store::PointStore;

use std::collections::BTreeMap;
use std::path::Path;

use serde_json::Value;

use crate::backend::BackendChoice;
use crate::config::{self, Config, LoadedConfig, Sliding};
use crate::error::{Error, Result};
use crate::heat::HeatSetup;
use crate::heating::{solve_heated, HeatingParams};
use crate::io::atomic::write_atomic;
use crate::io::{LockMode, StudyLock};
use crate::problem::{Executor, Problem};
use crate::solver::Silent;

/// File in the sweep directory that pins the configuration it was made with.
pub const CONFIG_FILE: &str = "sweep.toml";

/// File in the sweep directory holding the directory the configuration's
/// relative paths (a material file, a surface file) are resolved against.
pub(crate) const CONFIG_DIR_FILE: &str = "sweep.config_dir";

/// Hears about a sweep's progress: the front ends draw it (a progress bar
/// on the command line, nothing in Python); the library prints nothing.
pub trait SweepObserver {
    /// The executor the points run on, in one line (as `solve` states it).
    fn executor(&mut self, _line: &str) {}
    /// Point `done + 1` of `count` to solve in this run starts.
    fn point_started(&mut self, _done: usize, _count: usize, _id: &str) {}
    /// A point is finished and written.
    fn point_finished(&mut self, _done: usize, _count: usize, _id: &str) {}
    /// A warning of point `id`'s solve (it is also in the point's file).
    fn warning(&mut self, _id: &str, _message: &str) {}
    /// A point's solve failed: its error ends the run next, the points
    /// written before it stay (a run of the same command resumes).
    fn point_failed(&mut self, _point: &Point) {}
    /// A note on a merge: points left out, where Persson's curves come from.
    fn note(&mut self, _message: &str) {}
}

/// A [`SweepObserver`] that ignores everything.
#[derive(Debug, Default, Clone, Copy)]
pub struct Quiet;

impl SweepObserver for Quiet {}

/// What a sweep run did.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SweepRun {
    /// Points in the plan (all shards).
    pub total: usize,
    /// Points of this shard.
    pub in_shard: usize,
    /// Points already finished before this run.
    pub skipped: usize,
    /// Points solved by this run.
    pub solved: usize,
}

/// Run (or resume) the sweep of `cfg` into `dir`. `limit` stops after that
/// many new points (the rest is left for a later run).
///
/// The whole plan is checked first (the axes, the `[sweep.vary]` keys and
/// values, the problem of every combination), then `dir` is locked (made
/// if missing): the run alone, or shared with the other shards of the same
/// sweep with `--shard`; a second writer fails at once.
pub fn run_sweep(
    cfg: &LoadedConfig,
    dir: &Path,
    shard: Shard,
    limit: Option<usize>,
    backend: BackendChoice,
    observer: &mut dyn SweepObserver,
) -> Result<SweepRun> {
    Ok(run_and_merge(cfg, dir, shard, limit, backend, false, observer)?.0)
}

/// [`run_sweep`], then with `merge`, when the run covers every point
/// (no shard) and all are done, [`merge`] under the same lock: no other
/// writer comes between the last point and the merge. The points are
/// solved on the executor `backend` selects (as `solve` selects it, for
/// the first point's problem; its line goes to the observer).
pub fn run_and_merge(
    cfg: &LoadedConfig,
    dir: &Path,
    shard: Shard,
    limit: Option<usize>,
    backend: BackendChoice,
    merge: bool,
    observer: &mut dyn SweepObserver,
) -> Result<(SweepRun, Option<Vec<MergedRow>>)> {
    let sweep = cfg.config.sweep.clone().ok_or_else(|| {
        Error::Invalid(format!(
            "{}: a sweep needs a [sweep] section",
            cfg.path.display()
        ))
    })?;
    let plan = SweepPlan::new(&sweep)?;
    // Every check before any output: within one combination of the
    // `[sweep.vary]` values the points differ only in speed, load and
    // seed, each already checked by the plan, so the first point of every
    // combination that builds means they all do; a refused sweep creates
    // nothing.
    let mut selected = None;
    for combo in plan.vary_combinations() {
        let first = plan
            .points
            .iter()
            .find(|p| &p.vary == combo)
            .expect("a combination has points");
        // Every combination's problem and `[heating]` checked before the
        // first point is written.
        let (problem, heating) = point_problem(cfg, first)?;
        if let Some(params) = &heating {
            check_heat_at_every_speed(&plan, combo, &problem, params)?;
        }
        if selected.is_none() {
            selected = Some(Executor::select(backend, &problem)?);
        }
        // The precision each combination asks for, on the executor picked.
        if let Some((executor, _)) = &selected {
            problem.precision_on(executor)?;
        }
    }
    let (executor, line) = selected.expect("a plan has points");
    // The content of every file a combination reads is pinned with the
    // configuration, hashed before anything is written.
    let configs = plan
        .vary_combinations()
        .into_iter()
        .map(|combo| {
            let first = plan
                .points
                .iter()
                .find(|p| &p.vary == combo)
                .expect("a combination has points");
            point_config(cfg, first)
        })
        .collect::<Result<Vec<Config>>>()?;
    let files = files::pinned_files(&configs, &cfg.base_dir)?;
    observer.executor(&line);
    let mode = if shard == Shard::ALL {
        LockMode::Exclusive
    } else {
        LockMode::Shared
    };
    let _lock = StudyLock::acquire(dir, mode)?;
    let store = pin_config(cfg, &files, dir, mode)?;
    let mine: Vec<&Point> = plan
        .points
        .iter()
        .filter(|p| shard.contains(p.index))
        .collect();
    let todo: Vec<&&Point> = mine
        .iter()
        .filter(|p| !store.done(&p.id, "friction_coefficient"))
        .collect();
    let skipped = mine.len() - todo.len();
    let count = limit.map_or(todo.len(), |l| l.min(todo.len()));
    let mut solved = 0;
    for point in todo.into_iter().take(count) {
        observer.point_started(solved, count, &point.id);
        let value =
            solve_point(cfg, point, &executor).inspect_err(|_| observer.point_failed(point))?;
        for w in value["warnings"].as_array().into_iter().flatten() {
            observer.warning(&point.id, w.as_str().unwrap_or(""));
        }
        store.write(&point.id, &value)?;
        solved += 1;
        observer.point_finished(solved, count, &point.id);
    }
    let run = SweepRun {
        total: plan.points.len(),
        in_shard: mine.len(),
        skipped,
        solved,
    };
    let rows = if merge && shard == Shard::ALL && run.skipped + run.solved == run.in_shard {
        // The run holds the directory alone (no shard): merge under its lock.
        Some(merge::merge_locked(dir, false, observer)?.rows)
    } else {
        None
    };
    Ok((run, rows))
}

/// Solve one point on `executor`: the base configuration with the point's
/// speed, load and seed substituted.
pub(crate) fn solve_point(cfg: &LoadedConfig, point: &Point, executor: &Executor) -> Result<Value> {
    let (problem, heating) = point_problem(cfg, point)?;
    let (solution, heated) = match heating {
        Some(params) => {
            let h = solve_heated(&problem, &params, executor, &mut Silent)?;
            (h.solution, Some(h.report))
        }
        None => (problem.solve(executor, &mut Silent)?, None),
    };
    let analysis = solution.analyze_configured()?;
    let mut value = solution.summary_with(analysis.as_ref());
    if let Some(report) = heated {
        value["heating"] = serde_json::to_value(&report).expect("the report is serialisable");
    }
    if let Value::Object(map) = &mut value {
        map.remove("config");
        map.remove("residual_history");
        map.remove("contact_history");
        map.insert(
            "point".into(),
            serde_json::to_value(point).expect("serialisable"),
        );
    }
    Ok(value)
}

/// The heat problem of every point of the combination `combo` (its
/// `[heating]` `params` and the `problem` of its first point), checked at
/// each point's speed before anything is solved: the heat problem depends
/// on the speed (a pad's cell Peclet number `v a / kappa`), which the
/// first point's checks do not cover. A refusal names the point.
fn check_heat_at_every_speed(
    plan: &SweepPlan,
    combo: &BTreeMap<String, toml::Value>,
    problem: &Problem,
    params: &HeatingParams,
) -> Result<()> {
    let setup = params.heat_setup(problem)?;
    for point in plan.points.iter().filter(|p| &p.vary == combo) {
        let speed = match point.speed {
            Sliding::Speed(v) => v,
            // The combination's first point converted its xi, so the
            // scale exists.
            Sliding::Xi(xi) => problem.xi_scale().map_or(problem.speed, |s| s.speed(xi)),
        };
        HeatSetup { speed, ..setup }
            .check_sliding_or_at_rest()
            .map_err(|e| Error::Invalid(format!("[heating] at point {}: {e}", point.describe())))?;
    }
    Ok(())
}

/// The problem of one point: the base configuration with the point's
/// speed, load and seed substituted, checked whole, and its `[heating]`
/// when enabled.
fn point_problem(cfg: &LoadedConfig, point: &Point) -> Result<(Problem, Option<HeatingParams>)> {
    let mut config = point_config(cfg, point)?;
    config.sweep = None;
    let loading = config.loading.get_or_insert_with(Default::default);
    loading.set_sliding(point.speed);
    if let Some(f) = point.normal_load {
        loading.set_normal_load(f);
    }
    if let Some(seed) = point.seed {
        let generate = config
            .surface
            .as_mut()
            .and_then(|s| s.generate.as_mut())
            .ok_or_else(|| {
                Error::Invalid(format!(
                    "{}: [sweep] seeds need a generated surface ([surface.generate])",
                    cfg.path.display()
                ))
            })?;
        generate.seed = Some(seed);
    }
    let document = toml::Table::try_from(&config)
        .map_err(|e| Error::Invalid(format!("the configuration of point {}: {e}", point.id)))?;
    let ambient = config.loading.as_ref().and_then(|l| l.temperature);
    let heating = config.heating.clone();
    let point_cfg = LoadedConfig {
        config,
        path: cfg.path.clone(),
        base_dir: cfg.base_dir.clone(),
        document,
    };
    let problem = Problem::from_config(&point_cfg)?;
    problem.check_analysis()?;
    let heating = match &heating {
        Some(h) => HeatingParams::from_config(h, &problem, ambient)?,
        None => None,
    };
    Ok((problem, heating))
}

/// The configuration of `point` before its speed, load and seed: the
/// base document with every `[sweep.vary]` value set as `--set` sets it
/// (`config::set_replacing`, which makes the sections a key needs and
/// replaces the configuration's own alternative of the key: a varied `q1`
/// replaces `scales`, `rms_slope` `rms_height`, `mean_pressure`
/// `normal_load`) and typed again. A key the configuration does not have,
/// a value of the wrong type, or two keys of which a configuration gives
/// one, are refused in one line naming the key and the value.
pub fn point_config(cfg: &LoadedConfig, point: &Point) -> Result<Config> {
    if point.vary.is_empty() {
        return Ok(cfg.config.clone());
    }
    let name = cfg.path.display().to_string();
    let what = |key: &str, value: &toml::Value| format!("{name}: [sweep.vary] \"{key}\" = {value}");
    let mut document = cfg.document.clone();
    let mut given = Vec::new();
    for (key, value) in &point.vary {
        config::set_replacing(&mut document, key, value.clone(), &mut given)
            .map_err(|e| Error::Invalid(format!("{}: {e}", what(key, value))))?;
    }
    // Typed once all keys are set: keys that together make a section
    // (`layer.base` and `layer.thickness` without a `[layer]`) are valid
    // only together.
    let message = match config::parse_document(&document, &name) {
        Ok(config) => return Ok(config),
        Err(e) => parse_message(e),
    };
    // The key to name: the first whose value, set after those before it,
    // gives this same error.
    let mut partial = cfg.document.clone();
    let mut given = Vec::new();
    for (key, value) in &point.vary {
        config::set_replacing(&mut partial, key, value.clone(), &mut given).expect("set above");
        if let Err(e) = config::parse_document(&partial, &name) {
            if parse_message(e) == message {
                return Err(Error::Invalid(format!("{}: {message}", what(key, value))));
            }
        }
    }
    let values: Vec<String> = point
        .vary
        .iter()
        .map(|(k, v)| format!("\"{k}\" = {v}"))
        .collect();
    Err(Error::Invalid(format!(
        "{name}: [sweep.vary] {}: {message}",
        values.join(", ")
    )))
}

/// A configuration error without the line of the merged document it
/// names ("line N, key `k`: ...").
fn parse_message(e: config::ConfigError) -> String {
    let message = match e {
        config::ConfigError::Parse { message, .. } => message,
        other => other.to_string(),
    };
    match message.split_once(", ") {
        Some((head, rest)) if head.starts_with("line ") => rest.to_string(),
        _ => message,
    }
}

/// Record the configuration and the content of the `files` it reads in
/// `dir`, or check that they match those recorded there: a sweep
/// directory holds the points of one configuration (a run holding it
/// alone replaces a pin without points: [`PointStore::open`]).
/// The caller holds the directory's lock in `mode`.
fn pin_config(
    cfg: &LoadedConfig,
    files: &[files::PinnedFile],
    dir: &Path,
    mode: LockMode,
) -> Result<PointStore> {
    let pinned = files::with_files(cfg.document.clone(), files);
    let text = toml::to_string(&pinned).expect("a parsed document serialises");
    let store = PointStore::open(dir, CONFIG_FILE, &text, "sweep", mode)?;
    // Where the pinned configuration's relative paths point (for `merge`,
    // which rebuilds Persson's theory from it); not part of the pin.
    let base = std::fs::canonicalize(&cfg.base_dir).unwrap_or_else(|_| cfg.base_dir.clone());
    write_atomic(
        dir.join(CONFIG_DIR_FILE),
        base.display().to_string().as_bytes(),
    )?;
    Ok(store)
}
