//! Layers between the local limit and about a cell whose local compliance
//! vanishes: the thin-layer law continued to all orders on the cell grid
//! (physics.md section 3, "Finite thickness"; the continuation of
//! [`super::thin_law`] above the local limit of [`super::thin`]).
//!
//! A bonded incompressible layer has no local compliance
//! (`S(u) = 2 u^3 / 3 + O(u^5)`): the displacement of a cell-constant pressure is carried by
//! the spikes within the reach `R h` of the pressure's jumps, and collocated
//! at the cell centres (the resolved cell integral of [`super::cell`]) it
//! sees only what of those spikes reaches a centre. Against the exact
//! spectral layer on a smooth pressure at rest that misses 100 % of the response
//! up to `h = a/40`, 34 % at `a/10`, 12-16 % from `a/5` to `a/2`, 6 % at
//! `0.7 a` and 2 % at `a` (measured, tests/kernel/thin_switch.rs): below
//! about a cell the resolved kernel does not converge to the layer, and
//! the switch to it from the law at `R h = a/2` (`h = a/83`) jumped from
//! the law's response to almost nothing.
//!
//! Here the law `w = 2 (1 - nu^2) [S1 h - S3 h^3 lap] (J* p)` is taken to
//! every order of `S` by its symbol on the grid: the layer's multiplier
//! `2 (1 - nu^2) S(|q| h) / |q|` with `|q|^2` replaced by the five-point
//! Laplacian's
//!
//! `|q~|^2 = (4 / a_x^2) sin^2(q_x a_x / 2) + (4 / a_y^2) sin^2(q_y a_y / 2)`,
//!
//! `Ghat(q) = 2 (1 - nu^2) h g(h |q~|)`, `g(u) = S(u) / u = S1 + S3 u^2 + ...`
//! (even in `u`, so a function of the trigonometric polynomial `|q~|^2`:
//! periodic and analytic on the zone). Its lattice kernel
//!
//! `D(i, j) = (a_x a_y / (4 pi^2)) int_zone Ghat(q) cos(q_x i a_x) cos(q_y j a_y) d2q`
//!
//! is, to `O(h^5)`, exactly the law's stencil (`S1 h` on the cell,
//! `S3 h^3` times the five-point `-lap`), and for smooth pressures it is
//! the exact layer to `O((q a)^2)` at every thickness (the modified
//! wavenumber `|q~|^2 = |q|^2 (1 + O((q a)^2))`). It decays like the
//! layer's Green's function (`Theta` beyond its reach `R h`), faster where
//! `h << a`. The trapezoidal rule on `M x M` points of the zone is exact up
//! to the images `D(i + M m)`; with `M >= 4 W` and `W = R h / a + 8` cells
//! they are below round-off, and `D` is cut at `W`.
//!
//! The memory of Eq. 4 enters as in the law: `J* p` of the cell-constant
//! pressure at the centres along the sliding row (the sharp-step limit of
//! [`super::thin`]'s trail), then `D` on the grid,
//! `K(i, j) = sum_i' D(i - i', j) B(i' a)`, `B` the bracket of
//! [`SlidingKernel::law_bracket`].
//!
//! The friction stencil (physics.md section 5) is the work of the
//! cell-constant traction on this field, as the resolved kernel's
//! cell-averaged derivative is: `D(i) = [K(i a + a/2) - K(i a - a/2)] / a`
//! along `e_v`, with `K` off the lattice by the lattice shifted along the
//! trail, `K(i a + t, j) = sum_i' D(i - i', j) B(i' a + t)` (the memory
//! `J* p` is continuous along the trail; `D` couples the points of the
//! shifted lattice as it couples the centres). The elastic part stays
//! antisymmetric (`B`'s step takes 1/2 on the edges), so it does no work.
//! The centred difference `[K(i + 1) - K(i - 1)] / (2 a)` used before samples
//! the memory, which decays within `v tau`, one cell apart: where `v tau`
//! is about a cell it missed most of it (`configs/default.toml`'s pad at
//! 64^2 under 1 MPa, `h = 0.999 a`: 5.2e-4 against 8.4e-4 from the same
//! surface refined to 256^2, where the resolved kernel at `h = 1.001 a`
//! gives 8.6e-4; with `v tau = 4 a` 1.32e-3 against 1.60e-3). The work
//! on the cell edges gives 1.02e-3 and 1.67e-3 there (+22 % and +4 %: the
//! error falls as `v tau / a` grows, the continuation's memory being that
//! of the sharp cell-constant pressure); across the switch, measured in
//! tests/solver/thin_step.rs and BENCHMARKS.md "Thin-layer switches".
//! Across `e_v` the derivative stays the centred difference (the lattice
//! has no points between the rows).
//!
//! Nothing here needs `e_v` along a grid axis but the row bracket: off the
//! axes the memory at a point is the same line integral along a trail
//! between the grid lines, in closed form for a cell-constant pressure,
//! and `D` couples it in two dimensions (`kernel/thin_oblique.rs`; the
//! resolved cell integral took over there before, 2x off at `h = a/5`).

