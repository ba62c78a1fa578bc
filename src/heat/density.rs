//! A volume source's values on its depth layers (physics.md section 14):
//! each layer a map on the grid, plus the parts of it that are
//! band-limited well below the grid's resolution, held as their spectra
//! on coarser grids.
//!
//! The dissipation of a solved contact at depth `z` keeps only the modes
//! with `|q| z` up to a cut (`source/dissipation/band.rs`); deep layers
//! are evaluated on coarser grids and are exactly the trigonometric
//! interpolation of their coarse samples. The heat problem wants each
//! layer's spectrum on the grid, which for such a part is its coarse
//! spectrum placed at the same wavenumbers: a map of it would be one
//! inverse transform of the whole grid made only to be transformed forward
//! again. [`LayerDensity::maps`] gives the maps where they are wanted.

use num_complex::Complex64;
use rayon::prelude::*;

use super::error::{check_map, HeatError};
use crate::operator::signed_index;
use crate::surface::height_fft;

/// One band-limited part of a layer: the half spectrum (`height_fft`
/// layout) of its samples on an `mx x my` grid, as Fourier coefficients
/// (the forward transform over `mx my`), band-limited below that grid's
/// Nyquist modes.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Band {
    size: (usize, usize),
    coefficients: Vec<Complex64>,
}

impl Band {
    /// The part whose samples on the `mx x my` grid `size` are `values`.
    pub(crate) fn from_samples(
        values: &[f64],
        size: (usize, usize),
        plan: &height_fft::Forward,
        rows: &mut Vec<Complex64>,
    ) -> Result<Self, HeatError> {
        let (mx, my) = size;
        let mut coefficients = vec![Complex64::default(); mx * height_fft::half_len(my)];
        plan.run(values, rows, &mut coefficients)
            .map_err(|e| HeatError::Transform(e.to_string()))?;
        let scale = 1.0 / (mx * my) as f64;
        coefficients.iter_mut().for_each(|c| *c *= scale);
        Ok(Self { size, coefficients })
    }

    /// `full += scale * coefficients`, each at its own signed wavenumbers
    /// of the `nx x ny` half spectrum `full` (the coarse grid's Nyquist
    /// modes, round-off below the part's band, left out).
    pub(crate) fn add_into(&self, full: &mut [Complex64], (nx, ny): (usize, usize), scale: f64) {
        let (mx, my) = self.size;
        debug_assert!(mx < nx && my < ny);
        for (j, col) in self.coefficients.chunks(mx).enumerate() {
            if my % 2 == 0 && 2 * j == my {
                continue;
            }
            for (i, v) in col.iter().enumerate() {
                let (kx, nyq) = signed_index(i, mx);
                if nyq {
                    continue;
                }
                let i_full = (kx as isize).rem_euclid(nx as isize) as usize;
                full[j * nx + i_full] += v * scale;
            }
        }
    }

    /// The part's mean over the cell.
    fn mean(&self) -> f64 {
        self.coefficients[0].re
    }
}

/// A volume source \[W/m^3\] on depth layers of an `nx x ny` grid: each
/// layer its map (C order, axis 0 = x; none for a layer of band-limited
/// parts only) plus its band-limited parts.
#[derive(Debug, Clone, PartialEq)]
pub struct LayerDensity {
    nx: usize,
    ny: usize,
    layers: Vec<Layer>,
}

#[derive(Debug, Clone, PartialEq)]
struct Layer {
    map: Option<Vec<f64>>,
    bands: Vec<Band>,
}

impl LayerDensity {
    /// The source whose layers are the maps of `nx x ny` cells laid one
    /// after the other in `maps` (a last partial map is kept as given, for
    /// [`HeatSolver`](super::HeatSolver)'s shape check to name).
    pub fn from_maps(mut maps: Vec<f64>, nx: usize, ny: usize) -> Self {
        // Split from the end: each map copied once, beside the whole.
        let n = (nx * ny).max(1);
        let mut split = Vec::new();
        let partial = maps.len() % n;
        if partial != 0 {
            split.push(maps.split_off(maps.len() - partial));
        }
        while maps.len() > n {
            split.push(maps.split_off(maps.len() - n));
        }
        if !maps.is_empty() {
            maps.shrink_to_fit();
            split.push(maps);
        }
        split.reverse();
        Self::from_layer_maps(split, (nx, ny))
    }

    /// The source whose layers are the maps `maps`.
    pub(crate) fn from_layer_maps(maps: Vec<Vec<f64>>, size: (usize, usize)) -> Self {
        let bands = vec![Vec::new(); maps.len()];
        Self::with_bands(size, maps.into_iter().map(Some).collect(), bands)
    }

    /// The source of per-layer maps `maps` (`None` for a layer of parts
    /// only) and band-limited parts `bands`.
    pub(crate) fn with_bands(
        (nx, ny): (usize, usize),
        maps: Vec<Option<Vec<f64>>>,
        bands: Vec<Vec<Band>>,
    ) -> Self {
        debug_assert!(maps.len() == bands.len());
        let layers = maps
            .into_iter()
            .zip(bands)
            .map(|(map, bands)| Layer { map, bands })
            .collect();
        Self { nx, ny, layers }
    }

    /// The grid's `(nx, ny)`.
    pub fn size(&self) -> (usize, usize) {
        (self.nx, self.ny)
    }

