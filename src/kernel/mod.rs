//! Influence coefficients of the steady-sliding viscoelastic Green's function
//! (paper Eq. 4-6; physics.md section 3).
//!
//! For a source rectangle `ax x ay` centred at the origin carrying unit
//! uniform pressure, the normal displacement at offset `d` is
//!
//! `K(d) = (1-nu^2)/pi [ (1/E_inf) Theta(|d|/h) L(d) + int_0^inf ds phi(s) Theta(|d + s e_v|/h) L(d + s e_v) ]`
//!
//! for a half-space, with `L` Love's integral of `1/r` over the rectangle
//! ([`love`]) and `phi(s) = sum_k (C_k / (v tau_k)) exp(-s / (v tau_k))`
//! ([`mod@line`]). On a layer (Eq. 5), `L` becomes the cell integral `M` of
//! `Theta(r/h) / r` ([`cell`]; [`thickness`] for `Theta`), at the target
//! and along the sliding trail alike; [`ThetaRule::Collocation`] keeps the
//! paper's Eq. 6 (`Theta` at the centre-to-point distance times `L`).
//! The material remembers the pressure it met ahead (`+v`): at `v > 0` the
//! trailing neighbour (`-e_v`) gets the larger coefficient.
//!
//! The friction stencil (physics.md section 5) uses the cell-averaged
//! derivative `D_x(d) = (1/a_x) [Kbar(d_x + a_x/2, d_y) - Kbar(d_x - a_x/2, d_y)]`,
//! `Kbar(x, y) = (1/a_y) int K(x, y + t) dt` over the target cell's width, so
//! that `a^2 sum_i p_i sum_k D_x(i - k) p_k = int p du/dx dA` exactly for
//! piecewise-constant pressure ([`SlidingKernel::derivative`]).

mod average;
pub mod cell;
pub mod line;
pub mod love;
mod march;
pub mod progress;
pub mod quad;
mod table;
pub mod thickness;
mod thin;
mod thin_band;
mod thin_cross;
mod thin_law;
mod thin_oblique;
mod window;
pub use thin::THIN_RATIO_MIN;
pub use thin_band::BAND_RATIO_MAX;
pub use thin_law::thin_series;

use std::sync::Arc;

pub use cell::ThetaRule;
pub use table::{CoefficientTable, VertexTable};
pub use thickness::ThetaTable;

use crate::response::{Grid, ResponseError, SlidingResponse};
use cell::LayerCell;
use line::{memory_integral, KinkLine, LineProblem};
use love::LoveRect;

/// Errors evaluating influence coefficients; each names the offending value.
#[derive(Debug, thiserror::Error)]
pub enum KernelError {
    #[error("{0}")]
    Invalid(String),
    #[error(transparent)]
    Response(#[from] ResponseError),
}

/// An influence coefficient [m/Pa], split into the instantaneous (`1/E_inf`)
/// part and the memory (creep spectrum) part of Eq. 4.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Coefficient {
    pub elastic: f64,
    pub viscoelastic: f64,
}

impl Coefficient {
    /// Both parts NaN: the coefficient where the kernel is not defined
    /// (invalid cell sizes; off the lattice of the local thin-layer limit).
    pub(crate) const NAN: Coefficient = Coefficient {
        elastic: f64::NAN,
        viscoelastic: f64::NAN,
    };

    /// `elastic + viscoelastic` [m/Pa].
    pub fn total(&self) -> f64 {
        self.elastic + self.viscoelastic
    }
}

/// Axis of a cell-averaged derivative.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Axis {
    X,
    Y,
}

/// The steady-sliding kernel of Eq. 4-6 for one [`SlidingResponse`]
/// (material, speed, direction, layer): plan once, evaluate many
/// coefficients.
#[derive(Debug, Clone)]
pub struct SlidingKernel {
    /// `(1 - nu^2) / pi`.
    prefactor: f64,
    /// `1/E_inf` [1/Pa].
    glassy: f64,
    /// `(C_k, l_k = v tau_k)`; `l_k = 0` at `v = 0`, `inf` at `v = inf`.
    terms: Vec<(f64, f64)>,
    response: SlidingResponse,
    e: (f64, f64),
    theta: Option<Arc<ThetaTable>>,
    rule: ThetaRule,
    /// Whether layers far below a cell take the local limit ([`thin`]) and
    /// its law's continuation (`kernel/thin_band.rs`).
    local: bool,
}