use super::{Axis, Coefficient, SlidingKernel};
use crate::response::layer::compliance_ratio;
use crate::response::LayerBase;

use super::thin_law::thin_series;

/// The thickness in units of the shorter cell side below which a layer
/// whose local limit takes the thin-layer law keeps the grid-symbol
/// kernel of this module; from it on the resolved cell integral. At `h = a`
/// the two agree on smooth pressures to the discretisation error of
/// either (measured: see tests/kernel/thin_switch.rs).
pub const BAND_RATIO_MAX: f64 = 1.0;

/// `D(i, j)` over `|i|, |j| <= half` for cells `aa` along `e_v` and `at`
/// across (`i` along).
#[derive(Debug)]
pub(crate) struct BandStencil {
    pub half: usize,
    /// `values[i * (half + 1) + j]` for `i, j >= 0` (`D` is even in both).
    values: Vec<f64>,
}

impl BandStencil {
    /// `D(i, j)` [m/Pa per unit compliance]; zero beyond `half`.
    pub(crate) fn get(&self, i: i64, j: i64) -> f64 {
        let (i, j) = (i.unsigned_abs() as usize, j.unsigned_abs() as usize);
        if i > self.half || j > self.half {
            0.0
        } else {
            self.values[i * (self.half + 1) + j]
        }
    }

    /// The lattice kernel of the module docs for a layer of thickness `h`
    /// (`reach` = `R h` [m]) on `aa x at` cells, with `m` points per axis
    /// of the zone (`None`: `4 W` rounded up to 64).
    pub(crate) fn new(
        base: LayerBase,
        nu: f64,
        h: f64,
        reach: f64,
        (aa, at): (f64, f64),
        m: Option<usize>,
    ) -> Self {
        let half = (reach / aa.min(at)).ceil() as usize + 8;
        let m = m.unwrap_or_else(|| (4 * half).div_ceil(64) * 64);
        let (s1, s3) = thin_series(base, nu);
        let g = |u: f64| {
            if u < 1e-4 {
                s1 + s3 * u * u
            } else {
                compliance_ratio(base, nu, u) / u
            }
        };
        let two_pi = 2.0 * std::f64::consts::PI;
        // sin^2 of half the phase of each zone point, per axis.
        let sin2 = |a: f64| -> Vec<f64> {
            (0..m)
                .map(|k| {
                    let t = (0.5 * two_pi * k as f64 / m as f64).sin();
                    4.0 * t * t / (a * a)
                })
                .collect()
        };
        let (qa, qt) = (sin2(aa), sin2(at));
        // cos(2 pi k i / m) for i <= half.
        let cos: Vec<f64> = (0..m * (half + 1))
            .map(|n| {
                let (k, i) = (n / (half + 1), n % (half + 1));
                (two_pi * ((k * i) % m) as f64 / m as f64).cos()
            })
            .collect();
        // T(k, j) = sum_l Ghat(k, l) cos(l j), then D(i, j) = sum_k T(k, j) cos(k i).
        let prefactor = 2.0 * (1.0 - nu * nu) * h / (m * m) as f64;
        let mut t = vec![0.0; m * (half + 1)];
        for k in 0..m {
            let row = &mut t[k * (half + 1)..(k + 1) * (half + 1)];
            for l in 0..m {
                let gh = g(h * (qa[k] + qt[l]).sqrt());
                let c = &cos[l * (half + 1)..(l + 1) * (half + 1)];
                for (r, cj) in row.iter_mut().zip(c) {
                    *r += gh * cj;
                }
            }
        }
        let mut values = vec![0.0; (half + 1) * (half + 1)];
        for k in 0..m {
            let c = &cos[k * (half + 1)..(k + 1) * (half + 1)];
            let tk = &t[k * (half + 1)..(k + 1) * (half + 1)];
            for (i, ci) in c.iter().enumerate() {
                for (j, tj) in tk.iter().enumerate() {
                    values[i * (half + 1) + j] += prefactor * ci * tj;
                }
            }
        }
        Self { half, values }
    }
}

