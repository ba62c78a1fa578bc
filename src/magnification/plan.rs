//! The levels of a magnification study (physics.md section 12): the PSD
//! `C(q)` of the configuration held fixed, cut at each level's `q1`, each
//! level on the FFT-friendly grid that gives `K` cells per shortest
//! wavelength, and the configuration of each level, which is exactly the
//! one `viscoslide solve` takes for that surface.

use std::f64::consts::TAU;
use std::path::PathBuf;

use serde::Serialize;

use super::grid::level_grid;
use crate::config::{Formulation, LoadedConfig};
use crate::error::{Error, Result};
use crate::persson::psd::{continuum_self_affine, self_affine_table};
use crate::problem::check_memory;
use crate::solver::SolverParams;
use crate::surface::{
    lattice_moments, table_lattice_moments, GenerateParams, Normalisation, SelfAffinePsd,
    SynthParams, TabulatedPsd, UpperCutoff,
};

fn invalid(msg: impl Into<String>) -> Error {
    Error::Invalid(msg.into())
}

/// Where the levels' cut-offs come from.
#[derive(Debug, Clone, PartialEq)]
pub enum LevelSpec {
    /// `q1` of each level [1/m].
    Q1(Vec<f64>),
    /// Number of scales `N` of each level: `q1 = N q_L`.
    Scales(Vec<f64>),
}

/// Parse `2.51e5,5.62e5` (a `--q1` or `--scales` list) into numbers.
pub(crate) fn parse_list(flag: &str, text: &str) -> Result<Vec<f64>> {
    text.split(',')
        .map(|s| {
            let s = s.trim();
            s.parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| {
                    invalid(format!(
                        "{flag}: `{s}` is not a finite number; give a comma-separated list, e.g. 2.51e5,1.26e6,6.31e6"
                    ))
                })
        })
        .collect()
}

/// The default number of cells per shortest wavelength `2 pi / q1`.
pub const DEFAULT_CELLS_PER_WAVELENGTH: f64 = 4.0;

/// One level of the study, planned (nothing solved).
#[derive(Debug, Clone, Serialize)]
pub struct LevelPlan {
    /// Upper cut-off `q1` of the level [1/m].
    pub q1: f64,
    /// Cells along x and y.
    pub n: usize,
    pub ny: usize,
    /// `(2 pi / q1) / a`, `a = L / n`.
    pub cells_per_shortest_wavelength: f64,
    /// Spectral rms height `sqrt(C0 sum C dq^2)` of the level's surface \[m\].
    pub rms_height: f64,
    /// Spectral rms slope `sqrt(C0 sum |q|^2 C dq^2)` of the level's
    /// surface: the `rms_slope` with which `solve` generates exactly it
    /// (with a PSD table, reported only: the table sets the amplitude).
    pub rms_slope: f64,
    /// rms height of the continuum PSD over `[q_L, q1]` \[m\].
    pub rms_height_continuum: f64,
    /// rms slope of the continuum PSD over `[q_L, q1]`.
    pub rms_slope_continuum: f64,
    /// The truncated continuum PSD Persson's theory sees.
    #[serde(skip)]
    pub psd: TabulatedPsd,
    /// The level's `[surface.generate]` parameters.
    #[serde(skip)]
    pub params: LevelSurface,
}

/// How a level's surface is generated.
#[derive(Debug, Clone, PartialEq)]
pub enum LevelSurface {
    /// Self-affine, with the level's `rms_slope`.
    SelfAffine(GenerateParams),
    /// Synthesised from the PSD table, cut at the level's `q1`.
    Table(SynthParams),
}

impl LevelSurface {
    /// Seed of the random phases.
    pub fn seed(&self) -> u64 {
        match self {
            LevelSurface::SelfAffine(p) => p.seed,
            LevelSurface::Table(p) => p.seed,
        }
    }
}

/// The fixed self-affine PSD of a study: `C(q) = C0` on `[q_L, q0)`,
/// `C0 (q/q0)^(-2(H+1))` on `[q0, q1]` of the configuration.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SelfAffineBand {
    pub hurst: f64,
    pub ql_per_m: f64,
    pub rolloff_q0_per_m: f64,
    /// The configuration's `q1`, the most any level may take [1/m].
    pub q1_per_m: f64,
    /// `C0` \[m^4\]: the continuum value that gives the configuration's rms
    /// slope (or height) over its whole band.
    pub c0_m4: f64,
}

