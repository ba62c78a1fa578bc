//! Coarser grids at depth (physics.md section 14): at depth `z` a mode's
//! stress is `exp(-t)` times a polynomial `a + b t` of `t = |q| z`
//! (`|a|, |b| <= 3`), so the modes with `t > BAND_CUT` carry less than
//! `3 exp(-50) 51 ~ 3e-20` of their surface amplitude. The modes kept,
//! `|kx| <= B_x`, `|ky| <= B_y` (`B = floor(BAND_CUT L / (2 pi z))`, every
//! mode outside the box has `t > BAND_CUT`), make rates band-limited at
//! `B` and their squares at `2 B`: a grid of `M >= 4 B + 1` points per
//! axis samples them without aliasing, and the density's spectrum there
//! is its spectrum on the full grid, zero beyond `2 B` (exact
//! trigonometric interpolation). The cut leaves eight orders of magnitude
//! below the 1e-12 the planned density is pinned to for the rates' growth
//! with `|w|` and the pressure spectrum's spread between the modes kept
//! and those dropped.

use num_complex::Complex64;

use super::super::stress::unit_component;
use super::form::{accumulate, field_for};
use super::{transform_error, written_zeros, Dissipation};
use crate::heat::density::Band;
use crate::heat::error::HeatError;
use crate::operator::signed_index;
use crate::surface::height_fft;

/// The largest `t = |q| z` kept on a coarse grid.
pub(super) const BAND_CUT: f64 = 50.0;

/// The smallest `m >= n` (at least 2) of the form `2^a 3^b 5^c`.
pub(super) fn friendly(n: usize) -> usize {
    let mut m = n.max(2);
    loop {
        let mut r = m;
        for p in [2, 3, 5] {
            while r % p == 0 {
                r /= p;
            }
        }
        if r == 1 {
            return m;
        }
        m += 1;
    }
}

/// The band `B` kept at depth `z` along an axis of period `length`, and the
/// coarse size `M` that holds `2 B`; `None` when `M` would not be smaller
/// than the grid's `n` (or `z` is not positive).
pub(super) fn coarse_axis(n: usize, length: f64, z: f64) -> Option<(usize, usize)> {
    let b = (BAND_CUT * length / (std::f64::consts::TAU * z)).floor();
    if !(b.is_finite() && b >= 0.0) || b >= n as f64 {
        return None;
    }
    let b = b as usize;
    let m = friendly(4 * b + 1);
    (m < n).then_some((b, m))
}

/// Each coarse node's density, summed over the multipliers: zeros on its
/// coarse grid (per layer and node, empty for a full-grid node).
pub(super) fn coarse_sums(
    grids: &[CoarseGrid],
    plans: &[Vec<Option<Coarse>>],
) -> Vec<Vec<Vec<f64>>> {
    let zeros = |c: &Coarse| {
        let (mx, my) = grids[c.grid].size;
        written_zeros(mx * my)
    };
    plans
        .iter()
        .map(|layer| {
            layer
                .iter()
                .map(|p| p.as_ref().map_or(Vec::new(), zeros))
                .collect()
        })
        .collect()
}

/// A depth node evaluated on a coarser grid (`band.rs`): which of the
/// planned coarse grids, its band, and (for the general path) every regular
/// mode in its band (its index in `regular`, its index in the coarse half
/// spectrum).
pub(super) struct Coarse {
    pub grid: usize,
    /// The band `(B_x, B_y)` kept.
    pub band: (usize, usize),
    pub modes: Vec<(usize, usize)>,
}

/// A coarse grid's size and inverse transform.
pub(super) struct CoarseGrid {
    pub size: (usize, usize),
    pub fft: height_fft::Inverse,
}

impl Dissipation {
    /// The coarse grids the depth nodes need and, per layer and node, the
    /// coarse plan of a node whose band fits a coarser grid along both
    /// axes (`None`: the full grid); `with_modes`, each plan lists the
    /// regular modes of its band (the general path reads them, the
    /// separable one builds its columns from the band).
    pub(super) fn coarse_plans(
        &self,
        nodes: &[Vec<(f64, f64)>],
        with_modes: bool,
    ) -> (Vec<CoarseGrid>, Vec<Vec<Option<Coarse>>>) {
        let mut grids: Vec<CoarseGrid> = Vec::new();
        let plans = nodes
            .iter()
            .map(|layer| {
                layer
                    .iter()
                    .map(|&(z, _)| {
                        let (bx, mx) = coarse_axis(self.nx, self.length.0, z)?;
                        let (by, my) = coarse_axis(self.ny, self.length.1, z)?;
                        let grid = match grids.iter().position(|g| g.size == (mx, my)) {
                            Some(g) => g,
                            None => {
                                grids.push(CoarseGrid {
                                    size: (mx, my),
                                    fft: height_fft::Inverse::new(mx, my),
                                });
                                grids.len() - 1
                            }
                        };
                        let modes = self
                            .regular
                            .iter()
                            .enumerate()
                            .filter(|_| with_modes)
                            .filter_map(|(r, m)| {
                                let (kx, _) = signed_index(m.index % self.nx, self.nx);
                                let ky = m.index / self.nx;
                                (kx.abs() <= bx as f64 && ky <= by).then(|| {
                                    let i = (kx as isize).rem_euclid(mx as isize) as usize;
                                    (r, ky * mx + i)
                                })
                            })
                            .collect();
                        Some(Coarse {
                            grid,
                            band: (bx, by),
                            modes,
                        })
                    })
                    .collect()
            })
            .collect();
        (grids, plans)
    }

