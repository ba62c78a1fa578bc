//! The PSD sources of Persson's theory, all as a [`TabulatedPsd`] (a
//! piecewise power law in the project's radial convention,
//! `<h^2> = 2 pi Int q C(q) dq`):
//!
//! * [`continuum_self_affine`]: the analytic PSD of `[surface.generate]`,
//!   exact (a power law is a straight line in log-log axes), with `C0` set
//!   by the continuum integral of the prescribed rms height or rms slope;
//! * [`radial`]: the radial average of a height map's 2-D PSD, the
//!   `surface stats` code ([`psd_2d`] and [`radial_average`]);
//! * [`map_psd`]: that radial average as the preprocessing of the map
//!   prescribes (window, a scan's trusted band), checked against the
//!   map's real-space rms slope (physics.md section 11);
//! * a `q, C` CSV: [`TabulatedPsd::from_csv`] itself.

use serde::Serialize;

use crate::surface::{
    psd_2d, radial_average, rms_slope_real, slope_warning, trusted_band, Detrend, GenerateParams,
    HeightMap, Normalisation, Preprocessing, SelfAffinePsd, TabulatedPsd, Topography, Window,
};

use super::PerssonError;

/// The self-affine PSD of `params` in the continuum:
/// `C(q) = C0` on `q_L <= q < q0`, `C0 (q/q0)^(-2(H+1))` on `q0 <= q <= q1`,
/// with `C0` such that `2 pi Int_{qL}^{q1} q C dq` equals the prescribed
/// mean square height, or `2 pi Int_{qL}^{q1} q^3 C dq` the prescribed mean
/// square slope.
///
/// This differs on purpose from the `C0` of the generator
/// ([`crate::surface::generate_with_target`]), which normalises the
/// discrete sum over the grid's Fourier modes of one map; the two agree to
/// the accuracy with which the lattice sum approximates the integral
/// (a few percent for the first few scales).
///
/// Returns the table (two or three rows: `q_L`, the roll-off `q0` if any,
/// `q1`) and the target with its continuum `C0`. An anisotropic stretch is
/// an error: the theory is for isotropic roughness.
pub fn continuum_self_affine(
    params: &GenerateParams,
) -> Result<(TabulatedPsd, SelfAffinePsd), PerssonError> {
    if let Some(a) = params.anisotropy {
        if a.ratio != 1.0 {
            return Err(PerssonError::Invalid(format!(
                "the surface is anisotropic ([surface.generate] anisotropy ratio = {}); the theory is for isotropic roughness only",
                a.ratio
            )));
        }
    }
    let mut target = params.resolve()?;
    target.anisotropy = None;
    let unit = self_affine_table(&target)?;
    let c0 = match params.normalisation {
        Normalisation::RmsHeight(h) => h * h / unit.moment(0),
        Normalisation::RmsSlope(s) => s * s / unit.moment(2),
    };
    target.c0 = c0;
    Ok((self_affine_table(&target)?, target))
}

/// The table of the isotropic self-affine PSD `target` with its own `C0`
/// (two or three rows: `q_L`, the roll-off `q0` if any, `q1`): exact, a
/// power law is a straight line in log-log axes.
pub(crate) fn self_affine_table(target: &SelfAffinePsd) -> Result<TabulatedPsd, PerssonError> {
    let exponent = -2.0 * (target.hurst + 1.0);
    let mut q = vec![target.ql];
    let mut c = vec![target.c0];
    if target.q0 > target.ql {
        q.push(target.q0);
        c.push(target.c0);
    }
    q.push(target.q1);
    c.push(target.c0 * (target.q1 / target.q0).powf(exponent));
    Ok(TabulatedPsd::new(q, c, "self-affine PSD")?)
}

/// What [`radial`] kept of a height map's radial PSD.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct RadialInfo {
    /// Radial bins with `C > 0` above the round-off floor.
    pub bins: usize,
    /// Bins dropped as round-off (`C <= 1e-20` of the largest).
    pub dropped: usize,
    /// Degree of isotropy of the slopes, `gamma = lambda_min / lambda_max` of
    /// `<d_i h d_j h>` (1 for an isotropic surface; the theory assumes it).
    pub slope_isotropy: f64,
    /// The rms slope forward differences see in the 2-D PSD, the value the
    /// real-space slope is checked against
    /// ([`crate::surface::Psd2d::slope_check_value`]).
    pub rms_slope_fd_psd: f64,
}

