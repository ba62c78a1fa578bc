//! The heat solver: a [`HeatSetup`] planned once (the pad's table and
//! transforms, or the periodic cell's), then applied to any number of
//! sources. Every source is checked here before it reaches the numerics.

use super::background::{surface_background, surface_background_at, volume_background_at};
use super::density::LayerDensity;
use super::error::{check_map, check_rise, HeatError};
use super::layers::{check_depths, DepthLadder, DepthLayers};
use super::pad::PadPlan;
use super::periodic::PeriodicPlan;
use super::setup::{HeatDomain, HeatSetup};
use super::source::HeatSource;

/// A temperature rise on the grid.
#[derive(Debug, Clone, PartialEq)]
pub struct Temperature {
    /// The rise `T - T0` \[K\] at the cell centres, C order, axis 0 = x;
    /// the block's background included where there is one.
    pub rise: Vec<f64>,
    /// The block's background rise \[K\] included in `rise` (a periodic
    /// cell with a block length); `None` otherwise.
    pub background: Option<f64>,
}

impl Temperature {
    /// The largest rise \[K\].
    pub fn max(&self) -> f64 {
        self.rise.iter().copied().fold(f64::NEG_INFINITY, f64::max)
    }

    /// The mean rise \[K\].
    pub fn mean(&self) -> f64 {
        self.rise.iter().sum::<f64>() / self.rise.len() as f64
    }
}

const VOLUME_ON_PAD: &str =
    "a volume source is solved on a periodic cell only; give a surface flux for a pad";

enum Plan {
    Pad(Box<PadPlan>),
    Periodic(Box<PeriodicPlan>),
}

/// A heat problem planned once.
pub struct HeatSolver {
    setup: HeatSetup,
    plan: Plan,
}

impl HeatSolver {
    /// Check `setup` and plan it: the pad's table of cell integrals and its
    /// FFT embedding, or the periodic cell's multiplier.
    pub fn new(setup: HeatSetup) -> Result<Self, HeatError> {
        setup.check()?;
        let g = setup.grid;
        crate::io::memory::check_count(
            || format!("{} x {} heat problem", g.nx(), g.ny()),
            (g.nx() as u64).saturating_mul(g.ny() as u64),
            super::memory::plan_bytes_per_cell(setup.is_periodic()),
        )
        .map_err(|e| HeatError::Memory(e.to_string()))?;
        let plan = match setup.domain {
            HeatDomain::Pad => Plan::Pad(Box::new(PadPlan::new(&setup))),
            HeatDomain::Periodic { .. } => Plan::Periodic(Box::new(PeriodicPlan::new(&setup))),
        };
        Ok(Self { setup, plan })
    }

    /// The problem this solver was planned for.
    pub fn setup(&self) -> &HeatSetup {
        &self.setup
    }

    /// The mean of a map.
    fn mean(values: &[f64]) -> f64 {
        values.iter().sum::<f64>() / values.len() as f64
    }

    /// The steady surface rise under the surface flux `flux` \[W/m^2\],
    /// piecewise constant on the cells (pad) or sampled at them (periodic
    /// cell).
    pub fn surface(&mut self, flux: &[f64]) -> Result<Temperature, HeatError> {
        check_map("the heat flux", flux, self.shape(), None)?;
        let background = self
            .setup
            .contact_time()
            .map(|tc| surface_background(Self::mean(flux), &self.setup.conduction, tc));
        let mut rise = match &mut self.plan {
            Plan::Pad(p) => p.apply(flux),
            Plan::Periodic(p) => p.surface(flux),
        };
        add(&mut rise, background);
        check_rise(&rise, self.shape().1)?;
        Ok(Temperature { rise, background })
    }

