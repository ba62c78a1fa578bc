//! The heat of a solved contact (physics.md section 14): its heat source
//! ([`crate::heat::HeatSource`], the creep elements' dissipation or the
//! surface work of the pressure), the temperature rise it causes
//! ([`crate::heat::HeatSolver`]) and the energy balance, the source's
//! total against the friction power `mu F_N v`: `viscoslide heat
//! --from-run`, Python's `Result.heat` and [`Problem::contact_heating`].
//! The coupled solve (the effective-temperature fixed point,
//! `crate::heating`) evaluates the same source and rise at each
//! isothermal solve.

use serde_json::{json, Value};

use crate::error::Result;
use crate::heat::{
    Conduction, DepthRule, HeatDomain, HeatSetup, HeatSolver, HeatSource, SourceKind, Temperature,
    AT_REST_NOTE,
};
use crate::response::{Grid, SlidingResponse};

use super::{invalid, Problem, Solution};

/// Heat balance `|Int Q dV / (mu F_N v) - 1|` above which a warning is
/// given: the default depth layers hold it to 1e-3 (physics.md section 14).
const BALANCE_WARNING: f64 = 1e-2;

/// A warning where a heat source's total `heat_w` \[W\] and the friction's
/// power `friction_power_w` \[W\] differ by more than [`BALANCE_WARNING`],
/// or where a source carries heat against a friction power that is zero
/// or negative (fields and a friction that do not belong together).
pub(crate) fn balance_warning(heat_w: f64, friction_power_w: f64) -> Option<String> {
    let balance = heat_w / friction_power_w - 1.0;
    let off = if friction_power_w > 0.0 {
        balance.abs() > BALANCE_WARNING
    } else {
        heat_w > 0.0
    };
    off.then(|| {
        format!(
            "the heat source carries {heat_w:.6e} W against the friction's power mu F_N v = {friction_power_w:.6e} W ({balance:+.2e} relative): the depth layers or the grid do not resolve the dissipation"
        )
    })
}

/// What a contact whose heat source totals `heat_w` \[W\] but carries no
/// heat ([`HeatSource::carries_heat`]) is told instead of an energy
/// balance, which compares round-off with round-off there.
pub(crate) fn no_heat_note(heat_w: f64) -> String {
    format!(
        "the contact dissipates nothing (its heat source totals {heat_w:e} W, round-off of the work it moves: a purely elastic response at this speed, or no contact): every rise is zero"
    )
}

/// The heat source of a solved contact, its temperature rise and its
/// energy balance.
#[derive(Debug, Clone)]
pub struct ContactHeating {
    pub source: HeatSource,
    /// The surface rise `T - T0` \[K\] at the cell centres (the block's
    /// background included on a periodic cell with a block length).
    pub temperature: Temperature,
    /// The source-weighted rise `Theta` \[K\]: `Int theta D dV / Int D dV`
    /// (or weighted by the surface flux), the rise where the heat is
    /// released.
    pub effective_rise: f64,
    /// The source's total power \[W\]: `Int D dV`, or `sum q_s a_x a_y`.
    pub heat_power_w: f64,
    /// The friction power `mu F_N v` \[W\] it is checked against: the
    /// dissipation route's `mu` for the volume source (Appendix A3-A4),
    /// the stencil's (paper Eq. 9) for the surface flux.
    pub friction_power_w: f64,
    /// What the rise leaves out or may overstate, a sentence each
    /// ([`HeatSetup::notes`], [`HeatSource::returned_share_warning`]).
    pub notes: Vec<String>,
}

