//! The dissipation density `D` of the creep elements under a periodic
//! pressure field (physics.md section 14).
//!
//! The creep law as Kelvin-Voigt elements in series with the glassy
//! spring, with the constant Poisson ratio of the Green's function
//! (physics.md section 3): `eps = (1 + nu) J * s - nu J * tr(s) I`, the
//! element `k` straining as `e_k + tau_k de_k/dt = C_k [(1 + nu) s - nu
//! tr(s) I]`. The dashpots dissipate
//! `D = sum_k tau_k C_k [(1 + nu) |dev r_k|^2 + (1 - 2 nu) / 3 (tr r_k)^2]`
//! with `r_k` the stress rate seen through element `k`: for the mode
//! `exp(i q.x)`, met at `w = -v (q.e_v)`, `r_k = i w / (1 + i w tau_k)
//! P(q) S(q, z)` ([`super::stress`]). For `nu = 0.5` this is section 14's
//! `(3/2) sum_k (tau_k / C_k) |d eps_k/dt|^2` with the deviatoric law; for
//! `nu < 0.5` the elements creep in volume too, as the Green's function
//! with a constant `nu` has them. Each mode's depth integral is
//! `2 (1 - nu^2) / |q| sum_k tau_k C_k w^2 / (1 + w^2 tau_k^2)`, its share
//! of `-F_T v` in the Fourier dissipation sum (Appendix A3-A4), so
//! `Int D dV = mu F_N v` mode by mode.
//!
//! The grid's modes are those of the periodic formulation
//! (`operator/periodic.rs`): the rates are the band-limited fields sampled
//! at the grid points (inverse FFTs) and squared there. Each mode's stress
//! is `f (s_0 + t s_1)` with `t = |q| z`, `f = exp(-t)` and `s_0`, `s_1`
//! fixed by its direction ([`super::stress::stress_at`]): one exponential
//! per mode and depth, shared by the elements; the transforms are planned
//! once and the layers run side by side, each on one thread. A Nyquist mode
//! samples both signs of its Nyquist components; the operator averages its
//! multiplier over them, and so does the main field here. The rest of
//! `mean_s |m_s|^2` (what the friction's mode sum counts) is carried by the
//! odd parts over the signs, `mean_s s m_s`, whose fields at the grid
//! points are `(-1)^i` times a one-dimensional transform; their squares
//! are added (`nyquist.rs`), so that the grid sum of `D` is the Fourier sum exactly
//! (discrete Parseval). `D >= 0`: a sum of squares with positive weights.
//!
//! The elements' multipliers are not transformed one by one: over the
//! grid's frequencies they span fewer dimensions than there are elements
//! (13-16 of the SBR-like rubber's 24), and `rank.rs` combines them into
//! that many orthonormal combinations whose forms sum to `D` within
//! `2e-15` of each mode's power.
//!
//! At depth only the modes with `|q| z <= 50` are not negligible
//! (`band.rs`): where their band fits a smaller grid along both axes, a
//! node's rates are transformed and squared on that coarser grid, summed
//! there over multipliers and forward transformed: the layer's
//! band-limited part, which the heat problem places in its spectrum
//! without a map ([`LayerDensity`]). Those nodes have no Nyquist modes in
//! their band. Sliding along
//! x, the multipliers depend on `kx` only and every node, on the full grid
//! or a coarser one, takes `separable.rs`: the transforms along y once per
//! component and depth, one real transform along x per row and
//! multiplier. Sliding along y is sliding along x on the transposed field
//! (`Dissipation::transposed`); oblique sliding takes the general path.

mod band;
mod form;
mod nyquist;
mod rank;
mod separable;

use std::sync::Arc;

use num_complex::Complex64;
use rayon::prelude::*;
use rustfft::{Fft, FftPlanner};

use super::super::density::LayerDensity;
use super::super::error::HeatError;
use band::coarse_sums;
use form::{accumulate, component, field_for};
pub(crate) use rank::RateFn;
use separable::SeparableWork;

use super::stress::unit_component;
use crate::operator::{nyquist_signs, signed_index};
use crate::response::{Grid, SlidingResponse};
use crate::surface::height_fft;

