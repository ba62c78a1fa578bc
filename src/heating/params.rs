//! `[heating]` typed and checked against the problem it heats: every
//! default stated here, every refusal one line naming the key.

use crate::config::HeatingConfig;
use crate::config::{Formulation, MeshKind};
use crate::error::{Error, Result};
use crate::heat::{Conduction, HeatDomain, HeatSetup, SourceKind};
use crate::problem::Problem;

use super::branches::BranchSearch;

/// The bracket's default height above the ambient temperature \[K\].
pub(crate) const DEFAULT_MAX_RISE: f64 = 100.0;
/// The default tolerance on `|T0 + Theta(T) - T|` \[K\].
pub(crate) const DEFAULT_TOLERANCE: f64 = 1e-3;
/// Ratio of consecutive rises scanned for sign changes.
const SCAN_RATIO: f64 = 3.0;
/// At most this many isothermal solves per heated solve.
const MAX_EVALUATIONS: usize = 40;

/// Which self-consistent temperature is the answer.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BranchChoice {
    /// The coldest stable root: the branch a contact reaches as its speed
    /// rises from rest.
    Cold,
    /// The hottest stable root: the branch after the jump, as the speed
    /// falls from above the fold.
    Hot,
}

impl BranchChoice {
    /// The name used in configs and reports.
    pub fn name(self) -> &'static str {
        match self {
            BranchChoice::Cold => "cold",
            BranchChoice::Hot => "hot",
        }
    }
}

/// A checked `[heating]` section.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HeatingParams {
    pub conduction: Conduction,
    /// The block's length along the sliding direction \[m\] (periodic
    /// cells).
    pub block_length: Option<f64>,
    pub source: SourceKind,
    pub branch: BranchChoice,
    /// Ambient temperature `T0` \[C\]: `[loading] temperature`.
    pub ambient: f64,
    /// The bracket is `[T0, T0 + max_rise]` \[K\].
    pub max_rise: f64,
    /// Accepted `|T0 + Theta(T) - T|` \[K\].
    pub tolerance: f64,
    /// Scan the bracket on a coarse grid and close its roots on the full
    /// one (`true`, the default: grids of 128 cells a side and more), or
    /// scan it on the full grid (physics.md section 14; the rule that
    /// decides between the two answers is in `src/heating/two_level.rs`).
    pub coarse_scan: bool,
}

fn invalid(msg: impl Into<String>) -> Error {
    Error::Invalid(msg.into())
}

fn positive(key: &str, value: Option<f64>, unit: &str) -> Result<Option<f64>> {
    match value {
        Some(v) if !(v.is_finite() && v > 0.0) => Err(invalid(format!(
            "[heating] {key} = {v} {unit} must be positive and finite"
        ))),
        v => Ok(v),
    }
}

