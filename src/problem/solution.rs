//! The result of a solve: fields, scalars, convergence and timings, with
//! what it records of its problem; it analyses itself (the contact
//! analysis of paper Section IV), summarises itself (`summary.json`: every
//! scalar result, convergence, seed, configuration, version, backend, wall
//! time) and writes itself: maps as `.npy` (axis 0 = x = sliding
//! direction) and PNG figures, all files of one solve atomically (see
//! [`crate::io::StagedOutput`]).

use std::path::{Path, PathBuf};

use serde::Serialize;
use serde_json::{json, Value};

use crate::analysis::{self, AnalysisInputs, AnalysisParams, AnalysisReport, ContactStatistics};
use crate::config::{AnalysisConfig, Formulation, Precision};
use crate::error::Result;
use crate::io::{npy, StagedOutput};
use crate::material::Material;
use crate::plot;
use crate::solver::{ContactSolution, SolveInfo, WarmStart};
use crate::surface::Preprocessing;

use super::executor::DeviceTraffic;
use super::persson::PerssonEstimate;
use super::smooth_pad::SmoothPad;
use super::{MeshReport, Problem};

/// Wall-clock split of a solve \[s\].
#[derive(Debug, Clone, Copy, Serialize, Default)]
pub struct Timings {
    /// The fine grid's influence coefficients (tables), prepared once.
    pub coefficients_s: f64,
    /// Every grid's operator built from them (the cascade's coarse tables,
    /// transforms, preconditioner, device buffers; the adaptive rounds'
    /// meshes).
    pub operator_setup_s: f64,
    /// The contact iteration.
    pub iteration_s: f64,
    /// Friction, statistics and warnings of the answer.
    pub analysis_s: f64,
    /// The finite pad's smooth-pad reference (0 where there is none).
    pub smooth_pad_s: f64,
    pub total_s: f64,
}

/// What a solution keeps of its problem: everything but the height map.
#[derive(Debug, Clone)]
struct Record {
    nx: usize,
    ny: usize,
    cell_size: f64,
    cell_size_y: f64,
    cells_per_shortest_wavelength: Option<f64>,
    speed: f64,
    xi: Option<f64>,
    direction_rad: f64,
    seed: Option<u64>,
    preprocessing: Option<Preprocessing>,
    filled_points: usize,
    formulation: Formulation,
    precision: Precision,
    material: Material,
    document: toml::Table,
    analysis: Option<AnalysisConfig>,
}

/// Scalar and field results of one solve.
#[derive(Debug, Clone)]
pub struct Solution {
    /// Pressure, displacement, gap and contact on the grid, and the approach.
    pub fields: ContactSolution,
    pub info: SolveInfo,
    pub stats: ContactStatistics,
    /// `mu = -F_T / F_N` from the exact-work stencil (paper Eq. 9).
    pub friction_coefficient: f64,
    /// `mu` from the dissipated power (Appendix A3-A4).
    pub friction_coefficient_dissipation: f64,
    /// Which executor ran it.
    pub backend: String,
    pub timings: Timings,
    /// Cells solved for: `nx ny` on the uniform grid, the mesh's cells on
    /// the adaptive one.
    pub unknowns: usize,
    /// The adaptive mesh, when one was used.
    pub mesh: Option<MeshReport>,
    /// What the user should know about the validity of the result (also in
    /// `summary.json`).
    pub warnings: Vec<String>,
    /// Persson's theory at the same speed and nominal pressure
    /// ([`Problem::persson_estimate`]), or why it does not apply.
    pub persson: std::result::Result<PerssonEstimate, String>,
    /// The finite pad's own friction (the same pad without roughness) and
    /// the roughness part; `None` for the periodic formulation and the
    /// adaptive mesh.
    pub smooth_pad: Option<SmoothPad>,
    /// The device round trips of the solve's products (a GPU's mixed
    /// precision; the smooth pad's are its own), `None` elsewhere.
    pub device_traffic: Option<DeviceTraffic>,
    record: Record,
}

