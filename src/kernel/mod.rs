//! Influence coefficients of the steady-sliding viscoelastic Green's function
//! (paper Eq. 4-6; physics.md section 3).
//!
//! For a source rectangle `ax x ay` centred at the origin carrying unit
//! uniform pressure, the normal displacement at offset `d` is
//!
//! `K(d) = (1-nu^2)/pi [ (1/E_inf) Theta(|d|/h) L(d) + int_0^inf ds phi(s) Theta(|d + s e_v|/h) L(d + s e_v) ]`
//!
//! with `L` Love's integral of `1/r` over the rectangle ([`love`]),
//! `phi(s) = sum_k (C_k / (v tau_k)) exp(-s / (v tau_k))` ([`mod@line`]) and
//! `Theta` the thickness correction of Eq. 5 ([`thickness`]; `Theta = 1` for
//! a half-space), evaluated at the centre-to-point distance as in Eq. 6.
//! The material remembers the pressure it met ahead (`+v`): at `v > 0` the
//! trailing neighbour (`-e_v`) gets the larger coefficient.
//!
//! The friction stencil (physics.md section 5) uses the cell-averaged
//! derivative `D_x(d) = (1/a_x) [Kbar(d_x + a_x/2, d_y) - Kbar(d_x - a_x/2, d_y)]`,
//! `Kbar(x, y) = (1/a_y) int K(x, y + t) dt` over the target cell's width, so
//! that `a^2 sum_i p_i sum_k D_x(i - k) p_k = int p du/dx dA` exactly for
//! piecewise-constant pressure ([`SlidingKernel::derivative`]).

pub mod line;
pub mod love;
pub mod quad;
mod table;
pub mod thickness;

use std::sync::Arc;

pub use table::{CoefficientTable, VertexTable};
pub use thickness::{Layer, LayerBase, LayerConfig, ThetaTable};

use crate::material::Material;
use line::{memory_integral, KinkLine, LineProblem};
use love::LoveRect;

/// Errors evaluating influence coefficients; each names the offending value.
#[derive(Debug, thiserror::Error)]
pub enum KernelError {
    #[error("{0}")]
    Invalid(String),
}

/// Sliding parameters of a kernel (Eq. 4): speed, direction, optional layer.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KernelParams {
    /// Sliding speed `v` [m/s], `>= 0`; `0` is fully relaxed, `f64::INFINITY`
    /// fully glassy.
    pub speed: f64,
    /// In-plane angle of `e_v` from `+x` \[rad\].
    pub direction_rad: f64,
    /// Finite thickness (Eq. 5); `None` for a half-space.
    pub layer: Option<Layer>,
}

impl Default for KernelParams {
    fn default() -> Self {
        Self {
            speed: 0.0,
            direction_rad: 0.0,
            layer: None,
        }
    }
}

/// An influence coefficient [m/Pa], split into the instantaneous (`1/E_inf`)
/// part and the memory (creep spectrum) part of Eq. 4.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Coefficient {
    pub elastic: f64,
    pub viscoelastic: f64,
}

impl Coefficient {
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

/// The steady-sliding kernel of Eq. 4-6 for one (material, speed, layer):
/// plan once, evaluate many coefficients.
#[derive(Debug, Clone)]
pub struct SlidingKernel {
    /// `(1 - nu^2) / pi`.
    prefactor: f64,
    /// `1/E_inf` [1/Pa].
    glassy: f64,
    /// `(C_k, l_k = v tau_k)`; `l_k = 0` at `v = 0`, `inf` at `v = inf`.
    terms: Vec<(f64, f64)>,
    params: KernelParams,
    e: (f64, f64),
    theta: Option<Arc<ThetaTable>>,
}

/// Relative tolerance asked of the adaptive line integrals.
const TOL: f64 = 1e-14;

impl SlidingKernel {
    /// Plan a kernel: validates the speed and layer and tabulates `Theta`.
    pub fn new(material: &Material, params: KernelParams) -> Result<Self, KernelError> {
        if params.speed.is_nan() || params.speed < 0.0 {
            return Err(KernelError::Invalid(format!(
                "speed = {} m/s must be >= 0 (may be infinite)",
                params.speed
            )));
        }
        if !params.direction_rad.is_finite() {
            return Err(KernelError::Invalid(format!(
                "direction = {} rad must be finite",
                params.direction_rad
            )));
        }
        let theta = match params.layer {
            Some(layer) => Some(Arc::new(ThetaTable::new(layer, material.poisson)?)),
            None => None,
        };
        let v = params.speed;
        let terms = material
            .spectrum
            .terms
            .iter()
            .map(|t| {
                let l = if v.is_infinite() {
                    f64::INFINITY
                } else {
                    v * t.time
                };
                (t.compliance, l)
            })
            .collect();
        let (s, c) = params.direction_rad.sin_cos();
        // Snap directions along the axes so that 90 degrees is exactly +y.
        let snap = |x: f64| if x.abs() < 1e-15 { 0.0 } else { x };
        Ok(Self {
            prefactor: material.composite_factor() / std::f64::consts::PI,
            glassy: material.spectrum.glassy_compliance(),
            terms,
            params,
            e: (snap(c), snap(s)),
            theta,
        })
    }