impl HeatingParams {
    /// `[heating]` for `problem`, whose material is at the ambient
    /// temperature `ambient` (`[loading] temperature`, `None` when not
    /// given). `Ok(None)` when the section says `enabled = false`.
    pub fn from_config(
        cfg: &HeatingConfig,
        problem: &Problem,
        ambient: Option<f64>,
    ) -> Result<Option<Self>> {
        // The values are checked whether or not the section is enabled:
        // a disabled section (a sweep's isothermal points, or
        // `--set heating.enabled=false`) holds the same keys, which must
        // not be wrong unnoticed.
        let conductivity = positive("conductivity", cfg.conductivity, "W/(m K)")?;
        let density = positive("density", cfg.density, "kg/m^3")?;
        let specific_heat = positive("specific_heat", cfg.specific_heat, "J/(kg K)")?;
        let diffusivity = positive("diffusivity", cfg.diffusivity, "m^2/s")?;
        if diffusivity.is_some() && (density.is_some() || specific_heat.is_some()) {
            return Err(invalid(
                "[heating] give diffusivity or density and specific_heat, not both",
            ));
        }
        let block_length = positive("block_length", cfg.block_length, "m")?;
        let source = cfg
            .source
            .as_deref()
            .map(|name| {
                name.parse::<SourceKind>().map_err(|_| {
                    invalid(format!(
                        "[heating] source = \"{name}\": expected \"volume\" or \"surface\""
                    ))
                })
            })
            .transpose()?;
        match cfg.closure.as_deref().unwrap_or("effective") {
            "effective" => {}
            other => {
                return Err(invalid(format!(
                    "[heating] closure = \"{other}\": expected \"effective\" (one dissipation-weighted temperature)"
                )))
            }
        }
        let branch = match cfg.branch.as_deref().unwrap_or("cold") {
            "cold" => BranchChoice::Cold,
            "hot" => BranchChoice::Hot,
            other => {
                return Err(invalid(format!(
                    "[heating] branch = \"{other}\": expected \"cold\" or \"hot\""
                )))
            }
        };
        let max_rise = positive("max_rise", cfg.max_rise, "K")?.unwrap_or(DEFAULT_MAX_RISE);
        let tolerance = positive("tolerance", cfg.tolerance, "K")?.unwrap_or(DEFAULT_TOLERANCE);
        if cfg.enabled == Some(false) {
            return Ok(None);
        }
        let conductivity = conductivity
            .ok_or_else(|| invalid("[heating] needs conductivity (W/(m K); rubber 0.2-0.3)"))?;
        let diffusivity = match (diffusivity, density, specific_heat) {
            (Some(k), _, _) => k,
            (None, Some(rho), Some(c)) => {
                let k = conductivity / (rho * c);
                if !(k.is_finite() && k > 0.0) {
                    return Err(invalid(format!(
                        "[heating] conductivity / (density x specific_heat) = {conductivity} / ({rho} x {c}) = {k} m^2/s, the diffusivity, is beyond the range of f64: give diffusivity (m^2/s; rubber about 1e-7) instead"
                    )));
                }
                k
            }
            (None, _, _) => {
                return Err(invalid(
                    "[heating] needs diffusivity (m^2/s; rubber about 1e-7) or density (kg/m^3) and specific_heat (J/(kg K))",
                ))
            }
        };
        let periodic = problem.formulation == Formulation::Periodic;
        if periodic && block_length.is_none() {
            return Err(invalid(
                "[heating] block_length (m) is needed with formulation = \"periodic\": the periodic cell's mean heating is the block's background heating over its passage (physics.md section 14)",
            ));
        }
        if !periodic && block_length.is_some() {
            return Err(invalid(
                "[heating] block_length applies to periodic cells; a finite pad's heat problem is steady without it: remove it or use formulation = \"periodic\"",
            ));
        }
        // The volume source is solved on periodic half-spaces (the heat
        // module has no buried source on a pad, and a layer's stress is
        // not the half-space's): the default follows.
        let layered = problem.layer.is_some();
        let source = match source.unwrap_or(SourceKind::default_for(periodic, layered)) {
            SourceKind::Volume if layered => {
                return Err(invalid(
                    "[heating] source = \"volume\" (the creep elements' dissipation on depth layers) is solved on a half-space, whose stress a [layer] does not have: use source = \"surface\" (the default with a layer)",
                ))
            }
            SourceKind::Volume if periodic => SourceKind::Volume,
            SourceKind::Volume => {
                return Err(invalid(
                    "[heating] source = \"volume\" (the creep elements' dissipation on depth layers) is solved on periodic cells only: use source = \"surface\" on a finite pad, or formulation = \"periodic\"",
                ))
            }
            SourceKind::Surface => SourceKind::Surface,
        };
        if problem.mesh == MeshKind::Adaptive {
            return Err(invalid(
                "[heating] needs a uniform grid (the heat source of an adaptive mesh is not computed): use mesh = \"uniform\"",
            ));
        }
        if problem.material.wlf.is_none() {
            return Err(invalid(
                "[heating] needs the material's WLF constants (the friction's feedback is the modulus at the heated temperature): give [material] wlf = [C1, C2 (K), T_ref (C)]",
            ));
        }
        let ambient = ambient.ok_or_else(|| {
            invalid("[heating] needs [loading] temperature (C): the ambient temperature T0 the rubber is heated from")
        })?;
        let params = Self {
            conduction: Conduction {
                conductivity,
                diffusivity,
            },
            block_length,
            source,
            branch,
            ambient,
            max_rise,
            tolerance,
            coarse_scan: true,
        };
        // The heat problem at this speed (the block holds the cell, a
        // pad's cell Peclet number is within its limit): refused here,
        // before any solve, as for every point of a Python sweep.
        params
            .heat_setup(problem)?
            .check_sliding_or_at_rest()
            .map_err(|e| invalid(format!("[heating] {e}")))?;
        Ok(Some(params))
    }

    /// The heat problem of `problem`'s grid with these parameters.
    pub(crate) fn heat_setup(&self, problem: &Problem) -> Result<HeatSetup> {
        let grid = problem.grid()?;
        let domain = if grid.is_periodic() {
            HeatDomain::Periodic {
                block_length: self.block_length,
            }
        } else {
            HeatDomain::Pad
        };
        Ok(HeatSetup {
            grid,
            conduction: self.conduction,
            speed: problem.speed,
            direction_rad: problem.direction_rad,
            domain,
        })
    }

    /// The root search these parameters ask for.
    pub(crate) fn search(&self) -> BranchSearch {
        BranchSearch {
            t0: self.ambient,
            max_rise: self.max_rise,
            scan_ratio: SCAN_RATIO,
            tolerance: self.tolerance,
            max_evaluations: MAX_EVALUATIONS,
        }
    }
}
