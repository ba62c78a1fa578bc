//! Near-full contact on the non-periodic (Toeplitz) grid: where the contact
//! set covers most of the grid the inner solves are preconditioned with the
//! inverse of T. Chan's optimal circulant (`operator::chan_kernel`) instead
//! of the restricted inverse of the padded circulant. The answer is the
//! dense direct solver's, and the same as the padded preconditioner's; the
//! work is pinned (BENCHMARKS.md, "Near-full contact").

use crate::common;
use viscoslide::response::{Grid, SlidingResponse};

use common::*;
use viscoslide::internals::backend::CpuBackend;
use viscoslide::internals::kernel::SlidingKernel;
use viscoslide::internals::operator::{
    DenseOperator, GridOperator, OffsetTable, ToeplitzFft, CHAN_FRACTION,
};
use viscoslide::internals::solver::{
    self, reference, ContactProblem, Control, SolveInfo, SolverParams,
};

const LENGTH: f64 = 0.01;
/// xi = v tau / L = 1.17e-2 (the friction peak of `configs/default.toml`).
const SPEED: f64 = 1.17e-2 * LENGTH / 0.01;

fn table(n: usize) -> Vec<f64> {
    let kernel =
        SlidingKernel::new(&SlidingResponse::new(&paper_material(), SPEED, 0.0, None).unwrap())
            .unwrap();
    kernel
        .table(&Grid::square(n, n, LENGTH / n as f64).unwrap())
        .unwrap()
        .values
}

/// The padded circulant's restricted inverse only, whatever the contact
/// set (the preconditioner before the optimal circulant was added): the
/// operator without [`GridOperator::set_contact_fraction`].
struct PaddedOnly(ToeplitzFft);

impl GridOperator for PaddedOnly {
    fn shape(&self) -> (usize, usize) {
        self.0.shape()
    }
    fn apply(&mut self, x: &[f64], y: &mut [f64]) {
        self.0.apply(x, y)
    }
    fn has_preconditioner(&self) -> bool {
        self.0.has_preconditioner()
    }
    fn precondition(&mut self, x: &[f64], y: &mut [f64]) {
        self.0.precondition(x, y)
    }
}

fn solve<O: GridOperator>(
    op: O,
    g: &[f64],
    n: usize,
    l00: f64,
    load: f64,
) -> (solver::ContactSolution, SolveInfo) {
    let a = LENGTH / n as f64;
    let mut be = CpuBackend::new(op);
    solver::solve(
        &mut be,
        ContactProblem::new(g, a * a, l00, Control::Load(load)),
        &SolverParams::default(),
        None,
        &mut solver::Silent,
    )
    .unwrap()
}

fn rel_diff(x: &[f64], y: &[f64]) -> f64 {
    let num: f64 = x.iter().zip(y).map(|(a, b)| (a - b).powi(2)).sum();
    let den: f64 = y.iter().map(|b| b * b).sum();
    (num / den).sqrt()
}

fn fraction(c: &[f64]) -> f64 {
    c.iter().filter(|&&v| v > 0.5).count() as f64 / c.len() as f64
}

#[test]
fn near_full_contact_matches_dense_direct() {
    let n = 32;
    let a = LENGTH / n as f64;
    let values = table(n);
    let tab = OffsetTable {
        nx: n,
        ny: n,
        values: &values,
    };
    let g = gap_of(&trig_surface(n, LENGTH, 6, 0.8, 0.02, 11));
    let dense = DenseOperator::new(tab);
    let mut full = false;
    // Nominal pressures from about 80 % contact to full contact.
    for pressure in [1e5, 3e5, 1e6] {
        let load = pressure * LENGTH * LENGTH;
        let (p_ref, d_ref) =
            reference::solve_dense(dense.matrix(), &g, a * a, Control::Load(load), 500).unwrap();
        let (sol, info) = solve(
            ToeplitzFft::new(tab).with_preconditioner(),
            &g,
            n,
            tab.get(0, 0),
            load,
        );
        let f = fraction(&sol.contact);
        assert!(f > CHAN_FRACTION, "{pressure} Pa: contact {f}");
        full |= f == 1.0;
        assert!(info.preconditioner_applications > 0, "{info:?}");
        for (i, (p, q)) in sol.pressure.iter().zip(&p_ref).enumerate() {
            assert_eq!(
                *p > 0.0,
                *q > 0.0,
                "{pressure} Pa: contact set differs at {i}"
            );
        }
        // Both solve the same LCP, the iteration to a complementarity
        // residual of 1e-8 (as in solver_dense_reference.rs).
        let err = rel_diff(&sol.pressure, &p_ref);
        assert!(err < 1e-8, "{pressure} Pa: pressure rel err {err}");
        assert!((sol.approach - d_ref).abs() <= 1e-8 * d_ref.abs());
        assert!(info.residual <= 1e-8 && info.load_error < 1e-10, "{info:?}");
        eprintln!(
            "{pressure:.0e} Pa: contact {f:.4}, {} matvecs, pressure rel err {err:.2e}",
            info.matvecs
        );
    }
    assert!(full, "one case in full contact");
}

/// 256 x 256 grids solved from the bearing-area guess (no cascade) near
/// and at full contact: the answer of the padded preconditioner, and the
/// work pinned. Measured: 97.7 % contact, 118 matvecs (padded: 123; on a
/// single grid from the bearing-area guess the outer iterations dominate);
/// full contact, 62 matvecs (padded: 98; the gain grows with the grid,
/// 252 -> 62 at 512^2 through the cascade).
#[test]
fn near_full_contact_needs_few_matvecs() {
    let n = 256;
    let values = table(n);
    let tab = OffsetTable {
        nx: n,
        ny: n,
        values: &values,
    };
    // (modes of the surface, nominal pressure, matvec cap, contact, whether
    // it must beat the padded preconditioner by a quarter at least).
    for (kmax, pressure, cap, contact, faster) in
        [(64, 2e5, 150, 0.97, false), (24, 3e5, 80, 1.0, true)]
    {
        let g = gap_of(&trig_surface(n, LENGTH, kmax, 0.8, 0.02, 5));
        let load = pressure * LENGTH * LENGTH;
        let (new, info) = solve(
            ToeplitzFft::new(tab).with_preconditioner(),
            &g,
            n,
            tab.get(0, 0),
            load,
        );
        let (old, old_info) = solve(
            PaddedOnly(ToeplitzFft::new(tab).with_preconditioner()),
            &g,
            n,
            tab.get(0, 0),
            load,
        );
        let f = fraction(&new.contact);
        eprintln!(
            "{pressure:.0e} Pa: contact {f:.4}: {} matvecs ({} iterations), padded preconditioner {} ({} iterations)",
            info.matvecs, info.iterations, old_info.matvecs, old_info.iterations
        );
        assert!(f >= contact, "{pressure} Pa: contact {f}");
        assert_eq!(new.contact, old.contact, "{pressure} Pa: same contact set");
        // Both to a complementarity residual of 1e-8: the pressures agree
        // to about that.
        let err = rel_diff(&new.pressure, &old.pressure);
        assert!(err < 1e-7, "{pressure} Pa: pressure rel diff {err}");
        assert!(
            info.matvecs <= cap,
            "{pressure} Pa: {} matvecs",
            info.matvecs
        );
        assert!(
            !faster || 4 * info.matvecs <= 3 * old_info.matvecs,
            "{pressure} Pa: {} against {}",
            info.matvecs,
            old_info.matvecs
        );
    }
}
