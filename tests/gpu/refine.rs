//! The GPU path's f64 refinement (physics.md section 13): a solve of a
//! `configs/default.toml`-like problem in the GPU's default precision,
//! mixed (one iteration: f32 Krylov products and preconditioner on the
//! device, the residual of every GMRES restart in f64 on the host), gives
//! the CPU path's f64 answer; with `solver.gpu_refine = false` (f32) it
//! keeps the device's f32 answer. Skips with a reason without an adapter;
//! fails under `REQUIRE_GPU=1`. The finite pad's own friction
//! (`smooth_pad`) follows the same executor and precision.

use viscoslide::internals::solver::Silent;
use viscoslide::problem::{Executor, Problem, Solution};

/// `configs/default.toml` (32 scales, 8 cells per shortest wavelength at
/// 256^2) on a 128^2 grid: 16 scales, a few hundred contact cells in many
/// spots, a few seconds on lavapipe.
fn problem(extra: &[&str]) -> Problem {
    let path = crate::common::source_dir().join("configs/default.toml");
    let mut overrides = vec!["surface.generate.n=128".to_string()];
    overrides.extend(extra.iter().map(|s| s.to_string()));
    let cfg = viscoslide::config::load(&path, &overrides).expect("config loads");
    Problem::from_config(&cfg).expect("problem builds")
}

