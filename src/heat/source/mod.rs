//! The heat source of a solved contact (physics.md section 14): where the
//! power `mu F_N v` the rubber dissipates is released.
//!
//! - [`SourceKind::Volume`]: the dissipation density `D` of the creep
//!   elements on depth layers (`dissipation/`: the elements combined in
//!   `rank.rs`, the deep nodes on coarser grids in `band.rs`, sliding along
//!   x in `separable.rs`, the Nyquist modes in `nyquist.rs`, the form summed
//!   component by component in `form.rs`; its
//!   transforms `surface/height_fft.rs`'s planned ones, the stresses of
//!   each surface mode in `stress.rs`, the layers in `depth.rs`, the
//!   temperature each octave of modes dissipates at in `scales.rs`); a
//!   periodic cell on a half-space. `D` is the dashpots' power where they are, in
//!   the depth `~1/|q|` where each scale dissipates.
//! - [`SourceKind::Surface`]: the work of the contact pressure,
//!   `q_s = -v p (e_v . grad w)` (`work.rs`): the same total at the
//!   surface, cheaper, for pads and periodic cells, with or without a
//!   layer; it overstates flash temperatures.
//!
//! On a pad (non-periodic grid) only the surface flux is given: the heat
//! solver has no volume source there, and the cells' piecewise-constant
//! pressure, whose zero-padded transform the pad's friction integrates
//! (Appendix A3), has stresses that jump at every cell edge at the
//! surface, which a band-limited evaluation on the grid would not sum to
//! the pad's friction; the surface flux's total is its stencil friction
//! exactly.

mod depth;
mod dissipation;
mod scales;
mod stress;
mod work;

pub use depth::DepthRule;

use super::density::LayerDensity;
use super::error::HeatError;
use super::layers::DepthLayers;
use crate::response::{Grid, SlidingResponse};

pub(crate) use dissipation::Dissipation;
pub(crate) use scales::scale_rises;
pub use scales::ScaleBand;

/// Which heat source a solved contact gives.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum SourceKind {
    /// The creep elements' dissipation density on depth layers (periodic
    /// cells on a half-space).
    Volume,
    /// The work of the contact pressure at the surface.
    Surface,
}

impl SourceKind {
    /// `"volume"` or `"surface"`.
    pub fn name(&self) -> &'static str {
        match self {
            Self::Volume => "volume",
            Self::Surface => "surface",
        }
    }

    /// The source a contact is heated by unless told otherwise: the
    /// creep elements' dissipation on a periodic cell on a half-space,
    /// the surface work of the pressure on a pad (`periodic` false) or a
    /// layer (`layered`), where the volume source is not solved.
    pub fn default_for(periodic: bool, layered: bool) -> Self {
        if periodic && !layered {
            Self::Volume
        } else {
            Self::Surface
        }
    }

    /// Why this source cannot heat a contact on a pad (`periodic` false)
    /// or a layer (`layered`), or `None` where it can: a reason, to which
    /// each caller adds the fix in its own words (the key or flag that
    /// takes the surface source).
    pub fn unsupported(self, periodic: bool, layered: bool) -> Option<&'static str> {
        match self {
            Self::Surface => None,
            Self::Volume if layered => Some(
                "the volume source (the creep elements' dissipation on depth layers) is solved on a half-space, whose stress a layer does not have",
            ),
            Self::Volume if !periodic => Some(
                "the volume source (the creep elements' dissipation on depth layers) is solved on periodic cells only",
            ),
            Self::Volume => None,
        }
    }
}

impl std::str::FromStr for SourceKind {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "volume" => Ok(Self::Volume),
            "surface" => Ok(Self::Surface),
            _ => Err(format!(
                "the heat source is `volume` or `surface`, got `{s}`"
            )),
        }
    }
}

/// The share of its work that a surface work flux takes back above which
/// the heat it locates is warned of ([`HeatSource::returned_share_warning`]):
/// beyond one half, the net (the heat) is less than a third of the flux's
/// magnitude (`(1 - s) / (1 + s)`).
pub(crate) const RETURNED_SHARE_WARNING: f64 = 0.5;

/// A surface work flux whose net is at most this share of the work it
/// moves carries no heat ([`HeatSource::carries_heat`]): the sums' round-off
/// (measured 8e-16 on a 32^2 elastic cell) is far below it, the net of a
/// rubber with a loss tangent of 1e-9 above it.
pub(crate) const HEAT_ROUND_OFF: f64 = 1e-10;

/// A heat source on a grid, as [`super::HeatSolver`] takes it.
#[derive(Debug, Clone, PartialEq)]
pub enum HeatSource {
    /// A surface flux \[W/m^2\] per cell (C order, axis 0 = x).
    Surface { flux: Vec<f64> },
    /// A volume source \[W/m^3\], constant within each layer: layer `l`'s
    /// values in `density` (from a solved contact, the dissipation at the
    /// Gauss node whose share of its geometric layer layer `l` is,
    /// [`DepthRule`]; its deep layers band-limited parts).
    Volume {
        layers: DepthLayers,
        density: LayerDensity,
    },
}

impl HeatSource {
    /// The heat source of the cell pressures `pressure` \[Pa\] (C order,
    /// axis 0 = x) solved on `grid` under `response` (its material's creep
    /// elements at the solve's temperature, speed and direction): `kind`
    /// [`SourceKind::Volume`] on the layers of `rule` (periodic cells on a
    /// half-space only, refused otherwise in one line), or
    /// [`SourceKind::Surface`]. The speed must be `>= 0` and finite: at
    /// rest (`0`) nothing is dissipated and the source is zero (on the
    /// volume source's layers for that kind).
    pub fn from_contact(
        kind: SourceKind,
        pressure: &[f64],
        grid: &Grid,
        response: &SlidingResponse,
        rule: &DepthRule,
    ) -> Result<Self, HeatError> {
        Self::from_contact_until(kind, pressure, grid, response, rule, &mut || false)
    }

