//! Building a [`HeightMap`] from its `[surface]` section (the types live in
//! [`crate::config::surface`]).

use std::path::{Path, PathBuf};

use super::generate::{Anisotropy, GenerateParams, Normalisation, UpperCutoff};
use super::{
    parse_detrend, parse_window, BelowTable, Detrend, HeightMap, MissingData, Preprocessing,
    ReadOptions, SurfaceError, SurfaceFormat, SynthParams, Window,
};
use crate::config::{GenerateConfig, SphereConfig, SurfaceConfig};

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

impl GenerateConfig {
    /// With `psd` set: the table's path and the grid, seed and optional
    /// cut-off `q1` of the synthesis ([`super::generate_from_table`]);
    /// `None` without `psd`. The other self-affine keys cannot be combined
    /// with `psd`.
    pub fn synth_params(
        &self,
        fallback_length: Option<f64>,
    ) -> Result<Option<(PathBuf, SynthParams)>, SurfaceError> {
        let Some(psd) = &self.psd else {
            if let Some(b) = &self.below_table {
                return Err(SurfaceError::Invalid(format!(
                    "[surface.generate] below_table = {b:?} applies to a tabulated PSD: give `psd` or remove it"
                )));
            }
            return Ok(None);
        };
        let extra: Vec<&str> = [
            (self.hurst.is_some(), "hurst"),
            (self.scales.is_some(), "scales"),
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
                q1: self.q1,
                below: match &self.below_table {
                    Some(b) => BelowTable::parse(b)?,
                    None => BelowTable::default(),
                },
            },
        )))
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
    /// Check the section as every reader of it does: exactly one source,
    /// and the keys that describe a surface `file` only beside one.
    pub fn check(&self) -> Result<(), SurfaceError> {
        let given: Vec<&str> = [
            (self.file.is_some(), "`file`"),
            (self.generate.is_some(), "[surface.generate]"),
            (self.sphere.is_some(), "[surface.sphere]"),
        ]
        .into_iter()
        .filter_map(|(g, name)| g.then_some(name))
        .collect();
        match given.len() {
            1 => self.check_file_keys(),
            0 => Err(SurfaceError::Invalid(
                "[surface] needs either `file` (with `length`, m), a [surface.generate] table or a [surface.sphere] table".into(),
            )),
            _ => Err(SurfaceError::Invalid(format!(
                "[surface] has both {}; give one",
                given.join(" and ")
            ))),
        }
    }

    /// The keys that describe a surface `file` (`length_y`, `format`,
    /// `fill_missing`, `detrend`, `window`, `periodic`) are refused beside
    /// a generated surface or a sphere, which they would not change.
    fn check_file_keys(&self) -> Result<(), SurfaceError> {
        if self.file.is_some() {
            return Ok(());
        }
        if let Some(ly) = self.length_y {
            let hint = if self.generate.is_some() {
                "a generated surface has square cells of length / n: give [surface.generate] ny (cells along y) for a side of ny * length / n along y"
            } else {
                "a [surface.sphere] map is n x n cells of side length"
            };
            return Err(SurfaceError::Invalid(format!(
                "[surface] length_y = {ly} applies to a surface `file` only; {hint}"
            )));
        }
        let given: Vec<&str> = [
            (self.detrend.is_some(), "detrend"),
            (self.window.is_some(), "window"),
            (self.periodic.is_some(), "periodic"),
            (self.format.is_some(), "format"),
            (self.fill_missing.is_some(), "fill_missing"),
        ]
        .into_iter()
        .filter_map(|(g, k)| g.then_some(k))
        .collect();
        if !given.is_empty() {
            return Err(SurfaceError::Invalid(format!(
                "[surface] {} apply to a surface `file`; generated surfaces and spheres are taken as they are",
                given.join(", ")
            )));
        }
        Ok(())
    }

    /// Generator parameters when the surface is generated, `None` for a file.
    pub fn generate_params(&self) -> Result<Option<GenerateParams>, SurfaceError> {
        self.check()?;
        self.generate
            .as_ref()
            .filter(|g| g.psd.is_none())
            .map(|g| g.params(self.length))
            .transpose()
    }

    /// How `file` is prepared ([`Preprocessing`], physics.md section 11):
    /// the `detrend` and `window` keys over the defaults of a scan (or of
    /// a periodic map with `periodic = true`). `None` for a generated
    /// surface or a sphere, which are taken as they are; the keys that
    /// describe a file are refused there.
    pub fn preprocessing(&self) -> Result<Option<Preprocessing>, SurfaceError> {
        self.preprocessing_for(false)
    }

    /// [`SurfaceConfig::preprocessing`] for a solve with the periodic
    /// formulation when `periodic_solve`: that solve takes the map as one
    /// period of a periodic surface, so a map not marked `periodic` keeps
    /// its heights (`detrend = "none"`) and its PSDs take it as a period
    /// (`window = "none"`), unless `detrend` or `window` is given.
    pub fn preprocessing_for(
        &self,
        periodic_solve: bool,
    ) -> Result<Option<Preprocessing>, SurfaceError> {
        if self.file.is_none() {
            self.check_file_keys()?;
            return Ok(None);
        }
        let bad = |key: &str, e: String| SurfaceError::Invalid(format!("[surface] {key}: {e}"));
        let detrend = self
            .detrend
            .as_deref()
            .map(|d| parse_detrend(d).map_err(|e| bad("detrend", e)))
            .transpose()?;
        let window = self
            .window
            .as_deref()
            .map(|w| parse_window(w).map_err(|e| bad("window", e)))
            .transpose()?;
        let periodic = self.periodic.unwrap_or(false);
        let as_period = periodic_solve && !periodic;
        let detrend = detrend.or(as_period.then_some(Detrend::None));
        let window = window.or(as_period.then_some(Window::None));
        Ok(Some(Preprocessing::resolve(periodic, detrend, window)))
    }

    /// The height map: `file` (relative to `base_dir`; any format of
    /// [`super::read_topography`], `length` required for `.npy`/text;
    /// prepared by [`SurfaceConfig::preprocessing`], see [`super::prepare`]),
    /// generated from `[surface.generate]` (self-affine, or following the
    /// tabulated `psd`), or the `[surface.sphere]` paraboloid.
    pub fn load(&self, base_dir: &Path) -> Result<HeightMap, SurfaceError> {
        self.load_for(base_dir, false)
    }

    /// [`SurfaceConfig::load`] prepared by
    /// [`SurfaceConfig::preprocessing_for`] `(periodic_solve)`.
    pub fn load_for(
        &self,
        base_dir: &Path,
        periodic_solve: bool,
    ) -> Result<HeightMap, SurfaceError> {
        self.load_counting(base_dir, periodic_solve)
            .map(|(map, _)| map)
    }

    /// The `format` the section states, checked; `None`: by the file's
    /// extension.
    fn stated_format(&self) -> Result<Option<SurfaceFormat>, SurfaceError> {
        self.format
            .as_deref()
            .map(|f| {
                f.parse::<SurfaceFormat>()
                    .map_err(|e| SurfaceError::Invalid(format!("[surface] format: {e}")))
            })
            .transpose()
    }

    /// The grid `(nx, ny)` of the `[surface] file` when its header tells
    /// it without reading the heights (`.npy`), so that a grid too large
    /// for memory is refused before the file is read; `None` otherwise
    /// (other formats, or a header the full read will report on).
    pub fn file_grid(&self, base_dir: &Path) -> Option<(usize, usize)> {
        let file = base_dir.join(self.file.as_ref()?);
        let format = self
            .stated_format()
            .ok()?
            .unwrap_or_else(|| SurfaceFormat::from_path(&file));
        if format != SurfaceFormat::Npy {
            return None;
        }
        match crate::io::npy::read_shape(&file).ok()?.as_slice() {
            [nx, ny] => Some((*nx, *ny)),
            _ => None,
        }
    }

    /// [`SurfaceConfig::load_for`] with the number of a file's missing
    /// points filled by harmonic interpolation (`fill_missing`; 0 for a
    /// generated surface or a sphere).
    pub fn load_counting(
        &self,
        base_dir: &Path,
        periodic_solve: bool,
    ) -> Result<(HeightMap, usize), SurfaceError> {
        let pre = self.preprocessing_for(periodic_solve)?;
        if let Some(params) = self.generate_params()? {
            return super::generate(&params).map(|m| (m, 0));
        }
        if let Some(g) = &self.generate {
            if let Some((table, sp)) = g.synth_params(self.length)? {
                let table = super::TabulatedPsd::from_csv(&base_dir.join(table))?;
                return super::generate_from_table(&table, &sp).map(|m| (m, 0));
            }
        }
        if let Some(sphere) = &self.sphere {
            return sphere.height_map().map(|m| (m, 0));
        }
        let file = self.file.as_ref().ok_or_else(|| {
            SurfaceError::Invalid("[surface] needs `file` or [surface.generate]".into())
        })?;
        let format = self.stated_format()?;
        let path = base_dir.join(file);
        let opts = ReadOptions {
            format,
            length: self.length,
            length_y: self.length_y,
            missing: if self.fill_missing.unwrap_or(false) {
                MissingData::Fill
            } else {
                MissingData::Error
            },
        };
        let pre = pre.unwrap_or(Preprocessing::default_for(false));
        let topo = super::read_topography(&path, &opts)?;
        let map = super::prepare(&topo, &pre, &path.display().to_string())?;
        Ok((map, topo.filled))
    }
}