fn relative(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// Cells in contact in one solution and not in the other.
pub(crate) fn differing_cells(a: &Solution, b: &Solution) -> usize {
    a.fields
        .contact
        .iter()
        .zip(&b.fields.contact)
        .filter(|(x, y)| x != y)
        .count()
}

#[test]
fn refined_gpu_solve_equals_the_cpu_f64_solve() {
    let Some(ctx) = crate::common::gpu_context() else {
        return;
    };
    let p = problem(&[]);
    assert!(p.gpu_refine, "the refinement is the GPU path's default");
    let cpu = p.solve(&Executor::Cpu, &mut Silent).unwrap();
    let gpu = p.solve(&Executor::Gpu(ctx.clone()), &mut Silent).unwrap();
    let (mu_c, mu_g) = (cpu.friction_coefficient, gpu.friction_coefficient);
    let (a_c, a_g) = (
        cpu.stats.contact_area_fraction,
        gpu.stats.contact_area_fraction,
    );
    println!(
        "cpu: mu {mu_c:.9e}, area {a_c:.7}, {} matvecs; gpu: mu {mu_g:.9e}, area {a_g:.7}, {} matvecs, {} exact",
        cpu.info.matvecs, gpu.info.matvecs, gpu.info.exact_matvecs
    );
    // Both are f64 solves of the same operator to the tolerance 1e-8 (the
    // host table of the CPU path; the mixed iteration's residuals are the
    // host's f64 products), so the friction agrees far below 1e-7
    // (measured at 256^2: 4.5e-11 when the host refined the device's
    // answer in a second solve) and the contact sets are the same cells.
    assert!(relative(mu_g, mu_c) <= 1e-7, "friction {mu_g} vs {mu_c}");
    assert_eq!(differing_cells(&gpu, &cpu), 0, "contact sets differ");
    assert!(relative(a_g, a_c) <= 1e-7, "area {a_g} vs {a_c}");
    // One iteration met the tolerance, below the f32 floor of the device's
    // products alone (`unrefined_gpu_solve_keeps_the_device_answer`): its
    // residuals were f64 products, reported as exact matvecs, and its
    // history is one iteration's.
    assert!(gpu.info.residual <= 1e-8, "{}", gpu.info.residual);
    assert!(gpu.info.exact_matvecs > 0, "{:?}", gpu.info);
    assert_eq!(cpu.info.exact_matvecs, 0);
    assert_eq!(gpu.info.history.len(), gpu.info.iterations);
    assert!(!gpu.backend.contains("refined"), "{}", gpu.backend);
    let summary = gpu.summary();
    assert_eq!(summary["precision"], "mixed");
    assert_eq!(summary["exact_matvecs"], gpu.info.exact_matvecs);
    assert!(summary.get("gpu_refinement").is_none(), "no second stage");
}

#[test]
fn unrefined_gpu_solve_keeps_the_device_answer() {
    let Some(ctx) = crate::common::gpu_context() else {
        return;
    };
    // The option as `--set` gives it (the config path of CLI and Python).
    let p = problem(&["solver.gpu_refine=false"]);
    assert!(!p.gpu_refine);
    let gpu = p.solve(&Executor::Gpu(ctx), &mut Silent).unwrap();
    assert_eq!(gpu.info.exact_matvecs, 0, "no f64 products");
    assert_eq!(gpu.summary()["precision"], "f32");
    assert!(!gpu.backend.contains("refined"));
    // The f32 iteration stops at its rounding floor, above the requested
    // 1e-8 (measured 1.3e-5 at 256^2).
    assert!(gpu.info.residual > 1e-8, "{}", gpu.info.residual);
}

/// A finite pad's own friction (the same pad without roughness,
/// `smooth_pad`) is solved on the executor of the rough solve: on the GPU
/// in mixed precision like the rough solve (f32 products on the device,
/// f64 residuals on the host), so that it equals the CPU's f64 answer;
/// in f32 it keeps the device's f32 answer.
#[test]
fn the_smooth_pad_is_solved_on_the_gpu() {
    let Some(ctx) = crate::common::gpu_context() else {
        return;
    };
    let p = problem(&[]);
    let cpu = p.solve(&Executor::Cpu, &mut Silent).unwrap();
    let gpu = p.solve(&Executor::Gpu(ctx.clone()), &mut Silent).unwrap();
    let (pc, pg) = (
        cpu.smooth_pad
            .expect("a finite pad reports its own friction"),
        gpu.smooth_pad.expect("on the GPU too"),
    );
    println!("cpu: {pc:?}\ngpu: {pg:?}");
    // The CPU's is one f64 solve on the host.
    assert_eq!((pc.host_matvecs, pc.exact_matvecs), (0, 0));
    // The GPU's is one mixed iteration that converged with the device's
    // products (no solve on the host from scratch), its residuals in f64.
    assert_eq!(pg.host_matvecs, 0, "{pg:?}");
    assert!(pg.exact_matvecs > 0, "{pg:?}");
    // Both are f64 solves of the same flat-pad problem to the tolerance
    // 1e-8 (the constrained iteration from the bearing-area start, f64
    // residuals in both): the pad's friction
    // agrees far below 1e-7, as the rough solve's does.
    assert!(
        relative(pg.friction_coefficient, pc.friction_coefficient) <= 1e-7,
        "{pg:?} vs {pc:?}"
    );

    let f32_only = problem(&["solver.gpu_refine=false"])
        .solve(&Executor::Gpu(ctx), &mut Silent)
        .unwrap()
        .smooth_pad
        .expect("a finite pad reports its own friction");
    println!("gpu f32: {f32_only:?}");
    assert_eq!(f32_only.host_matvecs, 0, "the device's answer");
    assert_eq!(f32_only.exact_matvecs, 0, "in f32 alone");
    // The device's f32 answer: its table is about 4e-7 from the host's and
    // its Krylov solves aim at a relative residual of 1e-3 (the f32
    // flat pad's reach, `F32_TOLERANCE` in
    // src/problem/smooth_pad.rs), so the pad's friction is within 1e-2 of
    // the f64 answer (measured: 1.2e-5 here), and not equal to it.
    let e = relative(f32_only.friction_coefficient, pc.friction_coefficient);
    assert!(e <= 1e-2, "{f32_only:?} vs {pc:?}");
    assert!(e > 0.0, "the f32 answer is the device's own");
}

/// The paper experiment's pad (`configs/paper_experiment.toml`,
/// non-periodic) at 128^2, q1 = 7e5 1/m: its flat pad's contact set
/// covers more than half the grid, where the padded circulant's inverse
/// preconditions the f32 iteration badly (the device's solve missed its 1e-3 target within 300
/// matvecs and the host solved the pad from scratch: 74 of 74 matvecs on
/// the host). With the inverse of T. Chan's circulant above half the grid,
/// as on the host, the device's f32 stage converged and the host refined
/// it in a second solve (48 and 35 matvecs, measured on lavapipe). The
/// mixed iteration reaches the CPU's answer in one solve with the device's
/// products (no solve on the host from scratch).
#[test]
fn a_near_full_flat_pad_converges_on_the_device() {
    let Some(ctx) = crate::common::gpu_context() else {
        return;
    };
    let path = crate::common::source_dir().join("configs/paper_experiment.toml");
    let overrides = [
        "surface.generate.n=128",
        "surface.generate.q1=7e5",
        "solver.formulation=\"non_periodic\"",
        "analysis.enabled=false",
    ]
    .map(String::from);
    let cfg = viscoslide::config::load(&path, &overrides).expect("config loads");
    let p = Problem::from_config(&cfg).expect("problem builds");
    let cpu = p.solve(&Executor::Cpu, &mut Silent).unwrap();
    let gpu = p.solve(&Executor::Gpu(ctx), &mut Silent).unwrap();
    let (pc, pg) = (cpu.smooth_pad.unwrap(), gpu.smooth_pad.unwrap());
    println!("cpu: {pc:?}\ngpu: {pg:?}");
    assert!(pg.exact_matvecs > 0, "{pg:?}");
    assert_eq!(
        pg.host_matvecs, 0,
        "the device's solve did not converge: {pg:?}"
    );
    assert!(
        relative(pg.friction_coefficient, pc.friction_coefficient) <= 1e-7,
        "{pg:?} vs {pc:?}"
    );
}

/// Precision is one typed choice both executors take: on a GPU the default
/// of a uniform grid is `"mixed"` (`gpu_refine` true, the older spelling), `gpu_refine = false`
/// is the older spelling of `"f32"` (the same solve, bit for bit), and
/// `"f64"`, which the device cannot compute, is refused in one line before
/// anything is solved.
#[test]
fn precision_is_one_choice_on_the_gpu() {
    use viscoslide::config::Precision;
    let Some(ctx) = crate::common::gpu_context() else {
        return;
    };
    let gpu = Executor::Gpu(ctx);
    assert_eq!(problem(&[]).precision_on(&gpu).unwrap(), Precision::Mixed);
    assert_eq!(
        problem(&["solver.precision=\"mixed\""])
            .precision_on(&gpu)
            .unwrap(),
        Precision::Mixed
    );
    let alias = problem(&["solver.gpu_refine=false"]);
    let named = problem(&["solver.precision=\"f32\""]);
    assert_eq!(alias.precision_on(&gpu).unwrap(), Precision::F32);
    assert_eq!(named.precision_on(&gpu).unwrap(), Precision::F32);
    // The adaptive mesh has no mixed iteration: f32 by default.
    assert_eq!(
        problem(&["solver.mesh=\"adaptive\""])
            .precision_on(&gpu)
            .unwrap(),
        Precision::F32
    );
    let (a, b) = (
        alias.solve(&gpu, &mut Silent).unwrap(),
        named.solve(&gpu, &mut Silent).unwrap(),
    );
    assert_eq!(a.friction_coefficient, b.friction_coefficient);
    assert_eq!(a.info.matvecs, b.info.matvecs);
    assert_eq!(a.fields.pressure, b.fields.pressure);
    assert_eq!(a.summary()["precision"], "f32");

    // `gpu_refine = false` keeps the f32 iteration, which has no periodic
    // formulation: refused before solving, naming the key, and the fix it
    // suggests (the same problem without it) solves.
    let periodic = "solver.formulation=\"periodic\"";
    let err = problem(&["solver.gpu_refine=false", periodic])
        .precision_on(&gpu)
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("gpu_refine = false") && err.contains("remove gpu_refine"),
        "{err}"
    );
    assert!(!err.contains('\n'), "one line: {err}");
    let fixed = problem(&[periodic]);
    assert_eq!(fixed.precision_on(&gpu).unwrap(), Precision::Mixed);
    assert!(fixed.solve(&gpu, &mut Silent).is_ok());

    let f64_asked = problem(&["solver.precision=\"f64\""]);
    for err in [
        f64_asked.precision_on(&gpu).unwrap_err().to_string(),
        f64_asked.solve(&gpu, &mut Silent).unwrap_err().to_string(),
    ] {
        assert!(
            err.contains("precision = \"f64\"") && err.contains("f32"),
            "{err}"
        );
        assert!(!err.contains('\n'), "one line: {err}");
    }
}
