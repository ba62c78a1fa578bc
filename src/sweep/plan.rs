//! The points of a sweep: the values of `[sweep.vary]` keys x speeds (a
//! list or a log range of `v` or `xi`, each a typed [`Sliding`]) x
//! normal loads x surface realisations (seeds), in a fixed order, and the
//! deterministic split into shards.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use crate::config::{Sliding, SweepConfig};
use crate::error::{Error, Result};

/// One solve of the sweep.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Point {
    /// Position in the plan (0-based).
    pub index: usize,
    /// File stem of its result, `p0000`, `p0001`, ...
    pub id: String,
    pub speed: Sliding,
    pub normal_load: Option<f64>,
    pub seed: Option<u64>,
    /// The value of each `[sweep.vary]` key at this point (empty without
    /// one).
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub vary: BTreeMap<String, toml::Value>,
}

impl Point {
    /// The point as its settings name it, for a message: its file stem,
    /// then its speed (or `xi`), load, seed and `[sweep.vary]` values,
    /// e.g. `p0003 (v = 0.05 m/s, heating.max_rise = 1e-12)`.
    pub fn describe(&self) -> String {
        let mut parts = vec![match self.speed {
            Sliding::Speed(v) => format!("v = {v} m/s"),
            Sliding::Xi(x) => format!("xi = {x}"),
        }];
        if let Some(f) = self.normal_load {
            parts.push(format!("F_N = {f} N"));
        }
        if let Some(seed) = self.seed {
            parts.push(format!("seed {seed}"));
        }
        parts.extend(self.vary.iter().map(|(k, v)| format!("{k} = {v}")));
        format!("{} ({})", self.id, parts.join(", "))
    }
}

/// All points of a sweep, in plan order (the `[sweep.vary]` values, then
/// load, then speed, then seed; without `vary` the order and indices are
/// those of speed, load and seed alone).
#[derive(Debug, Clone, PartialEq)]
pub struct SweepPlan {
    pub points: Vec<Point>,
}

fn log_range(r: [f64; 3], key: &str) -> Result<Vec<f64>> {
    let [from, to, n] = r;
    if !(from > 0.0 && to > 0.0 && from.is_finite() && to.is_finite())
        || n < 1.0
        || n.fract() != 0.0
    {
        return Err(Error::Invalid(format!(
            "[sweep] {key} = [from, to, points] needs positive finite ends and a whole number of points, got {r:?}"
        )));
    }
    // Checked before anything is allocated: `n as usize` saturates, and
    // every point costs a plan entry, a solve and a row of the table.
    let count = if n < u64::MAX as f64 {
        n as u64
    } else {
        u64::MAX
    };
    check_points(&format!("[sweep] {key} of {n:e} points"), count)?;
    let n = count as usize;
    Ok((0..n)
        .map(|k| {
            if n == 1 {
                from
            } else {
                from * (to / from).powf(k as f64 / (n - 1) as f64)
            }
        })
        .collect())
}

/// Bytes one point of a sweep holds until the merge: its plan entry
/// (`Point`, its id) and its row of the merged table.
const POINT_BYTES: u64 = 256;

/// Refuse `count` sweep points that cannot be held in memory.
fn check_points(what: &str, count: u64) -> Result<()> {
    crate::io::memory::check_count(|| what.to_string(), count, POINT_BYTES)
        .map_err(|e| Error::Invalid(e.to_string()))
}

