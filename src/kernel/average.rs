//! Width averages of the spatial factor for the friction stencil
//! (physics.md section 5): `Kbar` needs the spatial factor averaged across
//! the target cell's width, transverse to the derivative's axis.

use super::love::LoveRect;
use super::thickness::ThetaTable;
use super::{gl10, gl4, quad, Axis, Cell, SlidingKernel};

impl SlidingKernel {
    /// Average of the spatial factor over the segment through `(px, py)` of
    /// the source cell's width, transverse to `axis`. Love's `L` near the
    /// source by its closed-form antiderivative, far away by 10-point
    /// (beyond 20 cells 4-point) Gauss-Legendre on the multipole form; on a
    /// layer plus the `psi` part of the cell integral ([`cell`]); with
    /// [`ThetaRule::Collocation`], `Theta` at the segment's centre times the
    /// average of `L` (or adaptive quadrature of `Theta L` on thin layers).
    pub(crate) fn transverse_average(&self, cell: &Cell, px: f64, py: f64, axis: Axis) -> f64 {
        let rect = &cell.love;
        let (ax, ay) = (rect.ax, rect.ay);
        let width = match axis {
            Axis::X => ay,
            Axis::Y => ax,
        };
        match (&cell.layer, &self.theta) {
            (Some(lc), _) => {
                let (gx, gy) = match axis {
                    Axis::X => (0.0, 0.5 * width),
                    Axis::Y => (0.5 * width, 0.0),
                };
                if lc.beyond(px, py, gx, gy) {
                    0.0
                } else if lc.is_polar() {
                    lc.cell_integral_average(px, py, axis)
                } else {
                    self.love_average(cell, px, py, axis, |x, y| rect.eval(x, y))
                        + lc.psi_part_average(px, py, axis)
                }
            }
            (None, Some(t)) => self.collocation_average(cell, t, px, py, axis),
            (None, None) => self.love_average(cell, px, py, axis, |x, y| rect.eval(x, y)),
        }
    }

    /// Width average of `L` (closed form near, Gauss-Legendre on `f` far;
    /// `f` is `L` or, for collocation, `Theta L`).
    fn love_average(
        &self,
        cell: &Cell,
        px: f64,
        py: f64,
        axis: Axis,
        f: impl Fn(f64, f64) -> f64,
    ) -> f64 {
        let rect = &cell.love;
        let (ax, ay) = (rect.ax, rect.ay);
        // Work in coordinates where the averaging runs along the second axis.
        let (u, w, width, along_w) = match axis {
            Axis::X => (px, py, ay, ax),
            Axis::Y => (py, px, ax, ay),
        };
        let r2 = u * u + w * w;
        let reach = rect.switch_radius_sq().sqrt() + width;
        if r2 > reach * reach {
            // 10 nodes next to the switch radius; 4 beyond 20 cell sizes,
            // where the Bernstein-ellipse parameter exceeds ~80.
            let far = r2 > (20.0 * along_w.max(width) + width).powi(2);
            let (gx, gw) = if far { gl4() } else { gl10() };
            let mut s = 0.0;
            for (t, wt) in gx.iter().zip(gw.iter()) {
                let t = w + 0.5 * width * t;
                s += wt
                    * match axis {
                        Axis::X => f(u, t),
                        Axis::Y => f(t, u),
                    };
            }
            return 0.5 * s;
        }
        let (lo, hi) = (w - 0.5 * width, w + 0.5 * width);
        let closed = match axis {
            Axis::X => rect.near_y_integral(u, lo, hi),
            Axis::Y if ax == ay => rect.near_y_integral(u, lo, hi),
            Axis::Y => LoveRect::new(ay, ax).near_y_integral(u, lo, hi),
        };
        closed / width
    }

    /// The paper's collocation (Eq. 6) for the width average: near the
    /// source `Theta` at the distance of the segment's centre times the
    /// closed form (for layers of at least four cells), otherwise adaptive
    /// quadrature of `Theta L`.
    fn collocation_average(
        &self,
        cell: &Cell,
        t: &ThetaTable,
        px: f64,
        py: f64,
        axis: Axis,
    ) -> f64 {
        let rect = &cell.love;
        let (ax, ay) = (rect.ax, rect.ay);
        let (u, w, width) = match axis {
            Axis::X => (px, py, ay),
            Axis::Y => (py, px, ax),
        };
        let f = self.spatial(cell);
        let thin = t.layer.thickness < 4.0 * ax.max(ay);
        if !thin {
            let r2 = u * u + w * w;
            let near = rect.switch_radius_sq().sqrt() + width;
            return if r2 > near * near {
                self.love_average(cell, px, py, axis, &f)
            } else {
                t.at_distance(r2.sqrt()) * self.love_average(cell, px, py, axis, |_, _| 0.0)
            };
        }
        let eval = |s: f64| match axis {
            Axis::X => f(u, s),
            Axis::Y => f(s, u),
        };
        let breaks = quad::clean_breaks(
            vec![-0.5 * width, 0.5 * width],
            w - 0.5 * width,
            w + 0.5 * width,
        );
        let scale = f(px, py).abs().max(1e-300);
        quad::adaptive(eval, &breaks, 1e-15 * scale * width, 1e-15, 2000) / width
    }
}
