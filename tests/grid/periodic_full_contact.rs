//! Periodic (spectral) formulation in full contact: closed forms of
//! physics.md section 9 (check 2), the field asymmetry of section 6 and the
//! agreement of the friction stencil with the Fourier dissipation sum
//! (Appendix Eq. A3-A4).

use crate::common;
use viscoslide::internals::operator::PeriodicResponse;
use viscoslide::response::{Grid, SlidingResponse};

use std::f64::consts::TAU;

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use viscoslide::internals::analysis::{
    friction_force_periodic, friction_force_stencil, full_contact_friction_stress,
};
use viscoslide::internals::backend::CpuBackend;
use viscoslide::internals::kernel::SlidingKernel;
use viscoslide::internals::operator::{GridOperator, OffsetTable, SpectralPeriodic, ToeplitzFft};
use viscoslide::internals::solver::{self, ContactProblem, Control, SolverParams};
use viscoslide::material::Material;

/// Solve the periodic full-contact problem for gap `g` at mean pressure `p0`
/// and return `(mu_stencil, mu_fourier, pressure)`.
fn full_contact_mu(
    material: &Material,
    g: &[f64],
    nx: usize,
    ny: usize,
    a: f64,
    speed: f64,
    p0: f64,
) -> (f64, f64, Vec<f64>) {
    let op = SpectralPeriodic::new(
        &Grid::square(nx, ny, a).unwrap(),
        &SlidingResponse::new(material, speed, 0.0, None).unwrap(),
        PeriodicResponse::Displacement,
    );
    let l00 = op.self_coefficient();
    let mut be = CpuBackend::new(op);
    let load = p0 * (nx * ny) as f64 * a * a;
    let params = SolverParams {
        tolerance: 1e-11,
        ..Default::default()
    };
    let (sol, _) = solver::solve_full_contact(
        &mut be,
        &ContactProblem::new(g, a * a, l00, Control::Load(load)),
        &params,
    )
    .unwrap();
    let mut d = SpectralPeriodic::new(
        &Grid::square(nx, ny, a).unwrap(),
        &SlidingResponse::new(material, speed, 0.0, None).unwrap(),
        PeriodicResponse::SlidingSlope,
    );
    let fs = friction_force_stencil(&mut d, &sol.pressure, a * a);
    let ff = friction_force_periodic(
        &sol.pressure,
        &Grid::square(nx, ny, a).unwrap(),
        &SlidingResponse::new(material, speed, 0.0, None).unwrap(),
    );
    (-fs / load, -ff / load, sol.pressure)
}