/// The dissipation density of a periodic pressure field, planned once:
/// the pressure's spectrum, the creep elements and the transforms.
pub(crate) struct Dissipation {
    nx: usize,
    ny: usize,
    length: (f64, f64),
    e: (f64, f64),
    speed: f64,
    nu: f64,
    /// `(C_k, tau_k)` of every element with `C_k > 0` (the tests' direct
    /// sums; the density takes `rates`).
    #[cfg_attr(not(test), allow(dead_code))]
    elements: Vec<(f64, f64)>,
    /// The elements' multipliers combined over the grid's frequencies
    /// (`rank.rs`).
    rates: Vec<RateFn>,
    /// Half spectrum of the pressure (`height_fft` layout), divided by
    /// `nx ny`.
    spectrum: Vec<Complex64>,
    /// Every mode of the half spectrum that is neither `q = 0` nor a
    /// Nyquist mode, with its pressure coefficient.
    regular: Vec<Regular>,
    fft: height_fft::Inverse,
    line_x: Arc<dyn Fft<f64>>,
    line_y: Arc<dyn Fft<f64>>,
    /// Whether sliding along x takes the separable path (the general one
    /// is the tests' reference).
    separable: bool,
}

/// A mode with one wavevector: its index in the half spectrum, `|q|`, the
/// direction `q / |q|`, the frequency `w = -v (q.e_v)` and `P(q) / N`.
#[derive(Clone, Copy)]
struct Regular {
    index: usize,
    n: (f64, f64),
    k: f64,
    w: f64,
    p: Complex64,
}

/// `(C_k, tau_k)` of every creep element of `response`'s material with
/// `C_k > 0` (those that dissipate).
fn creep_elements(response: &SlidingResponse) -> Vec<(f64, f64)> {
    response
        .material()
        .spectrum
        .terms
        .iter()
        .filter(|t| t.compliance > 0.0)
        .map(|t| (t.compliance, t.time))
        .collect()
}

/// One thread's work space.
struct Work {
    spec: Vec<Complex64>,
    field: Vec<f64>,
    first: Vec<f64>,
    amp: Vec<Complex64>,
    t: Vec<f64>,
    /// The inverse transform's work space.
    rows: Vec<Complex64>,
}

impl Dissipation {
    /// Plan `pressure` \[Pa\] on the periodic `grid` under `response`; a
    /// layer is refused (its stress field is not the half-space's), as is
    /// an infinite speed.
    pub fn new(
        pressure: &[f64],
        grid: &Grid,
        response: &SlidingResponse,
    ) -> Result<Self, HeatError> {
        if response.layer().is_some() {
            return Err(HeatError::Unsupported(
                "the dissipation density is solved on a half-space; for a layer use the surface work flux (source = surface)",
            ));
        }
        let (nx, ny) = grid.size();
        let mut spectrum = height_fft::forward(pressure, nx, ny).map_err(transform_error)?;
        let scale = 1.0 / (nx * ny) as f64;
        spectrum.iter_mut().for_each(|c| *c *= scale);
        let elements = creep_elements(response);
        let (e, speed) = (response.direction(), response.speed());
        let rates = rank::combined_rates(&elements, &frequencies(grid, e, speed))?;
        Ok(Self::planned(
            (nx, ny),
            grid.lengths(),
            e,
            speed,
            response.poisson(),
            elements,
            rates,
            spectrum,
        ))
    }

    /// The plan of the half spectrum `spectrum` (divided by `nx ny`) on
    /// an `nx x ny` grid of periods `length` \[m\], sliding along `e` at
    /// `speed`, with the elements and their combined multipliers.
    #[allow(clippy::too_many_arguments)]
    fn planned(
        (nx, ny): (usize, usize),
        length: (f64, f64),
        e: (f64, f64),
        speed: f64,
        nu: f64,
        elements: Vec<(f64, f64)>,
        rates: Vec<RateFn>,
        spectrum: Vec<Complex64>,
    ) -> Self {
        let tau2 = std::f64::consts::TAU;
        let regular = (0..(ny / 2 + 1) * nx)
            .filter_map(|index| {
                let (i, j) = (index % nx, index / nx);
                let (kx, nyq_x) = signed_index(i, nx);
                let (ky, nyq_y) = signed_index(j, ny);
                if (i == 0 && j == 0) || nyq_x || nyq_y {
                    return None;
                }
                let q = (tau2 * kx / length.0, tau2 * ky / length.1);
                let k = q.0.hypot(q.1);
                Some(Regular {
                    index,
                    n: (q.0 / k, q.1 / k),
                    k,
                    w: -speed * (q.0 * e.0 + q.1 * e.1),
                    p: spectrum[index],
                })
            })
            .collect();
        let mut planner = FftPlanner::<f64>::new();
        Self {
            nx,
            ny,
            length,
            e,
            speed,
            nu,
            elements,
            rates,
            spectrum,
            regular,
            fft: height_fft::Inverse::new(nx, ny),
            line_x: planner.plan_fft_inverse(nx),
            line_y: planner.plan_fft_inverse(ny),
            separable: true,
        }
    }

