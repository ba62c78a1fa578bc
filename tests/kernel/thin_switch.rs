//! The switches between the thin-layer kernels (physics.md section 3,
//! "Finite thickness"): the local limit of `kernel/thin.rs` and its law
//! (`kernel/thin_law.rs`) below `R h = a/2`, the law's continuation on the
//! grid (`kernel/thin_band.rs`) up to `h = a` for a layer without local
//! compliance, the resolved cell integral above. Each route against the
//! exact spectral layer (the periodic operator: each mode's closed-form
//! multiplier, independent of the tables) on smooth pressures, h/a swept
//! across both switches, and the coefficients of the two routes compared
//! at each switch.

use crate::common::*;
use viscoslide::internals::kernel::{SlidingKernel, ThetaTable, BAND_RATIO_MAX};
use viscoslide::internals::operator::{
    GridOperator, OffsetTable, PeriodicResponse, SpectralPeriodic, ToeplitzFft,
};
use viscoslide::material::{CreepSpectrum, Material};
use viscoslide::response::{Grid, Layer, LayerBase, SlidingResponse};

pub(crate) const A: f64 = 1e-4;
pub(crate) const N: usize = 48;

/// A Gaussian bump of `sigma` cells at the grid's centre (its tails at the
/// edge, 4 sigma for sigma = 6, are 3e-4 of the peak).
pub(crate) fn bump(sigma: f64) -> Vec<f64> {
    let c = 0.5 * (N as f64 - 1.0);
    (0..N * N)
        .map(|k| {
            let (i, j) = ((k / N) as f64 - c, (k % N) as f64 - c);
            1e5 * (-(i * i + j * j) / (2.0 * sigma * sigma)).exp()
        })
        .collect()
}

pub(crate) fn apply(values: &[f64], p: &[f64]) -> Vec<f64> {
    let mut op = ToeplitzFft::new(OffsetTable {
        nx: N,
        ny: N,
        values,
    });
    let mut w = vec![0.0; N * N];
    op.apply(p, &mut w);
    w
}

/// Largest difference over the largest reference value.
pub(crate) fn rel(w: &[f64], w_ref: &[f64]) -> f64 {
    let scale = w_ref.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    w.iter()
        .zip(w_ref)
        .fold(0.0f64, |m, (u, v)| m.max((u - v).abs()))
        / scale
}

fn material(nu: f64) -> Material {
    Material::new(
        CreepSpectrum::standard_linear_solid(1e7 / 3.0, 1e7, 0.01).unwrap(),
        nu,
    )
    .unwrap()
}

fn response(m: &Material, h: f64, base: LayerBase, speed: f64) -> SlidingResponse {
    SlidingResponse::new(m, speed, 0.0, Some(Layer { thickness: h, base })).unwrap()
}

fn reach(base: LayerBase, nu: f64) -> f64 {
    ThetaTable::new(
        Layer {
            thickness: 1.0,
            base,
        },
        nu,
    )
    .unwrap()
    .rho_end()
}

/// `(kernel, resolved cell integral, spectral)` displacements of a bump.
fn responses(r: &SlidingResponse, sigma: f64) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let grid = Grid::square(N, N, A).unwrap();
    let p = bump(sigma);
    let k = SlidingKernel::new(r).unwrap().table(&grid).unwrap();
    let g = SlidingKernel::new(r)
        .unwrap()
        .without_local_limit()
        .table(&grid)
        .unwrap();
    let mut exact = SpectralPeriodic::new(&grid, r, PeriodicResponse::Displacement);
    let mut w_ref = vec![0.0; N * N];
    exact.apply(&p, &mut w_ref);
    (apply(&k.values, &p), apply(&g.values, &p), w_ref)
}

