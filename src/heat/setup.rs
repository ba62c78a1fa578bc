//! What a heat problem is given: the grid of cells, the solid's heat
//! conduction, the sliding speed and direction, and whether the cells are
//! a pad or one period of a periodic cell (physics.md section 14). Every
//! check of these values lives here.

use super::error::{positive, HeatError};
use crate::response::Grid;

/// The cell Peclet number above which a pad is refused: measured, the
/// trailing row of a uniform square patch of 33 x 33 cells meets the
/// one-dimensional high-Peclet limit `(2 q / lam) sqrt(kappa x / (pi v))`
/// (averaged over the cell) to 0.1 % at 1e7, and falls to 68 % of it at
/// 4e7 and 35 % at 1e8: the wake is then narrower than the cell
/// integrals (`cell.rs`) resolve.
pub(crate) const PAD_PECLET_LIMIT: f64 = 1e7;

/// The relative round-off within which a block as long as the periodic
/// cell is taken as equal to it (the cell's length is a sum of cells).
const BLOCK_ROUND_OFF: f64 = 1e-12;

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
        self.check_at_rest()?;
        let rate = self.speed / self.conduction.diffusivity;
        if !rate.is_finite() {
            return Err(HeatError::OutOfRange(format!(
                "the speed over the diffusivity, {:e} m/s over {:e} m^2/s, is beyond the range of f64",
                self.speed, self.conduction.diffusivity
            )));
        }
        let peclet = self.peclet();
        if self.domain == HeatDomain::Pad && peclet > PAD_PECLET_LIMIT {
            return Err(HeatError::OutOfRange(format!(
                "the cell Peclet number v a / kappa = {peclet:.3e} is above {PAD_PECLET_LIMIT:e}, where a pad's cell integrals hold: the heat's wake behind a source is then narrower than a cell resolves; give smaller cells, or a periodic cell"
            )));
        }
        Ok(())
    }

    /// [`HeatSetup::check`] where the speed is not zero,
    /// [`HeatSetup::check_at_rest`] where it is (a contact at rest, or a
    /// sweep's static point): what a heated solve at this speed needs.
    pub(crate) fn check_sliding_or_at_rest(&self) -> Result<(), HeatError> {
        if self.speed == 0.0 {
            self.check_at_rest()
        } else {
            self.check()
        }
    }

    /// [`HeatSetup::check`] but for the speed, which may be zero: a
    /// contact at rest, whose zero source has zero rise without a
    /// solve.
    pub(crate) fn check_at_rest(&self) -> Result<(), HeatError> {
        self.conduction.check()?;
        if !self.direction_rad.is_finite() {
            return Err(HeatError::Direction(self.direction_rad));
        }
        let (lo, hi) = crate::response::CELL_SIDE_RANGE;
        let (ax, ay) = self.grid.cell();
        if ![ax, ay].iter().all(|a| (lo..=hi).contains(a)) {
            return Err(HeatError::OutOfRange(format!(
                "the cell {ax:e} x {ay:e} m is beyond the range of the heat problem's arithmetic (cells of {lo:.3e} m to {hi:.3e} m, whose squares f64 holds); give cells nearer the contact's scales"
            )));
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
            // A block as long as the cell, up to the round-off of the
            // cell's length (its cells' sum), is the cell itself.
            if l < cell * (1.0 - BLOCK_ROUND_OFF) {
                return Err(HeatError::BlockShorterThanCell { block: l, cell });
            }
        }
        Ok(())
    }

    /// The cell's length along the sliding direction \[m\]: the chord
    /// through its centre along `e_v`, `min(L_x / |e_x|, L_y / |e_y|)`
    /// (`L_x` sliding along x).
    pub fn cell_length_along_sliding(&self) -> f64 {
        self.chord(self.grid.lengths())
    }

    /// The chord along `e_v` through the centre of a rectangle of sides
    /// `(l_x, l_y)` \[m\]: `min(l_x / |e_x|, l_y / |e_y|)`.
    fn chord(&self, (lx, ly): (f64, f64)) -> f64 {
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

    /// The cell Peclet number `v a / kappa`, `a` a cell's length along
    /// the sliding direction (its chord through the centre along `e_v`,
    /// `min(a_x / |e_x|, a_y / |e_y|)`, as [`HeatSetup::cell_length_along_sliding`]
    /// measures the periodic cell).
    pub fn peclet(&self) -> f64 {
        self.speed * self.chord(self.grid.cell()) / self.conduction.diffusivity
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

#[cfg(test)]
mod tests {
    use super::*;

    fn setup(cell: (f64, f64), speed: f64, direction_rad: f64, domain: HeatDomain) -> HeatSetup {
        HeatSetup {
            grid: Grid::new(12, 7, cell).unwrap(),
            conduction: Conduction {
                conductivity: 0.25,
                diffusivity: 1e-7,
            },
            speed,
            direction_rad,
            domain,
        }
    }

    #[test]
    fn cells_beyond_the_arithmetic_are_refused() {
        for a in [1e-155, 1e-200, 1e155] {
            let e = setup((a, a), 0.1, 0.0, HeatDomain::Pad)
                .check()
                .unwrap_err();
            assert!(
                e.to_string()
                    .contains("beyond the range of the heat problem's arithmetic"),
                "{e}"
            );
        }
        assert!(setup((1e-100, 1e-100), 0.1, 0.0, HeatDomain::Pad)
            .check()
            .is_ok());
    }

    /// Inputs each valid whose ratio or Peclet number is not: refused in
    /// one line naming them (they hung the cell integrals, or lost the
    /// wake).
    #[test]
    fn speeds_beyond_the_rules_are_refused() {
        let s = |speed: f64, domain| setup((1e-5, 1e-5), speed, 0.0, domain);
        let e = s(1e303, HeatDomain::Periodic { block_length: None })
            .check()
            .unwrap_err();
        assert!(e.to_string().contains("beyond the range of f64"), "{e}");
        let e = s(1e6, HeatDomain::Pad).check().unwrap_err();
        assert!(e.to_string().contains("v a / kappa = 1.000e8"), "{e}");
        assert!(s(1e5, HeatDomain::Pad).check().is_ok());
        assert!(s(1e6, HeatDomain::Periodic { block_length: None })
            .check()
            .is_ok());
    }

    /// The cell Peclet number takes the cell's chord along the sliding
    /// direction: a cell of 1e-5 x 3e-5 m sliding along y is one of 3e-5
    /// m along its way.
    #[test]
    fn the_peclet_number_measures_the_cell_along_the_sliding() {
        let p = |dir: f64| setup((1e-5, 3e-5), 0.1, dir, HeatDomain::Pad).peclet();
        assert!((p(0.0) - 10.0).abs() < 1e-12);
        assert!((p(std::f64::consts::FRAC_PI_2) - 30.0).abs() < 1e-12);
        // At 45 degrees the chord leaves through the nearer side, x.
        assert!((p(std::f64::consts::FRAC_PI_4) - 10.0 * 2f64.sqrt()).abs() < 1e-9);
    }

    /// A block as long as the cell, which its cells' sum misses by
    /// round-off, is the cell.
    #[test]
    fn a_block_as_long_as_the_cell_is_taken() {
        let block = |l: f64| {
            setup(
                (1e-5, 1e-5),
                0.1,
                0.0,
                HeatDomain::Periodic {
                    block_length: Some(l),
                },
            )
            .check()
        };
        let cell = setup((1e-5, 1e-5), 0.1, 0.0, HeatDomain::Pad).cell_length_along_sliding();
        assert!(cell > 1.2e-4, "{cell}");
        assert!(block(1.2e-4).is_ok());
        assert!(block(1.19e-4).is_err());
    }
}
