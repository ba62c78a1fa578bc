//! Layers of finite thickness (physics.md section 3, "Finite thickness"):
//! exact in the periodic formulation (compliance `S(|q| h)` times the
//! half-space's per mode), and the non-periodic Eq. 5 kernel against it for
//! an elastic layer, where Eq. 5 is exact.

use crate::common;
use viscoslide::response::{Grid, Layer, LayerBase, SlidingResponse};

use std::f64::consts::TAU;

use num_complex::Complex64;
use viscoslide::internals::analysis::{
    friction_force_periodic, friction_force_stencil, full_contact_friction_stress,
};
use viscoslide::internals::backend::CpuBackend;
use viscoslide::internals::kernel::SlidingKernel;
use viscoslide::internals::operator::{
    periodic_multiplier, GridOperator, OffsetTable, PeriodicResponse, SpectralPeriodic, ToeplitzFft,
};
use viscoslide::internals::solver::{self, ContactProblem, Control, SolverParams};
use viscoslide::material::Material;
use viscoslide::response::layer::compliance_ratio;

/// Periodic full contact of `g = h0 (1 - cos k x)` at mean pressure `p0`:
/// `(mu_stencil, mu_fourier, pressure)`.
fn full_contact(
    response: &SlidingResponse,
    g: &[f64],
    (nx, ny, a): (usize, usize, f64),
    p0: f64,
) -> (f64, f64, Vec<f64>) {
    let grid = Grid::square(nx, ny, a).unwrap();
    let op = SpectralPeriodic::new(&grid, response, PeriodicResponse::Displacement);
    let l00 = op.self_coefficient();
    let mut be = CpuBackend::new(op);
    let load = p0 * (nx * ny) as f64 * a * a;
    let sp = SolverParams {
        tolerance: 1e-11,
        ..Default::default()
    };
    let (sol, _) = solver::solve_full_contact(
        &mut be,
        &ContactProblem::new(g, a * a, l00, Control::Load(load)),
        &sp,
    )
    .unwrap();
    let mut d = SpectralPeriodic::new(&grid, response, PeriodicResponse::SlidingSlope);
    let fs = friction_force_stencil(&mut d, &sol.pressure, a * a);
    let ff = friction_force_periodic(&sol.pressure, &grid, response);
    (-fs / load, -ff / load, sol.pressure)
}

/// `mu = k^2 h0^2 E2(k v) / (4 (1 - nu^2) p0 S(k h))` for both bases and
/// `k h = 0.3, 1, 3`, at five speeds across the loss peak, by the spectral
/// slope stencil and by the Fourier dissipation sum. As for the half-space
/// (tests/grid/periodic_full_contact.rs), the grid samples the single mode
/// exactly, so the only error is the linear solve: 1e-8.
#[test]
fn layered_sinusoid_friction_matches_closed_form() {
    let material = common::paper_material();
    let (nx, ny, length) = (64, 4, 0.01);
    let a = length / nx as f64;
    let k = TAU / length;
    let h0 = 1e-5;
    let g: Vec<f64> = (0..nx * ny)
        .map(|c| h0 * (1.0 - (k * ((c / ny) as f64 + 0.5) * a).cos()))
        .collect();
    let e_inf = material.spectrum.glassy_modulus;
    let v_peak = e_inf / material.spectrum.relaxed_modulus() / 0.01 / k;
    let mut worst = 0.0f64;
    for base in [LayerBase::Bonded, LayerBase::Frictionless] {
        for kh in [0.3, 1.0, 3.0] {
            let layer = Layer {
                thickness: kh / k,
                base,
            };
            let s = compliance_ratio(base, material.poisson, kh);
            // Full contact needs p0 >= k h0 |E| / (2 (1 - nu^2) S).
            let p0 = 2.0 * k * h0 * e_inf / (2.0 * material.composite_factor() * s);
            for decade in [-1.0, -0.5, 0.0, 0.5, 1.0] {
                let speed = v_peak * 10f64.powf(decade);
                let response = SlidingResponse::new(&material, speed, 0.0, Some(layer)).unwrap();
                let (ms, mf, p) = full_contact(&response, &g, (nx, ny, a), p0);
                assert!(p.iter().all(|&v| v > 0.0), "full contact needs p > 0");
                let e2 = material.spectrum.modulus(k * speed).im;
                let exact = k * k * h0 * h0 * e2 / (4.0 * material.composite_factor() * p0 * s);
                let lib = -full_contact_friction_stress(&[(k, 0.0, h0)], &response) / p0;
                for m in [ms, mf, lib] {
                    let rel = (m - exact).abs() / exact;
                    worst = worst.max(rel);
                    assert!(
                        rel < 1e-8,
                        "{base:?} kh = {kh}, v = {speed:.3e}: mu = {m:.12e}, exact {exact:.12e}"
                    );
                }
            }
        }
    }
    println!("layered sinusoid: worst relative error {worst:.2e}");
}

