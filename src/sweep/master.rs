//! What a merge adds for `[sweep.vary]` and temperature (physics.md
//! section 12): the varied keys as columns of `sweep.csv`, the curve
//! labels, and Grosch's master curve (friction against the reduced speed
//! `a_T v`, Proc. R. Soc. A 274, 21 (1963)), onto which the curves of
//! every temperature collapse exactly in the isothermal model
//! (`mu(v, T) = mu(a_T v, T_ref)`).

use super::row::MergedRow;
use crate::error::Result;
use crate::io::StagedOutput;
use crate::plot::{xy_chart, Mark, Series, XyChart};

/// File name of the master curve.
pub const MASTER_CURVE_FILE: &str = "master_curve.png";

/// Whether the rows come from materials at known temperatures.
fn has_temperature(rows: &[MergedRow]) -> bool {
    rows.iter()
        .any(|r| r.temperature.is_some() && r.shift_factor.is_some())
}

/// The varied keys of `rows`, in name order.
fn keys(rows: &[MergedRow]) -> Vec<String> {
    let mut keys: Vec<String> = rows.iter().flat_map(|r| r.vary.keys().cloned()).collect();
    keys.sort();
    keys.dedup();
    keys
}

/// The columns `sweep.csv` gains after its standard ones: each varied
/// key by its dotted name (the value as TOML writes it), then, for
/// materials at known temperatures, `temperature_c`, `shift_factor` and
/// `reduced_speed_m_s` (`a_T v`). Empty without either, so the table of a
/// plain sweep is unchanged.
pub fn extra_header(rows: &[MergedRow]) -> String {
    let mut cols = keys(rows);
    if has_temperature(rows) {
        cols.extend(["temperature_c", "shift_factor", "reduced_speed_m_s"].map(String::from));
    }
    cols.iter().map(|c| format!(",{c}")).collect()
}

/// The fields of [`extra_header`] for `row`.
pub fn extra_fields(rows: &[MergedRow], row: &MergedRow) -> String {
    let mut out = String::new();
    for k in keys(rows) {
        out.push(',');
        if let Some(v) = row.vary.get(&k) {
            // A TOML string carries quotes; a CSV field with a comma
            // (an array) is quoted.
            let text = v.to_string().replace('"', "'");
            if text.contains(',') {
                out.push_str(&format!("\"{text}\""));
            } else {
                out.push_str(&text);
            }
        }
    }
    if has_temperature(rows) {
        let one = |v: Option<f64>| v.map(|x| format!("{x:.8e}")).unwrap_or_default();
        out.push_str(&format!(
            ",{},{},{}",
            one(row.temperature),
            one(row.shift_factor),
            one(row.shift_factor.map(|a| a * row.speed))
        ));
    }
    out
}

/// Grosch's master curve: the friction of every row against `a_T v`, one
/// series per temperature (and load), with Persson's theory of each
/// temperature shifted alike (`theory`: label of a row group and its
/// curve `(v, mu)`; a row's group is `label(row)`), staged as
/// [`MASTER_CURVE_FILE`]. Drawn when the rows span more than one
/// temperature; returns whether it was drawn.
pub fn master_chart(
    staged: &mut StagedOutput,
    rows: &[MergedRow],
    label: &dyn Fn(&MergedRow) -> String,
    theory: &[(String, Vec<(f64, f64)>)],
) -> Result<bool> {
    let mut temps: Vec<f64> = rows.iter().filter_map(|r| r.temperature).collect();
    temps.sort_by(f64::total_cmp);
    temps.dedup();
    if temps.len() < 2 || !has_temperature(rows) {
        return Ok(false);
    }
    let mut groups: Vec<String> = rows.iter().map(label).collect();
    groups.dedup();
    let mut series = Vec::new();
    for (c, g) in groups.iter().enumerate() {
        let sel: Vec<&MergedRow> = rows
            .iter()
            .filter(|r| label(r) == *g && r.speed > 0.0 && r.shift_factor.is_some())
            .collect();
        let Some(a) = sel.first().and_then(|r| r.shift_factor) else {
            continue;
        };
        // Each row at its own `a_T v`: a heated sweep's rows sit at their
        // effective temperatures, one per speed.
        let mut s = Series::points(
            g.clone(),
            sel.iter()
                .map(|r| (r.shift_factor.unwrap_or(a) * r.speed, r.friction.0))
                .collect(),
            c,
        );
        s.mark = Mark::LineAndPoints;
        s.errors = Some(sel.iter().map(|r| r.friction.1).collect());
        series.push(s);
        let one_temperature = sel.iter().all(|r| r.shift_factor == Some(a));
        if one_temperature {
            if let Some((_, curve)) = theory.iter().find(|(l, _)| l == g) {
                let pts: Vec<(f64, f64)> = curve
                    .iter()
                    .map(|&(v, mu)| (a * v, mu))
                    .filter(|p| p.1.is_finite())
                    .collect();
                if !pts.is_empty() {
                    series.push(Series::line(format!("Persson, {g}"), pts, c));
                }
            }
        } else {
            // Rows at several temperatures: Persson's theory of each row at
            // its own temperature, as the row records it.
            let pts: Vec<(f64, f64)> = sel
                .iter()
                .filter_map(|r| Some((r.shift_factor? * r.speed, r.persson_friction?)))
                .filter(|p| p.1.is_finite())
                .collect();
            if !pts.is_empty() {
                series.push(Series::line(
                    format!("Persson at each row's temperature, {g}"),
                    pts,
                    c,
                ));
            }
        }
    }
    if series.is_empty() {
        return Ok(false);
    }
    xy_chart(
        &staged.path(MASTER_CURVE_FILE),
        &XyChart {
            title: "Master curve (Grosch): friction against a_T v".into(),
            x_label: "a_T v [m/s] (speed reduced to the WLF reference temperature)".into(),
            y_label: "friction coefficient".into(),
            log_x: true,
            log_y: false,
            series,
        },
    )?;
    Ok(true)
}