/// A source cell's precomputed pieces: Love's rectangle and, on a layer with
/// [`ThetaRule::CellIntegral`], the cell rules of `psi`.
#[derive(Debug, Clone)]
pub(crate) struct Cell {
    pub(crate) love: LoveRect,
    pub(crate) layer: Option<LayerCell>,
    /// The local limit of a layer much thinner than the cell ([`thin`]).
    pub(crate) thin: Option<Arc<thin::ThinProfile>>,
    /// The thin-layer law continued above the local limit (`kernel/thin_band.rs`).
    pub(crate) band: Option<Arc<thin_band::BandStencil>>,
}

/// Relative tolerance asked of the adaptive line integrals on a half-space.
const TOL: f64 = 1e-14;
/// The same on a layer: the cell rules of `psi` ([`cell`]) carry ~1e-13,
/// so asking more only multiplies panels.
const LAYER_TOL: f64 = 1e-12;

impl SlidingKernel {
    /// Plan the kernel of `response`: tabulates the layer's `Theta`.
    pub fn new(response: &SlidingResponse) -> Result<Self, KernelError> {
        let theta = match response.layer() {
            Some(layer) => Some(Arc::new(ThetaTable::new(layer, response.poisson())?)),
            None => None,
        };
        Ok(Self {
            prefactor: response.prefactor(),
            glassy: response.glassy_compliance(),
            terms: response.creep_lengths(1.0),
            e: response.direction(),
            response: response.clone(),
            theta,
            rule: ThetaRule::default(),
            local: true,
        })
    }

    /// The same kernel with `Theta` entering by `rule` (default
    /// [`ThetaRule::CellIntegral`]; no effect on a half-space).
    pub fn with_theta_rule(mut self, rule: ThetaRule) -> Self {
        self.rule = rule;
        self
    }

    /// The same kernel without the local limit of layers far below a cell
    /// nor the thin-layer law's continuation above it (`kernel/thin_band.rs`): the
    /// general cell integral at every thickness (the reference of the
    /// local limit's tests, slow and memory-hungry for very thin layers).
    pub fn without_local_limit(mut self) -> Self {
        self.local = false;
        self
    }

    /// How `Theta` enters the coefficients.
    pub fn theta_rule(&self) -> ThetaRule {
        self.rule
    }

    /// The layer's `Theta`, if any.
    pub fn theta(&self) -> Option<&ThetaTable> {
        self.theta.as_deref()
    }

    /// A source cell `ax x ay` with its rules.
    pub(crate) fn cell(&self, ax: f64, ay: f64) -> Cell {
        let thin = self.thin_profile(ax, ay);
        let band = match thin {
            None => self.band_stencil(ax, ay).map(Arc::new),
            Some(_) => None,
        };
        let layer = match (&self.theta, self.rule) {
            (Some(t), ThetaRule::CellIntegral) if thin.is_none() && band.is_none() => {
                Some(LayerCell::new(t, ax, ay))
            }
            _ => None,
        };
        Cell {
            love: LoveRect::new(ax, ay),
            layer,
            thin,
            band,
        }
    }

    /// Thickness in units of `a` below which the row march of the tables
    /// does not converge (`None`: it always does).
    pub(crate) fn thin_limit(&self) -> Option<f64> {
        match (&self.theta, self.rule) {
            (None, _) => None,
            // psi is analytic within 2h of a row: 8-point rules on one-cell
            // panels keep ~1e-10 down to h = a/2.
            (Some(_), ThetaRule::CellIntegral) => Some(0.5),
            // Theta(|x|/h) has a branch point at distance |y| from the row.
            (Some(_), ThetaRule::Collocation) => Some(4.0),
        }
    }

    /// The response this kernel was planned for.
    pub fn response(&self) -> &SlidingResponse {
        &self.response
    }

    /// Unit sliding direction `e_v`.
    pub fn direction(&self) -> (f64, f64) {
        self.e
    }

    /// The spatial factor of Eq. 4-6 for the source `cell` at the point
    /// `(x, y)` \[m\]: `L` on a half-space, the cell integral `M` of
    /// `Theta L` on a layer, or `Theta(r/h) L` by collocation.
    pub(crate) fn spatial<'a>(&'a self, cell: &'a Cell) -> impl Fn(f64, f64) -> f64 + 'a {
        move |x, y| match (&cell.layer, &self.theta) {
            (Some(lc), _) => {
                if lc.beyond(x, y, 0.0, 0.0) {
                    0.0
                } else if lc.is_polar() {
                    lc.cell_integral(x, y)
                } else {
                    cell.love.eval(x, y) + lc.psi_part(x, y)
                }
            }
            (None, Some(t)) => t.at_distance(x.hypot(y)) * cell.love.eval(x, y),
            (None, None) => cell.love.eval(x, y),
        }
    }

