//! The coarse grid on which a heated solve scans its bracket
//! (`two_level.rs`): the same surface, its heights averaged over blocks
//! of `f x f` cells as the cascade builds its coarse levels
//! (`src/problem/cascade.rs`), every other control unchanged.

use crate::problem::{highest, Control, Problem};
use crate::solver::cascade::restrict_mean;
use crate::surface::HeightMap;

/// The coarse grid's side is the full grid's over this factor at most.
pub(crate) const COARSE_FACTOR: usize = 4;

/// Nor fewer cells a side than this (the cascade's coarsest grid): below
/// it a coarse solve saves too little, and the full-grid scan runs alone.
pub(crate) const COARSE_MIN_SIDE: usize = 64;

/// `problem` on the coarse grid of its scan: both sides divided by the
/// largest power of two `f <= COARSE_FACTOR` that divides them and leaves
/// at least [`COARSE_MIN_SIDE`] cells; `None` where no `f >= 2` does.
/// Under approach control the indenter keeps its place (the approach is
/// measured from the highest summit, which the averaging lowers).
pub(crate) fn coarse_problem(problem: &Problem) -> Option<Problem> {
    let s = &problem.surface;
    let (nx, ny) = (s.nx, s.ny);
    let fits = |f: usize| {
        nx % f == 0 && ny % f == 0 && nx / f >= COARSE_MIN_SIDE && ny / f >= COARSE_MIN_SIDE
    };
    let mut f = COARSE_FACTOR;
    while f >= 2 && !fits(f) {
        f /= 2;
    }
    if f < 2 {
        return None;
    }
    let (mut cx, mut cy, mut heights) = (nx, ny, s.heights.clone());
    while cx > nx / f {
        heights = restrict_mean(&heights, cx, cy);
        (cx, cy) = (cx / 2, cy / 2);
    }
    let surface = HeightMap {
        nx: cx,
        ny: cy,
        cell_size: s.cell_size * f as f64,
        cell_size_y: s.cell_size_y * f as f64,
        heights,
    };
    let mut coarse = problem.clone();
    if let Control::Approach(d) = problem.control {
        coarse.control = Control::Approach(d + highest(&surface) - highest(s));
    }
    coarse.surface = surface;
    Some(coarse)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::{CreepSpectrum, Material};

    fn problem(nx: usize, ny: usize, control: Control) -> Problem {
        let heights = (0..nx * ny)
            .map(|c| ((c * 7919) % 101) as f64 * 1e-8)
            .collect();
        let surface = HeightMap {
            nx,
            ny,
            cell_size: 1e-6,
            cell_size_y: 2e-6,
            heights,
        };
        let sls = CreepSpectrum::standard_linear_solid(1e6, 3e6, 1e-3).unwrap();
        Problem::new(Material::new(sls, 0.5).unwrap(), surface, control, 1e-3)
    }

    #[test]
    fn the_coarse_grid_is_the_block_mean_of_the_map() {
        // 128 / 4 = 32 < 64 cells: the factor falls to 2.
        let c = coarse_problem(&problem(256, 128, Control::Load(1.0))).unwrap();
        assert_eq!((c.surface.nx, c.surface.ny), (128, 64));
        let p = problem(256, 256, Control::Approach(1e-7));
        let c = coarse_problem(&p).unwrap();
        let s = &c.surface;
        assert_eq!((s.nx, s.ny), (64, 64));
        assert_eq!((s.cell_size, s.cell_size_y), (4e-6, 8e-6));
        // Each coarse height is the mean of its 4 x 4 block (the sum
        // below differs from the nested 2 x 2 means by rounding only).
        for (i, j) in [(0, 0), (13, 50), (63, 63)] {
            let mut sum = 0.0;
            for a in 0..4 {
                for b in 0..4 {
                    sum += p.surface.heights[(4 * i + a) * 256 + 4 * j + b];
                }
            }
            let h = s.heights[i * 64 + j];
            assert!((h - sum / 16.0).abs() <= 1e-15 * sum.abs(), "{h} {sum}");
        }
        // The indenter keeps its place.
        match c.control {
            Control::Approach(d) => {
                let moved = highest(&p.surface) - highest(s);
                assert!((1e-7 - d - moved).abs() < 1e-20, "{d} {moved}");
            }
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn small_or_odd_grids_have_no_coarse_grid() {
        let load = Control::Load(1.0);
        assert!(coarse_problem(&problem(64, 64, load)).is_none());
        assert!(coarse_problem(&problem(126, 126, load)).is_none());
        let c = coarse_problem(&problem(128, 128, load)).unwrap();
        assert_eq!((c.surface.nx, c.surface.ny), (64, 64));
        let c = coarse_problem(&problem(512, 384, load)).unwrap();
        assert_eq!((c.surface.nx, c.surface.ny), (128, 96));
    }
}
