//! A [`Problem`] from a configuration: the `[material]`, `[surface]`,
//! `[loading]`, `[solver]` and optional `[layer]` and `[analysis]` sections,
//! read and checked, and the memory a grid needs.

use std::path::Path;

use crate::config::{
    Formulation, LoadedConfig, LoadingConfig, MeshKind, Precision, Pressing, SolverConfig,
    SurfaceConfig,
};
use crate::error::Result;
use crate::solver::{Control, SolverParams};

use super::{invalid, speed_of, AdaptiveParams, Problem, SurfaceSource};

impl Problem {
    /// Read and check the `[material]`, `[surface]`, `[loading]`, `[solver]`
    /// and optional `[layer]` sections.
    pub fn from_config(cfg: &LoadedConfig) -> Result<Self> {
        let material = cfg.material()?.build(&cfg.base_dir)?;
        let surface_cfg = cfg.surface()?;
        let sc = cfg.config.solver.clone().unwrap_or_default();
        let restart = sc.restart.unwrap_or(SolverParams::default().restart);
        let formulation = sc.formulation.unwrap_or_default();
        let precision = sc.precision.unwrap_or_default();
        // Refuse grids that cannot fit before generating them, or before
        // reading a file whose header gives its grid.
        if let Some(gp) = surface_cfg.generate_params()? {
            check_memory(gp.nx, gp.ny, restart, formulation, precision)?;
        }
        if let Some((nx, ny)) = surface_cfg.file_grid(&cfg.base_dir) {
            check_memory(nx, ny, restart, formulation, precision)?;
        }
        // The periodic formulation takes a measured map as one period.
        let periodic_solve = formulation == Formulation::Periodic;
        let (surface, filled_points) = surface_cfg.load_counting(&cfg.base_dir, periodic_solve)?;
        check_memory(surface.nx, surface.ny, restart, formulation, precision)?;
        let seed = surface_cfg.generate.as_ref().map(|g| g.seed.unwrap_or(0));
        let source = SurfaceSource::of(surface_cfg, &cfg.base_dir)?;
        let loading = cfg.config.loading.clone().ok_or_else(|| {
            invalid(format!(
                "{}: section [loading] is required (normal_load or mean_pressure, and speed or xi)",
                cfg.path.display()
            ))
        })?;
        let mut problem = Self::new(material, surface, Control::Load(0.0), 0.0)
            .with_loading(&loading)?
            .with_solver_config(&sc)?;
        let layer = cfg.config.layer.as_ref().map(|l| l.build()).transpose()?;
        problem.source = source;
        problem.preprocessing = surface_cfg.preprocessing_for(periodic_solve)?;
        problem.filled_points = filled_points;
        problem.layer = layer;
        problem.seed = seed;
        problem.document = cfg.document.clone();
        problem.analysis = cfg.config.analysis.clone();
        problem.check()?;
        Ok(problem)
    }

    /// The `[loading]` section on this problem: the normal load
    /// (`normal_load`, or `mean_pressure` times the map's area) or the
    /// approach, the speed (`speed`, or `xi` for a single-relaxation
    /// material) and the direction; `temperature` shifts the material by
    /// its WLF factor ([`crate::material::Material::at_temperature`]). Exactly one of the three
    /// controls and one of the two speeds must be given.
    pub fn with_loading(mut self, loading: &LoadingConfig) -> Result<Self> {
        loading.check_finite().map_err(invalid)?;
        let area0 = self.surface.length_x() * self.surface.length_y();
        self.control = match loading.pressing().map_err(invalid)? {
            Some(Pressing::NormalLoad(f)) => Control::Load(f),
            Some(Pressing::MeanPressure(p)) => {
                if !(p.is_finite() && p > 0.0) {
                    return Err(invalid(format!(
                        "[loading] mean_pressure must be positive and finite, got {p} Pa"
                    )));
                }
                let f = p * area0;
                if f < f64::MIN_POSITIVE {
                    return Err(invalid(format!(
                            "[loading] mean_pressure = {p:e} Pa over the map's {area0:e} m^2 is a normal load of {f:e} N, below double precision's normal range ({:e}); raise it",
                            f64::MIN_POSITIVE
                        )));
                }
                Control::Load(f)
            }
            Some(Pressing::Approach(d)) => Control::Approach(d),
            None => {
                return Err(invalid(
                    "[loading] needs one of normal_load (N), mean_pressure (Pa) or approach (m)",
                ))
            }
        };
        // The material at the temperature asked for, before `xi` reads its
        // creep time: the one shift every consumer of the spectrum sees.
        self.material = self.material.at(loading.temperature)?;
        let sliding = loading.sliding().map_err(invalid)?;
        self.speed = speed_of(sliding, &self.material, &self.surface)?;
        if let Some(t) = loading.temperature {
            self.check_shifted_speed(t)?;
        }
        self.direction_rad = crate::response::direction_rad(loading.direction_deg.unwrap_or(0.0));
        Ok(self)
    }