    /// [`HeatSource::from_contact`], asking `stop` between the volume
    /// source's depth nodes (its longest part): `true` gives up with
    /// [`HeatError::Cancelled`].
    pub(crate) fn from_contact_until(
        kind: SourceKind,
        pressure: &[f64],
        grid: &Grid,
        response: &SlidingResponse,
        rule: &DepthRule,
        stop: &mut dyn FnMut() -> bool,
    ) -> Result<Self, HeatError> {
        super::error::check_map("the pressure", pressure, grid.size(), None)?;
        let speed = response.speed();
        if speed != 0.0 {
            super::error::positive("the speed", speed, "m/s")?;
        }
        if let Some(why) = kind.unsupported(grid.is_periodic(), response.layer().is_some()) {
            return Err(HeatError::Unsupported(why));
        }
        match kind {
            SourceKind::Surface if speed == 0.0 => Ok(Self::Surface {
                flux: vec![0.0; pressure.len()],
            }),
            SourceKind::Surface => Ok(Self::Surface {
                flux: work::surface_work_flux(pressure, grid, response)?,
            }),
            SourceKind::Volume => {
                let (bytes, count) = super::memory::volume_bytes(grid, rule)?;
                crate::io::memory::check_fits(
                    || {
                        let (nx, ny) = grid.size();
                        format!("volume source of {nx} x {ny} cells on {count} depth layers")
                    },
                    bytes,
                )
                .map_err(|e| HeatError::Memory(e.to_string()))?;
                let (layers, depths) = rule.source_layers(grid)?;
                if speed == 0.0 {
                    let zeros = vec![vec![0.0; pressure.len()]; layers.count()];
                    let density = LayerDensity::from_layer_maps(zeros, grid.size());
                    return Ok(Self::Volume { layers, density });
                }
                let plan = Dissipation::new(pressure, grid, response)?;
                let nodes: Vec<Vec<(f64, f64)>> = depths.iter().map(|&z| vec![(z, 1.0)]).collect();
                let density = plan.layer_densities_until(&nodes, stop)?;
                Ok(Self::Volume { layers, density })
            }
        }
    }

    /// The total power \[W\] on cells of area `cell_area` \[m^2\]: `sum
    /// q_s a_x a_y`, or `sum_l h_l sum D_l a_x a_y`.
    pub fn power(&self, cell_area: f64) -> f64 {
        match self {
            Self::Surface { flux } => cell_area * flux.iter().sum::<f64>(),
            Self::Volume { layers, density } => {
                layers
                    .iter()
                    .zip(density.layer_sums())
                    .map(|((a, b), d)| (b - a) * d)
                    .sum::<f64>()
                    * cell_area
            }
        }
    }

    /// Whether the source carries heat: a total above zero and, for a
    /// surface work flux, above 1e-10 (`HEAT_ROUND_OFF`) of the work it moves
    /// (`sum |q_s|`): the net of a purely elastic response, work stored
    /// ahead of the contact and returned behind it, is round-off of
    /// either sign, and no heat (its rise, weighted by the flux's
    /// magnitude, would be decided by that sign).
    pub fn carries_heat(&self, cell_area: f64) -> bool {
        let net = self.power(cell_area);
        match self {
            Self::Surface { flux } => {
                net > HEAT_ROUND_OFF * cell_area * flux.iter().map(|q| q.abs()).sum::<f64>()
            }
            Self::Volume { .. } => net > 0.0,
        }
    }

    /// The share of the heat put in that the source takes back out: the
    /// negative flux over the positive, `sum max(-q_s, 0) / sum max(q_s,
    /// 0)`, for a surface work flux (which is negative where the surface
    /// rises back as it leaves the contact, `work.rs`); 0 for the volume
    /// source, a dissipation (`D >= 0`). Near 1 the flux is mostly elastic
    /// work stored ahead of the contact and returned behind it, and the
    /// heat, its net, a small difference of large parts.
    pub fn returned_share(&self) -> f64 {
        match self {
            Self::Surface { flux } => {
                let (gain, loss) =
                    flux.iter().fold(
                        (0.0, 0.0),
                        |(g, l), &q| {
                            if q > 0.0 {
                                (g + q, l)
                            } else {
                                (g, l - q)
                            }
                        },
                    );
                if gain > 0.0 {
                    loss / gain
                } else if loss > 0.0 {
                    f64::INFINITY
                } else {
                    0.0
                }
            }
            Self::Volume { .. } => 0.0,
        }
    }

    /// A warning where the source takes back more than one half of the
    /// work it puts in ([`HeatSource::returned_share`]): the heat is then
    /// located only roughly by the work flux, whose magnitude weights the
    /// effective temperature ([`super::HeatSolver::under`]).
    pub fn returned_share_warning(&self) -> Option<String> {
        let returned = self.returned_share();
        if returned <= RETURNED_SHARE_WARNING {
            return None;
        }
        Some(format!(
            "the surface work flux takes back {:.0} % of the work it puts in (it is negative where the surface rises back behind the contact, returning elastic energy): the heat, its net, is a small difference of large parts, located only roughly where the pressure works, whose magnitude weights the effective temperature; the volume source (source = \"volume\", periodic cells on a half-space) puts the heat where the rubber dissipates it",
            100.0 * returned
        ))
    }

    /// Which kind of source this is.
    pub fn kind(&self) -> SourceKind {
        match self {
            Self::Surface { .. } => SourceKind::Surface,
            Self::Volume { .. } => SourceKind::Volume,
        }
    }
}
