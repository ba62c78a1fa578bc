//! Aggregation of finished sweep points: mean and standard deviation over
//! surface realisations for every (load, speed), written to `sweep.csv`, and
//! the sweep plots (friction vs xi as the paper's Fig. 1, `A / A(xi = 0)` as
//! Fig. 7, anisotropy measures when present). The result depends only on
//! the set of point files, not on the order they were written in.
//!
//! Persson's theory (physics.md section 10) for the sweep's material,
//! surface and pressure is drawn in the same figures (a curve of 100
//! speeds per load over the sweep's range, when the pinned configuration
//! can be read back: see [`super::CONFIG_DIR_FILE`]; otherwise a line
//! through the values recorded with each point) and its values at each
//! row go into `sweep.csv` (`persson_friction`, `persson_area_fraction`,
//! `persson_area_ratio`).

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

use super::points::{read_points, PointResult};
use super::row::{mean_std, MergedRow};
use super::theory::{recorded_curves, theory_curves, theory_for};
use super::{heated, master, Point, SweepObserver, SweepPlan};

use crate::config;
use crate::error::{Error, Result};
use crate::io::{LockMode, StagedOutput, StudyLock};
use crate::plot::{xy_chart, Series, XyChart};

/// The points the sweep pinned in `dir` plans (all shards), from its
/// pinned configuration; `Err` says why they cannot be told.
fn planned_points(dir: &Path) -> std::result::Result<Vec<Point>, String> {
    let pin = dir.join(super::CONFIG_FILE);
    let text = std::fs::read_to_string(&pin).map_err(|e| format!("{}: {e}", pin.display()))?;
    let mut document: toml::Table =
        toml::from_str(&text).map_err(|e| format!("{}: {e}", pin.display()))?;
    document.remove(super::files::FILES_KEY);
    let name = pin.display().to_string();
    let config = config::parse_document(&document, &name).map_err(|e| e.to_string())?;
    let sweep = config
        .sweep
        .ok_or_else(|| format!("{name} has no [sweep] section"))?;
    Ok(SweepPlan::new(&sweep).map_err(|e| e.to_string())?.points)
}

/// The points of `planned` that no merged point stands for, each as its
/// settings name it (at most `SHOWN` of them, then how many more).
fn missing_text(missing: &[Point]) -> String {
    const SHOWN: usize = 5;
    let mut parts: Vec<String> = missing.iter().take(SHOWN).map(Point::describe).collect();
    if missing.len() > SHOWN {
        parts.push(format!("and {} more", missing.len() - SHOWN));
    }
    parts.join(", ")
}