impl Solution {
    #[allow(clippy::too_many_arguments)]
    pub(super) fn new(
        problem: &Problem,
        fields: ContactSolution,
        info: SolveInfo,
        stats: ContactStatistics,
        (friction_coefficient, friction_coefficient_dissipation): (f64, f64),
        backend: String,
        timings: Timings,
        unknowns: usize,
        mesh: Option<MeshReport>,
        mut warnings: Vec<String>,
    ) -> Self {
        let persson = problem.persson_estimate(stats.mean_pressure);
        if let Ok(PerssonEstimate { map: Some(m), .. }) = &persson {
            warnings.extend(m.warning.clone());
        }
        Self {
            fields,
            info,
            stats,
            // `+ 0.0` turns a negative zero (an elastic material's sum of
            // zeros with a minus sign) into zero, which the outputs print
            // as `0`, not `-0`.
            friction_coefficient: friction_coefficient + 0.0,
            friction_coefficient_dissipation: friction_coefficient_dissipation + 0.0,
            backend,
            timings,
            unknowns,
            mesh,
            warnings,
            persson,
            smooth_pad: None,
            device_traffic: None,
            record: Record {
                nx: problem.surface.nx,
                ny: problem.surface.ny,
                cell_size: problem.surface.cell_size,
                cell_size_y: problem.surface.cell_size_y,
                cells_per_shortest_wavelength: problem.cells_per_shortest_wavelength(),
                speed: problem.speed,
                xi: problem.xi(),
                direction_rad: problem.direction_rad,
                seed: problem.seed,
                preprocessing: problem.preprocessing,
                filled_points: problem.filled_points,
                formulation: problem.formulation,
                precision: problem.precision.unwrap_or_default(),
                material: problem.material.clone(),
                document: problem.document.clone(),
                analysis: problem.analysis.clone(),
            },
        }
    }

    /// Record the precision the solve ran in ([`Problem::precision_on`]).
    pub(super) fn record_precision(&mut self, precision: Precision) {
        self.record.precision = precision;
    }

    /// Grid `(nx, ny)`.
    pub fn grid(&self) -> (usize, usize) {
        (self.record.nx, self.record.ny)
    }

    /// Cells per shortest roughness wavelength of the grid solved on (see
    /// [`Problem::cells_per_shortest_wavelength`]); `None` for a sphere.
    pub fn cells_per_shortest_wavelength(&self) -> Option<f64> {
        self.record.cells_per_shortest_wavelength
    }

    /// Sliding speed \[m/s\].
    pub fn speed(&self) -> f64 {
        self.record.speed
    }

    /// `xi = v tau / L` for single-relaxation materials.
    pub fn xi(&self) -> Option<f64> {
        self.record.xi
    }

    /// `|mu - mu_d| / |mu_d|` of the two friction routes (absolute when
    /// `mu_d = 0`).
    pub fn friction_relative_difference(&self) -> f64 {
        let (mu, mu_d) = (
            self.friction_coefficient,
            self.friction_coefficient_dissipation,
        );
        if mu_d != 0.0 {
            (mu - mu_d).abs() / mu_d.abs()
        } else {
            (mu - mu_d).abs()
        }
    }

    /// This solution as the warm start of a neighbouring solve on the same
    /// grid (see [`Problem::solve_from`]).
    pub fn warm_start(&self) -> WarmStart {
        WarmStart {
            contact: self.fields.contact.clone(),
            pressure: self.fields.pressure.clone(),
            approach: self.fields.approach,
        }
    }

