//! Persson's theory (module [`crate::persson`]) for a configuration or a
//! [`Problem`]: a thin adapter that builds the theory's inputs (the
//! material, an isotropic PSD, the nominal pressure) so that theory and
//! simulation see the same rubber, the same surface and the same load.
//!
//! PSD: the continuum self-affine PSD of `[surface.generate]`
//! ([`persson::psd::continuum_self_affine`]), the radial average of a
//! surface file or of a height map given as values prepared as the solve
//! prepares it ([`persson::psd::map_psd`]: detrended, Hann-windowed, over
//! a scan's trusted band; physics.md section 11), or a `q, C` CSV. Nominal pressure: `loading.mean_pressure`,
//! else the normal load over the map's area (for a problem under
//! displacement control, the solved mean pressure).

use std::f64::consts::{PI, TAU};
use std::path::Path;

use serde::Serialize;

use crate::config::{LoadedConfig, XiScale};
use crate::error::{Error, Result};
use crate::material::Material;
use crate::persson::{self, psd::MapPsdReport, Persson, PerssonParams};
use crate::solver::Control;
use crate::surface::{Preprocessing, TabulatedPsd, Window};

use super::{Problem, SurfaceSource};

/// Where the theory's PSD came from.
#[derive(Debug, Clone, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum PsdSource {
    /// The continuum self-affine PSD of `[surface.generate]`.
    SelfAffine {
        hurst: f64,
        ql_per_m: f64,
        rolloff_q0_per_m: f64,
        q1_per_m: f64,
        c0_m4: f64,
    },
    /// The radial average of the config's surface file, prepared as the
    /// solve prepares it.
    SurfaceFile {
        path: String,
        #[serde(flatten)]
        map: MapPsdReport,
    },
    /// A `q, C` table.
    Table { path: String, rows: usize },
    /// The table `[surface.generate] psd` follows, over the band the grid
    /// synthesises in every direction: `2 pi / L` to the Nyquist
    /// wavenumber `pi / a`, or to the synthesis' cut-off `q1` below it.
    GeneratedTable {
        path: String,
        rows: usize,
        q_min_per_m: f64,
        q_max_per_m: f64,
    },
}

/// The inputs of the theory built from a config: a thin adapter, the
/// theory itself only sees the material, the PSD and the pressure.
#[derive(Debug, Clone)]
pub struct TheoryInputs {
    pub material: Material,
    pub psd: TabulatedPsd,
    pub source: PsdSource,
    /// `sigma0` \[Pa\].
    pub nominal_pressure: f64,
    /// How `sigma0` was obtained.
    pub pressure_from: String,
    /// Side of the surface along x \[m\] (defines `xi` for one-term spectra).
    pub length_x: Option<f64>,
    /// Nominal area `Lx Ly` of the surface \[m^2\], when the config defines it.
    pub area: Option<f64>,
    /// Notes about the theory's assumptions.
    pub notes: Vec<String>,
    /// Results that may mislead (a PSD whose rms slope disagrees with the
    /// map's).
    pub warnings: Vec<String>,
}

impl TheoryInputs {
    /// The scale of `xi = v tau / L` (the definition of `solve`) for a
    /// single-relaxation material and a surface of known side, else `None`.
    pub fn xi_scale(&self) -> Option<XiScale> {
        match (self.material.spectrum.terms.as_slice(), self.length_x) {
            ([t], Some(length)) => Some(XiScale {
                creep_time: t.time,
                length,
            }),
            _ => None,
        }
    }
}

