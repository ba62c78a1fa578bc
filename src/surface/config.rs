//! The `[surface]` section of a config.
//!
//! ```toml
//! [surface]                 # either a file ...
//! file = "heights.npy"      # .npy (float64/float32) or text matrix, m
//! length = 0.01             # side along x, m
//!
//! [surface.generate]        # ... or a generated self-affine surface
//! n = 512                   # cells along x (and y unless `ny` is given)
//! ny = 512                  # optional
//! length = 0.01             # side along x, m (or [surface] length)
//! hurst = 0.8               # 0 < H <= 1
//! scales = 64               # N: q1 = N q_L ... or q1 = 4.0e4 (1/m)
//! ql = 628.3                # optional lower cut-off, 1/m (default 2 pi / L)
//! rolloff_q0 = 1.3e3        # optional roll-off wavenumber, 1/m
//! rms_height = 1e-5         # m ... or rms_slope = 0.1
//! seed = 7
//! anisotropy = { ratio = 2.0, angle_deg = 30.0 }   # optional
//!
//! # ... or a surface following a tabulated PSD (q 1/m, C m^4 columns):
//! # [surface.generate] with n, ny, length, seed and psd = "psd.csv" only
//! ```
//!
//! A `file` may be `.x3p`, `.gwy` (sizes from the file; `length` optional),
//! `.npy` or a text matrix (`length` needed); `format = "x3p"` overrides the
//! extension, `length_y` gives a non-square side for `.npy`/text, and
//! `fill_missing = true` fills missing points by harmonic interpolation.

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::generate::{Anisotropy, GenerateParams, Normalisation, UpperCutoff};
use super::{HeightMap, MissingData, ReadOptions, SurfaceError, SurfaceFormat, SynthParams};

/// `[surface]`: a height map from `file` (with `length`, m), or generated
/// from `[surface.generate]`; exactly one of the two.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub struct SurfaceConfig {
    /// `.npy` (or plain-text) height map, heights in m at cell centres;
    /// relative to the config file's directory.
    pub file: Option<PathBuf>,
    /// Side of the map along x \[m\]; cells are square.
    pub length: Option<f64>,
    /// Generate a self-affine surface instead of reading one.
    pub generate: Option<GenerateConfig>,
    /// A rigid sphere instead (the Hertz paraboloid), for smooth contacts.
    pub sphere: Option<SphereConfig>,
    /// File format overriding the extension of `file`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub format: Option<SurfaceFormat>,
    /// Side of `file` along y \[m\] (`.npy`/text; default square cells).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub length_y: Option<f64>,
    /// Fill missing points of `file` by harmonic interpolation.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fill_missing: Option<bool>,
}

/// `[surface.sphere]`: the paraboloid `z = -(x^2 + y^2) / (2 R)` of a sphere
/// of radius `R` (the Hertz approximation, valid while the contact radius is
/// much smaller than `R`), centred on an `n x n` map of side `length`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SphereConfig {
    /// Cells per side.
    pub n: usize,
    /// Side of the map \[m\].
    pub length: f64,
    /// Sphere radius `R` \[m\].
    pub radius: f64,
}

impl SphereConfig {
    /// The height map of the paraboloid at the cell centres.
    pub fn height_map(&self) -> Result<HeightMap, SurfaceError> {
        if self.n < 2
            || !(self.length.is_finite() && self.length > 0.0)
            || !(self.radius.is_finite() && self.radius > 0.0)
        {
            return Err(SurfaceError::Invalid(format!(
                "[surface.sphere] needs n >= 2, length > 0 (m) and radius > 0 (m); got n = {}, length = {}, radius = {}",
                self.n, self.length, self.radius
            )));
        }
        let a = self.length / self.n as f64;
        let mut heights = vec![0.0; self.n * self.n];
        for i in 0..self.n {
            for j in 0..self.n {
                let x = (i as f64 + 0.5) * a - 0.5 * self.length;
                let y = (j as f64 + 0.5) * a - 0.5 * self.length;
                heights[i * self.n + j] = -(x * x + y * y) / (2.0 * self.radius);
            }
        }
        HeightMap::new(self.n, self.n, self.length, heights)
    }
}

/// `anisotropy = { ratio, angle_deg }` (see [`Anisotropy`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AnisotropyConfig {
    /// Stretch factor `s > 0` along `e(theta)`.
    pub ratio: f64,
    /// `theta` \[degrees\] from +x.
    pub angle_deg: f64,
}

