//! What the heated solve reports (physics.md section 14): the rises, the
//! `heating` object of `summary.json` ([`HeatingReport`]), the depth
//! profile's rows, and the heated contact with its outputs
//! ([`HeatedSolution`]: the solve's files plus `temperature.npy`,
//! `temperature.png` and `temperature_depth.csv`).

use serde::Serialize;

use crate::error::Result;
use crate::problem::{ExtraMap, Problem, Solution, SolveExtras};

use super::branches::{Branch, Evaluation};
use super::params::HeatingParams;
use crate::heat::ScaleBand;

/// The temperature rises of the answer \[K\].
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Rises {
    /// `Theta(T_eff)`, the dissipation-weighted rise: `T_eff - T0` to the
    /// search's tolerance (the branch's residual).
    pub effective: f64,
    /// The surface's highest rise.
    pub peak_surface: f64,
    /// The surface rise averaged over the cells in contact.
    pub mean_contact: f64,
    /// The periodic cell's background heating (its mean over a block's
    /// passage); none on a pad.
    pub background: Option<f64>,
}

/// What the heated solve reports (`summary.json`'s `heating`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct HeatingReport {
    /// `T0` \[C\].
    pub ambient_temperature: f64,
    /// `T_eff` of the chosen branch \[C\].
    pub effective_temperature: f64,
    pub temperature_rise: Rises,
    /// `"cold"` or `"hot"`.
    pub chosen_branch: &'static str,
    /// Every self-consistent temperature found in the bracket, coldest
    /// first.
    pub branches: Vec<Branch>,
    /// `[T0, T0 + max_rise]` \[C\].
    pub bracket: [f64; 2],
    /// How the bracket was searched.
    pub search: String,
    /// Isothermal solves spent on the full grid (the answer's).
    pub fixed_point_evaluations: usize,
    /// `Theta(T)` at every temperature solved on the full grid.
    pub evaluations: Vec<Evaluation>,
    /// Isothermal solves spent on the coarse grid that scanned the bracket
    /// (0 where the full grid scanned it).
    pub coarse_evaluations: usize,
    /// That coarse grid's cells `[nx, ny]` (the map's block means), none
    /// where the full grid scanned the bracket (sides below 128 cells).
    pub coarse_grid: Option<[usize; 2]>,
    /// The coarse grid's own `Theta(T)` at every temperature solved there.
    pub coarse_rises: Vec<Evaluation>,
    /// The largest relative difference between the full grid's `Theta` and
    /// the coarse grid's (scaled to agree at `T0`) where both were solved.
    pub coarse_discrepancy: Option<f64>,
    /// `Int Q dV` of the answer \[W\].
    pub heat_total_w: f64,
    /// `mu F_N v` of the answer \[W\].
    pub friction_power_w: f64,
    /// `mu` of the isothermal solve at `T0`, for comparison.
    pub isothermal_friction_coefficient: f64,
    /// Persson's `mu` at `T_eff` (the answer's own estimate), when it
    /// applies.
    pub persson_friction_coefficient: Option<f64>,
    /// `"volume"` or `"surface"`.
    pub source: &'static str,
    /// `"effective"`.
    pub closure: &'static str,
    /// The volume source's octaves of surface modes: each one's share of
    /// the power and the rise at which it dissipates (its own dissipation
    /// over depth weighting the rise where the dissipation is,
    /// [`crate::heat::ScaleBand`]); the shares weight the rises to the
    /// effective rise. Empty for the surface source, which has no depth.
    pub scales: Vec<ScaleBand>,
    /// `lam` \[W/(m K)\].
    pub conductivity: f64,
    /// `kappa` \[m^2/s\].
    pub diffusivity: f64,
    /// `L_b` \[m\], periodic cells.
    pub block_length: Option<f64>,
    /// `v L / kappa` with `L` the map's side along the sliding direction.
    pub peclet: f64,
    /// Where the answer may mislead.
    pub warnings: Vec<String>,
    /// Wall time of the whole heated solve \[s\].
    pub wall_time_s: f64,
    /// Of which the isothermal solves \[s\].
    pub solve_time_s: f64,
    /// Of which the heat sources and rises (the depth profile's included)
    /// \[s\].
    pub heat_time_s: f64,
}