/// Build the theory's inputs from `cfg`: the material of `[material]`; the
/// PSD of `psd_csv` if given, else of `[surface.generate]` (continuum) or of
/// the `[surface] file` (radial average of the map the solve uses, with
/// `window` if given, else the section's, over a scan's trusted band;
/// [`persson::psd::map_psd`]); the pressure
/// `loading.mean_pressure`, or `loading.normal_load` over the surface's
/// area.
pub fn theory_inputs(
    cfg: &LoadedConfig,
    psd_csv: Option<&Path>,
    window: Option<Window>,
) -> Result<TheoryInputs> {
    // The material at `[loading] temperature`, as `Problem::with_loading`
    // shifts it for the solve.
    let loading = cfg.config.loading.clone().unwrap_or_default();
    let material = cfg
        .material()?
        .build(&cfg.base_dir)?
        .at(loading.temperature)?;
    let mut notes = Vec::new();
    let mut warnings: Vec<String> = material.extrapolated_shift_warning().into_iter().collect();
    notes.extend(layer_note(cfg.config.layer.as_ref().map(|l| l.thickness)));
    let surface = cfg.config.surface.as_ref();
    let generate = match surface {
        Some(s) => s.generate_params()?,
        None => None,
    };
    // Side lengths (x, y) of the map when the config defines one.
    let mut sides: Option<(f64, f64)> = generate
        .as_ref()
        .map(|p| (p.length, p.length * p.ny as f64 / p.nx as f64));
    if let Some(sp) = surface.and_then(|s| s.sphere.as_ref()) {
        sides = Some((sp.length, sp.length));
    }
    let (psd, source) = if let Some(path) = psd_csv {
        let t = TabulatedPsd::from_csv(path)?;
        let rows = t.q().len();
        (
            t,
            PsdSource::Table {
                path: path.display().to_string(),
                rows,
            },
        )
    } else {
        match (surface, &generate) {
            (None, _) => {
                return Err(Error::Invalid(format!(
                    "{}: Persson's theory needs a [surface] section or --psd CSV",
                    cfg.path.display()
                )))
            }
            (Some(_), Some(p)) => {
                let (t, target) = persson::psd::continuum_self_affine(p)?;
                (
                    t,
                    PsdSource::SelfAffine {
                        hurst: target.hurst,
                        ql_per_m: target.ql,
                        rolloff_q0_per_m: target.q0,
                        q1_per_m: target.q1,
                        c0_m4: target.c0,
                    },
                )
            }
            (Some(s), None) if s.generate.as_ref().is_some_and(|g| g.psd.is_some()) => {
                let g = s.generate.as_ref().expect("generate");
                let (table, sp) = g.synth_params(s.length)?.expect("a psd table");
                let path = cfg.base_dir.join(table);
                let full = TabulatedPsd::from_csv(&path)?;
                let cell = sp.length / sp.nx as f64;
                let (lo, hi) = (TAU / sp.length, (PI / cell).min(sp.highest_q(&full)));
                let t = full.within(lo, hi, &path.display().to_string())?;
                let (q_min_per_m, q_max_per_m) = (t.q_min(), t.q_max());
                (
                    t,
                    PsdSource::GeneratedTable {
                        path: path.display().to_string(),
                        rows: full.q().len(),
                        q_min_per_m,
                        q_max_per_m,
                    },
                )
            }
            (Some(s), None) if s.sphere.is_some() => {
                return Err(Error::Invalid(
                    "Persson's theory is for randomly rough surfaces, not [surface.sphere]; give [surface.generate], a surface file or --psd CSV".into(),
                ))
            }
            (Some(s), None) => {
                let map = s.load(&cfg.base_dir)?;
                sides = Some((map.length_x(), map.length_y()));
                let mut pre = s
                    .preprocessing()?
                    .unwrap_or(Preprocessing::default_for(false));
                pre.window = window.unwrap_or(pre.window);
                let (t, info) = persson::psd::map_psd(&map, &pre, true)?;
                notes.extend(anisotropy_note(&info));
                warnings.extend(info.warning.clone());
                let path = s
                    .file
                    .as_ref()
                    .map(|f| cfg.base_dir.join(f).display().to_string())
                    .unwrap_or_default();
                (
                    t,
                    PsdSource::SurfaceFile { path, map: info },
                )
            }
        }
    };
    let (nominal_pressure, pressure_from) = match (loading.mean_pressure, loading.normal_load) {
        (Some(p), _) => (p, "loading.mean_pressure".to_string()),
        (None, Some(f)) => match sides {
            Some((lx, ly)) => (
                f / (lx * ly),
                format!("loading.normal_load / ({lx:.6e} m x {ly:.6e} m)"),
            ),
            None => {
                return Err(Error::Invalid(
                    "[loading] normal_load needs the surface's area; give loading.mean_pressure (Pa) with --psd".into(),
                ))
            }
        },
        (None, None) => {
            return Err(Error::Invalid(
                "Persson's theory needs the nominal pressure: [loading] mean_pressure (Pa) or normal_load (N)".into(),
            ))
        }
    };
    warnings.extend(slope_warning(&psd));
    Ok(TheoryInputs {
        material,
        psd,
        source,
        nominal_pressure,
        pressure_from,
        length_x: sides.map(|s| s.0),
        area: sides.map(|s| s.0 * s.1),
        notes,
        warnings,
    })
}