    /// The fields as the contact analysis sees them.
    pub fn analysis_inputs(&self) -> AnalysisInputs<'_> {
        let r = &self.record;
        AnalysisInputs {
            nx: r.nx,
            ny: r.ny,
            cell_size: r.cell_size,
            cell_size_y: r.cell_size_y,
            displacement: &self.fields.displacement,
            contact: &self.fields.contact,
            pressure: &self.fields.pressure,
            scales: document_scales(&r.document, r.nx as f64 * r.cell_size),
            xi: r.xi,
        }
    }

    /// The analysis parameters the problem's `[analysis]` section asks for
    /// (`None` when it is disabled). Periodic solves have periodic fields:
    /// no taper.
    pub fn analysis_params(&self) -> Option<AnalysisParams> {
        configured_analysis(self.record.analysis.as_ref(), self.record.formulation)
    }

    /// The contact analysis (paper Eq. 11-13, Fig. 8-10) of this solution.
    pub fn analyze(&self, params: &AnalysisParams) -> Result<AnalysisReport> {
        Ok(analysis::analyze(&self.analysis_inputs(), params)?)
    }

    /// The analysis the problem's `[analysis]` section asks for, `None`
    /// when it is disabled.
    pub fn analyze_configured(&self) -> Result<Option<AnalysisReport>> {
        self.analysis_params().map(|p| self.analyze(&p)).transpose()
    }

    /// The `summary.json` document without an analysis.
    pub fn summary(&self) -> Value {
        self.summary_with(None)
    }

    /// The `summary.json` document. Key names are fixed: scripts read them.
    /// With an analysis, its headline numbers appear under `analysis`.
    pub fn summary_with(&self, analysis: Option<&AnalysisReport>) -> Value {
        let s = &self.stats;
        let r = &self.record;
        let spec = &r.material.spectrum;
        let persson = match &self.persson {
            Ok(p) => json!({
                "nominal_pressure": p.nominal_pressure,
                "psd": p.psd,
                "map_psd": p.map,
                "notes": p.notes,
                "theory": "Persson, J. Chem. Phys. 115, 3840 (2001); physics.md section 10",
            }),
            Err(why) => json!({ "not_evaluated": why }),
        };
        let preprocessing = match &r.preprocessing {
            Some(p) => json!(p),
            None => json!({ "detrend": "none", "window": "none", "taken_as_is": true }),
        };
        let mut doc = json!({
            "friction_coefficient": self.friction_coefficient,
            "friction_coefficient_dissipation": self.friction_coefficient_dissipation,
            "friction_relative_difference": self.friction_relative_difference(),
            "contact_area_fraction": s.contact_area_fraction,
            "contact_area": s.contact_area,
            "contact_cells": s.contact_cells,
            "approach": self.fields.approach,
            "max_pressure": s.max_pressure,
            "mean_pressure": s.mean_pressure,
            "normal_load": s.normal_load,
            "pressure_centroid": s.pressure_centroid,
            "speed": r.speed,
            "xi": r.xi,
            "direction_deg": r.direction_rad.to_degrees(),
            "grid": [r.nx, r.ny],
            "cell_size": r.cell_size,
            "cells_per_shortest_wavelength": r.cells_per_shortest_wavelength,
            "length": [r.nx as f64 * r.cell_size, r.ny as f64 * r.cell_size_y],
            "unknowns": self.unknowns,
            "mesh": self.mesh,
            "iterations": self.info.iterations,
            "matvecs": self.info.matvecs,
            "preconditioner_applications": self.info.preconditioner_applications,
            "matvecs_by_level": self.info.levels,
            "residual": self.info.residual,
            "load_error": self.info.load_error,
            "residual_history": self.info.history,
            "contact_history": self.info.contact_history,
            "backend": self.backend,
            "wall_time_s": self.timings.total_s,
            "timings": self.timings,
            "seed": r.seed,
            "version": crate::version::VERSION,
            "formulation": r.formulation,
            "material": {
                "relaxed_modulus": spec.relaxed_modulus(),
                "glassy_modulus": spec.glassy_modulus,
                "poisson": r.material.poisson,
                "creep_spectrum": spec.terms.iter().map(|t| [t.compliance, t.time]).collect::<Vec<_>>(),
            },
            "config": r.document,
            "analysis": analysis.map(analysis_headline),
            "warnings": self.warnings,
            "persson_friction_coefficient": self.persson.as_ref().ok().map(|p| p.friction_coefficient),
            "persson_contact_area_fraction": self.persson.as_ref().ok().map(|p| p.contact_area_fraction),
            "persson": persson,
        });
        doc["surface_preprocessing"] = preprocessing;
        // Missing points of a measured map filled before solving.
        doc["filled_points"] = json!(r.filled_points);
        doc["precision"] = json!(r.precision);
        doc["exact_matvecs"] = json!(self.info.exact_matvecs);
        // Where a GPU's mixed-precision products spend their time: the
        // host's conversions and writes, the device, the readback.
        doc["device_traffic"] = json!(self.device_traffic);
        // The isothermal temperature and its WLF shift `a_T` (relative to
        // `T_ref`; mu(v, T) = mu(a_T v, T_ref), physics.md section 12);
        // null for a material without WLF constants.
        let shift = r.material.temperature_shift();
        doc["temperature"] = json!(shift.map(|s| s.temperature));
        doc["shift_factor"] = json!(shift.map(|s| s.shift_factor));
        doc["reference_temperature"] = json!(shift.map(|s| s.reference_temperature));
        // The temperatures of the data the WLF constants were fitted to,
        // when recorded: beyond them the shift is extrapolated (warned).
        doc["wlf_range"] = json!(r.material.wlf.and_then(|w| w.data_range));
        // The data's angular frequencies at the solve's temperature, when
        // recorded: a decade beyond them the moduli are extrapolated.
        doc["frequency_range"] = json!(r.material.frequency_range);
        if let Value::Object(p) = &mut doc["persson"] {
            p.insert("temperature".into(), json!(shift.map(|s| s.temperature)));
            p.insert("shift_factor".into(), json!(shift.map(|s| s.shift_factor)));
        }
        // The cell side along y beside `cell_size` (along x): rectangular
        // cells (physics.md section 11).
        doc["cell_size_y"] = json!(r.cell_size_y);
        // The finite pad's own part and the roughness part (non-periodic
        // uniform grids), with Persson against the roughness part.
        doc["smooth_pad_friction_coefficient"] =
            json!(self.smooth_pad.map(|p| p.friction_coefficient));
        doc["roughness_friction_coefficient"] =
            json!(self.smooth_pad.map(|p| p.roughness_friction_coefficient));
        doc["smooth_pad"] = json!(self.smooth_pad.map(|p| {
            let persson = self.persson.as_ref().ok().map(|e| e.friction_coefficient);
            json!({
                "friction_coefficient": p.friction_coefficient,
                "roughness_friction_coefficient": p.roughness_friction_coefficient,
                "share": p.share,
                "persson_over_roughness_part": persson.map(|m| m / p.roughness_friction_coefficient),
                "matvecs": p.matvecs,
                "exact_matvecs": p.exact_matvecs,
                "host_matvecs": p.host_matvecs,
                "time_s": p.time_s,
                "device_traffic": p.device_traffic,
                "what": "the same pad without roughness, at the same load and speed, solved by the constrained iteration on the executor of the rough solve (the CPU: in f64; a GPU: in the rough solve's precision, mixed (f32 products on the device, f64 residuals on the host: exact_matvecs) or f32 on the device to a relative residual of 1e-3; solved in f64 on the host where the device's solve did not converge: host_matvecs of matvecs); friction by paper Eq. 9",
            })
        }));
        // The process's peak resident memory so far (after this solve; in a
        // sweep, over every solve before it too), for sizing jobs.
        doc["peak_memory_bytes"] = json!(crate::io::memory::peak_resident());
        doc
    }

    /// Write every output of this solve into `dir`, the configured analysis
    /// included: all files appear together or not at all. Returns the
    /// written paths.
    pub fn write(&self, dir: &Path) -> Result<Vec<PathBuf>> {
        self.write_with(dir, &SolveExtras::default())
    }

    /// [`Solution::write`] with what a layer above the solve adds (the
    /// heated solve's `heating` object and temperature maps), in the same
    /// all-or-nothing write.
    pub(crate) fn write_with(&self, dir: &Path, extras: &SolveExtras) -> Result<Vec<PathBuf>> {
        let report = self.analyze_configured()?;
        let (nx, ny) = (self.record.nx, self.record.ny);
        let (ax, ay) = (self.record.cell_size, self.record.cell_size_y);
        let mut staged = StagedOutput::new(dir)?;
        let set: Vec<&str> = SOLVE_FILES
            .iter()
            .chain(analysis::ANALYSIS_FILES.iter())
            .chain(EXTRA_FILES.iter())
            .copied()
            .collect();
        staged.replaces(&set);
        let mut doc = self.summary_with(report.as_ref());
        for (key, value) in &extras.summary {
            doc[*key] = value.clone();
        }
        staged.write(
            "summary.json",
            serde_json::to_string_pretty(&doc)
                .expect("summary is serialisable")
                .as_bytes(),
        )?;
        let sol = &self.fields;
        for (name, field) in [
            ("pressure.npy", &sol.pressure),
            ("displacement.npy", &sol.displacement),
            ("gap.npy", &sol.gap),
            ("contact.npy", &sol.contact),
        ] {
            staged.write(name, &npy::encode_f64(&[nx, ny], field))?;
        }
        let extent = (0.0, nx as f64 * ax, 0.0, ny as f64 * ay);
        let title_suffix = match self.record.xi {
            Some(xi) => format!("xi = {xi:.3e}"),
            None => format!("v = {:.3e} m/s", self.record.speed),
        };
        let p = staged.path("pressure.png");
        plot::heatmap(
            &p,
            &format!("Contact pressure, {title_suffix}"),
            &plot::Field {
                nx,
                ny,
                values: &sol.pressure,
                extent,
            },
            "p [Pa]",
            None,
        )?;
        let c = staged.path("contact.png");
        plot::heatmap(
            &c,
            &format!(
                "Contact area (A/A0 = {:.4}), {title_suffix}",
                self.stats.contact_area_fraction
            ),
            &plot::Field {
                nx,
                ny,
                values: &sol.contact,
                extent,
            },
            "in contact",
            None,
        )?;
        if let Some(r) = &report {
            analysis::write_analysis(&mut staged, &self.analysis_inputs(), r)?;
        }
        for (name, bytes) in &extras.files {
            debug_assert!(EXTRA_FILES.contains(name), "{name} is not in EXTRA_FILES");
            staged.write(name, bytes)?;
        }
        for map in &extras.maps {
            debug_assert!(
                EXTRA_FILES.contains(&map.file),
                "{} is not in EXTRA_FILES",
                map.file
            );
            staged.write(
                &format!("{}.npy", map.file.trim_end_matches(".png")),
                &npy::encode_f64(&[nx, ny], &map.values),
            )?;
            let path = staged.path(map.file);
            plot::heatmap(
                &path,
                &format!("{}, {title_suffix}", map.title),
                &plot::Field {
                    nx,
                    ny,
                    values: &map.values,
                    extent,
                },
                map.unit,
                None,
            )?;
        }
        Ok(staged.commit()?)
    }
}