/// Sinusoid `g = h0 (1 - cos k x)` in full contact: `mu(v)` equals
/// `k^2 h0^2 E2(k v) / (4 (1 - nu^2) p0)` over five decades of speed. The
/// grid samples the single mode exactly and the periodic multiplier is the
/// continuous one, so the only error is the linear solve (GMRES to 1e-13
/// relative): 1e-8 leaves five orders of margin and still fails on any
/// factor, sign or normalisation error. The scan's argmax sits at the loss
/// peak of `E2`, `omega* = (E_inf / E0) / tau` for the standard linear
/// solid (creep time `tau`).
#[test]
fn sinusoid_friction_matches_closed_form_over_five_decades() {
    let material = common::paper_material();
    let (nx, ny, length) = (64, 4, 0.01);
    let a = length / nx as f64;
    let k = TAU / length;
    let h0 = 1e-5;
    let g: Vec<f64> = (0..nx * ny)
        .map(|c| h0 * (1.0 - (k * ((c / ny) as f64 + 0.5) * a).cos()))
        .collect();
    let e_inf = material.spectrum.glassy_modulus;
    // Full contact needs p0 >= k h0 |E| / (2 (1 - nu^2)) at every speed.
    let p0 = 2.0 * k * h0 * e_inf / (2.0 * material.composite_factor());
    // E2 = E_inf (r - 1) w tau / (r^2 + (w tau)^2), r = E_inf / E0: peak at w tau = r.
    let omega_peak = e_inf / material.spectrum.relaxed_modulus() / 0.01;
    let v_peak = omega_peak / k;
    let count = 101;
    let mut worst: f64 = 0.0;
    let mut scan = Vec::new();
    for s in 0..count {
        let speed = v_peak * 10f64.powf(-2.5 + 5.0 * s as f64 / (count - 1) as f64);
        let (ms, mf, p) = full_contact_mu(&material, &g, nx, ny, a, speed, p0);
        assert!(p.iter().all(|&v| v > 0.0), "full contact needs p > 0");
        let e2 = material.spectrum.modulus(k * speed).im;
        let exact = k * k * h0 * h0 * e2 / (4.0 * material.composite_factor() * p0);
        assert!(exact > 0.0);
        for m in [ms, mf] {
            let rel = (m - exact).abs() / exact;
            worst = worst.max(rel);
            assert!(
                rel < 1e-8,
                "v = {speed:.3e}: mu = {m:.12e}, exact {exact:.12e}"
            );
        }
        scan.push((speed, ms, exact));
    }
    println!("sinusoid: worst relative error {worst:.2e} over {count} speeds");
    let argmax = |f: &dyn Fn(&(f64, f64, f64)) -> f64| {
        (0..scan.len())
            .max_by(|&i, &j| f(&scan[i]).total_cmp(&f(&scan[j])))
            .unwrap()
    };
    let im = argmax(&|t| t.1);
    assert_eq!(im, argmax(&|t| t.2));
    // The scan step is 0.05 decades: the argmax is within half a step of v*.
    let off = (scan[im].0 / v_peak).log10().abs();
    println!(
        "sinusoid: argmax v = {:.4e} m/s, loss peak v* = {v_peak:.4e} m/s, mu_max = {:.6e}",
        scan[im].0, scan[im].1
    );
    assert!(
        off <= 0.025 + 1e-12,
        "argmax off the loss peak by {off} decades"
    );
}

/// At `v > 0` the trailing side (-x) of a pressure bump keeps the larger
/// displacement (the material remembers the load it passed under); at
/// `v = 0` the field is mirror-symmetric. The sign is cross-checked against
/// the real-space kernel of [`ToeplitzFft`] (physics.md section 3), an
/// independent derivation of the direction.
#[test]
fn trailing_side_keeps_the_larger_displacement() {
    let material = common::paper_material();
    let (n, length) = (64, 0.01);
    let a = length / n as f64;
    let c = n / 2;
    let bump: Vec<f64> = (0..n * n)
        .map(|k| {
            let (i, j) = ((k / n) as f64 - c as f64, (k % n) as f64 - c as f64);
            (-(i * i + j * j) / 8.0).exp()
        })
        .collect();
    let probe = 6;
    for speed in [0.0, 0.05, 0.5] {
        let mut op = SpectralPeriodic::new(
            &Grid::square(n, n, a).unwrap(),
            &SlidingResponse::new(&material, speed, 0.0, None).unwrap(),
            PeriodicResponse::Displacement,
        );
        let mut u = vec![0.0; n * n];
        op.apply(&bump, &mut u);
        let trailing = u[(c - probe) * n + c];
        let leading = u[(c + probe) * n + c];
        let kernel =
            SlidingKernel::new(&SlidingResponse::new(&material, speed, 0.0, None).unwrap())
                .unwrap();
        let table = kernel.table(&Grid::square(n, n, a).unwrap()).unwrap();
        let mut np = ToeplitzFft::new(OffsetTable {
            nx: n,
            ny: n,
            values: &table.values,
        });
        let mut w = vec![0.0; n * n];
        np.apply(&bump, &mut w);
        let (wt, wl) = (w[(c - probe) * n + c], w[(c + probe) * n + c]);
        println!(
            "v = {speed}: periodic trailing {trailing:.6e} leading {leading:.6e}; non-periodic trailing {wt:.6e} leading {wl:.6e}"
        );
        if speed == 0.0 {
            assert!((trailing - leading).abs() <= 1e-12 * trailing.abs());
        } else {
            assert!(trailing > leading * (1.0 + 1e-3), "periodic field mirrored");
            assert!(wt > wl * (1.0 + 1e-3), "non-periodic field mirrored");
        }
    }
}

