//! Elastic periodic contact of a height map read from `.npy`, for the peer
//! comparison `scripts/tamaas_compare.py` (not run in CI).
//!
//! Usage: `periodic_elastic SURFACE.npy LENGTH_M YOUNG_PA POISSON TOLERANCE P1,P2,...`
//! with the nominal pressures `P` in Pa. Prints one JSON object per load:
//! contact fraction, mean gap, approach, iterations and the wall time of
//! operator construction plus solve.

use std::time::Instant;
use viscoslide::internals::operator::PeriodicResponse;
use viscoslide::response::{Grid, SlidingResponse};

use viscoslide::internals::backend::CpuBackend;
use viscoslide::internals::operator::SpectralPeriodic;
use viscoslide::internals::solver::{self, ContactProblem, Control, SolverParams};
use viscoslide::io::npy;
use viscoslide::material::{CreepSpectrum, Material};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.len() != 6 {
        return Err(
            "usage: periodic_elastic SURFACE.npy LENGTH_M YOUNG_PA POISSON TOLERANCE P1,P2,..."
                .into(),
        );
    }
    let (nx, ny, z) = npy::read_2d(&args[0])?;
    let length: f64 = args[1].parse()?;
    let young: f64 = args[2].parse()?;
    let poisson: f64 = args[3].parse()?;
    let tolerance: f64 = args[4].parse()?;
    let loads: Vec<f64> = args[5]
        .split(',')
        .map(|s| s.parse())
        .collect::<Result<_, _>>()?;
    if nx != ny {
        return Err("the comparison uses square grids".into());
    }
    let material = Material::new(CreepSpectrum::new(young, vec![])?, poisson)?;
    let a = length / nx as f64;
    let zmax = z.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
    let g: Vec<f64> = z.iter().map(|v| zmax - v).collect();
    let params = SolverParams {
        tolerance,
        ..Default::default()
    };
    for p0 in loads {
        let start = Instant::now();
        let op = SpectralPeriodic::new(
            &Grid::square(nx, ny, a).unwrap(),
            &SlidingResponse::new(&material, 0.0, 0.0, None).unwrap(),
            PeriodicResponse::Displacement,
        );
        let l00 = op.self_coefficient();
        let mut be = CpuBackend::new(op);
        let (sol, info) = solver::solve(
            &mut be,
            ContactProblem::new(&g, a * a, l00, Control::Load(p0 * length * length)),
            &params,
            None,
            &mut solver::Silent,
        )?;
        let seconds = start.elapsed().as_secs_f64();
        let n = (nx * ny) as f64;
        let fraction = sol.contact.iter().sum::<f64>() / n;
        let mean_gap = sol.gap.iter().map(|v| v.max(0.0)).sum::<f64>() / n;
        println!(
            "{{\"pressure\": {p0:e}, \"contact_fraction\": {fraction:.12e}, \"mean_gap\": {mean_gap:.12e}, \"approach\": {:.12e}, \"iterations\": {}, \"matvecs\": {}, \"residual\": {:e}, \"seconds\": {seconds:.6}}}",
            sol.approach, info.iterations, info.matvecs, info.residual
        );
    }
    Ok(())
}
