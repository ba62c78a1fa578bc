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
}