    /// Whether the coefficient at `(dx, dy)` vanishes because neither the
    /// target nor its sliding trail comes within the reach of `Theta`.
    fn out_of_reach(&self, cell: &Cell, dx: f64, dy: f64, margin: f64) -> bool {
        let Some(lc) = &cell.layer else { return false };
        let (ex, ey) = self.e;
        // Closest point of the trail d + s e_v (s >= 0) to the cell centre.
        let s = (-(dx * ex + dy * ey)).max(0.0);
        let (px, py) = (dx + s * ex, dy + s * ey);
        let half_diag = 0.5 * cell.love.ax.hypot(cell.love.ay);
        px.hypot(py) > lc.reach() + half_diag + margin
    }

    /// `K(d)` at point offset `(dx, dy)` \[m\] from the centre of a source
    /// rectangle `ax x ay` \[m\] carrying unit pressure (Eq. 4/6) [m/Pa].
    /// Invalid cell sizes give NaN; see [`Self::try_coefficient`].
    pub fn coefficient(&self, dx: f64, dy: f64, ax: f64, ay: f64) -> Coefficient {
        self.try_coefficient(dx, dy, ax, ay)
            .unwrap_or(Coefficient::NAN)
    }

    /// [`Self::coefficient`] with the cell size checked.
    pub fn try_coefficient(
        &self,
        dx: f64,
        dy: f64,
        ax: f64,
        ay: f64,
    ) -> Result<Coefficient, KernelError> {
        Grid::new(1, 1, (ax, ay))?;
        Ok(self.coefficient_with(&self.cell(ax, ay), dx, dy))
    }

    pub(crate) fn coefficient_with(&self, cell: &Cell, dx: f64, dy: f64) -> Coefficient {
        if let Some(p) = &cell.thin {
            return self.thin_coefficient(p, cell, dx, dy);
        }
        if let Some(b) = &cell.band {
            return self.band_coefficient(b, cell.love.ax, cell.love.ay, dx, dy);
        }
        if self.out_of_reach(cell, dx, dy, 0.0) {
            return Coefficient::default();
        }
        let f = self.spatial(cell);
        let rect = &cell.love;
        let (ax, ay) = (rect.ax, rect.ay);
        let f0 = f(dx, dy);
        let kinks = cell_kinks(ax, ay);
        let scale = rect.eval(dx, dy) * self.total_compliance();
        let problem = LineProblem {
            d: (dx, dy),
            e: self.e,
            terms: &self.terms,
            a_min: ax.min(ay),
            a_max: ax.max(ay),
            kinks: &kinks,
            abs_tol: self.tol() * scale,
            rel_tol: self.tol(),
        };
        let mem = memory_integral(&problem, &f);
        Coefficient {
            elastic: self.prefactor * self.glassy * f0,
            viscoelastic: self.prefactor * mem,
        }
    }

    /// Cell-averaged derivative `D_x` or `D_y` [1/Pa] at offset `(dx, dy)`
    /// (physics.md section 5): the target cell has the source's size.
    /// Invalid cell sizes give NaN.
    pub fn derivative(&self, dx: f64, dy: f64, ax: f64, ay: f64, axis: Axis) -> f64 {
        if Grid::new(1, 1, (ax, ay)).is_err() {
            return f64::NAN;
        }
        self.derivative_with(&self.cell(ax, ay), dx, dy, axis)
    }

    pub(crate) fn derivative_with(&self, cell: &Cell, dx: f64, dy: f64, axis: Axis) -> f64 {
        if let Some(p) = &cell.thin {
            return self.thin_derivative(p, cell, dx, dy, axis);
        }
        if let Some(b) = &cell.band {
            // The work on the cell edges, as the law's (`thin_law`).
            return self.band_derivative(b, (cell.love.ax, cell.love.ay), (dx, dy), axis);
        }
        let (ax, ay) = (cell.love.ax, cell.love.ay);
        match axis {
            Axis::X => {
                (self.kbar(cell, dx + 0.5 * ax, dy, Axis::X)
                    - self.kbar(cell, dx - 0.5 * ax, dy, Axis::X))
                    / ax
            }
            Axis::Y => {
                (self.kbar(cell, dx, dy + 0.5 * ay, Axis::Y)
                    - self.kbar(cell, dx, dy - 0.5 * ay, Axis::Y))
                    / ay
            }
        }
    }

    /// Relative tolerance of the adaptive integrals.
    pub(crate) fn tol(&self) -> f64 {
        if self.theta.is_some() {
            LAYER_TOL
        } else {
            TOL
        }
    }