    /// At temperature `t` \[C\], the speed and every `xi_k = v a_T tau_k /
    /// L` of the shifted material finite, and nonzero when sliding: a
    /// shift factor in the WLF validity range (physics.md section 12)
    /// keeps them so unless the inputs are themselves extreme.
    fn check_shifted_speed(&self, t: f64) -> Result<()> {
        let v = self.speed;
        if v.is_nan() || v < 0.0 {
            // A negative (or NaN) speed is the speed's own error, which
            // `Problem::check` names; no temperature would mend it.
            return Ok(());
        }
        let length = self.surface.length_x();
        for (k, term) in self.material.spectrum.terms.iter().enumerate() {
            let xi = v * term.time / length;
            if !(v.is_finite() && xi.is_finite() && (v == 0.0 || xi > 0.0)) {
                return Err(invalid(format!(
                    "[loading] temperature = {t} C: the speed {v} m/s and the shifted creep time {} of {} s give xi = v tau / L = {xi}, outside the range of double precision; give a temperature nearer T_ref or another speed",
                    k + 1,
                    term.time
                )));
            }
        }
        Ok(())
    }

    /// The `[solver]` section on this problem: iteration controls (missing
    /// keys take [`SolverParams::default`]), the cascade's depth, the
    /// precision, formulation, mesh and the adaptive mesh's controls.
    pub fn with_solver_config(mut self, sc: &SolverConfig) -> Result<Self> {
        let defaults = SolverParams::default();
        self.params = SolverParams {
            tolerance: sc.tolerance.unwrap_or(defaults.tolerance),
            max_iterations: sc.max_iterations.unwrap_or(defaults.max_iterations),
            max_matvecs: sc.max_matvecs.unwrap_or(defaults.max_matvecs),
            restart: sc.restart.unwrap_or(defaults.restart),
            precondition: sc.precondition.unwrap_or(defaults.precondition),
        };
        self.cascade_levels = sc
            .cascade_levels
            .unwrap_or(super::cascade::DEFAULT_CASCADE_LEVELS);
        self.precision = sc.precision;
        match (sc.precision, sc.gpu_refine) {
            (Some(p @ Precision::Mixed), Some(false)) | (Some(p @ Precision::F32), Some(true)) => {
                return Err(invalid(format!(
                    "[solver] precision = \"{}\" and gpu_refine = {} disagree (gpu_refine is the older spelling of a GPU's precision: true \"mixed\", false \"f32\"); give precision alone",
                    p.name(),
                    sc.gpu_refine == Some(true)
                )))
            }
            _ => {}
        }
        for (key, value, what) in [
            (
                "max_matvecs",
                self.params.max_matvecs,
                "the budget of operator products",
            ),
            (
                "max_iterations",
                self.params.max_iterations,
                "the budget of active-set iterations",
            ),
            (
                "restart",
                self.params.restart,
                "the GMRES restart length, default 30",
            ),
        ] {
            if value == 0 {
                return Err(invalid(format!(
                    "[solver] {key} = 0: must be at least 1 ({what})"
                )));
            }
        }
        if self.cascade_levels == 0 {
            return Err(invalid(
                "[solver] cascade_levels must be at least 1 (1: the fine grid only)",
            ));
        }
        self.gpu_refine = sc.gpu_refine.unwrap_or(true);
        self.formulation = sc.formulation.unwrap_or_default();
        self.mesh = sc.mesh.unwrap_or_default();
        let ad = AdaptiveParams::default();
        self.adaptive = match &sc.adaptive {
            Some(c) => AdaptiveParams {
                max_level: c.max_level.unwrap_or(ad.max_level),
                initial_fraction: c.initial_fraction.unwrap_or(ad.initial_fraction),
                margin: c.margin.unwrap_or(ad.margin),
                max_rounds: c.max_rounds.unwrap_or(ad.max_rounds),
            },
            None => ad,
        };
        if sc.adaptive.is_some() && self.mesh != MeshKind::Adaptive {
            return Err(invalid(
                "[solver.adaptive] is given but [solver] mesh is not \"adaptive\"",
            ));
        }
        Ok(self)
    }