/// Aggregate the points of `dir` into rows, ordered by `[sweep.vary]`
/// combination (plan order), planned load, then speed (the group keys are
/// bit patterns of non-negative floats, whose order is the numeric order),
/// with the ids of the points merged.
pub(crate) fn aggregate(
    dir: &Path,
    observer: &mut dyn SweepObserver,
) -> Result<(Vec<MergedRow>, BTreeSet<String>)> {
    let mut points = read_points(dir, observer)?;
    let ids = points.iter().map(|p| p.id.clone()).collect();
    let key = |p: &PointResult| (p.key_combo, p.key_load.to_bits(), p.key_speed.to_bits());
    points.sort_by_key(|p| (key(p), p.seed));
    // Static areas per (combination, planned load, seed) for A / A(0).
    let mut static_area = BTreeMap::new();
    for p in points.iter().filter(|p| p.speed == 0.0) {
        static_area.insert((p.key_combo, p.key_load.to_bits(), p.seed), p.area);
    }
    let mut groups: BTreeMap<(usize, u64, u64), Vec<&PointResult>> = BTreeMap::new();
    for p in &points {
        groups.entry(key(p)).or_default().push(p);
    }
    let rows: Vec<MergedRow> = groups
        .values()
        .map(|g| {
            let col = |f: &dyn Fn(&PointResult) -> f64| {
                mean_std(&g.iter().map(|p| f(p)).collect::<Vec<_>>())
            };
            let opt = |f: &dyn Fn(&PointResult) -> Option<f64>| {
                let v: Option<Vec<f64>> = g.iter().map(|p| f(p)).collect();
                v.map(|v| mean_std(&v))
            };
            MergedRow {
                vary: g[0].vary.clone(),
                temperature: g[0].temperature,
                shift_factor: g[0].shift_factor,
                normal_load: col(&|p| p.load).0,
                speed: g[0].speed,
                xi: g[0].xi,
                realisations: g.len(),
                friction: col(&|p| p.mu),
                friction_dissipation: col(&|p| p.mu_d),
                area_fraction: col(&|p| p.area),
                area_ratio: opt(&|p| {
                    static_area
                        .get(&(p.key_combo, p.key_load.to_bits(), p.seed))
                        .map(|a0| p.area / a0)
                }),
                gamma: opt(&|p| p.gamma),
                lambda: opt(&|p| p.lambda),
                persson_friction: opt(&|p| p.persson_mu).map(|m| m.0),
                persson_area_fraction: opt(&|p| p.persson_area).map(|m| m.0),
                persson_area_ratio: None,
                heating: heated::aggregate(
                    &g.iter().map(|p| p.heating.as_ref()).collect::<Vec<_>>(),
                ),
            }
        })
        .collect();
    Ok((rows, ids))
}

fn fmt_opt(v: Option<(f64, f64)>) -> (String, String) {
    v.map_or((String::new(), String::new()), |(m, s)| {
        (format!("{m:.8e}"), format!("{s:.8e}"))
    })
}

/// The CSV text of `rows`.
pub fn csv(rows: &[MergedRow]) -> String {
    let mut out = String::from(
        "normal_load_n,speed_m_s,xi,realisations,friction_mean,friction_std,friction_dissipation_mean,friction_dissipation_std,area_fraction_mean,area_fraction_std,area_ratio_mean,area_ratio_std,gamma_mean,gamma_std,lambda_mean,lambda_std,persson_friction,persson_area_fraction,persson_area_ratio",
    );
    out.push_str(&master::extra_header(rows));
    out.push_str(&heated::extra_header(rows));
    out.push('\n');
    let one = |v: Option<f64>| v.map(|x| format!("{x:.8e}")).unwrap_or_default();
    for r in rows {
        let (arm, ars) = fmt_opt(r.area_ratio);
        let (gm, gs) = fmt_opt(r.gamma);
        let (lm, ls) = fmt_opt(r.lambda);
        out.push_str(&format!(
            "{:.8e},{:.8e},{},{},{:.8e},{:.8e},{:.8e},{:.8e},{:.8e},{:.8e},{arm},{ars},{gm},{gs},{lm},{ls},{},{},{}\n",
            r.normal_load,
            r.speed,
            r.xi.map(|x| format!("{x:.8e}")).unwrap_or_default(),
            r.realisations,
            r.friction.0,
            r.friction.1,
            r.friction_dissipation.0,
            r.friction_dissipation.1,
            r.area_fraction.0,
            r.area_fraction.1,
            one(r.persson_friction),
            one(r.persson_area_fraction),
            one(r.persson_area_ratio),
        ));
        let extra = master::extra_fields(rows, r) + &heated::extra_fields(rows, r);
        out.insert_str(out.len() - 1, &extra);
    }
    out
}

/// What a merge merged: the rows, and the points of the sweep's plan
/// that no finished point stands for.
#[derive(Debug, Clone)]
pub struct Merged {
    pub rows: Vec<MergedRow>,
    /// Points the sweep plans (all shards); `None` when the pinned
    /// configuration cannot be planned again (then `missing` is empty).
    pub planned: Option<usize>,
    /// The planned points not merged (unsolved, or a file of another study).
    pub missing: Vec<Point>,
}

