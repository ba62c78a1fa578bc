//! One period of a periodic cell: the rise about the mean, mode by mode
//! (physics.md section 14): a surface flux gives
//! `theta(k, z) = q(k) exp(-m z) / (lam m)`; a volume source on depth
//! layers `theta(k, z) = 1 / (2 lam m) Int [exp(-m |z - z'|) +
//! exp(-m (z + z'))] Q(k, z') dz'`, each layer's integral in closed form
//! ([`super::modes::layer_integral`]). The mean (`k = 0`) is zero here;
//! [`super::background`] gives the block's.
//!
//! The surface multiplier `1 / (lam m)` is applied by the periodic elastic
//! formulation's transforms ([`SpectralEngine`] at the grid's own size,
//! planned once). Depth maps and volume sources are one-shot: each source
//! map is transformed once, each depth's spectrum summed over the layers
//! and transformed back once (`surface/height_fft.rs`).

use num_complex::Complex64;
use rayon::prelude::*;

use super::error::HeatError;
use super::layers::DepthLayers;
use super::modes::{layer_integral, Modes};
use super::setup::HeatSetup;
use crate::operator::SpectralEngine;
use crate::surface::height_fft;

/// The periodic cell's transforms and modes, planned once.
pub(crate) struct PeriodicPlan {
    engine: SpectralEngine<f64>,
    modes: Modes,
    conductivity: f64,
}

impl PeriodicPlan {
    pub fn new(setup: &HeatSetup) -> Self {
        let g = setup.grid;
        let modes = Modes {
            nx: g.nx(),
            ny: g.ny(),
            length: (g.nx() as f64 * g.cell().0, g.ny() as f64 * g.cell().1),
            e: setup.direction(),
            rate: setup.speed / setup.conduction.diffusivity,
        };
        let lam = setup.conduction.conductivity;
        let mut engine = SpectralEngine::new(g.nx(), g.ny(), g.nx(), g.ny());
        engine.set_multiplier(half_spectrum(&modes, |m| 1.0 / (lam * m)));
        Self {
            engine,
            modes,
            conductivity: lam,
        }
    }

    /// The surface rise about the mean \[K\] under `flux` \[W/m^2\].
    pub fn surface(&mut self, flux: &[f64]) -> Vec<f64> {
        let mut rise = vec![0.0; flux.len()];
        self.engine.apply(flux, &mut rise);
        rise
    }

    /// The rise about the mean \[K\] at each depth \[m\] under the surface
    /// `flux` \[W/m^2\].
    pub fn surface_at(&self, flux: &[f64], depths: &[f64]) -> Result<Vec<Vec<f64>>, HeatError> {
        let lam = self.conductivity;
        let spec = self.forward(flux)?;
        depths
            .iter()
            .map(|&z| {
                let out = self.weighted(&spec, |m| (-m * z).exp() / (lam * m));
                self.inverse(out)
            })
            .collect()
    }

    /// The rise about the mean \[K\] at each depth \[m\] under the volume
    /// source `source` \[W/m^3\]: layer `l`'s map at
    /// `source[l * nx * ny..(l + 1) * nx * ny]`.
    pub fn volume(
        &self,
        layers: &DepthLayers,
        source: &[f64],
        depths: &[f64],
    ) -> Result<Vec<Vec<f64>>, HeatError> {
        let lam = self.conductivity;
        let n = self.modes.nx * self.modes.ny;
        let mut sums: Vec<Vec<Complex64>> = Vec::with_capacity(depths.len());
        for (l, bounds) in layers.iter().enumerate() {
            let spec = self.forward(&source[l * n..(l + 1) * n])?;
            for (d, &z) in depths.iter().enumerate() {
                let w = self.weighted(&spec, |m| layer_integral(m, bounds, z) / (2.0 * lam * m));
                match sums.get_mut(d) {
                    Some(sum) => sum.par_iter_mut().zip(&w).for_each(|(s, v)| *s += v),
                    None => sums.push(w),
                }
            }
        }
        sums.into_iter().map(|s| self.inverse(s)).collect()
    }

    fn forward(&self, values: &[f64]) -> Result<Vec<Complex64>, HeatError> {
        height_fft::forward(values, self.modes.nx, self.modes.ny)
            .map_err(|e| HeatError::Transform(e.to_string()))
    }

    /// `f(m)` times the spectrum, mode by mode (0 at `k = 0`).
    fn weighted(
        &self,
        spec: &[Complex64],
        f: impl Fn(Complex64) -> Complex64 + Sync,
    ) -> Vec<Complex64> {
        let nx = self.modes.nx;
        let modes = &self.modes;
        let mut out = vec![Complex64::default(); spec.len()];
        out.par_chunks_mut(nx)
            .zip(spec.par_chunks(nx))
            .enumerate()
            .for_each(|(j, (o, s))| {
                for (i, (o, s)) in o.iter_mut().zip(s).enumerate() {
                    *o = modes
                        .average(i, j, &f)
                        .map_or(Complex64::default(), |w| w * s);
                }
            });
        out
    }

    fn inverse(&self, spec: Vec<Complex64>) -> Result<Vec<f64>, HeatError> {
        let (nx, ny) = (self.modes.nx, self.modes.ny);
        let scale = 1.0 / (nx * ny) as f64;
        let mut out =
            height_fft::inverse(spec, nx, ny).map_err(|e| HeatError::Transform(e.to_string()))?;
        out.par_iter_mut().for_each(|v| *v *= scale);
        Ok(out)
    }
}

/// The multiplier `f(m)` of every mode of the half spectrum (`ny / 2 + 1`
/// columns of `nx` modes, column-major, as [`SpectralEngine`] holds them),
/// 0 at `k = 0`.
fn half_spectrum(modes: &Modes, f: impl Fn(Complex64) -> Complex64 + Sync) -> Vec<Complex64> {
    let nx = modes.nx;
    let mut out = vec![Complex64::default(); (modes.ny / 2 + 1) * nx];
    out.par_chunks_mut(nx).enumerate().for_each(|(j, col)| {
        for (i, v) in col.iter_mut().enumerate() {
            *v = modes.average(i, j, &f).unwrap_or_default();
        }
    });
    out
}