/// Random band-limited surface (integer wave numbers up to 8 on 64^2, so
/// every mode is sampled exactly) in full contact: `mu` equals the exact
/// linear response summed over modes, and the stencil `a^2 p . (D p)` equals
/// the Fourier dissipation sum (they are the same sum: 1e-10 bounds the
/// round-off of two FFT paths).
#[test]
fn random_surface_full_contact_matches_mode_sum() {
    let material = common::paper_material();
    let (n, length) = (64usize, 0.01);
    let a = length / n as f64;
    let q = TAU / length;
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let mut modes = Vec::new();
    let kmax = 8i32;
    for kx in -kmax..=kmax {
        for ky in 0..=kmax {
            if (ky == 0 && kx <= 0) || kx * kx + ky * ky > kmax * kmax {
                continue;
            }
            let amp = 1e-6 * ((kx * kx + ky * ky) as f64).powf(-0.9);
            modes.push((kx, ky, amp, rng.random_range(0.0..TAU)));
        }
    }
    let z: Vec<f64> = (0..n * n)
        .map(|c| {
            let (x, y) = (((c / n) as f64 + 0.5) * a, ((c % n) as f64 + 0.5) * a);
            modes
                .iter()
                .map(|&(kx, ky, h, ph)| h * (q * (kx as f64 * x + ky as f64 * y) + ph).cos())
                .sum()
        })
        .collect();
    let g = common::gap_of(&z);
    let kmodes: Vec<(f64, f64, f64)> = modes
        .iter()
        .map(|&(kx, ky, h, _)| (q * kx as f64, q * ky as f64, h))
        .collect();
    let p0 = 1e6;
    for speed in [0.01, 0.1, 1.0, 10.0] {
        let (ms, mf, p) = full_contact_mu(&material, &g, n, n, a, speed, p0);
        assert!(p.iter().all(|&v| v > 0.0), "full contact needs p > 0");
        let exact = -full_contact_friction_stress(
            &kmodes,
            &SlidingResponse::new(&material, speed, 0.0, None).unwrap(),
        ) / p0;
        let rel = (ms - exact).abs() / exact;
        let same = (ms - mf).abs() / ms.abs();
        println!("v = {speed}: mu stencil {ms:.12e}, Fourier {mf:.12e}, exact {exact:.12e}; rel {rel:.2e}, stencil-Fourier {same:.2e}");
        assert!(rel < 1e-8, "v = {speed}: {ms} vs exact {exact}");
        assert!(same < 1e-10, "v = {speed}: stencil {ms} vs Fourier {mf}");
    }
}

/// Stencil and Fourier sum agree on arbitrary periodic fields too (not only
/// solver outputs), in an oblique sliding direction and on odd sizes.
#[test]
fn stencil_equals_fourier_sum_on_random_fields() {
    let material = common::paper_material();
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    for &(nx, ny, dir) in &[(32usize, 48usize, 0.0), (45, 30, 0.7), (64, 64, -2.0)] {
        let a = 1e-4;
        let p: Vec<f64> = (0..nx * ny).map(|_| rng.random_range(0.0..1e5)).collect();
        for speed in [1e-3, 0.1, 10.0] {
            let mut d = SpectralPeriodic::new(
                &Grid::square(nx, ny, a).unwrap(),
                &SlidingResponse::new(&material, speed, dir, None).unwrap(),
                PeriodicResponse::SlidingSlope,
            );
            let fs = friction_force_stencil(&mut d, &p, a * a);
            let ff = friction_force_periodic(
                &p,
                &Grid::square(nx, ny, a).unwrap(),
                &SlidingResponse::new(&material, speed, dir, None).unwrap(),
            );
            assert!(fs < 0.0, "friction must oppose sliding: {fs}");
            assert!(
                (fs - ff).abs() <= 1e-10 * fs.abs(),
                "{nx}x{ny} dir {dir} v {speed}: {fs} vs {ff}"
            );
        }
    }
}
