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

use std::collections::BTreeMap;
use std::path::Path;

use serde::Deserialize;

use super::{master, Point};

use crate::config::{self, LoadedConfig};
use crate::error::{Error, Result};
use crate::io::StagedOutput;
use crate::persson::{self, Persson, PerssonParams};
use crate::plot::{xy_chart, Series, XyChart};
use crate::problem::persson::{theory_inputs, TheoryInputs};

/// One row of `sweep.csv`.
#[derive(Debug, Clone, PartialEq)]
pub struct MergedRow {
    /// The `[sweep.vary]` values of the row (empty without them).
    pub vary: BTreeMap<String, toml::Value>,
    /// Temperature \[C\] and WLF shift factor `a_T` of the row's
    /// material, when it has WLF constants (physics.md section 12).
    pub temperature: Option<f64>,
    pub shift_factor: Option<f64>,
    pub normal_load: f64,
    pub speed: f64,
    pub xi: Option<f64>,
    pub realisations: usize,
    /// `(mean, standard deviation)` of each quantity.
    pub friction: (f64, f64),
    pub friction_dissipation: (f64, f64),
    pub area_fraction: (f64, f64),
    /// `A / A(v = 0)` of the same realisation and load, when the static point exists.
    pub area_ratio: Option<(f64, f64)>,
    pub gamma: Option<(f64, f64)>,
    pub lambda: Option<(f64, f64)>,
    /// Persson's `mu` at this speed and load.
    pub persson_friction: Option<f64>,
    /// Persson's `A/A0` at this speed and load.
    pub persson_area_fraction: Option<f64>,
    /// Persson's `A(v) / A(0)` at this load.
    pub persson_area_ratio: Option<f64>,
}

struct PointResult {
    /// Grouping keys: the plan position of the point's `[sweep.vary]`
    /// combination, its planned load (NaN when the config's) and speed.
    key_combo: usize,
    vary: BTreeMap<String, toml::Value>,
    temperature: Option<f64>,
    shift_factor: Option<f64>,
    key_load: f64,
    key_speed: f64,
    load: f64,
    speed: f64,
    xi: Option<f64>,
    seed: i64,
    mu: f64,
    mu_d: f64,
    area: f64,
    gamma: Option<f64>,
    lambda: Option<f64>,
    persson_mu: Option<f64>,
    persson_area: Option<f64>,
}

fn mean_std(v: &[f64]) -> (f64, f64) {
    let n = v.len() as f64;
    let mean = v.iter().sum::<f64>() / n;
    let var = if v.len() > 1 {
        v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0)
    } else {
        0.0
    };
    (mean, var.sqrt())
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
}

/// The analysis numbers a merge aggregates.
#[derive(Deserialize)]
struct Headline {
    gamma: Option<f64>,
    lambda: Option<f64>,
}

fn read_points(dir: &Path) -> Result<Vec<PointResult>> {
    let points_dir = dir.join("points");
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
    let mut out = Vec::new();
    for path in names {
        let text = std::fs::read_to_string(&path).map_err(|e| Error::io(&path, e))?;
        let v: PointFile = serde_json::from_str(&text)
            .map_err(|e| Error::Invalid(format!("{}: not a point result: {e}", path.display())))?;
        out.push(PointResult {
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
        });
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

/// Aggregate the points of `dir` into rows, ordered by `[sweep.vary]`
/// combination (plan order), planned load, then speed (the group keys are
/// bit patterns of non-negative floats, whose order is the numeric order).
pub fn aggregate(dir: &Path) -> Result<Vec<MergedRow>> {
    let mut points = read_points(dir)?;
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
            }
        })
        .collect();
    Ok(rows)
}

/// Persson's theory for the sweep in `dir` at one combination of its
/// `[sweep.vary]` values: its pinned configuration read back with the
/// recorded directory for relative paths (the sweep directory itself when
/// none is recorded). `Err` says why not.
fn theory_for(
    dir: &Path,
    vary: &BTreeMap<String, toml::Value>,
) -> std::result::Result<TheoryInputs, String> {
    let path = dir.join(super::CONFIG_FILE);
    let text = std::fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut document: toml::Table =
        toml::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))?;
    // The combination's `[sweep.vary]` values, set as the sweep set them.
    for (key, value) in vary {
        config::set_value(&mut document, key, value.clone())?;
    }
    let name = path.display().to_string();
    let config = config::parse_document(&document, &name).map_err(|e| e.to_string())?;
    let base_dir = std::fs::read_to_string(dir.join(super::CONFIG_DIR_FILE))
        .map(|t| Path::new(t.trim()).to_path_buf())
        .unwrap_or_else(|_| dir.to_path_buf());
    let cfg = LoadedConfig {
        config,
        path,
        base_dir,
        document,
    };
    theory_inputs(&cfg, None, None).map_err(|e| e.to_string())
}

/// The theory's curves per load label: `(x, mu, A/A0, A/A(0))` at 100
/// speeds over the positive speeds of its rows.
type Curve = Vec<(f64, f64, f64, f64)>;

