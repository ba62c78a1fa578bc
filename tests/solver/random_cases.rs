//! The random-case convergence set (issue #41, item 1): valid problems
//! drawn deterministically by seed across materials (SLS, Prony, SLS with a
//! WLF shift at a temperature), formulations (non-periodic, periodic),
//! precisions (f64, mixed), control (normal load, mean pressure, approach),
//! speeds over 8 decades, glassy/relaxed ratios up to 1000, rectangular
//! grids and layers. Every case must converge or be refused with a message
//! that names an invalid input; each converged answer is checked here as a
//! solution of the complementarity problem, from its fields, not from the
//! solver's own report (`check_complementarity`).
//!
//! A bounded subset runs with the suite; the whole set with
//! `cargo test --release --test solver random_cases::full -- --ignored --nocapture`
//! (counts in BENCHMARKS.md, "Random-case convergence set"). With
//! `VISCOSLIDE_RANDOM_CASES_DIR=DIR` the full run also writes each case's
//! TOML to `DIR/case-SEED.toml`, for running another build's command line
//! on the same set.

use viscoslide::config;
use viscoslide::internals::solver::{Control, SolverError};
use viscoslide::problem::{Executor, Problem, Solution};

/// Cases in the full set.
const FULL: u64 = 240;
/// Every `SUBSET_STRIDE`-th case runs with the suite.
const SUBSET_STRIDE: u64 = 8;

/// SplitMix64: a small deterministic generator (no dependency).
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in `[0, 1)`.
    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }

    fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }

    /// Log-uniform in `[lo, hi]`.
    fn log(&mut self, lo: f64, hi: f64) -> f64 {
        (lo.ln() + (hi.ln() - lo.ln()) * self.unit()).exp()
    }

    fn pick<T: Copy>(&mut self, items: &[T]) -> T {
        items[(self.next() % items.len() as u64) as usize]
    }
}

/// The configuration of case `seed` (TOML text).
pub(crate) fn case(seed: u64) -> String {
    let mut r = Rng(seed.wrapping_mul(0x2545_f491_4f6c_dd1d) ^ 0x5eed);
    let e0 = r.log(1e5, 1e7);
    let ratio = r.log(2.0, 1000.0);
    let poisson = r.uniform(0.3, 0.5);
    let tau = r.log(1e-4, 1.0);
    let material = match r.next() % 5 {
        // A Prony series of three branches sharing E_inf - E0, times a
        // decade apart around tau.
        0 => {
            let w = [r.unit() + 0.1, r.unit() + 0.1, r.unit() + 0.1];
            let s: f64 = w.iter().sum();
            let branches: Vec<String> = w
                .iter()
                .enumerate()
                .map(|(j, wj)| {
                    format!(
                        "[{:e}, {:e}]",
                        (ratio - 1.0) * e0 * wj / s,
                        tau * 10f64.powi(j as i32 - 1)
                    )
                })
                .collect();
            format!(
                "model = \"prony\"\nrelaxed_modulus = {e0:e}\nprony = [{}]\npoisson = {poisson}\n",
                branches.join(", ")
            )
        }
        // SLS with a WLF shift, at a temperature within 30 K of T_ref
        // (a_T between about 1e-3 and 1e4 for these constants).
        1 => format!(
            "model = \"sls\"\nrelaxed_modulus = {e0:e}\nglassy_modulus = {:e}\ncreep_time = {tau:e}\npoisson = {poisson}\nwlf = [8.86, 101.6, 20.0]\n",
            ratio * e0
        ),
        _ => format!(
            "model = \"sls\"\nrelaxed_modulus = {e0:e}\nglassy_modulus = {:e}\ncreep_time = {tau:e}\npoisson = {poisson}\n",
            ratio * e0
        ),
    };
    let n = r.pick(&[16usize, 24, 32, 48, 64]);
    let ny = if r.unit() < 0.3 { n / 2 } else { n };
    let length = r.log(1e-3, 2e-2);
    let hurst = r.uniform(0.5, 0.9);
    let scales = r.pick(&[2usize, 3, 4, 6, 8]).min(n / 4);
    let rms_height = r.log(1e-3, 0.1) * length / scales as f64;
    let surface_seed = r.next() % 1_000_000_000;
    let speed = r.log(1e-6, 1e2);
    let mut loading = format!("speed = {speed:e}\n");
    if material.contains("wlf") {
        loading += &format!("temperature = {}\n", r.uniform(-10.0, 50.0));
    }
    // Nominal pressures from 1e-4 to 0.3 of the relaxed modulus.
    let p0 = e0 * r.log(1e-4, 0.3);
    let area = length * length * ny as f64 / n as f64;
    match r.next() % 3 {
        0 => loading += &format!("normal_load = {:e}\n", p0 * area),
        1 => loading += &format!("mean_pressure = {p0:e}\n"),
        _ => loading += &format!("approach = {:e}\n", rms_height * r.uniform(0.1, 3.0)),
    }
    let formulation = if r.unit() < 0.4 {
        "periodic"
    } else {
        "non_periodic"
    };
    let precision = if r.unit() < 0.3 { "mixed" } else { "f64" };
    let layer = if r.unit() < 0.2 {
        format!(
            "\n[layer]\nthickness = {:e}\nbase = \"{}\"\n",
            length * r.log(0.02, 2.0),
            r.pick(&["bonded", "frictionless"])
        )
    } else {
        String::new()
    };
    format!(
        "[material]\n{material}\n[surface.generate]\nn = {n}\nny = {ny}\nlength = {length:e}\nhurst = {hurst}\nscales = {scales}\nseed = {surface_seed}\nrms_height = {rms_height:e}\n\n[loading]\n{loading}\n[solver]\nformulation = \"{formulation}\"\nprecision = \"{precision}\"\n{layer}"
    )
}