/// The analysis parameters an `[analysis]` section asks for on a solve of
/// `formulation` (`None` when it is disabled). Periodic solves have
/// periodic fields: no taper.
pub(super) fn configured_analysis(
    section: Option<&AnalysisConfig>,
    formulation: Formulation,
) -> Option<AnalysisParams> {
    let cfg = section.cloned().unwrap_or_default();
    if !cfg.enabled.unwrap_or(true) {
        return None;
    }
    Some(AnalysisParams::configured(
        &cfg,
        formulation == Formulation::Periodic,
    ))
}

/// The surface's number of scales `q1 / q0` that the configuration
/// `document` records, for a map of side `lx` \[m\] along x (`q0 = 2 pi /
/// lx`); `None` where it records none.
pub(super) fn document_scales(document: &toml::Table, lx: f64) -> Option<f64> {
    let config = serde_json::to_value(document).unwrap_or(Value::Null);
    analysis::scales_from_config(&config, 2.0 * std::f64::consts::PI / lx)
}

/// The files a solve writes besides the analysis's
/// ([`analysis::ANALYSIS_FILES`]); a new write replaces the whole set.
const SOLVE_FILES: [&str; 7] = [
    "summary.json",
    "pressure.npy",
    "displacement.npy",
    "gap.npy",
    "contact.npy",
    "pressure.png",
    "contact.png",
];