    /// The parameters this kernel was planned for.
    pub fn params(&self) -> &KernelParams {
        &self.params
    }

    /// Unit sliding direction `e_v`.
    pub fn direction(&self) -> (f64, f64) {
        self.e
    }

    /// Check a cell size: positive and finite.
    pub fn check_cell(ax: f64, ay: f64) -> Result<(), KernelError> {
        for (name, a) in [("ax", ax), ("ay", ay)] {
            if !(a.is_finite() && a > 0.0) {
                return Err(KernelError::Invalid(format!(
                    "cell size {name} = {a} m must be positive and finite"
                )));
            }
        }
        Ok(())
    }

    fn spatial<'a>(&'a self, rect: &'a LoveRect) -> impl Fn(f64, f64) -> f64 + 'a {
        move |x, y| {
            let l = rect.eval(x, y);
            match &self.theta {
                Some(t) => t.at_distance(x.hypot(y)) * l,
                None => l,
            }
        }
    }

    /// `K(d)` at point offset `(dx, dy)` \[m\] from the centre of a source
    /// rectangle `ax x ay` \[m\] carrying unit pressure (Eq. 4/6) [m/Pa].
    /// Invalid cell sizes give NaN; see [`Self::try_coefficient`].
    pub fn coefficient(&self, dx: f64, dy: f64, ax: f64, ay: f64) -> Coefficient {
        self.try_coefficient(dx, dy, ax, ay).unwrap_or(Coefficient {
            elastic: f64::NAN,
            viscoelastic: f64::NAN,
        })
    }

    /// [`Self::coefficient`] with the cell size checked.
    pub fn try_coefficient(
        &self,
        dx: f64,
        dy: f64,
        ax: f64,
        ay: f64,
    ) -> Result<Coefficient, KernelError> {
        Self::check_cell(ax, ay)?;
        let rect = LoveRect::new(ax, ay);
        Ok(self.coefficient_with(&rect, dx, dy))
    }

