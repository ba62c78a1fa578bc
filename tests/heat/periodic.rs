//! The periodic cell mode by mode: a single surface mode against
//! `theta = q / (lam m)` written out here, its decay with depth, the
//! Nyquist modes, and the mean (no steady state; the block's background
//! heating with a block length).

use num_complex::Complex64;
use viscoslide::heat::{Conduction, HeatDomain, HeatSetup, HeatSolver};
use viscoslide::response::Grid;

const LAMBDA: f64 = 0.25;
const KAPPA: f64 = 1e-7;

fn setup(
    nx: usize,
    ny: usize,
    dx: f64,
    dy: f64,
    speed: f64,
    deg: f64,
    block: Option<f64>,
) -> HeatSetup {
    HeatSetup {
        grid: Grid::new(nx, ny, (dx, dy)).unwrap(),
        conduction: Conduction {
            conductivity: LAMBDA,
            diffusivity: KAPPA,
        },
        speed,
        direction_rad: deg.to_radians(),
        domain: HeatDomain::Periodic {
            block_length: block,
        },
    }
}

/// `m = sqrt(|k|^2 - i v (k.e_v) / kappa)`, `Re m > 0` (physics.md
/// section 14).
fn m_of(k: (f64, f64), speed: f64, deg: f64) -> Complex64 {
    let t = deg.to_radians();
    let ke = k.0 * t.cos() + k.1 * t.sin();
    let m = Complex64::new(k.0 * k.0 + k.1 * k.1, -speed * ke / KAPPA).sqrt();
    assert!(m.re > 0.0);
    m
}

/// `q(x) = q0 cos(k.x + p)` on the cell centres of mode `(kx, ky)` (signed
/// indices), and the rise `Re[q0 exp(i (k.x + p)) exp(-m z) / (lam m)]`.
struct Mode {
    nx: usize,
    ny: usize,
    dx: f64,
    dy: f64,
    kx: i32,
    ky: i32,
}

impl Mode {
    fn k(&self) -> (f64, f64) {
        let tau = std::f64::consts::TAU;
        (
            tau * self.kx as f64 / (self.nx as f64 * self.dx),
            tau * self.ky as f64 / (self.ny as f64 * self.dy),
        )
    }

    fn phase(&self, i: usize, j: usize) -> f64 {
        let k = self.k();
        k.0 * (i as f64 + 0.5) * self.dx + k.1 * (j as f64 + 0.5) * self.dy + 0.4
    }

    fn flux(&self, q0: f64) -> Vec<f64> {
        let mut out = Vec::with_capacity(self.nx * self.ny);
        for i in 0..self.nx {
            for j in 0..self.ny {
                out.push(q0 * self.phase(i, j).cos());
            }
        }
        out
    }

    fn rise(&self, q0: f64, speed: f64, deg: f64, z: f64) -> Vec<f64> {
        let m = m_of(self.k(), speed, deg);
        let amp = q0 * (-m * z).exp() / (LAMBDA * m);
        let mut out = Vec::with_capacity(self.nx * self.ny);
        for i in 0..self.nx {
            for j in 0..self.ny {
                out.push((amp * Complex64::from_polar(1.0, self.phase(i, j))).re);
            }
        }
        out
    }
}

fn max_abs(a: &[f64]) -> f64 {
    a.iter().fold(0.0f64, |m, b| m.max(b.abs()))
}

/// The largest difference.
fn difference(got: &[f64], want: &[f64]) -> f64 {
    got.iter()
        .zip(want)
        .fold(0.0f64, |a, (g, w)| a.max((g - w).abs()))
}

/// The largest difference relative to the largest value.
fn relative(got: &[f64], want: &[f64]) -> f64 {
    difference(got, want) / max_abs(want)
}

/// A single mode of a rectangular-celled cell, sliding at 30 degrees,
/// from `v L / kappa = 0.1` to 1e4, at the surface and at depth: 1e-9
/// relative (the target; the transforms' round-off is ~1e-15).
#[test]
fn a_single_mode_is_q_over_lambda_m() {
    let mut worst: f64 = 0.0;
    for (kx, ky) in [(3, -2), (1, 0), (0, 5), (-7, 9)] {
        let mode = Mode {
            nx: 64,
            ny: 48,
            dx: 2e-6,
            dy: 3e-6,
            kx,
            ky,
        };
        for speed in [1e-4, 1e-2, 1.0, 7.8] {
            let mut solver = HeatSolver::new(setup(64, 48, 2e-6, 3e-6, speed, 30.0, None)).unwrap();
            let flux = mode.flux(2e5);
            let t = solver.surface(&flux).unwrap();
            assert_eq!(t.background, None);
            let err = relative(&t.rise, &mode.rise(2e5, speed, 30.0, 0.0));
            assert!(err < 1e-9, "mode ({kx}, {ky}), v {speed}: {err:e}");
            worst = worst.max(err);
            // Below the surface the mode decays as exp(-Re m z), to 1e-11
            // of the surface's at the deepest point at the highest speed;
            // the transforms' round-off stays that of the surface's rise,
            // so depths are measured against the surface's largest rise.
            let depths = [0.0, 4e-6, 3e-5];
            let scale = max_abs(&mode.rise(2e5, speed, 30.0, 0.0));
            for (t, z) in solver
                .surface_at(&flux, &depths)
                .unwrap()
                .iter()
                .zip(depths)
            {
                let want = mode.rise(2e5, speed, 30.0, z);
                let err = difference(&t.rise, &want) / scale;
                assert!(err < 1e-9, "mode ({kx}, {ky}), v {speed}, z {z}: {err:e}");
                worst = worst.max(err);
            }
        }
    }
    eprintln!("single periodic modes: largest relative error {worst:.2e}");
}

