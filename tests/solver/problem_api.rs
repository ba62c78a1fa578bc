//! The library API as a front end without configuration files uses it (the
//! Python package): a problem built from values and config sections equals
//! the one read from the same configuration, and an observer can stop a
//! solve.

use viscoslide::config::{self, LoadingConfig, SolverConfig};
use viscoslide::internals::solver::{Control, Observer, Silent, SolverError};
use viscoslide::problem::{Executor, Problem};
use viscoslide::Error;

const CONFIG: &str = r#"
[material]
model = "sls"
relaxed_modulus = 3.3333333333333335e6
glassy_modulus = 1.0e7
creep_time = 0.01
poisson = 0.5

[surface.generate]
n = 32
length = 0.01
hurst = 0.8
scales = 4
rms_slope = 0.02
seed = 3

[loading]
mean_pressure = 3000.0
xi = 1.17e-2
direction_deg = 10.0

[solver]
tolerance = 1e-9
cascade_levels = 2
formulation = "periodic"
"#;

fn from_config() -> Problem {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("c.toml");
    std::fs::write(&path, CONFIG).unwrap();
    Problem::from_config(&config::load(&path, &[]).unwrap()).unwrap()
}

#[test]
fn loading_and_solver_sections_build_the_configured_problem() {
    let reference = from_config();
    let loading = LoadingConfig {
        mean_pressure: Some(3000.0),
        xi: Some(1.17e-2),
        direction_deg: Some(10.0),
        ..Default::default()
    };
    let solver: SolverConfig =
        toml::from_str("tolerance = 1e-9\ncascade_levels = 2\nformulation = \"periodic\"").unwrap();
    let built = Problem::new(
        reference.material.clone(),
        reference.surface.clone(),
        Control::Load(1.0),
        0.0,
    )
    .with_loading(&loading)
    .unwrap()
    .with_solver_config(&solver)
    .unwrap();
    assert_eq!(built.control, reference.control);
    assert_eq!(built.speed, reference.speed);
    assert_eq!(built.direction_rad, reference.direction_rad);
    assert_eq!(built.params, reference.params);
    assert_eq!(built.cascade_levels, 2);
    assert_eq!(built.cascade_levels, reference.cascade_levels);
    assert_eq!(built.precision, reference.precision);
    assert_eq!(built.formulation, reference.formulation);
    assert_eq!(built.mesh, reference.mesh);

    // Both or neither of the controls, and no speed, are refused by name.
    let both = LoadingConfig {
        normal_load: Some(1.0),
        ..loading.clone()
    };
    let e = built.clone().with_loading(&both).unwrap_err().to_string();
    assert!(e.contains("only one of normal_load"), "{e}");
    let still = LoadingConfig {
        xi: None,
        ..loading
    };
    let e = built.with_loading(&still).unwrap_err().to_string();
    assert!(e.contains("needs speed"), "{e}");
}

/// Counts polls and asks to stop after `stop_after` of them.
struct StopAfter {
    polls: usize,
    stop_after: usize,
}

impl Observer for StopAfter {
    fn cancelled(&mut self) -> bool {
        self.polls += 1;
        self.polls > self.stop_after
    }
}

#[test]
fn an_observer_stops_a_solve_between_operator_applications() {
    let problem = from_config();
    // Never stopping: polled at least once per operator application.
    let mut count = StopAfter {
        polls: 0,
        stop_after: usize::MAX,
    };
    let solution = problem.solve(&Executor::Cpu, &mut count).unwrap();
    let reference = problem.solve(&Executor::Cpu, &mut Silent).unwrap();
    assert_eq!(solution.fields.pressure, reference.fields.pressure);
    assert!(count.polls >= solution.info.iterations, "{}", count.polls);

    // Stopping part-way, on every discretisation: an error, no solution.
    for formulation in ["periodic", "non_periodic"] {
        let sc: SolverConfig = toml::from_str(&format!("formulation = \"{formulation}\"")).unwrap();
        let problem = problem.clone().with_solver_config(&sc).unwrap();
        for stop_after in [0, 3, 20] {
            let mut stop = StopAfter {
                polls: 0,
                stop_after,
            };
            match problem.solve(&Executor::Cpu, &mut stop) {
                Err(Error::Solver(SolverError::Cancelled)) => {}
                other => panic!("{formulation}, stop after {stop_after}: {other:?}"),
            }
            assert_eq!(stop.polls, stop_after + 1);
        }
    }
}

