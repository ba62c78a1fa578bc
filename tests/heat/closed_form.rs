//! The pad's surface rise under a uniform flux on a square patch against
//! the moving point source integrated over the patch independently
//! (`reference.rs`), at the centre, behind, ahead and beside, Peclet
//! numbers `v a / kappa` from 1e-2 to 1e3 (`a` the patch's side).
//!
//! The module's rise at a cell centre is the sum over the patch's cells of
//! the exact cell integrals, i.e. exactly the patch integral: there is no
//! discretisation error to allow for, only the quadrature of each
//! (1e-11 per piece) and the FFT's round-off (1e-16 of the largest
//! rise: up to ~2e-7 relative at the coolest points tested, half a cell
//! ahead of the patch at Peclet 1e3 and beside it at 300, where the rise
//! is ~1e-9 of the centre's; ~1e-14 elsewhere). The tolerance, 1e-4
//! relative, is the target; the errors measured are printed
//! (`--nocapture`).

use viscoslide::heat::{surface_temperature, Conduction, HeatDomain, HeatSetup};
use viscoslide::response::Grid;

use crate::reference::{patch_integral, stationary, Motion, Rect};

const LAMBDA: f64 = 0.25;
const KAPPA: f64 = 1e-7;
/// Flux on the patch [W/m^2].
const FLUX: f64 = 1e5;
/// Side of the patch [m].
const SIDE: f64 = 1e-3;

/// A patch of `n.0 x n.1` cells starting at cell `start` of a grid of
/// `grid` cells, sides `SIDE / n`.
struct Pad {
    grid: (usize, usize),
    n: (usize, usize),
    start: (usize, usize),
}

impl Pad {
    fn cell(&self) -> (f64, f64) {
        (SIDE / self.n.0 as f64, SIDE / self.n.1 as f64)
    }

    fn patch(&self) -> Rect {
        let (dx, dy) = self.cell();
        (
            self.start.0 as f64 * dx,
            (self.start.0 + self.n.0) as f64 * dx,
            self.start.1 as f64 * dy,
            (self.start.1 + self.n.1) as f64 * dy,
        )
    }

    fn centre_of(&self, (i, j): (usize, usize)) -> (f64, f64) {
        let (dx, dy) = self.cell();
        ((i as f64 + 0.5) * dx, (j as f64 + 0.5) * dy)
    }

    /// The module's rise on the grid at Peclet number `pe`, sliding at
    /// `deg` from +x.
    fn solve(&self, pe: f64, deg: f64) -> Vec<f64> {
        let (dx, dy) = self.cell();
        let (nx, ny) = self.grid;
        let mut flux = vec![0.0; nx * ny];
        for i in self.start.0..self.start.0 + self.n.0 {
            for j in self.start.1..self.start.1 + self.n.1 {
                flux[i * ny + j] = FLUX;
            }
        }
        let setup = HeatSetup {
            grid: Grid::new(nx, ny, (dx, dy)).unwrap(),
            conduction: Conduction {
                conductivity: LAMBDA,
                diffusivity: KAPPA,
            },
            speed: pe * KAPPA / SIDE,
            direction_rad: deg.to_radians(),
            domain: HeatDomain::Pad,
        };
        surface_temperature(setup, &flux).unwrap().rise
    }

    /// The reference rise at cell `c`.
    fn reference(&self, pe: f64, deg: f64, c: (usize, usize)) -> f64 {
        let t = deg.to_radians();
        let m = Motion {
            e: (t.cos(), t.sin()),
            rate: pe / SIDE,
        };
        FLUX / (std::f64::consts::TAU * LAMBDA) * patch_integral(m, self.centre_of(c), self.patch())
    }
}

/// The largest relative error over the points `(name, cell)`.
fn worst(pad: &Pad, pe: f64, deg: f64, points: &[(&str, (usize, usize))]) -> f64 {
    let rise = pad.solve(pe, deg);
    let ny = pad.grid.1;
    let mut worst: f64 = 0.0;
    for (name, c) in points {
        let got = rise[c.0 * ny + c.1];
        let want = pad.reference(pe, deg, *c);
        let err = (got / want - 1.0).abs();
        eprintln!("Pe {pe:e}, {deg} deg, {name} {c:?}: {got:.10e} K vs {want:.10e} K, relative error {err:.2e}");
        assert!(err < 1e-4, "Pe {pe}, {name}: {got} vs {want} ({err:e})");
        worst = worst.max(err);
    }
    worst
}

