//! Magnification studies (physics.md section 12): friction and contact
//! area against the short-wavelength cut-off `q1`, the boundary-element
//! solution and Persson's theory side by side.
//!
//! The PSD `C(q)` of the configuration's `[surface.generate]` is held fixed:
//! its rms slope (or height) sets the continuum plateau `C0` over the whole
//! band `[q_L, q1]` of the configuration, or a tabulated (measured,
//! stitched) PSD `psd = "table.csv"` is taken as it is, and each level cuts
//! it at its own `q1` (at most the configuration's, or the table's largest
//! `q`). Each level is generated on the
//! FFT-friendly grid with `K` cells per shortest wavelength, with the same
//! seed and the same `C0`, so every level holds exactly the same Fourier
//! modes below its cut-off; its `rms_slope` is the one with which `viscoslide
//! solve` generates exactly that surface (`plan::level_config`).
//!
//! A level at one speed is a point: points are solved independently,
//! written to `DIR/points/` through the sweep's [`PointStore`] and skipped
//! when a run resumes; `--shard K/N` runs a deterministic subset
//! ([`Shard`]). When every point exists, [`report::MagnificationReport`]
//! writes `magnification.json`, `magnification.csv` and
//! `magnification.png` together.

mod grid;
pub(crate) mod plan;
mod report;

pub(crate) use plan::parse_list;
pub use plan::{FixedPsd, LevelPlan, LevelSpec, LevelSurface, SelfAffineBand, TableBand};
pub use report::{LevelResult, MagnificationReport, PerssonCurve, ReportContext};

use std::path::{Path, PathBuf};
use std::time::Instant;

use serde_json::json;

use crate::config::LoadedConfig;
use crate::error::{Error, Result};
use crate::io::{LockMode, OutputError, StudyLock};
use crate::material::Material;
use crate::persson::{Persson, PerssonParams, PerssonPoint};
use crate::problem::{Executor, Problem};
use crate::solver::{Control, Observer};
use crate::surface::TabulatedPsd;
use crate::sweep::files::{pinned_files, with_files, PinnedFile};
use crate::sweep::{PointStore, Shard};

/// File in the study directory that pins the study it holds.
pub(crate) const PIN_FILE: &str = "magnification.toml";

/// Controls of a study.
#[derive(Debug, Clone, PartialEq)]
pub struct MagnificationParams {
    pub levels: LevelSpec,
    /// Cells per shortest wavelength `2 pi / q1` of every level.
    pub cells_per_wavelength: f64,
    /// Sliding speeds \[m/s\]; `None`: the configuration's.
    pub speeds: Option<Vec<f64>>,
}

impl MagnificationParams {
    /// The controls from the options every front end takes: exactly one
    /// of `q1` \[1/m\] and `scales`, `cells` per shortest wavelength, the
    /// `speeds` \[m/s\] (`None`: the configuration's).
    pub fn from_options(
        q1: Option<Vec<f64>>,
        scales: Option<Vec<f64>>,
        cells: f64,
        speeds: Option<Vec<f64>>,
    ) -> Result<Self> {
        let levels = match (q1, scales) {
            (Some(q), None) => LevelSpec::Q1(q),
            (None, Some(s)) => LevelSpec::Scales(s),
            _ => return Err(Error::Invalid(
                "give the levels with exactly one of q1 (--q1 Q1,Q2,..., in 1/m) and scales (--scales N1,N2,...)"
                    .into(),
            )),
        };
        Ok(Self {
            levels,
            cells_per_wavelength: cells,
            speeds,
        })
    }

    /// `levels` at the default resolution and the configuration's speed.
    pub fn new(levels: LevelSpec) -> Self {
        Self {
            levels,
            cells_per_wavelength: plan::DEFAULT_CELLS_PER_WAVELENGTH,
            speeds: None,
        }
    }
}

/// One solve of the study: a level at a speed.
#[derive(Debug, Clone, PartialEq)]
pub struct StudyPoint {
    /// Position in the plan (speeds outer, levels inner).
    pub index: usize,
    /// File stem of its result.
    pub id: String,
    /// Index into [`Study::levels`].
    pub level: usize,
    /// \[m/s\].
    pub speed: f64,
}