    pub(crate) fn coefficient_with(&self, rect: &LoveRect, dx: f64, dy: f64) -> Coefficient {
        let f = self.spatial(rect);
        let (ax, ay) = (rect.ax, rect.ay);
        let f0 = f(dx, dy);
        let kinks = [
            KinkLine::X(-0.5 * ax),
            KinkLine::X(0.5 * ax),
            KinkLine::Y(-0.5 * ay),
            KinkLine::Y(0.5 * ay),
        ];
        let scale = rect.eval(dx, dy) * (self.glassy + self.terms.iter().map(|t| t.0).sum::<f64>());
        let problem = LineProblem {
            d: (dx, dy),
            e: self.e,
            terms: &self.terms,
            a_min: ax.min(ay),
            a_max: ax.max(ay),
            kinks: &kinks,
            abs_tol: TOL * scale,
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
        if Self::check_cell(ax, ay).is_err() {
            return f64::NAN;
        }
        let rect = LoveRect::new(ax, ay);
        self.derivative_with(&rect, dx, dy, axis)
    }

    pub(crate) fn derivative_with(&self, rect: &LoveRect, dx: f64, dy: f64, axis: Axis) -> f64 {
        let (ax, ay) = (rect.ax, rect.ay);
        match axis {
            Axis::X => {
                (self.kbar(rect, dx + 0.5 * ax, dy, Axis::X)
                    - self.kbar(rect, dx - 0.5 * ax, dy, Axis::X))
                    / ax
            }
            Axis::Y => {
                (self.kbar(rect, dx, dy + 0.5 * ay, Axis::Y)
                    - self.kbar(rect, dx, dy - 0.5 * ay, Axis::Y))
                    / ay
            }
        }
    }

    /// `Kbar` [m/Pa]: `K` averaged across the target cell's width transverse
    /// to `axis`, at the point `(x, y)`.
    fn kbar(&self, rect: &LoveRect, x: f64, y: f64, axis: Axis) -> f64 {
        let (ax, ay) = (rect.ax, rect.ay);
        let fbar = |px: f64, py: f64| self.transverse_average(rect, px, py, axis);
        let mut kinks = vec![
            KinkLine::X(-0.5 * ax),
            KinkLine::X(0.5 * ax),
            KinkLine::Y(-0.5 * ay),
            KinkLine::Y(0.5 * ay),
        ];
        match axis {
            Axis::X => kinks.extend([KinkLine::Y(-ay), KinkLine::Y(0.0), KinkLine::Y(ay)]),
            Axis::Y => kinks.extend([KinkLine::X(-ax), KinkLine::X(0.0), KinkLine::X(ax)]),
        }
        let f0 = fbar(x, y);
        let scale = f0.abs() * (self.glassy + self.terms.iter().map(|t| t.0).sum::<f64>());
        let problem = LineProblem {
            d: (x, y),
            e: self.e,
            terms: &self.terms,
            a_min: ax.min(ay),
            a_max: ax.max(ay),
            kinks: &kinks,
            abs_tol: TOL * scale,
        };
        let mem = memory_integral(&problem, fbar);
        self.prefactor * (self.glassy * f0 + mem)
    }

    /// Average of `Theta L` over the segment through `(px, py)` of the source
    /// cell's width, transverse to `axis`. Near the source (and always with a
    /// thin layer) by the closed-form antiderivative or adaptive quadrature,
    /// far away by 10-point (beyond 20 cells 4-point) Gauss-Legendre on the
    /// multipole form.
    pub(crate) fn transverse_average(&self, rect: &LoveRect, px: f64, py: f64, axis: Axis) -> f64 {
        let (ax, ay) = (rect.ax, rect.ay);
        // Work in coordinates where the averaging runs along the second axis.
        let (u, w, width, along_w) = match axis {
            Axis::X => (px, py, ay, ax),
            Axis::Y => (py, px, ax, ay),
        };
        let f = self.spatial(rect);
        let eval = |t: f64| match axis {
            Axis::X => f(u, t),
            Axis::Y => f(t, u),
        };
        let r2 = u * u + w * w;
        let reach = rect.switch_radius_sq().sqrt() + width;
        let thin = self
            .theta
            .as_ref()
            .is_some_and(|t| t.layer.thickness < 4.0 * along_w.max(width));
        if r2 > reach * reach && !thin {
            // 10 nodes next to the switch radius; 4 beyond 20 cell sizes,
            // where the Bernstein-ellipse parameter exceeds ~80.
            let far = r2 > (20.0 * along_w.max(width) + width).powi(2);
            let (gx, gw) = if far { gl4() } else { gl10() };
            let mut s = 0.0;
            for (t, wt) in gx.iter().zip(gw.iter()) {
                s += wt * eval(w + 0.5 * width * t);
            }
            return 0.5 * s;
        }
        let closed = match axis {
            Axis::X => rect.near_y_integral(u, w - 0.5 * width, w + 0.5 * width),
            Axis::Y => {
                let tr = LoveRect::new(ay, ax);
                tr.near_y_integral(u, w - 0.5 * width, w + 0.5 * width)
            }
        } / width;
        match &self.theta {
            None => closed,
            // Near the source `Theta` is taken at the distance of the segment's
            // centre, as paper Eq. 6 takes it at the centre-to-centre distance
            // for `K`: the closed form stays exact for `L`, and the relative
            // error of the approximation is O((a / h)^2).
            Some(t) if !thin => t.at_distance(r2.sqrt()) * closed,
            Some(_) => {
                let breaks = quad::clean_breaks(
                    vec![-0.5 * width, 0.5 * width],
                    w - 0.5 * width,
                    w + 0.5 * width,
                );
                let scale = f(px, py).abs().max(1e-300);
                quad::adaptive(eval, &breaks, 1e-15 * scale * width, 1e-15, 2000) / width
            }
        }
    }

    /// Table of `K` over all `(2nx-1) x (2ny-1)` offsets of an `nx x ny` grid
    /// of square cells of side `cell` \[m\] (rayon). Uses the row march when
    /// `e_v` is along a grid axis (see the `table` module docs), per-offset
    /// evaluation otherwise. Panics on an invalid cell size; see
    /// [`Self::try_table`].
    pub fn table(&self, nx: usize, ny: usize, cell: f64) -> CoefficientTable {
        self.try_table(nx, ny, cell).expect("valid cell size")
    }

    /// [`Self::table`] with the cell size checked.
    pub fn try_table(
        &self,
        nx: usize,
        ny: usize,
        cell: f64,
    ) -> Result<CoefficientTable, KernelError> {
        Self::check_cell(cell, cell)?;
        check_grid(nx, ny)?;
        Ok(table::build(self, nx, ny, cell, None))
    }

    /// Table of the cell-averaged derivative `D_x` or `D_y` [1/Pa] over all
    /// offsets (same layout as [`Self::table`]). Fast when `axis` is the
    /// sliding axis; per-offset otherwise. Panics on an invalid cell size.
    pub fn derivative_table(
        &self,
        nx: usize,
        ny: usize,
        cell: f64,
        axis: Axis,
    ) -> CoefficientTable {
        self.try_derivative_table(nx, ny, cell, axis)
            .expect("valid cell size")
    }

    /// [`Self::derivative_table`] with the cell size checked.
    pub fn try_derivative_table(
        &self,
        nx: usize,
        ny: usize,
        cell: f64,
        axis: Axis,
    ) -> Result<CoefficientTable, KernelError> {
        Self::check_cell(cell, cell)?;
        check_grid(nx, ny)?;
        Ok(table::build(self, nx, ny, cell, Some(axis)))
    }

    /// [`VertexTable`]: `K` at the corner offsets `((i + 1/2) a, (j + 1/2) a)`
    /// of an `nx x ny` grid of square cells of side `cell` \[m\], by the row
    /// march where [`Self::table`] uses it.
    pub fn try_vertex_table(
        &self,
        nx: usize,
        ny: usize,
        cell: f64,
    ) -> Result<VertexTable, KernelError> {
        Self::check_cell(cell, cell)?;
        check_grid(nx, ny)?;
        Ok(table::build_vertex(self, nx, ny, cell))
    }

    /// The reference per-offset table (no fast path), for tests and for
    /// directions off the grid axes.
    pub fn table_per_offset(
        &self,
        nx: usize,
        ny: usize,
        cell: f64,
        derivative: Option<Axis>,
    ) -> CoefficientTable {
        table::per_offset(self, nx, ny, cell, derivative)
    }
}

fn check_grid(nx: usize, ny: usize) -> Result<(), KernelError> {
    if nx == 0 || ny == 0 {
        return Err(KernelError::Invalid(format!(
            "grid {nx} x {ny} must have at least one cell per side"
        )));
    }
    Ok(())
}

fn gl4() -> &'static (Vec<f64>, Vec<f64>) {
    static GL: std::sync::OnceLock<(Vec<f64>, Vec<f64>)> = std::sync::OnceLock::new();
    GL.get_or_init(|| quad::gauss_legendre(4))
}

fn gl10() -> &'static (Vec<f64>, Vec<f64>) {
    static GL: std::sync::OnceLock<(Vec<f64>, Vec<f64>)> = std::sync::OnceLock::new();
    GL.get_or_init(|| quad::gauss_legendre(10))
}