impl SweepPlan {
    /// Expand the axes of `cfg` into points.
    pub fn new(cfg: &SweepConfig) -> Result<Self> {
        let axes = [
            cfg.speed.is_some(),
            cfg.xi.is_some(),
            cfg.speed_range.is_some(),
            cfg.xi_range.is_some(),
        ];
        if axes.iter().filter(|&&a| a).count() != 1 {
            return Err(Error::Invalid(
                "[sweep] give exactly one of speed, xi, speed_range and xi_range".into(),
            ));
        }
        for (key, list) in [("speed", &cfg.speed), ("xi", &cfg.xi)] {
            if list.as_ref().is_some_and(Vec::is_empty) {
                return Err(Error::Invalid(format!(
                    "[sweep] {key} is empty: give at least one value"
                )));
            }
        }
        if cfg.normal_load.as_ref().is_some_and(Vec::is_empty) {
            return Err(Error::Invalid(
                "[sweep] normal_load is empty: give at least one load (N) or leave it out".into(),
            ));
        }
        let (mut speeds, xi) = if let Some(v) = &cfg.speed {
            (v.clone(), false)
        } else if let Some(v) = &cfg.xi {
            (v.clone(), true)
        } else if let Some(r) = cfg.speed_range {
            (log_range(r, "speed_range")?, false)
        } else {
            (
                log_range(cfg.xi_range.expect("one axis"), "xi_range")?,
                true,
            )
        };
        if let Some(bad) = speeds.iter().find(|v| !(v.is_finite() && **v >= 0.0)) {
            return Err(Error::Invalid(format!(
                "[sweep] speeds must be >= 0 and finite, got {bad}"
            )));
        }
        if cfg.include_static.unwrap_or(true) && !speeds.contains(&0.0) {
            speeds.insert(0, 0.0);
        }
        let loads: Vec<Option<f64>> = match &cfg.normal_load {
            Some(l) => {
                if let Some(bad) = l.iter().find(|f| !(f.is_finite() && **f > 0.0)) {
                    return Err(Error::Invalid(format!(
                        "[sweep] normal loads must be positive, got {bad} N"
                    )));
                }
                l.iter().map(|&f| Some(f)).collect()
            }
            None => vec![None],
        };
        let seeds: Vec<Option<u64>> = match &cfg.seeds {
            Some(s) if s.is_empty() => return Err(Error::Invalid("[sweep] seeds is empty".into())),
            Some(s) => s.iter().map(|&x| Some(x)).collect(),
            None => vec![None],
        };
        let vary = vary_axes(cfg)?;
        let combos = vary
            .iter()
            .try_fold(1u64, |acc, (_, v)| acc.checked_mul(v.len() as u64))
            .unwrap_or(u64::MAX);
        let total = [loads.len(), speeds.len(), seeds.len()]
            .iter()
            .try_fold(combos, |acc, &k| acc.checked_mul(k as u64))
            .unwrap_or(u64::MAX);
        check_points(
            &format!(
                "sweep of {combos} [sweep.vary] values x {} loads x {} speeds x {} seeds",
                loads.len(),
                speeds.len(),
                seeds.len()
            ),
            total,
        )?;
        let mut points = Vec::with_capacity(total as usize);
        for combo in combinations(&vary) {
            for &normal_load in &loads {
                for &v in &speeds {
                    for &seed in &seeds {
                        let index = points.len();
                        points.push(Point {
                            index,
                            id: super::store::point_id(index),
                            speed: if xi {
                                Sliding::Xi(v)
                            } else {
                                Sliding::Speed(v)
                            },
                            normal_load,
                            seed,
                            vary: combo.clone(),
                        });
                    }
                }
            }
        }
        Ok(Self { points })
    }

    /// The distinct `[sweep.vary]` combinations, in plan order.
    pub fn vary_combinations(&self) -> Vec<&BTreeMap<String, toml::Value>> {
        let mut out: Vec<&BTreeMap<String, toml::Value>> = Vec::new();
        for p in &self.points {
            if out.last() != Some(&&p.vary) {
                out.push(&p.vary);
            }
        }
        out
    }
}

/// The most `[sweep.vary]` combinations (the product of the lengths of
/// its lists) a sweep takes: every combination is built and checked
/// before the first point is solved, so the limit is checked first.
pub const MAX_VARY_COMBINATIONS: u64 = 10_000;

