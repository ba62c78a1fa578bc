//! Resolution of a discretised problem and the transfer of a solution to a
//! finer grid: what a refinement study (coarse to fine) needs from the
//! library API.

use crate::config::Formulation;
use crate::error::{Error, Result};
use crate::solver::{Control, WarmStart};

use super::{highest, Problem, Solution, SurfaceSource};

/// Below this many cells per shortest roughness wavelength a solve warns
/// (console and `summary.json`): the finest scales of the surface are not
/// resolved and friction and area still change under refinement.
pub(crate) const MIN_CELLS_PER_WAVELENGTH: f64 = 4.0;

/// Where the shortest roughness wavelength of a problem comes from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ShortestWavelength {
    /// A generated surface: `2 pi / q1`, its upper cut-off \[m\].
    UpperCutoff(f64),
    /// A surface read from a file or given as values: its spectrum is not
    /// known, so its shortest wavelength is taken to be the grid's Nyquist
    /// wavelength, two cells \[m\].
    Nyquist(f64),
}

impl ShortestWavelength {
    /// The wavelength \[m\].
    pub fn length(self) -> f64 {
        match self {
            ShortestWavelength::UpperCutoff(l) | ShortestWavelength::Nyquist(l) => l,
        }
    }
}

impl Problem {
    /// The shortest roughness wavelength of the surface: `2 pi / q1` for a
    /// generated surface, the grid's Nyquist wavelength (2 cells) for a
    /// surface read from a file or given as values, `None` for a sphere
    /// (no roughness). On rectangular cells the grid's Nyquist wavelength
    /// is that of the longer side.
    pub fn shortest_wavelength(&self) -> Option<ShortestWavelength> {
        let a = self.coarser_cell_side();
        match &self.source {
            SurfaceSource::Generated(p) => p
                .resolve()
                .ok()
                .map(|psd| ShortestWavelength::UpperCutoff(std::f64::consts::TAU / psd.q1)),
            SurfaceSource::Synthesised { table, params, .. }
                if params.highest_q(table) < std::f64::consts::PI / a =>
            {
                Some(ShortestWavelength::UpperCutoff(
                    std::f64::consts::TAU / params.highest_q(table),
                ))
            }
            SurfaceSource::File(_) | SurfaceSource::Given | SurfaceSource::Synthesised { .. } => {
                Some(ShortestWavelength::Nyquist(2.0 * a))
            }
            SurfaceSource::Sphere(_) => None,
        }
    }

    /// Cells per shortest wavelength: the shortest roughness wavelength of
    /// the surface ([`Problem::shortest_wavelength`]: `2 pi / q1` of a
    /// generated surface; for a surface read from a file or given as values
    /// the grid's Nyquist wavelength, so exactly 2) divided by the cell size
    /// `a`. It measures how well the finest scale of the roughness is
    /// resolved: 2 is the least a grid can carry, below
    /// 4 (`MIN_CELLS_PER_WAVELENGTH`) a solve warns. `None` for a sphere.
    pub fn cells_per_shortest_wavelength(&self) -> Option<f64> {
        self.shortest_wavelength()
            .map(|w| w.length() / self.coarser_cell_side())
    }

    /// The longer side of a cell \[m\]: the resolution of the coarser axis.
    pub(super) fn coarser_cell_side(&self) -> f64 {
        self.surface.cell_size.max(self.surface.cell_size_y)
    }

    /// The warning a solve of this problem carries about its resolution,
    /// if any.
    pub fn resolution_warning(&self) -> Option<String> {
        let w = self.shortest_wavelength()?;
        let cells = w.length() / self.coarser_cell_side();
        if cells >= MIN_CELLS_PER_WAVELENGTH {
            return None;
        }
        let what = match w {
            ShortestWavelength::UpperCutoff(l) => format!(
                "the shortest roughness wavelength 2 pi / q1 = {l:.4e} m spans {cells:.2} cells"
            ),
            ShortestWavelength::Nyquist(_) => {
                "the surface has no known spectrum (read from a file or given as values), so its shortest wavelength is taken as the grid's Nyquist wavelength, 2 cells".to_string()
            }
        };
        Some(format!(
            "{what}, below {MIN_CELLS_PER_WAVELENGTH}: the finest roughness is under-resolved and friction and contact area are not converged in the grid (check with `viscoslide refine`)"
        ))
    }