/// The PSD table `[surface.generate] psd` of a study, held fixed: each
/// level synthesises it cut at its `q1`, and Persson's theory takes it over
/// `[2 pi / L, q1]`, as `solve` and `persson` do for that level.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TableBand {
    /// The table's file.
    pub path: String,
    pub rows: usize,
    /// Lowest wavenumber of the grid, `2 pi / L` [1/m].
    pub ql_per_m: f64,
    pub q_min_per_m: f64,
    pub q_max_per_m: f64,
    /// The most any level may take: the table's largest `q`, or the
    /// configuration's `q1` below it [1/m].
    pub q1_per_m: f64,
    #[serde(skip)]
    pub table: TabulatedPsd,
}

/// The fixed PSD of a study (physics.md section 12).
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum FixedPsd {
    SelfAffine(SelfAffineBand),
    Table(TableBand),
}

impl FixedPsd {
    /// `C0` \[m^4\] of a self-affine PSD; `None` for a table.
    pub fn c0_m4(&self) -> Option<f64> {
        match self {
            FixedPsd::SelfAffine(b) => Some(b.c0_m4),
            FixedPsd::Table(_) => None,
        }
    }

    /// The PSD cut at `q1`, as a table for Persson's theory.
    pub fn truncated(&self, q1: f64) -> Result<TabulatedPsd> {
        match self {
            FixedPsd::SelfAffine(b) => truncated_psd(b, q1),
            FixedPsd::Table(t) => Ok(t.table.within(t.ql_per_m, q1, &t.path)?),
        }
    }
}

/// The self-affine PSD cut at `q1` (`q0 < q1`), as a table for Persson's
/// theory.
pub fn truncated_psd(fixed: &SelfAffineBand, q1: f64) -> Result<TabulatedPsd> {
    Ok(self_affine_table(&SelfAffinePsd {
        ql: fixed.ql_per_m,
        q0: fixed.rolloff_q0_per_m,
        q1,
        hurst: fixed.hurst,
        c0: fixed.c0_m4,
        anisotropy: None,
    })?)
}

/// The surface a study is made of.
#[derive(Debug, Clone)]
pub enum BaseSurface {
    /// A self-affine `[surface.generate]`.
    SelfAffine(GenerateParams),
    /// `[surface.generate] psd`: the table (read from `path`) and its
    /// synthesis parameters.
    Table {
        path: PathBuf,
        table: TabulatedPsd,
        params: SynthParams,
    },
}

/// The surface of the configuration, or why a magnification study cannot
/// be made of it.
pub fn config_params(cfg: &LoadedConfig) -> Result<BaseSurface> {
    let surface = cfg.surface()?;
    if let Some(g) = surface.generate.as_ref().filter(|g| g.psd.is_some()) {
        let (table, params) = g.synth_params(surface.length)?.expect("a psd table");
        let path = cfg.base_dir.join(table);
        return Ok(BaseSurface::Table {
            table: TabulatedPsd::from_csv(&path)?,
            path,
            params,
        });
    }
    let params = surface.generate_params()?.ok_or_else(|| {
        invalid(format!(
            "{}: a magnification study needs a generated self-affine surface or a PSD table ([surface.generate]); a surface file or a sphere has no PSD to cut at several q1",
            cfg.path.display()
        ))
    })?;
    if params.anisotropy.is_some_and(|a| a.ratio != 1.0) {
        return Err(invalid(format!(
            "{}: a magnification study sets Persson's theory beside every level, which is for isotropic roughness; remove [surface.generate] anisotropy",
            cfg.path.display()
        )));
    }
    Ok(BaseSurface::SelfAffine(params))
}

