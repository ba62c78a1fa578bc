//! Nested iteration (a coarse-to-fine cascade): solve the same physical
//! problem on grids of `n/2^k` cells a side first and start each finer
//! solve from the prolonged pressure, approach and contact set of the
//! coarser one (full-multigrid style nested iteration; for rough contact the
//! "cascade multi-resolution" identification of the trial contact domain of
//! Bemporad & Paggi, Int. J. Solids Struct. 62, 263, 2015). On the fine grid
//! the active-set iteration then starts next to its solution: a few outer
//! iterations instead of the dozens a bearing-area guess needs.
//!
//! The routine knows nothing of materials or surfaces: the caller builds
//! each level (its backend, the gap profile on that grid, the cell area and
//! the self coefficient) in a closure. [`restrict_mean`] and
//! [`WarmStart::prolonged`] are the grid transfers.

use serde::Serialize;

use super::active_set::solve;
use super::{
    ContactProblem, ContactSolution, Control, Observer, SolveInfo, SolverError, SolverParams,
    WarmStart,
};
use crate::backend::Backend;

/// One grid of a cascade, built by the caller.
pub struct CascadeLevel<B> {
    pub backend: B,
    /// Gap profile `g >= 0` on this grid, C order (`nx` rows of `ny`).
    pub gap: Vec<f64>,
    /// Area of one cell \[m^2\].
    pub cell_area: f64,
    /// `L_00` of this grid's operator.
    pub self_coefficient: f64,
}

/// Convergence of one grid of a cascade.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LevelInfo {
    pub nx: usize,
    pub ny: usize,
    /// Active-set iterations on this grid.
    pub iterations: usize,
    /// Operator applications on this grid (not scaled).
    pub matvecs: usize,
    /// Preconditioner applications on this grid (not scaled).
    pub preconditioner_applications: usize,
    /// Final complementarity residual on this grid.
    pub residual: f64,
}

/// Tolerance of the coarse grids' solves: their solutions are starts only.
pub const COARSE_TOLERANCE: f64 = 1e-4;

/// The grids of a cascade for an `nx x ny` problem, coarse to fine: halve
/// both sides while they are even and the smaller stays `>= coarsest`, at
/// most `max_levels` grids in all (the fine one included).
pub fn cascade_shapes(
    nx: usize,
    ny: usize,
    coarsest: usize,
    max_levels: usize,
) -> Vec<(usize, usize)> {
    let mut shapes = vec![(nx, ny)];
    let (mut x, mut y) = (nx, ny);
    while shapes.len() < max_levels.max(1)
        && x % 2 == 0
        && y % 2 == 0
        && (x / 2).min(y / 2) >= coarsest
    {
        x /= 2;
        y /= 2;
        shapes.push((x, y));
    }
    shapes.reverse();
    shapes
}

/// Restrict a field of an `nx x ny` grid (both even) to the `nx/2 x ny/2`
/// grid by averaging each 2 x 2 block of cells.
pub fn restrict_mean(values: &[f64], nx: usize, ny: usize) -> Vec<f64> {
    assert!(nx % 2 == 0 && ny % 2 == 0, "the grid sides must be even");
    assert_eq!(values.len(), nx * ny, "one value per cell");
    let (cx, cy) = (nx / 2, ny / 2);
    let mut out = vec![0.0; cx * cy];
    for i in 0..cx {
        for j in 0..cy {
            let at = |di: usize, dj: usize| values[(2 * i + di) * ny + 2 * j + dj];
            out[i * cy + j] = 0.25 * (at(0, 0) + at(0, 1) + at(1, 0) + at(1, 1));
        }
    }
    out
}

/// Each cell of an `nx x ny` field repeated on its 2 x 2 children of the
/// `2nx x 2ny` grid (piecewise-constant prolongation).
pub fn prolong_constant(values: &[f64], nx: usize, ny: usize) -> Vec<f64> {
    assert_eq!(values.len(), nx * ny, "one value per cell");
    let fy = 2 * ny;
    let mut out = vec![0.0; 4 * nx * ny];
    for i in 0..2 * nx {
        for j in 0..fy {
            out[i * fy + j] = values[(i / 2) * ny + j / 2];
        }
    }
    out
}

impl WarmStart {
    /// The start on the `2nx x 2ny` grid from a solution on the `nx x ny`
    /// grid of the same domain: pressure and contact set prolonged
    /// piecewise-constantly (the load `a^2 sum p` is kept), same approach.
    pub fn prolonged(solution: &ContactSolution, nx: usize, ny: usize) -> Self {
        Self {
            contact: prolong_constant(&solution.contact, nx, ny),
            pressure: prolong_constant(&solution.pressure, nx, ny),
            approach: solution.approach,
        }
    }
}