    /// Relative tolerance of the width averages' line integrals (the
    /// friction stencil's `Kbar`) on `a_x x a_y` cells: [`Self::tol`] times
    /// the squared aspect ratio. The closed-form width average of Love's
    /// integral ([`love::LoveRect::near_y_integral`]) cancels like
    /// `eps r^3 / (a_min^2 a_max)` out to the switch radius `~3 a_max`, so
    /// its round-off grows with the square of the aspect ratio; asking
    /// less of the adaptive rule only spends its whole panel budget on
    /// every target (a 32^2 pad of 10:1 cells spent 28 s there, one of
    /// 100:1 hours). Square cells keep [`Self::tol`].
    pub(crate) fn average_tol(&self, (ax, ay): (f64, f64)) -> f64 {
        let r = ax.max(ay) / ax.min(ay);
        self.tol() * r * r
    }

    /// `(1/E_inf) + sum_k C_k` [1/Pa].
    fn total_compliance(&self) -> f64 {
        self.glassy + self.terms.iter().map(|t| t.0).sum::<f64>()
    }

    /// `Kbar` [m/Pa]: `K` averaged across the target cell's width transverse
    /// to `axis`, at the point `(x, y)`.
    pub(super) fn kbar(&self, cell: &Cell, x: f64, y: f64, axis: Axis) -> f64 {
        let (ax, ay) = (cell.love.ax, cell.love.ay);
        if self.out_of_reach(cell, x, y, ax.max(ay)) {
            return 0.0;
        }
        let fbar = |px: f64, py: f64| self.transverse_average(cell, px, py, axis);
        let mut kinks = cell_kinks(ax, ay).to_vec();
        match axis {
            Axis::X => kinks.extend([KinkLine::Y(-ay), KinkLine::Y(0.0), KinkLine::Y(ay)]),
            Axis::Y => kinks.extend([KinkLine::X(-ax), KinkLine::X(0.0), KinkLine::X(ax)]),
        }
        let f0 = fbar(x, y);
        // On a layer the average may vanish where the trail still meets the
        // source: take the half-space's scale there.
        let local = match cell.layer {
            Some(_) => f0.abs().max(cell.love.eval(x, y)),
            None => f0.abs(),
        };
        let scale = local * self.total_compliance();
        let problem = LineProblem {
            d: (x, y),
            e: self.e,
            terms: &self.terms,
            a_min: ax.min(ay),
            a_max: ax.max(ay),
            kinks: &kinks,
            abs_tol: self.average_tol((ax, ay)) * scale,
            rel_tol: self.average_tol((ax, ay)),
        };
        let mem = memory_integral(&problem, fbar);
        self.prefactor * (self.glassy * f0 + mem)
    }

    /// Table of `K` over all `(2nx-1) x (2ny-1)` offsets of `grid` (rayon).
    /// Uses the row march when `e_v` is along a grid axis (see the `table`
    /// module docs), per-offset evaluation otherwise. Refuses a table that
    /// does not fit in memory, cells outside the range its arithmetic holds
    /// (1.5e-154 m to 1.3e154 m), and a table with a value that is not
    /// finite: each refusal names the cell size.
    pub fn table(&self, grid: &Grid) -> Result<CoefficientTable, KernelError> {
        check_grid(grid)?;
        all_finite(table::build(self, grid, None, false), "K")
    }

    /// Table of the cell-averaged derivative `D_x` or `D_y` [1/Pa] over all
    /// offsets (same layout as [`Self::table`]). Fast when `axis` is the
    /// sliding axis; per-offset otherwise. Refused as [`Self::table`] is.
    pub fn derivative_table(
        &self,
        grid: &Grid,
        axis: Axis,
    ) -> Result<CoefficientTable, KernelError> {
        check_grid(grid)?;
        let name = match axis {
            Axis::X => "dK/dx",
            Axis::Y => "dK/dy",
        };
        all_finite(table::build(self, grid, Some(axis), false), name)
    }

    /// [`VertexTable`]: `K` at the corner offsets `((i + 1/2) a, (j + 1/2) a)`
    /// of `grid`, by the row march where [`Self::table`] uses it. The
    /// adaptive mesh's level tables need square cells: rectangular ones are
    /// refused.
    pub fn vertex_table(&self, grid: &Grid) -> Result<VertexTable, KernelError> {
        if !grid.is_square() {
            let (ax, ay) = grid.cell();
            return Err(KernelError::Invalid(format!(
                "the vertex table of the adaptive mesh needs square cells, not {ax} x {ay} m"
            )));
        }
        check_grid(grid)?;
        let (nx, ny) = grid.size();
        Ok(table::build_vertex(self, nx, ny, grid.cell().0))
    }