impl SlidingKernel {
    /// Whether `ax x ay` cells take the grid-symbol kernel of this module:
    /// a layer above the local limit and below [`BAND_RATIO_MAX`] of the
    /// shorter side, whose local limit at the switch (`R h = a/2`) is the
    /// thin-layer law; sliding in any direction (off the grid axes by
    /// `kernel/thin_oblique.rs`).
    pub(crate) fn is_band(&self, ax: f64, ay: f64) -> bool {
        let Some(t) = &self.theta else { return false };
        if self.rule != super::ThetaRule::CellIntegral || !self.local {
            return false;
        }
        let a = ax.min(ay);
        let h = t.layer.thickness;
        if t.reach() <= 0.5 * a || h >= BAND_RATIO_MAX * a {
            return false;
        }
        let p = super::thin::profile(t);
        // The law's criterion at the switch, h / a = 1 / (2 R).
        p.m0 < 20.0 * p.c2.abs() / (2.0 * p.reach)
    }

    /// The stencil of `ax x ay` cells in the frame of `e_v` (along, across)
    /// on a grid axis, in the grid's (x, y) otherwise.
    pub(crate) fn band_stencil(&self, ax: f64, ay: f64) -> Option<BandStencil> {
        if !self.is_band(ax, ay) {
            return None;
        }
        let t = self.theta.as_ref()?;
        let (aa, at) = self
            .frame(0.0, 0.0, ax, ay)
            .map_or((ax, ay), |(_, _, aa, at)| (aa, at));
        Some(BandStencil::new(
            t.layer.base,
            t.poisson,
            t.layer.thickness,
            t.reach(),
            (aa, at),
            None,
        ))
    }

    /// `K(d)` of the module docs at the offset `(dx, dy)`: on a grid axis
    /// NaN off the lattice of cell centres and off its copy shifted by half
    /// a cell along `e_v` (the cell edges of the friction stencil); off the
    /// axes by `kernel/thin_oblique.rs`.
    pub(crate) fn band_coefficient(
        &self,
        b: &BandStencil,
        ax: f64,
        ay: f64,
        dx: f64,
        dy: f64,
    ) -> Coefficient {
        let Some((x, c, aa, at)) = self.frame(dx, dy, ax, ay) else {
            return self.oblique_coefficient(b, (ax, ay), (dx, dy));
        };
        let (i, j) = ((x / aa).round(), (c / at).round());
        // The lattice along the trail, shifted by `t` = 0 or half a cell.
        let t = x - i * aa;
        let t = if t.abs() <= 1e-9 * aa {
            0.0
        } else if (t.abs() - 0.5 * aa).abs() <= 1e-9 * aa {
            0.5 * aa * t.signum()
        } else {
            return Coefficient::NAN;
        };
        if (c - j * at).abs() > 1e-9 * at || !i.is_finite() {
            return Coefficient::NAN;
        }
        let (i, j) = (i as i64, j as i64);
        if j.unsigned_abs() as usize > b.half {
            return Coefficient::default();
        }
        let w = b.half as i64;
        let mut out = Coefficient::default();
        for s in i - w..=i + w {
            let d = b.get(i - s, j);
            if d == 0.0 {
                continue;
            }
            let (el, mem) = self.law_bracket(s as f64 * aa + t, aa);
            out.elastic += d * el;
            out.viscoelastic += d * mem;
        }
        out
    }
}

