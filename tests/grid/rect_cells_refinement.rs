//! Refinement study on rectangular cells (physics.md sections 9.5 and 11):
//! the same continuous surface sampled at the cell centres of square, 2:1
//! and 1:2.5 cells converges to the same friction and contact area.

use std::f64::consts::TAU;

use rand::{Rng, SeedableRng};
use viscoslide::internals::solver::{Control, Silent};
use viscoslide::material::{CreepSpectrum, Material};
use viscoslide::problem::{Executor, Problem};
use viscoslide::surface::HeightMap;

const LENGTH: f64 = 0.01;

/// A smooth band-limited surface on the square `L x L` (integer wave
/// numbers up to 4 in `2 pi / L`, rms slope 0.02) at the centres of an
/// `nx x ny` grid of `L/nx x L/ny` cells.
fn surface(nx: usize, ny: usize) -> Vec<f64> {
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(17);
    let kmax = 4;
    let mut modes = Vec::new();
    for kx in -kmax..=kmax {
        for ky in 0..=kmax {
            let k2 = (kx * kx + ky * ky) as f64;
            if (ky == 0 && kx <= 0) || k2 > (kmax * kmax) as f64 {
                continue;
            }
            modes.push((
                kx as f64,
                ky as f64,
                k2.powf(-0.9),
                rng.random_range(0.0..TAU),
            ));
        }
    }
    let q = TAU / LENGTH;
    let s2: f64 = modes
        .iter()
        .map(|m| m.2 * m.2 * q * q * (m.0 * m.0 + m.1 * m.1) / 2.0)
        .sum();
    let scale = 0.02 / s2.sqrt();
    let (ax, ay) = (LENGTH / nx as f64, LENGTH / ny as f64);
    (0..nx * ny)
        .map(|c| {
            let (x, y) = (((c / ny) as f64 + 0.5) * ax, ((c % ny) as f64 + 0.5) * ay);
            scale
                * modes
                    .iter()
                    .map(|m| m.2 * (q * (m.0 * x + m.1 * y) + m.3).cos())
                    .sum::<f64>()
        })
        .collect()
}

/// `(mu by Eq. 9, mu by dissipation, A/A0)` on an `nx x ny` grid, 3 kPa at
/// the friction peak of the paper material (`xi = 1.17e-2`).
fn solve(nx: usize, ny: usize) -> (f64, f64, f64) {
    let m = Material::new(
        CreepSpectrum::standard_linear_solid(1e7 / 3.0, 1e7, 0.01).unwrap(),
        0.5,
    )
    .unwrap();
    let map = HeightMap::with_cells(
        nx,
        ny,
        LENGTH / nx as f64,
        LENGTH / ny as f64,
        surface(nx, ny),
    )
    .unwrap();
    let load = 3e3 * LENGTH * LENGTH;
    let s = Problem::new(m, map, Control::Load(load), 1.17e-2 * LENGTH / 0.01)
        .solve(&Executor::Cpu, &mut Silent)
        .unwrap();
    (
        s.friction_coefficient,
        s.friction_coefficient_dissipation,
        s.stats.contact_area_fraction,
    )
}

#[test]
fn square_and_rectangular_cells_converge_to_the_same_friction_and_area() {
    // Three levels per shape, each halving both sides of the cell.
    let shapes: [(&str, [(usize, usize); 3]); 3] = [
        ("square", [(32, 32), (64, 64), (128, 128)]),
        ("2:1", [(16, 32), (32, 64), (64, 128)]),
        ("1:2.5", [(40, 16), (80, 32), (160, 64)]),
    ];
    let mut results = Vec::new();
    for (name, grids) in shapes {
        let mut levels = Vec::new();
        for (nx, ny) in grids {
            let (mu, mu_d, area) = solve(nx, ny);
            println!(
                "{name:6} {nx:4} x {ny:4}: mu {mu:.6e} (dissipation {mu_d:.6e}), A/A0 {area:.6}"
            );
            levels.push((mu, mu_d, area));
        }
        results.push((name, levels));
    }
    let rel = |a: f64, b: f64| (a - b).abs() / b.abs();
    let square = &results[0].1;
    for (name, levels) in &results[1..] {
        for (what, pick) in [
            (
                "mu",
                (|l: &(f64, f64, f64)| l.0) as fn(&(f64, f64, f64)) -> f64,
            ),
            ("A/A0", |l: &(f64, f64, f64)| l.2),
        ] {
            let diffs: Vec<f64> = (0..3)
                .map(|k| rel(pick(&levels[k]), pick(&square[k])))
                .collect();
            // The discretisation error left at the finest level, estimated
            // (first-order convergence) by the last refinement step of
            // either shape.
            let step = rel(pick(&levels[2]), pick(&levels[1]))
                .max(rel(pick(&square[2]), pick(&square[1])));
            println!("{name} vs square, {what}: differences {diffs:?}, last step {step:.3e}");
            assert!(
                diffs[2] < diffs[0],
                "{name} {what}: the difference to square cells does not shrink: {diffs:?}"
            );
            assert!(
                diffs[2] <= 2.0 * step,
                "{name} {what}: the finest difference {} exceeds twice the last step {step}",
                diffs[2]
            );
        }
    }
}
