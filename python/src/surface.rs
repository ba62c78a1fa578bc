//! `viscoslide.Surface`'s native half: a height map generated, read from a
//! file (every format the library reads) or given as values, built through
//! the library's `[surface]` section (`SurfaceConfig::load`) where one
//! describes it, so that a generated surface keeps its parameters and seed
//! (a problem can re-generate it on another grid) and the section is
//! recorded in a solve's `summary.json`.

use std::borrow::Cow;
use std::path::{Path, PathBuf};

use numpy::{IntoPyArray, PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray2};
use pyo3::prelude::*;
use viscoslide::problem::SurfaceSource;
use viscoslide::surface::{
    parse_detrend, parse_window, prepare, psd_2d, radial_average, rms_slope_real, slope_warning,
    stats_with_window, Detrend, HeightMap, MissingData, Preprocessing, SurfaceConfig, Topography,
    Window,
};

use crate::errors::value_error;
use crate::problem;

/// A height map on a grid of square cells (axis 0 = x = sliding direction).
#[pyclass(name = "Surface", module = "viscoslide._native", frozen)]
#[derive(Clone)]
pub struct NativeSurface {
    pub map: HeightMap,
    /// What it was made from.
    pub source: SurfaceSource,
    /// Seed of a generated surface.
    pub seed: Option<u64>,
    /// The `[surface]` section that makes it (`None` for values).
    pub section: Option<SurfaceConfig>,
    /// How a measured map was prepared (`None`: generated, taken as it is).
    pub preprocessing: Option<Preprocessing>,
    /// An array not marked periodic, prepared as one period for a solve
    /// with the periodic formulation (detrend and window `none` unless
    /// given; [`SurfaceConfig::preprocessing_for`]); `None` when that is
    /// `map` itself, and for files ([`NativeSurface::as_period`]).
    pub period: Option<(HeightMap, Preprocessing)>,
    /// Missing points filled by harmonic interpolation (`fill_missing`).
    pub filled: usize,
}

impl NativeSurface {
    /// The surface of a `[surface]` section, relative paths resolved
    /// against `base_dir`.
    pub(crate) fn from_config(section: SurfaceConfig, base_dir: &Path) -> PyResult<Self> {
        let (map, filled) = section
            .load_counting(base_dir, false)
            .map_err(value_error)?;
        let source = SurfaceSource::of(&section, base_dir).map_err(value_error)?;
        let seed = section.generate.as_ref().map(|g| g.seed.unwrap_or(0));
        let preprocessing = section.preprocessing().map_err(value_error)?;
        Ok(Self {
            map,
            source,
            seed,
            section: Some(section),
            preprocessing,
            // A file is read again as one period only when a periodic
            // solve asks for it ([`NativeSurface::as_period`]).
            period: None,
            filled,
        })
    }

    /// The map as one period, for a solve with the periodic formulation
    /// ([`SurfaceConfig::preprocessing_for`]); `None` when that is `map`
    /// itself. An array's is made with the surface; a file's (its path is
    /// absolute) is read again here, when a periodic solve needs it.
    pub fn as_period(&self) -> PyResult<Option<(Cow<'_, HeightMap>, Preprocessing)>> {
        if let Some((m, p)) = &self.period {
            return Ok(Some((Cow::Borrowed(m), *p)));
        }
        let Some(section) = &self.section else {
            return Ok(None);
        };
        match section.preprocessing_for(true).map_err(value_error)? {
            Some(p) if Some(p) != self.preprocessing => {
                let map = section
                    .load_for(Path::new("."), true)
                    .map_err(value_error)?;
                Ok(Some((Cow::Owned(map), p)))
            }
            _ => Ok(None),
        }
    }
}

/// A window by its config name (`none`, `hann`, `blackman_harris`).
pub fn window(name: &str) -> PyResult<Window> {
    parse_window(name).map_err(value_error)
}

impl NativeSurface {
    /// The window named, else the map's own (Hann for a scan, none for a
    /// periodic or generated map).
    fn window_of(&self, name: Option<&str>) -> PyResult<Window> {
        match name {
            Some(n) => window(n),
            None => Ok(self.preprocessing.map(|p| p.window).unwrap_or(Window::None)),
        }
    }
}