    /// `P(kx, ky) / N` of the real pressure (`ky < 0` by its Hermitian
    /// symmetry).
    fn coefficient(&self, kx: isize, ky: isize) -> Complex64 {
        if ky >= 0 {
            self.half_coefficient(kx, ky)
        } else {
            self.half_coefficient(-kx, -ky).conj()
        }
    }

    /// The half spectrum's coefficient at `(kx, ky >= 0)`.
    fn half_coefficient(&self, kx: isize, ky: isize) -> Complex64 {
        let i = kx.rem_euclid(self.nx as isize) as usize;
        self.spectrum[ky as usize * self.nx + i]
    }

    /// Whether the sliding is along y (`e_v = (0, 1)` or `(0, -1)`).
    fn along_y(&self) -> bool {
        self.e.0 == 0.0
    }

    /// The plan of the field transposed (x and y swapped: the pressure
    /// `p'(x, y) = p(y, x)`, its half spectrum `P'(kx, ky) = P(ky, kx)`),
    /// sliding along the swapped direction: sliding along y becomes
    /// sliding along x. The dissipation form does not depend on the axes'
    /// order, so its density is this plan's transposed.
    fn transposed(&self) -> Self {
        let (nx, ny) = (self.ny, self.nx);
        // Index `(i, j)` of the swapped grid is `(kx, ky) = (j, i)` here
        // (`j <= ny / 2`: a non-negative `kx`).
        let spectrum: Vec<Complex64> = (0..(ny / 2 + 1) * nx)
            .map(|index| {
                let ky = signed_index(index % nx, self.ny).0 as isize;
                self.coefficient((index / nx) as isize, ky)
            })
            .collect();
        let mut plan = Self::planned(
            (nx, ny),
            (self.length.1, self.length.0),
            (self.e.1, self.e.0),
            self.speed,
            self.nu,
            self.elements.clone(),
            self.rates.clone(),
            spectrum,
        );
        plan.separable = self.separable;
        plan
    }

    /// The multipliers whose dissipation forms sum to `D`: one per
    /// element, `sqrt(tau_k C_k) i w / (1 + i w tau_k)` (the sums
    /// `rank.rs` combines).
    #[cfg(test)]
    fn element_rates(&self) -> Vec<RateFn> {
        self.elements
            .iter()
            .map(|&(c, tau)| RateFn(vec![((tau * c).sqrt(), tau)]))
            .collect()
    }

    /// The weighted sums `sum_n w_n D(z_n)` \[W/m^3\] over each layer's
    /// nodes `(z_n, w_n)` (a layer average by a Gauss rule, or one node
    /// of weight 1, as [`super::HeatSource::from_contact`] asks for each of
    /// its layers): layer `l`'s map at `[l * nx * ny..(l + 1) * nx * ny]`.
    /// `stop` is asked before each depth node (sliding along an axis) or
    /// multiplier (otherwise): `true` gives up with [`HeatError::Cancelled`].
    pub fn layer_densities_until(
        &self,
        nodes: &[Vec<(f64, f64)>],
        stop: &mut dyn FnMut() -> bool,
    ) -> Result<LayerDensity, HeatError> {
        self.densities_with(&self.rates, nodes, stop)
    }

