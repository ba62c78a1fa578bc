//! The heated solve's shared case (tests/heat/heated.rs on the CPU,
//! tests/gpu/heated.rs on the device as a pad), and the isothermal solve
//! its answer is checked against.

use viscoslide::problem::{Executor, Problem, Silent, Solution};

/// The default config's single-relaxation rubber with the "universal" WLF
/// constants at `T_ref = 17 C`, a 32^2 periodic cell of 0.2 mm at 1 MPa
/// sliding at 0.1 m/s under a 5 cm block: a rise of kelvins (the block's
/// background heating dominates), in the range where the background's
/// formula holds (no warning).
pub const HEATED_CELL: &str = r#"
[material]
model = "sls"
relaxed_modulus = 3.3333333333333335e6
glassy_modulus = 1.0e7
creep_time = 1e-4
poisson = 0.5
wlf = [8.86, 101.6, 17.0]

[surface.generate]
n = 32
length = 0.0002
hurst = 0.8
scales = 4
rms_slope = 0.3
seed = 3

[loading]
mean_pressure = 1e6
speed = 0.1
temperature = 17.0

[solver]
formulation = "periodic"
tolerance = 1e-11

[analysis]
enabled = false

[heating]
conductivity = 0.25
diffusivity = 1e-7
block_length = 0.05
"#;

/// [`HEATED_CELL`] as a finite pad (no block, whose background heating a
/// periodic cell needs), for `solver.formulation = "non_periodic"`: the
/// surface work of its pressure as the source (the default on a pad).
pub fn heated_pad() -> String {
    HEATED_CELL.replace("block_length = 0.05\n", "")
}

/// The isothermal solve of `problem` at `t` \[C\] on the CPU, from
/// scratch.
pub fn isothermal_at(problem: &Problem, t: f64) -> Solution {
    let mut at = problem.clone();
    at.material = problem.material.at_temperature(t).unwrap();
    at.solve(&Executor::Cpu, &mut Silent).unwrap()
}