/// Solve on the grids `shapes` (coarse to fine, each side doubling from one
/// to the next; [`cascade_shapes`]), level `k` built by `build(k, shape)`.
/// The coarse grids are solved to `max(tolerance, COARSE_TOLERANCE)` from
/// the bearing-area guess (the coarsest) or the prolonged coarser solution;
/// the finest to `params.tolerance`. The returned [`SolveInfo`] is the
/// finest grid's, with `matvecs` and `preconditioner_applications` as
/// fine-grid equivalents (each application weighted by its grid's cells
/// over the fine grid's) and the detail in `levels`.
///
/// `start` replaces the coarsest grid's bearing-area guess (e.g. a solution
/// prolonged from an even coarser solve).
pub fn solve_cascade<B, F>(
    shapes: &[(usize, usize)],
    mut build: F,
    control: Control,
    params: &SolverParams,
    start: Option<&WarmStart>,
    observer: &mut dyn Observer,
) -> Result<(ContactSolution, SolveInfo), SolverError>
where
    B: Backend,
    F: FnMut(usize, (usize, usize)) -> Result<CascadeLevel<B>, SolverError>,
{
    let Some(&(fx, fy)) = shapes.last() else {
        return Err(SolverError::Invalid(
            "a cascade needs at least one grid".into(),
        ));
    };
    for w in shapes.windows(2) {
        if w[1] != (2 * w[0].0, 2 * w[0].1) {
            return Err(SolverError::Invalid(format!(
                "cascade grids must double from one level to the next: {:?} then {:?}",
                w[0], w[1]
            )));
        }
    }
    let fine_cells = (fx * fy) as f64;
    let mut levels = Vec::with_capacity(shapes.len());
    let mut scaled = (0.0, 0.0, 0.0);
    let mut warm: Option<WarmStart> = start.cloned();
    let last = shapes.len() - 1;
    for (k, &(nx, ny)) in shapes.iter().enumerate() {
        let mut level = build(k, (nx, ny))?;
        if level.backend.grid_len() != nx * ny {
            return Err(SolverError::Invalid(format!(
                "level {k} was built with {} cells, expected {nx} x {ny}",
                level.backend.grid_len()
            )));
        }
        let level_params = if k == last {
            params.clone()
        } else {
            SolverParams {
                tolerance: params.tolerance.max(COARSE_TOLERANCE),
                ..params.clone()
            }
        };
        let problem = ContactProblem::new(
            std::mem::take(&mut level.gap),
            level.cell_area,
            level.self_coefficient,
            control,
        );
        let (solution, info) = solve(
            &mut level.backend,
            problem,
            &level_params,
            warm.take(),
            observer,
        )?;
        let weight = (nx * ny) as f64 / fine_cells;
        scaled.0 += weight * info.matvecs as f64;
        scaled.1 += weight * info.preconditioner_applications as f64;
        scaled.2 += weight * info.exact_matvecs as f64;
        levels.push(LevelInfo {
            nx,
            ny,
            iterations: info.iterations,
            matvecs: info.matvecs,
            preconditioner_applications: info.preconditioner_applications,
            residual: info.residual,
        });
        if k == last {
            let info = SolveInfo {
                matvecs: scaled.0.ceil() as usize,
                preconditioner_applications: scaled.1.ceil() as usize,
                exact_matvecs: scaled.2.ceil() as usize,
                levels,
                ..info
            };
            return Ok((solution, info));
        }
        warm = Some(WarmStart::prolonged(&solution, nx, ny));
    }
    unreachable!("the loop returns at the finest grid")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shapes_halve_while_even() {
        assert_eq!(
            cascade_shapes(512, 256, 64, 10),
            vec![(128, 64), (256, 128), (512, 256)]
        );
        assert_eq!(
            cascade_shapes(512, 512, 64, 2),
            vec![(256, 256), (512, 512)]
        );
        assert_eq!(
            cascade_shapes(100, 100, 8, 10),
            vec![(25, 25), (50, 50), (100, 100)]
        );
        assert_eq!(cascade_shapes(33, 64, 8, 10), vec![(33, 64)]);
    }

    #[test]
    fn transfers_keep_means_and_load() {
        let (nx, ny) = (4, 6);
        let v: Vec<f64> = (0..nx * ny).map(|k| (k * 7 % 5) as f64).collect();
        let c = restrict_mean(&v, nx, ny);
        assert_eq!(c.len(), 6);
        let mean = |x: &[f64]| x.iter().sum::<f64>() / x.len() as f64;
        assert!((mean(&c) - mean(&v)).abs() < 1e-14);
        assert_eq!(c[0], 0.25 * (v[0] + v[1] + v[6] + v[7]));
        let f = prolong_constant(&c, 2, 3);
        assert_eq!(restrict_mean(&f, 4, 6), c);
        // load: (2a)^2 sum p_coarse = a^2 sum p_fine
        assert!((4.0 * c.iter().sum::<f64>() - f.iter().sum::<f64>()).abs() < 1e-12);
    }
}