    /// [`Dissipation::layer_densities_until`] as the sum over the
    /// multipliers `rates`.
    fn densities_with(
        &self,
        rates: &[RateFn],
        nodes: &[Vec<(f64, f64)>],
        stop: &mut dyn FnMut() -> bool,
    ) -> Result<LayerDensity, HeatError> {
        let n = self.nx * self.ny;
        if self.separable && self.along_y() && self.speed != 0.0 {
            // Sliding along y: along x on the transposed field (its coarse
            // parts brought onto the grid to be transposed with it).
            let swapped = self.transposed().densities_with(rates, nodes, stop)?;
            let swapped = swapped.maps()?;
            let density = swapped
                .chunks(n)
                .map(|map| {
                    let mut out = vec![0.0; n];
                    height_fft::transpose_into(map, self.ny, self.nx, &mut out);
                    out
                })
                .collect();
            return Ok(LayerDensity::from_layer_maps(density, (self.nx, self.ny)));
        }
        if self.speed == 0.0 || !self.speed.is_finite() {
            let zeros = vec![vec![0.0; n]; nodes.len()];
            return Ok(LayerDensity::from_layer_maps(zeros, (self.nx, self.ny)));
        }
        let separable = self.separable && self.along_x();
        let (grids, plans) = self.coarse_plans(nodes, !separable);
        // A map for each layer with a node on the full grid (the others
        // are their coarse nodes' band-limited parts alone).
        let mut density: Vec<Vec<f64>> = plans
            .iter()
            .map(|l| l.iter().any(Option::is_none))
            .map(|full| if full { written_zeros(n) } else { Vec::new() })
            .collect();
        let mut coarse = coarse_sums(&grids, &plans);
        // Sliding along x: every node by `separable.rs`, one after the
        // other (each one's transforms run on the pool), on the full grid
        // or its coarse one.
        if separable {
            let full = self.full_columns();
            let mut work = SeparableWork::default();
            let mut spare = Vec::new();
            for (((out, nodes), plans), coarse) in
                density.iter_mut().zip(nodes).zip(&plans).zip(&mut coarse)
            {
                for ((&(z, weight), plan), acc) in nodes.iter().zip(plans).zip(coarse) {
                    stopped(stop)?;
                    match plan {
                        None => self.add_separable(&full, rates, z, weight, &mut work, out)?,
                        Some(c) => {
                            let band = self.band_columns(grids[c.grid].size, c.band, spare);
                            self.add_separable(&band, rates, z, weight, &mut work, acc)?;
                            spare = band.recycle();
                        }
                    }
                }
            }
        }
        // The general path: per multiplier, `rate(w) P / N` of every regular
        // mode, shared by the depths.
        let mut values = vec![Complex64::default(); self.regular.len()];
        for rate in rates.iter().filter(|_| !separable) {
            stopped(stop)?;
            values.par_iter_mut().zip(&self.regular).for_each(|(v, m)| {
                *v = rate.at(m.w) * m.p;
            });
            density
                .par_iter_mut()
                .zip(nodes.par_iter())
                .zip(plans.par_iter())
                .zip(coarse.par_iter_mut())
                .try_for_each_init(
                    || None,
                    |work: &mut Option<Work>, (((out, nodes), plans), coarse)| {
                        for ((&(z, weight), plan), acc) in nodes.iter().zip(plans).zip(coarse) {
                            match plan {
                                None => {
                                    let work = work.get_or_insert_with(|| self.work());
                                    self.add_density(rate, &values, z, weight, work, out)?
                                }
                                Some(c) => {
                                    self.add_coarse(&values, c, &grids[c.grid], z, weight, acc)?
                                }
                            }
                        }
                        Ok::<(), HeatError>(())
                    },
                )?;
        }
        let bands = self.band_parts(&grids, &plans, &coarse)?;
        let maps = density.into_iter().map(|m| (!m.is_empty()).then_some(m));
        Ok(LayerDensity::with_bands(
            (self.nx, self.ny),
            maps.collect(),
            bands,
        ))
    }

    fn work(&self) -> Work {
        let (n, nh) = (self.nx * self.ny, self.nx * (self.ny / 2 + 1));
        Work {
            spec: vec![Complex64::default(); nh],
            field: vec![0.0; n],
            first: vec![0.0; n],
            amp: vec![Complex64::default(); self.regular.len()],
            t: vec![0.0; self.regular.len()],
            rows: Vec::new(),
        }
    }

    /// `out += weight D_rate(z)`: the dissipation form of the stress-rate
    /// field of `rate` at depth `z`, its Nyquist odd parts included.
    fn add_density(
        &self,
        rate: &RateFn,
        values: &[Complex64],
        z: f64,
        weight: f64,
        work: &mut Work,
        out: &mut [f64],
    ) -> Result<(), HeatError> {
        let nu = self.nu;
        // `rate P f` and `t` of every regular mode; the stresses follow
        // component by component.
        for (((m, v), amp), t) in self
            .regular
            .iter()
            .zip(values)
            .zip(&mut work.amp)
            .zip(&mut work.t)
        {
            *t = m.k * z;
            *amp = v * (-*t).exp();
        }
        let nyquist = self.nyquist_parts(rate, z);
        // The five deviatoric components, then the trace (whose weight
        // `(1 - 2 nu) / 3` vanishes for `nu = 0.5`).
        let count = if nu == 0.5 { 5 } else { 6 };
        let (dev, trace) = (weight * (1.0 + nu), weight * (1.0 - 2.0 * nu) / 3.0);
        for c in 0..count {
            // Every entry is written below but `q = 0`'s (the transform
            // consumed the last component's).
            work.spec[0] = Complex64::default();
            for ((m, amp), &t) in self.regular.iter().zip(&work.amp).zip(&work.t) {
                work.spec[m.index] = *amp * unit_component(m.n, t, nu, c);
            }
            if self.nx % 2 == 0 {
                for (j, p) in nyquist.row.iter().enumerate() {
                    work.spec[j * self.nx + self.nx / 2] = component(&p.mean, c);
                }
            }
            if self.ny % 2 == 0 {
                for (i, p) in nyquist.column.iter().enumerate() {
                    work.spec[(self.ny / 2) * self.nx + i] = component(&p.mean, c);
                }
            }
            let into = field_for(c, &mut work.field, &mut work.first);
            self.fft
                .run(&mut work.spec, &mut work.rows, into)
                .map_err(transform_error)?;
            accumulate(c, &work.field, &work.first, out, dev, trace);
        }
        self.add_nyquist(&nyquist, weight, out);
        Ok(())
    }