/// `[surface.generate]`: parameters of [`super::generate`]. Every key is
/// optional in the type so that command-line flags can be merged on top;
/// [`GenerateConfig::params`] checks which are required.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub struct GenerateConfig {
    /// Cells along x (and along y unless `ny` is given), `>= 8`.
    pub n: Option<usize>,
    /// Cells along y.
    pub ny: Option<usize>,
    /// Side along x \[m\].
    pub length: Option<f64>,
    /// Hurst exponent.
    pub hurst: Option<f64>,
    /// Number of scales `N` (`q1 = N q_L`); exclusive with `q1`.
    pub scales: Option<f64>,
    /// Upper cut-off [1/m]; exclusive with `scales`.
    pub q1: Option<f64>,
    /// Lower cut-off `q_L` [1/m]; default `2 pi / length`.
    pub ql: Option<f64>,
    /// Roll-off wavenumber `q0` [1/m]; default `q_L` (no roll-off).
    pub rolloff_q0: Option<f64>,
    /// rms height \[m\]; exclusive with `rms_slope`.
    pub rms_height: Option<f64>,
    /// rms slope; exclusive with `rms_height`.
    pub rms_slope: Option<f64>,
    /// Seed of the random phases; default 0.
    pub seed: Option<u64>,
    /// Optional anisotropic stretch.
    pub anisotropy: Option<AnisotropyConfig>,
    /// A tabulated PSD (CSV, q \[1/m\], C \[m^4\]) to follow instead of the
    /// self-affine formula (relative to the config's directory).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub psd: Option<PathBuf>,
}

impl GenerateConfig {
    /// With `psd` set: the table's path and the grid and seed of the
    /// synthesis ([`super::generate_from_table`]); `None` without `psd`.
    /// The self-affine keys cannot be combined with `psd`.
    pub fn synth_params(
        &self,
        fallback_length: Option<f64>,
    ) -> Result<Option<(PathBuf, SynthParams)>, SurfaceError> {
        let Some(psd) = &self.psd else {
            return Ok(None);
        };
        let extra: Vec<&str> = [
            (self.hurst.is_some(), "hurst"),
            (self.scales.is_some(), "scales"),
            (self.q1.is_some(), "q1"),
            (self.ql.is_some(), "ql"),
            (self.rolloff_q0.is_some(), "rolloff_q0"),
            (self.rms_height.is_some(), "rms_height"),
            (self.rms_slope.is_some(), "rms_slope"),
            (self.anisotropy.is_some(), "anisotropy"),
        ]
        .into_iter()
        .filter_map(|(g, k)| g.then_some(k))
        .collect();
        if !extra.is_empty() {
            return Err(SurfaceError::Invalid(format!(
                "[surface.generate] psd = {:?} follows the table; remove {}",
                psd.display().to_string(),
                extra.join(", ")
            )));
        }
        let n = self.n.ok_or_else(|| {
            SurfaceError::Invalid("[surface.generate] needs `n` (cells along x)".into())
        })?;
        let length = self.length.or(fallback_length).ok_or_else(|| {
            SurfaceError::Invalid("[surface.generate] needs `length` (side along x, m)".into())
        })?;
        Ok(Some((
            psd.clone(),
            SynthParams {
                nx: n,
                ny: self.ny.unwrap_or(n),
                length,
                seed: self.seed.unwrap_or(0),
            },
        )))
    }

    /// Keys set in `over` replace those of `self`.
    pub fn merged(&self, over: &GenerateConfig) -> GenerateConfig {
        GenerateConfig {
            n: over.n.or(self.n),
            ny: over.ny.or(self.ny),
            length: over.length.or(self.length),
            hurst: over.hurst.or(self.hurst),
            scales: over.scales.or(self.scales),
            q1: over.q1.or(self.q1),
            ql: over.ql.or(self.ql),
            rolloff_q0: over.rolloff_q0.or(self.rolloff_q0),
            rms_height: over.rms_height.or(self.rms_height),
            rms_slope: over.rms_slope.or(self.rms_slope),
            seed: over.seed.or(self.seed),
            anisotropy: over.anisotropy.or(self.anisotropy),
            psd: over.psd.clone().or_else(|| self.psd.clone()),
        }
    }

