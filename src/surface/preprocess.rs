//! One preprocessing rule for every measured map (physics.md section 11),
//! whatever its file format or front end: a map that is not one period of
//! a periodic surface has its least-squares plane removed before it is
//! solved on and before any PSD is taken of it, and every PSD of it uses
//! the Hann window. A tilt left in a scan is geometry the solver presses
//! into the rubber and, in a PSD, an edge step that leaks as `C ~ q^-4`.
//!
//! [`Preprocessing`] holds the two choices, [`prepare`] turns a
//! [`Topography`] into the [`HeightMap`] the solver uses (the one place
//! where this happens for files, configs and arrays), and [`slope_warning`]
//! is the check of any PSD estimate: its rms slope `sqrt(2 pi Int q^3 C dq)`
//! against the real-space rms slope of the same detrended map.
//! Generated and synthesised surfaces are periodic by construction and are
//! not preprocessed.

use serde::{Deserialize, Serialize};

use super::{detrend, Detrend, HeightMap, SurfaceError, Topography, Window};

/// Relative difference between the rms slope of a PSD and the real-space
/// rms slope of its map above which the PSD is flagged (physics.md
/// section 11: a sound estimate agrees within some 10-20 %).
pub const SLOPE_TOLERANCE: f64 = 0.2;

/// How a map is prepared: the polynomial removed before solving and before
/// any PSD, and the window of its PSDs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct Preprocessing {
    /// Whether the map is one period of a periodic surface (else a scan,
    /// whose PSDs are trusted only inside [`super::trusted_band`]).
    pub periodic: bool,
    pub detrend: Detrend,
    pub window: Window,
}

impl Preprocessing {
    /// The defaults: a map that is one period of a periodic surface is
    /// taken as it is (no detrending, no window); any other map (a scan)
    /// loses its mean plane and gets the Hann window.
    pub fn default_for(periodic: bool) -> Self {
        if periodic {
            Self {
                periodic,
                detrend: Detrend::None,
                window: Window::None,
            }
        } else {
            Self {
                periodic,
                detrend: Detrend::Plane,
                window: Window::Hann,
            }
        }
    }

    /// [`Preprocessing::default_for`] with the choices given replacing
    /// the defaults.
    pub fn resolve(periodic: bool, detrend: Option<Detrend>, window: Option<Window>) -> Self {
        let d = Self::default_for(periodic);
        Self {
            periodic,
            detrend: detrend.unwrap_or(d.detrend),
            window: window.unwrap_or(d.window),
        }
    }
}

/// A detrending by its name: `none`, `mean`, `plane` or `quadratic`.
pub fn parse_detrend(s: &str) -> Result<Detrend, String> {
    match s.trim().to_ascii_lowercase().as_str() {
        "none" => Ok(Detrend::None),
        "mean" => Ok(Detrend::Mean),
        "plane" => Ok(Detrend::Plane),
        "quadratic" => Ok(Detrend::Quadratic),
        _ => Err(format!("detrend '{s}': use none, mean, plane or quadratic")),
    }
}

/// A window by its name: `none`, `hann` or `blackman-harris`
/// (`blackman_harris`).
pub fn parse_window(s: &str) -> Result<Window, String> {
    match s.trim().to_ascii_lowercase().as_str() {
        "none" => Ok(Window::None),
        "hann" => Ok(Window::Hann),
        "blackman-harris" | "blackman_harris" => Ok(Window::BlackmanHarris),
        _ => Err(format!("window '{s}': use none, hann or blackman-harris")),
    }
}

impl Window {
    /// The name [`parse_window`] reads (`none`, `hann`, `blackman-harris`).
    pub fn name(self) -> &'static str {
        match self {
            Window::None => "none",
            Window::Hann => "hann",
            Window::BlackmanHarris => "blackman-harris",
        }
    }
}

/// The line that says how many of a map's `total` points were missing
/// and filled by harmonic interpolation (`None` when none were).
pub(crate) fn filled_note(filled: usize, total: usize) -> Option<String> {
    (filled > 0).then(|| {
        format!(
            "{filled} of {total} points ({:.3} %) were missing and filled by harmonic (Laplace) interpolation",
            100.0 * filled as f64 / total as f64
        )
    })
}

/// The height map the solver uses: `topo` with `pre.detrend` removed.
/// Missing points must have been filled; cells must be square
/// ([`Topography::to_height_map`]). `name` labels errors.
pub fn prepare(
    topo: &Topography,
    pre: &Preprocessing,
    name: &str,
) -> Result<HeightMap, SurfaceError> {
    detrend(topo, pre.detrend).to_height_map(name)
}

