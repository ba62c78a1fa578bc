//! The levels of a magnification study (physics.md section 12): the PSD
//! `C(q)` of the configuration held fixed, cut at each level's `q1`, each
//! level on the FFT-friendly grid that gives `K` cells per shortest
//! wavelength, and the configuration of each level, which is exactly the
//! one `viscoslide solve` takes for that surface.

use std::f64::consts::TAU;

use serde::Serialize;

use crate::config::{Formulation, LoadedConfig};
use crate::error::{Error, Result};
use crate::persson::psd::{continuum_self_affine, self_affine_table};
use crate::problem::check_memory;
use crate::solver::SolverParams;
use crate::surface::{
    lattice_moments, GenerateParams, Normalisation, SelfAffinePsd, TabulatedPsd, UpperCutoff,
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
pub fn parse_list(flag: &str, text: &str) -> Result<Vec<f64>> {
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

/// Whether `n` has no prime factor above 5 (a size the FFTs handle with
/// their fastest radices).
fn smooth(mut n: usize) -> bool {
    for p in [2, 3, 5] {
        while n % p == 0 {
            n /= p;
        }
    }
    n == 1
}

/// Whether the solver's coarse-to-fine cascade, which halves a grid while
/// its side is even and the half at least 64 cells, reaches a grid of
/// fewer than 128 cells from `n` (a 4050 grid stops at 2025 and solves
/// most of its contact there: several times slower than 4096).
fn cascades_down(mut n: usize) -> bool {
    while n % 2 == 0 && n / 2 >= 64 {
        n /= 2;
    }
    n < 128
}

fn gcd(a: usize, b: usize) -> usize {
    if b == 0 {
        a
    } else {
        gcd(b, a % b)
    }
}

/// The grid `(nx, ny)` of a level: the smallest FFT-friendly `nx` (no
/// prime factor above 5, halving down to fewer than 128 cells for the
/// solver's cascade; any multiple of the aspect's denominator when no such
/// size is one) with at least `cells` cells per shortest wavelength
/// `2 pi / q1` on a side `length`, and `ny` keeping the configuration's
/// side along y exactly (`ny / nx` of the configuration), both at least 8.
pub fn level_grid(cells: f64, q1: f64, length: f64, nx0: usize, ny0: usize) -> (usize, usize) {
    // A hair below the exact count so that round-off in K q1 L / (2 pi)
    // does not add a cell.
    let need = (cells * q1 * length / TAU * (1.0 - 1e-12)).ceil().max(8.0) as usize;
    let g = gcd(nx0, ny0);
    let (p, q) = (ny0 / g, nx0 / g);
    let ny_of = |n: usize| n.checked_mul(p).map(|m| m / q).unwrap_or(usize::MAX);
    let fits = |n: usize| n >= need && n % q == 0 && ny_of(n) >= 8;
    // Every size with both properties is c 2^k with c < 128 5-smooth.
    let n = (1..128usize)
        .filter(|&c| smooth(c))
        .flat_map(|c| (0..48u32).filter_map(move |k| c.checked_mul(1usize << k)))
        .filter(|&n| fits(n) && cascades_down(n) && cascades_down(ny_of(n)))
        .min()
        .unwrap_or_else(|| need.div_ceil(q).max(8usize.div_ceil(p.max(1))) * q);
    (n, ny_of(n))
}

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
    /// surface: the `rms_slope` with which `solve` generates exactly it.
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
    pub params: GenerateParams,
}

/// The fixed PSD of a study: `C(q) = C0` on `[q_L, q0)`,
/// `C0 (q/q0)^(-2(H+1))` on `[q0, q1]` of the configuration.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct FixedPsd {
    pub hurst: f64,
    pub ql_per_m: f64,
    pub rolloff_q0_per_m: f64,
    /// The configuration's `q1`, the most any level may take [1/m].
    pub q1_per_m: f64,
    /// `C0` \[m^4\]: the continuum value that gives the configuration's rms
    /// slope (or height) over its whole band.
    pub c0_m4: f64,
}

/// The fixed PSD cut at `q1` (`q0 < q1`), as a table for Persson's
/// theory.
pub fn truncated_psd(fixed: &FixedPsd, q1: f64) -> Result<TabulatedPsd> {
    Ok(self_affine_table(&SelfAffinePsd {
        ql: fixed.ql_per_m,
        q0: fixed.rolloff_q0_per_m,
        q1,
        hurst: fixed.hurst,
        c0: fixed.c0_m4,
        anisotropy: None,
    })?)
}

