//! One period of a periodic cell: the rise about the mean, mode by mode
//! (physics.md section 14): a surface flux gives
//! `theta(k, z) = q(k) exp(-m z) / (lam m)`; a volume source on depth
//! layers `theta(k, z) = 1 / (2 lam m) Int [exp(-m |z - z'|) +
//! exp(-m (z + z'))] Q(k, z') dz'`, each layer's integral in closed form
//! ([`super::modes::layer_integral`]). The mean (`k = 0`) is zero here;
//! [`super::background`] gives the block's.
//!
//! `1 / (lam m)` is taken as `(1 / m) / lam`: the complex reciprocal
//! squares its argument, and `|lam m|^2` leaves f64 for conductivities
//! near its range whose rises it holds.
//!
//! The surface multiplier `1 / (lam m)` is applied by the periodic elastic
//! formulation's transforms ([`SpectralEngine`] at the grid's own size,
//! planned once). Depth maps and volume sources are one-shot: each source
//! map is transformed once, each depth's spectrum summed over the layers
//! and transformed back once (`surface/height_fft.rs`).

use num_complex::Complex64;
use rayon::prelude::*;

use super::density::LayerDensity;
use super::error::HeatError;
use super::layers::{DepthLadder, DepthLayers};
use super::modes::{layer_integral, Modes};
use super::setup::HeatSetup;
use super::sweep::{Sweep, SweepLayers};
use crate::operator::{column_weight, SpectralEngine};
use crate::surface::height_fft::{self, ReducedInverse};

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
        engine.set_multiplier(half_spectrum(&modes, |m| m.inv() / lam));
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
                let out = self.weighted(&spec, |m| (-m * z).exp() * m.inv() / lam);
                self.inverse(out)
            })
            .collect()
    }

    /// The mean and the highest value of the rise about the mean \[K\] at
    /// each depth of `ladder` under the surface `flux` \[W/m^2\]: the maps
    /// of [`PeriodicPlan::surface_at`], one at a time and reduced as they
    /// are transformed back ([`ReducedInverse`]).
    ///
    /// Each mode carries its rise `q(k) exp(-m z) / (lam m)` from one depth
    /// to the next by the factor `exp(-m step dn)`, recomputed only where
    /// the ladder's increment `dn` changes (once per octave of
    /// [`DepthLadder::octaves`]): a product of at most one factor per depth,
    /// each exact to rounding, where every depth used to cost an `exp` per
    /// mode. A mode whose `Re(m) z` exceeds `DEEP_CUT` is left out from
    /// that depth on: its factor is below `exp(-DEEP_CUT)`. The Nyquist
    /// modes' averages over the signs are computed at each depth.
    pub fn surface_extremes(
        &self,
        flux: &[f64],
        ladder: &DepthLadder,
    ) -> Result<Vec<(f64, f64)>, HeatError> {
        let lam = self.conductivity;
        let spec = self.forward(flux)?;
        let (nx, ny) = (self.modes.nx, self.modes.ny);
        let modes = &self.modes;
        let nyquist =
            |i: usize, j: usize| (nx % 2 == 0 && 2 * i == nx) || (ny % 2 == 0 && 2 * j == ny);
        // Per mode: m (NaN at a Nyquist mode), the rise at the last depth
        // (a Nyquist mode: q(k)), and the factor of the current increment.
        let mut state = vec![Carried::default(); spec.len()];
        state
            .par_chunks_mut(nx)
            .zip(spec.par_chunks(nx))
            .enumerate()
            .for_each(|(j, (o, s))| {
                for (i, (o, s)) in o.iter_mut().zip(s).enumerate() {
                    if nyquist(i, j) {
                        o.m = Complex64::new(f64::NAN, 0.0);
                        o.rise = *s;
                        continue;
                    }
                    let mut m = Complex64::default();
                    if modes
                        .average(i, j, |mm| {
                            m = mm;
                            mm
                        })
                        .is_some()
                    {
                        o.m = m;
                        o.rise = s * m.inv() / lam;
                    }
                }
            });
        let scale = 1.0 / (nx * ny) as f64;
        let (step, multiples) = ladder.parts();
        let mut inverse = ReducedInverse::new(nx, ny);
        let mut last = (0, 0);
        let mut rows = Vec::with_capacity(multiples.len());
        for &n in multiples {
            let z = n as f64 * step;
            let dn = n - last.0;
            let fresh = dn != last.1;
            let h = dn as f64 * step;
            let (sum, max) = inverse
                .sum_and_max(&mut state, |j, st, row| {
                    let mut any = false;
                    for (i, (c, o)) in st.iter_mut().zip(row.iter_mut()).enumerate() {
                        if c.m.re.is_nan() {
                            // A Nyquist mode: `rise` holds q(k).
                            *o = modes
                                .average(i, j, |m| (-m * z).exp() * m.inv() / lam)
                                .map_or(Complex64::default(), |w| w * c.rise);
                            any = true;
                            continue;
                        }
                        if c.rise == Complex64::default() {
                            continue;
                        }
                        if c.m.re * z > DEEP_CUT {
                            c.rise = Complex64::default();
                            continue;
                        }
                        if dn > 0 {
                            if fresh {
                                c.factor = (-c.m * h).exp();
                            }
                            c.rise *= c.factor;
                        }
                        *o = c.rise;
                        any = true;
                    }
                    any
                })
                .map_err(|e| HeatError::Transform(e.to_string()))?;
            rows.push((sum * scale / (nx * ny) as f64, max * scale));
            if dn > 0 {
                last = (n, dn);
            }
        }
        Ok(rows)
    }

    /// The rise about the mean \[K\] at each depth \[m\] under the volume
    /// source `source` \[W/m^3\], one layer's spectrum at a time.
    pub fn volume(
        &self,
        layers: &DepthLayers,
        source: &LayerDensity,
        depths: &[f64],
    ) -> Result<Vec<Vec<f64>>, HeatError> {
        let lam = self.conductivity;
        let mut sums: Vec<Vec<Complex64>> = Vec::with_capacity(depths.len());
        let plan = height_fft::Forward::new(self.modes.nx, self.modes.ny);
        let mut rows = Vec::new();
        for (l, bounds) in layers.iter().enumerate() {
            let spec = source.spectrum(l, &plan, &mut rows)?;
            for (d, &z) in depths.iter().enumerate() {
                let w = self.weighted(&spec, |m| {
                    layer_integral(m, bounds, z) * m.inv() / (2.0 * lam)
                });
                match sums.get_mut(d) {
                    Some(sum) => sum.par_iter_mut().zip(&w).for_each(|(s, v)| *s += v),
                    None => sums.push(w),
                }
            }
        }
        sums.into_iter().map(|s| self.inverse(s)).collect()
    }

    /// The surface rise about the mean \[K\] under the volume source
    /// `source` \[W/m^3\] (layers as [`PeriodicPlan::volume`]) and the sum
    /// `sum_l h_l sum_cells theta(z_l) Q_l` \[K W/m^2 per cell\] term by
    /// term (one per layer), `z_l`
    /// layer `l`'s middle: the weighted rise that `Theta` needs, mode by
    /// mode without a depth map (module docs; discrete Parseval,
    /// `sum_x a b = (1 / N) sum_k conj(A) B` over the full spectrum).
    ///
    /// Each mode's rises at the layers' middles come from one sweep down
    /// and one up (`sweep.rs`): `O(L)` per mode for `L` layers, where the
    /// depth maps take `O(L^2)` closed forms.
    ///
    /// With `keep`, also the spectra of the rise about the mean at the
    /// surface and at each layer's middle, each mode's rises at all of
    /// them from the same sweep, written over the layers' spectra: their
    /// extremes ([`PeriodicPlan::extremes`]) are the depth profile, which
    /// the caller may want only once it knows the weighted rise.
    pub fn volume_scan(
        &self,
        layers: &DepthLayers,
        source: &LayerDensity,
        keep: bool,
    ) -> Result<VolumeScan, HeatError> {
        let lam = self.conductivity;
        let (nx, ny) = (self.modes.nx, self.modes.ny);
        let n = nx * ny;
        let nh = height_fft::half_len(ny);
        let mut specs = source.spectra(&height_fft::Forward::new(nx, ny))?;
        let bounds: Vec<(f64, f64)> = layers.iter().collect();
        let sweep_layers = SweepLayers::new(&bounds);
        let modes = &self.modes;
        let mut surface = vec![Complex64::default(); nh * nx];
        // Row `j` of every layer's spectrum, side by side.
        let mut rows: Vec<Vec<&mut [Complex64]>> = (0..nh).map(|_| Vec::new()).collect();
        for spec in specs.iter_mut() {
            for (j, row) in spec.chunks_mut(nx).enumerate() {
                rows[j].push(row);
            }
        }
        let layer_count = bounds.len();
        let column_sums: Vec<Vec<f64>> = rows
            .par_iter_mut()
            .zip(surface.par_chunks_mut(nx))
            .enumerate()
            .map_init(
                || Sweep::new(bounds.len()),
                |sweep, (j, (layer_rows, top))| {
                    let weight = column_weight(j, ny);
                    let mut sums = vec![0.0; layer_count];
                    for (i, out) in top.iter_mut().enumerate() {
                        sweep
                            .q
                            .iter_mut()
                            .zip(layer_rows.iter())
                            .for_each(|(q, r)| *q = r[i]);
                        // The Nyquist average of the mode's multiplier: the
                        // rises are linear in it.
                        let mut variants = 0.0;
                        sweep.clear();
                        let found = modes.average(i, j, |m| {
                            variants += 1.0;
                            sweep.add(m, &sweep_layers, lam)
                        });
                        let Some(t) = found else {
                            if keep {
                                layer_rows
                                    .iter_mut()
                                    .for_each(|r| r[i] = Complex64::default());
                            }
                            continue;
                        };
                        *out = t;
                        let share = weight / variants;
                        for (((s, r), q), (a, b)) in
                            sums.iter_mut().zip(&sweep.rise).zip(&sweep.q).zip(&bounds)
                        {
                            *s += share * (b - a) * (q.conj() * r).re;
                        }
                        if keep {
                            for (r, rise) in layer_rows.iter_mut().zip(&sweep.rise) {
                                r[i] = rise / variants;
                            }
                        }
                    }
                    sums
                },
            )
            .collect();
        drop(rows);
        let mut by_layer = vec![0.0; layer_count];
        for sums in &column_sums {
            by_layer.iter_mut().zip(sums).for_each(|(t, s)| *t += s);
        }
        by_layer.iter_mut().for_each(|t| *t /= n as f64);
        let rises = keep.then(|| LayerRises {
            surface: surface.clone(),
            layers: specs,
        });
        Ok(VolumeScan {
            surface: self.inverse(surface)?,
            by_layer,
            rises,
        })
    }

    /// The mean and the highest value of the rise about the mean \[K\] at
    /// the surface and at each layer's middle from the spectra
    /// [`PeriodicPlan::volume_scan`] kept: the maps of
    /// [`PeriodicPlan::volume`] at those depths, reduced as they are
    /// transformed back ([`ReducedInverse`]).
    pub fn extremes(&self, rises: &LayerRises) -> Result<Vec<(f64, f64)>, HeatError> {
        let (nx, ny) = (self.modes.nx, self.modes.ny);
        let n = nx * ny;
        let scale = 1.0 / n as f64;
        let mut inverse = ReducedInverse::new(nx, ny);
        let mut none = vec![(); height_fft::half_len(ny) * nx];
        std::iter::once(&rises.surface)
            .chain(&rises.layers)
            .map(|spec| {
                let (sum, max) = inverse
                    .sum_and_max(&mut none, |j, _, row| {
                        row.copy_from_slice(&spec[j * nx..(j + 1) * nx]);
                        true
                    })
                    .map_err(|e| HeatError::Transform(e.to_string()))?;
                Ok((sum * scale / n as f64, max * scale))
            })
            .collect()
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

/// One mode's rise carried down the depths of
/// [`PeriodicPlan::surface_extremes`].
#[derive(Debug, Clone, Copy, Default)]
struct Carried {
    m: Complex64,
    rise: Complex64,
    factor: Complex64,
}

/// A mode whose `Re(m) z` exceeds this is left out of the rise at depth
/// `z` ([`PeriodicPlan::surface_extremes`]): `exp(-40) = 4e-18` of its
/// surface amplitude, below the maps' round-off.
const DEEP_CUT: f64 = 40.0;

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

/// What [`PeriodicPlan::volume_scan`] gives: the surface rise about the
/// mean \[K\], each layer's term `h_l sum_cells theta(z_l) Q_l` of the
/// weighted sum, and (when asked to keep them) the spectra of the rise at
/// the surface and at each layer's middle, for [`PeriodicPlan::extremes`].
pub(crate) struct VolumeScan {
    pub surface: Vec<f64>,
    pub by_layer: Vec<f64>,
    pub rises: Option<LayerRises>,
}

/// The half spectra of the rise about the mean at the surface and at each
/// layer's middle ([`PeriodicPlan::volume_scan`]).
pub(crate) struct LayerRises {
    surface: Vec<Complex64>,
    layers: Vec<Vec<Complex64>>,
}
