//! The adaptive solve: mesh, solve, certify on the fine grid, refine.
//!
//! 1. Initial mesh: fine cells where the surface is within the highest
//!    `initial_fraction` of its area (where contact is possible); coarse
//!    cells (up to `2^max_level` fine cells a side) elsewhere, each at the
//!    height of its highest point ([`QuadMesh::restrict_gap`]).
//! 2. Solve the contact problem of [`crate::solver`] on the mesh's cells
//!    (to 1e-5 while the mesh still moves; the settled mesh is solved again
//!    at the requested tolerance and certified once more).
//! 3. Certify: evaluate the displacement at the centre of every fine cell
//!    inside a coarse cell (the full-resolution field, from the mesh's
//!    pressure) and its gap `g - delta + u`.
//! 4. Next mesh: fine at every fine cell that has been in contact or has
//!    interpenetrated in any round (kept, so the loop cannot cycle), grown
//!    by `margin`, and at the highest point of every coarse cell that
//!    carries pressure; the rest of the initial guess coarsens again. Repeat until no fine
//!    cell interpenetrates and no coarse cell carries pressure.
//!
//! At that point the pressure lives on fine cells only, every fine cell of
//! a coarse cell is open, and the fine cells of the mesh satisfy the
//! complementarity conditions: the result is the solution of the uniform
//! fine-grid problem (to the solver's tolerance), with unknowns only where
//! the contact needs them.

use std::sync::Arc;

use serde::Serialize;

use crate::mesh::{dilate, MeshError, QuadMesh};
use crate::operator::{AdaptiveOperator, GridOperator, LevelTables, OffsetTable, ToeplitzFft};
use crate::solver::{ContactSolution, SolveInfo, SolverError, WarmStart};

/// Controls of the adaptive mesh (`[solver.adaptive]`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct AdaptiveParams {
    /// Coarsest level: blocks of `2^max_level` fine cells a side (default 5).
    pub max_level: u8,
    /// Fraction of the area, the highest part of the surface, meshed fine
    /// from the start (default 0.1).
    pub initial_fraction: f64,
    /// Fine cells added around every refined cell (default 1).
    pub margin: usize,
    /// Solve-certify-refine rounds allowed (default 12).
    pub max_rounds: usize,
}

impl Default for AdaptiveParams {
    fn default() -> Self {
        Self {
            max_level: 5,
            initial_fraction: 0.1,
            margin: 1,
            max_rounds: 12,
        }
    }
}

impl AdaptiveParams {
    /// Check the ranges; the message names the offending key.
    pub fn check(&self) -> Result<(), String> {
        if self.max_level > 12 {
            return Err(format!(
                "[solver.adaptive] max_level must be at most 12, got {}",
                self.max_level
            ));
        }
        if !(self.initial_fraction > 0.0 && self.initial_fraction <= 1.0) {
            return Err(format!(
                "[solver.adaptive] initial_fraction must be in (0, 1], got {}",
                self.initial_fraction
            ));
        }
        if self.max_rounds == 0 {
            return Err("[solver.adaptive] max_rounds must be at least 1".into());
        }
        Ok(())
    }
}

/// What the mesh looked like (reported in `summary.json`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MeshReport {
    /// Cells of the final mesh (the unknowns).
    pub unknowns: usize,
    /// Cells of the uniform fine grid.
    pub fine_cells: usize,
    /// Final mesh cells per level (index = level).
    pub level_counts: Vec<usize>,
    /// Solve-certify-refine rounds.
    pub rounds: usize,
    /// Unknowns of each round's mesh.
    pub unknowns_history: Vec<usize>,
    /// Memory of the coefficient tables \[bytes\].
    pub table_bytes: usize,
}

/// The result on the fine grid, with the mesh it was found on.
#[derive(Debug, Clone)]
pub struct AdaptiveSolution {
    /// Fields on the fine grid (`nx ny`, C order): pressure (zero in coarse
    /// cells), the full-resolution displacement and gap, contact mask.
    pub solution: ContactSolution,
    /// Convergence over all rounds: iterations and matvecs summed, the last
    /// round's residual and load error, histories concatenated.
    pub info: SolveInfo,
    pub mesh: QuadMesh,
    pub report: MeshReport,
}