/// A scale's share of the power below which its temperature is not
/// counted among the scales' extremes ([`scale_extremes`]).
const SCALE_SHARE_COUNTED: f64 = 0.01;

/// The coldest and the hottest of the octaves `scales` that carry at least
/// [`SCALE_SHARE_COUNTED`] of the power; none without such octaves (the
/// surface source).
pub(crate) fn scale_extremes(scales: &[ScaleBand]) -> Option<(&ScaleBand, &ScaleBand)> {
    let counted = || {
        scales
            .iter()
            .filter(|s| s.power_share >= SCALE_SHARE_COUNTED)
    };
    let cold = counted().min_by(|a, b| a.rise.total_cmp(&b.rise))?;
    let hot = counted().max_by(|a, b| a.rise.total_cmp(&b.rise))?;
    Some((cold, hot))
}

/// `scale`'s rise, octave and share of the power, in words.
pub(crate) fn scale_text(scale: &ScaleBand) -> String {
    format!(
        "{:.4e} K (|q| {:.3e} to {:.3e} 1/m, {:.1} % of the power)",
        scale.rise,
        scale.wavenumber_min,
        scale.wavenumber_max,
        100.0 * scale.power_share
    )
}

/// The change of the friction across the scales' temperatures above which
/// the single effective temperature is warned of.
const SCALE_SPREAD_WARNING: f64 = 0.1;

/// A warning where the coldest and the hottest of the octaves of modes
/// that carry the power ([`scale_extremes`]) dissipate at rises so far
/// apart that the friction, changing between `mu_ambient` at `T0` and
/// `mu_effective` at `T0 + rise`, would differ by more than
/// [`SCALE_SPREAD_WARNING`] between them. The effective closure is exact
/// to first order where every scale's friction responds alike to
/// temperature (the scales' rises, weighted by their power, average to
/// the effective rise); their spread times the friction's slope measures
/// how much rests on that.
pub(super) fn scales_warning(
    scales: &[ScaleBand],
    rise: f64,
    mu_ambient: f64,
    mu_effective: f64,
) -> Option<String> {
    let (cold, hot) = scale_extremes(scales)?;
    if ![rise, mu_ambient, mu_effective].iter().all(|&x| x > 0.0) {
        return None;
    }
    let slope = (mu_effective / mu_ambient).ln() / rise;
    let change = slope.abs() * (hot.rise - cold.rise);
    if change.is_nan() || change <= SCALE_SPREAD_WARNING {
        return None;
    }
    Some(format!(
        "the scales that carry the power dissipate at rises from {} to {} (heating.scales), and the friction changes by {:.2} % per K between T0 and T_eff: about {:.0} % across that spread; the effective closure gives every scale T_eff, exact only to first order where all scales' friction responds alike to temperature",
        scale_text(cold),
        scale_text(hot),
        100.0 * slope,
        100.0 * change
    ))
}

/// The report's Peclet number `v L / kappa` of `problem` under `params`,
/// `L` the map's side along the sliding direction.
pub(super) fn peclet(problem: &Problem, params: &HeatingParams) -> f64 {
    let s = &problem.surface;
    let (lx, ly) = (s.nx as f64 * s.cell_size, s.ny as f64 * s.cell_size_y);
    let (ex, ey) = crate::response::unit_direction(problem.direction_rad);
    let along = if ex.abs() >= ey.abs() { lx } else { ly };
    problem.speed * along / params.conduction.diffusivity
}

/// Persson's friction coefficient beside `solution`, when his theory
/// applies to it (the report's `persson_friction_coefficient`).
pub(super) fn persson_friction(solution: &Solution) -> Option<f64> {
    solution
        .persson
        .as_ref()
        .ok()
        .map(|p| p.friction_coefficient)
}

/// One depth of the answer's temperature profile.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct DepthRow {
    /// Depth below the surface \[m\].
    pub depth: f64,
    /// The rise averaged over the cell's plane at that depth \[K\].
    pub mean_rise: f64,
    /// Its highest value \[K\].
    pub max_rise: f64,
    /// The volume source averaged over the layer holding that depth
    /// \[W/m^3\] (volume sources; 0 at the surface).
    pub mean_source: f64,
}