/// Degree of isotropy of a map's slopes (`gamma`,
/// [`persson::psd::RadialInfo::slope_isotropy`]) below which Persson's
/// theory, isotropic, is noted to see only the radial average.
const SLOPE_ISOTROPY_NOTE: f64 = 0.7;

/// The note beside Persson's theory of a problem with a layer of
/// `thickness` \[m\] (`None`: no layer, no note): the theory is for a
/// half-space.
fn layer_note(thickness: Option<f64>) -> Option<String> {
    thickness.map(|h| {
        format!(
            "the problem has a [layer] (h = {h:.3e} m); Persson's theory here is for a half-space and ignores it: its numbers compare with the solve only where the contact's wavelengths are much shorter than h"
        )
    })
}

/// The note beside Persson's theory of a map whose slopes are anisotropic
/// (`gamma` below [`SLOPE_ISOTROPY_NOTE`]): the isotropic theory sees
/// the map's radial average.
fn anisotropy_note(map: &MapPsdReport) -> Option<String> {
    let gamma = map.radial.slope_isotropy;
    (gamma < SLOPE_ISOTROPY_NOTE).then(|| {
        format!(
            "the map's slopes are anisotropic (gamma = {gamma:.3}, the ratio of its mean square slopes along its principal axes); the isotropic theory uses its radial average"
        )
    })
}

/// The warning of Persson's theory on `psd` whose rms slope (`sqrt(2 pi
/// Int q^3 C dq)`) is beyond the small-slope limit the model warns at: the
/// theory, like the model, is for nearly flat surfaces.
pub(crate) fn slope_warning(psd: &TabulatedPsd) -> Option<String> {
    let limit = super::warnings::RMS_SLOPE_LIMIT;
    let slope = psd.moment(2).sqrt();
    (slope > limit).then(|| {
        format!(
            "the rms slope of the PSD is {slope:.3e}, beyond {limit}: Persson's theory, like the model, is for nearly flat surfaces (small slopes) and does not hold there; lower rms_slope or check the units of the PSD or the heights"
        )
    })
}

/// The warnings of a Persson curve of `material` over the speeds `from`
/// to `to` \[m/s\] on `psd`: the frequencies `v q` it excites, from the
/// slowest speed on the PSD's first wavenumber to the fastest on its last,
/// a decade beyond the material's data
/// ([`Material::extrapolated_frequencies_warnings`]).
pub(crate) fn curve_frequency_warnings(
    material: &Material,
    psd: &TabulatedPsd,
    from: f64,
    to: f64,
) -> Vec<String> {
    let q = psd.q();
    material.extrapolated_frequencies_warnings(from * q[0], to * q[q.len() - 1])
}

impl Problem {
    /// What Persson's theory of this problem leaves out, noted beside its
    /// numbers: a layer (the theory is for a half-space) and, with `map`
    /// (the radial average of a map), slopes that are anisotropic.
    pub fn persson_notes(&self, map: Option<&MapPsdReport>) -> Vec<String> {
        layer_note(self.layer.map(|l| l.thickness))
            .into_iter()
            .chain(map.and_then(anisotropy_note))
            .collect()
    }

