//! Viscoelastic friction of the CPU solver: full-contact sinusoid against
//! the closed form, stencil against dissipation on a rough patch, limits,
//! and a refinement study (physics.md section 9, checks 2, 4 and 5).

mod common;

use common::*;
use viscoslide::analysis;
use viscoslide::backend::CpuBackend;
use viscoslide::kernel::{Axis, KernelParams, SlidingKernel};
use viscoslide::operator::{OffsetTable, ToeplitzFft};
use viscoslide::solver::{self, Control, SolverParams};

/// Friction of a full-contact sinusoid `g = h0 cos(k x)` on a long strip pad
/// (`nx x ny` cells of side `a`), minus the friction of the same flat pad
/// without texture: in full contact the problem is linear, so this removes
/// the pad-edge (flat-punch) contribution and leaves the texture's.
fn strip_friction(speed: f64, h0: f64, k: f64, p0: f64, nx: usize, ny: usize, a: f64) -> (f64, f64) {
    let m = paper_material();
    let kernel = SlidingKernel::new(&m, KernelParams { speed, ..Default::default() }).unwrap();
    let table = kernel.table(nx, ny, a);
    let tab = OffsetTable { nx, ny, values: &table.values };
    let d = kernel.derivative_table(nx, ny, a, Axis::X);
    let load = p0 * (nx * ny) as f64 * a * a;
    let mut forces = Vec::new();
    for amp in [h0, 0.0] {
        let mut g = vec![0.0; nx * ny];
        for i in 0..nx {
            let x = (i as f64 + 0.5) * a;
            for j in 0..ny {
                g[i * ny + j] = amp * (1.0 - (k * x).cos());
            }
        }
        let mut be = CpuBackend::new(ToeplitzFft::new(tab));
        let (sol, _) = solver::solve(&mut be, &g, a * a, tab.get(0, 0), Control::Load(load), &SolverParams::default(), &mut solver::Silent).unwrap();
        assert!(sol.contact.iter().all(|&c| c > 0.5), "full contact expected");
        let mut op = ToeplitzFft::new(OffsetTable { nx, ny, values: &d.values });
        forces.push(analysis::friction_force_stencil(&mut op, &sol.pressure, a));
    }
    (-(forces[0] - forces[1]) / load, -forces[0] / load)
}

#[test]
fn full_contact_sinusoid_matches_closed_form() {
    let m = paper_material();
    let (nx, ny, per) = (512, 16, 16);
    let length = 0.01;
    let a = length / nx as f64;
    let k = std::f64::consts::TAU / (per as f64 * a);
    let h0 = 1e-6;
    for wtau in [0.3, 1.0, 3.0] {
        let speed = wtau / (k * 0.01);
        let e = m.spectrum.modulus(k * speed);
        let composite = 1.0 - m.poisson * m.poisson;
        // Full contact needs p0 >= k h0 |E| / (2 (1 - nu^2)); use twice that.
        let p0 = k * h0 * e.norm() / composite;
        let exact = k * k * h0 * h0 * e.im / (4.0 * composite * p0);
        let (mu, mu_raw) = strip_friction(speed, h0, k, p0, nx, ny, a);
        let err = (mu - exact).abs() / exact;
        eprintln!("k v tau = {wtau}: mu = {mu:.5e} (with pad edges {mu_raw:.5e}), exact {exact:.5e}, rel err {err:.3e}");
        // 16 cells per wavelength: piecewise-constant pressure and the finite
        // pad leave a few percent; the issue asks for 5 %.
        assert!(err < 0.05, "rel err {err}");
    }
}

#[test]
fn rough_patch_friction_two_ways_and_limits() {
    let m = paper_material();
    let (n, length) = (128, 0.01);
    let a = length / n as f64;
    let z = trig_surface(n, length, 16, 0.8, 0.02, 11);
    let load = 3e3 * length * length; // 3 kPa nominal, as in the paper
    let xi_peak = 1.17e-2;
    let mut mus = Vec::new();
    for xi in [0.0, xi_peak, 1e4] {
        let speed = xi * length / 0.01;
        let (sol, info, kernel) = solve_grid(&m, &z, n, length, speed, Control::Load(load));
        let frac = sol.contact.iter().filter(|&&c| c > 0.5).count() as f64 / (n * n) as f64;
        let (mu, mu_d) = friction(&kernel, &m, &sol, n, a, speed);
        eprintln!("xi = {xi:.3e}: A/A0 = {frac:.4}, mu = {mu:.5e}, dissipation {mu_d:.5e}, {} iters, {} matvecs", info.iterations, info.matvecs);
        mus.push((mu, mu_d, frac));
    }
    let (mu_p, mu_dp, frac_p) = mus[1];
    assert!(frac_p > 0.005 && frac_p < 0.2, "partial contact with many spots: {frac_p}");
    assert!(mu_p > 0.0);
    // Both routes compute the same integral for the piecewise-constant
    // pressure; they differ only by the Fourier quadrature.
    assert!((mu_p - mu_dp).abs() / mu_p < 0.02, "{mu_p} vs {mu_dp}");
    assert!(mus[0].0.abs() < 1e-12, "v = 0: {}", mus[0].0);
    assert!(mus[2].0.abs() < 1e-3 * mu_p, "v -> inf: {}", mus[2].0);
    // Stiffening: the contact shrinks towards E0/E_inf = 1/3 of the relaxed area.
    assert!(mus[2].2 < mus[1].2 && mus[1].2 < mus[0].2);
}

#[test]
fn refinement_of_friction_and_area() {
    let m = paper_material();
    let length = 0.01;
    let load = 3e3 * length * length;
    let speed = 1.17e-2 * length / 0.01;
    let mut res = Vec::new();
    for n in [128, 256] {
        let z = trig_surface(n, length, 8, 0.8, 0.02, 5);
        let (sol, _, kernel) = solve_grid(&m, &z, n, length, speed, Control::Load(load));
        let frac = sol.contact.iter().filter(|&&c| c > 0.5).count() as f64 / (n * n) as f64;
        let (mu, _) = friction(&kernel, &m, &sol, n, length / n as f64, speed);
        eprintln!("n = {n}: A/A0 = {frac:.5}, mu = {mu:.5e}");
        res.push((mu, frac));
    }
    let dmu = (res[1].0 - res[0].0).abs() / res[1].0;
    let da = (res[1].1 - res[0].1).abs() / res[1].1;
    eprintln!("refinement 128 -> 256: friction changes {:.2} %, area {:.2} %", 100.0 * dmu, 100.0 * da);
    assert!(dmu < 0.03 && da < 0.03, "friction {dmu}, area {da}");
}
