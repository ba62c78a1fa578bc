//! A GPU's mixed precision is one iteration (physics.md section 13): the
//! CPU backend's mixed-precision iteration over
//! [`MixedOperator`], whose Krylov products and preconditioner run on the
//! device in f32 and whose exact products (the residual of every GMRES
//! restart) are the host's f64 operator. Pinned here: the operator against
//! independent f64 products on both formulations, and the solve against
//! the CPU's f64 solve on both formulations and on a flat pad in full
//! contact. Skips with a reason without an adapter; fails under
//! `REQUIRE_GPU=1`.

use viscoslide::internals::backend::gpu::mixed::{impulse_response, wrapped_table, MixedOperator};
use viscoslide::internals::backend::gpu::{GpuBackend, GpuOptions};
use viscoslide::internals::backend::{Backend, CpuBackend};
use viscoslide::internals::operator::{
    GridOperator, GridWork, OffsetTable, PeriodicResponse, SpectralPeriodic, ToeplitzFft,
};
use viscoslide::internals::solver::Silent;
use viscoslide::problem::{Executor, Problem, Solution};
use viscoslide::response::{Grid, SlidingResponse};

use super::conformance::paper_table;

/// `tests/solver/mixed_precision.rs`'s problem (64^2, tolerance 1e-10)
/// at 0.1 m/s.
fn problem(formulation: &str, precision: &str) -> Problem {
    crate::common::mixed_case(formulation, precision, 0.1, "")
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs().max(1e-300)
}

fn rel_l2(a: &[f64], b: &[f64]) -> f64 {
    let num: f64 = a.iter().zip(b).map(|(x, y)| (x - y) * (x - y)).sum();
    let den: f64 = b.iter().map(|y| y * y).sum();
    (num / den).sqrt()
}

fn differing(a: &Solution, b: &Solution) -> usize {
    a.fields
        .contact
        .iter()
        .zip(&b.fields.contact)
        .filter(|(x, y)| x != y)
        .count()
}

/// The GPU's mixed solve against the CPU's f64 solve, to the CPU mixed
/// path's own tolerances (`tests/solver/mixed_precision.rs`: friction by
/// both routes and contact area within 1e-6 relative, the 1e-10 residual
/// met), with the same contact set: the device's exact products are the
/// host's f64 operator itself (the CPU's mixed path rounds its multiplier
/// to f32 and may differ by a cell). It is one iteration (one history of
/// its outer iterations) whose residuals were taken in f64: exact matvecs
/// reported, and a residual of 1e-10 that its f32 products alone do not
/// reach (the f32 iteration stops near 1e-5, `refine.rs`).
fn check_against_f64(mixed: &Solution, f64s: &Solution) {
    println!(
        "mu {:.12e} / {:.12e} ({:.1e}), area {:.1e}, {} cells differ, matvecs {} (+{} exact) / {}, residual {:.1e}",
        mixed.friction_coefficient,
        f64s.friction_coefficient,
        rel(mixed.friction_coefficient, f64s.friction_coefficient),
        rel(
            mixed.stats.contact_area_fraction,
            f64s.stats.contact_area_fraction
        ),
        differing(mixed, f64s),
        mixed.info.matvecs,
        mixed.info.exact_matvecs,
        f64s.info.matvecs,
        mixed.info.residual
    );
    assert!(mixed.backend.starts_with("gpu"), "{}", mixed.backend);
    assert_eq!(mixed.summary()["precision"], "mixed");
    assert!(mixed.info.exact_matvecs > 0, "no f64 residuals");
    assert_eq!(
        mixed.summary()["exact_matvecs"],
        mixed.info.exact_matvecs,
        "summary.json reports the exact products"
    );
    assert_eq!(f64s.info.exact_matvecs, 0);
    assert_eq!(
        mixed.info.history.len(),
        mixed.info.iterations,
        "one iteration's history"
    );
    assert!(
        rel(mixed.friction_coefficient, f64s.friction_coefficient) < 1e-6,
        "friction"
    );
    assert!(
        rel(
            mixed.friction_coefficient_dissipation,
            f64s.friction_coefficient_dissipation
        ) < 1e-6,
        "dissipation route"
    );
    assert!(
        rel(
            mixed.stats.contact_area_fraction,
            f64s.stats.contact_area_fraction
        ) < 1e-6,
        "area"
    );
    assert_eq!(differing(mixed, f64s), 0, "contact sets differ");
    assert!(
        mixed.info.residual <= 1e-10,
        "residual {}",
        mixed.info.residual
    );
}

