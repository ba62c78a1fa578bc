//! What a heat problem is given: the grid of cells, the solid's heat
//! conduction, the sliding speed and direction, and whether the cells are
//! a pad or one period of a periodic cell (physics.md section 14). Every
//! check of these values lives here.

use super::error::{positive, HeatError};

/// A uniform grid of `nx x ny` rectangular cells of sides `dx x dy` \[m\]
/// (axis 0 = x; values in C order, `values[i * ny + j]`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HeatGrid {
    pub nx: usize,
    pub ny: usize,
    /// Cell side along x \[m\].
    pub dx: f64,
    /// Cell side along y \[m\].
    pub dy: f64,
}

impl HeatGrid {
    /// Number of cells.
    pub fn cells(&self) -> usize {
        self.nx * self.ny
    }

    /// Area of one cell \[m^2\].
    pub fn cell_area(&self) -> f64 {
        self.dx * self.dy
    }

    fn check(&self) -> Result<(), HeatError> {
        if self.nx == 0 || self.ny == 0 {
            return Err(HeatError::Empty("the grid"));
        }
        positive("the cell size along x", self.dx, "m")?;
        positive("the cell size along y", self.dy, "m")?;
        Ok(())
    }
}

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
    pub grid: HeatGrid,
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
    /// grid with cells.
    pub fn check(&self) -> Result<(), HeatError> {
        self.grid.check()?;
        self.conduction.check()?;
        positive("the speed", self.speed, "m/s")?;
        if !self.direction_rad.is_finite() {
            return Err(HeatError::Direction(self.direction_rad));
        }
        if let HeatDomain::Periodic {
            block_length: Some(l),
        } = self.domain
        {
            positive("the block length", l, "m")?;
        }
        Ok(())
    }

    /// Unit vector `e_v` of the sliding direction; components below 1e-15
    /// are snapped to zero, so that 90 degrees is exactly +y and the
    /// tables of a direction along an axis are exactly mirror-symmetric.
    pub fn direction(&self) -> (f64, f64) {
        let (s, c) = self.direction_rad.sin_cos();
        let snap = |x: f64| if x.abs() < 1e-15 { 0.0 } else { x };
        (snap(c), snap(s))
    }

    /// The cell Peclet number `v dx / kappa` (`dx` the side along x).
    pub fn peclet(&self) -> f64 {
        self.speed * self.grid.dx / self.conduction.diffusivity
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
}
