//! `[surface]`: a height map read from a file, generated, or a sphere; built
//! into a height map by `SurfaceConfig::load` in [`crate::surface`].
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
//! # [surface.generate] with n, ny, length, seed and psd = "psd.csv" only,
//! # and optionally q1 (1/m): modes above it get zero amplitude, the others
//! # are unchanged (the same realisation cut at q1; magnification studies)
//! ```
//!
//! A `file` may be `.x3p`, `.gwy` (sizes from the file; `length` optional),
//! `.npy` or a text matrix (`length` needed); `format = "x3p"` overrides the
//! extension, `length_y` gives a non-square side for `.npy`/text, and
//! `fill_missing = true` fills missing points by harmonic interpolation.
//!
//! A `file` is a scan, not one period of a periodic surface, unless
//! `periodic = true`: its mean plane is removed before solving and before
//! any PSD (`detrend = "none" | "mean" | "plane" | "quadratic"`, default
//! `"plane"`; `"none"` for a periodic map), and its PSDs use the Hann
//! window (`window = "none" | "hann" | "blackman_harris"`, default
//! `"hann"`; `"none"` for a periodic map). Generated surfaces are taken as
//! they are (physics.md section 11).

use std::path::PathBuf;

use serde::{Deserialize, Serialize};

/// `[surface]`: a height map from `file` (with `length`, m), or generated
/// from `[surface.generate]`; exactly one of the two.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub struct SurfaceConfig {
    /// `.npy` (or plain-text) height map, heights in m at cell centres;
    /// relative to the config file's directory.
    pub file: Option<PathBuf>,
    /// Side of the map along x \[m\] (cells `length / nx` along x).
    pub length: Option<f64>,
    /// Generate a self-affine surface instead of reading one.
    pub generate: Option<GenerateConfig>,
    /// A rigid sphere instead (the Hertz paraboloid), for smooth contacts.
    pub sphere: Option<SphereConfig>,
    /// Format of `file` overriding its extension: "x3p", "gwy", "npy" or "text".
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub format: Option<String>,
    /// Side of `file` along y \[m\] (`.npy`/text; default square cells;
    /// otherwise rectangular cells `length_y / ny` along y). A file key
    /// only: a generated surface has square cells and takes its side
    /// along y from `[surface.generate] ny`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub length_y: Option<f64>,
    /// Fill missing points of `file` by harmonic interpolation (default:
    /// a file with missing points is an error).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fill_missing: Option<bool>,
    /// Polynomial removed from `file` before solving and before any PSD:
    /// "none", "mean", "plane" or "quadratic" (default "plane"; "none"
    /// when `periodic`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub detrend: Option<String>,
    /// Window of the PSDs of `file`: "none", "hann" or "blackman_harris"
    /// (default "hann"; "none" when `periodic`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub window: Option<String>,
    /// `file` is one period of a periodic surface (default false: a scan).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub periodic: Option<bool>,
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

/// `anisotropy = { ratio, angle_deg }` (see `crate::surface::Anisotropy`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AnisotropyConfig {
    /// Stretch factor `s > 0` along `e(theta)`.
    pub ratio: f64,
    /// `theta` \[degrees\] from +x.
    pub angle_deg: f64,
}

/// `[surface.generate]`: parameters of `crate::surface::generate`. Every key is
/// optional in the type so that command-line flags can be merged on top;
/// `GenerateConfig::params` checks which are required.
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
    /// Upper cut-off [1/m]; exclusive with `scales`. With `psd`: modes
    /// with `|q| > q1` are left out of the synthesis and every other mode
    /// is unchanged (the same surface cut at `q1`).
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
    /// self-affine formula (relative to the config's directory); only `n`,
    /// `ny`, `length`, `seed` and the optional cut-off `q1` go with it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub psd: Option<PathBuf>,
    /// With `psd`: what the grid's modes below the table's first row get,
    /// `"first_bin"` (default: the first row's value down to its bin's
    /// lower edge), `"extrapolate"` (the first two rows' power law further
    /// down) or `"none"`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub below_table: Option<String>,
}

impl GenerateConfig {
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
            below_table: over
                .below_table
                .clone()
                .or_else(|| self.below_table.clone()),
        }
    }
}