    /// `acc += weight D_rate(z)` on the coarse grid of `plan`, for the
    /// multiplier whose values `rate(w) P / N` at the regular modes are
    /// `values`.
    pub(super) fn add_coarse(
        &self,
        values: &[Complex64],
        plan: &Coarse,
        grid: &CoarseGrid,
        z: f64,
        weight: f64,
        acc: &mut [f64],
    ) -> Result<(), HeatError> {
        let nu = self.nu;
        let (mx, my) = grid.size;
        let mut spec = vec![Complex64::default(); mx * (my / 2 + 1)];
        let mut field = vec![0.0; mx * my];
        let mut first = vec![0.0; mx * my];
        let mut rows = Vec::new();
        let amp: Vec<(Complex64, f64)> = plan
            .modes
            .iter()
            .map(|&(r, _)| {
                let t = self.regular[r].k * z;
                (values[r] * (-t).exp(), t)
            })
            .collect();
        let count = if nu == 0.5 { 5 } else { 6 };
        let (dev, trace) = (weight * (1.0 + nu), weight * (1.0 - 2.0 * nu) / 3.0);
        for c in 0..count {
            spec.iter_mut().for_each(|v| *v = Complex64::default());
            for (&(r, index), &(a, t)) in plan.modes.iter().zip(&amp) {
                spec[index] = a * unit_component(self.regular[r].n, t, nu, c);
            }
            grid.fft
                .run(&mut spec, &mut rows, field_for(c, &mut field, &mut first))
                .map_err(transform_error)?;
            accumulate(c, &field, &first, acc, dev, trace);
        }
        Ok(())
    }

    /// The coarse nodes' densities `coarse` (per layer and node, empty
    /// for a full-grid node) as band-limited parts of their layers: each
    /// transformed forward on its coarse grid (the heat problem places
    /// them in its layers' spectra; `LayerDensity::maps` brings them onto
    /// the grid where maps are wanted).
    pub(super) fn band_parts(
        &self,
        grids: &[CoarseGrid],
        plans: &[Vec<Option<Coarse>>],
        coarse: &[Vec<Vec<f64>>],
    ) -> Result<Vec<Vec<Band>>, HeatError> {
        let forward: Vec<height_fft::Forward> = grids
            .iter()
            .map(|g| height_fft::Forward::new(g.size.0, g.size.1))
            .collect();
        let mut rows = Vec::new();
        plans
            .iter()
            .zip(coarse)
            .map(|(plans, coarse)| {
                plans
                    .iter()
                    .zip(coarse)
                    .filter_map(|(plan, acc)| plan.as_ref().map(|c| (c, acc)))
                    .map(|(c, acc)| {
                        Band::from_samples(acc, grids[c.grid].size, &forward[c.grid], &mut rows)
                    })
                    .collect()
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn friendly_sizes() {
        let got: Vec<usize> = [1, 2, 7, 11, 13, 17, 97, 457, 917]
            .iter()
            .map(|&n| friendly(n))
            .collect();
        assert_eq!(got, [2, 2, 8, 12, 15, 18, 100, 480, 960]);
    }

    /// Every mode outside the kept box has `t > BAND_CUT`, and the coarse
    /// size holds twice the band.
    #[test]
    fn band_and_size() {
        let (n, length) = (1024, 1.0);
        for z in [0.01, 0.03, 0.1, 0.5, 2.0] {
            if let Some((b, m)) = coarse_axis(n, length, z) {
                let q_out = std::f64::consts::TAU * (b + 1) as f64 / length;
                assert!(q_out * z > BAND_CUT, "z {z}: b {b}");
                assert!(m > 4 * b && m < n, "z {z}: m {m} b {b}");
            } else {
                assert!(z < 0.05, "z {z} left on the full grid");
            }
        }
    }
}