    /// The steady rise at each of `depths` \[m\] (0: the surface) under the
    /// surface flux `flux` \[W/m^2\]; below the surface on a periodic cell
    /// only.
    pub fn surface_at(
        &mut self,
        flux: &[f64],
        depths: &[f64],
    ) -> Result<Vec<Temperature>, HeatError> {
        check_map("the heat flux", flux, self.shape(), None)?;
        check_depths(depths)?;
        if let Plan::Pad(_) = self.plan {
            if depths.iter().any(|&z| z > 0.0) {
                return Err(HeatError::Unsupported(
                    "the rise below the surface of a pad is not solved; use a periodic cell",
                ));
            }
            let t = self.surface(flux)?;
            return Ok(depths.iter().map(|_| t.clone()).collect());
        }
        let Plan::Periodic(p) = &self.plan else {
            unreachable!("pads returned above")
        };
        let maps = p.surface_at(flux, depths)?;
        let qbar = Self::mean(flux);
        let c = self.setup.conduction;
        let ny = self.shape().1;
        maps.into_iter()
            .zip(depths)
            .map(|(mut rise, &z)| {
                let background = self
                    .setup
                    .contact_time()
                    .map(|tc| surface_background_at(qbar, z, &c, tc));
                add(&mut rise, background);
                check_rise(&rise, ny)?;
                Ok(Temperature { rise, background })
            })
            .collect()
    }

    /// The mean and the highest rise \[K\] at each depth of `ladder` under
    /// the surface flux `flux` \[W/m^2\] on a periodic cell: those of
    /// [`HeatSolver::surface_at`]'s maps (to round-off), computed one
    /// depth at a time from modes carried down the ladder.
    pub(crate) fn surface_extremes(
        &mut self,
        flux: &[f64],
        ladder: &DepthLadder,
    ) -> Result<Vec<(f64, f64)>, HeatError> {
        check_map("the heat flux", flux, self.shape(), None)?;
        let Plan::Periodic(p) = &self.plan else {
            return Err(HeatError::Unsupported(
                "the rise below the surface of a pad is not solved; use a periodic cell",
            ));
        };
        let extremes = p.surface_extremes(flux, ladder)?;
        let qbar = Self::mean(flux);
        let c = self.setup.conduction;
        Ok(extremes
            .into_iter()
            .zip(ladder.depths())
            .map(|((mean, max), z)| {
                let b = self
                    .setup
                    .contact_time()
                    .map_or(0.0, |tc| surface_background_at(qbar, z, &c, tc));
                (mean + b, max + b)
            })
            .collect())
    }

    /// The steady rise at each of `depths` \[m\] under the volume source
    /// `source` \[W/m^3\], constant within each of `layers` on each cell
    /// ([`LayerDensity::from_maps`] for maps laid one after the other),
    /// the surface adiabatic; on a periodic cell only.
    pub fn volume(
        &mut self,
        layers: &DepthLayers,
        source: &LayerDensity,
        depths: &[f64],
    ) -> Result<Vec<Temperature>, HeatError> {
        self.volume_checks(layers, source)?;
        check_depths(depths)?;
        let (p, background) = self.volume_plan(layers, source)?;
        let maps = p.volume(layers, source, depths)?;
        let ny = self.shape().1;
        maps.into_iter()
            .zip(depths)
            .map(|(mut rise, &z)| {
                let background = background.at(z);
                add(&mut rise, background);
                check_rise(&rise, ny)?;
                Ok(Temperature { rise, background })
            })
            .collect()
    }

    /// The depth \[m\], mean and highest rise \[K\] at the surface and at
    /// each layer's middle under the volume source `source` (as
    /// [`HeatSolver::volume`] at those depths, without holding the maps);
    /// on a periodic cell only. (The heated solve takes the same rows from
    /// the sweep that gives its rise, [`HeatSolver::under_with`]; this
    /// entry checks them against the depth maps.)
    #[cfg(test)]
    pub(crate) fn volume_extremes(
        &mut self,
        layers: &DepthLayers,
        source: &LayerDensity,
    ) -> Result<DepthExtremes, HeatError> {
        self.volume_checks(layers, source)?;
        let (p, background) = self.volume_plan(layers, source)?;
        let scan = p.volume_scan(layers, source, true)?;
        let rises = scan.rises.expect("the rises were kept");
        Ok(profile_rows(&background, p.extremes(&rises)?))
    }