    /// Generator parameters; `fallback_length` (`[surface] length`) is used
    /// when `length` is not given here. Errors name the missing or
    /// conflicting keys. The values themselves are checked by
    /// [`GenerateParams::resolve`].
    pub fn params(&self, fallback_length: Option<f64>) -> Result<GenerateParams, SurfaceError> {
        let missing = |k: &str, unit: &str| {
            SurfaceError::Invalid(format!("[surface.generate] needs `{k}` ({unit})"))
        };
        let n = self.n.ok_or_else(|| missing("n", "cells along x"))?;
        let length = match (self.length, fallback_length) {
            (Some(l), Some(f)) if l != f => {
                return Err(SurfaceError::Invalid(format!(
                    "[surface] length = {f} and [surface.generate] length = {l} disagree; give one"
                )))
            }
            (Some(l), _) | (None, Some(l)) => l,
            (None, None) => return Err(missing("length", "side along x, m")),
        };
        let hurst = self
            .hurst
            .ok_or_else(|| missing("hurst", "Hurst exponent, 0 < H <= 1"))?;
        let upper = match (self.scales, self.q1) {
            (Some(s), None) => UpperCutoff::Scales(s),
            (None, Some(q)) => UpperCutoff::Q1(q),
            _ => return Err(SurfaceError::Invalid(
                "[surface.generate] needs exactly one of `scales` (N, q1 = N q_L) and `q1` (1/m)"
                    .into(),
            )),
        };
        let normalisation = match (self.rms_height, self.rms_slope) {
            (Some(h), None) => Normalisation::RmsHeight(h),
            (None, Some(s)) => Normalisation::RmsSlope(s),
            _ => {
                return Err(SurfaceError::Invalid(
                    "[surface.generate] needs exactly one of `rms_height` (m) and `rms_slope`"
                        .into(),
                ))
            }
        };
        Ok(GenerateParams {
            nx: n,
            ny: self.ny.unwrap_or(n),
            length,
            hurst,
            upper,
            ql: self.ql,
            rolloff_q0: self.rolloff_q0,
            normalisation,
            seed: self.seed.unwrap_or(0),
            anisotropy: self.anisotropy.map(|a| Anisotropy {
                ratio: a.ratio,
                angle_deg: a.angle_deg,
            }),
        })
    }
}

impl SurfaceConfig {
    /// Check that exactly one source is given.
    fn check_source(&self) -> Result<(), SurfaceError> {
        let given: Vec<&str> = [
            (self.file.is_some(), "`file`"),
            (self.generate.is_some(), "[surface.generate]"),
            (self.sphere.is_some(), "[surface.sphere]"),
        ]
        .into_iter()
        .filter_map(|(g, name)| g.then_some(name))
        .collect();
        match given.len() {
            1 => Ok(()),
            0 => Err(SurfaceError::Invalid(
                "[surface] needs either `file` (with `length`, m), a [surface.generate] table or a [surface.sphere] table".into(),
            )),
            _ => Err(SurfaceError::Invalid(format!(
                "[surface] has both {}; give one",
                given.join(" and ")
            ))),
        }
    }

    /// Generator parameters when the surface is generated, `None` for a file.
    pub fn generate_params(&self) -> Result<Option<GenerateParams>, SurfaceError> {
        self.check_source()?;
        self.generate
            .as_ref()
            .filter(|g| g.psd.is_none())
            .map(|g| g.params(self.length))
            .transpose()
    }

    /// The height map: `file` (relative to `base_dir`, `length` required),
    /// generated from `[surface.generate]`, or the `[surface.sphere]` paraboloid.
    pub fn load(&self, base_dir: &Path) -> Result<HeightMap, SurfaceError> {
        if let Some(params) = self.generate_params()? {
            return super::generate(&params);
        }
        if let Some(g) = &self.generate {
            if let Some((table, sp)) = g.synth_params(self.length)? {
                let table = super::TabulatedPsd::from_csv(&base_dir.join(table))?;
                return super::generate_from_table(&table, &sp);
            }
        }
        if let Some(sphere) = &self.sphere {
            return sphere.height_map();
        }
        let file = self.file.as_ref().ok_or_else(|| {
            SurfaceError::Invalid("[surface] needs `file` or [surface.generate]".into())
        })?;
        let path = base_dir.join(file);
        let opts = ReadOptions {
            format: self.format,
            length: self.length,
            length_y: self.length_y,
            missing: if self.fill_missing.unwrap_or(false) {
                MissingData::Fill
            } else {
                MissingData::Error
            },
        };
        super::read_topography(&path, &opts)?.to_height_map(&path.display().to_string())
    }
}