/// Radial average of the 2-D PSD of `map` (the code of `surface stats`:
/// [`psd_2d`] with `window`, then [`radial_average`]), as a table for
/// log-log interpolation. Bins with `C` at or below `1e-20` of the largest
/// (round-off of the FFT outside a generated surface's band) are dropped.
pub fn radial(map: &HeightMap, window: Window) -> Result<(TabulatedPsd, RadialInfo), PerssonError> {
    let psd = psd_2d(map, window)?;
    let m = psd.slope_tensor();
    let tr = m[0][0] + m[1][1];
    let det = m[0][0] * m[1][1] - m[0][1] * m[0][1];
    let disc = (0.25 * tr * tr - det).max(0.0).sqrt();
    let slope_isotropy = if tr > 0.0 {
        (0.5 * tr - disc) / (0.5 * tr + disc)
    } else {
        1.0
    };
    let r = radial_average(&psd);
    let peak = r.c.iter().copied().fold(0.0, f64::max);

    let floor = 1e-20 * peak;
    let (q, c): (Vec<f64>, Vec<f64>) =
        r.q.iter()
            .zip(&r.c)
            .filter(|(_, c)| **c > floor)
            .map(|(q, c)| (*q, *c))
            .unzip();
    if q.len() < 2 {
        let why = if peak > 0.0 {
            format!(
                "has power in {} radial bin(s) of its PSD and the theory integrates over at least two; give a map of more cells",
                q.len()
            )
        } else {
            "has no roughness (its PSD is zero); the theory needs a rough surface".to_string()
        };
        return Err(PerssonError::Invalid(format!(
            "the {} x {} map {why}",
            map.nx, map.ny
        )));
    }
    let info = RadialInfo {
        bins: q.len(),
        dropped: r.q.len() - q.len(),
        slope_isotropy,
        rms_slope_fd_psd: psd.slope_check_value(window),
    };
    Ok((
        TabulatedPsd::new(q, c, "radial PSD of the height map")?,
        info,
    ))
}

/// How the PSD of a height map was made for the theory, with its check.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MapPsdReport {
    /// Polynomial removed from the map before solving and before the PSD
    /// (`None`: a map given as values, taken as it is).
    pub detrend: Option<Detrend>,
    /// Window of the 2-D PSD.
    pub window: Window,
    /// The band the table covers \[1/m\]: the trusted band of a scan
    /// ([`trusted_band`]), zero outside it; the whole radial average of a
    /// periodic map.
    pub q_band_per_m: [f64; 2],
    /// Whether the band is a scan's trusted band.
    pub trusted_band: bool,
    pub radial: RadialInfo,
    /// `sqrt(2 pi Int q^3 C dq)` of the table.
    pub rms_slope_psd: f64,
    /// Real-space rms slope of the same map ([`rms_slope_real`]).
    pub rms_slope_real: f64,
    /// Set when the two differ by more than 20 % ([`slope_warning`]).
    pub warning: Option<String>,
}

/// The PSD Persson's theory sees for a height map prepared by `pre`
/// (physics.md section 11): the radial average of its 2-D PSD with
/// `pre.window`; for a scan (`!pre.periodic`) only over its trusted band
/// (zero outside), for a periodic map over every bin. Checked against the
/// map's real-space rms slope. `map` is already detrended (the map the
/// solver uses, [`crate::surface::prepare`]).
pub fn map_psd(
    map: &HeightMap,
    pre: &Preprocessing,
    detrended: bool,
) -> Result<(TabulatedPsd, MapPsdReport), PerssonError> {
    let (full, radial_info) = radial(map, pre.window)?;
    let (table, band, trusted) = if pre.periodic {
        let band = [full.q_min(), full.q_max()];
        (full, band, false)
    } else {
        let topo = Topography::from_height_map(map);
        if let Some(why) = crate::surface::empty_band_reason(&topo) {
            return Err(PerssonError::Invalid(format!(
                "{why}; give a wider map, or mark one period of a periodic map periodic"
            )));
        }
        let (lo, hi) = trusted_band(&topo);
        let t = full.within(lo, hi, "radial PSD of the height map over its trusted band")?;
        let band = [t.q_min(), t.q_max()];
        (t, band, true)
    };
    let rms_slope_psd = table.moment(2).sqrt();
    let rms_slope_real =
        rms_slope_real(map.nx, map.ny, map.cell_size, map.cell_size_y, &map.heights);
    let warning = slope_warning(
        radial_info.rms_slope_fd_psd,
        rms_slope_real,
        "the PSD of the surface map used by Persson's theory",
    );
    Ok((
        table,
        MapPsdReport {
            detrend: detrended.then_some(pre.detrend),
            window: pre.window,
            q_band_per_m: band,
            trusted_band: trusted,
            radial: radial_info,
            rms_slope_psd,
            rms_slope_real,
            warning,
        },
    ))
}