/// Precision is one typed choice (`[solver] precision`) that the CPU takes
/// or refuses in one line: f64 by default, `"mixed"` as asked, `"f32"` (a
/// GPU's f32 iteration alone) refused; `gpu_refine`, the older spelling of
/// a GPU's precision, leaves the CPU in f64, and contradicting `precision`
/// it is refused when the problem is built.
#[test]
fn precision_is_one_choice_on_the_cpu() {
    use viscoslide::config::Precision;
    let with = |solver: &str| -> Result<Problem, Error> {
        let base = from_config();
        let sc: SolverConfig = toml::from_str(solver).unwrap();
        Problem::new(base.material, base.surface, Control::Load(1e-3), 1e-3).with_solver_config(&sc)
    };
    let cpu = Executor::Cpu;
    assert_eq!(from_config().precision, None);
    assert_eq!(from_config().precision_on(&cpu).unwrap(), Precision::F64);
    let mixed = with("precision = \"mixed\"").unwrap();
    assert_eq!(mixed.precision_on(&cpu).unwrap(), Precision::Mixed);
    let alias = with("gpu_refine = false").unwrap();
    assert_eq!(alias.precision_on(&cpu).unwrap(), Precision::F64);
    let f32_only = with("precision = \"f32\"").unwrap();
    for err in [
        f32_only.precision_on(&cpu).unwrap_err().to_string(),
        f32_only.solve(&cpu, &mut Silent).unwrap_err().to_string(),
    ] {
        assert!(
            err.contains("precision = \"f32\"") && err.contains("GPU"),
            "{err}"
        );
        assert!(!err.contains('\n'), "one line: {err}");
    }
    for (solver, key) in [
        (
            "precision = \"mixed\"\ngpu_refine = false",
            "gpu_refine = false",
        ),
        (
            "precision = \"f32\"\ngpu_refine = true",
            "gpu_refine = true",
        ),
    ] {
        let err = with(solver).unwrap_err().to_string();
        assert!(err.contains(key) && err.contains("disagree"), "{err}");
    }
    // Agreeing spellings are taken.
    assert!(with("precision = \"mixed\"\ngpu_refine = true").is_ok());
    // f32 runs on a GPU only, which solves the non-periodic formulation.
    let periodic = with("precision = \"f32\"\nformulation = \"periodic\"").unwrap();
    let err = periodic.check().unwrap_err().to_string();
    assert!(err.contains("f32") && err.contains("periodic"), "{err}");
}

/// A load or approach whose pressures and displacements, squared and
/// summed over the grid, leave f64 is refused in one line naming it
/// (before: a NaN friction with exit 0 from 1e160 Pa, a residual NaN after
/// 50,002 matvecs from 1e200 Pa, "the surfaces do not touch" for an
/// approach of 1e155 m); huge loads inside the range still solve, with a
/// finite friction.
#[test]
fn loads_beyond_double_precision_are_refused_in_one_line() {
    let base = from_config();
    let solve = |loading: LoadingConfig, formulation: &str| {
        let solver: SolverConfig =
            toml::from_str(&format!("formulation = \"{formulation}\"")).unwrap();
        base.clone()
            .with_loading(&LoadingConfig {
                xi: Some(1.17e-2),
                ..loading
            })
            .unwrap()
            .with_solver_config(&solver)
            .unwrap()
            .solve(&Executor::Cpu, &mut Silent)
    };
    for formulation in ["periodic", "non_periodic"] {
        let refused = [
            (
                LoadingConfig {
                    mean_pressure: Some(1e160),
                    ..Default::default()
                },
                "the normal load 1e156 N",
            ),
            (
                LoadingConfig {
                    approach: Some(1e155),
                    ..Default::default()
                },
                "the approach 1e155 m",
            ),
        ];
        // A periodic cell refuses any approach beyond full contact first.
        let refused = &refused[..if formulation == "periodic" { 1 } else { 2 }];
        for (loading, what) in refused.iter().cloned() {
            let e = solve(loading, formulation).unwrap_err().to_string();
            assert!(
                e.contains(what) && e.contains("beyond double precision") && !e.contains('\n'),
                "{formulation}: {e}"
            );
        }
        let huge = LoadingConfig {
            mean_pressure: Some(1e100),
            ..Default::default()
        };
        let s = solve(huge, formulation).unwrap();
        assert!(s.friction_coefficient.is_finite(), "{formulation}");
        assert!(
            s.friction_coefficient_dissipation.is_finite(),
            "{formulation}"
        );
    }
}