/// Real-space rms slope `sqrt(<(dh/dx)^2 + (dh/dy)^2>)` of `nx x ny`
/// heights on `dx x dy` pixels, the one definition every front end reports
/// and checks: forward differences `(h[i+1,j] - h[i,j]) / dx` and
/// `(h[i,j+1] - h[i,j]) / dy`, averaged over the `(nx-1) x (ny-1)` points
/// where both exist (no wrap-around). This is SurfaceTopography's
/// `rms_gradient` of a non-periodic map; its spectral counterpart is
/// [`super::Psd2d::rms_slope_fd`] (the PSD seen through the same
/// differences), which [`slope_warning`] compares it with.
pub fn rms_slope_real(nx: usize, ny: usize, dx: f64, dy: f64, heights: &[f64]) -> f64 {
    if nx < 2 || ny < 2 {
        return 0.0;
    }
    let h = |i: usize, j: usize| heights[i * ny + j];
    let mut s2 = 0.0;
    for i in 0..nx - 1 {
        for j in 0..ny - 1 {
            let gx = (h(i + 1, j) - h(i, j)) / dx;
            let gy = (h(i, j + 1) - h(i, j)) / dy;
            s2 += gx * gx + gy * gy;
        }
    }
    (s2 / ((nx - 1) * (ny - 1)) as f64).sqrt()
}

/// The warning for a PSD whose rms slope `psd_slope` differs from the
/// real-space rms slope `real_slope` of the same map by more than
/// [`SLOPE_TOLERANCE`] (relative to the real-space value); `what` names
/// the PSD. `None` when they agree.
pub fn slope_warning(psd_slope: f64, real_slope: f64, what: &str) -> Option<String> {
    let diff = (psd_slope - real_slope).abs() / real_slope.abs().max(f64::MIN_POSITIVE);
    (diff > SLOPE_TOLERANCE).then(|| {
        format!(
            "{what}: the rms slope it gives forward differences, sqrt(sum ((2/a_x) sin(q_x a_x/2))^2 + ((2/a_y) sin(q_y a_y/2))^2) C dq^2) = {psd_slope:.4e}, differs from the real-space rms slope {real_slope:.4e} of the same map (forward differences) by {:.0} % (more than {:.0} %): the PSD is not a sound estimate (a tilt or curvature left in the map, edge leakage, no window); detrend the map (plane or quadratic) and use a window (hann)",
            100.0 * diff,
            100.0 * SLOPE_TOLERANCE
        )
    })
}

/// How far a map is from one period of a periodic surface: the rms step
/// between its opposite edges (`h[0, j] - h[nx-1, j]`, `h[i, 0] - h[i,
/// ny-1]`), beside the rms step between neighbouring cells, along x and
/// y, in units of the map's rms height. On a period the edge steps are
/// neighbour steps; on a scan they are of the order of the rms height.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct EdgeSteps {
    pub edge_x: f64,
    pub edge_y: f64,
    pub cell_x: f64,
    pub cell_y: f64,
}

/// The [`EdgeSteps`] of `nx x ny` heights (`heights[i * ny + j]`); `None`
/// for a map under 2 x 2 cells or a flat one.
pub(crate) fn edge_steps(nx: usize, ny: usize, heights: &[f64]) -> Option<EdgeSteps> {
    let n = heights.len() as f64;
    if nx < 2 || ny < 2 || heights.len() != nx * ny {
        return None;
    }
    let mean = heights.iter().sum::<f64>() / n;
    let rms = (heights.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / n).sqrt();
    if !(rms > 0.0 && rms.is_finite()) {
        return None;
    }
    let at = |i: usize, j: usize| heights[i * ny + j];
    let rms_of = |d: &mut dyn Iterator<Item = f64>| {
        let (s, c) = d.fold((0.0, 0usize), |(s, c), v| (s + v * v, c + 1));
        (s / c.max(1) as f64).sqrt() / rms
    };
    Some(EdgeSteps {
        edge_x: rms_of(&mut (0..ny).map(|j| at(0, j) - at(nx - 1, j))),
        edge_y: rms_of(&mut (0..nx).map(|i| at(i, 0) - at(i, ny - 1))),
        cell_x: rms_of(
            &mut (0..nx - 1)
                .flat_map(|i| (0..ny).map(move |j| (i, j)))
                .map(|(i, j)| at(i + 1, j) - at(i, j)),
        ),
        cell_y: rms_of(
            &mut (0..nx)
                .flat_map(|i| (0..ny - 1).map(move |j| (i, j)))
                .map(|(i, j)| at(i, j + 1) - at(i, j)),
        ),
    })
}
