//! What a heat problem is given: the grid of cells, the solid's heat
//! conduction, the sliding speed and direction, and whether the cells are
//! a pad or one period of a periodic cell (physics.md section 14). Every
//! check of these values lives here.

use super::error::{positive, HeatError};
use crate::response::Grid;

/// Heat conduction of the solid (rubber: `lam` 0.2-0.3 W/(m K), `kappa`
/// about 1e-7 m^2/s).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Conduction {
    /// Thermal conductivity `lam` \[W/(m K)\].
    pub conductivity: f64,
    /// Thermal diffusivity `kappa = lam / (rho c)` \[m^2/s\].
    pub diffusivity: f64,
}

impl Conduction {
    fn check(&self) -> Result<(), HeatError> {
        positive("the conductivity", self.conductivity, "W/(m K)")?;
        positive("the diffusivity", self.diffusivity, "m^2/s")?;
        Ok(())
    }
}

/// Where the cells sit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum HeatDomain {
    /// A finite pad on an unbounded half-space: the steady moving-source
    /// solution (no heat outside the cells' sources).
    Pad,
    /// One period of a periodic cell. Its mean (`k = 0`) has no steady
    /// state; with the length `L_b` \[m\] of the block along the sliding
    /// direction the mean is the block's background heating over a
    /// passage, `(4/3) qbar sqrt(kappa t_c / pi) / lam`, `t_c = L_b / v`;
    /// without it the rise is given about its unknown mean.
    Periodic { block_length: Option<f64> },
}

/// A steady heat problem: a rubber half-space (`z >= 0`) moving past the
/// cells with velocity `-v e_v`, `e_v` at `direction_rad` from +x.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HeatSetup {
    /// The cells of the source map ([`Grid`]: checked where it is built).
    pub grid: Grid,
    pub conduction: Conduction,
    /// Sliding speed `v` \[m/s\].
    pub speed: f64,
    /// Sliding direction, radians from +x.
    pub direction_rad: f64,
    pub domain: HeatDomain,
}

impl HeatSetup {
    /// Every value checked: positive, finite speed, conductivity,
    /// diffusivity, cell sides and block length; a finite direction; a
    /// grid with cells; a block at least as long as the periodic cell
    /// along the sliding direction ([`HeatSetup::cell_length_along_sliding`]).
    pub fn check(&self) -> Result<(), HeatError> {
        positive("the speed", self.speed, "m/s")?;
        self.check_at_rest()
    }

    /// [`HeatSetup::check`] but for the speed, which may be zero: a
    /// contact at rest, whose zero source has zero rise without a
    /// solve.
    pub(crate) fn check_at_rest(&self) -> Result<(), HeatError> {
        self.conduction.check()?;
        if !self.direction_rad.is_finite() {
            return Err(HeatError::Direction(self.direction_rad));
        }
        self.check_block()
    }

    /// A periodic cell's block length, where one is given: positive,
    /// finite and at least the cell's length along the sliding direction
    /// ([`HeatSetup::cell_length_along_sliding`]). Needs no speed, so a
    /// heated solve checks it before any solve, at rest too.
    pub fn check_block(&self) -> Result<(), HeatError> {
        if let HeatDomain::Periodic {
            block_length: Some(l),
        } = self.domain
        {
            positive("the block length", l, "m")?;
            let cell = self.cell_length_along_sliding();
            if l < cell {
                return Err(HeatError::BlockShorterThanCell { block: l, cell });
            }
        }
        Ok(())
    }

    /// The cell's length along the sliding direction \[m\]: the chord
    /// through its centre along `e_v`, `min(L_x / |e_x|, L_y / |e_y|)`
    /// (`L_x` sliding along x).
    pub fn cell_length_along_sliding(&self) -> f64 {
        let (lx, ly) = self.grid.lengths();
        let (ex, ey) = self.direction();
        let along = |l: f64, e: f64| if e == 0.0 { f64::INFINITY } else { l / e.abs() };
        along(lx, ex).min(along(ly, ey))
    }

    /// Unit vector `e_v` of the sliding direction
    /// (`(cos, sin)` of the direction from +x, components below 1e-15
    /// snapped to zero as in the sliding response).
    pub fn direction(&self) -> (f64, f64) {
        crate::response::unit_direction(self.direction_rad)
    }

    /// The cell Peclet number `v dx / kappa` (`dx` the side along x).
    pub fn peclet(&self) -> f64 {
        self.speed * self.grid.cell().0 / self.conduction.diffusivity
    }

    /// The time `t_c = L_b / v` \[s\] a rubber element spends in the
    /// block's nominal contact (periodic cells with a block length).
    pub fn contact_time(&self) -> Option<f64> {
        match self.domain {
            HeatDomain::Periodic {
                block_length: Some(l),
            } => Some(l / self.speed),
            _ => None,
        }
    }