/// `S -> 1` for `k h -> inf`: a layer a thousand wavelengths thick gives the
/// half-space's pressure and friction to round-off.
#[test]
fn thick_layer_is_the_half_space_in_the_periodic_cell() {
    let material = common::paper_material();
    let (nx, ny, length) = (32, 32, 0.01);
    let a = length / nx as f64;
    let z = common::trig_surface(nx, length, 6, 0.8, 0.02, 5);
    let g = common::gap_of(&z);
    let speed = 1e-3;
    let half = SlidingResponse::new(&material, speed, 0.0, None).unwrap();
    // Up to thicknesses whose `(|q| h)^2` leaves f64.
    let thick = |thickness: f64, base| {
        let layer = Some(Layer { thickness, base });
        SlidingResponse::new(&material, speed, 0.0, layer).unwrap()
    };
    let grid = Grid::square(nx, ny, a).unwrap();
    let mut results = vec![];
    let responses = [
        half,
        thick(1e3 * length, LayerBase::Bonded),
        thick(1e300, LayerBase::Bonded),
        thick(1e300, LayerBase::Frictionless),
    ];
    for response in responses {
        let op = SpectralPeriodic::new(&grid, &response, PeriodicResponse::Displacement);
        let l00 = op.self_coefficient();
        let mut be = CpuBackend::new(op);
        let (sol, _) = solver::solve(
            &mut be,
            ContactProblem::new(&g, a * a, l00, Control::Load(3e3 * length * length)),
            &SolverParams::default(),
            None,
            &mut solver::Silent,
        )
        .unwrap();
        let ff = friction_force_periodic(&sol.pressure, &grid, &response);
        results.push((sol.pressure, ff));
    }
    let scale = results[0].0.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    for thick in &results[1..] {
        for (p, q) in results[0].0.iter().zip(&thick.0) {
            assert!((p - q).abs() <= 1e-12 * scale, "{p} vs {q}");
        }
        let (f0, f1) = (results[0].1, thick.1);
        assert!((f0 - f1).abs() <= 1e-12 * f0.abs(), "{f0} vs {f1}");
    }
}

/// The response of the non-periodic (Eq. 4-5) table to `p_i = cos(k x_i)`
/// on a pad, in its interior (farther than the reach of `Theta` plus the
/// memory trail from every edge, where the pad's finite size cannot be
/// felt), against the exact lattice response of piecewise-constant cells,
/// `u_i = Re[sigma e^{i k x_i}]`,
/// `sigma = sum_m m(k_m) sinc(k_m a / 2)`, `k_m = k + 2 pi m / a`,
/// `m(q) = 2 (1 - nu^2) S(|q| h) J*(-q v) / |q|` (the periodic multiplier).
/// Returns `(worst interior error / max |u|, sigma, m(k), 2 (1-nu^2) / (E0 k))`.
fn lattice_check(
    material: &Material,
    layer: Layer,
    speed: f64,
    a: f64,
    wavelength_cells: f64,
) -> (f64, Complex64, Complex64, f64) {
    let k = TAU / (wavelength_cells * a);
    let response = SlidingResponse::new(material, speed, 0.0, Some(layer)).unwrap();
    let kernel = SlidingKernel::new(&response).unwrap();
    let reach = kernel.theta().unwrap().reach();
    let trail = 46.0 * speed * material.spectrum.terms[0].time;
    let margin = ((reach + trail) / a).ceil() as usize + 2;
    let ym = (reach / a).ceil() as usize + 2;
    let (nx, ny) = (2 * margin + 128, 2 * ym + 16);
    let table = kernel.table(&Grid::square(nx, ny, a).unwrap()).unwrap();
    let mut op = ToeplitzFft::new(OffsetTable {
        nx,
        ny,
        values: &table.values,
    });
    let p: Vec<f64> = (0..nx * ny)
        .map(|c| (k * (c / ny) as f64 * a).cos())
        .collect();
    let mut u = vec![0.0; nx * ny];
    op.apply(&p, &mut u);
    let mult = |q: f64| {
        material.spectrum.compliance(-q * speed)
            * (2.0
                * material.composite_factor()
                * compliance_ratio(layer.base, material.poisson, q.abs() * layer.thickness)
                / q.abs())
    };
    let sinc = |t: f64| t.sin() / t;
    let mut sigma = Complex64::default();
    for m in -20000i64..=20000 {
        let q = k + TAU * m as f64 / a;
        sigma += mult(q) * sinc(0.5 * q * a);
    }
    let umax = u.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let mut worst = 0.0f64;
    for i in margin..nx - margin {
        for j in ym..ny - ym {
            let want = (sigma * Complex64::from_polar(1.0, k * i as f64 * a)).re;
            worst = worst.max((u[i * ny + j] - want).abs() / umax);
        }
    }
    let g_hs = 2.0 * material.composite_factor() / (material.spectrum.relaxed_modulus() * k);
    (worst, sigma, mult(k), g_hs)
}