/// The generator parameters of the configuration's surface, or why a
/// magnification study cannot be made of it.
pub fn config_params(cfg: &LoadedConfig) -> Result<GenerateParams> {
    let surface = cfg.surface()?;
    if surface.generate.as_ref().is_some_and(|g| g.psd.is_some()) {
        return Err(invalid(format!(
            "{}: a magnification study of a surface synthesised from a PSD table ([surface.generate] psd) is not supported; use a self-affine [surface.generate] (hurst, q1 or scales, rms_slope or rms_height)",
            cfg.path.display()
        )));
    }
    let params = surface.generate_params()?.ok_or_else(|| {
        invalid(format!(
            "{}: a magnification study needs a generated self-affine surface ([surface.generate]); a surface file or a sphere has no PSD to cut at several q1",
            cfg.path.display()
        ))
    })?;
    if params.anisotropy.is_some_and(|a| a.ratio != 1.0) {
        return Err(invalid(format!(
            "{}: a magnification study sets Persson's theory beside every level, which is for isotropic roughness; remove [surface.generate] anisotropy",
            cfg.path.display()
        )));
    }
    Ok(params)
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
            "--cells-per-wavelength must be at least 2 (the Nyquist limit), got {cells}"
        )));
    }
    let mut base = config_params(cfg)?;
    // The configuration's own grid need not carry its q1 (each level has
    // its own grid): check the PSD on one that does.
    let ql = base.ql.unwrap_or(TAU / base.length);
    let q1_config = match base.upper {
        UpperCutoff::Scales(n) => n * ql,
        UpperCutoff::Q1(q) => q,
    };
    if q1_config.is_finite() && q1_config > 0.0 {
        (base.nx, base.ny) = level_grid(2.0, q1_config, base.length, base.nx, base.ny);
    }
    let (_, target) = continuum_self_affine(&base)?;
    let fixed = FixedPsd {
        hurst: target.hurst,
        ql_per_m: target.ql,
        rolloff_q0_per_m: target.q0,
        q1_per_m: target.q1,
        c0_m4: target.c0,
    };
    let (flag, values) = match spec {
        LevelSpec::Q1(v) => ("--q1", v),
        LevelSpec::Scales(v) => ("--scales", v),
    };
    if values.is_empty() {
        return Err(invalid(format!("{flag} is empty: give at least one level")));
    }
    let q1s: Vec<f64> = match spec {
        LevelSpec::Q1(v) => v.clone(),
        LevelSpec::Scales(v) => v.iter().map(|n| n * target.ql).collect(),
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
        if q1 > target.q1 * (1.0 + 1e-12) {
            return Err(invalid(format!(
                "{flag} {given}: q1 = {q1:.6e} 1/m exceeds the configuration's q1 = {:.6e} 1/m, the end of the PSD it defines; raise [surface.generate] q1 (the PSD is extended with the same C0) or cut lower",
                target.q1
            )));
        }
        if q1 <= target.q0 {
            return Err(invalid(format!(
                "{flag} {given}: q1 = {q1:.6e} 1/m must exceed the PSD's {} = {:.6e} 1/m",
                if target.q0 > target.ql {
                    "roll-off q0"
                } else {
                    "lower cut-off q_L"
                },
                target.q0
            )));
        }
        let q1 = q1.min(target.q1);
        let (n, ny) = level_grid(cells, q1, base.length, base.nx, base.ny);
        check_memory(n, ny, restart, formulation)
            .map_err(|e| invalid(format!("{flag} {given}: {e}")))?;
        let mut params = GenerateParams {
            nx: n,
            ny,
            upper: UpperCutoff::Q1(q1),
            normalisation: Normalisation::RmsSlope(1.0),
            ..base.clone()
        };
        let (m0, m2) = lattice_moments(&params)?;
        let rms_slope = (target.c0 * m2).sqrt();
        params.normalisation = Normalisation::RmsSlope(rms_slope);
        let psd = truncated_psd(&fixed, q1)?;
        levels.push(LevelPlan {
            q1,
            n,
            ny,
            cells_per_shortest_wavelength: TAU / q1 / (base.length / n as f64),
            rms_height: (target.c0 * m0).sqrt(),
            rms_slope,
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
/// `ny`), `rms_slope` of the level (`scales` and `rms_height` removed), the
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
    generate.scales = None;
    generate.rms_slope = Some(level.rms_slope);
    generate.rms_height = None;
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grids_are_fft_friendly_and_resolve_k_cells() {
        // Paper experiment: L = 2 pi / 2.51e4.
        let l = 2.5032990e-4;
        for (q1, want) in [(2.51e5, 45), (2.82e6, 480), (6.31e6, 1024)] {
            let (n, ny) = level_grid(4.0, q1, l, 1024, 1024);
            assert_eq!((n, ny), (want, want), "q1 = {q1}");
            assert!(TAU / q1 / (l / n as f64) >= 4.0);
        }
        // Exactly 40 cells needed: no extra cell from round-off.
        let q1 = 40.0 * TAU / l / 4.0;
        assert_eq!(level_grid(4.0, q1, l, 64, 64).0, 40);
        // 16 cells at the experiment's q1: 4096, not 4050 (= 2 x 2025).
        assert_eq!(level_grid(16.0, 6.31e6, l, 64, 64).0, 4096);
        assert!(cascades_down(4096) && cascades_down(120) && !cascades_down(4050));
        // Aspect 3:2 kept exactly.
        let (n, ny) = level_grid(4.0, 2.51e5, l, 96, 64);
        assert_eq!(n * 2, ny * 3);
        assert!(smooth(n) && n >= 40);
        assert!(smooth(1024) && smooth(450) && !smooth(14));
    }
}
