//! Fast against naive: the FFT operator against the dense operator, and the
//! iterative contact solver against the dense direct LCP solver (faer LU in
//! an active-set loop), with the real viscoelastic coefficients.

use crate::common;
use viscoslide::response::{Grid, SlidingResponse};

use common::*;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use viscoslide::internals::backend::CpuBackend;
use viscoslide::internals::kernel::SlidingKernel;
use viscoslide::internals::operator::{DenseOperator, GridOperator, OffsetTable, ToeplitzFft};
use viscoslide::internals::solver::{self, reference, ContactProblem, Control, SolverParams};

#[test]
fn fft_operator_matches_dense_on_random_vectors() {
    let m = paper_material();
    for &(nx, ny, speed) in &[
        (5usize, 7usize, 0.0),
        (12, 12, 0.01),
        (17, 9, 0.1),
        (24, 31, 1.0),
        (32, 32, 0.03),
    ] {
        let a = 1e-4;
        let kernel =
            SlidingKernel::new(&SlidingResponse::new(&m, speed, 0.0, None).unwrap()).unwrap();
        let table = kernel.table(&Grid::square(nx, ny, a).unwrap()).unwrap();
        let tab = OffsetTable {
            nx,
            ny,
            values: &table.values,
        };
        let mut fft = ToeplitzFft::new(tab);
        let mut dense = DenseOperator::new(tab);
        let mut rng = ChaCha8Rng::seed_from_u64(nx as u64 * 1000 + ny as u64);
        for _ in 0..3 {
            let x: Vec<f64> = (0..nx * ny).map(|_| rng.random_range(-1.0..1.0)).collect();
            let mut y1 = vec![0.0; nx * ny];
            let mut y2 = vec![0.0; nx * ny];
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
}

#[test]
fn iterative_matches_dense_direct_across_the_friction_peak() {
    let m = paper_material();
    let length = 0.01;
    for n in [24usize, 32] {
        let a = length / n as f64;
        let z = trig_surface(n, length, 6, 0.8, 0.02, 3 + n as u64);
        let g = gap_of(&z);
        let load = 3e3 * length * length;
        // xi = v tau / L from well below to well above the peak (1.17e-2).
        for xi in [1e-4, 3e-3, 1.17e-2, 5e-2, 1.0] {
            let speed = xi * length / 0.01;
            let kernel =
                SlidingKernel::new(&SlidingResponse::new(&m, speed, 0.0, None).unwrap()).unwrap();
            let table = kernel.table(&Grid::square(n, n, a).unwrap()).unwrap();
            let tab = OffsetTable {
                nx: n,
                ny: n,
                values: &table.values,
            };
            let dense = DenseOperator::new(tab);
            let (p_ref, d_ref) =
                reference::solve_dense(dense.matrix(), &g, a * a, Control::Load(load), 500)
                    .unwrap();
            let mut be = CpuBackend::new(ToeplitzFft::new(tab));
            let (sol, info) = solver::solve(
                &mut be,
                ContactProblem::new(&g, a * a, tab.get(0, 0), Control::Load(load)),
                &SolverParams::default(),
                None,
                &mut solver::Silent,
            )
            .unwrap();
            let cells = sol.contact.iter().filter(|&&c| c > 0.5).count();
            assert!(cells > 3 && cells < n * n / 2, "partial contact: {cells}");
            for (i, (p, q)) in sol.pressure.iter().zip(&p_ref).enumerate() {
                assert_eq!(
                    *p > 0.0,
                    *q > 0.0,
                    "n={n} xi={xi}: contact set differs at {i}"
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
            assert!(
                num / den < 1e-8,
                "n={n} xi={xi}: pressure rel err {}",
                num / den
            );
            assert!((sol.approach - d_ref).abs() <= 1e-8 * d_ref.abs());
            assert!(info.residual <= 1e-8 && info.load_error < 1e-10, "{info:?}");
            eprintln!(
                "n={n} xi={xi:.1e}: {cells} cells, {} iterations, {} matvecs, pressure rel err {:.2e}",
                info.iterations,
                info.matvecs,
                num / den
            );
        }
    }
}
