//! The temperature each scale of a periodic contact dissipates at
//! (physics.md section 14, "Feedback (closure)"): the effective
//! temperature taken apart by the surface modes whose dissipation it
//! weights.
//!
//! The volume source's grid sum at depth `z` is a sum over the surface
//! modes (discrete Parseval, `dissipation/`): `sum_q c_q phi(|q| z)`, with
//! `c_q = |P(q)|^2 R(w_q)`, `R(w) = sum_k tau_k C_k w^2 / (1 + w^2
//! tau_k^2)` (the dashpots' power at the frequency `w = -v q.e_v` the mode
//! is met with, averaged over a Nyquist mode's signs) and `phi(t) =
//! exp(-2 t) H(t)` the dissipation form of the unit mode's stress
//! (`stress.rs`), `H` a quadratic in `t = |q| z` that does not depend on
//! the mode's direction. On the source's layers (each Gauss node's share of
//! its panel, [`DepthRule`]) mode `q` puts `c_q h_l phi(|q| z_l)` into layer
//! `l` (`z_l` the node), where the heat problem gives the
//! dissipation-weighted rise `theta_l = sum theta Q / sum Q` (the block's
//! background included). The rise at which mode `q` dissipates is
//! `theta_l` weighted by the mode's own dissipation over the layers,
//!
//! `theta(q) = sum_l theta_l h_l phi(|q| z_l) / sum_l h_l phi(|q| z_l)`,
//!
//! the temperature of physics.md's per-scale closure ("mode `k` sees the
//! temperature weighted by the dissipation at the depths where that mode
//! dissipates"). Weighted by each mode's power `c_q sum_l h_l phi(|q| z_l)`
//! these average to the effective rise `Theta` exactly (the layers' powers
//! are the modes' sums), so the scales' temperatures are `T_eff` taken
//! apart: small scales, dissipating near the surface under the contact
//! spots, see the flash temperature; long ones, deep, the background. They
//! are reported by octaves of `|q|`, each with its share of the power.

use num_complex::Complex64;
use rayon::prelude::*;

use super::super::error::HeatError;
use super::depth::DepthRule;
use super::stress::{dissipation_form, unit_component};
use crate::operator::{column_weight, nyquist_signs, signed_index};
use crate::response::{Grid, SlidingResponse};
use crate::surface::height_fft;

/// Beyond `2 |q| z` of this, `exp(-2 |q| z)` is below `1e-35` of the
/// mode's surface value: the deeper layers take none of its power.
const DEEPEST_EXPONENT: f64 = 80.0;

/// An octave's share of the power below which it holds only the
/// transforms' round-off (a pressure without modes there) and is left out.
const ROUND_OFF_SHARE: f64 = 1e-14;

/// One octave of wavenumbers and the rise at which it dissipates.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct ScaleBand {
    /// The octave's lowest wavenumber `|q|` \[1/m\] (included).
    pub wavenumber_min: f64,
    /// Its highest \[1/m\] (excluded; twice the lowest).
    pub wavenumber_max: f64,
    /// Its modes' share of the dissipated power.
    pub power_share: f64,
    /// The rise at which its modes dissipate \[K\] (module docs).
    pub rise: f64,
}

/// The octaves of `|q|` (from the cell's fundamental, `2 pi / max(L_x,
/// L_y)`) of the pressure `pressure` \[Pa\] solved on the periodic `grid`
/// under `response`, and the rise at which each dissipates, from the
/// source's layers of `rule` and each layer's `(h_l sum theta Q, h_l sum
/// Q)` (`layers`, as the heat problem sums them). Octaves without power
/// (below [`ROUND_OFF_SHARE`] of it) are left out; the shares sum to 1 and
/// the rises, weighted by them, to the effective rise (module docs), both
/// to that round-off.
pub(crate) fn scale_rises(
    pressure: &[f64],
    grid: &Grid,
    response: &SlidingResponse,
    rule: &DepthRule,
    layers: &[(f64, f64)],
) -> Result<Vec<ScaleBand>, HeatError> {
    let (fundamental, sums) = band_sums(pressure, grid, response, rule, layers)?;
    let total: f64 = sums.iter().map(|s| s.1).sum();
    if total.is_nan() || total <= 0.0 {
        return Ok(Vec::new());
    }
    Ok(sums
        .iter()
        .enumerate()
        .filter(|(_, s)| s.1 > ROUND_OFF_SHARE * total)
        .map(|(b, &(weighted, power))| {
            let low = fundamental * 2f64.powi(b as i32);
            ScaleBand {
                wavenumber_min: low,
                wavenumber_max: 2.0 * low,
                power_share: power / total,
                rise: weighted / power,
            }
        })
        .collect())
}