    /// The periodic plan a volume source is solved on (a pad refused) and
    /// the block's background rise of `source` on `layers`.
    fn volume_plan<'a>(
        &'a self,
        layers: &'a DepthLayers,
        source: &LayerDensity,
    ) -> Result<(&'a PeriodicPlan, Background<'a>), HeatError> {
        let Plan::Periodic(p) = &self.plan else {
            return Err(HeatError::Unsupported(VOLUME_ON_PAD));
        };
        Ok((
            p,
            Background {
                layers,
                means: source.layer_means(),
                conduction: self.setup.conduction,
                contact_time: self.setup.contact_time(),
            },
        ))
    }

    /// Check a volume source's shape and values.
    fn volume_checks(&self, layers: &DepthLayers, source: &LayerDensity) -> Result<(), HeatError> {
        if source.size() != self.shape() {
            let (nx, ny) = source.size();
            return Err(HeatError::Shape {
                name: "the volume source",
                found: nx * ny * source.layer_count(),
                nx: self.setup.grid.nx(),
                ny: self.setup.grid.ny(),
                expected: layers.count() * self.setup.grid.cells(),
            });
        }
        source.check(layers.count())
    }

    /// The surface rise under `source`, and the source-weighted rise
    /// `Int theta Q dV / Int Q dV` \[K\] (physics.md section 14's
    /// `Theta`, the rise where the heat is released): for a volume source
    /// the rise at each layer's middle weighted by the layer's source, for
    /// a surface flux the surface rise weighted by the flux's magnitude
    /// `|q_s|`. The total source must be positive.
    ///
    /// A surface work flux is negative where the surface rises back behind
    /// the contact (the elastic energy it returns): weighted by the signed
    /// flux, the mean is a ratio of two small differences of large parts
    /// as the sliding becomes elastic, and grows without bound while the
    /// heat vanishes (1e6 times the highest surface rise, measured). Its
    /// magnitude weights the rise where the pressure works on the surface,
    /// a mean that lies between the map's lowest and highest rise and
    /// vanishes with the heat; where the flux is one-signed it is the
    /// flux-weighted mean. A volume source's weighted rise is summed
    /// mode by mode without depth maps (`PeriodicPlan::volume_scan`):
    /// the same sum as from [`HeatSolver::volume`]'s maps at the layers'
    /// middles, to round-off.
    pub fn under(&mut self, source: &HeatSource) -> Result<(Temperature, f64), HeatError> {
        let under = self.under_with(source, None)?;
        Ok((under.temperature, under.weighted))
    }

    /// [`HeatSolver::under`] and, for a volume source, each layer's share
    /// of the weighted rise and of the power, and where `profile` is given
    /// and holds for the weighted rise \[K\], the rows of
    /// [`HeatSolver::volume_extremes`] from the same sweep over the modes
    /// (a surface flux's profile is [`HeatSolver::surface_extremes`]): the
    /// heated solve wants the profile of its answer only, which it knows
    /// by the weighted rise.
    pub(crate) fn under_with(
        &mut self,
        source: &HeatSource,
        profile: Option<&dyn Fn(f64) -> bool>,
    ) -> Result<Under, HeatError> {
        match source {
            HeatSource::Surface { flux } => {
                let t = self.surface(flux)?;
                positive_total(flux.iter().sum())?;
                let magnitude: f64 = flux.iter().map(|q| q.abs()).sum();
                let weighted: f64 = t.rise.iter().zip(flux).map(|(r, q)| r * q.abs()).sum();
                Ok(Under {
                    temperature: t,
                    weighted: finite_weighted(weighted / magnitude)?,
                    profile: None,
                    layers: None,
                })
            }
            HeatSource::Volume { layers, density } => {
                self.volume_checks(layers, density)?;
                let (p, background) = self.volume_plan(layers, density)?;
                let scan = p.volume_scan(layers, density, profile.is_some())?;
                let mut rise = scan.surface;
                let surface = background.at(0.0);
                add(&mut rise, surface);
                check_rise(&rise, self.shape().1)?;
                // The background at each layer's middle, weighted by the
                // layer's source.
                let n = self.setup.grid.cells();
                let by_layer: Vec<(f64, f64)> = layers
                    .iter()
                    .zip(&background.means)
                    .zip(&scan.by_layer)
                    .map(|(((a, b), mean), swept)| {
                        let q = (b - a) * mean * n as f64;
                        let t = background.at(0.5 * (a + b)).unwrap_or(0.0);
                        (swept + q * t, q)
                    })
                    .collect();
                let weighted: f64 = by_layer.iter().map(|l| l.0).sum();
                let total: f64 = by_layer.iter().map(|l| l.1).sum();
                let weighted = finite_weighted(weighted / positive_total(total)?)?;
                let rows = match (profile, scan.rises) {
                    (Some(wanted), Some(rises)) if wanted(weighted) => {
                        Some(profile_rows(&background, p.extremes(&rises)?))
                    }
                    _ => None,
                };
                Ok(Under {
                    temperature: Temperature {
                        rise,
                        background: surface,
                    },
                    weighted,
                    profile: rows,
                    layers: Some(by_layer),
                })
            }
        }
    }

    fn shape(&self) -> (usize, usize) {
        (self.setup.grid.nx(), self.setup.grid.ny())
    }
}

