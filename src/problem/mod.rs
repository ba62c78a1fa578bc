//! The library API: a [`Problem`] (material, surface, loading, layer,
//! solver options), built from a configuration or directly from values;
//! [`Problem::solve`] on an [`Executor`] gives a [`Solution`] (fields,
//! scalars, convergence, timings) that analyses ([`Solution::analyze`]),
//! summarises ([`Solution::summary`]) and writes itself
//! ([`Solution::write`], all files or none). Every front end (the command
//! line, sweeps, comparisons) goes through this module.
//!
//! - [`setup`]: reading and checking a problem from a configuration.
//! - [`executor`]: CPU or GPU, and the choice for `--backend`.
//! - [`solve`]: the one path through a solve: the operator chosen by
//!   formulation x mesh, the executor by backend, one call of the iteration.
//! - [`adaptive`]: the solve-certify-refine loop of the adaptive mesh.
//! - `precision`: the arithmetic of a solve on an executor
//!   ([`Problem::precision_on`]).
//! - [`solution`]: the result, its summary, analysis and files.
//! - [`warnings`]: what a solution says about its own validity.
//! - `heating`: the heat of a solved contact ([`ContactHeating`]).
//! - [`persson`]: Persson's theory for a configuration or a problem, the
//!   analytic reference beside every simulation.
//!
//! Re-discretising: [`Problem::with_grid`] gives the same physical problem on
//! another grid (a generated surface is generated again with the same seed
//! and parameters; a sphere is sampled again), and [`Problem::solve_from`]
//! takes an optional warm start, so a coarse-to-fine cascade is wired in
//! one place.

pub mod adaptive;
mod cascade;
pub mod executor;
mod friction;
mod heating;
pub mod persson;
mod precision;
pub mod resolution;
pub mod setup;
pub mod smooth_pad;
pub mod solution;
pub mod solve;
pub mod warnings;

use std::path::PathBuf;

pub use adaptive::{AdaptiveParams, AdaptiveSolution, MeshReport};
pub use executor::{DeviceTraffic, Executor};
pub use heating::ContactHeating;
pub(crate) use heating::{balance_warning, no_heat_note};
pub use resolution::ShortestWavelength;
pub(crate) use resolution::MIN_CELLS_PER_WAVELENGTH;
pub use setup::check_memory;
pub(crate) use setup::memory_estimate;
pub(crate) use solution::{ExtraMap, SolveExtras};
pub use solution::{Solution, Timings};
pub(crate) use solve::Discretisation;

// The engine types the library API takes or returns (the engine itself is
// under `crate::internals`).
pub use crate::analysis::{AnalysisParams, AnalysisReport};
pub use crate::backend::BackendChoice;
pub use crate::kernel::{Axis, CoefficientTable, SlidingKernel};
pub use crate::solver::{
    ContactSolution, Control, Observer, Silent, SolveInfo, SolverError, SolverParams,
};

use crate::config::{
    AnalysisConfig, Formulation, MeshKind, Precision, Sliding, SphereConfig, XiScale,
};
use crate::error::{Error, Result};
use crate::material::Material;
use crate::response::{Grid, Layer, SlidingResponse};
use crate::surface::{GenerateParams, HeightMap, Preprocessing, SynthParams, TabulatedPsd};

/// Where the surface of a problem came from: what [`Problem::with_grid`]
/// needs to sample it again at another resolution.
#[derive(Debug, Clone, PartialEq)]
pub enum SurfaceSource {
    /// Generated from these parameters (the seed included).
    Generated(GenerateParams),
    /// The paraboloid of a sphere.
    Sphere(SphereConfig),
    /// Synthesised from the tabulated PSD read from `path` with random
    /// phases per Fourier mode (`[surface.generate] psd`): resolution
    /// consistent like [`SurfaceSource::Generated`].
    Synthesised {
        path: PathBuf,
        table: TabulatedPsd,
        params: SynthParams,
    },
    /// Read from this file: one resolution only.
    File(PathBuf),
    /// Given as a height map by the caller: one resolution only.
    Given,
}