    /// The warnings of a Persson curve of this problem on `psd` over
    /// `speeds` \[m/s\], as `viscoslide persson` gives them: the
    /// material's temperature beyond its WLF data, an rms slope beyond the
    /// small-slope limit, and the frequencies the positive speeds excite
    /// beyond its frequency data.
    pub fn persson_curve_warnings(&self, psd: &TabulatedPsd, speeds: &[f64]) -> Vec<String> {
        let mut out: Vec<String> = self
            .material
            .extrapolated_shift_warning()
            .into_iter()
            .chain(slope_warning(psd))
            .collect();
        let positive = speeds.iter().copied().filter(|v| *v > 0.0 && v.is_finite());
        let (from, to) = positive.fold((f64::INFINITY, 0.0_f64), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
        if to > 0.0 {
            out.extend(curve_frequency_warnings(&self.material, psd, from, to));
        }
        out
    }
}

/// Persson's theory at a solve's speed and nominal pressure, recorded
/// beside the simulated friction and area.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PerssonEstimate {
    /// `mu` of the theory.
    pub friction_coefficient: f64,
    /// `A/A0 = P(q1)` of the theory.
    pub contact_area_fraction: f64,
    /// `sigma0` \[Pa\] the theory was evaluated at.
    pub nominal_pressure: f64,
    /// Which PSD: `self_affine` (continuum), `generated_table` (the table a
    /// synthesised surface follows, over the grid's band) or
    /// `radial_average` (of the map).
    pub psd: &'static str,
    /// How the radial average of a map was made (preprocessing, band,
    /// rms-slope check); `None` for the other PSDs.
    pub map: Option<MapPsdReport>,
    /// What the theory leaves out of this problem (a layer, a map's
    /// anisotropy), as `viscoslide persson` notes it.
    pub notes: Vec<String>,
}

impl Problem {
    /// The isotropic PSD Persson's theory sees for this problem's surface:
    /// the continuum self-affine PSD of a generated surface, the table a
    /// synthesised surface follows (over the band `2 pi / L` to `pi / a`
    /// the grid carries), the radial average of a surface read from a file
    /// or given as values. `Err`
    /// says why the theory does not apply (a sphere, an anisotropic
    /// surface).
    pub fn persson_psd(&self) -> std::result::Result<(TabulatedPsd, &'static str), String> {
        self.persson_psd_report().map(|(t, kind, _)| (t, kind))
    }

    /// [`Problem::persson_psd`] with, for the radial average of a map, how
    /// it was made: the map's preprocessing (a map given as values
    /// without a record is taken as it is, unwindowed, over every bin),
    /// the band and the rms-slope check ([`persson::psd::map_psd`]).
    pub fn persson_psd_report(
        &self,
    ) -> std::result::Result<(TabulatedPsd, &'static str, Option<MapPsdReport>), String> {
        match &self.source {
            SurfaceSource::Generated(p) => persson::psd::continuum_self_affine(p)
                .map(|(t, _)| (t, "self_affine", None))
                .map_err(|e| e.to_string()),
            SurfaceSource::Sphere(_) => {
                Err("Persson's theory is for randomly rough surfaces, not a sphere".to_string())
            }
            SurfaceSource::Synthesised {
                table,
                path,
                params,
            } => {
                let a = self.surface.cell_size;
                table
                    .within(
                        TAU / self.surface.length_x(),
                        (PI / a).min(params.highest_q(table)),
                        &path.display().to_string(),
                    )
                    .map(|t| (t, "generated_table", None))
                    .map_err(|e| e.to_string())
            }
            SurfaceSource::File(_) | SurfaceSource::Given => {
                let (pre, detrended) = match self.preprocessing {
                    Some(p) => (p, true),
                    None => (Preprocessing::default_for(true), false),
                };
                persson::psd::map_psd(&self.surface, &pre, detrended)
                    .map(|(t, r)| (t, "radial_average", Some(r)))
                    .map_err(|e| e.to_string())
            }
        }
    }

    /// Persson's theory at this problem's speed; `mean_pressure` \[Pa\] is
    /// used under displacement control (the solved nominal pressure), the
    /// prescribed load over the map's area otherwise. `Err` says why the
    /// theory was not evaluated.
    pub fn persson_estimate(
        &self,
        mean_pressure: f64,
    ) -> std::result::Result<PerssonEstimate, String> {
        let (psd, kind, map) = self.persson_psd_report()?;
        let sigma0 = match self.control {
            Control::Load(f) => f / (self.surface.length_x() * self.surface.length_y()),
            Control::Approach(_) => mean_pressure,
        };
        let p = Persson::new(&self.material, &psd, sigma0, PerssonParams::default())
            .and_then(|t| t.point(self.speed))
            .map_err(|e| e.to_string())?;
        let notes = self.persson_notes(map.as_ref());
        Ok(PerssonEstimate {
            friction_coefficient: p.friction_coefficient,
            contact_area_fraction: p.contact_area_fraction,
            nominal_pressure: sigma0,
            psd: kind,
            map,
            notes,
        })
    }
}