/// A bonded incompressible layer, h/a swept from below the local limit
/// (`h* = a / (2 R) = a / 83`) to above `h = a`, at rest and sliding with
/// `v tau = 3 a`: the kernel's displacement of a smooth bump against the
/// exact spectral layer stays within the five-point Laplacian's error at
/// every thickness (`a^2 / (4 sigma^2)` at the peak: 2.8 % for sigma = 3
/// cells, 0.69 % for 6; the memory of the cell-constant pressure adds its
/// own `O(a^2)`; above `h = a` the resolved cell integral's own
/// collocation error, 2.1 % at `h = a`): asserted 4 % and 2.5 %; measured
/// at most 3.1 % and 2.1 %. Before, the resolved cell integral took over
/// at `h*` and missed 93-100 % of the response there (its collocation at
/// the cell centres sees none of the spikes at the pressure's jumps),
/// 34-54 % at a/10 and 9-23 % from a/5 to a/2: asserted above 90 % at
/// `h*` here, the side that was wrong. At `h = a` (the upper switch) the
/// two routes agree with each other to their own errors (measured 2.0-3.2 %
/// apart, asserted 4 %).
#[test]
fn bonded_incompressible_layer_is_continuous_across_the_switches() {
    let m = paper_material();
    let h_star = A / (2.0 * reach(LayerBase::Bonded, 0.5));
    let ratios = [
        0.999 * h_star / A,
        1.001 * h_star / A,
        0.05,
        0.1,
        0.2,
        0.35,
        0.5,
        0.7,
        0.999 * BAND_RATIO_MAX,
        1.001 * BAND_RATIO_MAX,
        1.5,
    ];
    for speed in [0.0, 3.0 * A / 0.01] {
        for &r in &ratios {
            let resp = response(&m, r * A, LayerBase::Bonded, speed);
            let k = SlidingKernel::new(&resp).unwrap();
            assert_eq!(k.is_thin_law(A, A), r < BAND_RATIO_MAX, "h/a = {r}");
            for (sigma, bound) in [(3.0, 4e-2), (6.0, 2.5e-2)] {
                let (w, w_res, w_ref) = responses(&resp, sigma);
                let (e, e_res) = (rel(&w, &w_ref), rel(&w_res, &w_ref));
                eprintln!(
                    "v = {speed}, h/a = {r:.4}, sigma = {sigma}: kernel {e:.2e}, resolved {e_res:.2e}"
                );
                assert!(e < bound, "h/a = {r}, sigma = {sigma}: {e:e}");
                if (r - 1.001 * h_star / A).abs() < 1e-9 {
                    assert!(e_res > 0.9, "resolved at the local limit: {e_res:e}");
                }
                if (r - 0.999 * BAND_RATIO_MAX).abs() < 1e-9 {
                    let d = rel(&w, &w_res);
                    eprintln!("  band against resolved at h = a: {d:.2e}");
                    assert!(d < 4e-2, "{d:e}");
                }
            }
        }
    }
}

/// The coefficients of the two routes at each switch, a hair on either
/// side (`h = 0.999` and `1.001` of it), sliding with `v tau = 0.3 a` (the
/// memory reaches the trailing neighbours):
/// * bonded incompressible at `R h = a/2`: the law (below) and its grid
///   continuation (above) are the same stencil to `O(S5 (q h)^2)`, at most
///   `1.8 (pi h / a)^2 = 2.6e-3` of the self coefficient; asserted 5e-3
///   after scaling out the law's `h^3` (measured 1.3e-3).
/// * bonded compressible (nu = 0.3) and frictionless at `R h = a/2`: the
///   local limit (below) and the resolved cell integral (above) are the
///   same collocated cell integral, closed form against quadrature
///   (1e-8 apart at one thickness, tests/kernel/thin_layer.rs); scaled by
///   the local compliance's `h`, what is left is the `O(h / a)` edge part
///   times the 0.2 % step in `h`: asserted 1e-3 of the self coefficient
///   (measured 1.2e-7 bonded, 3.9e-9 frictionless).
/// * bonded incompressible at `h = a` (band below, resolved above): the
///   self coefficient and its neighbours agree to the discretisation
///   error of the two: 0.5 % at the self coefficient, 5.2 % of it at the
///   trailing neighbour, where the memory (`v tau = 0.3 a`) decays within
///   the cell (the continuation takes the memory of the cell-constant
///   pressure at the centres, the resolved kernel along the continuous
///   trail); asserted 8 %.
#[test]
fn coefficients_of_the_two_routes_meet_at_each_switch() {
    let speed = 0.3 * A / 0.01;
    let offsets = [(0, 0), (1, 0), (-1, 0), (-2, 0), (0, 1), (-1, 1)];
    let cases = [
        (LayerBase::Bonded, 0.5, None, 3.0, 5e-3, true),
        (LayerBase::Bonded, 0.3, None, 1.0, 1e-3, false),
        (LayerBase::Frictionless, 0.5, None, 1.0, 1e-3, false),
        (
            LayerBase::Bonded,
            0.5,
            Some(BAND_RATIO_MAX * A),
            0.0,
            8e-2,
            true,
        ),
    ];
    for (base, nu, at, power, bound, law_below) in cases {
        let m = material(nu);
        let h0 = at.unwrap_or(A / (2.0 * reach(base, nu)));
        let grid = Grid::square(4, 4, A).unwrap();
        let table = |h: f64| {
            let k = SlidingKernel::new(&response(&m, h, base, speed)).unwrap();
            let t = k.table(&grid).unwrap();
            let s = (h0 / h).powf(power);
            (k.is_thin_law(A, A), offsets.map(|(i, j)| s * t.get(i, j)))
        };
        let (law_lo, lo) = table(0.999 * h0);
        let (law_hi, hi) = table(1.001 * h0);
        assert_eq!(law_lo, law_below, "{base:?} {nu}");
        assert_eq!(law_hi, law_below && at.is_none(), "{base:?} {nu}");
        for ((i, j), (l, u)) in offsets.iter().zip(lo.iter().zip(&hi)) {
            let d = (l - u).abs() / lo[0].abs();
            eprintln!(
                "{base:?} nu = {nu} h = {h0:.4e}: K({i}, {j}) below {l:.6e} above {u:.6e}: {d:.1e}"
            );
            assert!(d < bound, "{base:?} nu = {nu} K({i}, {j}): {l:e} vs {u:e}");
        }
    }
}