/// One steady-sliding contact problem, checked.
#[derive(Debug, Clone)]
pub struct Problem {
    pub material: Material,
    pub surface: HeightMap,
    /// What the surface was made from.
    pub source: SurfaceSource,
    /// How a measured map was prepared before it became `surface`
    /// (detrending, the window of its PSDs; physics.md section 11);
    /// `None` for generated surfaces, spheres and maps given as values
    /// without a record, which are taken as they are.
    pub preprocessing: Option<Preprocessing>,
    /// Missing points of a measured map filled by harmonic interpolation
    /// (`fill_missing`) before it became `surface`; 0 where none were.
    pub filled_points: usize,
    pub control: Control,
    /// Sliding speed \[m/s\].
    pub speed: f64,
    /// Sliding direction \[rad\] from +x.
    pub direction_rad: f64,
    pub layer: Option<Layer>,
    pub params: SolverParams,
    /// Grids of the coarse-to-fine cascade at most, the fine one included
    /// (`[solver] cascade_levels`, default 8; 1: the fine grid only): uniform
    /// grids without an outside start.
    pub cascade_levels: usize,
    /// Arithmetic of the iteration (`[solver] precision`, physics.md
    /// section 13) on every executor; `None`: each executor's own
    /// ([`Problem::precision_on`]).
    pub precision: Option<Precision>,
    /// Where `precision` is `None`, a GPU's on a uniform grid: true
    /// (default) [`Precision::Mixed`], the one iteration of f32 products on
    /// the device and f64 residuals on the host; false [`Precision::F32`]
    /// (`[solver] gpu_refine`, the older spelling).
    pub gpu_refine: bool,
    pub formulation: Formulation,
    /// Uniform grid or adaptive quadtree (non-periodic formulation).
    pub mesh: MeshKind,
    /// Controls of the adaptive mesh.
    pub adaptive: AdaptiveParams,
    /// Seed of a generated surface.
    pub seed: Option<u64>,
    /// The merged configuration document (recorded in `summary.json`).
    pub document: toml::Table,
    /// `[analysis]` settings (`None`: the defaults, analysis on).
    pub analysis: Option<AnalysisConfig>,
}

pub(super) fn invalid(msg: impl Into<String>) -> Error {
    Error::Invalid(msg.into())
}

impl Problem {
    /// A problem from values: `surface` pressed by `control` and sliding
    /// along +x at `speed` \[m/s\] on a half-space of `material`; the
    /// non-periodic formulation on a uniform grid with the default solver
    /// controls. Change any of them with the `with_*` methods.
    pub fn new(material: Material, surface: HeightMap, control: Control, speed: f64) -> Self {
        Self {
            material,
            surface,
            source: SurfaceSource::Given,
            preprocessing: None,
            filled_points: 0,
            control,
            speed,
            direction_rad: 0.0,
            layer: None,
            params: SolverParams::default(),
            cascade_levels: cascade::DEFAULT_CASCADE_LEVELS,
            precision: None,
            gpu_refine: true,
            formulation: Formulation::default(),
            mesh: MeshKind::default(),
            adaptive: AdaptiveParams::default(),
            seed: None,
            document: toml::Table::new(),
            analysis: None,
        }
    }

    /// [`Problem::new`] on a generated self-affine surface (physics.md
    /// section 8): the surface is generated from `surface` and recorded, so
    /// that [`Problem::with_grid`] can generate it again at another size.
    pub fn generated(
        material: Material,
        surface: GenerateParams,
        control: Control,
        speed: f64,
    ) -> Result<Self> {
        setup::check_memory(
            surface.nx,
            surface.ny,
            SolverParams::default().restart,
            Formulation::default(),
            Precision::default(),
        )?;
        let map = crate::surface::generate(&surface)?;
        let mut problem = Self::new(material, map, control, speed);
        problem.seed = Some(surface.seed);
        problem.source = SurfaceSource::Generated(surface);
        Ok(problem)
    }

    /// Sliding direction in degrees from +x.
    pub fn with_direction_deg(mut self, degrees: f64) -> Self {
        self.direction_rad = crate::response::direction_rad(degrees);
        self
    }

    /// A layer of finite thickness on a rigid base (paper Eq. 5).
    pub fn with_layer(mut self, layer: Layer) -> Self {
        self.layer = Some(layer);
        self
    }

    /// Solver controls.
    pub fn with_solver_params(mut self, params: SolverParams) -> Self {
        self.params = params;
        self
    }

    /// At most `levels` grids of the coarse-to-fine cascade, the fine one
    /// included (1: the fine grid only).
    pub fn with_cascade_levels(mut self, levels: usize) -> Self {
        self.cascade_levels = levels;
        self
    }

    /// The arithmetic of the iteration on every executor (physics.md
    /// section 13; refused in one line where an executor cannot run it).
    pub fn with_precision(mut self, precision: Precision) -> Self {
        self.precision = Some(precision);
        self
    }

    /// The periodic or non-periodic formulation.
    pub fn with_formulation(mut self, formulation: Formulation) -> Self {
        self.formulation = formulation;
        self
    }