impl ContactHeating {
    /// The heat of the cell pressures `pressure` \[Pa\] solved on `grid`
    /// under `response`, in a rubber of `conduction`; `block_length` \[m\]
    /// gives a periodic cell its background heating; `friction_power_w`
    /// is the solve's `mu F_N v` by the route matching `kind`. At rest
    /// (speed 0) nothing is dissipated: every rise is zero, with a note
    /// saying so. On a layer, a note where the heat reaches deep into it
    /// (the heat problem is a half-space). `stop` is asked between the
    /// volume source's depth nodes: `true` gives up with the solve's
    /// cancellation ([`crate::solver::SolverError::Cancelled`]).
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        pressure: &[f64],
        grid: &Grid,
        response: &SlidingResponse,
        conduction: Conduction,
        block_length: Option<f64>,
        kind: SourceKind,
        rule: &DepthRule,
        friction_power_w: f64,
        stop: &mut dyn FnMut() -> bool,
    ) -> Result<Self> {
        if block_length.is_some() && !grid.is_periodic() {
            return Err(invalid(
                "a block length is for periodic cells: a pad's steady rise needs none",
            ));
        }
        let setup = HeatSetup {
            grid: *grid,
            conduction,
            speed: response.speed(),
            direction_rad: response.direction_rad(),
            domain: if grid.is_periodic() {
                HeatDomain::Periodic { block_length }
            } else {
                HeatDomain::Pad
            },
        };
        if response.speed() == 0.0 {
            // At rest nothing is dissipated: the zero source has zero rise
            // (as the heated solve's answer at rest, `heating/no_heat.rs`).
            setup.check_at_rest()?;
            let source = HeatSource::from_contact(kind, pressure, grid, response, rule)?;
            let background = matches!(
                setup.domain,
                HeatDomain::Periodic {
                    block_length: Some(_)
                }
            );
            return Ok(Self {
                heat_power_w: source.power(grid.cell_area()),
                source,
                temperature: Temperature {
                    rise: vec![0.0; pressure.len()],
                    background: background.then_some(0.0),
                },
                effective_rise: 0.0,
                // `mu F_N v` at `v = 0`, without the sign of `mu`.
                friction_power_w: 0.0,
                notes: vec![AT_REST_NOTE.to_string()],
            });
        }
        setup.check()?;
        let source = HeatSource::from_contact_until(kind, pressure, grid, response, rule, stop)?;
        let heat_power_w = source.power(grid.cell_area());
        if !heat_power_w.is_finite() {
            // Pressures whose squares (the dissipation) or products with
            // the slopes (the surface work) leave f64: not "no heat".
            let peak = pressure.iter().fold(0.0f64, |m, p| m.max(p.abs()));
            return Err(invalid(format!(
                "the {} heat source is beyond the range of f64 (its total power is {heat_power_w:e} W): pressures up to {peak:e} Pa at {:e} m/s are too large for its arithmetic; give the pressure in Pa of a physical contact",
                kind.name(),
                response.speed()
            )));
        }
        if !source.carries_heat(grid.cell_area()) {
            // Nothing dissipated (a purely elastic response at this speed,
            // whose work flux nets round-off, or no pressure): no rise
            // anywhere, as the heated solve's evaluation answers it.
            return Ok(Self {
                heat_power_w,
                source,
                temperature: Temperature {
                    rise: vec![0.0; pressure.len()],
                    background: setup.contact_time().map(|_| 0.0),
                },
                effective_rise: 0.0,
                friction_power_w,
                notes: vec![no_heat_note(heat_power_w)],
            });
        }
        let mut solver = HeatSolver::new(setup)?;
        let (temperature, effective_rise) = solver.under(&source)?;
        let mut notes = setup.notes();
        notes.extend(balance_warning(heat_power_w, friction_power_w).map(|w| {
            format!("{w}, or the fields and the friction given do not belong together (a run's summary.json edited, or the fields of another solve)")
        }));
        notes.extend(source.returned_share_warning());
        notes.extend(response.layer().and_then(|l| setup.layer_note(l.thickness)));
        Ok(Self {
            heat_power_w,
            source,
            temperature,
            effective_rise,
            friction_power_w,
            notes,
        })
    }

    /// `heat_power_w / friction_power_w - 1`; 0 where both are zero (at
    /// rest).
    pub fn balance(&self) -> f64 {
        if self.heat_power_w == 0.0 && self.friction_power_w == 0.0 {
            return 0.0;
        }
        self.heat_power_w / self.friction_power_w - 1.0
    }

    /// The numbers of `heat.json`: source, rise, balance.
    pub fn report(&self) -> Value {
        let (layers, bounds) = match &self.source {
            HeatSource::Volume { layers, .. } => (Some(layers.count()), Some(layers.bounds())),
            HeatSource::Surface { .. } => (None, None),
        };
        json!({
            "source": self.source.kind().name(),
            "depth_layers": layers,
            "layer_bounds_m": bounds,
            "max_rise_k": self.temperature.max(),
            "mean_rise_k": self.temperature.mean(),
            "min_rise_k": self.temperature.rise.iter().copied().fold(f64::INFINITY, f64::min),
            "background_rise_k": self.temperature.background,
            "effective_rise_k": self.effective_rise,
            "heat_total_w": self.heat_power_w,
            "friction_power_w": self.friction_power_w,
            "energy_balance": self.balance(),
            "notes": self.notes,
        })
    }
}

impl Solution {
    /// The friction power `mu F_N v` \[W\] at `speed` \[m/s\] that a heat
    /// source of `kind` carries exactly: the dissipation route's `mu` for
    /// the volume source (Appendix A3-A4), the stencil's (paper Eq. 9) for
    /// the surface work flux.
    pub(crate) fn friction_power_w(&self, kind: SourceKind, speed: f64) -> f64 {
        let mu = match kind {
            SourceKind::Volume => self.friction_coefficient_dissipation,
            SourceKind::Surface => self.friction_coefficient,
        };
        mu * self.stats.normal_load * speed
    }
}

impl Problem {
    /// The heat of `solution` (solved from this problem) in a rubber of
    /// `conduction` ([`ContactHeating::new`]); adaptive meshes are refused.
    pub fn contact_heating(
        &self,
        solution: &Solution,
        conduction: Conduction,
        block_length: Option<f64>,
        kind: SourceKind,
        rule: &DepthRule,
    ) -> Result<ContactHeating> {
        self.contact_heating_until(solution, conduction, block_length, kind, rule, &mut || {
            false
        })
    }

    /// [`Problem::contact_heating`], asking `stop` between the volume
    /// source's depth nodes ([`ContactHeating::new`]).
    pub fn contact_heating_until(
        &self,
        solution: &Solution,
        conduction: Conduction,
        block_length: Option<f64>,
        kind: SourceKind,
        rule: &DepthRule,
        stop: &mut dyn FnMut() -> bool,
    ) -> Result<ContactHeating> {
        if solution.mesh.is_some() {
            return Err(invalid(
                "the heat source of an adaptive-mesh solve is not computed; solve on a uniform grid",
            ));
        }
        let power = solution.friction_power_w(kind, self.speed);
        ContactHeating::new(
            &solution.fields.pressure,
            &self.grid()?,
            &self.response()?,
            conduction,
            block_length,
            kind,
            rule,
            power,
            stop,
        )
    }
}
