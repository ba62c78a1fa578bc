//! The heated solve (physics.md section 14) on the GPU executor: every
//! evaluation of the fixed point `T = T0 + Theta(T)` is an isothermal solve
//! in mixed precision (the default of a GPU solve: f32 products on the
//! device, f64 residuals on the host), and the heat problem is solved on the host from its fields.
//! The answer is the CPU's: the same effective temperature within the
//! fixed point's tolerance, and the exact identity `mu_heated = mu(T_eff)`
//! against an independent isothermal CPU solve. Skips with a reason without
//! an adapter; fails under `REQUIRE_GPU=1`.

use viscoslide::config;
use viscoslide::heating::{solve_heated, HeatingParams};
use viscoslide::internals::solver::Silent;
use viscoslide::problem::{Executor, Problem};

#[test]
fn a_heated_solve_on_the_gpu_gives_the_cpu_answer() {
    let Some(ctx) = crate::common::gpu_context() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("case.toml");
    // tests/heat/heated.rs's rubber and surface as a pad (the GPU path's
    // formulation): a rise of about a kelvin.
    std::fs::write(&path, crate::common::heating::heated_pad()).unwrap();
    let cfg = config::load(&path, &["solver.formulation=\"non_periodic\"".to_string()]).unwrap();
    let problem = Problem::from_config(&cfg).unwrap();
    let params =
        HeatingParams::from_config(cfg.config.heating.as_ref().unwrap(), &problem, Some(17.0))
            .unwrap()
            .expect("heating enabled");
    let cpu = solve_heated(&problem, &params, &Executor::Cpu, &mut Silent).unwrap();
    let gpu = solve_heated(&problem, &params, &Executor::Gpu(ctx), &mut Silent).unwrap();
    let (tc, tg) = (
        cpu.report.effective_temperature,
        gpu.report.effective_temperature,
    );
    println!(
        "cpu: T_eff {tc:.6} C, mu {:.9e}, {} evaluations; gpu: T_eff {tg:.6} C, mu {:.9e}, {} evaluations, backend {}",
        cpu.solution.friction_coefficient,
        cpu.report.fixed_point_evaluations,
        gpu.solution.friction_coefficient,
        gpu.report.fixed_point_evaluations,
        gpu.solution.backend
    );
    assert!(
        gpu.solution.backend.starts_with("gpu"),
        "{}",
        gpu.solution.backend
    );
    assert!(
        gpu.solution.info.exact_matvecs > 0,
        "each evaluation is the mixed iteration, its residuals in f64"
    );
    assert_eq!(gpu.solution.summary()["precision"], "mixed");
    // A rise of the order of a kelvin: the feedback is exercised.
    assert!(tc - 17.0 > 0.1, "{tc}");
    // Both are roots of the same g(T) = T0 + Theta(T) - T, whose
    // evaluations agree to the mixed solves' 1e-10 (tests/gpu/refine.rs),
    // each closed to the fixed point's tolerance (1e-3 K by default).
    assert!(
        (tg - tc).abs() <= params.tolerance,
        "T_eff {tg} on the GPU against {tc} on the CPU (tolerance {})",
        params.tolerance
    );
    assert_eq!(
        gpu.report.branches.len(),
        cpu.report.branches.len(),
        "the same branches"
    );
    // The exact identity across executors: the GPU's heated friction is the
    // isothermal friction at its own T_eff, solved independently on the
    // CPU in f64, to the mixed solves' agreement (1e-7, as
    // tests/gpu/refine.rs bounds it).
    let iso = crate::common::heating::isothermal_at(&problem, tg);
    let e = (gpu.solution.friction_coefficient - iso.friction_coefficient).abs()
        / iso.friction_coefficient.abs();
    assert!(
        e <= 1e-7,
        "mu_heated {} against mu(T_eff) {} ({e:e})",
        gpu.solution.friction_coefficient,
        iso.friction_coefficient
    );
}