impl SlidingKernel {
    /// The friction stencil of the module docs along `axis`: the work on
    /// the cell edges along `e_v`, the centred difference across; off the
    /// axes the work on the cell edges along both (`kernel/thin_oblique.rs`).
    pub(crate) fn band_derivative(
        &self,
        b: &BandStencil,
        (ax, ay): (f64, f64),
        (dx, dy): (f64, f64),
        axis: Axis,
    ) -> f64 {
        if self.frame(0.0, 0.0, ax, ay).is_none() {
            return self.oblique_derivative(b, (ax, ay), (dx, dy), axis);
        }
        let (ex, ey, a) = match axis {
            Axis::X => (ax, 0.0, ax),
            Axis::Y => (0.0, ay, ay),
        };
        let k = |x: f64, y: f64| self.band_coefficient(b, ax, ay, x, y).total();
        if self.along(axis) {
            (k(dx + 0.5 * ex, dy + 0.5 * ey) - k(dx - 0.5 * ex, dy - 0.5 * ey)) / a
        } else {
            (k(dx + ex, dy + ey) - k(dx - ex, dy - ey)) / (2.0 * a)
        }
    }

    /// Whether `axis` is the sliding direction's (a grid axis).
    pub(super) fn along(&self, axis: Axis) -> bool {
        match axis {
            Axis::X => self.e.1 == 0.0,
            Axis::Y => self.e.0 == 0.0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// At `h << a` the stencil is the law's, `S3 h^3` times the five-point
    /// `-lap` (bonded incompressible, `2 (1 - nu^2) S3 = 1`), plus the next
    /// order `2 (1 - nu^2) S5 h^5 lap^2` (`S5 = -6/5`: `S = (2 u^3 / 3)
    /// (1 - 9 u^2 / 5 + ...)`; the 13-point `lap^2` is 20 on the cell, -8,
    /// 2 and 1 on its neighbours, diagonals and second neighbours, over
    /// `a^4`), to the order after, `(h / a)^4 = 1e-8` relative (asserted
    /// 1e-6 of the self coefficient); and doubling the zone's points at
    /// `h = a` changes nothing beyond round-off (the images are gone).
    #[test]
    fn stencil_is_the_law_to_leading_order_and_converged() {
        let (a, h) = (1.0, 1e-2);
        let b = BandStencil::new(LayerBase::Bonded, 0.5, h, 41.5 * h, (a, a), None);
        let (c3, c5) = (h.powi(3) / (a * a), -1.8 * h.powi(5) / a.powi(4));
        for (i, j, lap, lap2) in [
            (0, 0, 4.0, 20.0),
            (1, 0, -1.0, -8.0),
            (0, -1, -1.0, -8.0),
            (1, 1, 0.0, 2.0),
            (2, 0, 0.0, 1.0),
            (3, 0, 0.0, 0.0),
        ] {
            let expected = lap * c3 + lap2 * c5;
            let d = b.get(i, j);
            assert!(
                (d - expected).abs() < 1e-6 * 4.0 * c3,
                "({i}, {j}): {d:e} vs {expected:e}"
            );
        }
        let h = 1.0;
        let b1 = BandStencil::new(LayerBase::Bonded, 0.5, h, 41.5 * h, (a, a), None);
        let b2 = BandStencil::new(
            LayerBase::Bonded,
            0.5,
            h,
            41.5 * h,
            (a, a),
            Some(2 * 4 * b1.half.div_ceil(64) * 64),
        );
        let d0 = b1.get(0, 0).abs();
        for (i, j) in [(0, 0), (1, 0), (2, 3), (10, 4), (30, 0)] {
            assert!(
                (b1.get(i, j) - b2.get(i, j)).abs() < 1e-13 * d0,
                "({i}, {j})"
            );
        }
        let edge = (0..=b1.half as i64)
            .map(|j| b1.get(b1.half as i64, j).abs())
            .fold(0.0, f64::max);
        assert!(edge < 1e-14 * d0, "{edge:e}");
    }
}