/// What [`HeatSolver::under_with`] gives.
pub(crate) struct Under {
    /// The surface rise.
    pub temperature: Temperature,
    /// `Theta` \[K\]: the rise weighted by the source.
    pub weighted: f64,
    /// A volume source's depth profile, when asked.
    pub profile: Option<DepthExtremes>,
    /// A volume source's layers: each one's `h_l sum_cells theta(z_l) Q_l`
    /// (the background included) and `h_l sum_cells Q_l`, whose sums'
    /// ratio is `weighted`.
    pub layers: Option<Vec<(f64, f64)>>,
}

/// The block's background heating of a volume source on a periodic cell
/// (physics.md section 14): the layers' mean sources over a passage of
/// `contact_time` (`None`: no block, no background).
struct Background<'a> {
    layers: &'a DepthLayers,
    /// Each layer's mean source \[W/m^3\].
    means: Vec<f64>,
    conduction: super::setup::Conduction,
    contact_time: Option<f64>,
}

impl Background<'_> {
    /// The background rise \[K\] at depth `z` \[m\].
    fn at(&self, z: f64) -> Option<f64> {
        self.contact_time
            .map(|tc| volume_background_at(self.layers, &self.means, z, &self.conduction, tc))
    }
}

/// The rises about the mean `extremes` (surface first) as
/// [`DepthExtremes`], the block's background added.
fn profile_rows(background: &Background, extremes: Vec<(f64, f64)>) -> DepthExtremes {
    extremes
        .into_iter()
        .zip(profile_depths(background.layers))
        .map(|((mean, max), z)| {
            let b = background.at(z).unwrap_or(0.0);
            (z, mean + b, max + b)
        })
        .collect()
}

/// The depth \[m\], mean and highest rise \[K\] at the surface and at each
/// layer's middle of a volume source's rise, surface first.
pub(crate) type DepthExtremes = Vec<(f64, f64, f64)>;

/// The depths \[m\] of a volume source's profile rows on `layers`
/// ([`DepthExtremes`]): the surface, then each layer's middle.
pub(crate) fn profile_depths(layers: &DepthLayers) -> impl Iterator<Item = f64> + '_ {
    std::iter::once(0.0).chain(layers.iter().map(|(a, b)| 0.5 * (a + b)))
}

fn positive_total(total: f64) -> Result<f64, HeatError> {
    super::error::positive("the total heat source", total, "W")
}

/// The source-weighted rise, refused where its sums left f64 (a source
/// over the conductivity near f64's range, whose rises are each finite).
fn finite_weighted(weighted: f64) -> Result<f64, HeatError> {
    if weighted.is_finite() {
        Ok(weighted)
    } else {
        Err(HeatError::OutOfRange(format!(
            "the source-weighted temperature rise is {weighted} K: the heat source over the conductivity is beyond the range of f64"
        )))
    }
}

fn add(rise: &mut [f64], background: Option<f64>) {
    if let Some(b) = background {
        rise.iter_mut().for_each(|v| *v += b);
    }
}