/// A Nyquist mode (`cos(pi i)` along x, even `nx`) samples `+k` and `-k`:
/// its multiplier is their average, the real part of `1 / (lam m)`, and
/// the rise stays real and of the same pattern.
#[test]
fn nyquist_modes_take_the_average_of_both_signs() {
    let (nx, ny, dx) = (16, 6, 1e-6);
    let mut flux = vec![0.0; nx * ny];
    for i in 0..nx {
        for j in 0..ny {
            flux[i * ny + j] = if i % 2 == 0 { 1e5 } else { -1e5 };
        }
    }
    let speed = 0.05;
    let t = HeatSolver::new(setup(nx, ny, dx, dx, speed, 0.0, None))
        .unwrap()
        .surface(&flux)
        .unwrap();
    let kn = std::f64::consts::PI / dx;
    let gain = (1.0 / (LAMBDA * m_of((kn, 0.0), speed, 0.0))).re;
    for (r, q) in t.rise.iter().zip(&flux) {
        assert!(
            (r - gain * q).abs() < 1e-12 * (gain * 1e5).abs(),
            "{r} vs {}",
            gain * q
        );
    }
}

/// The mean has no steady state: without a block length the rise has zero
/// mean and the solver says so; with one, the mean is `(4/3) qbar
/// sqrt(kappa t_c / pi) / lam`, `t_c = L_b / v`, reported apart, the rest
/// unchanged.
#[test]
fn the_mean_is_the_blocks_background() {
    let mode = Mode {
        nx: 32,
        ny: 32,
        dx: 5e-6,
        dy: 5e-6,
        kx: 2,
        ky: 1,
    };
    let (qbar, speed, block) = (3e4, 0.3, 0.01);
    let flux: Vec<f64> = mode.flux(1e5).iter().map(|q| q + qbar).collect();
    let mut free = HeatSolver::new(setup(32, 32, 5e-6, 5e-6, speed, 0.0, None)).unwrap();
    let notes = free.setup().notes();
    assert!(
        notes.len() == 1 && notes[0].contains("no steady state"),
        "{notes:?}"
    );
    let t = free.surface(&flux).unwrap();
    let mean = t.rise.iter().sum::<f64>() / t.rise.len() as f64;
    assert!(mean.abs() < 1e-12 * t.max(), "{mean}");
    let mut blocked = HeatSolver::new(setup(32, 32, 5e-6, 5e-6, speed, 0.0, Some(block))).unwrap();
    // The block gives the mean (this 160 um cell's depth, 25 um, is 0.44
    // of the passage's diffusion length: that note stands).
    let notes = blocked.setup().notes();
    assert!(
        notes.iter().all(|n| !n.contains("no steady state")),
        "{notes:?}"
    );
    let b = blocked.surface(&flux).unwrap();
    let want = 4.0 / 3.0 * qbar * (KAPPA * block / speed / std::f64::consts::PI).sqrt() / LAMBDA;
    let got = b.background.unwrap();
    assert!((got / want - 1.0).abs() < 1e-14, "{got} vs {want}");
    for (x, y) in b.rise.iter().zip(&t.rise) {
        assert!((x - got - y).abs() < 1e-12 * want, "{x} vs {y}");
    }
    let modal = mode.rise(1e5, speed, 0.0, 0.0);
    assert!(relative(&t.rise, &modal) < 1e-9);
}

/// A block whose passage is too short for the cell is noted: where the
/// depth `L / (2 pi)` of the longest period (across the sliding here)
/// exceeds 0.3 of the diffusion length `sqrt(kappa L_b / v)`, and not
/// below.
#[test]
fn a_passage_too_short_for_the_cell_is_noted() {
    let (block, dx) = (0.01, 5e-6);
    let depth = 128.0 * dx / std::f64::consts::TAU;
    // The speed at which the depth is 0.3 of the diffusion length.
    let edge = KAPPA * block * (0.3 / depth).powi(2);
    let notes = |v: f64| setup(32, 128, dx, dx, v, 0.0, Some(block)).notes();
    assert_eq!(notes(0.98 * edge), Vec::<String>::new());
    let n = notes(1.02 * edge);
    assert!(
        n.len() == 1 && n[0].contains("longest period 6.400e-4 m"),
        "{n:?}"
    );
}