    /// Check the values: a positive load or approach, a speed `>= 0`, a
    /// finite direction, a tolerance in (0, 1), and the combinations the
    /// formulations support. Every solve checks its problem first.
    pub fn check(&self) -> Result<()> {
        match self.control {
            Control::Load(f) if !(f.is_finite() && f > 0.0) => {
                return Err(invalid(format!(
                    "[loading] the normal load must be positive and finite, got {f} N"
                )))
            }
            Control::Approach(d) if !(d.is_finite() && d > 0.0) => {
                return Err(invalid(format!(
                    "[loading] approach must be positive and finite, got {d} m"
                )))
            }
            _ => {}
        }
        if self.speed.is_nan() || self.speed < 0.0 {
            return Err(invalid(format!(
                "[loading] speed must be >= 0, got {} m/s",
                self.speed
            )));
        }
        if self.speed.is_infinite() {
            return Err(invalid(format!(
                "[loading] speed = {} m/s must be finite",
                self.speed
            )));
        }
        if !self.direction_rad.is_finite() {
            return Err(invalid("[loading] direction_deg must be finite"));
        }
        self.check_sides()?;
        self.check_heights()?;
        self.check_periodic_approach()?;
        if !(self.params.tolerance > 0.0 && self.params.tolerance < 1.0) {
            return Err(invalid(format!(
                "[solver] tolerance must be in (0, 1), got {}",
                self.params.tolerance
            )));
        }
        if self.mesh == MeshKind::Adaptive && self.formulation == Formulation::Periodic {
            return Err(invalid(
                "[solver] mesh = \"adaptive\" needs formulation = \"non_periodic\" (the periodic formulation is spectral)",
            ));
        }
        // Checked here, not at the solve, so that a study or a sweep
        // refuses it before its first point.
        if self.mesh == MeshKind::Adaptive && self.precision == Some(Precision::Mixed) {
            return Err(invalid(
                "[solver] precision = \"mixed\" applies to uniform and periodic grids; the adaptive mesh is not refined (use precision = \"f64\" on the CPU, \"f32\" on a GPU, or mesh = \"uniform\")",
            ));
        }
        if self.formulation == Formulation::Periodic && self.precision == Some(Precision::F32) {
            return Err(invalid(
                "[solver] precision = \"f32\" runs on a GPU, which solves the non-periodic formulation; use precision = \"f64\" or \"mixed\" with formulation = \"periodic\"",
            ));
        }
        self.adaptive.check().map_err(invalid)?;
        if self.mesh == MeshKind::Adaptive {
            self.check_adaptive_cells()?;
        }
        self.check_layer_cells()?;
        Ok(())
    }

    /// The analysis that the `[analysis]` section runs after the solve
    /// (`solve`, Python's `solve` and a sweep's points analyse each
    /// solution), checked on this grid before anything is solved: its
    /// parameters, and a grid large enough for its band (at least 4 cells
    /// per side for the default `zeta1 = 1`). A problem solved without its
    /// analysis (a refinement level) need not pass it.
    pub fn check_analysis(&self) -> Result<()> {
        let Some(params) =
            super::solution::configured_analysis(self.analysis.as_ref(), self.formulation)
        else {
            return Ok(());
        };
        let scales = super::solution::document_scales(&self.document, self.surface.length_x());
        crate::analysis::fields::check_grid(self.surface.nx, self.surface.ny, &params, scales)?;
        Ok(())
    }