/// What became of one case.
#[derive(Debug)]
pub(crate) enum Outcome {
    Converged { matvecs: usize },
    Refused(String),
    Failed(String),
}

/// Check `solution` of `problem` as a solution of the complementarity
/// problem from its fields: `p >= 0` on every cell; `gap >= 0` and
/// `p gap = 0` to the rounding of the gap (a contact cell's gap is a
/// cancellation of terms of size `|u|`, so it is known to about
/// `eps |u|_max`; the bound is `tol_gap = 1e-6 |u|_max`, far above the
/// f64 and mixed (f32 products, f64 refinement) rounding and far below
/// any physical gap); the load (load control) to `1e-6` relative, which
/// the solver's 1e-8 residual meets with room. Returns what fails.
pub(crate) fn check_complementarity(problem: &Problem, solution: &Solution) -> Result<(), String> {
    let f = &solution.fields;
    let pmax = f.pressure.iter().fold(0.0f64, |a, &p| a.max(p));
    if pmax <= 0.0 {
        return Err("no cell carries pressure".into());
    }
    if let Some(p) = f.pressure.iter().find(|&&p| p.is_nan() || p < 0.0) {
        return Err(format!("negative or NaN pressure {p:e}"));
    }
    let umax = f.displacement.iter().fold(0.0f64, |a, &u| a.max(u.abs()));
    let tol_gap = 1e-6 * umax.max(f64::MIN_POSITIVE);
    if let Some(g) = f.gap.iter().find(|&&g| g.is_nan() || g < -tol_gap) {
        return Err(format!("gap {g:e} below -{tol_gap:e}"));
    }
    for (&p, &g) in f.pressure.iter().zip(&f.gap) {
        if p > 1e-6 * pmax && g.abs() > tol_gap {
            return Err(format!(
                "pressure {p:e} on a cell whose gap is {g:e} (tolerance {tol_gap:e})"
            ));
        }
    }
    if let Control::Load(load) = problem.control {
        let map = &problem.surface;
        let carried = map.cell_size * map.cell_size_y * f.pressure.iter().sum::<f64>();
        let err = (carried - load).abs() / load;
        if err > 1e-6 {
            return Err(format!("carried load {carried:e} N against {load:e} N"));
        }
    }
    Ok(())
}