/// The fixed PSD of a self-affine configuration and its grid `(length,
/// nx, ny)`.
fn self_affine_psd(mut base: GenerateParams) -> Result<(SelfAffineBand, f64, usize, usize)> {
    // The configuration's own grid need not carry its q1 (each level has
    // its own grid): check the PSD on one that does.
    let ql = base.ql.unwrap_or(TAU / base.length);
    let q1_config = match base.upper {
        UpperCutoff::Scales(n) => n * ql,
        UpperCutoff::Q1(q) => q,
    };
    let (nx, ny) = (base.nx, base.ny);
    if q1_config.is_finite() && q1_config > 0.0 {
        (base.nx, base.ny) = level_grid(2.0, q1_config, base.length, base.nx, base.ny);
    }
    let (_, target) = continuum_self_affine(&base)?;
    Ok((
        SelfAffineBand {
            hurst: target.hurst,
            ql_per_m: target.ql,
            rolloff_q0_per_m: target.q0,
            q1_per_m: target.q1,
            c0_m4: target.c0,
        },
        base.length,
        nx,
        ny,
    ))
}

/// The fixed PSD and the planned levels of `spec` at `cells` cells per
/// shortest wavelength, every level checked (cut-off within the PSD's
/// band, grid within memory).
pub fn plan_levels(
    cfg: &LoadedConfig,
    spec: &LevelSpec,
    cells: f64,
) -> Result<(FixedPsd, Vec<LevelPlan>)> {
    if !(cells.is_finite() && cells >= 2.0) {
        return Err(invalid(format!(
            "cells_per_wavelength (--cells-per-wavelength) must be at least 2 (the Nyquist limit), got {cells}"
        )));
    }
    let base = config_params(cfg)?;
    let (fixed, length, nx0, ny0) = match &base {
        BaseSurface::SelfAffine(p) => {
            let (band, length, nx, ny) = self_affine_psd(p.clone())?;
            (FixedPsd::SelfAffine(band), length, nx, ny)
        }
        BaseSurface::Table {
            path,
            table,
            params,
        } => {
            if !(params.length.is_finite() && params.length > 0.0) {
                return Err(invalid(format!(
                    "[surface.generate] length must be a finite length > 0 (m), got {}",
                    params.length
                )));
            }
            let band = TableBand {
                path: path.display().to_string(),
                rows: table.q().len(),
                ql_per_m: TAU / params.length,
                q_min_per_m: table.q_min(),
                q_max_per_m: table.q_max(),
                q1_per_m: params.highest_q(table),
                table: table.clone(),
            };
            (FixedPsd::Table(band), params.length, params.nx, params.ny)
        }
    };
    // The cut-offs a level must lie between, and q_L for `--scales`.
    let (ql, floor, floor_name, top, top_name) = match &fixed {
        FixedPsd::SelfAffine(b) => (
            b.ql_per_m,
            b.rolloff_q0_per_m,
            if b.rolloff_q0_per_m > b.ql_per_m {
                "roll-off q0"
            } else {
                "lower cut-off q_L"
            },
            b.q1_per_m,
            "the configuration's q1",
        ),
        FixedPsd::Table(t) => (
            t.ql_per_m,
            t.ql_per_m.max(t.q_min_per_m),
            if t.q_min_per_m > t.ql_per_m {
                "PSD table's smallest q"
            } else {
                "lowest wavenumber 2 pi / L"
            },
            t.q1_per_m,
            if t.q1_per_m < t.q_max_per_m {
                "the configuration's q1"
            } else {
                "the largest q of the PSD table"
            },
        ),
    };
    let (flag, values) = match spec {
        LevelSpec::Q1(v) => ("q1 (--q1)", v),
        LevelSpec::Scales(v) => ("scales (--scales)", v),
    };
    if values.is_empty() {
        return Err(invalid(format!("{flag} is empty: give at least one level")));
    }
    let q1s: Vec<f64> = match spec {
        LevelSpec::Q1(v) => v.clone(),
        LevelSpec::Scales(v) => v.iter().map(|n| n * ql).collect(),
    };
    for (w, v) in q1s.windows(2).zip(values.windows(2)) {
        if w[1] <= w[0] {
            return Err(invalid(format!(
                "{flag} must increase strictly (coarse to fine magnification), but {} comes before {}",
                v[0], v[1]
            )));
        }
    }
    let sc = cfg.config.solver.clone().unwrap_or_default();
    let restart = sc.restart.unwrap_or(SolverParams::default().restart);
    let formulation: Formulation = sc.formulation.unwrap_or_default();
    let mut levels = Vec::with_capacity(q1s.len());
    for (&q1, &given) in q1s.iter().zip(values) {
        if q1 > top * (1.0 + 1e-12) {
            let hint = match &fixed {
                FixedPsd::SelfAffine(_) => "raise [surface.generate] q1 (the PSD is extended with the same C0) or cut lower",
                FixedPsd::Table(_) => "cut lower, or extend the table",
            };
            return Err(invalid(format!(
                "{flag} {given}: q1 = {q1:.6e} 1/m exceeds {top_name} = {top:.6e} 1/m, the end of the PSD it defines; {hint}"
            )));
        }
        if q1 <= floor {
            return Err(invalid(format!(
                "{flag} {given}: q1 = {q1:.6e} 1/m must exceed the PSD's {floor_name} = {floor:.6e} 1/m"
            )));
        }
        let q1 = q1.min(top);
        let (n, ny) = level_grid(cells, q1, length, nx0, ny0);
        check_memory(
            n,
            ny,
            restart,
            formulation,
            sc.precision.unwrap_or_default(),
        )
        .map_err(|e| invalid(format!("{flag} {given}: {e}")))?;
        let psd = fixed.truncated(q1)?;
        let (m0, m2, params) = match &base {
            BaseSurface::SelfAffine(b) => {
                let c0 = fixed.c0_m4().expect("self-affine");
                let mut params = GenerateParams {
                    nx: n,
                    ny,
                    upper: UpperCutoff::Q1(q1),
                    normalisation: Normalisation::RmsSlope(1.0),
                    ..b.clone()
                };
                let (m0, m2) = lattice_moments(&params)?;
                params.normalisation = Normalisation::RmsSlope((c0 * m2).sqrt());
                (c0 * m0, c0 * m2, LevelSurface::SelfAffine(params))
            }
            BaseSurface::Table { table, params, .. } => {
                let params = SynthParams {
                    nx: n,
                    ny,
                    q1: Some(q1),
                    ..*params
                };
                let (m0, m2) = table_lattice_moments(table, &params);
                (m0, m2, LevelSurface::Table(params))
            }
        };
        levels.push(LevelPlan {
            q1,
            n,
            ny,
            cells_per_shortest_wavelength: TAU / q1 / (length / n as f64),
            rms_height: m0.sqrt(),
            rms_slope: m2.sqrt(),
            rms_height_continuum: psd.moment(0).sqrt(),
            rms_slope_continuum: psd.moment(2).sqrt(),
            psd,
            params,
        });
    }
    Ok((fixed, levels))
}