    /// The number of layers.
    pub fn layer_count(&self) -> usize {
        self.layers.len()
    }

    /// Each layer's whole map \[W/m^3\], one after the other: the maps
    /// given, with each band-limited part transformed onto the grid.
    pub fn maps(&self) -> Result<Vec<f64>, HeatError> {
        let (nx, ny) = (self.nx, self.ny);
        let n = nx * ny;
        let mut maps = Vec::with_capacity(n * self.layers.len());
        let inverse = height_fft::Inverse::new(nx, ny);
        let mut spec = Vec::new();
        let (mut rows, mut field) = (Vec::new(), Vec::new());
        for layer in &self.layers {
            let start = maps.len();
            match &layer.map {
                Some(m) => maps.extend_from_slice(m),
                None => maps.resize(start + n, 0.0),
            }
            if layer.bands.is_empty() {
                continue;
            }
            spec.clear();
            spec.resize(nx * height_fft::half_len(ny), Complex64::default());
            field.resize(n, 0.0);
            layer
                .bands
                .iter()
                .for_each(|b| b.add_into(&mut spec, (nx, ny), 1.0));
            inverse
                .run(&mut spec, &mut rows, &mut field)
                .map_err(|e| HeatError::Transform(e.to_string()))?;
            maps[start..]
                .par_iter_mut()
                .zip(&field)
                .for_each(|(m, f)| *m += f);
        }
        Ok(maps)
    }

    /// Each layer's half spectrum on the grid ([`Self::spectrum`]), all
    /// at once. `plan` is the grid's forward transform.
    pub(crate) fn spectra(
        &self,
        plan: &height_fft::Forward,
    ) -> Result<Vec<Vec<Complex64>>, HeatError> {
        let mut rows = Vec::new();
        (0..self.layers.len())
            .map(|l| self.spectrum(l, plan, &mut rows))
            .collect()
    }

    /// Layer `l`'s half spectrum on the grid, unnormalised (the forward
    /// transform of its whole map): its map's transform plus each part's
    /// coefficients times the cells. `plan` is the grid's forward
    /// transform, `rows` its work space.
    pub(crate) fn spectrum(
        &self,
        l: usize,
        plan: &height_fft::Forward,
        rows: &mut Vec<Complex64>,
    ) -> Result<Vec<Complex64>, HeatError> {
        let (nx, ny) = (self.nx, self.ny);
        let layer = &self.layers[l];
        let mut spec = vec![Complex64::default(); nx * height_fft::half_len(ny)];
        if let Some(map) = &layer.map {
            plan.run(map, rows, &mut spec)
                .map_err(|e| HeatError::Transform(e.to_string()))?;
        }
        for b in &layer.bands {
            b.add_into(&mut spec, (nx, ny), (nx * ny) as f64);
        }
        Ok(spec)
    }

    /// Each layer's sum over the cells \[W/m^3\] (a part's sum is its
    /// constant coefficient times the cells).
    pub fn layer_sums(&self) -> Vec<f64> {
        let n = (self.nx * self.ny) as f64;
        self.layers
            .iter()
            .map(|layer| {
                let map: f64 = layer.map.iter().flatten().sum();
                let parts: f64 = layer.bands.iter().map(Band::mean).sum();
                map + parts * n
            })
            .collect()
    }

    /// Each layer's mean over the cell \[W/m^3\].
    pub fn layer_means(&self) -> Vec<f64> {
        let n = (self.nx * self.ny).max(1) as f64;
        self.layer_sums().into_iter().map(|s| s / n).collect()
    }

    /// Refused in one line unless there are `expected_layers` layers, each
    /// map of the grid's cells, and every value is finite.
    pub(crate) fn check(&self, expected_layers: usize) -> Result<(), HeatError> {
        let (nx, ny) = (self.nx, self.ny);
        let n = nx * ny;
        let found: usize = self
            .layers
            .iter()
            .map(|l| l.map.as_ref().map_or(n, Vec::len))
            .sum();
        let whole = self
            .layers
            .iter()
            .all(|l| l.map.as_ref().is_none_or(|m| m.len() == n));
        if self.layers.len() != expected_layers || !whole {
            return Err(HeatError::Shape {
                name: "the volume source",
                found,
                nx,
                ny,
                expected: expected_layers * n,
            });
        }
        for (l, layer) in self.layers.iter().enumerate() {
            if let Some(map) = &layer.map {
                check_map("the volume source", map, (nx, ny), Some(l))?;
            }
            let finite = |b: &Band| {
                b.coefficients
                    .iter()
                    .all(|c| c.re.is_finite() && c.im.is_finite())
            };
            if !layer.bands.iter().all(finite) {
                return Err(HeatError::OutOfRange(format!(
                    "the volume source's layer {l} is not finite: its band-limited part has a coefficient beyond the range of f64"
                )));
            }
        }
        Ok(())
    }

    /// The bytes its values hold.
    #[cfg(test)]
    pub(crate) fn bytes(&self) -> usize {
        self.layers
            .iter()
            .map(|l| {
                8 * l.map.as_ref().map_or(0, Vec::len)
                    + 16 * l.bands.iter().map(|b| b.coefficients.len()).sum::<usize>()
            })
            .sum()
    }
}