/// A checked study: every level planned, nothing solved.
#[derive(Debug, Clone)]
pub struct Study {
    pub cfg: LoadedConfig,
    pub params: MagnificationParams,
    pub psd: FixedPsd,
    pub levels: Vec<LevelPlan>,
    pub speeds: Vec<f64>,
    pub points: Vec<StudyPoint>,
    pub material: Material,
    /// Nominal pressure `sigma0` \[Pa\] of every level.
    pub nominal_pressure: f64,
    /// The files the configuration reads, their content hashed (pinned).
    files: Vec<PinnedFile>,
    /// Persson's theory for each level's truncated PSD (outer) at each of
    /// `speeds` (inner), evaluated once by [`Study::new`] as its check and
    /// taken again at the levels' cut-offs by [`Study::persson_curves`].
    level_theory: Vec<Vec<PerssonPoint>>,
}

impl Study {
    /// Plan and check the study of `cfg` (isothermal: an enabled
    /// `[heating]` is refused): levels within the PSD's band,
    /// grids within memory, the coarsest level built whole (material,
    /// loading, solver), a nominal pressure for the theory, Persson's theory
    /// evaluated at every level and speed. Writes nothing.
    pub fn new(cfg: &LoadedConfig, params: MagnificationParams) -> Result<Self> {
        cfg.refuse_heating("a magnification study")?;
        let (psd, levels) = plan::plan_levels(cfg, &params.levels, params.cells_per_wavelength)?;
        let loading = cfg.config.loading.clone().unwrap_or_default();
        if loading.approach.is_some() {
            return Err(Error::Invalid(
                "a magnification study needs a prescribed load ([loading] mean_pressure or normal_load): under a prescribed approach the load would change with q1".into(),
            ));
        }
        // The coarsest level built whole checks the material, the loading
        // and the solver sections (the solver's combinations included),
        // which every level shares; the checks that depend on the cell
        // (a layer against the cell size) are strictest on its grid.
        let coarse = Problem::from_config(&plan::level_config(cfg, &levels[0], None)?)?;
        let speeds = match &params.speeds {
            Some(v) if v.is_empty() => {
                return Err(Error::Invalid(
                    "speeds (--speeds) is empty: give at least one speed (m/s)".into(),
                ))
            }
            Some(v) => v.clone(),
            None => vec![coarse.speed],
        };
        if let Some(bad) = speeds.iter().find(|v| !(v.is_finite() && **v >= 0.0)) {
            return Err(Error::Invalid(format!(
                "speeds must be finite and >= 0 m/s, got {bad}"
            )));
        }
        for (k, v) in speeds.iter().enumerate() {
            if speeds[..k].contains(v) {
                return Err(Error::Invalid(format!(
                    "speeds (--speeds) lists {v} twice: give each speed once"
                )));
            }
        }
        let nominal_pressure = match coarse.control {
            Control::Load(f) => f / (coarse.surface.length_x() * coarse.surface.length_y()),
            Control::Approach(_) => unreachable!("refused above"),
        };
        // Persson's theory evaluated at every level and speed (milliseconds):
        // speeds or a pressure beyond its double precision are refused here,
        // before the study's directory is made, not at the first report.
        let level_theory = levels
            .iter()
            .map(|level| persson_at(&coarse.material, &level.psd, nominal_pressure, &speeds))
            .collect::<Result<Vec<_>>>()?;
        let mut points = Vec::with_capacity(speeds.len() * levels.len());
        for &speed in &speeds {
            for level in 0..levels.len() {
                let index = points.len();
                points.push(StudyPoint {
                    index,
                    id: crate::sweep::store::point_id(index),
                    level,
                    speed,
                });
            }
        }
        let files = pinned_files([&cfg.config], &cfg.base_dir)?;
        Ok(Self {
            files,
            cfg: cfg.clone(),
            params,
            psd,
            levels,
            speeds,
            points,
            material: coarse.material,
            nominal_pressure,
            level_theory,
        })
    }

    /// What a study directory pins: the configuration, the content of the
    /// files it reads and the planned levels and speeds (a rerun with
    /// other levels, or a changed file, needs another directory).
    pub fn pin_text(&self) -> String {
        let levels: Vec<toml::Value> = self
            .levels
            .iter()
            .map(|l| {
                let mut t = toml::Table::new();
                t.insert("q1".into(), toml::Value::Float(l.q1));
                t.insert("n".into(), toml::Value::Integer(l.n as i64));
                t.insert("ny".into(), toml::Value::Integer(l.ny as i64));
                toml::Value::Table(t)
            })
            .collect();
        let mut study = toml::Table::new();
        study.insert("levels".into(), toml::Value::Array(levels));
        study.insert(
            "speeds".into(),
            toml::Value::Array(self.speeds.iter().map(|&v| toml::Value::Float(v)).collect()),
        );
        let mut doc = toml::Table::new();
        doc.insert("study".into(), toml::Value::Table(study));
        doc.insert(
            "config".into(),
            toml::Value::Table(self.cfg.document.clone()),
        );
        toml::to_string(&with_files(doc, &self.files)).expect("a table serialises")
    }

