//! The grid every operator, table and figure is defined on: `nx x ny` cells
//! of sides `dx x dy` (physics.md section 3, "Discretisation"; rectangular
//! cells: section 11), periodic or not.

use super::ResponseError;

/// The cell sides the kernel's and the heat problem's arithmetic hold for:
/// their squares (and the squared distances and wavenumbers they form)
/// normal f64 numbers, `sqrt(f64::MIN_POSITIVE)` to `sqrt(f64::MAX)`
/// (1.5e-154 m to 1.3e154 m). Outside, coefficients come out NaN or zero,
/// and a heat rise on cells of 1e-200 m came out 2.5 times too low.
pub(crate) const CELL_SIDE_RANGE: (f64, f64) = (1.4916681462400413e-154, 1.3407807929942596e154);

/// The greatest common divisor of two cell counts (`a` where `b` is 0).
pub(crate) fn gcd(a: usize, b: usize) -> usize {
    if b == 0 {
        a
    } else {
        gcd(b, a % b)
    }
}

/// `nx x ny` cells of sides `dx` along x and `dy` along y \[m\], on a
/// periodic cell (the spectral formulation, physics.md section 6) or a
/// finite pad (the Toeplitz formulation). Checked once, in [`Grid::new`]:
/// at least one cell per side, sides positive and finite.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Grid {
    nx: usize,
    ny: usize,
    dx: f64,
    dy: f64,
    periodic: bool,
}

impl Grid {
    /// A finite (non-periodic) grid.
    pub fn new(nx: usize, ny: usize, (dx, dy): (f64, f64)) -> Result<Self, ResponseError> {
        if nx == 0 || ny == 0 {
            return Err(ResponseError::Invalid(format!(
                "grid {nx} x {ny} must have at least one cell per side"
            )));
        }
        for (name, a) in [("ax", dx), ("ay", dy)] {
            if !(a.is_finite() && a > 0.0) {
                return Err(ResponseError::Invalid(format!(
                    "cell size {name} = {a} m must be positive and finite"
                )));
            }
        }
        Ok(Self {
            nx,
            ny,
            dx,
            dy,
            periodic: false,
        })
    }

    /// A finite grid of square cells of side `a` \[m\].
    pub fn square(nx: usize, ny: usize, a: f64) -> Result<Self, ResponseError> {
        Self::new(nx, ny, (a, a))
    }

    /// The same cells as one period of a periodic surface.
    pub fn periodic(mut self) -> Self {
        self.periodic = true;
        self
    }

    /// `(nx, ny)`.
    pub fn size(&self) -> (usize, usize) {
        (self.nx, self.ny)
    }

    /// Cells along x.
    pub fn nx(&self) -> usize {
        self.nx
    }

    /// Cells along y.
    pub fn ny(&self) -> usize {
        self.ny
    }

    /// `(dx, dy)` \[m\].
    pub fn cell(&self) -> (f64, f64) {
        (self.dx, self.dy)
    }

    /// Whether the cells are square (to the bit).
    pub fn is_square(&self) -> bool {
        self.dx == self.dy
    }

    /// Whether the grid is one period of a periodic surface.
    pub fn is_periodic(&self) -> bool {
        self.periodic
    }

    /// `nx ny`.
    pub fn cells(&self) -> usize {
        self.nx * self.ny
    }

    /// `(L_x, L_y) = (nx dx, ny dy)` \[m\].
    pub fn lengths(&self) -> (f64, f64) {
        (self.nx as f64 * self.dx, self.ny as f64 * self.dy)
    }

    /// Area of one cell `dx dy` \[m^2\].
    pub fn cell_area(&self) -> f64 {
        self.dx * self.dy
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_cell_side_range_is_where_squares_are_normal() {
        assert_eq!(CELL_SIDE_RANGE.0, f64::MIN_POSITIVE.sqrt());
        assert_eq!(CELL_SIDE_RANGE.1, f64::MAX.sqrt());
    }

    #[test]
    fn refuses_empty_grids_and_bad_cells_naming_them() {
        let e = Grid::new(0, 4, (1.0, 1.0)).unwrap_err().to_string();
        assert!(e.contains("0 x 4"), "{e}");
        let e = Grid::new(4, 4, (1.0, f64::NAN)).unwrap_err().to_string();
        assert!(e.contains("ay = NaN"), "{e}");
        let e = Grid::square(4, 4, -1.0).unwrap_err().to_string();
        assert!(e.contains("ax = -1"), "{e}");
        let g = Grid::new(4, 2, (1.0, 3.0)).unwrap().periodic();
        assert_eq!(g.lengths(), (4.0, 6.0));
        assert!(g.is_periodic() && !g.is_square());
    }
}
