//! `[loading]`: what presses the bodies together and how fast they slide.

use serde::{Deserialize, Serialize};

/// `[loading]`: what presses the bodies together and how fast they slide.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub struct LoadingConfig {
    /// Normal load `F_N` \[N\].
    pub normal_load: Option<f64>,
    /// Nominal mean pressure `p0 = F_N / A0` \[Pa\] (`A0` the map's area).
    pub mean_pressure: Option<f64>,
    /// Rigid approach `delta` \[m\] (displacement control instead of load).
    pub approach: Option<f64>,
    /// Sliding speed `v` [m/s].
    pub speed: Option<f64>,
    /// Dimensionless speed `xi = v tau / L` (single-relaxation materials;
    /// `tau` the creep time, `L` the map's side along x).
    pub xi: Option<f64>,
    /// Sliding direction, degrees from +x (default 0).
    pub direction_deg: Option<f64>,
    /// Temperature \[C\] of an isothermal solve: every creep time of the
    /// material is scaled by its WLF shift factor `a_T` (physics.md section
    /// 12; needs the material's WLF constants).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub temperature: Option<f64>,
}

impl LoadingConfig {
    /// The sliding speed as given: `speed` or `xi`, exactly one.
    pub fn sliding(&self) -> Result<Sliding, &'static str> {
        match (self.speed, self.xi) {
            (Some(v), None) => Ok(Sliding::Speed(v)),
            (None, Some(xi)) => Ok(Sliding::Xi(xi)),
            (None, None) => Err("[loading] needs speed (m/s) or xi (v tau / L)"),
            _ => Err("[loading] give only one of speed (m/s) and xi"),
        }
    }

    /// Every value given is a finite number: a NaN or an infinity (`inf`
    /// in a file, `--set loading.speed=inf`) is refused in one line naming
    /// its key, before anything converts or solves with it.
    pub fn check_finite(&self) -> Result<(), String> {
        for (key, value, unit) in [
            ("normal_load", self.normal_load, " N"),
            ("mean_pressure", self.mean_pressure, " Pa"),
            ("approach", self.approach, " m"),
            ("speed", self.speed, " m/s"),
            ("xi", self.xi, ""),
            ("direction_deg", self.direction_deg, ""),
            ("temperature", self.temperature, " C"),
        ] {
            if let Some(v) = value.filter(|v| !v.is_finite()) {
                return Err(format!("[loading] {key} = {v}{unit} must be finite"));
            }
        }
        Ok(())
    }

    /// What presses the bodies together as given: at most one of
    /// `normal_load`, `mean_pressure` and `approach` (`None` where none
    /// is).
    pub(crate) fn pressing(&self) -> Result<Option<Pressing>, &'static str> {
        match (self.normal_load, self.mean_pressure, self.approach) {
            (Some(f), None, None) => Ok(Some(Pressing::NormalLoad(f))),
            (None, Some(p), None) => Ok(Some(Pressing::MeanPressure(p))),
            (None, None, Some(d)) => Ok(Some(Pressing::Approach(d))),
            (None, None, None) => Ok(None),
            _ => Err(
                "[loading] give only one of normal_load (N), mean_pressure (Pa) and approach (m)",
            ),
        }
    }

    /// Set the sliding speed, replacing `speed` and `xi`.
    pub fn set_sliding(&mut self, sliding: Sliding) {
        (self.speed, self.xi) = match sliding {
            Sliding::Speed(v) => (Some(v), None),
            Sliding::Xi(x) => (None, Some(x)),
        };
    }

    /// Set the normal load \[N\], replacing `mean_pressure` and `approach`.
    pub fn set_normal_load(&mut self, load: f64) {
        self.normal_load = Some(load);
        self.mean_pressure = None;
        self.approach = None;
    }
}

/// What presses the bodies together, as a user gives it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Pressing {
    /// `F_N` \[N\].
    NormalLoad(f64),
    /// `p0 = F_N / A0` \[Pa\].
    MeanPressure(f64),
    /// The rigid approach \[m\].
    Approach(f64),
}

/// A sliding speed as a user gives it: in m/s, or as the dimensionless
/// `xi = v tau / L`. Serialised as `{"speed": v}` or `{"xi": xi}`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Sliding {
    /// `v` \[m/s\].
    Speed(f64),
    /// `xi = v tau / L`.
    Xi(f64),
}

impl Sliding {
    /// The number as given (m/s or xi).
    pub fn value(&self) -> f64 {
        match *self {
            Sliding::Speed(v) | Sliding::Xi(v) => v,
        }
    }
}

/// The one conversion between a speed `v` \[m/s\] and `xi = v tau / L`
/// (paper Section III): `tau` the creep time of a single-relaxation
/// material, `L` the map's side along x.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct XiScale {
    /// Creep time `tau` \[s\].
    pub creep_time: f64,
    /// Side of the map along x \[m\].
    pub length: f64,
}

impl XiScale {
    /// `v = xi L / tau` \[m/s\].
    pub fn speed(&self, xi: f64) -> f64 {
        xi * self.length / self.creep_time
    }

    /// `xi = v tau / L`.
    pub fn xi(&self, speed: f64) -> f64 {
        speed * self.creep_time / self.length
    }
}