/// Square cells sliding along +x: 31 x 31 cells on the patch (a cell
/// centre at its centre), 64 x 64 on the grid. Behind (-x) a quarter side
/// past the trailing edge; ahead half a cell past the leading edge; beside
/// at a distance that stays inside the wake's reach, `a sqrt(20 / Pe)` at
/// most (beyond it the rise is below 1e-9 of the centre's at Peclet 1e3,
/// lost in the round-off of any sum).
#[test]
fn uniform_square_patch_matches_the_moving_source_integral() {
    let pad = Pad {
        grid: (64, 64),
        n: (31, 31),
        start: (16, 16),
    };
    let mut all: f64 = 0.0;
    for pe in [1e-2, 1e-1, 1.0, 10.0, 100.0, 1e3] {
        let side = (31.0 * (20.0f64 / pe).sqrt() - 0.5).clamp(0.0, 8.0) as usize;
        let points = [
            ("centre", (31, 31)),
            ("behind", (8, 31)),
            ("ahead", (47, 31)),
            ("beside", (31, 47 + side)),
        ];
        all = all.max(worst(&pad, pe, 0.0, &points));
    }
    eprintln!("square patch, Pe 1e-2..1e3: largest relative error {all:.2e}");
}

/// Rectangular cells (`dy = dx / 3`: 31 x 93 cells on the patch) and a
/// direction off the axes (30 degrees): the same patch integral.
#[test]
fn rectangular_cells_and_oblique_sliding_match_too() {
    let rect = Pad {
        grid: (64, 192),
        n: (31, 93),
        start: (16, 48),
    };
    for pe in [1.0, 100.0] {
        let points = [
            ("centre", (31, 94)),
            ("behind", (8, 94)),
            ("ahead", (47, 94)),
            ("beside", (31, 150)),
        ];
        worst(&rect, pe, 0.0, &points);
    }
    let square = Pad {
        grid: (64, 64),
        n: (31, 31),
        start: (16, 16),
    };
    // Behind: the centre minus 0.7 a e_v; on the leading side, half a
    // cell past the leading edge x = a; beside: the centre plus 0.7 a
    // across e_v (cells rounded).
    let points = [
        ("centre", (31, 31)),
        ("behind", (12, 20)),
        ("leading side", (47, 40)),
        ("beside", (20, 50)),
    ];
    for pe in [0.1, 10.0, 300.0] {
        worst(&square, pe, 30.0, &points);
    }
}

/// At rest (Peclet 1e-9) the rise is the stationary closed form
/// `q / (2 pi lam) Int 1/R` (Love's corner function): to 1e-8, the
/// Peclet number's own effect (~1e-9) and the quadrature's.
#[test]
fn the_slow_limit_is_the_stationary_closed_form() {
    let pad = Pad {
        grid: (48, 40),
        n: (15, 21),
        start: (20, 10),
    };
    let rise = pad.solve(1e-9, 0.0);
    let ny = pad.grid.1;
    for c in [(27, 20), (3, 20), (36, 20), (27, 35), (0, 0), (47, 39)] {
        let want =
            FLUX / (std::f64::consts::TAU * LAMBDA) * stationary(pad.centre_of(c), pad.patch());
        let got = rise[c.0 * ny + c.1];
        let err = (got / want - 1.0).abs();
        eprintln!("rest, cell {c:?}: relative error {err:.2e}");
        assert!(err < 1e-8, "{c:?}: {got} vs {want}");
    }
    // The centre of a square patch of side a: 4 q (a/2) ln(1 + sqrt 2) / (pi lam).
    let sq = Pad {
        grid: (31, 31),
        n: (31, 31),
        start: (0, 0),
    };
    let got = sq.solve(1e-9, 0.0)[15 * 31 + 15];
    let want = 2.0 * FLUX * SIDE * (1.0 + 2f64.sqrt()).ln() / (std::f64::consts::PI * LAMBDA);
    assert!((got / want - 1.0).abs() < 1e-8, "{got} vs {want}");
}