    /// A warm start for this problem from `solution` of `coarse`, the same
    /// physical problem on a coarser grid (see [`Problem::with_grid`]).
    ///
    /// - Approach: shifted by the change of the highest summit (`delta` is
    ///   measured from it), so that the rigid indenter keeps its position.
    /// - Contact set: the cells whose predicted gap
    ///   `g - delta + u` is `<= 0`, with the coarse displacement `u`
    ///   interpolated bilinearly to the fine cell centres (periodic
    ///   wrap-around for the periodic formulation): the fine roughness
    ///   decides which cells of a coarse contact spot touch, as in a cascade
    ///   multi-resolution identification of the contact domain.
    /// - Pressure: piecewise constant (each fine cell takes the pressure of
    ///   the coarse cell that contains its centre; 2 x 2 blocks for a grid
    ///   twice as fine) on that set, zero elsewhere, rescaled to the
    ///   prescribed load.
    ///
    /// Prolonging the coarse contact set itself (2 x 2 blocks) is a worse
    /// start than the solver's own guess: the contact area shrinks under
    /// refinement and every block holds cells that must leave.
    pub fn prolong(&self, coarse: &Problem, solution: &Solution) -> Result<WarmStart> {
        let (nxc, nyc) = solution.grid();
        if (nxc, nyc) != (coarse.surface.nx, coarse.surface.ny) {
            return Err(Error::Invalid(format!(
                "the solution is on a {nxc} x {nyc} grid, its problem on {} x {}",
                coarse.surface.nx, coarse.surface.ny
            )));
        }
        let (nx, ny) = (self.surface.nx, self.surface.ny);
        let (lx, ly) = (self.surface.length_x(), self.surface.length_y());
        let (lxc, lyc) = (coarse.surface.length_x(), coarse.surface.length_y());
        if (lx - lxc).abs() > 1e-9 * lx || (ly - lyc).abs() > 1e-9 * ly {
            return Err(Error::Invalid(format!(
                "prolongation needs the same domain: {lxc:.6e} x {lyc:.6e} m against {lx:.6e} x {ly:.6e} m"
            )));
        }
        let approach = solution.fields.approach + highest(&self.surface) - highest(&coarse.surface);
        let periodic = self.formulation == Formulation::Periodic;
        let u = bilinear(
            &solution.fields.displacement,
            (nxc, nyc),
            (nx, ny),
            periodic,
        );
        let g = self.gap_profile();
        let map = |i: usize, n: usize, nc: usize| ((2 * i + 1) * nc / (2 * n)).min(nc - 1);
        let mut pressure = vec![0.0; nx * ny];
        let mut contact = vec![0.0; nx * ny];
        for i in 0..nx {
            let ic = map(i, nx, nxc);
            for j in 0..ny {
                let c = i * ny + j;
                if g[c] - approach + u[c] <= 0.0 {
                    contact[c] = 1.0;
                    pressure[c] = solution.fields.pressure[ic * nyc + map(j, ny, nyc)];
                }
            }
        }
        if contact.iter().all(|&m| m < 0.5) {
            // The predicted set is empty (no coarse contact): take the
            // highest summit, the solver grows the set from there.
            let top = (0..g.len())
                .min_by(|&a, &b| g[a].total_cmp(&g[b]))
                .unwrap_or(0);
            contact[top] = 1.0;
        }
        if let Control::Load(f) = self.control {
            let carried = self.surface.cell_area() * pressure.iter().sum::<f64>();
            if carried > 0.0 {
                let s = f / carried;
                pressure.iter_mut().for_each(|p| *p *= s);
            }
        }
        Ok(WarmStart {
            contact,
            pressure,
            approach,
        })
    }
}

/// Bilinear interpolation of a cell-centred field from an `nxc x nyc` grid
/// to an `nx x ny` grid over the same domain (wrapping around when
/// `periodic`, clamped to the edge cells otherwise).
fn bilinear(
    f: &[f64],
    (nxc, nyc): (usize, usize),
    (nx, ny): (usize, usize),
    periodic: bool,
) -> Vec<f64> {
    let axis = |i: usize, n: usize, nc: usize| -> (usize, usize, f64) {
        let x = (i as f64 + 0.5) * nc as f64 / n as f64 - 0.5;
        let x0 = x.floor();
        let t = x - x0;
        let k0 = x0 as isize;
        let idx = |k: isize| -> usize {
            if periodic {
                k.rem_euclid(nc as isize) as usize
            } else {
                k.clamp(0, nc as isize - 1) as usize
            }
        };
        (idx(k0), idx(k0 + 1), t)
    };
    let mut out = vec![0.0; nx * ny];
    for i in 0..nx {
        let (i0, i1, s) = axis(i, nx, nxc);
        for j in 0..ny {
            let (j0, j1, t) = axis(j, ny, nyc);
            let v = |a: usize, b: usize| f[a * nyc + b];
            out[i * ny + j] = (1.0 - s) * ((1.0 - t) * v(i0, j0) + t * v(i0, j1))
                + s * ((1.0 - t) * v(i1, j0) + t * v(i1, j1));
        }
    }
    out
}