    /// The reference per-offset table of `K` (`derivative = None`) or of
    /// `D_x`/`D_y` (no fast path), for tests and for directions off the grid
    /// axes.
    pub fn table_per_offset(&self, grid: &Grid, derivative: Option<Axis>) -> CoefficientTable {
        table::build(self, grid, derivative, true)
    }
}

/// `table` if every value is finite, else the first that is not, named
/// ([`non_finite`]).
fn all_finite(table: CoefficientTable, name: &str) -> Result<CoefficientTable, KernelError> {
    let Some(k) = table.values.iter().position(|v| !v.is_finite()) else {
        return Ok(table);
    };
    let row = 2 * table.ny - 1;
    let offset = (
        (k / row) as i64 - (table.nx as i64 - 1),
        (k % row) as i64 - (table.ny as i64 - 1),
    );
    Err(non_finite(
        name,
        offset,
        table.values[k],
        (table.cell_size, table.cell_size_y),
    ))
}

/// The cell sides `(ax, ay)` \[m\] as a refusal names them.
fn cells_named((ax, ay): (f64, f64)) -> String {
    if ax == ay {
        format!("the cell size {ax:e} m")
    } else {
        format!("the cell size {ax:e} x {ay:e} m")
    }
}

/// The cell sides the kernel's arithmetic holds for
/// ([`crate::response::CELL_SIDE_RANGE`]).
pub(crate) fn check_cell_range((ax, ay): (f64, f64)) -> Result<(), KernelError> {
    let (lo, hi) = crate::response::CELL_SIDE_RANGE;
    if [ax, ay].iter().all(|a| (lo..=hi).contains(a)) {
        return Ok(());
    }
    Err(KernelError::Invalid(format!(
        "{} is beyond the range of the kernel's arithmetic (cells of {lo:.3e} m to {hi:.3e} m, whose squares f64 holds); give cells nearer the contact's scales",
        cells_named((ax, ay))
    )))
}

/// A coefficient `name` at cell `offset` that came out `value`, not finite,
/// on cells `cell` \[m\] within [`check_cell_range`]: a distance whose
/// square leaves f64's range (an offset far across a grid of huge cells).
/// The refusal names the cell size.
pub(crate) fn non_finite(
    name: &str,
    offset: (i64, i64),
    value: f64,
    cell: (f64, f64),
) -> KernelError {
    KernelError::Invalid(format!(
        "{} is beyond the range of the kernel's arithmetic: {name} at offset ({}, {}) comes out {value}; give cells nearer the contact's scales",
        cells_named(cell),
        offset.0, offset.1
    ))
}

/// Bytes per entry of a table: the value and as much again of work space
/// (the row march's rows, the per-offset evaluation's chunks).
const TABLE_BYTES_PER_OFFSET: u64 = 16;

/// The grid's cells within [`check_cell_range`], and the table of its `2
/// nx x 2 ny` offsets (with checked arithmetic) fits in the memory
/// available ([`crate::io::memory`]).
fn check_grid(grid: &Grid) -> Result<(), KernelError> {
    check_cell_range(grid.cell())?;
    let (nx, ny) = grid.size();
    let offsets = (2 * nx as u64).saturating_mul(2 * ny as u64);
    crate::io::memory::check_count(
        || format!("coefficient table of {nx} x {ny} cells"),
        offsets,
        TABLE_BYTES_PER_OFFSET,
    )
    .map_err(|e| KernelError::Invalid(e.to_string()))
}

/// Lines on which the spatial factor of an `ax x ay` source cell has kinks:
/// its edges.
fn cell_kinks(ax: f64, ay: f64) -> [KinkLine; 4] {
    [
        KinkLine::X(-0.5 * ax),
        KinkLine::X(0.5 * ax),
        KinkLine::Y(-0.5 * ay),
        KinkLine::Y(0.5 * ay),
    ]
}

pub(crate) fn gl4() -> &'static (Vec<f64>, Vec<f64>) {
    static GL: std::sync::OnceLock<(Vec<f64>, Vec<f64>)> = std::sync::OnceLock::new();
    GL.get_or_init(|| quad::gauss_legendre(4))
}

pub(crate) fn gl10() -> &'static (Vec<f64>, Vec<f64>) {
    static GL: std::sync::OnceLock<(Vec<f64>, Vec<f64>)> = std::sync::OnceLock::new();
    GL.get_or_init(|| quad::gauss_legendre(10))
}