#[pymethods]
impl NativeSurface {
    /// A surface from the keys of `[surface.generate]` given as JSON
    /// (a self-affine surface, or one following a tabulated `psd` file
    /// relative to `base_dir`).
    #[staticmethod]
    fn generate(generate_json: &str, base_dir: PathBuf) -> PyResult<Self> {
        // Typed by the configuration's parser: a bad key or value named.
        let mut surface = toml::Table::new();
        surface.insert(
            "generate".into(),
            problem::json_section("surface.generate", generate_json)?,
        );
        let mut document = toml::Table::new();
        document.insert("surface".into(), toml::Value::Table(surface));
        let generate = problem::parse(&document, "Surface.generate")?
            .surface
            .and_then(|s| s.generate)
            .unwrap_or_default();
        let mut section = SurfaceConfig {
            generate: Some(generate),
            ..Default::default()
        };
        if let Some(g) = section.generate.as_mut() {
            g.psd = g.psd.as_ref().map(|p| base_dir.join(p));
        }
        Self::from_config(section, &base_dir)
    }

    /// The one-line warnings of a generated surface's making: a stretch the
    /// grid cannot hold ([`viscoslide::surface::anisotropy_warning`]); none
    /// for any other surface.
    fn generation_warnings(&self) -> PyResult<Vec<String>> {
        Ok(match &self.source {
            SurfaceSource::Generated(p) => viscoslide::surface::anisotropy_warning(p)
                .map_err(value_error)?
                .into_iter()
                .collect(),
            _ => Vec::new(),
        })
    }

    /// A surface read from `path` in any format the library reads (`.x3p`,
    /// `.gwy`, `.npy`, text); `length` (m) is needed for `.npy` and text.
    #[staticmethod]
    #[allow(clippy::too_many_arguments)]
    #[pyo3(signature = (path, length=None, length_y=None, format=None, fill_missing=false, detrend=None, window=None, periodic=false))]
    fn from_file(
        path: PathBuf,
        length: Option<f64>,
        length_y: Option<f64>,
        format: Option<String>,
        fill_missing: bool,
        detrend: Option<String>,
        window: Option<String>,
        periodic: bool,
    ) -> PyResult<Self> {
        let path = std::path::absolute(&path).unwrap_or(path);
        let section = SurfaceConfig {
            file: Some(path),
            length,
            length_y,
            format,
            fill_missing: fill_missing.then_some(true),
            detrend,
            window,
            periodic: periodic.then_some(true),
            ..Default::default()
        };
        Self::from_config(section, Path::new("."))
    }

    /// A surface from heights \[m\] (float64, axis 0 = x; NaN marks a
    /// missing point), `length` \[m\] the side along x and `length_y` the
    /// side along y (default: square cells; otherwise cells `length / nx x
    /// length_y / ny`), prepared by the one rule of the library
    /// ([`prepare`]): missing points refused or filled (`fill_missing`), the
    /// `detrend` polynomial removed and `window` for its PSDs, with the
    /// defaults of a scan unless `periodic`.
    #[staticmethod]
    #[pyo3(signature = (heights, length, length_y=None, detrend=None, window=None, periodic=false, fill_missing=false))]
    #[allow(clippy::too_many_arguments)]
    fn from_array(
        heights: PyReadonlyArray2<'_, f64>,
        length: f64,
        length_y: Option<f64>,
        detrend: Option<String>,
        window: Option<String>,
        periodic: bool,
        fill_missing: bool,
    ) -> PyResult<Self> {
        let view = heights.as_array();
        let (nx, ny) = view.dim();
        let values: Vec<f64> = view.iter().copied().collect();
        let dx = length / nx.max(1) as f64;
        let dy = length_y.map_or(dx, |ly| ly / ny.max(1) as f64);
        let mut topo = Topography::new(nx, ny, dx, dy, values, "heights").map_err(value_error)?;
        let missing = if fill_missing {
            MissingData::Fill
        } else {
            MissingData::Error
        };
        topo.handle_missing(missing, "heights")
            .map_err(value_error)?;
        let detrend = detrend
            .as_deref()
            .map(parse_detrend)
            .transpose()
            .map_err(value_error)?;
        let window = window
            .as_deref()
            .map(parse_window)
            .transpose()
            .map_err(value_error)?;
        let pre = Preprocessing::resolve(periodic, detrend, window);
        let map = prepare(&topo, &pre, "heights").map_err(value_error)?;
        // As one period, for the periodic formulation (the rule of
        // `SurfaceConfig::preprocessing_for`).
        let as_period = Preprocessing::resolve(
            periodic,
            detrend.or((!periodic).then_some(Detrend::None)),
            window.or((!periodic).then_some(Window::None)),
        );
        let period = if as_period == pre {
            None
        } else {
            Some((
                prepare(&topo, &as_period, "heights").map_err(value_error)?,
                as_period,
            ))
        };
        Ok(Self {
            map,
            source: SurfaceSource::Given,
            seed: None,
            section: None,
            preprocessing: Some(pre),
            period,
            filled: topo.filled,
        })
    }