    /// The mean over the cell of `Int D dz` \[W/m^2\] in closed form:
    /// `sum_q |P(q) / N|^2 2 (1 - nu^2) / |q| sum_k tau_k C_k w^2 / (1 +
    /// w^2 tau_k^2)` over every mode (Nyquist modes averaged over their
    /// signs).
    #[cfg(test)]
    pub fn exact_power_per_area(&self) -> f64 {
        let (nx, ny) = (self.nx, self.ny);
        let nyh = ny / 2 + 1;
        if self.speed == 0.0 || !self.speed.is_finite() {
            return 0.0;
        }
        let tau2 = std::f64::consts::TAU;
        (0..nyh * nx)
            .into_par_iter()
            .map(|k| {
                let (i, j) = (k % nx, k / nx);
                if i == 0 && j == 0 {
                    return 0.0;
                }
                let (kx, nyq_x) = signed_index(i, nx);
                let (ky, nyq_y) = signed_index(j, ny);
                let sx = nyquist_signs(nyq_x);
                let sy = nyquist_signs(nyq_y);
                let mut w_sum = 0.0;
                for &a in sx {
                    for &b in sy {
                        let q = (a * tau2 * kx / self.length.0, b * tau2 * ky / self.length.1);
                        let w = -self.speed * (q.0 * self.e.0 + q.1 * self.e.1);
                        let creep: f64 = self
                            .elements
                            .iter()
                            .map(|&(c, tau)| tau * c * w * w / (1.0 + w * w * tau * tau))
                            .sum();
                        w_sum += 2.0 * (1.0 - self.nu * self.nu) / q.0.hypot(q.1) * creep;
                    }
                }
                let weight = crate::operator::column_weight(j, ny);
                weight * self.spectrum[k].norm_sqr() * w_sum / (sx.len() * sy.len()) as f64
            })
            .sum::<f64>()
    }
}

/// Every `|w| = v |q.e_v|` \[rad/s\] the grid's modes meet, the signs of
/// the Nyquist components included, sorted, without repeats.
fn frequencies(grid: &Grid, e: (f64, f64), speed: f64) -> Vec<f64> {
    let (nx, ny) = grid.size();
    let length = grid.lengths();
    let tau2 = std::f64::consts::TAU;
    let mut freqs: Vec<f64> = (0..(ny / 2 + 1) * nx)
        .into_par_iter()
        .flat_map_iter(|index| {
            let (kx, nyq_x) = signed_index(index % nx, nx);
            let (ky, nyq_y) = signed_index(index / nx, ny);
            let sx = nyquist_signs(nyq_x);
            let sy = nyquist_signs(nyq_y);
            sx.iter().flat_map(move |a| {
                sy.iter().map(move |b| {
                    let q = (a * tau2 * kx / length.0, b * tau2 * ky / length.1);
                    (speed * (q.0 * e.0 + q.1 * e.1)).abs()
                })
            })
        })
        .collect();
    freqs.par_sort_unstable_by(f64::total_cmp);
    freqs.dedup();
    freqs
}

/// [`HeatError::Cancelled`] where `stop` says so.
fn stopped(stop: &mut dyn FnMut() -> bool) -> Result<(), HeatError> {
    if stop() {
        return Err(HeatError::Cancelled);
    }
    Ok(())
}

/// `len` zeros, written now rather than left to the kernel's zero page:
/// a map that is then added to (`+=`, its first access a read) would map
/// the shared zero page on the read and fault again on the write, a
/// fault that flushes the page from every thread's TLB. Written first,
/// each page faults once. The density maps (hundreds of MB at 1024^2)
/// took a fifth of an evaluation in those second faults.
pub(super) fn written_zeros(len: usize) -> Vec<f64> {
    let mut v = Vec::with_capacity(len);
    v.resize(len, 0.0);
    v
}

/// A failed transform of `height_fft`.
fn transform_error(e: crate::surface::SurfaceError) -> HeatError {
    HeatError::Transform(e.to_string())
}

#[cfg(test)]
mod tests;