/// The `[sweep.vary]` keys and their values, checked: config paths
/// (dotted keys of a section, no whitespace, each key once after its parts
/// are trimmed as `--set` trims them), non-empty lists without a value
/// twice, no key that the sweep's own axes set (the speed always; the load
/// with `normal_load`; the seed with `seeds`) or of `[sweep]` itself, and
/// at most [`MAX_VARY_COMBINATIONS`] combinations. Whether a key exists
/// and takes such a value is the configuration's to say, when each point
/// is built.
fn vary_axes(cfg: &SweepConfig) -> Result<Vec<(String, Vec<toml::Value>)>> {
    let Some(vary) = &cfg.vary else {
        return Ok(Vec::new());
    };
    let mut taken = vec!["loading.speed", "loading.xi"];
    if cfg.normal_load.is_some() {
        taken.extend([
            "loading.normal_load",
            "loading.mean_pressure",
            "loading.approach",
        ]);
    }
    if cfg.seeds.is_some() {
        taken.push("surface.generate.seed");
    }
    // A key given twice (once with a stray space) first: that is the
    // mistake to name, not the space.
    let keys: Vec<(&String, String)> = vary.keys().map(|k| (k, normal_key(k))).collect();
    for (i, (key, k)) in keys.iter().enumerate() {
        if let Some((other, _)) = keys[..i].iter().find(|(_, n)| n == k) {
            return Err(Error::Invalid(format!(
                "[sweep.vary] \"{other}\" and \"{key}\" are the same key \"{k}\": give it once"
            )));
        }
    }
    let mut out: Vec<(String, Vec<toml::Value>)> = Vec::new();
    for ((key, k), values) in keys.into_iter().zip(vary.values()) {
        if !k.contains('.') || k.split('.').any(str::is_empty) {
            return Err(Error::Invalid(format!(
                "[sweep.vary] \"{key}\": expected a dotted config key such as \"loading.temperature\""
            )));
        }
        if key.chars().any(char::is_whitespace) {
            return Err(Error::Invalid(format!(
                "[sweep.vary] \"{key}\": a config key has no spaces; write \"{k}\""
            )));
        }
        if k == "sweep" || k.starts_with("sweep.") {
            return Err(Error::Invalid(format!(
                "[sweep.vary] \"{key}\": the sweep's own keys cannot be varied"
            )));
        }
        if taken.contains(&k.as_str()) {
            return Err(Error::Invalid(format!(
                "[sweep.vary] \"{key}\" is an axis of [sweep] already (speed, xi, normal_load, seeds): give its values there"
            )));
        }
        if values.is_empty() {
            return Err(Error::Invalid(format!(
                "[sweep.vary] \"{key}\" is empty: give at least one value"
            )));
        }
        for (i, v) in values.iter().enumerate() {
            if values[..i].iter().any(|w| same_value(v, w)) {
                return Err(Error::Invalid(format!(
                    "[sweep.vary] \"{key}\" lists {v} twice: give each value once (realisations are [sweep] seeds)"
                )));
            }
        }
        out.push((k, values.clone()));
    }
    let combos = out
        .iter()
        .try_fold(1u64, |acc, (_, v)| acc.checked_mul(v.len() as u64))
        .unwrap_or(u64::MAX);
    if combos > MAX_VARY_COMBINATIONS {
        let sizes: Vec<String> = out.iter().map(|(_, v)| v.len().to_string()).collect();
        return Err(Error::Invalid(format!(
            "[sweep.vary] makes {} = {combos} combinations, above the limit of {MAX_VARY_COMBINATIONS}; split the sweep into several",
            sizes.join(" x ")
        )));
    }
    Ok(out)
}

/// A `[sweep.vary]` key as `--set` reads it: its dotted parts trimmed.
fn normal_key(key: &str) -> String {
    key.split('.').map(str::trim).collect::<Vec<_>>().join(".")
}

/// Whether two values of one `[sweep.vary]` list are the same setting
/// (numbers compared by value: `7` and `7.0` are one temperature).
fn same_value(a: &toml::Value, b: &toml::Value) -> bool {
    let number = |v: &toml::Value| match v {
        toml::Value::Integer(i) => Some(*i as f64),
        toml::Value::Float(f) => Some(*f),
        _ => None,
    };
    match (number(a), number(b)) {
        (Some(x), Some(y)) => x == y,
        _ => a == b,
    }
}

/// Every combination of the `vary` values, the last key fastest.
fn combinations(vary: &[(String, Vec<toml::Value>)]) -> Vec<BTreeMap<String, toml::Value>> {
    let mut out = vec![BTreeMap::new()];
    for (key, values) in vary {
        out = out
            .into_iter()
            .flat_map(|c| {
                values.iter().map(move |v| {
                    let mut c = c.clone();
                    c.insert(key.clone(), v.clone());
                    c
                })
            })
            .collect();
    }
    out
}

/// `K/N`: this job runs the points whose index is `K` modulo `N`
/// (`0 <= K < N`, as Slurm's `SLURM_ARRAY_TASK_ID` with `--array=0-(N-1)`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shard {
    pub k: usize,
    pub n: usize,
}

impl Shard {
    /// Every point.
    pub const ALL: Shard = Shard { k: 0, n: 1 };

    /// Whether the point with plan index `index` belongs to this shard.
    pub fn contains(&self, index: usize) -> bool {
        index % self.n == self.k
    }
}

impl std::str::FromStr for Shard {
    type Err = String;

