//! Physical checks of the CPU contact solver (physics.md section 9).

use crate::common;

use common::*;
use viscoslide::internals::solver::Control;

/// Hertz: a sphere of radius `r` pressed with load `f` on a half-space of
/// plane-strain modulus `e_star`: contact radius and peak pressure.
fn hertz(f: f64, r: f64, e_star: f64) -> (f64, f64) {
    let a = (3.0 * f * r / (4.0 * e_star)).cbrt();
    (a, 3.0 * f / (2.0 * std::f64::consts::PI * a * a))
}

fn sphere(n: usize, length: f64, radius: f64) -> Vec<f64> {
    let a = length / n as f64;
    let mut z = vec![0.0; n * n];
    for i in 0..n {
        for j in 0..n {
            let x = (i as f64 + 0.5) * a - length / 2.0;
            let y = (j as f64 + 0.5) * a - length / 2.0;
            z[i * n + j] = -(x * x + y * y) / (2.0 * radius);
        }
    }
    z
}

#[test]
fn hertz_limits_converge_under_refinement() {
    let m = paper_material();
    let (radius, load, length) = (0.01, 0.6, 3.2e-3);
    for (speed, modulus) in [(0.0, 1e7 / 3.0), (f64::INFINITY, 1e7)] {
        let (ah, ph) = hertz(load, radius, modulus / 0.75);
        let mut errors = Vec::new();
        for n in [32, 64, 128] {
            let (sol, _, _) = solve_grid(
                &m,
                &sphere(n, length, radius),
                n,
                length,
                speed,
                Control::Load(load),
            );
            let a = length / n as f64;
            let cells = sol.contact.iter().filter(|&&c| c > 0.5).count();
            let radius_num = (cells as f64 * a * a / std::f64::consts::PI).sqrt();
            let pmax = sol.pressure.iter().cloned().fold(0.0, f64::max);
            let (ea, ep) = ((radius_num - ah).abs() / ah, (pmax - ph).abs() / ph);
            eprintln!(
                "v = {speed}: n = {n}: contact radius err {ea:.3e}, peak pressure err {ep:.3e}"
            );
            errors.push((ea, ep));
        }
        // The error must fall under refinement and be small on the finest grid:
        // the radius is quantised by one cell (a/a_H ~ 2.5 % at 128^2).
        assert!(
            errors[2].0 < errors[0].0 && errors[2].0 < 0.03,
            "{errors:?}"
        );
        assert!(
            errors[2].1 < errors[0].1 && errors[2].1 < 0.03,
            "{errors:?}"
        );
    }
}

#[test]
fn zero_speed_gives_zero_friction_and_mirror_symmetric_pressure() {
    let m = paper_material();
    let (n, length) = (64, 3.2e-3);
    let (sol, _, kernel) = solve_grid(
        &m,
        &sphere(n, length, 0.01),
        n,
        length,
        0.0,
        Control::Load(0.6),
    );
    let (mu, mu_d) = friction(&kernel, &m, &sol, n, length / n as f64, 0.0);
    assert!(mu.abs() < 1e-12 && mu_d == 0.0, "mu = {mu}, {mu_d}");
    let pmax = sol.pressure.iter().cloned().fold(0.0, f64::max);
    for i in 0..n {
        for j in 0..n {
            let d = (sol.pressure[i * n + j] - sol.pressure[(n - 1 - i) * n + j]).abs();
            assert!(d <= 1e-7 * pmax, "asymmetry {d} at ({i},{j})");
        }
    }
}

#[test]
fn sliding_sphere_shifts_pressure_forward_and_loses_the_trailing_edge() {
    let m = paper_material();
    let (n, length, radius, load) = (64, 3.2e-3, 0.01, 0.6);
    let a_h = hertz(load, radius, 1e7 / 3.0 / 0.75).0;
    let speed = a_h / 0.01; // v tau / a_H = 1
    let (sol, _, kernel) = solve_grid(
        &m,
        &sphere(n, length, radius),
        n,
        length,
        speed,
        Control::Load(load),
    );
    let a = length / n as f64;
    let xs: Vec<usize> = (0..n * n)
        .filter(|&k| sol.contact[k] > 0.5)
        .map(|k| k / n)
        .collect();
    let (imin, imax) = (*xs.iter().min().unwrap(), *xs.iter().max().unwrap());
    let centre = n as f64 / 2.0 - 0.5;
    // The trailing side (-x) loses contact first: the contact ends closer to
    // the centre behind it than ahead of it.
    assert!(
        (centre - imin as f64) < (imax as f64 - centre),
        "contact from {imin} to {imax}"
    );
    let (mu, mu_d) = friction(&kernel, &m, &sol, n, a, speed);
    assert!(mu > 0.0 && mu_d > 0.0, "{mu} {mu_d}");
    // Same integral two ways; the Fourier quadrature (padding 4) is good to ~0.3 %.
    assert!((mu - mu_d).abs() / mu < 0.01, "{mu} vs {mu_d}");
    eprintln!("sphere v tau/a_H = 1: mu = {mu:.4e}, dissipation {mu_d:.4e}, contact x in [{imin}, {imax}]");
}
