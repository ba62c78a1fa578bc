//! Viscoelastic friction of the CPU solver: full-contact sinusoid against
//! the closed form, stencil against dissipation on a rough patch, limits,
//! and a refinement study (physics.md section 9, checks 2, 4 and 5).

use crate::common;
use viscoslide::response::{Grid, SlidingResponse};

use common::*;
use viscoslide::internals::backend::CpuBackend;
use viscoslide::internals::kernel::{Axis, SlidingKernel};
use viscoslide::internals::operator::{GridOperator, OffsetTable, ToeplitzFft};
use viscoslide::internals::solver::{self, ContactProblem, Control, SolverParams};

/// Friction force per unit area of a sinusoidal texture `g = h0 cos(k x)`
/// in full contact on a square pad of `n x n` cells of side `a`: in full
/// contact the problem is linear, so the texture's own pressure follows from
/// one solve with zero net load, and its friction is the quadratic form of
/// the exact-work stencil. Also returns the smallest total pressure of the
/// loaded pad (`p0` added), to confirm full contact with the contact solver.
fn texture_friction(speed: f64, h0: f64, k: f64, p0: f64, n: usize, a: f64) -> (f64, f64) {
    let m = paper_material();
    let kernel = SlidingKernel::new(&SlidingResponse::new(&m, speed, 0.0, None).unwrap()).unwrap();
    let table = kernel.table(&Grid::square(n, n, a).unwrap()).unwrap();
    let tab = OffsetTable {
        nx: n,
        ny: n,
        values: &table.values,
    };
    let d = kernel
        .derivative_table(&Grid::square(n, n, a).unwrap(), Axis::X)
        .unwrap();
    let mut g = vec![0.0; n * n];
    for i in 0..n {
        let x = (i as f64 + 0.5) * a;
        for j in 0..n {
            g[i * n + j] = h0 * (1.0 - (k * x).cos());
        }
    }
    let mut be = CpuBackend::new(ToeplitzFft::new(tab));
    let params = SolverParams::default();
    let (tex, _) = solver::solve_full_contact(
        &mut be,
        &ContactProblem::new(&g, a * a, tab.get(0, 0), Control::Load(0.0)),
        &params,
    )
    .unwrap();
    let mut op = ToeplitzFft::new(OffsetTable {
        nx: n,
        ny: n,
        values: &d.values,
    });
    // Friction density in the central half of the pad, away from the edges
    // where the cut texture has its own (edge) response.
    let mut dp = vec![0.0; n * n];
    op.apply(&tex.pressure, &mut dp);
    let (lo, hi) = (n / 4, 3 * n / 4);
    let mut force = 0.0;
    for i in lo..hi {
        for j in lo..hi {
            force += a * a * tex.pressure[i * n + j] * dp[i * n + j];
        }
    }
    let area = ((hi - lo) * (hi - lo)) as f64 * a * a;
    // The loaded pad with the contact solver: full contact in the interior.
    let load = p0 * (n * n) as f64 * a * a;
    let (sol, _) = solver::solve(
        &mut be,
        ContactProblem::new(&g, a * a, tab.get(0, 0), Control::Load(load)),
        &params,
        None,
        &mut solver::Silent,
    )
    .unwrap();
    let out = sol.contact.iter().filter(|&&c| c < 0.5).count();
    assert!(out < n * n / 100, "{out} cells out of contact");
    (force / area, out as f64)
}

#[test]
fn full_contact_sinusoid_matches_closed_form() {
    let m = paper_material();
    // A square pad 16 wavelengths wide: the texture must extend over many
    // wavelengths in y too, or the 1/r kernel sees a strip, not a plane.
    let (n, per) = (256, 16);
    let length = 0.01;
    let a = length / n as f64;
    let k = std::f64::consts::TAU / (per as f64 * a);
    let h0 = 1e-6;
    for wtau in [0.3, 1.0, 3.0] {
        let speed = wtau / (k * 0.01);
        let e = m.spectrum.modulus(k * speed);
        let composite = 1.0 - m.poisson * m.poisson;
        // Full contact of the infinite texture needs p0 >= k h0 |E| / (2 (1 - nu^2));
        // a finite flat pad carries about half its mean pressure in the middle
        // (flat-punch profile), so use four times that.
        let p0 = 2.0 * k * h0 * e.norm() / composite;
        let exact = k * k * h0 * h0 * e.im / (4.0 * composite * p0);
        let (force_per_area, out) = texture_friction(speed, h0, k, p0, n, a);
        let mu = -force_per_area / p0;
        let err = (mu - exact).abs() / exact;
        eprintln!("k v tau = {wtau}: mu = {mu:.5e}, exact {exact:.5e}, rel err {err:.3e} ({out} pad cells out of contact)");
        // 16 cells per wavelength: the piecewise-constant pressure leaves
        // at most about (k a)^2 / 12 ~ 1.3 % (the issue allows 5 %).
        assert!(err < 0.02, "rel err {err}");
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
    assert!(
        frac_p > 0.005 && frac_p < 0.2,
        "partial contact with many spots: {frac_p}"
    );
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
    eprintln!(
        "refinement 128 -> 256: friction changes {:.2} %, area {:.2} %",
        100.0 * dmu,
        100.0 * da
    );
    assert!(dmu < 0.03 && da < 0.03, "friction {dmu}, area {da}");
}