/// The heated contact.
#[derive(Debug, Clone)]
pub struct HeatedSolution {
    /// The isothermal solve at `T_eff`: its friction is the heated
    /// friction; its warnings include the heating's.
    pub solution: Solution,
    /// The surface rise `T - T0` at the cell centres \[K\] (C order, axis
    /// 0 = x).
    pub surface_rise: Vec<f64>,
    /// The rise against depth (periodic cells; a pad's rise is solved at
    /// its surface only).
    pub depth_profile: Option<Vec<DepthRow>>,
    pub report: HeatingReport,
}

impl HeatedSolution {
    /// `summary.json`'s `heating` object: the report, and where the depth
    /// profile is.
    pub fn summary(&self) -> serde_json::Value {
        let mut heating = serde_json::to_value(&self.report).expect("the report is serialisable");
        heating["depth_profile"] = match &self.depth_profile {
            Some(_) => "temperature_depth.csv".into(),
            None => "not solved below a pad's surface (periodic cells only)".into(),
        };
        heating
    }

    /// The `heating` object, the temperature map and the depth profile,
    /// for [`Solution::write_with`].
    pub(crate) fn extras(&self) -> SolveExtras {
        let heating = self.summary();
        let mut files = Vec::new();
        if let Some(rows) = &self.depth_profile {
            let mut csv = String::from("depth_m,mean_rise_k,max_rise_k,mean_source_w_m3\n");
            for r in rows {
                csv.push_str(&format!(
                    "{:e},{:e},{:e},{:e}\n",
                    r.depth, r.mean_rise, r.max_rise, r.mean_source
                ));
            }
            files.push(("temperature_depth.csv", csv.into_bytes()));
        }
        SolveExtras {
            summary: vec![("heating", heating)],
            files,
            maps: vec![ExtraMap {
                file: "temperature.png",
                title: format!(
                    "Surface temperature rise (T_eff = {:.3} C, T0 = {} C)",
                    self.report.effective_temperature, self.report.ambient_temperature
                ),
                unit: "T - T0 [K]",
                values: self.surface_rise.clone(),
            }],
        }
    }

    /// Write the answer's outputs into `dir` (all or nothing): the solve's
    /// files, `summary.json` with its `heating` object, `temperature.npy`
    /// and `.png`, and `temperature_depth.csv` on periodic cells.
    pub fn write(&self, dir: &std::path::Path) -> Result<Vec<std::path::PathBuf>> {
        self.solution.write_with(dir, &self.extras())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn band(low: f64, share: f64, rise: f64) -> ScaleBand {
        ScaleBand {
            wavenumber_min: low,
            wavenumber_max: 2.0 * low,
            power_share: share,
            rise,
        }
    }

    /// The friction's slope between T0 and T_eff times the counted
    /// octaves' spread: warned above 10 %, an octave under 1 % of the
    /// power not counted.
    #[test]
    fn the_scales_spread_is_warned_where_the_friction_follows_it() {
        // mu rises by e^0.2 over a 2 K rise: 10 % per K.
        let (mu0, mu1) = (0.1, 0.1 * 0.2f64.exp());
        let scales = [
            band(1e4, 0.005, 0.1),
            band(2e4, 0.3, 1.5),
            band(4e4, 0.695, 2.7),
        ];
        let w = scales_warning(&scales, 2.0, mu0, mu1).expect("12 % across 1.2 K");
        assert!(w.contains("1.5000e0 K") && w.contains("2.7000e0 K"), "{w}");
        assert!(
            w.contains("10.00 % per K") && w.contains("about 12 %"),
            "{w}"
        );
        // 0.9 K apart: 9 %, not warned; the 0.5 % octave would make it 26 %.
        let close = [scales[0], band(2e4, 0.3, 1.8), scales[2]];
        assert!(scales_warning(&close, 2.0, mu0, mu1).is_none());
        // No slope, no rise, no scales: nothing to say.
        assert!(scales_warning(&scales, 2.0, mu0, mu0).is_none());
        assert!(scales_warning(&scales, 0.0, mu0, mu1).is_none());
        assert!(scales_warning(&[], 2.0, mu0, mu1).is_none());
    }
}