/// Why an adaptive solve failed.
#[derive(Debug, thiserror::Error)]
pub enum AdaptiveError {
    #[error(transparent)]
    Solver(#[from] SolverError),
    #[error(transparent)]
    Mesh(#[from] MeshError),
    #[error("the adaptive mesh did not settle in {rounds} rounds ({marked} fine cells still interpenetrate or carry coarse pressure); raise [solver.adaptive] max_rounds or initial_fraction")]
    NotSettled { rounds: usize, marked: usize },
}

/// The gap below which a certified fine cell counts as interpenetrating:
/// `-tol |delta|` plus a rounding allowance on the displacement.
fn penetration_threshold(tolerance: f64, delta: f64, u_scale: f64) -> f64 {
    -(tolerance * delta.abs() + 1e-12 * u_scale)
}

/// Solve on an adaptive mesh. `g_fine` is the fine gap profile
/// (`max z - z`, `nx ny` values), `tables` the level tables of the fine
/// grid (built for at least `params.max_level`), and `solve_on_mesh` runs
/// the constrained iteration on one mesh: given the mesh and its gap
/// profile it returns the solution over the mesh's unknowns
/// `x_S = p_S (s_S/a)^2` (cell area `a^2` in the load constraint; see
/// [`AdaptiveOperator`]). `tolerance` is the solver's relative tolerance.
pub fn solve_adaptive(
    g_fine: &[f64],
    tables: Arc<LevelTables>,
    params: &AdaptiveParams,
    tolerance: f64,
    mut solve_on_mesh: impl FnMut(
        &QuadMesh,
        &[f64],
        Option<&WarmStart>,
        f64,
    ) -> Result<(ContactSolution, SolveInfo), SolverError>,
) -> Result<AdaptiveSolution, AdaptiveError> {
    params.check().map_err(MeshError::Invalid)?;
    let (nx, ny) = tables.shape();
    let a = tables.cell_size();
    if g_fine.len() != nx * ny {
        return Err(MeshError::Invalid(format!(
            "the gap profile has {} cells, the grid {nx} x {ny} needs {}",
            g_fine.len(),
            nx * ny
        ))
        .into());
    }
    let max_level = params.max_level.min(tables.max_level());
    // Initial refinement: the highest `initial_fraction` of the surface.
    let mut sorted = g_fine.to_vec();
    sorted.sort_unstable_by(f64::total_cmp);
    let cut = ((params.initial_fraction * sorted.len() as f64).ceil() as usize)
        .clamp(1, sorted.len())
        - 1;
    let threshold = sorted[cut];
    let mut allowed: Vec<u8> = g_fine
        .iter()
        .map(|&g| if g <= threshold { 0 } else { max_level })
        .collect();
    // Fine cells found in contact or interpenetrating in any round stay
    // fine, so the loop cannot cycle.
    let mut kept = vec![false; nx * ny];

    let mut total = SolveInfo {
        iterations: 0,
        matvecs: 0,
        residual: f64::INFINITY,
        load_error: 0.0,
        history: vec![],
        contact_history: vec![],
        ..SolveInfo::default()
    };
    let mut unknowns_history = vec![];
    let mut marked_count = 0;
    let mut previous: Option<(QuadMesh, ContactSolution)> = None;
    // Rounds that still move the mesh need no tight solve; the settled mesh
    // is solved once more at the requested tolerance and certified again.
    let mut round_tolerance = tolerance.max(LOOSE_TOLERANCE);
    let mut certifier = Certifier::new(nx, ny);
    for round in 1..=params.max_rounds {
        let mesh = QuadMesh::from_levels(nx, ny, a, max_level, &allowed)?;
        unknowns_history.push(mesh.len());
        let g_mesh = mesh.restrict_gap(g_fine);
        let start = previous
            .as_ref()
            .map(|(old, sol)| transfer(old, sol, &mesh));
        let (sol, info) = solve_on_mesh(&mesh, &g_mesh, start.as_ref(), round_tolerance)?;
        total.iterations += info.iterations;
        total.matvecs += info.matvecs;
        total.residual = info.residual;
        total.load_error = info.load_error;
        total.history.extend(&info.history);
        total.contact_history.extend(&info.contact_history);

        // Certificate on the fine cells of the coarse cells.
        let fine_in_coarse = mesh.fine_cells_in_coarse();
        let u_c = certifier.displacement(&tables, &mesh, &sol.pressure, &fine_in_coarse);
        let delta = sol.approach;
        let u_scale = sol.displacement.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let thr = penetration_threshold(round_tolerance, delta, u_scale);
        let mut new = vec![false; nx * ny];
        marked_count = 0;
        for (&f, &u) in fine_in_coarse.iter().zip(&u_c) {
            if g_fine[f] - delta + u < thr {
                new[f] = true;
                marked_count += 1;
            }
        }
        let coarse_contact: Vec<usize> = (0..mesh.len())
            .filter(|&k| mesh.cells[k].level > 0 && sol.pressure[k] > 0.0)
            .collect();
        marked_count += coarse_contact.len();
        if marked_count == 0 && round_tolerance > tolerance {
            round_tolerance = tolerance;
            previous = Some((mesh, sol));
            continue;
        }
        if marked_count == 0 {
            let solution = fine_fields(&mesh, &sol, g_fine, &fine_in_coarse, &u_c);
            let report = MeshReport {
                unknowns: mesh.len(),
                fine_cells: nx * ny,
                level_counts: mesh.level_counts(),
                rounds: round,
                unknowns_history,
                table_bytes: tables.bytes(),
            };
            return Ok(AdaptiveSolution {
                solution,
                info: total,
                mesh,
                report,
            });
        }
        // Next mesh: fine around the contact found and every penetration so
        // far; a coarse cell in contact splits one level; the rest coarsens.
        for (p, n) in kept.iter_mut().zip(&new) {
            *p |= *n;
        }
        for (k, c) in mesh.cells.iter().enumerate() {
            if c.level == 0 && sol.contact[k] > 0.5 {
                kept[c.i as usize * ny + c.j as usize] = true;
            }
        }
        // A coarse cell in contact touches at its highest point: refine there.
        for &k in &coarse_contact {
            let (xr, yr) = mesh.cells[k].fine_ranges();
            let mut best = (f64::INFINITY, 0);
            for ix in xr {
                for iy in yr.clone() {
                    let f = ix * ny + iy;
                    if g_fine[f] < best.0 {
                        best = (g_fine[f], f);
                    }
                }
            }
            kept[best.1] = true;
        }
        allowed = dilate(&kept, nx, ny, params.margin)
            .iter()
            .map(|&f| if f { 0 } else { max_level })
            .collect();
        previous = Some((mesh, sol));
    }
    Err(AdaptiveError::NotSettled {
        rounds: params.max_rounds,
        marked: marked_count,
    })
}

/// Solver tolerance of the rounds that still move the mesh.
const LOOSE_TOLERANCE: f64 = 1e-5;

/// The full-resolution displacement at the fine cells of coarse cells:
/// pairwise from the level tables, or, when that would cost more than one
/// zero-padded FFT product on the fine grid, by the uniform grid's Toeplitz
/// operator applied to the mesh pressure spread over the fine cells (the
/// same sums: a coarse cell's uniform pressure is its fine cells').
struct Certifier {
    nx: usize,
    ny: usize,
    fft: Option<ToeplitzFft>,
    /// Pair evaluations worth one point-level of the padded FFT.
    fft_cost: f64,
}

impl Certifier {
    fn new(nx: usize, ny: usize) -> Self {
        Self {
            nx,
            ny,
            fft: None,
            fft_cost: FFT_COST_PER_POINT,
        }
    }

    fn displacement(
        &mut self,
        tables: &Arc<LevelTables>,
        mesh: &QuadMesh,
        x: &[f64],
        fine: &[usize],
    ) -> Vec<f64> {
        let (nx, ny) = (self.nx, self.ny);
        let nnz = x.iter().filter(|&&v| v != 0.0).count();
        let pairs = fine.len() as f64 * nnz as f64;
        let padded = (4 * nx * ny) as f64;
        if pairs <= self.fft_cost * padded * padded.log2() {
            return AdaptiveOperator::new(tables.clone(), mesh).displacement_at_fine(x, fine);
        }
        let op = self.fft.get_or_insert_with(|| {
            let table = tables.uniform_table();
            ToeplitzFft::new(OffsetTable {
                nx,
                ny,
                values: &table,
            })
        });
        let mut p = vec![0.0; nx * ny];
        for (k, c) in mesh.cells.iter().enumerate() {
            if x[k] == 0.0 {
                continue;
            }
            let share = x[k] / (c.span() * c.span()) as f64;
            let (xr, yr) = c.fine_ranges();
            for ix in xr {
                for iy in yr.clone() {
                    p[ix * ny + iy] = share;
                }
            }
        }
        let mut u = vec![0.0; nx * ny];
        op.apply(&p, &mut u);
        fine.iter().map(|&f| u[f]).collect()
    }
}

/// Pair evaluations that cost as much as one point and log2-level of the
/// padded FFT product (measured on 2 cores at 1024^2: 0.5 ns per pair,
/// 0.23 ns per point-level for a forward and an inverse transform).
const FFT_COST_PER_POINT: f64 = 0.5;

/// A warm start on the refined mesh `new` from the solution `sol` on `old`:
/// cells that were fine keep their state; fine cells of a coarse cell that
/// was in contact start in contact with its pressure; the rest start open.
fn transfer(old: &QuadMesh, sol: &ContactSolution, new: &QuadMesh) -> WarmStart {
    let mut contact = vec![0.0; new.len()];
    let mut pressure = vec![0.0; new.len()];
    for (k, c) in new.cells.iter().enumerate() {
        if c.level != 0 {
            continue;
        }
        let (ix, iy) = (c.i as usize, c.j as usize);
        let o = old.owner(ix, iy);
        let span = old.cells[o].span() as f64;
        if sol.contact[o] > 0.5 && sol.pressure[o] > 0.0 {
            contact[k] = 1.0;
            // Unknowns are forces in fine-cell units: share the coarse one.
            pressure[k] = sol.pressure[o] / (span * span);
        }
    }
    if contact.iter().all(|&m| m <= 0.5) {
        // Nothing carried over (cannot happen after a converged solve, which
        // always has contact); fall back to the fresh guess via a tiny set.
        if let Some(k) = (0..new.len()).find(|&k| new.cells[k].level == 0) {
            contact[k] = 1.0;
        }
    }
    WarmStart {
        contact,
        pressure,
        approach: sol.approach,
    }
}

/// The mesh solution as fine-grid fields.
fn fine_fields(
    mesh: &QuadMesh,
    sol: &ContactSolution,
    g_fine: &[f64],
    fine_in_coarse: &[usize],
    u_coarse: &[f64],
) -> ContactSolution {
    let (nx, ny) = (mesh.nx, mesh.ny);
    let n = nx * ny;
    let mut pressure = vec![0.0; n];
    let mut displacement = vec![0.0; n];
    let mut contact = vec![0.0; n];
    for ix in 0..nx {
        for iy in 0..ny {
            let k = mesh.owner(ix, iy);
            if mesh.cells[k].level == 0 {
                let f = ix * ny + iy;
                pressure[f] = sol.pressure[k];
                displacement[f] = sol.displacement[k];
                contact[f] = sol.contact[k];
            }
        }
    }
    for (&f, &u) in fine_in_coarse.iter().zip(u_coarse) {
        displacement[f] = u;
    }
    let gap = g_fine
        .iter()
        .zip(&displacement)
        .map(|(g, u)| g - sol.approach + u)
        .collect();
    ContactSolution {
        pressure,
        displacement,
        gap,
        contact,
        approach: sol.approach,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kernel::SlidingKernel;
    use crate::material::{CreepSpectrum, Material};
    use crate::response::SlidingResponse;

    /// The FFT route of the certificate gives the pairwise sums, coarse
    /// sources included (1e-12 relative: both are exact up to round-off).
    #[test]
    fn certificate_routes_agree() {
        let m = Material::new(
            CreepSpectrum::standard_linear_solid(1e7 / 3.0, 1e7, 0.01).unwrap(),
            0.5,
        )
        .unwrap();
        let k = SlidingKernel::new(&SlidingResponse::new(&m, 2e-2, 0.0, None).unwrap()).unwrap();
        let (nx, ny, a) = (40usize, 28usize, 1e-4);
        let tables = Arc::new(LevelTables::new(&k, nx, ny, a, 3).unwrap());
        let mut fine = vec![false; nx * ny];
        for f in [3 * ny + 4, 20 * ny + 9, 33 * ny + 25] {
            fine[f] = true;
        }
        let mesh = QuadMesh::from_mask(nx, ny, a, 3, &fine).unwrap();
        let x: Vec<f64> = (0..mesh.len())
            .map(|i| {
                if i % 4 == 1 {
                    0.0
                } else {
                    1.0 + (i % 7) as f64
                }
            })
            .collect();
        let cells = mesh.fine_cells_in_coarse();
        let mut pairwise = Certifier::new(nx, ny);
        pairwise.fft_cost = f64::INFINITY;
        let mut fft = Certifier::new(nx, ny);
        fft.fft_cost = 0.0;
        let u1 = pairwise.displacement(&tables, &mesh, &x, &cells);
        let u2 = fft.displacement(&tables, &mesh, &x, &cells);
        assert!(fft.fft.is_some() && pairwise.fft.is_none());
        let num: f64 = u1.iter().zip(&u2).map(|(p, q)| (p - q).powi(2)).sum();
        let den: f64 = u1.iter().map(|p| p * p).sum();
        assert!((num / den).sqrt() < 1e-12, "{:.2e}", (num / den).sqrt());
    }
}
