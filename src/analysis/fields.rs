//! The contact analysis of one solved map: deformed-surface anisotropy
//! (Eq. 11-13), contact-area anisotropy from `C_chi` (Fig. 10) and
//! contact-spot statistics (physics.md section 5).

use super::anisotropy::{deformed_anisotropy, MIN_GRID_GAMMA, REFERENCE_HURST};
use super::chi::{chi_spectrum, contour_level, ChiLevel};
use super::report::{
    param, AnalysisError, AnalysisInputs, AnalysisParams, AnalysisReport, ChiReport,
};
use super::spots::{find_spots, statistics_of, Connectivity};
use crate::surface::{psd_2d, HeightMap};

pub(super) fn check_inputs(inp: &AnalysisInputs<'_>) -> Result<(), AnalysisError> {
    let n = inp.nx * inp.ny;
    for (name, f) in [
        ("displacement", inp.displacement),
        ("contact", inp.contact),
        ("pressure", inp.pressure),
    ] {
        if f.len() != n {
            return Err(AnalysisError::Shape {
                name: name.into(),
                found: [f.len(), 1],
                expected: [inp.nx, inp.ny],
            });
        }
    }
    for (name, a) in [
        ("cell_size", inp.cell_size),
        ("cell_size_y", inp.cell_size_y),
    ] {
        if !(a.is_finite() && a > 0.0) {
            return Err(param(name, a, "must be a length > 0 (m)"));
        }
    }
    Ok(())
}

/// Contact fraction above which the contact-area anisotropy is warned to
/// describe the gaps.
const NEAR_FULL_CONTACT: f64 = 0.9;

fn check_params(p: &AnalysisParams) -> Result<(), AnalysisError> {
    if !(p.zeta1.is_finite() && p.zeta1 >= 0.0) {
        return Err(param("zeta1", p.zeta1, "must be finite and >= 0"));
    }
    if let Some(z2) = p.zeta2 {
        if !(z2.is_finite() && z2 > p.zeta1) {
            return Err(param("zeta2", z2, "must be finite and exceed zeta1"));
        }
    }
    if p.chi_levels.is_empty() {
        return Err(param("levels", "[]", "give at least one level in (0, 1)"));
    }
    for &l in &p.chi_levels {
        if !(l > 0.0 && l < 1.0) {
            return Err(param("levels", l, "levels of C_chi/C_chi(0) lie in (0, 1)"));
        }
    }
    if let Some(r) = p.chi_window_cells {
        if !(r.is_finite() && r >= 2.0) {
            return Err(param("chi_window_cells", r, "must be at least 2 cells"));
        }
    }
    if p.rays < 3 {
        return Err(param("rays", p.rays, "need at least 3 rays"));
    }
    Ok(())
}

/// The upper band factor `zeta2` of an `nx x ny` map's analysis: as
/// given, else the surface's number of scales `scales` (when above
/// `zeta1`), else the Nyquist wavenumber of the shorter side,
/// `min(nx, ny) / 2`. That default band is empty below
/// `2 (floor(zeta1) + 1)` cells per side (4 for the paper's `zeta1 = 1`):
/// such a grid is refused, naming its size and that minimum.
pub(crate) fn band_end(
    nx: usize,
    ny: usize,
    params: &AnalysisParams,
    scales: Option<f64>,
) -> Result<f64, AnalysisError> {
    let zeta2 = match (params.zeta2, scales) {
        (Some(z), _) => z,
        (None, Some(s)) if s.is_finite() && s > params.zeta1 => s,
        _ => (nx.min(ny) / 2) as f64,
    };
    if zeta2 > params.zeta1 {
        return Ok(zeta2);
    }
    if params.zeta2.is_some() {
        return Err(param("zeta2", zeta2, "must exceed zeta1"));
    }
    // The default band ends at the grid's Nyquist wavenumber.
    Err(AnalysisError::SmallGrid {
        nx,
        ny,
        zeta1: params.zeta1,
        min: 2 * (params.zeta1.floor() as usize + 1),
    })
}

/// The analysis of an `nx x ny` map (`scales` as in [`band_end`]) checked
/// before its solve: its parameters and a band that is not empty, the
/// checks [`analyze`] makes before it reads a field.
pub(crate) fn check_grid(
    nx: usize,
    ny: usize,
    params: &AnalysisParams,
    scales: Option<f64>,
) -> Result<(), AnalysisError> {
    check_params(params)?;
    band_end(nx, ny, params, scales).map(|_| ())
}