/// The steady surface rise of `setup` under the surface flux `flux`
/// \[W/m^2\] (plans and solves once: [`HeatSolver`] for many fluxes).
pub fn surface_temperature(setup: HeatSetup, flux: &[f64]) -> Result<Temperature, HeatError> {
    // The flux is checked before the plan, which may take a while.
    setup.check()?;
    check_map(
        "the heat flux",
        flux,
        (setup.grid.nx(), setup.grid.ny()),
        None,
    )?;
    HeatSolver::new(setup)?.surface(flux)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::heat::{Conduction, HeatDomain};
    use crate::response::Grid;

    /// A periodic cell of `nx x ny` rectangular cells of rubber sliding
    /// at 0.3 m/s, 0.5 rad from x, with the block `block`.
    fn slanted_cell(nx: usize, ny: usize, block: Option<f64>) -> HeatSolver {
        HeatSolver::new(HeatSetup {
            grid: Grid::new(nx, ny, (2e-6, 3e-6)).unwrap(),
            conduction: Conduction {
                conductivity: 0.25,
                diffusivity: 1e-7,
            },
            speed: 0.3,
            direction_rad: 0.5,
            domain: HeatDomain::Periodic {
                block_length: block,
            },
        })
        .unwrap()
    }

    /// The planned profile's mean and peak are those of the depth maps
    /// (the same sums, the deep modes left out below `exp(-40)`): 1e-12 of
    /// the surface's peak, on a rough random flux with odd and even sides
    /// (Nyquist modes), a slanted sliding direction and a block.
    #[test]
    fn surface_extremes_are_the_depth_maps_mean_and_peak() {
        for (nx, ny) in [(48, 36), (33, 20)] {
            let mut solver = slanted_cell(nx, ny, Some(0.01));
            let flux: Vec<f64> = (0..nx * ny)
                .map(|c| {
                    if (c * 7919) % 13 < 2 {
                        1e6 * (1 + c % 5) as f64
                    } else {
                        0.0
                    }
                })
                .collect();
            // Irregular steps (a factor per depth), and the profile's
            // octaves (a factor per octave, carried over up to 8 depths).
            let ladders = [
                DepthLadder::new(1e-7, vec![0, 1, 20, 300, 1000, 10_000]).unwrap(),
                DepthLadder::octaves(2e-7, 1e-3, 8).unwrap(),
            ];
            for ladder in &ladders {
                let maps = solver.surface_at(&flux, &ladder.depths()).unwrap();
                let extremes = solver.surface_extremes(&flux, ladder).unwrap();
                let scale = maps[0].max();
                for (t, (mean, max)) in maps.iter().zip(&extremes) {
                    assert!(
                        (t.mean() - mean).abs() <= 1e-12 * scale,
                        "{} {mean}",
                        t.mean()
                    );
                    assert!((t.max() - max).abs() <= 1e-12 * scale, "{} {max}", t.max());
                }
            }
        }
    }

    /// The volume source's profile rows (the surface and each layer's
    /// middle, from one sweep per mode) are the mean and peak of
    /// [`HeatSolver::volume`]'s maps at those depths, with and without a
    /// block (its background added), on even and odd grids with Nyquist
    /// modes, oblique sliding: 1e-12 of the surface peak (round-off of
    /// sums over layers in another order).
    #[test]
    fn volume_extremes_are_the_depth_maps_mean_and_peak() {
        for ((nx, ny), block) in [
            ((48, 36), Some(0.01)),
            ((33, 20), None),
            ((32, 21), Some(1e-4)),
        ] {
            let mut solver = slanted_cell(nx, ny, block);
            let layers = DepthLayers::new(vec![0.0, 1e-7, 5e-7, 2e-6, 1e-5, 1e-4]).unwrap();
            let n = nx * ny;
            let source: Vec<f64> = (0..layers.count() * n)
                .map(|c| {
                    if (c * 7919) % 13 < 3 {
                        1e12 * (1 + c % 5) as f64 / (1 + c / n) as f64
                    } else {
                        0.0
                    }
                })
                .collect();
            let mut depths = vec![0.0];
            depths.extend(layers.iter().map(|(a, b)| 0.5 * (a + b)));
            let density = LayerDensity::from_maps(source, nx, ny);
            let maps = solver.volume(&layers, &density, &depths).unwrap();
            let rows = solver.volume_extremes(&layers, &density).unwrap();
            assert_eq!(rows.len(), depths.len());
            let scale = maps[0].max();
            for ((t, (z, mean, max)), depth) in maps.iter().zip(&rows).zip(&depths) {
                assert_eq!(z, depth);
                assert!(
                    (t.mean() - mean).abs() <= 1e-12 * scale,
                    "{} {mean}",
                    t.mean()
                );
                assert!((t.max() - max).abs() <= 1e-12 * scale, "{} {max}", t.max());
            }
        }
    }
}
