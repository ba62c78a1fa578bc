//! Layers much thinner than a cell whose local compliance vanishes: the
//! thin-layer law on the cell grid (physics.md section 3, "Finite
//! thickness"; the local limit of [`super::thin`]).
//!
//! The layer's compliance ratio is odd in `u = |q| h`,
//! `S(u) = S1 u + S3 u^3 + O(u^5)`, so for `|q| h << 1` the displacement
//! of a pressure mode is `2 (1 - nu^2) J* (S1 h + S3 h^3 |q|^2) p`: in real
//! space `w = 2 (1 - nu^2) [S1 h - S3 h^3 lap] (J* p)`, with `J* p` the
//! memory of Eq. 4 along the sliding trail. Bonded (from the closed form of
//! [`super::thickness::compliance_ratio`]): `S1 = (1 - 2 nu) / (2 (1 - nu)^2)`,
//! `S3 = [4 k / 3 - S1 (2 k + 2)] / (8 (1 - nu)^2)`, `k = 3 - 4 nu`; at
//! `nu = 1/2`, `S1 = 0`, `S3 = 2/3` and `w = -(h^3 / E) lap p` (shear
//! modulus `E / 3`). Frictionless: `S = u/2 - u^5/90 + ...`, `S3 = 0`.
//!
//! Where `S1` vanishes (a bonded layer near incompressibility) the paper's
//! collocation at cell centres sees nothing: a uniformly loaded cell
//! deforms only within the layer's reach of its edges. Averaging those edge
//! spikes over the cell instead (the cell-averaged, Galerkin coefficient of
//! piecewise-constant pressure: `-2 c2 h^2 / a` on the cell, `c2 h^2 / (2 a)`
//! on its four neighbours, `c2 = 4 int rho Theta < 0`) is no better: for a
//! smooth pressure it gives `|c2| a / (2 h)` times the law's displacement
//! (the jumps of the cell-constant pressure are an artefact of the ansatz,
//! not the solid's). The law is therefore discretised on the cell centres
//! as it stands: `J* p` is the memory bracket of the cell-constant
//! pressure at the centres (the sharp-step limit of [`super::thin`]'s
//! trail, `h -> 0`), and `-lap` the five-point Laplacian with the cell
//! sides, consistent to `O((q a)^2)` for pressures smooth on the grid
//! (tests/kernel_thin_layer.rs checks the order against the exact
//! spectral layer). The friction stencil is the work of the cell-constant
//! traction on the same field, `[K(x + a/2) - K(x - a/2)] / a` along the
//! sliding direction (`J* p` is continuous along the trail; the
//! Laplacian's points shift with the target), the centred difference
//! across it; its elastic (`1/E_inf`) part stays antisymmetric. It is the
//! stencil of its continuation above the local limit
//! (`kernel/thin_band.rs`, where the centred difference it replaces is
//! measured), so that the two stay continuous at the switch.

use super::thin::ThinProfile;
use super::{Axis, Coefficient, SlidingKernel};
use crate::response::LayerBase;

/// `(S1, S3)` of `S(u) = S1 u + S3 u^3 + ...` (module docs).
pub fn thin_series(base: LayerBase, nu: f64) -> (f64, f64) {
    match base {
        LayerBase::Bonded => {
            let k = 3.0 - 4.0 * nu;
            let d = 8.0 * (1.0 - nu) * (1.0 - nu);
            let s1 = (2.0 * k - 2.0) / d;
            (s1, (4.0 * k / 3.0 - s1 * (2.0 * k + 2.0)) / d)
        }
        LayerBase::Frictionless => (0.5, 0.0),
    }
}

impl SlidingKernel {
    /// Whether the law of this module replaces [`super::thin`]'s local
    /// compliance on `ax x ay` cells: the local compliance `m0 h` is
    /// swamped by the edge term `c2 h^2` of the shorter side.
    pub(crate) fn thin_law(&self, p: &ThinProfile, ax: f64, ay: f64) -> bool {
        let h = self.theta.as_ref().map_or(0.0, |t| t.layer.thickness);
        p.m0 < 20.0 * p.c2.abs() * h / ax.min(ay)
    }

    /// Whether `ax x ay` cells take the thin-layer law of this module (a
    /// layer in the local limit whose local compliance vanishes against
    /// its edge term: bonded, near incompressibility) or its continuation
    /// above the local limit (`kernel/thin_band.rs`).
    pub fn is_thin_law(&self, ax: f64, ay: f64) -> bool {
        self.thin_profile(ax, ay)
            .is_some_and(|p| self.thin_law(&p, ax, ay))
            || self.is_band(ax, ay)
    }

