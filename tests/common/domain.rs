//! Periodic against non-periodic solves of one rough surface, shared by the
//! domain-size test and the example that regenerates the study in docs/.
#![allow(dead_code)]

use viscoslide::internals::analysis::{friction_force_periodic, friction_force_stencil};
use viscoslide::internals::backend::CpuBackend;
use viscoslide::internals::operator::PeriodicResponse;
use viscoslide::internals::operator::SpectralPeriodic;
use viscoslide::internals::solver::{self, ContactProblem, Control, SolverParams};
use viscoslide::response::{Grid, SlidingResponse};

pub const LENGTH: f64 = 0.01;
pub const TAU: f64 = 0.01;
/// Nominal pressures [Pa]: about 1 % and 5 % of contact at this slope.
pub const LOADS: [f64; 2] = [2e3, 1e4];
pub const SLOPE: f64 = 0.1;

/// `(mu, contact fraction)` of one formulation.
#[derive(Debug, Clone, Copy)]
pub struct Outcome {
    pub mu: f64,
    pub area: f64,
}

pub fn surface(n: usize) -> Vec<f64> {
    super::trig_surface(n, LENGTH, 16, 0.8, SLOPE, 11)
}

pub fn periodic(z: &[f64], n: usize, speed: f64, p0: f64) -> Outcome {
    let material = super::paper_material();
    let a = LENGTH / n as f64;
    let op = SpectralPeriodic::new(
        &Grid::square(n, n, a).unwrap(),
        &SlidingResponse::new(&material, speed, 0.0, None).unwrap(),
        PeriodicResponse::Displacement,
    );
    let l00 = op.self_coefficient();
    let mut be = CpuBackend::new(op);
    let load = p0 * LENGTH * LENGTH;
    let (sol, _) = solver::solve(
        &mut be,
        ContactProblem::new(super::gap_of(z), a * a, l00, Control::Load(load)),
        &SolverParams::default(),
        None,
        &mut solver::Silent,
    )
    .unwrap();
    let mut d = SpectralPeriodic::new(
        &Grid::square(n, n, a).unwrap(),
        &SlidingResponse::new(&material, speed, 0.0, None).unwrap(),
        PeriodicResponse::SlidingSlope,
    );
    let fs = friction_force_stencil(&mut d, &sol.pressure, a * a);
    let ff = friction_force_periodic(
        &sol.pressure,
        &Grid::square(n, n, a).unwrap(),
        &SlidingResponse::new(&material, speed, 0.0, None).unwrap(),
    );
    assert!((fs - ff).abs() <= 1e-9 * ff.abs() + 1e-12 * load);
    Outcome {
        mu: -fs / load,
        area: sol.contact.iter().sum::<f64>() / (n * n) as f64,
    }
}

pub fn non_periodic(z: &[f64], n: usize, speed: f64, p0: f64) -> Outcome {
    let material = super::paper_material();
    let a = LENGTH / n as f64;
    let (sol, _, kernel) = super::solve_grid(
        &material,
        z,
        n,
        LENGTH,
        speed,
        Control::Load(p0 * LENGTH * LENGTH),
    );
    let (mu, _) = super::friction(&kernel, &material, &sol, n, a, speed);
    Outcome {
        mu,
        area: sol.contact.iter().sum::<f64>() / (n * n) as f64,
    }
}

pub fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}