/// The files a layer above the solve may add ([`SolveExtras`]); every
/// write replaces them too, so that no stale map outlives its solve.
const EXTRA_FILES: [&str; 4] = [
    "temperature.npy",
    "temperature.png",
    "temperature_depth.csv",
    "heat.json",
];

/// What a layer above the solve adds to its outputs.
#[derive(Debug, Clone, Default)]
pub(crate) struct SolveExtras {
    /// `summary.json` keys and their values.
    pub summary: Vec<(&'static str, Value)>,
    /// Files by name (one of `temperature_depth.csv`, `heat.json`).
    pub files: Vec<(&'static str, Vec<u8>)>,
    /// Maps on the solve's grid, each written as `NAME.npy` and drawn as
    /// `NAME.png` (`file` is the PNG's name: `temperature.png`).
    pub maps: Vec<ExtraMap>,
}

/// One map of [`SolveExtras`].
#[derive(Debug, Clone)]
pub(crate) struct ExtraMap {
    /// The PNG's file name.
    pub file: &'static str,
    /// The plot's title (the speed is appended).
    pub title: String,
    /// The colour bar's label.
    pub unit: &'static str,
    /// One value per cell (C order, axis 0 = x).
    pub values: Vec<f64>,
}

/// The headline numbers of an analysis, as recorded in `summary.json`.
fn analysis_headline(r: &AnalysisReport) -> Value {
    json!({
        "gamma": r.gamma,
        "theta_p_deg": r.theta_p_deg,
        "m20": r.m20,
        "m02": r.m02,
        "m11": r.m11,
        "lambda": r.lambda,
        "ellipse_angle_deg": r.ellipse_angle_deg,
        "spots": r.spots.count,
    })
}
