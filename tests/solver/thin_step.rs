//! The friction across the upper end of the thin-layer band (`h = a`,
//! `kernel/thin_band.rs`: the law's grid continuation below, the resolved
//! cell integral above; physics.md section 3 and 5) against the same
//! surface refined four times at the same thickness, where `h = 4 a` and
//! the resolved kernel converges (measured 0.2 % from 256^2 to 512^2).

use viscoslide::config::{self, SolverConfig};
use viscoslide::internals::solver;
use viscoslide::problem::{Executor, Problem};

/// `configs/default.toml`'s pad under 1 MPa on a bonded incompressible
/// layer of thickness `h` (near full contact), `n^2` cells, `xi = v tau /
/// L`, in `formulation` (`"non_periodic"` or `"periodic"`).
pub(crate) fn bonded_pad(n: usize, h: f64, xi: f64, formulation: &str) -> Problem {
    bonded_pad_with(n, h, xi, formulation, &[])
}

/// [`bonded_pad`] with `overrides` (`section.key=value`) applied.
pub(crate) fn bonded_pad_with(
    n: usize,
    h: f64,
    xi: f64,
    formulation: &str,
    overrides: &[String],
) -> Problem {
    let text = format!(
        r#"
[material]
model = "sls"
relaxed_modulus = 3.3333333333333335e6
glassy_modulus = 1.0e7
creep_time = 0.01
poisson = 0.5

[surface.generate]
n = {n}
length = 0.01
hurst = 0.8
scales = 32
rms_slope = 0.02
rolloff_q0 = 5026.548
seed = 1

[loading]
mean_pressure = 1e6
xi = {xi:e}

[layer]
thickness = {h:e}
base = "bonded"

[solver]
tolerance = 1e-8
"#
    );
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("c.toml");
    std::fs::write(&path, text).unwrap();
    let sc: SolverConfig = toml::from_str(&format!("formulation = \"{formulation}\"")).unwrap();
    Problem::from_config(&config::load(&path, overrides).unwrap())
        .unwrap()
        .with_solver_config(&sc)
        .unwrap()
}

/// The friction of [`bonded_pad`] in the non-periodic formulation.
fn mu(n: usize, h: f64, xi: f64) -> f64 {
    let problem = bonded_pad(n, h, xi, "non_periodic");
    let s = problem.solve(&Executor::Cpu, &mut solver::Silent).unwrap();
    s.friction_coefficient
}

/// h/a swept across the band's upper end on the 64^2 pad, each against
/// the 256^2 refinement of the same surface (same Fourier modes) at the
/// same `h`:
/// * memory resolved (`v tau = 4 a`, xi = 0.0625), h/a = 0.9, 0.999,
///   1.001, 1.1: each side within the grid's discretisation error of the
///   refined value, measured +4.3 %, +4.1 % (continuation) and -6.0 %,
///   -5.7 % (resolved); asserted 8 %, so the step at `h = a` is at most
///   16 % (measured 9.6 %). The continuation's friction
///   stencil as the centred difference of its coefficients read -18 %
///   there (1.32e-3 against 1.60e-3) and fails this.
/// * the issue's case (`v tau = 0.75 a`, xi = 1.17e-2, memory within a
///   cell), h/a = 0.999 and 1.001: +22 % (continuation: its memory is
///   that of the sharp cell-constant pressure) and +3 % (resolved);
///   asserted 25 %. The centred difference read -38 % (5.2e-4 against
///   8.4e-4; a 40 % step to the resolved side's 8.6e-4); the step is now
///   16 %.
#[test]
fn friction_is_continuous_across_the_band_upper_end() {
    let a = 0.01 / 64.0;
    for (xi, ratios, bound) in [
        (0.0625, &[0.9, 0.999, 1.001, 1.1][..], 0.08),
        (1.17e-2, &[0.999, 1.001][..], 0.25),
    ] {
        let mut sides = vec![];
        for &r in ratios {
            let (coarse, fine) = (mu(64, r * a, xi), mu(256, r * a, xi));
            let e = coarse / fine - 1.0;
            eprintln!("xi = {xi}, h/a = {r}: mu {coarse:.4e}, 256^2 {fine:.4e}: {e:+.3}");
            assert!(
                e.abs() < bound,
                "xi = {xi}, h/a = {r}: {coarse:e} vs {fine:e}"
            );
            sides.push(coarse);
        }
        let k = ratios.iter().position(|&r| r > 1.0).unwrap();
        let step = (sides[k] / sides[k - 1] - 1.0).abs();
        eprintln!("xi = {xi}: step at h = a {step:.3}");
        assert!(step < 2.0 * bound, "xi = {xi}: step {step:e}");
    }
}