/// The configuration of one level at `speed` \[m/s\] (`None`: the
/// configuration's): the study's with `surface.generate.q1 = q1`, `n` (and
/// `ny`), `rms_slope` of the level (`scales` and `rms_height` removed; with
/// a PSD table only `q1`, `n` and `ny` are set), the
/// speed set and `[sweep]` removed: what `viscoslide solve` reads to solve
/// exactly this level.
pub fn level_config(
    cfg: &LoadedConfig,
    level: &LevelPlan,
    speed: Option<f64>,
) -> Result<LoadedConfig> {
    let mut config = cfg.config.clone();
    config.sweep = None;
    let generate = config
        .surface
        .as_mut()
        .and_then(|s| s.generate.as_mut())
        .ok_or_else(|| invalid("a magnification study needs [surface.generate]"))?;
    generate.n = Some(level.n);
    if generate.ny.is_some() || level.ny != level.n {
        generate.ny = Some(level.ny);
    }
    generate.q1 = Some(level.q1);
    // A table has no amplitude key: the table itself sets the level's
    // amplitude, cut at q1.
    if generate.psd.is_none() {
        generate.scales = None;
        generate.rms_slope = Some(level.rms_slope);
        generate.rms_height = None;
    }
    if let Some(v) = speed {
        config
            .loading
            .get_or_insert_with(Default::default)
            .set_sliding(crate::config::Sliding::Speed(v));
    }
    let document = toml::Table::try_from(&config).map_err(|e| {
        invalid(format!(
            "the configuration of the level q1 = {:.6e}: {e}",
            level.q1
        ))
    })?;
    Ok(LoadedConfig {
        config,
        path: cfg.path.clone(),
        base_dir: cfg.base_dir.clone(),
        document,
    })
}