/// Solve the configuration `text` on the CPU and judge the outcome.
pub(crate) fn run(text: &str) -> Outcome {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("case.toml");
    std::fs::write(&path, text).unwrap();
    let problem = match config::load(&path, &[])
        .map_err(|e| e.to_string())
        .and_then(|c| Problem::from_config(&c).map_err(|e| e.to_string()))
    {
        Ok(p) => p,
        Err(e) => return Outcome::Refused(e),
    };
    match problem.solve(&Executor::Cpu, &mut viscoslide::internals::solver::Silent) {
        Ok(solution) => match check_complementarity(&problem, &solution) {
            Ok(()) => Outcome::Converged {
                matvecs: solution.info.matvecs,
            },
            Err(e) => Outcome::Failed(format!("said converged, but {e}")),
        },
        Err(e) => {
            let text = e.to_string();
            let no_convergence = text.contains("no convergence")
                || std::error::Error::source(&e)
                    .and_then(|s| s.downcast_ref::<SolverError>())
                    .is_some_and(|s| matches!(s, SolverError::NoConvergence { .. }));
            if no_convergence {
                Outcome::Failed(text)
            } else {
                Outcome::Refused(text)
            }
        }
    }
}

/// Run `seeds`; print one line per case and the counts; return the
/// failures and the refusals that do not name an input.
fn run_set(seeds: impl Iterator<Item = u64>) -> Vec<String> {
    let dump = std::env::var_os("VISCOSLIDE_RANDOM_CASES_DIR");
    let mut matvecs = Vec::new();
    let mut refused = 0;
    let mut bad = Vec::new();
    for seed in seeds {
        let text = case(seed);
        if let Some(dir) = &dump {
            std::fs::create_dir_all(dir).unwrap();
            let path = std::path::Path::new(dir).join(format!("case-{seed}.toml"));
            std::fs::write(path, &text).unwrap();
        }
        let outcome = run(&text);
        eprintln!("case {seed}: {outcome:?}");
        match outcome {
            Outcome::Converged { matvecs: m } => matvecs.push(m),
            Outcome::Refused(why) => {
                refused += 1;
                if !names_an_input(&why) {
                    bad.push(format!(
                        "case {seed} refused without naming an input: {why}"
                    ));
                }
            }
            Outcome::Failed(why) => bad.push(format!("case {seed} failed: {why}\n{text}")),
        }
    }
    matvecs.sort_unstable();
    let median = matvecs.get(matvecs.len() / 2).copied().unwrap_or(0);
    eprintln!(
        "converged {}, refused {refused}, failed {}; matvecs median {median}, max {}",
        matvecs.len(),
        bad.len(),
        matvecs.last().copied().unwrap_or(0)
    );
    bad
}

/// Whether a refusal names the input it refuses (a configuration key or
/// the quantity it sets).
fn names_an_input(why: &str) -> bool {
    [
        "approach",
        "load",
        "pressure",
        "temperature",
        "thickness",
        "layer",
        "modulus",
        "speed",
        "surface",
    ]
    .iter()
    .any(|k| why.contains(k))
}

#[test]
fn a_bounded_subset_of_the_random_cases_converges() {
    let bad = run_set((0..FULL).step_by(SUBSET_STRIDE as usize));
    assert!(bad.is_empty(), "{}", bad.join("\n"));
}

#[test]
#[ignore = "the full set: minutes; run with --ignored"]
fn full() {
    let bad = run_set(0..FULL);
    assert!(bad.is_empty(), "{}", bad.join("\n"));
}

#[test]
fn the_generator_is_deterministic_and_covers_the_axes() {
    assert_eq!(case(7), case(7));
    let all: Vec<String> = (0..FULL).map(case).collect();
    for needle in [
        "model = \"prony\"",
        "wlf",
        "formulation = \"periodic\"",
        "formulation = \"non_periodic\"",
        "precision = \"mixed\"",
        "normal_load",
        "mean_pressure",
        "approach",
        "[layer]",
    ] {
        let count = all.iter().filter(|c| c.contains(needle)).count();
        assert!(count >= FULL as usize / 20, "{needle}: {count} cases");
    }
}