/// The octaves' sums `(sum_q c_q sum_l theta_l h_l phi_l, sum_q c_q sum_l
/// h_l phi_l)` over their modes, from the fundamental (returned first).
fn band_sums(
    pressure: &[f64],
    grid: &Grid,
    response: &SlidingResponse,
    rule: &DepthRule,
    layers: &[(f64, f64)],
) -> Result<(f64, Vec<(f64, f64)>), HeatError> {
    let per_layer = layer_terms(grid, rule, layers)?;
    let (nx, ny) = grid.size();
    let (lx, ly) = grid.lengths();
    let tau2 = std::f64::consts::TAU;
    let fundamental = tau2 / lx.max(ly);
    let spectrum =
        height_fft::forward(pressure, nx, ny).map_err(|e| HeatError::Transform(e.to_string()))?;
    let (e, speed) = (response.direction(), response.speed());
    // `R(w) = sum_k tau_k C_k w^2 / (1 + w^2 tau_k^2) = -w J''(w)`.
    let spectrum_j = &response.material().spectrum;
    let power_at = |w: f64| -> f64 { -w * spectrum_j.compliance(w).im };
    let form = unit_form(response.poisson());
    let nh = ny / 2 + 1;
    let bands = (0..nh)
        .into_par_iter()
        .fold(Vec::<(f64, f64)>::new, |mut bands, j| {
            let (ky, nyq_y) = signed_index(j, ny);
            let weight = column_weight(j, ny);
            for i in 0..nx {
                let (kx, nyq_x) = signed_index(i, nx);
                if i == 0 && j == 0 {
                    continue;
                }
                let q = (tau2 * kx / lx, tau2 * ky / ly);
                let k = q.0.hypot(q.1);
                let (sx, sy) = (nyquist_signs(nyq_x), nyquist_signs(nyq_y));
                let mut r = 0.0;
                for a in sx {
                    for b in sy {
                        r += power_at(-speed * (a * q.0 * e.0 + b * q.1 * e.1));
                    }
                }
                let c = weight * spectrum[j * nx + i].norm_sqr() * r / (sx.len() * sy.len()) as f64;
                if c == 0.0 {
                    continue;
                }
                let (mut weighted, mut power) = (0.0, 0.0);
                for &(z, h, theta) in &per_layer {
                    let t = k * z;
                    if 2.0 * t > DEEPEST_EXPONENT {
                        break;
                    }
                    let d = h * (-2.0 * t).exp() * (form[0] + t * (form[1] + t * form[2]));
                    power += d;
                    weighted += d * theta;
                }
                let b = band_of(k, fundamental);
                if bands.len() <= b {
                    bands.resize(b + 1, (0.0, 0.0));
                }
                bands[b].0 += c * weighted;
                bands[b].1 += c * power;
            }
            bands
        })
        .reduce(Vec::new, |mut a, b| {
            if a.len() < b.len() {
                a.resize(b.len(), (0.0, 0.0));
            }
            a.iter_mut().zip(&b).for_each(|(x, y)| {
                x.0 += y.0;
                x.1 += y.1;
            });
            a
        });
    Ok((fundamental, bands))
}

/// The octave of `|q| = k` counted from `fundamental`: a ratio within
/// round-off of a power of two counts in the octave it starts.
fn band_of(k: f64, fundamental: f64) -> usize {
    let ratio = k / fundamental;
    // Exact powers of two land on their own octave's lower edge.
    (ratio * (1.0 + 4.0 * f64::EPSILON)).log2().floor().max(0.0) as usize
}

/// Each source layer's node depth `z_l` \[m\], thickness `h_l` \[m\] and
/// dissipation-weighted rise `theta_l` \[K\] (0 where the layer has no
/// power), from `layers` (`(h_l sum theta Q, h_l sum Q)`).
fn layer_terms(
    grid: &Grid,
    rule: &DepthRule,
    layers: &[(f64, f64)],
) -> Result<Vec<(f64, f64, f64)>, HeatError> {
    let (source_layers, nodes) = rule.source_layers(grid)?;
    if source_layers.count() != layers.len() {
        return Err(HeatError::Layers(format!(
            "{} layers of heat against {} of the depth rule",
            layers.len(),
            source_layers.count()
        )));
    }
    Ok(source_layers
        .iter()
        .zip(&nodes)
        .zip(layers)
        .map(|(((a, b), &z), &(weighted, power))| {
            let theta = if power > 0.0 { weighted / power } else { 0.0 };
            (z, b - a, theta)
        })
        .collect())
}