    /// The adaptive quadtree mesh with `params` (non-periodic formulation).
    pub fn with_adaptive_mesh(mut self, params: AdaptiveParams) -> Self {
        self.mesh = MeshKind::Adaptive;
        self.adaptive = params;
        self
    }

    /// `[analysis]` settings used by [`Solution::write`].
    pub fn with_analysis(mut self, analysis: AnalysisConfig) -> Self {
        self.analysis = Some(analysis);
        self
    }

    /// Cells along y of this problem's map on `n` cells along x with its
    /// side along y kept exactly: `n ny / nx`, refused where it is not a
    /// whole number (a rounded count would change the side along y, and
    /// with it the nominal pressure of a prescribed load).
    pub fn grid_y(&self, n: usize) -> Result<usize> {
        let (nx, ny) = (self.surface.nx, self.surface.ny);
        let cells = ny as u128 * n as u128;
        if cells % nx as u128 != 0 {
            return Err(invalid(format!(
                "{n} cells along x do not keep the side along y of the {nx} x {ny} map: {n} x {ny} / {nx} = {:.3} cells along y is not whole, and a rounded count would change the side (and the nominal pressure); use a multiple of {} cells along x",
                cells as f64 / nx as f64,
                nx / crate::response::gcd(nx, ny)
            )));
        }
        Ok(usize::try_from(cells / nx as u128).unwrap_or(usize::MAX))
    }

    /// The same physical problem on a grid of `n` cells along x (and the
    /// same side along y, [`Problem::grid_y`]): a generated surface is generated again
    /// from the same parameters and seed, a sphere sampled again. The load,
    /// speed, material and controls are unchanged; the recorded
    /// configuration says the new `n`. A surface read from a file or given
    /// as values has one resolution and is refused.
    pub fn with_grid(&self, n: usize) -> Result<Self> {
        let (nx, ny) = (self.surface.nx, self.surface.ny);
        let ny_new = self.grid_y(n)?;
        setup::check_memory(
            n,
            ny_new,
            self.params.restart,
            self.formulation,
            self.precision.unwrap_or_default(),
        )?;
        let (surface, source) = match &self.source {
            SurfaceSource::Generated(p) => {
                let p = GenerateParams {
                    nx: n,
                    ny: ny_new,
                    ..p.clone()
                };
                (crate::surface::generate(&p)?, SurfaceSource::Generated(p))
            }
            SurfaceSource::Sphere(s) => {
                let s = SphereConfig { n, ..*s };
                (s.height_map()?, SurfaceSource::Sphere(s))
            }
            SurfaceSource::Synthesised {
                path,
                table,
                params,
            } => {
                let params = SynthParams {
                    nx: n,
                    ny: ny_new,
                    ..*params
                };
                (
                    crate::surface::generate_from_table(table, &params)?,
                    SurfaceSource::Synthesised {
                        path: path.clone(),
                        table: table.clone(),
                        params,
                    },
                )
            }
            SurfaceSource::File(path) => {
                return Err(invalid(format!(
                    "the surface read from {} has one resolution ({nx} x {ny}); re-discretising needs a generated surface or a sphere",
                    path.display()
                )))
            }
            SurfaceSource::Given => {
                return Err(invalid(format!(
                    "a surface given as values has one resolution ({nx} x {ny}); re-discretising needs a generated surface or a sphere"
                )))
            }
        };
        let mut document = self.document.clone();
        record_grid(&mut document, &source);
        // Under approach control the indenter keeps its place: the approach
        // is measured from the highest summit, which rises as finer scales
        // are resolved.
        let control = match self.control {
            Control::Approach(d) => {
                let d = d + highest(&surface) - highest(&self.surface);
                record_approach(&mut document, d);
                Control::Approach(d)
            }
            load => load,
        };
        Ok(Self {
            surface,
            source,
            document,
            control,
            ..self.clone()
        })
    }

    /// The conversion between speed and `xi = v tau / L` of this material
    /// and map (single-relaxation materials only).
    pub fn xi_scale(&self) -> Option<XiScale> {
        xi_scale_of(&self.material, &self.surface).ok()
    }

    /// `xi = v tau / L` for single-relaxation materials.
    pub fn xi(&self) -> Option<f64> {
        self.xi_scale().map(|s| s.xi(self.speed))
    }

    /// The same problem sliding at `sliding` (m/s, or `xi` for a
    /// single-relaxation material).
    pub fn with_sliding(mut self, sliding: Sliding) -> Result<Self> {
        self.speed = speed_of(sliding, &self.material, &self.surface)?;
        Ok(self)
    }