    /// `(elastic, memory)` parts of `J* p` at the along offset `x` from a
    /// unit cell-constant pressure on `[-aa/2, aa/2]`: `1/E_inf` times the
    /// step, plus per creep term `C_k (e^{-s1/l} - e^{-s2/l})`, `s1`, `s2`
    /// the distances along the trail to the cell's edges.
    pub(super) fn law_bracket(&self, x: f64, aa: f64) -> (f64, f64) {
        let d = 0.5 * aa - x.abs();
        let pv = if d.abs() <= 1e-9 * aa {
            0.5
        } else if d > 0.0 {
            1.0
        } else {
            0.0
        };
        let s1 = (-0.5 * aa - x).max(0.0);
        let s2 = (0.5 * aa - x).max(0.0);
        let mem = self
            .terms
            .iter()
            .map(|&(c, l)| {
                let m = if l == 0.0 {
                    pv
                } else if !l.is_finite() {
                    0.0
                } else {
                    (-s1 / l).exp() - (-s2 / l).exp()
                };
                c * m
            })
            .sum();
        (self.glassy * pv, mem)
    }

    /// `K(d)` of the law (module docs) at the offset `(dx, dy)`: NaN off a
    /// grid-axis direction or off the lattice of cell centres across `e_v`.
    pub(crate) fn law_coefficient(&self, ax: f64, ay: f64, dx: f64, dy: f64) -> Coefficient {
        let Some((x, c, aa, at)) = self.frame(dx, dy, ax, ay) else {
            return Coefficient::NAN;
        };
        let Some(t) = &self.theta else {
            return Coefficient::NAN;
        };
        let j = (c / at).round();
        if (c - j * at).abs() > 1e-9 * at || !j.is_finite() {
            return Coefficient::NAN;
        }
        let (s1, s3) = thin_series(t.layer.base, t.poisson);
        let h = t.layer.thickness;
        let scale = 2.0 * std::f64::consts::PI * self.prefactor;
        let b = |x: f64| self.law_bracket(x, aa);
        // -lap across: 2 on the source's row, -1 on each neighbour.
        let across = match j.abs() as u64 {
            0 => 2.0,
            1 => -1.0,
            _ => return Coefficient::default(),
        };
        let (b0, bm, bp) = (b(x), b(x - aa), b(x + aa));
        let part = |f: fn((f64, f64)) -> f64| {
            let on_row = if j == 0.0 { 1.0 } else { 0.0 };
            let along = on_row * (2.0 * f(b0) - f(bm) - f(bp)) / (aa * aa);
            let lap = along + across * f(b0) / (at * at);
            scale * (s1 * h * on_row * f(b0) + s3 * h * h * h * lap)
        };
        Coefficient {
            elastic: part(|v| v.0),
            viscoelastic: part(|v| v.1),
        }
    }

    /// The friction stencil's derivative of the law along `axis`
    /// (module docs): [`Self::law_coefficient`] on the cell edges along the
    /// sliding direction, its centred difference across.
    pub(crate) fn law_derivative(&self, ax: f64, ay: f64, dx: f64, dy: f64, axis: Axis) -> f64 {
        let (ex, ey, a) = match axis {
            Axis::X => (ax, 0.0, ax),
            Axis::Y => (0.0, ay, ay),
        };
        let k = |x: f64, y: f64| self.law_coefficient(ax, ay, x, y).total();
        if self.along(axis) {
            (k(dx + 0.5 * ex, dy + 0.5 * ey) - k(dx - 0.5 * ex, dy - 0.5 * ey)) / a
        } else {
            (k(dx + ex, dy + ey) - k(dx - ex, dy - ey)) / (2.0 * a)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::response::layer::compliance_ratio;

    /// The series against the closed form at `u = 1e-2`: the remainder
    /// over `u^3` is `S5 u^2 = 1e-4 S5`; 1e-3 allows `|S5|` up to 10 and
    /// fails on any coefficient of `u` or `u^3` off by more than 1e-3.
    #[test]
    fn series_matches_the_compliance_ratio() {
        let u: f64 = 1e-2;
        for base in [LayerBase::Bonded, LayerBase::Frictionless] {
            for nu in [0.0, 0.3, 0.45, 0.5] {
                let (s1, s3) = thin_series(base, nu);
                let s = compliance_ratio(base, nu, u);
                let r = (s - s1 * u - s3 * u.powi(3)) / u.powi(3);
                assert!(r.abs() < 1e-3, "{base:?} {nu}: {r:e}");
            }
        }
        let (s1, s3) = thin_series(LayerBase::Bonded, 0.5);
        assert!(s1 == 0.0 && (s3 - 2.0 / 3.0).abs() < 1e-15);
    }
}