    /// Persson's theory at 48 cut-offs log-spaced over the levels' range
    /// (and at every level), per speed: the smooth curves of the figure. At
    /// a level's own cut-off the theory is the one [`Study::new`] evaluated
    /// (the same PSD, material, pressure and speeds).
    pub fn persson_curves(&self) -> Result<Vec<PerssonCurve>> {
        const POINTS: usize = 48;
        let (lo, hi) = (self.levels[0].q1, self.levels[self.levels.len() - 1].q1);
        let mut q1s: Vec<f64> = (0..POINTS)
            .map(|k| lo * (hi / lo).powf(k as f64 / (POINTS - 1) as f64))
            .chain(self.levels.iter().map(|l| l.q1))
            .collect();
        q1s.sort_by(f64::total_cmp);
        q1s.dedup();
        let mut curves: Vec<PerssonCurve> = self.speeds.iter().map(|&v| (v, Vec::new())).collect();
        for &q1 in &q1s {
            let theory = match self.levels.iter().position(|l| l.q1 == q1) {
                Some(level) => self.level_theory[level].clone(),
                None => persson_at(
                    &self.material,
                    &self.psd.truncated(q1)?,
                    self.nominal_pressure,
                    &self.speeds,
                )?,
            };
            for (curve, p) in curves.iter_mut().zip(theory) {
                curve
                    .1
                    .push((q1, p.friction_coefficient, p.contact_area_fraction));
            }
        }
        Ok(curves)
    }

    /// The configuration `viscoslide solve` solves exactly point `point` with.
    pub fn point_config(&self, point: &StudyPoint) -> Result<LoadedConfig> {
        plan::level_config(&self.cfg, &self.levels[point.level], Some(point.speed))
    }

    /// Solve one point: the level's problem (exactly the one `solve` builds
    /// from [`Study::point_config`]) and Persson's theory for the level's
    /// truncated PSD.
    pub fn solve_point(
        &self,
        point: &StudyPoint,
        executor: &Executor,
        observer: &mut dyn Observer,
    ) -> Result<LevelResult> {
        let t0 = Instant::now();
        let level = &self.levels[point.level];
        let problem = Problem::from_config(&self.point_config(point)?)?;
        let solution = problem.solve(executor, observer)?;
        let theory = persson_at(
            &self.material,
            &level.psd,
            self.nominal_pressure,
            &[point.speed],
        )?[0];
        Ok(LevelResult {
            speed: point.speed,
            q1: level.q1,
            n: level.n,
            ny: level.ny,
            cells_per_shortest_wavelength: level.cells_per_shortest_wavelength,
            rms_height: level.rms_height,
            rms_slope: level.rms_slope,
            rms_slope_continuum: level.rms_slope_continuum,
            friction_coefficient: solution.friction_coefficient,
            friction_coefficient_dissipation: solution.friction_coefficient_dissipation,
            contact_area_fraction: solution.stats.contact_area_fraction,
            persson_friction_coefficient: theory.friction_coefficient,
            persson_contact_area_fraction: theory.contact_area_fraction,
            matvecs: solution.info.matvecs,
            iterations: solution.info.iterations,
            residual: solution.info.residual,
            wall_time_s: t0.elapsed().as_secs_f64(),
            backend: solution.backend.clone(),
            warnings: solution.warnings.clone(),
        })
    }
}

/// Persson's theory (default quadrature) for `material` on `psd` under
/// `nominal_pressure` \[Pa\], at each of `speeds` \[m/s\]: friction and
/// contact area of one cut-off of the study (physics.md section 12).
fn persson_at(
    material: &Material,
    psd: &TabulatedPsd,
    nominal_pressure: f64,
    speeds: &[f64],
) -> Result<Vec<PerssonPoint>> {
    Ok(Persson::new(material, psd, nominal_pressure, PerssonParams::default())?.curve(speeds)?)
}

/// Hears about a study's progress.
pub trait StudyObserver {
    /// Point `done + 1` of `count` to solve in this run starts.
    fn point_started(
        &mut self,
        _done: usize,
        _count: usize,
        _point: &StudyPoint,
        _level: &LevelPlan,
    ) {
    }
    /// A point is finished.
    fn point_finished(&mut self, _done: usize, _count: usize, _result: &LevelResult) {}
    /// The observer of each solve's iterations.
    fn solver(&mut self) -> &mut dyn Observer;
}