    /// The map's sides in the range of a generated surface's `length`
    /// ([`crate::surface::LENGTH_RANGE`], a nanometre to a kilometre):
    /// beyond it a load spread over the map, its heights and gaps leave
    /// double precision's useful range, and a pad of 1e150 m was refused
    /// as a load too small or a solve that did not converge. Refused in
    /// one line naming the side, its key and the range.
    fn check_sides(&self) -> Result<()> {
        let (lo, hi) = crate::surface::LENGTH_RANGE;
        let s = &self.surface;
        for (axis, key, side, cell) in [
            ("x", "length", s.length_x(), s.cell_size),
            ("y", "length_y", s.length_y(), s.cell_size_y),
        ] {
            if !(lo..=hi).contains(&side) {
                return Err(invalid(format!(
                    "[surface] the map's side along {axis} is {side:e} m (`{key}`; {} cells of {cell:e} m): it must lie in [{lo:e}, {hi:e}] m (a nanometre to a kilometre: beyond, the heights, gaps and loads leave double precision's useful range); check the map's length and unit",
                    if axis == "x" { s.nx } else { s.ny },
                )));
            }
        }
        Ok(())
    }

    /// The map's rms height and rms slope (forward differences) finite:
    /// heights beyond about 1e150 m, a unit read wrong, square out of f64,
    /// and such a map solved and reported an rms slope of inf. Refused in
    /// one line naming the statistic and the largest height.
    fn check_heights(&self) -> Result<()> {
        let s = &self.surface;
        let n = s.heights.len().max(1) as f64;
        let mean = s.heights.iter().sum::<f64>() / n;
        let rms_height = (s.heights.iter().map(|h| (h - mean).powi(2)).sum::<f64>() / n).sqrt();
        let rms_slope =
            crate::surface::rms_slope_real(s.nx, s.ny, s.cell_size, s.cell_size_y, &s.heights);
        for (what, value) in [("rms height", rms_height), ("rms slope", rms_slope)] {
            if !value.is_finite() {
                return Err(crate::surface::overflow(what, value, &s.heights).into());
            }
        }
        Ok(())
    }

    /// The periodic formulation under approach control: its displacements
    /// have zero mean (the `q = 0` multiplier is 0, paper Appendix), so the
    /// contact closes at the approach `mean(g)`, the highest summit above
    /// the mean plane, and a larger approach has no solution (at it, the
    /// mean pressure is undetermined). Refused in one line naming the bound.
    fn check_periodic_approach(&self) -> Result<()> {
        let Control::Approach(d) = self.control else {
            return Ok(());
        };
        if self.formulation != Formulation::Periodic {
            return Ok(());
        }
        let g = self.gap_profile();
        let full = g.iter().sum::<f64>() / g.len().max(1) as f64;
        // Within round-off of the bound counts as at it.
        if d >= full * (1.0 - 1e-9) {
            return Err(invalid(format!(
                "[loading] approach = {d:e} m is at or beyond full contact of the periodic cell, reached at {full:.6e} m (the highest summit above the mean plane): a periodic cell's displacements have zero mean, so no larger approach has a solution; give an approach below {full:.6e} m, a mean_pressure, or formulation = \"non_periodic\""
            )));
        }
        Ok(())
    }

    /// A layer far below a cell (kernel's `check_layer_cells`): at least
    /// `kernel::THIN_RATIO_MIN` of a cell on every formulation; the
    /// tables' local limit also asks for a grid-axis direction, a uniform
    /// mesh and a compressible or frictionless layer.
    fn check_layer_cells(&self) -> Result<()> {
        let Some(layer) = self.layer else {
            return Ok(());
        };
        let (ax, ay) = self.surface.cell();
        let a = ax.max(ay);
        if self.formulation == Formulation::Periodic {
            if layer.thickness < crate::kernel::THIN_RATIO_MIN * a {
                return Err(invalid(format!(
                    "[layer] thickness = {:e} m is {:.3e} of a cell ({a:e} m), below the bound of {:e} of a cell; use cells of at most {:e} m or a thicker layer",
                    layer.thickness,
                    layer.thickness / a,
                    crate::kernel::THIN_RATIO_MIN,
                    layer.thickness / crate::kernel::THIN_RATIO_MIN
                )));
            }
            return Ok(());
        }
        let kernel = self.sliding_kernel()?;
        kernel.check_layer_cells(ax, ay)?;
        if self.mesh == MeshKind::Adaptive && kernel.is_thin(ax, ay) {
            return Err(invalid(format!(
                "[layer] thickness = {:e} m is {:.3e} of a cell: the adaptive mesh needs a layer resolved by its finest cells; use mesh = \"uniform\"",
                layer.thickness,
                layer.thickness / a
            )));
        }
        Ok(())
    }