    /// The same problem pressed by the normal load `load` \[N\].
    pub fn with_normal_load(mut self, load: f64) -> Self {
        self.control = Control::Load(load);
        self
    }

    /// The steady-sliding kernel of this problem's response (paper
    /// Eq. 4-5).
    pub fn sliding_kernel(&self) -> Result<SlidingKernel> {
        Ok(SlidingKernel::new(&self.response()?)?)
    }

    /// The sliding response of this material, speed, direction and layer,
    /// as every operator and the friction routes take it.
    pub fn response(&self) -> Result<SlidingResponse> {
        Ok(SlidingResponse::new(
            &self.material,
            self.speed,
            self.direction_rad,
            self.layer,
        )?)
    }

    /// The surface's grid: its cells, periodic when the formulation is.
    pub fn grid(&self) -> Result<Grid> {
        let s = &self.surface;
        let grid = Grid::new(s.nx, s.ny, (s.cell_size, s.cell_size_y))?;
        Ok(match self.formulation {
            Formulation::Periodic => grid.periodic(),
            Formulation::NonPeriodic => grid,
        })
    }

    /// Gap profile `g = max(z) - z` (physics.md section 1).
    pub fn gap_profile(&self) -> Vec<f64> {
        let zmax = highest(&self.surface);
        self.surface.heights.iter().map(|z| zmax - z).collect()
    }
}

/// The highest summit of a height map \[m\].
pub(crate) fn highest(surface: &HeightMap) -> f64 {
    surface
        .heights
        .iter()
        .copied()
        .fold(f64::NEG_INFINITY, f64::max)
}

/// `[loading] approach` of the recorded config set to `d` where it has one.
fn record_approach(document: &mut toml::Table, d: f64) {
    if let Some(toml::Value::Table(loading)) = document.get_mut("loading") {
        if loading.contains_key("approach") {
            loading.insert("approach".into(), toml::Value::Float(d));
        }
    }
}

/// The `xi` scale of `material` on `surface`, or why there is none.
fn xi_scale_of(material: &Material, surface: &HeightMap) -> Result<XiScale> {
    match material.spectrum.terms.as_slice() {
        [t] => Ok(XiScale {
            creep_time: t.time,
            length: surface.length_x(),
        }),
        terms => Err(invalid(format!(
            "[loading] xi = v tau / L needs a single-relaxation material (this one has {} creep terms); give speed (m/s)",
            terms.len()
        ))),
    }
}

/// The speed \[m/s\] of `sliding` for `material` on `surface`.
pub(super) fn speed_of(sliding: Sliding, material: &Material, surface: &HeightMap) -> Result<f64> {
    Ok(match sliding {
        Sliding::Speed(v) => v,
        // Named as given: a NaN or negative xi is xi's error, not the
        // speed's it converts to.
        Sliding::Xi(xi) if xi.is_nan() || xi < 0.0 => {
            return Err(invalid(format!("[loading] xi must be >= 0, got {xi}")))
        }
        Sliding::Xi(xi) => {
            let scale = xi_scale_of(material, surface)?;
            let v = scale.speed(xi);
            if !v.is_finite() {
                return Err(invalid(format!(
                    "[loading] xi = {xi:e} is the speed xi L / tau = {v} m/s (L = {:e} m, tau = {:e} s), beyond double precision; give a smaller xi",
                    scale.length, scale.creep_time
                )));
            }
            v
        }
    })
}

/// Write the grid of a re-discretised surface into the recorded document.
fn record_grid(document: &mut toml::Table, source: &SurfaceSource) {
    let section = |doc: &mut toml::Table, name: &str| -> Option<toml::Table> {
        match doc.get(name) {
            Some(toml::Value::Table(t)) => Some(t.clone()),
            _ => None,
        }
    };
    let Some(mut surface) = section(document, "surface") else {
        return;
    };
    let (key, n, ny) = match source {
        SurfaceSource::Generated(p) => ("generate", p.nx, Some(p.ny)),
        SurfaceSource::Sphere(s) => ("sphere", s.n, None),
        SurfaceSource::Synthesised { params, .. } => ("generate", params.nx, Some(params.ny)),
        _ => return,
    };
    if let Some(toml::Value::Table(t)) = surface.get_mut(key) {
        t.insert("n".into(), toml::Value::Integer(n as i64));
        if let Some(ny) = ny {
            if ny != n || t.contains_key("ny") {
                t.insert("ny".into(), toml::Value::Integer(ny as i64));
            }
        }
    }
    document.insert("surface".into(), toml::Value::Table(surface));
}