/// The coefficients `[H_0, H_1, H_2]` of `H(t) = H_0 + H_1 t + H_2 t^2`,
/// the dissipation form of the unit mode's stress divided by `exp(-2 t)`
/// (the form of its real part plus that of its imaginary part; the same
/// for every direction, the form being invariant under rotations about z).
fn unit_form(nu: f64) -> [f64; 3] {
    let h = |t: f64| {
        let c: Vec<Complex64> = (0..6)
            .map(|c| unit_component((1.0, 0.0), t, nu, c))
            .collect();
        let part = |f: fn(&Complex64) -> f64| {
            let dev = [f(&c[0]), f(&c[1]), f(&c[2]), f(&c[3]), f(&c[4])];
            dissipation_form(&dev, f(&c[5]), nu)
        };
        part(|v| v.re) + part(|v| v.im)
    };
    let (h0, h1, h2) = (h(0.0), h(1.0), h(2.0));
    let second = 0.5 * (h2 - 2.0 * h1 + h0);
    [h0, h1 - h0 - second, second]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::heat::source::stress::mode_stress;

    /// `H` is the form of the stress of a mode in any direction.
    #[test]
    fn the_unit_form_is_the_stress_form_in_every_direction() {
        for nu in [0.5, 0.3, -0.2] {
            let h = unit_form(nu);
            for q in [(3.0, 4.0), (-2.0, 0.5), (0.0, 1.0)] {
                let k = f64::hypot(q.0, q.1);
                for t in [0.0, 0.3, 1.7, 6.0] {
                    let s = mode_stress(q, t / k, nu);
                    let part = |f: fn(&Complex64) -> f64| {
                        dissipation_form(&s.dev.map(|c| f(&c)), f(&s.trace), nu)
                    };
                    let want = part(|c| c.re) + part(|c| c.im);
                    let got = (-2.0 * t).exp() * (h[0] + t * (h[1] + t * h[2]));
                    let scale = h.iter().map(|c| c.abs()).sum::<f64>();
                    assert!(
                        (got - want).abs() <= 1e-14 * scale,
                        "{nu} {q:?} {t}: {got} {want}"
                    );
                }
            }
        }
    }

    use crate::heat::{Conduction, HeatDomain, HeatSetup, HeatSolver, HeatSource, SourceKind};
    use crate::material::{CreepSpectrum, Material};

    const CELL: f64 = 2e-6;
    const SPEED: f64 = 0.05;

    fn response(direction_rad: f64) -> SlidingResponse {
        let material = Material::new(
            CreepSpectrum::standard_linear_solid(3.3e6, 1e7, 1e-4).unwrap(),
            0.5,
        )
        .unwrap();
        SlidingResponse::new(&material, SPEED, direction_rad, None).unwrap()
    }

    /// The octaves, the layers' `(h_l sum theta Q, h_l sum Q)` and the
    /// effective rise of `pressure` on a periodic `nx x ny` grid heated
    /// with a block of 1 cm.
    fn heated(
        pressure: &[f64],
        (nx, ny): (usize, usize),
        direction_rad: f64,
    ) -> (Vec<ScaleBand>, Vec<(f64, f64)>, f64) {
        let grid = Grid::new(nx, ny, (CELL, 1.5 * CELL)).unwrap().periodic();
        let r = response(direction_rad);
        let rule = DepthRule::default();
        let source =
            HeatSource::from_contact(SourceKind::Volume, pressure, &grid, &r, &rule).unwrap();
        let mut solver = HeatSolver::new(HeatSetup {
            grid,
            conduction: Conduction {
                conductivity: 0.25,
                diffusivity: 1e-7,
            },
            speed: SPEED,
            direction_rad,
            domain: HeatDomain::Periodic {
                block_length: Some(0.01),
            },
        })
        .unwrap();
        let under = solver.under_with(&source, None).unwrap();
        let layers = under.layers.unwrap();
        let bands = scale_rises(pressure, &grid, &r, &rule, &layers).unwrap();
        (bands, layers, under.weighted)
    }

    /// The dissipation of the unit mode `q` summed over the source's layers
    /// with the weights `weight(l)`, from `mode_stress` (not `unit_form`).
    fn over_layers(q: (f64, f64), nx: usize, ny: usize, weight: impl Fn(usize) -> f64) -> f64 {
        let grid = Grid::new(nx, ny, (CELL, 1.5 * CELL)).unwrap().periodic();
        let (layers, nodes) = DepthRule::default().source_layers(&grid).unwrap();
        layers
            .iter()
            .zip(&nodes)
            .enumerate()
            .map(|(l, ((a, b), &z))| {
                let s = mode_stress(q, z, 0.5);
                let part = |f: fn(&Complex64) -> f64| {
                    dissipation_form(&s.dev.map(|c| f(&c)), f(&s.trace), 0.5)
                };
                weight(l) * (b - a) * (part(|c| c.re) + part(|c| c.im))
            })
            .sum()
    }

    /// A pressure of two cosines (and a mean): each octave holding one of
    /// them has all its power, in the share of the two modes' powers
    /// `|P|^2 R(w) sum_l h_l phi` and at the layers' rises weighted by
    /// its own `phi`, both summed here from the stresses; the shares weight
    /// the rises to the effective rise. Along x and oblique.
    #[test]
    fn two_modes_dissipate_in_their_octaves_at_their_own_depths() {
        let (nx, ny) = (32, 24);
        let (lx, ly) = (nx as f64 * CELL, ny as f64 * 1.5 * CELL);
        // Wavenumbers 3 along x (octave 1 of the fundamental 2 pi / lx)
        // and (1, 9) (|q| about 10.1 of them: octave 3).
        let modes = [((3, 0), 4e4), ((1, 9), 2.5e4)];
        let pressure: Vec<f64> = (0..nx * ny)
            .map(|c| {
                let (x, y) = ((c / ny) as f64 * CELL, (c % ny) as f64 * 1.5 * CELL);
                1e5 + modes
                    .iter()
                    .map(|&((i, j), a)| {
                        let arg = std::f64::consts::TAU * (i as f64 * x / lx + j as f64 * y / ly);
                        a * arg.cos()
                    })
                    .sum::<f64>()
            })
            .collect();
        for direction in [0.0, 0.6] {
            let (bands, layers, effective) = heated(&pressure, (nx, ny), direction);
            let r = response(direction);
            let e = r.direction();
            let tau2 = std::f64::consts::TAU;
            let fundamental = tau2 / lx.max(ly);
            let theta = |l: usize| {
                let (w, p) = layers[l];
                if p > 0.0 {
                    w / p
                } else {
                    0.0
                }
            };
            let mut powers = Vec::new();
            for &((i, j), a) in &modes {
                let q = (tau2 * i as f64 / lx, tau2 * j as f64 / ly);
                let k = q.0.hypot(q.1);
                let w = -SPEED * (q.0 * e.0 + q.1 * e.1);
                let t = r.material().spectrum.terms[0];
                let rate = t.time * t.compliance * w * w / (1.0 + w * w * t.time * t.time);
                let total = over_layers(q, nx, ny, |_| 1.0);
                let rise = over_layers(q, nx, ny, theta) / total;
                let octave = (k / fundamental).log2().floor() as usize;
                let band = bands
                    .iter()
                    .find(|b| b.wavenumber_min <= k && k < b.wavenumber_max)
                    .expect("the mode's octave");
                assert!(
                    (band.wavenumber_min / (fundamental * 2f64.powi(octave as i32)) - 1.0).abs()
                        < 1e-15
                );
                assert!((band.rise / rise - 1.0).abs() < 1e-12, "{band:?} {rise}");
                powers.push(a * a * rate * total);
            }
            assert_eq!(bands.len(), 2, "{bands:?}");
            let share = powers[0] / (powers[0] + powers[1]);
            assert!(
                (bands[0].power_share / share - 1.0).abs() < 1e-12,
                "{bands:?} {share}"
            );
            let mean: f64 = bands.iter().map(|b| b.power_share * b.rise).sum();
            assert!((mean / effective - 1.0).abs() < 1e-12, "{mean} {effective}");
            // The long mode reaches deeper, where the block's background
            // is cooler than the flash under the short one.
            assert!(bands[0].rise != bands[1].rise);
        }
    }

    /// On a rough pressure with odd and even sides (Nyquist modes) the
    /// octaves' rises, weighted by their shares, are the effective rise:
    /// the modes' sums over the layers are the layers' powers.
    #[test]
    fn the_octaves_average_to_the_effective_rise() {
        for (nx, ny) in [(40, 30), (33, 21)] {
            let pressure: Vec<f64> = (0..nx * ny)
                .map(|c| {
                    if (c * 7919) % 13 < 3 {
                        1e6 * (1 + c % 5) as f64
                    } else {
                        0.0
                    }
                })
                .collect();
            for direction in [0.0, 0.4, std::f64::consts::FRAC_PI_2] {
                let (bands, _, effective) = heated(&pressure, (nx, ny), direction);
                assert!(bands.len() >= 4, "{bands:?}");
                let shares: f64 = bands.iter().map(|b| b.power_share).sum();
                let mean: f64 = bands.iter().map(|b| b.power_share * b.rise).sum();
                assert!((shares - 1.0).abs() < 1e-13, "{shares}");
                assert!(
                    (mean / effective - 1.0).abs() < 1e-12,
                    "{nx}x{ny} {direction}: {mean} {effective}"
                );
            }
        }
    }

    #[test]
    fn octaves_start_at_the_fundamental() {
        assert_eq!(band_of(1.0, 1.0), 0);
        assert_eq!(band_of(1.99, 1.0), 0);
        assert_eq!(band_of(2.0, 1.0), 1);
        assert_eq!(band_of(3.0 * 0.1, 0.1), 1);
        assert_eq!(band_of(4.0 * 0.1, 0.1), 2);
    }
}