/// Fill the Persson columns of `rows` from `inputs` (each load at its
/// measured nominal pressure) and return the smooth curves per load.
fn theory_curves(
    inputs: &TheoryInputs,
    rows: &mut [MergedRow],
    label: &dyn Fn(&MergedRow) -> String,
    use_xi: bool,
) -> Result<Vec<(String, Curve)>> {
    let area = inputs.area;
    let mut loads: Vec<String> = rows.iter().map(label).collect();
    loads.dedup();
    let mut curves = Vec::new();
    for load in loads {
        let idx: Vec<usize> = (0..rows.len())
            .filter(|&i| label(&rows[i]) == load)
            .collect();
        let sigma0 = match area {
            Some(a) => idx.iter().map(|&i| rows[i].normal_load).sum::<f64>() / idx.len() as f64 / a,
            None => inputs.nominal_pressure,
        };
        let theory = Persson::new(
            &inputs.material,
            &inputs.psd,
            sigma0,
            PerssonParams::default(),
        )?;
        let a0 = theory.point(0.0)?.contact_area_fraction;
        let speeds: Vec<f64> = idx.iter().map(|&i| rows[i].speed).collect();
        for (&i, p) in idx.iter().zip(theory.curve(&speeds)?) {
            let r = &mut rows[i];
            r.persson_friction.get_or_insert(p.friction_coefficient);
            r.persson_area_fraction
                .get_or_insert(p.contact_area_fraction);
            r.persson_area_ratio = Some(p.contact_area_fraction / a0);
        }
        let pos = speeds.iter().copied().filter(|v| *v > 0.0);
        let (lo, hi) = (
            pos.clone().fold(f64::INFINITY, f64::min),
            pos.fold(0.0, f64::max),
        );
        if hi <= 0.0 {
            continue;
        }
        let xi_scale = inputs.xi_scale();
        let curve = theory
            .curve(&persson::log_speeds(lo, hi, 100))?
            .into_iter()
            .map(|p| {
                let x = match (use_xi, xi_scale) {
                    (true, Some(s)) => s.xi(p.speed),
                    _ => p.speed,
                };
                (
                    x,
                    p.friction_coefficient,
                    p.contact_area_fraction,
                    p.contact_area_fraction / a0,
                )
            })
            .collect();
        curves.push((load, curve));
    }
    Ok(curves)
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
        out.insert_str(out.len() - 1, &master::extra_fields(rows, r));
    }
    out
}

/// Merge the finished points of `dir` into `dir/sweep.csv` and the plots
/// (written atomically together). Returns the rows.
pub fn merge(dir: &Path) -> Result<Vec<MergedRow>> {
    let mut rows = aggregate(dir)?;
    let use_xi = rows.iter().all(|r| r.xi.is_some());
    let x_of = |r: &MergedRow| if use_xi { r.xi.unwrap_or(0.0) } else { r.speed };
    let x_label = if use_xi { "xi = v tau / L" } else { "v [m/s]" };
    // Loads as planned, to the precision a user types them, after the
    // `[sweep.vary]` values of the row.
    let label = |r: &MergedRow| {
        let vary = master::vary_text(&r.vary);
        let load = format!("F_N = {:.4e} N", r.normal_load);
        if vary.is_empty() {
            load
        } else {
            format!("{vary}, {load}")
        }
    };
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
                eprintln!("note: Persson's theory drawn from the points' own values ({why})");
                curves.extend(recorded_curves(chunk, &label, &x_of));
            }
        }
        start = end;
    }
    let mut staged = StagedOutput::new(dir)?;
    staged.write("sweep.csv", csv(&rows).as_bytes())?;
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
    Ok(rows)
}

/// Persson's curves from the values each point recorded (the pinned
/// configuration cannot be read back), `A/A(0)` from the static point's.
fn recorded_curves(
    rows: &mut [MergedRow],
    label: &dyn Fn(&MergedRow) -> String,
    x_of: &dyn Fn(&MergedRow) -> f64,
) -> Vec<(String, Curve)> {
    let statics: BTreeMap<String, f64> = rows
        .iter()
        .filter(|r| r.speed == 0.0)
        .filter_map(|r| r.persson_area_fraction.map(|a| (label(r), a)))
        .collect();
    for r in rows.iter_mut() {
        if let (Some(a), Some(a0)) = (r.persson_area_fraction, statics.get(&label(r))) {
            r.persson_area_ratio = Some(a / a0);
        }
    }
    let mut labels: Vec<String> = rows.iter().map(label).collect();
    labels.dedup();
    labels
        .iter()
        .map(|l| {
            let c: Curve = rows
                .iter()
                .filter(|r| label(r) == *l && x_of(r) > 0.0)
                .filter_map(|r| {
                    Some((
                        x_of(r),
                        r.persson_friction?,
                        r.persson_area_fraction?,
                        r.persson_area_ratio.unwrap_or(f64::NAN),
                    ))
                })
                .collect();
            (l.clone(), c)
        })
        .filter(|(_, c)| !c.is_empty())
        .collect()
}
