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

/// Output depths at integer multiples of one step, `0 <= n_0 < n_1 < ...`
/// (`z_i = step n_i`): between consecutive depths a mode's rise changes by
/// the factor `exp(-m step (n_i - n_{i-1}))`, which a run of equal
/// increments computes once ([`super::periodic::PeriodicPlan::surface_extremes`]).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct DepthLadder {
    step: f64,
    multiples: Vec<u64>,
}

impl DepthLadder {
    /// The multiples `multiples` of `step` \[m\] (finite, positive),
    /// increasing.
    pub fn new(step: f64, multiples: Vec<u64>) -> Result<Self, HeatError> {
        if !(step.is_finite() && step > 0.0) {
            return Err(HeatError::Depth(step));
        }
        if multiples.is_empty() {
            return Err(HeatError::Empty("the list of output depths"));
        }
        if let Some(w) = multiples.windows(2).find(|w| w[1] <= w[0]) {
            return Err(HeatError::Layers(format!(
                "output depths must increase, got {} steps after {}",
                w[1], w[0]
            )));
        }
        Ok(Self { step, multiples })
    }

    /// The surface, then `per_octave` depths per octave (a power of two)
    /// from `shallow` down to the first at or past `deep` (\[m\], `0 <
    /// shallow < deep`): within each octave `[s 2^k, s 2^(k+1))` the depths
    /// are evenly spaced, so consecutive depths are `1 + 1 / per_octave` to
    /// `1 + 1 / (2 per_octave - 1)` apart in ratio, and each octave is one
    /// run of equal increments.
    pub fn octaves(shallow: f64, deep: f64, per_octave: u64) -> Result<Self, HeatError> {
        if !(shallow.is_finite() && shallow > 0.0) {
            return Err(HeatError::Depth(shallow));
        }
        if !(deep.is_finite() && deep > shallow) {
            return Err(HeatError::Depth(deep));
        }
        assert!(per_octave.is_power_of_two(), "a power of two per octave");
        let step = shallow / per_octave as f64;
        let (mut n, mut stride) = (per_octave, 1);
        let mut multiples = vec![0];
        loop {
            multiples.push(n);
            if n as f64 * step >= deep {
                break;
            }
            n += stride;
            if n == 2 * per_octave * stride {
                stride *= 2;
            }
        }
        Self::new(step, multiples)
    }

    /// The depths \[m\].
    pub fn depths(&self) -> Vec<f64> {
        self.multiples
            .iter()
            .map(|&n| n as f64 * self.step)
            .collect()
    }

    /// The step \[m\] and the multiples.
    pub fn parts(&self) -> (f64, &[u64]) {
        (self.step, &self.multiples)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The profile's ladder: the surface, then 8 evenly spaced depths per
    /// octave from `shallow` (ratios 1.067-1.125) to the first depth at or
    /// past `deep`; the increments constant within an octave.
    #[test]
    fn octaves_are_geometric_runs_of_equal_steps() {
        let ladder = DepthLadder::octaves(1e-7, 1.3e-4, 8).unwrap();
        let z = ladder.depths();
        assert_eq!(z[0], 0.0);
        assert_eq!(z[1], 1e-7);
        assert!(z[z.len() - 2] < 1.3e-4 && z[z.len() - 1] >= 1.3e-4);
        // 1300 = 2^10.34: the surface, 10 whole octaves and 4 depths of
        // the 11th (up to 1408 = 1.1 2^10).
        assert_eq!(z.len(), 1 + 8 * 10 + 4);
        for w in z[1..].windows(2) {
            let r = w[1] / w[0];
            assert!(
                (1.0 + 1.0 / 15.0 - 1e-12..=1.125 + 1e-12).contains(&r),
                "{r}"
            );
        }
        let (_, n) = ladder.parts();
        let steps: Vec<u64> = n[1..].windows(2).map(|w| w[1] - w[0]).collect();
        assert_eq!(&steps[..9], &[1, 1, 1, 1, 1, 1, 1, 1, 2]);
        assert_eq!(steps.iter().filter(|&&s| s == 4).count(), 8);
        assert!(DepthLadder::octaves(1e-3, 1e-4, 8).is_err());
        assert!(DepthLadder::octaves(0.0, 1e-4, 8).is_err());
        assert!(DepthLadder::new(1e-7, vec![3, 3]).is_err());
    }
}