    /// How the map was prepared, as JSON (`None` for a generated surface).
    fn preprocessing_json(&self) -> Option<String> {
        self.preprocessing
            .as_ref()
            .map(|p| serde_json::to_string(p).unwrap_or_default())
    }

    /// Heights \[m\], shape `(nx, ny)`.
    #[getter]
    fn heights<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        self.map
            .heights
            .clone()
            .into_pyarray(py)
            .reshape([self.map.nx, self.map.ny])
    }

    /// `(nx, ny)`.
    #[getter]
    fn shape(&self) -> (usize, usize) {
        (self.map.nx, self.map.ny)
    }

    /// Side of a cell along x \[m\].
    #[getter]
    fn cell_size(&self) -> f64 {
        self.map.cell_size
    }

    /// Sides of a cell `(dx, dy)` \[m\].
    #[getter]
    fn cell_sizes(&self) -> (f64, f64) {
        self.map.cell()
    }

    /// `(Lx, Ly)` \[m\].
    #[getter]
    fn lengths(&self) -> (f64, f64) {
        (self.map.length_x(), self.map.length_y())
    }

    /// Seed of a generated surface.
    #[getter]
    fn seed(&self) -> Option<u64> {
        self.seed
    }

    /// The `[surface]` section that makes this surface, as JSON (`None`
    /// for heights given as values).
    fn section_json(&self) -> Option<String> {
        self.section
            .as_ref()
            .map(|s| serde_json::to_string(s).unwrap_or_default())
    }

    /// Radial PSD: `(q [1/m], C [m^4], modes per bin)`.
    #[allow(clippy::type_complexity)]
    #[pyo3(signature = (window_name=None))]
    fn psd<'py>(
        &self,
        py: Python<'py>,
        window_name: Option<&str>,
    ) -> PyResult<(
        Bound<'py, PyArray1<f64>>,
        Bound<'py, PyArray1<f64>>,
        Bound<'py, PyArray1<usize>>,
    )> {
        let psd = psd_2d(&self.map, self.window_of(window_name)?).map_err(value_error)?;
        let r = radial_average(&psd);
        Ok((
            r.q.into_pyarray(py),
            r.c.into_pyarray(py),
            r.count.into_pyarray(py),
        ))
    }

    /// Statistics (rms height, slope, curvature, ...) as JSON, with the
    /// map's `preprocessing` and the `warnings` of the rms-slope check of
    /// the PSD (physics.md section 11).
    #[pyo3(signature = (window_name=None))]
    fn stats_json(&self, window_name: Option<&str>) -> PyResult<String> {
        let s = stats_with_window(&self.map, self.window_of(window_name)?).map_err(value_error)?;
        let m = &self.map;
        let real = rms_slope_real(m.nx, m.ny, m.cell_size, m.cell_size_y, &m.heights);
        let warnings: Vec<String> =
            slope_warning(s.rms_slope_fd_psd, real, "the radial PSD of this map")
                .into_iter()
                .collect();
        let mut doc = serde_json::to_value(&s).map_err(value_error)?;
        doc["rms_slope_real"] = serde_json::json!(real);
        doc["preprocessing"] = serde_json::json!(self.preprocessing);
        doc["warnings"] = serde_json::json!(warnings);
        serde_json::to_string(&doc).map_err(value_error)
    }
}
