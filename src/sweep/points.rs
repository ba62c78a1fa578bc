//! The finished points of a sweep directory as a merge reads them: the
//! point files of the pinned study under their own names, with the
//! numbers `sweep.csv` aggregates.

use std::collections::BTreeMap;
use std::path::Path;

use serde::Deserialize;

use super::heated::HeatedPoint;
use super::{Point, SweepObserver};
use crate::error::{Error, Result};

/// One finished point.
pub(super) struct PointResult {
    /// The point's file stem in the plan.
    pub(super) id: String,
    /// Grouping keys: the plan position of the point's `[sweep.vary]`
    /// combination, its planned load (NaN when the config's) and speed.
    pub(super) key_combo: usize,
    pub(super) vary: BTreeMap<String, toml::Value>,
    pub(super) temperature: Option<f64>,
    pub(super) shift_factor: Option<f64>,
    pub(super) key_load: f64,
    pub(super) key_speed: f64,
    pub(super) load: f64,
    pub(super) speed: f64,
    pub(super) xi: Option<f64>,
    pub(super) seed: i64,
    pub(super) mu: f64,
    pub(super) mu_d: f64,
    pub(super) area: f64,
    pub(super) gamma: Option<f64>,
    pub(super) lambda: Option<f64>,
    pub(super) persson_mu: Option<f64>,
    pub(super) persson_area: Option<f64>,
    /// The point's heating report's headline, for a heated point.
    pub(super) heating: Option<HeatedPoint>,
}

/// A point file as `sweep` writes it (the keys of `summary.json` it keeps).
#[derive(Deserialize)]
struct PointFile {
    normal_load: f64,
    speed: f64,
    xi: Option<f64>,
    seed: Option<i64>,
    friction_coefficient: f64,
    friction_coefficient_dissipation: f64,
    contact_area_fraction: f64,
    analysis: Option<Headline>,
    point: Point,
    /// The study the point was solved for ([`super::store::study_id`]).
    #[serde(default)]
    study: Option<String>,
    /// Persson's theory at the point (absent in points of older versions).
    #[serde(default)]
    persson_friction_coefficient: Option<f64>,
    #[serde(default)]
    persson_contact_area_fraction: Option<f64>,
    /// Temperature and WLF shift of the point (absent in older versions).
    #[serde(default)]
    temperature: Option<f64>,
    #[serde(default)]
    shift_factor: Option<f64>,
    /// The heated solve's report (a point with `[heating]`), as written.
    #[serde(default)]
    heating: Option<serde_json::Value>,
}

/// The analysis numbers a merge aggregates.
#[derive(Deserialize)]
struct Headline {
    gamma: Option<f64>,
    lambda: Option<f64>,
}

pub(super) fn read_points(
    dir: &Path,
    observer: &mut dyn SweepObserver,
) -> Result<Vec<PointResult>> {
    let points_dir = dir.join("points");
    if !dir.exists() {
        return Err(Error::Invalid(format!(
            "{}: no such directory (`viscoslide sweep CONFIG --out DIR` makes a sweep directory)",
            dir.display()
        )));
    }
    if !dir.is_dir() {
        return Err(Error::Invalid(format!(
            "{}: not a directory (a sweep directory is the --out of `viscoslide sweep`)",
            dir.display()
        )));
    }
    if !points_dir.is_dir() {
        return Err(Error::Invalid(format!(
            "{}: not a sweep directory (it has no points/ folder; `viscoslide sweep CONFIG --out DIR` makes one)",
            dir.display()
        )));
    }
    let entries = std::fs::read_dir(&points_dir).map_err(|e| Error::io(&points_dir, e))?;
    let mut names: Vec<_> = entries
        .filter_map(|e| e.ok())
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|x| x == "json"))
        .collect();
    names.sort();
    // Only the points of the pinned study: a file of another (an earlier
    // version's, or copied in) is left out, and said so.
    let pin = dir.join(super::CONFIG_FILE);
    let study = std::fs::read_to_string(&pin)
        .map(|t| super::store::study_id(&t))
        .map_err(|e| Error::io(&pin, e))?;
    let mut foreign = 0;
    // Files holding another point than their name says (copied or renamed
    // by hand): a rerun solves the named point again, so they are no result
    // of it here either.
    let mut misplaced = Vec::new();
    let mut out = Vec::new();
    for path in names {
        let text = std::fs::read_to_string(&path).map_err(|e| Error::io(&path, e))?;
        let not_a_point = |e: serde_json::Error| {
            Error::Invalid(format!("{}: not a point result: {e}", path.display()))
        };
        let value: serde_json::Value = serde_json::from_str(&text).map_err(not_a_point)?;
        let v = PointFile::deserialize(&value).map_err(not_a_point)?;
        if v.study.as_deref() != Some(study.as_str()) {
            foreign += 1;
            continue;
        }
        let stem = path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default();
        if let Err(held) = super::store::records(&value, &stem) {
            misplaced.push(format!("{stem}.json holds {held}"));
            continue;
        }
        out.push(PointResult {
            id: v.point.id.clone(),
            key_combo: v.point.index,
            vary: v.point.vary.clone(),
            temperature: v.temperature,
            shift_factor: v.shift_factor,
            key_load: v.point.normal_load.unwrap_or(f64::NAN),
            key_speed: v.point.speed.value(),
            load: v.normal_load,
            speed: v.speed,
            xi: v.xi,
            seed: v.seed.unwrap_or(-1),
            mu: v.friction_coefficient,
            mu_d: v.friction_coefficient_dissipation,
            area: v.contact_area_fraction,
            gamma: v.analysis.as_ref().and_then(|a| a.gamma),
            lambda: v.analysis.as_ref().and_then(|a| a.lambda),
            persson_mu: v.persson_friction_coefficient,
            persson_area: v.persson_contact_area_fraction,
            // A report without the numbers merged (an older version's)
            // leaves the row's heating columns empty.
            heating: v
                .heating
                .and_then(|h| serde_json::from_value::<HeatedPoint>(h).ok()),
        });
    }
    if foreign > 0 {
        observer.note(&format!(
            "{foreign} point files in {} belong to another study than {} pins; left out",
            points_dir.display(),
            pin.display()
        ));
    }
    if !misplaced.is_empty() {
        const SHOWN: usize = 5;
        let mut named: Vec<String> = misplaced.iter().take(SHOWN).cloned().collect();
        if misplaced.len() > SHOWN {
            named.push(format!("and {} more", misplaced.len() - SHOWN));
        }
        observer.note(&format!(
            "{} point files in {} hold another point than their name says ({}); left out (a rerun of the sweep solves the points they are named for)",
            misplaced.len(),
            points_dir.display(),
            named.join(", ")
        ));
    }
    if out.is_empty() {
        return Err(Error::Invalid(format!(
            "{}: no finished points",
            points_dir.display()
        )));
    }
    // A combination's key: the smallest plan index among its points (the
    // `[sweep.vary]` values are the outermost axis, so this is plan order).
    let mut first: Vec<(BTreeMap<String, toml::Value>, usize)> = Vec::new();
    for p in &out {
        match first.iter_mut().find(|(v, _)| *v == p.vary) {
            Some((_, i)) => *i = (*i).min(p.key_combo),
            None => first.push((p.vary.clone(), p.key_combo)),
        }
    }
    for p in &mut out {
        p.key_combo = first.iter().find(|(v, _)| *v == p.vary).expect("seen").1;
    }
    Ok(out)
}