    fn from_str(s: &str) -> std::result::Result<Self, String> {
        let (k, n) = s
            .split_once('/')
            .ok_or_else(|| format!("shard '{s}': expected K/N"))?;
        let k: usize = k
            .trim()
            .parse()
            .map_err(|_| format!("shard '{s}': K is not a number"))?;
        let n: usize = n
            .trim()
            .parse()
            .map_err(|_| format!("shard '{s}': N is not a number"))?;
        if n == 0 || k >= n {
            return Err(format!("shard '{s}': need 0 <= K < N"));
        }
        Ok(Shard { k, n })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn plan() -> SweepPlan {
        SweepPlan::new(&SweepConfig {
            xi_range: Some([1e-4, 1e-1, 7.0]),
            normal_load: Some(vec![0.1, 0.3]),
            seeds: Some(vec![1, 2, 3]),
            ..Default::default()
        })
        .unwrap()
    }

    #[test]
    fn axes_expand_in_a_fixed_order() {
        let p = plan();
        assert_eq!(p.points.len(), 2 * 8 * 3);
        assert_eq!(p.points[0].speed, Sliding::Xi(0.0));
        assert!((p.points[3].speed.value() - 1e-4).abs() < 1e-18);
        assert!((p.points[3 * 7].speed.value() - 1e-1).abs() < 1e-15);
        assert_eq!(p.points[47].normal_load, Some(0.3));
        assert_eq!(p, plan(), "deterministic");
    }

    #[test]
    fn shards_partition_the_points_exactly() {
        let p = plan();
        for n in 1..=7 {
            let mut seen = vec![0; p.points.len()];
            for k in 0..n {
                let s: Shard = format!("{k}/{n}").parse().unwrap();
                for pt in &p.points {
                    if s.contains(pt.index) {
                        seen[pt.index] += 1;
                    }
                }
            }
            assert!(seen.iter().all(|&c| c == 1), "n = {n}: {seen:?}");
        }
        assert!("3/3".parse::<Shard>().is_err());
        assert!("1/0".parse::<Shard>().is_err());
        assert!("a/2".parse::<Shard>().is_err());
    }

    #[test]
    fn vary_values_are_crossed_outermost() {
        let base = plan();
        let mut vary = BTreeMap::new();
        vary.insert(
            "loading.temperature".to_string(),
            vec![toml::Value::Float(7.0), toml::Value::Float(27.0)],
        );
        vary.insert(
            "layer.thickness".to_string(),
            vec![toml::Value::Float(1e-3)],
        );
        let p = SweepPlan::new(&SweepConfig {
            xi_range: Some([1e-4, 1e-1, 7.0]),
            normal_load: Some(vec![0.1, 0.3]),
            seeds: Some(vec![1, 2, 3]),
            vary: Some(vary),
            ..Default::default()
        })
        .unwrap();
        assert_eq!(p.points.len(), 2 * base.points.len());
        assert_eq!(p.vary_combinations().len(), 2);
        let n = base.points.len();
        for (k, b) in base.points.iter().enumerate() {
            for (c, t) in [7.0, 27.0].iter().enumerate() {
                let q = &p.points[c * n + k];
                assert_eq!(
                    (q.speed, q.normal_load, q.seed),
                    (b.speed, b.normal_load, b.seed)
                );
                assert_eq!(q.vary["loading.temperature"], toml::Value::Float(*t));
                assert_eq!(q.vary["layer.thickness"], toml::Value::Float(1e-3));
            }
        }
        // Keys the axes set, of [sweep] itself, undotted or empty: refused.
        for (key, values) in [
            ("loading.speed", vec![toml::Value::Float(1.0)]),
            ("surface.generate.seed", vec![toml::Value::Integer(1)]),
            ("sweep.seeds", vec![toml::Value::Integer(1)]),
            ("temperature", vec![toml::Value::Float(1.0)]),
            ("loading.temperature", vec![]),
        ] {
            let mut vary = BTreeMap::new();
            vary.insert(key.to_string(), values);
            let e = SweepPlan::new(&SweepConfig {
                speed: Some(vec![1.0]),
                seeds: Some(vec![1]),
                vary: Some(vary),
                ..Default::default()
            })
            .unwrap_err()
            .to_string();
            assert!(e.contains(key) && !e.contains('\n'), "{e}");
        }
    }

    #[test]
    fn bad_axes_are_refused() {
        assert!(SweepPlan::new(&SweepConfig::default()).is_err());
        assert!(SweepPlan::new(&SweepConfig {
            xi: Some(vec![1.0]),
            speed: Some(vec![1.0]),
            ..Default::default()
        })
        .is_err());
        assert!(SweepPlan::new(&SweepConfig {
            xi_range: Some([0.0, 1.0, 3.0]),
            ..Default::default()
        })
        .is_err());
    }
}