#[test]
fn mixed_gpu_solve_is_one_iteration_with_f64_residuals() {
    let Some(ctx) = crate::common::gpu_context() else {
        return;
    };
    let gpu = Executor::Gpu(ctx);
    for formulation in ["non_periodic", "periodic"] {
        println!("{formulation}:");
        let f64s = problem(formulation, "f64")
            .solve(&Executor::Cpu, &mut Silent)
            .unwrap();
        let mixed = problem(formulation, "mixed")
            .solve(&gpu, &mut Silent)
            .unwrap();
        check_against_f64(&mixed, &f64s);
    }
}

/// A flat pad in full contact (every cell pressed, the contact set the
/// whole grid: where the preconditioner is T. Chan's circulant and where
/// the device's f32 iteration used to miss its target, `refine.rs`), at the
/// CPU mixed path's tolerances as above.
#[test]
fn mixed_gpu_solve_of_a_flat_pad() {
    let Some(ctx) = crate::common::gpu_context() else {
        return;
    };
    let flat = |precision: &str| {
        let mut p = problem("non_periodic", precision);
        p.surface.heights.iter_mut().for_each(|z| *z = 0.0);
        p
    };
    let f64s = flat("f64").solve(&Executor::Cpu, &mut Silent).unwrap();
    let mixed = flat("mixed")
        .solve(&Executor::Gpu(ctx), &mut Silent)
        .unwrap();
    assert!(
        f64s.stats.contact_area_fraction > 0.9,
        "{}",
        f64s.stats.contact_area_fraction
    );
    check_against_f64(&mixed, &f64s);
    // Every f32 product crossed the bus: the rough solve's and the smooth
    // pad's round trips counted apart (at least one per fine-grid
    // equivalent matvec: coarse grids' products count whole, and the
    // preconditioner's too); the CPU's solve has none.
    let traffic = mixed
        .device_traffic
        .expect("a mixed GPU solve counts its round trips");
    assert!(traffic.round_trips >= mixed.info.matvecs, "{traffic:?}");
    let pad = mixed.smooth_pad.expect("a non-periodic pad");
    let pad_traffic = pad.device_traffic.expect("the pad's own round trips");
    assert!(pad_traffic.round_trips >= pad.matvecs, "{pad_traffic:?}");
    assert!(f64s.device_traffic.is_none());
    assert!(f64s.smooth_pad.and_then(|p| p.device_traffic).is_none());
}

/// `x` on the cells of `cells`, a spread of signs and scales.
fn values(cells: &[usize]) -> Vec<f64> {
    cells
        .iter()
        .map(|&c| ((c * 7919 % 1013) as f64 / 1013.0 - 0.3) * 1e4)
        .collect()
}

/// Two contact sets of an `n`-cell grid (every third cell; a band of
/// rows) and the whole grid.
fn sets(nx: usize, ny: usize) -> Vec<Vec<usize>> {
    let n = nx * ny;
    vec![
        (0..n).step_by(3).collect(),
        (ny * nx / 4..ny * nx / 2).collect(),
        (0..n).collect(),
    ]
}

/// The operator's products against f64 references on every set (the
/// first again after the second, through its cached device index):
/// `apply_set` within 1e-5 relative L2 of the f64 product (the device's
/// f32 matvec, about 100 f32 rounding units for the few hundred
/// accumulated operations per entry, as `conformance.rs` bounds it; its
/// input rounded to f32 adds 6e-8) and above 1e-12 (it is f32);
/// `apply_set_exact` within 1e-12 (f64 FFTs: about 1e-15 per entry).
fn check_products(op: &mut MixedOperator, reference: impl Fn(&[usize], &[f64]) -> Vec<f64>) {
    let (nx, ny) = op.shape();
    let mut work = GridWork::default();
    let all = sets(nx, ny);
    let before = op.traffic();
    for cells in all.iter().chain(std::iter::once(&all[0])) {
        let x = values(cells);
        let want = reference(cells, &x);
        let (mut lo, mut ex) = (vec![0.0; cells.len()], vec![0.0; cells.len()]);
        op.apply_set(cells, &x, &mut lo, &mut work);
        op.apply_set_exact(cells, &x, &mut ex, &mut work);
        let (e_lo, e_ex) = (rel_l2(&lo, &want), rel_l2(&ex, &want));
        println!(
            "{} of {} cells: apply_set {e_lo:.2e}, apply_set_exact {e_ex:.2e}",
            cells.len(),
            nx * ny
        );
        assert!(e_lo <= 1e-5 && e_lo > 1e-12, "apply_set {e_lo:e}");
        assert!(e_ex <= 1e-12, "apply_set_exact {e_ex:e}");
    }
    assert_eq!(op.epsilon(), f32::EPSILON as f64);
    // One round trip per f32 product (the exact ones stay on the host):
    // each set's f32 values up and back, its positions up once per change
    // of set (the first set again after the second is a change).
    let traffic = op.traffic().since(&before);
    let values: usize = all.iter().map(Vec::len).sum::<usize>() + all[0].len();
    assert_eq!(traffic.round_trips, all.len() + 1);
    assert_eq!(traffic.set_uploads, all.len() + 1);
    assert_eq!(traffic.bytes_from_device, 4 * values as u64);
    assert_eq!(traffic.bytes_to_device, 8 * values as u64);
    assert!(traffic.to_device_s >= 0.0 && traffic.device_s > 0.0 && traffic.from_device_s >= 0.0);
}