    /// Whether the cells are one period of a periodic cell.
    pub fn is_periodic(&self) -> bool {
        matches!(self.domain, HeatDomain::Periodic { .. })
    }

    /// What the rise leaves out or may overstate, a sentence each:
    /// - a periodic cell without a block length: its mean has no steady
    ///   state, and the rise is given about it;
    /// - a periodic cell whose longest period `L` (of either axis) reaches
    ///   deeper, `L / (2 pi)`, than 0.3 of the diffusion length `sqrt(kappa
    ///   t_c)` of one passage (physics.md section 14): the background
    ///   heating's formula needs the heat released well within that
    ///   length, and the modes constant along the sliding direction, which
    ///   no sliding refreshes, settle only after about `(L / 2 pi)^2 /
    ///   kappa`; within the passage their steady rise is not reached.
    pub fn notes(&self) -> Vec<String> {
        let HeatDomain::Periodic { block_length } = self.domain else {
            return Vec::new();
        };
        let Some(lb) = block_length else {
            return vec![NO_BLOCK_NOTE.to_string()];
        };
        let (lx, ly) = self.grid.lengths();
        let period = lx.max(ly);
        let depth = period / (2.0 * std::f64::consts::PI);
        let passage = lb / self.speed;
        let diffusion = (self.conduction.diffusivity * passage).sqrt();
        if depth > PASSAGE_DEPTH_SHARE * diffusion {
            vec![format!(
                "the cell's longest period {period:.3e} m reaches about {depth:.3e} m deep, against the diffusion length sqrt(kappa L_b / v) = {diffusion:.3e} m of one passage: the background heating's formula needs the first much smaller, and the steady rise of the modes constant along the sliding direction, which settle in about {:.3e} s (the passage takes {passage:.3e} s), overstates what one passage reaches (physics.md section 14); take a smaller cell or a longer block",
                depth * depth / self.conduction.diffusivity
            )]
        } else {
            Vec::new()
        }
    }

    /// Where the rubber is a layer `thickness` \[m\] thick: the heat
    /// problem is a rubber half-space, so once the heat reaches the
    /// layer's base (whose conduction is not modelled) the rise depends
    /// on it. The depth the heat reaches: with a block length, one
    /// passage under the block, `sqrt(kappa L_b / v)` (physics.md section
    /// 14); otherwise the thermal boundary layer of the cell's length `L`
    /// along the sliding ([`HeatSetup::cell_length_along_sliding`]),
    /// `min(L, sqrt(kappa L / v))`. A sentence when that depth exceeds
    /// [`LAYER_DEPTH_SHARE`] of the thickness; `None` at rest, where no
    /// heat is released.
    pub(crate) fn layer_note(&self, thickness: f64) -> Option<String> {
        if self.speed == 0.0 {
            return None;
        }
        let kappa = self.conduction.diffusivity;
        let (depth, how) = match self.domain {
            HeatDomain::Periodic {
                block_length: Some(lb),
            } => (
                (kappa * lb / self.speed).sqrt(),
                "the block's passage sqrt(kappa L_b / v)",
            ),
            domain => {
                let along = self.cell_length_along_sliding();
                (
                    along.min((kappa * along / self.speed).sqrt()),
                    if domain == HeatDomain::Pad {
                        "the pad's thermal boundary layer min(L, sqrt(kappa L / v))"
                    } else {
                        "the cell's thermal boundary layer min(L, sqrt(kappa L / v))"
                    },
                )
            }
        };
        (depth > LAYER_DEPTH_SHARE * thickness).then(|| {
            format!(
                "the heat problem is a rubber half-space, but the rubber is a layer {thickness:.3e} m thick: heat reaches about {depth:.3e} m deep ({how}), so the layer's base, whose conduction is not modelled, changes the rise (a metal base lowers it); the rise holds only where that depth is well within the layer"
            )
        })
    }
}

/// The heat of a layered rubber stays within its layer while the depth it
/// reaches is below this share of the thickness
/// ([`HeatSetup::layer_note`]).
pub(crate) const LAYER_DEPTH_SHARE: f64 = 0.3;

/// What the heat of a contact at rest says of itself (the heated solve
/// adds what its answer is).
pub(crate) const AT_REST_NOTE: &str =
    "at rest (speed = 0) nothing is dissipated, so every temperature rise is zero";

/// What a periodic cell without a block length says about its mean.
pub(crate) const NO_BLOCK_NOTE: &str = "periodic cell without a block length: the mean rise (k = 0) has no steady state, so the rise is given about its mean (zero mean); give the block length along the sliding direction for the block's background heating";

/// A periodic cell's rise holds while the depth `L / (2 pi)` of its longest
/// period `L` is below this share of the diffusion length `sqrt(kappa
/// t_c)` of one passage ([`HeatSetup::notes`]).
pub(crate) const PASSAGE_DEPTH_SHARE: f64 = 0.3;