/// Analyse one solved contact (physics.md section 5; paper Section IV).
///
/// 1. Eq. 11-13 on the displacement, band `zeta1 q0 <= |q| <= zeta2 q0`
///    (see [`super::anisotropy`]).
/// 2. `C_chi` contours and centred least-squares ellipses (see [`super::chi`]).
/// 3. Spots under 4-connectivity (see [`super::spots`]).
pub fn analyze(
    inputs: &AnalysisInputs<'_>,
    params: &AnalysisParams,
) -> Result<AnalysisReport, AnalysisError> {
    check_inputs(inputs)?;
    check_params(params)?;
    let (nx, ny) = (inputs.nx, inputs.ny);
    let (ax, ay) = (inputs.cell_size, inputs.cell_size_y);
    let map = HeightMap::with_cells(nx, ny, ax, ay, inputs.displacement.to_vec())?;
    let psd = psd_2d(&map, params.window)?;
    let zeta2 = band_end(nx, ny, params, inputs.scales)?;
    let def = deformed_anisotropy(&psd, params.zeta1, zeta2);

    let spots = find_spots(inputs.contact, nx, ny, Connectivity::Four);
    let count_8 = find_spots(inputs.contact, nx, ny, Connectivity::Eight).len();
    let spot_stats = statistics_of(&spots, count_8, ax * ay);
    let contact_cells = inputs.contact.iter().filter(|&&c| c > 0.5).count();

    let chi = if contact_cells == 0 {
        None
    } else {
        let radius = params.chi_window_cells.unwrap_or_else(|| {
            let (mut sw, mut sv) = (0.0, 0.0);
            for s in &spots {
                let w = s.cells as f64;
                sw += w;
                sv += w * s.major_variance();
            }
            1.5 * (4.0 * (sv / sw).sqrt()).max(2.0)
        });
        let spec = chi_spectrum(inputs.contact, nx, ny, (ax, ay), radius);
        let levels: Vec<ChiLevel> = params
            .chi_levels
            .iter()
            .map(|&l| contour_level(&spec, l, params.rays))
            .collect();
        Some(ChiReport {
            window_radius_cells: spec.window_radius_cells,
            flat_radius_cells: spec.flat_radius_cells,
            background_cells: spec.background_cells,
            c0: spec.c0,
            q0: spec.dqx,
            levels,
        })
    };
    let first = chi
        .as_ref()
        .and_then(|c| c.levels.iter().find(|l| l.ellipse.is_some()));
    let t = def.tensor;
    let mut warnings = Vec::new();
    // The band in units of q0 = 2 pi / Lx against the grid's Nyquist
    // wavenumber pi / max(ax, ay).
    let nyquist = (std::f64::consts::PI / ax.max(ay)) / def.band.q0;
    if zeta2 > nyquist * (1.0 + 1e-9) {
        warnings.push(format!(
            "zeta2 = {zeta2} reaches beyond the grid's Nyquist wavenumber pi / a (zeta2 = {nyquist:.1}): the band holds there only the corners of the spectrum, so gamma and theta_P are the grid's, not the surface's; give zeta2 <= {nyquist:.1}"
        ));
    }
    if def.band.grid_gamma < MIN_GRID_GAMMA {
        warnings.push(format!(
            "the band {} <= |q|/q0 <= {zeta2} of this {nx} x {ny} map samples directions unevenly (mode spacing {:.3} q0 along x, {:.3} q0 along y): an isotropic surface would give gamma = {:.3} here (H = {REFERENCE_HURST}), so gamma and theta_P describe the map's shape; use a map closer to square or a band well above the coarser spacing",
            params.zeta1,
            psd.dqx / def.band.q0,
            psd.dqy / def.band.q0,
            def.band.grid_gamma
        ));
    }
    if let (Some(c), Some(asked)) = (&chi, params.chi_window_cells) {
        // The estimator caps its window below half the map's shorter side.
        if asked > c.window_radius_cells * (1.0 + 1e-9) {
            warnings.push(format!(
                "the C_chi window radius {asked} cells is beyond the largest this map allows ({:.1} cells, below half its shorter side), which was used instead: lambda and the ellipse are those of that window",
                c.window_radius_cells
            ));
        }
    }
    let fraction = contact_cells as f64 / (nx * ny) as f64;
    if fraction > NEAR_FULL_CONTACT {
        warnings.push(format!(
            "the contact covers {:.1} % of the map: C_chi is then the spectrum of the few gaps left, and lambda and the ellipse describe them rather than contact spots",
            100.0 * fraction
        ));
    }
    Ok(AnalysisReport {
        m20: t.m20,
        m02: t.m02,
        m11: t.m11,
        gamma: t.gamma,
        theta_p_deg: t.theta_p_deg,
        tensor: t,
        tensor_normalised: def.normalised,
        band: def.band,
        filtered_mean_square: def.mean_square,
        window: params.window,
        lambda: first.and_then(|l| l.ellipse.map(|e| e.lambda)),
        ellipse_angle_deg: first.and_then(|l| l.ellipse.map(|e| e.angle_deg)),
        lambda_level: first.map(|l| l.level),
        chi,
        spots: spot_stats,
        contact_area_fraction: fraction,
        params: params.clone(),
        warnings,
        version: crate::version::VERSION,
    })
}