/// Sliding layer (`v > 0`): the paper's Eq. 4-5 take `Theta` at the
/// displaced point `|x + v tau z|`, so in Fourier space the kernel is
/// `S(|q| h) 2 (1 - nu^2) J*(-q.v) / |q|`, the exact layer for a
/// frequency-independent Poisson ratio (correspondence principle). The
/// non-periodic cell-integral table reproduces the exact lattice response
/// to 1e-9 at speeds across the loss peak, for both bases.
#[test]
fn sliding_eq5_is_the_exact_layer() {
    let material = common::paper_material();
    let a = 3.125e-4;
    let tau = material.spectrum.terms[0].time;
    for (base, h_cells) in [(LayerBase::Bonded, 1.0), (LayerBase::Frictionless, 2.0)] {
        let layer = Layer {
            thickness: h_cells * a,
            base,
        };
        for l_cells in [0.3, 3.0] {
            let speed = l_cells * a / tau;
            let (worst, sigma, m, _) = lattice_check(&material, layer, speed, a, 32.0);
            println!(
                "{base:?} h = {h_cells} a, v tau = {l_cells} a: interior vs exact lattice response {worst:.2e}; sigma / m(k) - 1 = {:.3e}",
                (sigma / m - 1.0).norm()
            );
            assert!(worst < 1e-9, "{worst:e}");
        }
    }
}

/// Elastic layer (`v = 0`): Eq. 5 is exact, so the non-periodic table of
/// cell integrals applied to `p_i = cos(k x_i)` on a pad reproduces, in
/// the interior (farther than the reach of `Theta` from every edge, where
/// the pad's finite size cannot be felt), the exact lattice response of
/// piecewise-constant cells,
/// `sigma(k) = sum_m G(|k + 2 pi m / a|) sinc((k + 2 pi m / a) a / 2)`,
/// `G(q) = 2 (1 - nu^2) S(q h) / (E0 q)`, to 1e-9 of the largest
/// displacement. Against the periodic exact operator, whose multiplier is
/// `G(k)` for the sampled mode, the only difference is this
/// discretisation: the cell's `sinc` and the alias images, whose size is
/// set by the half-space's `G_hs(k) = 2 (1 - nu^2) / (E0 k)`, not by the
/// layer's (a thin bonded incompressible layer has `S(kh) = O((kh)^3)`
/// while its aliases see `S ~ 1`): `|sigma - G(k)| <= (k a)^2 / 6 G_hs(k)`.
#[test]
fn elastic_eq5_matches_the_exact_periodic_layer() {
    let material = common::paper_material();
    let a = 3.125e-4;
    let wavelength_cells = 32.0;
    let k = TAU / (wavelength_cells * a);
    for (base, h_cells) in [
        (LayerBase::Bonded, 1.0),
        (LayerBase::Bonded, 2.0),
        (LayerBase::Frictionless, 1.5),
    ] {
        let layer = Layer {
            thickness: h_cells * a,
            base,
        };
        let (worst, sigma, m, g_hs) = lattice_check(&material, layer, 0.0, a, wavelength_cells);
        let disc = (sigma.re - m.re) / g_hs;
        println!(
            "{base:?} h = {h_cells} a (k h = {:.3}): interior vs exact lattice response {worst:.2e}; Eq. 5 cells vs periodic exact {disc:.3e} of G_hs, {:.3e} of G (bound (ka)^2/6 = {:.3e})",
            k * layer.thickness,
            (sigma.re - m.re) / m.re,
            (k * a).powi(2) / 6.0
        );
        assert!(worst < 1e-9, "{worst:e}");
        assert!(sigma.im.abs() < 1e-15 * g_hs && m.im == 0.0);
        assert!(disc.abs() <= (k * a).powi(2) / 6.0, "{disc}");
        // The periodic operator's multiplier for this mode is m(k).
        let per = periodic_multiplier(
            &SlidingResponse::new(&material, 0.0, 0.0, Some(layer)).unwrap(),
            &Grid::square(wavelength_cells as usize, 4, a).unwrap(),
            1,
            0,
            PeriodicResponse::Displacement,
        );
        assert!((per - m).norm() < 1e-14 * m.norm());
    }
}
