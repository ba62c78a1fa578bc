//! The block's background heating: the mean (`k = 0`) rise of a periodic
//! cell, which has no steady state (physics.md section 14, "Periodic
//! cell").
//!
//! A block of length `L_b` along `e_v` keeps each rubber element in the
//! nominal contact for `t_c = L_b / v`, heated by the cell's mean source
//! as a 1-D half-space with an adiabatic surface. A plane source of
//! strength `q` \[W/m^2\] at depth `z'`, switched on at `t = 0`, raises
//! depth `z` by `(q / lam) sqrt(kappa t) [ierfc(|z - z'| / s) + ierfc((z +
//! z') / s)]`, `s = 2 sqrt(kappa t)` (Carslaw & Jaeger sec. 2.9, with its
//! image); at the surface, for `z' = 0`, `2 q sqrt(kappa t / pi) / lam`,
//! whose average over the passage is `(4/3) qbar sqrt(kappa t_c / pi) /
//! lam`. Layers integrate the plane source over their thickness in closed
//! form (`Int ierfc = -i2erfc`); the average over the passage is a
//! Gauss-Legendre sum in `u = sqrt(t / t_c)` on panels halving towards 0.

use super::layers::DepthLayers;
use super::setup::Conduction;
use crate::gauss::gauss_legendre;

/// `(4/3) qbar sqrt(kappa t_c / pi) / lam` \[K\]: the surface rise
/// averaged over a passage of `t_c` \[s\] under the mean flux `qbar`
/// \[W/m^2\].
pub(crate) fn surface_background(qbar: f64, conduction: &Conduction, contact_time: f64) -> f64 {
    4.0 / 3.0 * qbar * (conduction.diffusivity * contact_time / std::f64::consts::PI).sqrt()
        / conduction.conductivity
}

impl Conduction {
    /// The block's background surface rise \[K\] under the mean flux
    /// `qbar` \[W/m^2\] averaged over a passage of `contact_time` \[s\]:
    /// `(4/3) qbar sqrt(kappa t_c / pi) / lam`.
    pub fn surface_background(&self, qbar: f64, contact_time: f64) -> f64 {
        surface_background(qbar, self, contact_time)
    }
}

/// The rise at depth `z` \[m\] averaged over a passage of `t_c` \[s\]
/// under the mean surface flux `qbar` \[W/m^2\].
pub fn surface_background_at(qbar: f64, z: f64, conduction: &Conduction, contact_time: f64) -> f64 {
    if z == 0.0 {
        return surface_background(qbar, conduction, contact_time);
    }
    let reach = (conduction.diffusivity * contact_time).sqrt();
    passage_average(|u| {
        let root = u * reach;
        2.0 * qbar / conduction.conductivity * root * ierfc(z / (2.0 * root))
    })
}

/// The rise at depth `z` \[m\] averaged over a passage of `t_c` \[s\]
/// under the mean volume source `means[l]` \[W/m^3\] of each layer.
pub fn volume_background_at(
    layers: &DepthLayers,
    means: &[f64],
    z: f64,
    conduction: &Conduction,
    contact_time: f64,
) -> f64 {
    let reach = (conduction.diffusivity * contact_time).sqrt();
    passage_average(|u| {
        let root = u * reach;
        let s = 2.0 * root;
        layers
            .iter()
            .zip(means)
            .map(|((a, b), q)| {
                // The antiderivative in z' of ierfc(|z' - z| / s).
                let f = |d: f64| d.signum() * s * quarter_less_i2erfc(d.abs() / s);
                let direct = f(b - z) - f(a - z);
                let image =
                    s * (quarter_less_i2erfc((z + b) / s) - quarter_less_i2erfc((z + a) / s));
                q / conduction.conductivity * root * (direct + image)
            })
            .sum()
    })
}

/// `(1 / t_c) Int_0^t_c f dt` for `f` given as a function of `u =
/// sqrt(t / t_c)`: `Int_0^1 2 u f(u) du`, 8-point Gauss-Legendre on the
/// panels `[2^-(k+1), 2^-k]`, `k < 50` (below, `f = O(u)` leaves less than
/// `2^-100` of the integral).
fn passage_average(f: impl Fn(f64) -> f64) -> f64 {
    let (x, w) = gauss_legendre(8);
    let mut sum = 0.0;
    let mut hi = 1.0f64;
    for _ in 0..50 {
        let lo = 0.5 * hi;
        let (c, h) = (0.5 * (lo + hi), 0.5 * (hi - lo));
        sum += h * x
            .iter()
            .zip(&w)
            .map(|(xi, wi)| {
                let u = c + h * xi;
                wi * 2.0 * u * f(u)
            })
            .sum::<f64>();
        hi = lo;
    }
    sum
}