impl Merged {
    /// The missing points as their settings name them, for a message (the
    /// first five, then how many more); empty when none is missing.
    pub fn missing_text(&self) -> String {
        missing_text(&self.missing)
    }
}

/// Merge the finished points of `dir` into `dir/sweep.csv`, `merge.json`
/// (how many points the sweep plans, which of them are missing) and the
/// plots (written atomically together). A sweep with points missing (a
/// shard not run yet, a run stopped early) is refused, naming them,
/// unless `partial`. Notes (points left out, Persson's theory from the
/// points' own values) go to `observer`.
pub fn merge(dir: &Path, partial: bool, observer: &mut dyn SweepObserver) -> Result<Merged> {
    crate::io::atomic::recover(dir);
    if !dir.join("points").is_dir() {
        // aggregate's error, before the lock (which would make `dir`).
        aggregate(dir, observer)?;
    }
    // One writer: no sweep adds points while they are merged.
    let _lock = StudyLock::acquire(dir, LockMode::Exclusive)?;
    merge_locked(dir, partial, observer)
}

/// [`merge`] with `dir` already locked.
pub(super) fn merge_locked(
    dir: &Path,
    partial: bool,
    observer: &mut dyn SweepObserver,
) -> Result<Merged> {
    let (mut rows, ids) = aggregate(dir, observer)?;
    let (planned, missing) = match planned_points(dir) {
        Ok(plan) => {
            let missing: Vec<Point> = plan
                .iter()
                .filter(|p| !ids.contains(&p.id))
                .cloned()
                .collect();
            (Some(plan.len()), missing)
        }
        Err(why) if partial => {
            observer.note(&format!(
                "which points the sweep plans cannot be told ({why}); merged the {} finished ones",
                ids.len()
            ));
            (None, Vec::new())
        }
        Err(why) => {
            return Err(Error::Invalid(format!(
                "{}: which points the sweep plans cannot be told ({why}); `viscoslide merge --partial` merges the finished ones",
                dir.display()
            )))
        }
    };
    if !missing.is_empty() && !partial {
        return Err(Error::Invalid(format!(
            "{}: {} of the sweep's {} points are missing: {}; run the shards that hold them (the same `viscoslide sweep` command resumes), or merge the finished ones with `viscoslide merge --partial`",
            dir.display(),
            missing.len(),
            planned.unwrap_or_default(),
            missing_text(&missing)
        )));
    }
    let use_xi = rows.iter().all(|r| r.xi.is_some());
    let x_of = |r: &MergedRow| if use_xi { r.xi.unwrap_or(0.0) } else { r.speed };
    let x_label = if use_xi { "xi = v tau / L" } else { "v [m/s]" };
    let label = |r: &MergedRow| r.curve_label();
    let mut loads: Vec<String> = rows.iter().map(label).collect();
    loads.dedup();
    // Persson's theory per `[sweep.vary]` combination (the rows of one are
    // contiguous): smooth curves from the pinned configuration, else the
    // values each point recorded (A/A(0) from the static point's).
    let mut curves = Vec::new();
    let mut start = 0;
    while start < rows.len() {
        let end = start
            + rows[start..]
                .iter()
                .take_while(|r| r.vary == rows[start].vary)
                .count();
        let chunk = &mut rows[start..end];
        match theory_for(dir, &chunk[0].vary) {
            Ok(inputs) => curves.extend(theory_curves(&inputs, chunk, &label, use_xi)?),
            Err(why) => {
                observer.note(&format!(
                    "Persson's theory drawn from the points' own values ({why})"
                ));
                curves.extend(recorded_curves(chunk, &label, &x_of));
            }
        }
        start = end;
    }
    let mut staged = StagedOutput::for_study(dir, &["points"])?;
    staged.write("sweep.csv", csv(&rows).as_bytes())?;
    let record = serde_json::json!({
        "complete": planned.is_some() && missing.is_empty(),
        "points_planned": planned,
        "points_merged": ids.len(),
        "missing": missing.iter().map(Point::describe).collect::<Vec<_>>(),
    });
    staged.write(
        MERGE_FILE,
        serde_json::to_string_pretty(&record)
            .expect("serialisable")
            .as_bytes(),
    )?;
    type Pick = fn(&MergedRow) -> Option<(f64, f64)>;
    type TheoryPick = Option<fn(&(f64, f64, f64, f64)) -> f64>;
    // Paper Fig. 1 and 7 are against xi; Fig. 6 is against the speed.
    let (friction_title, area_title) = if use_xi {
        (
            "Viscoelastic friction (paper Fig. 1)",
            "Contact area A / A(xi = 0) (paper Fig. 7)",
        )
    } else {
        (
            "Viscoelastic friction against sliding speed (paper Fig. 6)",
            "Contact area A / A(v = 0)",
        )
    };
    let fraction_title = if use_xi {
        "Contact area fraction against xi"
    } else {
        "Contact area fraction against sliding speed"
    };
    let charts: [(&str, &str, &str, Pick, TheoryPick); 5] = [
        (
            "friction_vs_xi.png",
            friction_title,
            "friction coefficient",
            |r| Some(r.friction),
            Some(|c| c.1),
        ),
        (
            "area_ratio_vs_xi.png",
            area_title,
            "A / A(0)",
            |r| r.area_ratio,
            Some(|c| c.3),
        ),
        (
            "area_fraction_vs_xi.png",
            fraction_title,
            "A / A0",
            |r| Some(r.area_fraction),
            Some(|c| c.2),
        ),
        (
            "gamma_vs_xi.png",
            "Degree of isotropy of the deformed surface",
            "gamma",
            |r| r.gamma,
            None,
        ),
        (
            "lambda_vs_xi.png",
            "Contact-area anisotropy",
            "lambda",
            |r| r.lambda,
            None,
        ),
    ];
    for (file, title, ylabel, pick, theory) in charts {
        let mut series = Vec::new();
        for (c, load) in loads.iter().enumerate() {
            let sel: Vec<(f64, f64, f64)> = rows
                .iter()
                .filter(|r| label(r) == *load && x_of(r) > 0.0)
                .filter_map(|r| pick(r).map(|(m, s)| (x_of(r), m, s)))
                .collect();
            if sel.is_empty() {
                continue;
            }
            let mut s = Series::points(load.clone(), sel.iter().map(|t| (t.0, t.1)).collect(), c);
            s.mark = crate::plot::Mark::LineAndPoints;
            s.errors = Some(sel.iter().map(|t| t.2).collect());
            series.push(s);
            let curve = curves.iter().find(|(l, _)| l == load).map(|(_, c)| c);
            if let (Some(f), Some(curve)) = (theory, curve) {
                let pts: Vec<(f64, f64)> = curve
                    .iter()
                    .map(|c| (c.0, f(c)))
                    .filter(|p| p.1.is_finite())
                    .collect();
                if !pts.is_empty() {
                    series.push(Series::line(format!("Persson, {load}"), pts, c + 3));
                }
            }
        }
        if series.is_empty() {
            continue;
        }
        xy_chart(
            &staged.path(file),
            &XyChart {
                title: title.into(),
                x_label: x_label.into(),
                y_label: ylabel.into(),
                log_x: true,
                log_y: false,
                series,
            },
        )?;
    }
    // Grosch's master curve when the rows span several temperatures.
    let theory: Vec<(String, Vec<(f64, f64)>)> = if use_xi {
        Vec::new()
    } else {
        curves
            .iter()
            .map(|(l, c)| (l.clone(), c.iter().map(|p| (p.0, p.1)).collect()))
            .collect()
    };
    master::master_chart(&mut staged, &rows, &label, &theory)?;
    staged.commit()?;
    Ok(Merged {
        rows,
        planned,
        missing,
    })
}

/// The merge's record beside `sweep.csv`: points planned, merged, missing.
pub(crate) const MERGE_FILE: &str = "merge.json";
