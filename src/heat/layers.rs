//! Depth layers of a volume heat source: the boundaries
//! `0 = z_0 < z_1 < ... < z_L` \[m\] below the surface, the source `Q`
//! \[W/m^3\] constant within each layer on each cell.

use super::error::HeatError;

/// Layer boundaries from the surface down.
#[derive(Debug, Clone, PartialEq)]
pub struct DepthLayers {
    bounds: Vec<f64>,
}

impl DepthLayers {
    /// Layers between consecutive `bounds`: the first must be 0, the rest
    /// finite and increasing.
    pub fn new(bounds: Vec<f64>) -> Result<Self, HeatError> {
        if bounds.len() < 2 {
            return Err(HeatError::Layers(format!(
                "give the surface (0) and at least one depth below it, got {bounds:?}"
            )));
        }
        if bounds[0] != 0.0 {
            return Err(HeatError::Layers(format!(
                "the first boundary must be the surface, 0, got {}",
                bounds[0]
            )));
        }
        if let Some(w) = bounds
            .windows(2)
            .find(|w| !(w[1] > w[0] && w[1].is_finite()))
        {
            return Err(HeatError::Layers(format!(
                "boundaries must be finite and increase, got {} after {}",
                w[1], w[0]
            )));
        }
        Ok(Self { bounds })
    }

    /// `count` layers of equal thickness down to `depth` \[m\].
    pub fn uniform(depth: f64, count: usize) -> Result<Self, HeatError> {
        if count == 0 {
            return Err(HeatError::Empty("the list of depth layers"));
        }
        super::error::positive("the depth of the layers", depth, "m")?;
        Self::new(
            (0..=count)
                .map(|k| depth * k as f64 / count as f64)
                .collect(),
        )
    }

    /// Number of layers.
    pub fn count(&self) -> usize {
        self.bounds.len() - 1
    }

    /// `(top, bottom)` of layer `l` \[m\].
    pub fn layer(&self, l: usize) -> (f64, f64) {
        (self.bounds[l], self.bounds[l + 1])
    }

    /// The boundaries, from the surface down.
    pub fn bounds(&self) -> &[f64] {
        &self.bounds
    }

    /// Every layer's `(top, bottom)`.
    pub fn iter(&self) -> impl Iterator<Item = (f64, f64)> + '_ {
        self.bounds.windows(2).map(|w| (w[0], w[1]))
    }
}

/// Check output depths: finite and `>= 0`.
pub(crate) fn check_depths(depths: &[f64]) -> Result<(), HeatError> {
    if depths.is_empty() {
        return Err(HeatError::Empty("the list of output depths"));
    }
    match depths.iter().find(|z| !(z.is_finite() && **z >= 0.0)) {
        Some(&z) => Err(HeatError::Depth(z)),
        None => Ok(()),
    }
}