/// The non-periodic operator against the dense sum over the set of the
/// f64 offset table (paper Eq. 7, written out here).
#[test]
fn mixed_operator_matches_the_host_f64_toeplitz_operator() {
    let Some(ctx) = crate::common::gpu_context() else {
        return;
    };
    let (nx, ny) = (48, 40);
    let table = paper_table(nx, ny, 0.01 / nx as f64, 0.1);
    let tab = OffsetTable {
        nx,
        ny,
        values: &table,
    };
    let options = GpuOptions {
        preconditioner: true,
        ..GpuOptions::default()
    };
    let device = GpuBackend::new(ctx, nx, ny, &table, options).unwrap();
    let host = ToeplitzFft::new(tab).with_preconditioner();
    let mut op = MixedOperator::new(device, Box::new(host));
    assert!(op.has_preconditioner());
    let dense = |cells: &[usize], x: &[f64]| -> Vec<f64> {
        cells
            .iter()
            .map(|&i| {
                let (ix, iy) = ((i / ny) as isize, (i % ny) as isize);
                cells
                    .iter()
                    .zip(x)
                    .map(|(&k, &xk)| {
                        let (kx, ky) = ((k / ny) as isize, (k % ny) as isize);
                        tab.get(ix - kx, iy - ky) * xk
                    })
                    .sum()
            })
            .collect()
    };
    check_products(&mut op, dense);
    // Wrapped in the CPU backend it is the mixed iteration's operator.
    assert!(CpuBackend::new(op).refines());
}

/// The periodic operator (its circulant given to the device as an offset
/// table, [`wrapped_table`]) against the host's f64 spectral product of
/// the set's values scattered on the grid.
#[test]
fn mixed_operator_matches_the_host_f64_periodic_operator() {
    let Some(ctx) = crate::common::gpu_context() else {
        return;
    };
    let (nx, ny, a) = (48, 40, 1e-4);
    let material = crate::common::paper_material();
    let response = SlidingResponse::new(&material, 0.05, 0.3, None).unwrap();
    let grid = Grid::square(nx, ny, a).unwrap().periodic();
    let spectral = || SpectralPeriodic::new(&grid, &response, PeriodicResponse::Displacement);
    let mut host = spectral().with_preconditioner();
    let c = impulse_response(nx * ny, |x, y| host.apply_exact(x, y));
    let k = impulse_response(nx * ny, |x, y| host.precondition(x, y));
    let options = GpuOptions::default();
    let device = GpuBackend::new(ctx.clone(), nx, ny, &wrapped_table(nx, ny, &c), options);
    let inverse = GpuBackend::new(ctx, nx, ny, &wrapped_table(nx, ny, &k), options);
    let mut op = MixedOperator::new(device.unwrap(), Box::new(host)).with_inverse(inverse.unwrap());
    assert!(op.has_preconditioner());
    let mut reference = spectral();
    let product = |cells: &[usize], x: &[f64]| -> Vec<f64> {
        let mut full = vec![0.0; nx * ny];
        for (&c, &v) in cells.iter().zip(x) {
            full[c] = v;
        }
        let mut y = vec![0.0; nx * ny];
        spectral().apply(&full, &mut y);
        cells.iter().map(|&c| y[c]).collect()
    };
    check_products(&mut op, product);
    // The preconditioner, the host's inverse multiplier, to f32 rounding
    // (bound as the products').
    let mut host = spectral().with_preconditioner();
    let mut work = GridWork::default();
    for cells in sets(nx, ny) {
        let x = values(&cells);
        let (mut got, mut want) = (vec![0.0; cells.len()], vec![0.0; cells.len()]);
        op.precondition_set(&cells, &x, &mut got, &mut work);
        host.precondition_set(&cells, &x, &mut want, &mut work);
        let e = rel_l2(&got, &want);
        println!("preconditioner on {} cells: {e:.2e}", cells.len());
        assert!(e <= 1e-5, "{e:e}");
    }
    // The whole-grid product too.
    let x = values(&(0..nx * ny).collect::<Vec<_>>());
    let (mut y, mut want) = (vec![0.0; nx * ny], vec![0.0; nx * ny]);
    op.apply(&x, &mut y);
    reference.apply(&x, &mut want);
    let e = rel_l2(&y, &want);
    println!("whole grid: {e:.2e}");
    assert!(e <= 1e-5, "{e:e}");
}
