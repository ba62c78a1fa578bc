//! The iterative solver against the dense direct LCP solver on a synthetic
//! non-symmetric block-Toeplitz operator: elastic Love coefficients plus a
//! memory term that samples the same kernel at points shifted along +x
//! (the structure of the viscoelastic kernel, Eq. 4, with a crude quadrature).
//! This isolates the solver from the kernel module.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use viscoslide::backend::CpuBackend;
use viscoslide::operator::{DenseOperator, OffsetTable, ToeplitzFft};
use viscoslide::solver::{self, reference, Control, SolverParams};

/// Love's integral of 1/r over the unit-free square [-h, h]^2 seen from (x, y).
fn love(x: f64, y: f64, h: f64) -> f64 {
    let f = |a: f64, b: f64| {
        let r = (a * a + b * b).sqrt();
        let p1 = if a.abs() > 0.0 { a * (b + r).ln() } else { 0.0 };
        let p2 = if b.abs() > 0.0 { b * (a + r).ln() } else { 0.0 };
        p1 + p2
    };
    f(x + h, y + h) - f(x + h, y - h) - f(x - h, y + h) + f(x - h, y - h)
}

fn table(nx: usize, ny: usize, a: f64, memory: f64) -> Vec<f64> {
    let mut t = Vec::with_capacity((2 * nx - 1) * (2 * ny - 1));
    for di in -(nx as isize - 1)..=(nx as isize - 1) {
        for dj in -(ny as isize - 1)..=(ny as isize - 1) {
            let (x, y) = (di as f64 * a, dj as f64 * a);
            let el = love(x, y, a / 2.0);
            let mem: f64 = (0..8)
                .map(|k| {
                    let s = (k as f64 + 0.5) * 0.75 * a;
                    (-(s / (2.0 * a))).exp() * love(x + s, y, a / 2.0)
                })
                .sum::<f64>()
                * 0.75
                / 2.0;
            t.push(0.75 / std::f64::consts::PI * (1e-7 * el + memory * 2e-7 * mem));
        }
    }
    t
}

fn rough(n: usize, seed: u64, a: f64) -> Vec<f64> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let modes: Vec<(f64, f64, f64, f64)> = (0..12)
        .map(|_| {
            (
                rng.random_range(1.0..6.0),
                rng.random_range(1.0..6.0),
                rng.random_range(0.0..6.28),
                rng.random_range(0.3..1.0),
            )
        })
        .collect();
    let mut z = vec![0.0; n * n];
    let l = n as f64 * a;
    for i in 0..n {
        for j in 0..n {
            let (x, y) = (i as f64 * a, j as f64 * a);
            z[i * n + j] = modes
                .iter()
                .map(|(kx, ky, ph, amp)| {
                    amp * (6.283 * (kx * x + ky * y) / l + ph).cos() / (kx * kx + ky * ky)
                })
                .sum::<f64>()
                * 1e-6;
        }
    }
    let zmax = z.iter().cloned().fold(f64::MIN, f64::max);
    z.iter().map(|v| zmax - v).collect()
}

#[test]
fn fft_operator_matches_dense_on_random_vectors() {
    for &(nx, ny) in &[(5usize, 7usize), (12, 12), (17, 9), (24, 31)] {
        let t = table(nx, ny, 1e-4, 1.0);
        let tab = OffsetTable { nx, ny, values: &t };
        let mut fft = ToeplitzFft::new(tab);
        let mut dense = DenseOperator::new(tab);
        let mut rng = ChaCha8Rng::seed_from_u64(nx as u64 * 1000 + ny as u64);
        let x: Vec<f64> = (0..nx * ny).map(|_| rng.random_range(-1.0..1.0)).collect();
        let mut y1 = vec![0.0; nx * ny];
        let mut y2 = vec![0.0; nx * ny];
        use viscoslide::operator::GridOperator;
        fft.apply(&x, &mut y1);
        dense.apply(&x, &mut y2);
        let num: f64 = y1
            .iter()
            .zip(&y2)
            .map(|(a, b)| (a - b).powi(2))
            .sum::<f64>()
            .sqrt();
        let den: f64 = y2.iter().map(|b| b * b).sum::<f64>().sqrt();
        // Both are exact up to round-off; FFT round-off is ~eps log N.
        assert!(num / den < 1e-12, "{nx}x{ny}: rel err {}", num / den);
    }
}

#[test]
fn iterative_matches_dense_direct_on_nonsymmetric_operator() {
    for &(n, memory) in &[(24usize, 0.0), (24, 1.0), (32, 1.0)] {
        let a = 1e-4;
        let t = table(n, n, a, memory);
        let tab = OffsetTable {
            nx: n,
            ny: n,
            values: &t,
        };
        let g = rough(n, 7 + n as u64, a);
        let load = 0.02 * 1e7 * 1e-6 * (n as f64 * a); // a few percent contact
        let dense = DenseOperator::new(tab);
        let (p_ref, d_ref) =
            reference::solve_dense(dense.matrix(), &g, a * a, Control::Load(load), 500).unwrap();
        let mut be = CpuBackend::new(ToeplitzFft::new(tab));
        let l00 = tab.get(0, 0);
        let (sol, info) = solver::solve(
            &mut be,
            &g,
            a * a,
            l00,
            Control::Load(load),
            &SolverParams::default(),
            &mut solver::Silent,
        )
        .unwrap();
        let cells = sol.contact.iter().filter(|&&c| c > 0.5).count();
        assert!(cells > 3 && cells < n * n / 3, "partial contact: {cells}");
        for i in 0..n * n {
            assert_eq!(
                sol.pressure[i] > 0.0,
                p_ref[i] > 0.0,
                "contact set differs at {i}"
            );
        }
        let num: f64 = sol
            .pressure
            .iter()
            .zip(&p_ref)
            .map(|(x, y)| (x - y).powi(2))
            .sum::<f64>()
            .sqrt();
        let den: f64 = p_ref.iter().map(|y| y * y).sum::<f64>().sqrt();
        assert!(num / den < 1e-8, "n={n}: pressure rel err {}", num / den);
        assert!((sol.approach - d_ref).abs() <= 1e-8 * d_ref.abs().max(1e-12));
        assert!(info.residual <= 1e-8 && info.load_error < 1e-10, "{info:?}");
        eprintln!(
            "n={n} memory={memory}: {} cells, {} iters, {} matvecs, rel err {:.2e}",
            cells,
            info.iterations,
            info.matvecs,
            num / den
        );
    }
}