/// `ierfc(x) = exp(-x^2) / sqrt(pi) - x erfc(x)`, `x >= 0` (0 where it
/// underflows).
fn ierfc(x: f64) -> f64 {
    if x > 26.0 {
        return 0.0;
    }
    (-x * x).exp() / std::f64::consts::PI.sqrt() - x * libm::erfc(x)
}

/// `1/4 - i2erfc(x) = Int_0^x ierfc`, `x >= 0`, without the cancellation
/// of the difference where `x` is small (layers far shallower than the
/// passage's diffusion length: below `x = 1e-8` the difference kept no
/// digit, and a block of 1e300 m had no background): below `x = 0.03`
/// its series `x / sqrt(pi) - x^2 / 2 + (x^3 / 3 - x^5 / 30 + x^7 / 210)
/// / sqrt(pi)`, whose next term is `x^8 / 1512` of it (5e-16 at 0.03,
/// where the difference has lost two digits, 1.5e-15).
fn quarter_less_i2erfc(x: f64) -> f64 {
    if x < 0.03 {
        let r = 1.0 / std::f64::consts::PI.sqrt();
        let x2 = x * x;
        return x * (r - 0.5 * x + x2 * r * (1.0 / 3.0 - x2 / 30.0 + x2 * x2 / 210.0));
    }
    0.25 - i2erfc(x)
}

/// `i2erfc(x) = (erfc(x) - 2 x ierfc(x)) / 4`, `x >= 0`.
fn i2erfc(x: f64) -> f64 {
    if x > 26.0 {
        return 0.0;
    }
    0.25 * (libm::erfc(x) - 2.0 * x * ierfc(x))
}

#[cfg(test)]
mod tests {
    use super::*;

    const RUBBER: Conduction = Conduction {
        conductivity: 0.25,
        diffusivity: 1e-7,
    };

    /// At the surface the quadrature reproduces the closed form (the
    /// panels' sum to 1e-13), and a thin layer at the surface carrying
    /// `Q h = qbar` the surface flux's background to `O(h / sqrt(kappa
    /// t_c))`.
    #[test]
    fn the_averages_meet_the_closed_form() {
        let (q, tc) = (3e3, 0.02);
        let exact = surface_background(q, &RUBBER, tc);
        let quad = passage_average(|u| {
            2.0 * q / RUBBER.conductivity * u * (RUBBER.diffusivity * tc).sqrt() * ierfc(0.0)
        });
        assert!((quad / exact - 1.0).abs() < 1e-13, "{quad} vs {exact}");
        let near = surface_background_at(q, 1e-12, &RUBBER, tc);
        assert!((near / exact - 1.0).abs() < 1e-6, "{near} vs {exact}");
        let reach = (RUBBER.diffusivity * tc).sqrt();
        for frac in [1e-3, 1e-4] {
            let h = frac * reach;
            let layers = DepthLayers::new(vec![0.0, h]).unwrap();
            let v = volume_background_at(&layers, &[q / h], 0.0, &RUBBER, tc);
            assert!(
                (v / exact - 1.0).abs() < 2.0 * frac,
                "{frac}: {v} vs {exact}"
            );
        }
    }

    /// A passage whose diffusion length dwarfs the layers (a block of
    /// 1e300 m, say): the layers' background is the surface flux's to
    /// `O(h / sqrt(kappa t_c))`, at their top and middle alike, not the
    /// zero of `1/4 - i2erfc(x)` formed as a difference at `x ~ 1e-18`;
    /// and the series below `x = 0.03` meets the difference above it.
    #[test]
    fn a_long_passage_keeps_the_layers_background() {
        let q = 3e3;
        let h = 1e-6;
        let layers = DepthLayers::new(vec![0.0, 0.25 * h, h]).unwrap();
        for tc in [1e3, 1e12, 1e30, 1e300] {
            let exact = surface_background(q, &RUBBER, tc);
            for z in [0.0, 0.5 * h] {
                let v = volume_background_at(&layers, &[q / h, q / h], z, &RUBBER, tc);
                let reach = (RUBBER.diffusivity * tc).sqrt();
                let bound = 1e-13_f64.max(4.0 * h / reach);
                assert!(
                    (v / exact - 1.0).abs() < bound,
                    "t_c {tc} z {z}: {v} vs {exact}"
                );
            }
        }
        for x in [0.0299, 0.03, 0.0301] {
            let diff = 0.25 - i2erfc(x);
            let series = {
                let r = 1.0 / std::f64::consts::PI.sqrt();
                let x2 = x * x;
                x * (r - 0.5 * x + x2 * r * (1.0 / 3.0 - x2 / 30.0 + x2 * x2 / 210.0))
            };
            assert!(
                (series / diff - 1.0).abs() < 3e-15,
                "{x}: {series} vs {diff}"
            );
            assert!((quarter_less_i2erfc(x) / diff - 1.0).abs() < 3e-15, "{x}");
        }
    }
}