/// A [`StudyObserver`] that ignores everything.
#[derive(Debug, Default, Clone, Copy)]
pub struct Quiet;

impl Observer for Quiet {}

impl StudyObserver for Quiet {
    fn solver(&mut self) -> &mut dyn Observer {
        self
    }
}

/// What a run did.
#[derive(Debug, Clone)]
pub struct StudyRun {
    /// Points of the study (all shards).
    pub total: usize,
    /// Points of this shard.
    pub in_shard: usize,
    /// Points finished before this run.
    pub skipped: usize,
    /// Points solved by this run.
    pub solved: usize,
    /// The report, once every point of the study exists.
    pub report: Option<MagnificationReport>,
    /// The files written with the report.
    pub written: Vec<PathBuf>,
}

/// Key every finished point file has.
const DONE_KEY: &str = "friction_coefficient";

/// Run (or resume) `study`: with `dir`, the points of `shard` not yet in
/// `dir/points/` are solved and stored, and once all points of the study
/// exist (from this run or others) the report is written into `dir`; without
/// `dir` (the whole study, `shard` must be [`Shard::ALL`]) nothing is
/// written and the report is returned.
pub fn run(
    study: &Study,
    executor: &Executor,
    dir: Option<&Path>,
    shard: Shard,
    observer: &mut dyn StudyObserver,
) -> Result<StudyRun> {
    if dir.is_none() && shard != Shard::ALL {
        return Err(Error::Invalid(
            "shard (--shard) needs an output directory to store the points in".into(),
        ));
    }
    // The study is checked whole ([`Study::new`]); its first write takes
    // the directory: alone, or shared with the other shards.
    let mode = if shard == Shard::ALL {
        LockMode::Exclusive
    } else {
        LockMode::Shared
    };
    let mut lock = dir.map(|d| StudyLock::acquire(d, mode)).transpose()?;
    let store = match dir {
        Some(d) => Some(PointStore::open(
            d,
            PIN_FILE,
            &study.pin_text(),
            "magnification study",
            mode,
        )?),
        None => None,
    };
    let mine: Vec<&StudyPoint> = study
        .points
        .iter()
        .filter(|p| shard.contains(p.index))
        .collect();
    let mut results: Vec<Option<LevelResult>> = vec![None; study.points.len()];
    if let Some(store) = &store {
        for p in &study.points {
            results[p.index] = store
                .read(&p.id, DONE_KEY)
                .and_then(|v| serde_json::from_value(v).ok());
        }
    }
    let todo: Vec<&&StudyPoint> = mine.iter().filter(|p| results[p.index].is_none()).collect();
    let skipped = mine.len() - todo.len();
    let count = todo.len();
    for (done, point) in todo.into_iter().enumerate() {
        observer.point_started(done, count, point, &study.levels[point.level]);
        let result = study.solve_point(point, executor, observer.solver())?;
        if let Some(store) = &store {
            let mut value = serde_json::to_value(&result).expect("serialisable");
            value["point"] = json!({ "index": point.index, "level": point.level });
            store.write(&point.id, &value)?;
        }
        observer.point_finished(done, count, &result);
        results[point.index] = Some(result);
    }
    let all: Option<Vec<LevelResult>> = results.into_iter().collect();
    let (report, written) = match all {
        Some(levels) => {
            let report = MagnificationReport::new(
                levels,
                ReportContext {
                    speeds: study.speeds.clone(),
                    psd: study.psd.clone(),
                    cells_per_wavelength: study.params.cells_per_wavelength,
                    nominal_pressure: study.nominal_pressure,
                    seed: study.levels[0].params.seed(),
                    document: study.cfg.document.clone(),
                    persson_curves: study.persson_curves()?,
                    temperature_shift: study.material.temperature_shift(),
                },
            );
            if shard != Shard::ALL {
                // The report takes the directory alone: a shard lets its
                // shared lock go first, and leaves the report to a shard
                // still at work (it writes it when it ends).
                lock = None;
            }
            match dir.map(|d| report.write(d)).transpose() {
                Ok(written) => (Some(report), written.unwrap_or_default()),
                Err(Error::Output(OutputError::Busy { .. })) if shard != Shard::ALL => {
                    (None, Vec::new())
                }
                Err(e) => return Err(e),
            }
        }
        None => (None, Vec::new()),
    };
    drop(lock);
    Ok(StudyRun {
        total: study.points.len(),
        in_shard: mine.len(),
        skipped,
        solved: count,
        report,
        written,
    })
}