    /// The adaptive quadtree merges 2 x 2 blocks of square cells into square
    /// cells (physics.md section 7; its level tables and vertex offsets are
    /// built for squares): rectangular cells are refused with the remedy.
    pub(super) fn check_adaptive_cells(&self) -> Result<()> {
        if self.surface.square_cells() {
            return Ok(());
        }
        Err(invalid(format!(
            "[solver] mesh = \"adaptive\" needs square cells (its quadtree merges square blocks), the map has {:.4e} m x {:.4e} m cells; use mesh = \"uniform\" or resample the map to square pixels",
            self.surface.cell_size, self.surface.cell_size_y
        )))
    }
}

impl SurfaceSource {
    /// What the `[surface]` section `section` makes its surface from,
    /// relative paths resolved against `base_dir`: generated parameters, a
    /// PSD table with its synthesis parameters, a sphere or a file.
    pub fn of(section: &SurfaceConfig, base_dir: &Path) -> Result<Self> {
        Ok(
            match (section.generate_params()?, &section.sphere, &section.file) {
                (Some(p), _, _) => SurfaceSource::Generated(p),
                (None, None, None) if section.generate.is_some() => {
                    let g = section.generate.as_ref().expect("generate");
                    match g.synth_params(section.length)? {
                        Some((table, params)) => {
                            let path = base_dir.join(table);
                            SurfaceSource::Synthesised {
                                table: crate::surface::TabulatedPsd::from_csv(&path)?,
                                path,
                                params,
                            }
                        }
                        None => SurfaceSource::Given,
                    }
                }
                (None, Some(s), _) => SurfaceSource::Sphere(*s),
                (None, None, Some(f)) => SurfaceSource::File(base_dir.join(f)),
                (None, None, None) => SurfaceSource::Given,
            },
        )
    }
}

/// Bytes the CPU path needs for an `nx x ny` grid, by array (B/cell,
/// BENCHMARKS.md "Mixed precision"): the operator's spectra and spectrum
/// buffer (periodic: multiplier and inverse, 8 + 8 in f64, 4 + 4 in mixed
/// precision, and an 8 B buffer; non-periodic: twice as many modes on the
/// padded transform, T. Chan's circulant and the coefficient table during
/// set-up); the iteration's grid vectors: pressure and gap (f64, 16), the
/// contact mask (1 byte) and the line search's previous pressure and gap
/// (16); the heights and the gap profile (16); and a Krylov basis of
/// `restart + 5` f64 vectors over a contact set of a twentieth of the grid
/// (rough-surface contacts are smaller; the iteration refuses, in words, a
/// larger set that does not fit as it grows).
pub(crate) fn memory_estimate(
    nx: usize,
    ny: usize,
    restart: usize,
    formulation: Formulation,
    precision: Precision,
) -> u64 {
    let n = (nx as u64).saturating_mul(ny as u64);
    let spectra: u64 = match (formulation, precision) {
        (Formulation::Periodic, Precision::F64) => 24,
        (Formulation::Periodic, Precision::Mixed | Precision::F32) => 16,
        // Set-up: table (32), wrapped kernel (32) and its f64 spectrum
        // (32) beside the engine being built.
        (Formulation::NonPeriodic, Precision::F64) => 112 + 32,
        (Formulation::NonPeriodic, Precision::Mixed | Precision::F32) => 68 + 64,
    };
    let basis = (8 * (restart as u64 + 5)).div_ceil(20);
    n.saturating_mul(spectra + 33 + 16 + basis)
}

/// Refuse an `nx x ny` grid whose memory estimate exceeds the memory
/// available now (read from `/proc/meminfo`; no check where it is absent).
pub fn check_memory(
    nx: usize,
    ny: usize,
    restart: usize,
    formulation: Formulation,
    precision: Precision,
) -> Result<()> {
    let need = memory_estimate(nx, ny, restart, formulation, precision);
    crate::io::memory::check_fits(|| format!("{nx} x {ny} grid"), need)
        .map_err(|e| invalid(e.to_string()))
}
