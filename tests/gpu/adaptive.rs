//! The adaptive (non-uniform mesh) GPU operator against its CPU twins:
//! influence coefficients between cells of different sizes against
//! `SlidingKernel::coefficient` (paper Eq. 4 and Eq. 6), the matrix-free
//! matvec against a dense CPU evaluation of the same sum (paper Eq. 7), and
//! a full contact solve on `GpuBackend::with_adaptive` against the CPU solve
//! with the dense operator. The GPU computes in f32; tolerances are stated
//! per test. Every test skips (with the reason printed) when no adapter
//! exists, and fails under `REQUIRE_GPU=1`.

use crate::common;
use viscoslide::response::SlidingResponse;
use viscoslide::response::{Layer, LayerBase};

use std::collections::HashMap;
use std::time::Instant;

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use viscoslide::internals::backend::gpu::adaptive::{pair_coefficients, MeshCells};
use viscoslide::internals::backend::gpu::engine::Engine;
use viscoslide::internals::backend::gpu::{shaders, GpuBackend};
use viscoslide::internals::backend::{Backend, CpuBackend};
use viscoslide::internals::kernel::SlidingKernel;
use viscoslide::internals::operator::GridOperator;
use viscoslide::internals::solver::{self, ContactProblem, Control, SolverParams};
use viscoslide::material::Material;

/// Finest cell side [m].
pub(crate) const A: f64 = 1e-4;
/// Creep time of the paper material [s].
pub(crate) const TAU: f64 = 0.01;

/// The shipped SBR-like fit (`configs/material_sbr_like.toml`: 34 creep
/// times of ratio e, 24 of them with nonzero compliance).
fn sbr_material() -> Material {
    let root = crate::common::source_dir().join("configs");
    let loaded = viscoslide::config::load(&root.join("material_sbr_like.toml"), &[]).unwrap();
    let m = loaded.material().unwrap().build(&loaded.base_dir).unwrap();
    assert!(m.spectrum.terms.len() >= 20, "{}", m.spectrum.terms.len());
    m
}

/// 34 creep times in geometric progression of ratio e, all with nonzero
/// compliance (as tests/gpu/conformance.rs).
fn dense_34_material() -> Material {
    use viscoslide::material::{CreepSpectrum, CreepTerm};
    let terms: Vec<CreepTerm> = (0..34)
        .map(|k| {
            let x = (k as f64 - 17.0) / 6.0;
            CreepTerm {
                compliance: 2e-7 * (-x * x).exp() / 10.6,
                time: 1e-9 * (k as f64).exp(),
            }
        })
        .collect();
    Material::new(CreepSpectrum::new(1e7, terms).unwrap(), 0.5).unwrap()
}

/// A half-space sliding state: speed [m/s] and direction [rad].
pub(crate) type Sliding = (f64, f64);

pub(crate) fn params(speed: f64, direction: f64) -> Sliding {
    (speed, direction)
}

/// The response of `material` in the sliding state `p` (half-space).
pub(crate) fn response(material: &Material, (speed, direction): Sliding) -> SlidingResponse {
    SlidingResponse::new(material, speed, direction, None).unwrap()
}

/// `n` nonnegative pressures below 1e5 Pa, a fraction `zeros` of them zero.
pub(crate) fn sparse_pressures(rng: &mut ChaCha8Rng, n: usize, zeros: f64) -> Vec<f64> {
    (0..n)
        .map(|_| {
            if rng.random_range(0.0..1.0) < zeros {
                0.0
            } else {
                rng.random_range(0.0..1e5)
            }
        })
        .collect()
}

/// `L x` on the device, read back.
pub(crate) fn gpu_apply(g: &mut GpuBackend, x: &[f64]) -> Vec<f64> {
    let n = x.len();
    let mut gx = g.zeros(n);
    g.upload(x, &mut gx);
    let mut gy = g.zeros(n);
    g.apply(&gx, &mut gy);
    let mut got = vec![0.0; n];
    g.download(&gy, &mut got);
    got
}

pub(crate) fn rel_l2(a: &[f64], b: &[f64]) -> f64 {
    let num: f64 = a.iter().zip(b).map(|(x, y)| (x - y) * (x - y)).sum();
    let den: f64 = b.iter().map(|y| y * y).sum();
    (num / den).sqrt()
}

#[test]
fn adaptive_shaders_validate() {
    for name in [
        "coefficients.wgsl",
        "adaptive_coefficients.wgsl",
        "adaptive_matvec.wgsl",
    ] {
        let src = shaders::compose(name).unwrap();
        assert!(
            src.contains("fn unit_coefficient"),
            "{name} lacks green.wgsl"
        );
        if let Err(e) = shaders::validate(&src) {
            panic!("{name}:\n{e}");
        }
    }
    // Kernels that do not need the Green's function do not get it.
    assert!(!shaders::compose("axpy.wgsl")
        .unwrap()
        .contains("fn unit_coefficient"));
}

/// Target offsets [m] from a source centre: inside, on the edge, at the
/// corner, near, along and across the sliding direction (+x) and far (up to
/// 200 a), for a source of side `s`.
pub(crate) fn offsets(s: f64) -> Vec<(f64, f64)> {
    let mut v = vec![
        (0.0, 0.0),
        (0.3 * s, -0.2 * s),
        (0.5 * s, 0.0),
        (-0.5 * s, 0.1 * s),
        (0.5 * s, 0.5 * s),
        (0.0, -0.5 * s),
        (0.75 * s, 0.25 * s),
        (-1.25 * s, 0.75 * s),
        (1.5 * s, -1.5 * s),
        (17.5 * A, -30.5 * A),
        (150.0 * A, 120.0 * A),
        (-90.5 * A, 160.5 * A),
    ];
    for d in [1.0, 1.5, 2.5, 4.0, 7.0, 12.5, 25.0, 50.0, 100.0, 200.0] {
        let d = d * A;
        v.extend([(d, 0.0), (-d, 0.0), (0.0, d), (0.0, -d), (d, 0.5 * d)]);
    }
    v
}

/// Worst relative error of the device pair coefficients against
/// `SlidingKernel::coefficient(..).total()` over the pairs with
/// `|K| >= 1e-6 max |K|` (sources of sides a, 2a, 4a, 8a).
pub(crate) fn pair_error(engine: &mut Engine, material: &Material, p: Sliding) -> f64 {
    let kernel = SlidingKernel::new(&response(material, p)).unwrap();
    let mut targets = Vec::new();
    let mut sources = Vec::new();
    let mut cpu = Vec::new();
    for level in 0..4 {
        let s = A * (1 << level) as f64;
        // Source centres away from the origin: the offsets are what matter.
        let (sx, sy) = (0.37 * A * level as f64, -1.13 * A);
        for (dx, dy) in offsets(s) {
            targets.push((sx + dx, sy + dy));
            sources.push((sx, sy, s));
            cpu.push(kernel.coefficient(dx, dy, s, s).total());
        }
    }
    let gpu = pair_coefficients(engine, &response(material, p), &targets, &sources).unwrap();
    let max = cpu.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let mut worst = 0.0f64;
    for (k, (g, c)) in gpu.iter().zip(&cpu).enumerate() {
        assert!(g.is_finite(), "pair {k}: {g}");
        if c.abs() >= 1e-6 * max {
            let e = (g - c).abs() / c.abs();
            if e > 1e-5 {
                println!(
                    "  pair {k}: source {:?}, target {:?}: gpu {g:.6e} cpu {c:.6e} rel {e:.2e}",
                    sources[k], targets[k]
                );
            }
            worst = worst.max(e);
        }
    }
    worst
}

/// Acceptance bound: relative error <= 1e-5 wherever |K| >= 1e-6 max |K|
/// (f32 evaluation of a kernel the CPU integrates to 1e-14).
#[test]
fn pair_coefficients_match_cpu_sls() {
    let Some(ctx) = crate::common::gpu_context() else {
        return;
    };
    let mut engine = Engine::new(ctx);
    let m = common::paper_material();
    let t0 = Instant::now();
    let mut cases: Vec<(String, Sliding)> = vec![
        ("v = 0".into(), params(0.0, 0.0)),
        ("v = inf".into(), params(f64::INFINITY, 0.0)),
    ];
    for lambda in [0.1, 3.0, 300.0] {
        cases.push((
            format!("v tau / a = {lambda}"),
            params(lambda * A / TAU, 0.0),
        ));
    }
    cases.push((
        "v tau / a = 3, direction 0.5 rad".into(),
        params(3.0 * A / TAU, 0.5),
    ));
    cases.push((
        "v tau / a = 3, direction pi/2".into(),
        params(3.0 * A / TAU, std::f64::consts::FRAC_PI_2),
    ));
    let mut failures = Vec::new();
    for (name, p) in cases {
        let e = pair_error(&mut engine, &m, p);
        println!("SLS {name}: max relative error {e:.3e}");
        if e > 1e-5 {
            failures.push(format!("{name}: {e:.3e}"));
        }
    }
    println!(
        "SLS pair coefficients in {:.1} s",
        t0.elapsed().as_secs_f64()
    );
    assert!(failures.is_empty(), "{failures:?}");
}

/// Same bound as the SLS test, for broad spectra: memory lengths from
/// relaxed (below 1e-7 source sides) to glassy at the same speed.
#[test]
fn pair_coefficients_match_cpu_broad_spectra() {
    let Some(ctx) = crate::common::gpu_context() else {
        return;
    };
    let mut engine = Engine::new(ctx);
    let t0 = Instant::now();
    let mut failures = Vec::new();
    let sbr = sbr_material();
    let n_sbr = sbr.spectrum.terms.len();
    for (name, m, speeds) in [
        (
            format!("SBR-like fit ({n_sbr} terms)"),
            sbr,
            vec![0.0, 1e-6, 1e-3, 1.0, f64::INFINITY],
        ),
        (
            "34-term spectrum".to_string(),
            dense_34_material(),
            vec![1e-6, 1e-3],
        ),
    ] {
        for v in speeds {
            let e = pair_error(&mut engine, &m, params(v, 0.0));
            println!("{name} v = {v} m/s: max relative error {e:.3e}");
            if e > 1e-5 {
                failures.push(format!("{name} v = {v}: {e:.3e}"));
            }
        }
    }
    println!(
        "broad-spectrum pair coefficients in {:.1} s",
        t0.elapsed().as_secs_f64()
    );
    assert!(failures.is_empty(), "{failures:?}");
}

/// A quadtree-like mesh: a `2f x 2f` patch of fine cells (side a) centred
/// at the origin, surrounded by `levels - 1` rings of 2a, 4a, ... cells,
/// each ring doubling the half-width (`f` a multiple of `2^(levels-2)`).
pub(crate) fn ring_mesh(f: usize, levels: u32) -> MeshCells {
    let mut cells = MeshCells::default();
    let mut inner = 0i64;
    let mut outer = f as i64;
    for level in 0..levels {
        let side = 1i64 << level;
        let mut i = -outer;
        while i < outer {
            let mut j = -outer;
            while j < outer {
                let inside = i >= -inner && i < inner && j >= -inner && j < inner;
                if !inside {
                    cells.x.push((i as f64 + 0.5 * side as f64) * A);
                    cells.y.push((j as f64 + 0.5 * side as f64) * A);
                    cells.side.push(side as f64 * A);
                }
                j += side;
            }
            i += side;
        }
        inner = outer;
        outer *= 2;
    }
    cells
}

/// The dense matrix `M[t][s] = K(x_t - x_s; s_s) (a / s_s)^2` on the CPU
/// (row major), coefficients memoised by (offset, source side).
pub(crate) fn dense(cells: &MeshCells, kernel: &SlidingKernel) -> Vec<f64> {
    let n = cells.len();
    let mut memo: HashMap<(i64, i64, i64), f64> = HashMap::new();
    let mut m = vec![0.0; n * n];
    for t in 0..n {
        for s in 0..n {
            let (dx, dy, side) = (
                cells.x[t] - cells.x[s],
                cells.y[t] - cells.y[s],
                cells.side[s],
            );
            let key = (
                (4.0 * dx / A).round() as i64,
                (4.0 * dy / A).round() as i64,
                (side / A).round() as i64,
            );
            let k = *memo
                .entry(key)
                .or_insert_with(|| kernel.coefficient(dx, dy, side, side).total());
            m[t * n + s] = k * (A / side).powi(2);
        }
    }
    m
}

pub(crate) struct DenseCells {
    pub(crate) n: usize,
    pub(crate) m: Vec<f64>,
}

impl GridOperator for DenseCells {
    fn shape(&self) -> (usize, usize) {
        (self.n, 1)
    }

    fn apply(&mut self, x: &[f64], y: &mut [f64]) {
        for (t, yt) in y.iter_mut().enumerate() {
            *yt = self.m[t * self.n..(t + 1) * self.n]
                .iter()
                .zip(x)
                .map(|(a, b)| a * b)
                .sum();
        }
    }
}

/// A 12 x 12 fine patch with rings of 2a, 4a and 8a cells (468 cells),
/// random nonnegative x with 40% or 75% zeros.
/// Acceptance bound: relative L2 <= 1e-5 (f32 coefficients of relative
/// error about 1e-6 summed with Kahan compensation).
#[test]
fn adaptive_matvec_matches_dense_cpu() {
    if crate::common::gpu_context().is_none() {
        return;
    }
    let m = common::paper_material();
    let cells = ring_mesh(6, 4);
    assert_eq!(cells.len(), 468);
    let n = cells.len();
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let mut failures = Vec::new();
    // About 280 nonzero sources (two chunks of the kernel) at the first
    // speed, about 120 at the second.
    for (lambda, zeros) in [(3.0, 0.4), (300.0, 0.75)] {
        let p = params(lambda * A / TAU, 0.0);
        let t0 = Instant::now();
        let mat = dense(&cells, &SlidingKernel::new(&response(&m, p)).unwrap());
        let t_cpu = t0.elapsed().as_secs_f64();
        let engine = Engine::new(crate::common::gpu_context().unwrap());
        let mut g = GpuBackend::with_adaptive(engine, &response(&m, p), &cells).unwrap();
        assert_eq!(g.grid_len(), n);
        let x = sparse_pressures(&mut rng, n, zeros);
        let mut want = vec![0.0; n];
        DenseCells { n, m: mat }.apply(&x, &mut want);
        let mut gx = g.zeros(n);
        g.upload(&x, &mut gx);
        let mut gy = g.zeros(n);
        let t1 = Instant::now();
        g.apply(&gx, &mut gy);
        let mut got = vec![0.0; n];
        g.download(&gy, &mut got);
        let t_gpu = t1.elapsed().as_secs_f64();
        let e = rel_l2(&got, &want);
        let nonzero = x.iter().filter(|&&v| v != 0.0).count();
        println!(
            "matvec {n} cells ({nonzero} nonzero), v tau / a = {lambda}: relative L2 {e:.3e} (dense CPU matrix {t_cpu:.1} s, device matvec {t_gpu:.2} s)"
        );
        if e > 1e-5 {
            failures.push(format!("v tau / a = {lambda}: {e:.3e}"));
        }
    }
    assert!(failures.is_empty(), "{failures:?}");
}

/// A sphere-like indenter on an 8 x 8 fine patch with a ring of 2a cells
/// (112 cells), load-controlled, on the GPU
/// adaptive backend and on the CPU with the same dense operator. Acceptance:
/// identical contact sets and pressure relative L2 <= 1e-3 (the GPU solve
/// runs in f32 with its tolerance clamped to f32 epsilon).
#[test]
fn adaptive_solve_matches_dense_cpu() {
    if crate::common::gpu_context().is_none() {
        return;
    }
    let m = common::paper_material();
    let cells = ring_mesh(4, 2);
    let n = cells.len();
    let radius = 40.0 * A;
    let g: Vec<f64> = (0..n)
        .map(|k| (cells.x[k].powi(2) + cells.y[k].powi(2)) / (2.0 * radius))
        .collect();
    let mut failures = Vec::new();
    for lambda in [1.0, 30.0] {
        let p = params(lambda * A / TAU, 0.0);
        let kernel = SlidingKernel::new(&response(&m, p)).unwrap();
        let self_coefficient = kernel.coefficient(0.0, 0.0, A, A).total();
        let mat = dense(&cells, &kernel);
        // About ten fine cells in contact.
        let load = 1e5 * 12.0 * A * A;
        let control = Control::Load(load);
        let sp = SolverParams::default();
        let t0 = Instant::now();
        let mut cpu = CpuBackend::new(DenseCells { n, m: mat });
        let (sc, ic) = solver::solve(
            &mut cpu,
            ContactProblem::new(&g, A * A, self_coefficient, control),
            &sp,
            None,
            &mut solver::Silent,
        )
        .unwrap();
        let t_cpu = t0.elapsed().as_secs_f64();
        let engine = Engine::new(crate::common::gpu_context().unwrap());
        let mut be = GpuBackend::with_adaptive(engine, &response(&m, p), &cells).unwrap();
        let t1 = Instant::now();
        let (sg, ig) = solver::solve(
            &mut be,
            ContactProblem::new(&g, A * A, self_coefficient, control),
            &sp,
            None,
            &mut solver::Silent,
        )
        .unwrap();
        let t_gpu = t1.elapsed().as_secs_f64();
        let area = |c: &[f64]| c.iter().filter(|&&v| v > 0.5).count();
        let e = rel_l2(&sg.pressure, &sc.pressure);
        let same = sg.contact == sc.contact;
        println!(
            "solve {n} cells, v tau / a = {lambda}: contact {} (gpu) vs {} (cpu) cells, identical {same}, pressure rel L2 {e:.2e}, approach {:.6e} vs {:.6e}; gpu {} it / {} matvecs in {t_gpu:.1} s, cpu {} it / {} matvecs in {t_cpu:.1} s",
            area(&sg.contact),
            area(&sc.contact),
            sg.approach,
            sc.approach,
            ig.iterations,
            ig.matvecs,
            ic.iterations,
            ic.matvecs,
        );
        if !same {
            failures.push(format!("v tau / a = {lambda}: contact sets differ"));
        }
        if e > 1e-3 {
            failures.push(format!("v tau / a = {lambda}: pressure rel L2 {e:.2e}"));
        }
    }
    assert!(failures.is_empty(), "{failures:?}");
}

/// Finite layers, negative speeds, ragged or degenerate meshes and
/// mismatched pair lists are refused with `GpuError::Invalid`.
#[test]
fn adaptive_refuses_invalid_input() {
    use viscoslide::internals::backend::gpu::{AdaptiveMatvec, GpuError};

    let Some(ctx) = crate::common::gpu_context() else {
        return;
    };
    let mut engine = Engine::new(ctx);
    let m = common::paper_material();
    let cells = ring_mesh(2, 2);
    let layer = SlidingResponse::new(
        &m,
        0.1,
        0.0,
        Some(Layer {
            thickness: 1e-3,
            base: LayerBase::Bonded,
        }),
    )
    .unwrap();
    let invalid = |r: Result<AdaptiveMatvec, GpuError>| matches!(r, Err(GpuError::Invalid(_)));
    assert!(invalid(AdaptiveMatvec::new(&mut engine, &layer, &cells)));
    // A negative speed has no response to plan.
    assert!(SlidingResponse::new(&m, -1.0, 0.0, None).is_err());
    let half = response(&m, params(0.1, 0.0));
    let mut ragged = cells.clone();
    ragged.y.pop();
    assert!(invalid(AdaptiveMatvec::new(&mut engine, &half, &ragged)));
    let mut flat = cells.clone();
    flat.side[3] = 0.0;
    assert!(invalid(AdaptiveMatvec::new(&mut engine, &half, &flat)));
    assert!(invalid(AdaptiveMatvec::new(
        &mut engine,
        &half,
        &MeshCells::default()
    )));
    let p = params(0.1, 0.0);
    assert!(matches!(
        pair_coefficients(&mut engine, &half, &[(0.0, 0.0)], &[]),
        Err(GpuError::Invalid(_))
    ));
    assert!(matches!(
        pair_coefficients(&mut engine, &layer, &[(0.0, 0.0)], &[(0.0, 0.0, A)]),
        Err(GpuError::Invalid(_))
    ));
    assert_eq!(
        pair_coefficients(&mut engine, &response(&m, p), &[], &[]).unwrap(),
        Vec::<f64>::new()
    );
    assert!(cells.fine_side() == A && MeshCells::default().fine_side().is_nan());
}

/// The level tables computed on the device (level 0 by `level_table.wgsl`,
/// coarser levels by `level_box_sum.wgsl`) against the host's f64
/// `LevelTables`, entry by entry on both lattices of levels 0-3: the paper
/// material at three speeds (v tau / a = 0, 3, 300) sliding along x and
/// obliquely, and the 34-term spectrum. Bound: relative error <= 1e-5
/// wherever the entry exceeds 1e-6 of the lattice's maximum (the conformance
/// bound of the uniform table; level-0 f32 coefficients are good to about
/// 5e-7, and each level adds four positive terms).
#[test]
fn gpu_level_tables_match_the_host() {
    use viscoslide::internals::backend::gpu::GpuLevelTables;
    use viscoslide::internals::operator::LevelTables;
    if crate::common::gpu_context().is_none() {
        return;
    }
    let (nx, ny, levels) = (20usize, 14usize, 3u8);
    let paper = common::paper_material();
    let dense34 = dense_34_material();
    let cases: Vec<(&str, &Material, Sliding)> = vec![
        ("paper v=0", &paper, params(0.0, 0.0)),
        ("paper vtau/a=3 +x", &paper, params(3.0 * A / TAU, 0.0)),
        (
            "paper vtau/a=300 oblique",
            &paper,
            params(300.0 * A / TAU, 0.7),
        ),
        ("34 terms", &dense34, params(1e-3, 0.3)),
    ];
    let mut engine = Engine::new(crate::common::gpu_context().unwrap());
    let mut worst: f64 = 0.0;
    for (name, m, p) in cases {
        let kernel = SlidingKernel::new(&response(m, p)).unwrap();
        let host = LevelTables::new(&kernel, nx, ny, A, levels).unwrap();
        let dev = GpuLevelTables::new(&mut engine, &response(m, p), nx, ny, A, levels).unwrap();
        assert_eq!(dev.max_level(), levels);
        for level in 0..=levels {
            for parity in 0..2usize {
                let read = dev.read(&mut engine, level, parity);
                let (e, at) = table_error(&host, level, parity, &read);
                worst = worst.max(e);
                assert!(e <= 1e-5, "{name}: level {level} parity {parity}: {at}");
            }
        }
    }
    println!("level tables: worst relative error {worst:.2e}");
}

/// The worst relative difference of a device level table (`read`: its
/// `GpuLevelTables::read`) from the host's coefficients, over the entries
/// above 1e-6 of its largest, and where it is.
#[allow(clippy::type_complexity)]
pub(crate) fn table_error(
    host: &viscoslide::internals::operator::LevelTables,
    level: u8,
    parity: usize,
    read: &((i64, i64), (i64, i64), Vec<f64>),
) -> (f64, String) {
    let (kmin, kmax, got) = read;
    let w = (kmax.1 - kmin.1 + 1) as usize;
    let scale = got.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    let par = parity as i64;
    let mut worst = (0.0, String::new());
    for (i, &g) in got.iter().enumerate() {
        let (kx, ky) = (kmin.0 + (i / w) as i64, kmin.1 + (i % w) as i64);
        let want = host.coefficient(level, 2 * kx + par, 2 * ky + par);
        if want.abs() > 1e-6 * scale {
            let e = (g - want).abs() / want.abs();
            if e > worst.0 {
                worst = (
                    e,
                    format!("offset ({kx}, {ky}): gpu {g:.7e} host {want:.7e} ({e:.1e})"),
                );
            }
        }
    }
    worst
}

/// The device operator from device level tables against the host
/// `AdaptiveOperator`, on three quadtree meshes with cells of levels 0-3:
/// a small one (one workgroup of targets, one tile of sources), one with
/// more than a workgroup of fine cells (several workgroups and source
/// tiles) and one where every target sums over 3,000 fine sources. Random nonnegative unknowns with 30 % and 80 % zeros at
/// v tau / a = 3 along x and 30 obliquely, and once with every fine (then
/// every level-1) unknown zero, so that a level's pass has no source (the
/// first pass must still write). Bound: relative L2 <= 1e-5 (f32 table
/// entries of relative error below 1e-6, sums Kahan-compensated).
#[test]
fn gpu_level_matvec_matches_the_host_operator() {
    use viscoslide::internals::backend::gpu::GpuLevelTables;
    use viscoslide::internals::mesh::QuadMesh;
    use viscoslide::internals::operator::{AdaptiveOperator, LevelTables};
    if crate::common::gpu_context().is_none() {
        return;
    }
    let levels = 3u8;
    let patches = |nx: usize, ny: usize, centres: &[(usize, usize)], half: usize| {
        let mut fine = vec![false; nx * ny];
        for &(cx, cy) in centres {
            for ix in cx - half..=cx + half {
                for iy in cy - half..=cy + half {
                    fine[ix * ny + iy] = true;
                }
            }
        }
        QuadMesh::from_mask(nx, ny, A, levels, &fine).unwrap()
    };
    let small = patches(40, 28, &[(7, 6), (25, 19), (33, 4)], 2);
    let large = patches(
        96,
        80,
        &[(10, 10), (30, 60), (50, 20), (70, 70), (85, 40), (20, 40)],
        5,
    );
    for mesh in [&small, &large] {
        let counts = mesh.level_counts();
        assert!(counts.iter().all(|&c| c > 0), "levels {counts:?}");
    }
    assert!(
        large.level_counts()[0] > 2 * 256,
        "{:?}",
        large.level_counts()
    );
    // Every target sums thousands of sources (long per-invocation loops).
    let centres: Vec<(usize, usize)> = (0..16)
        .map(|k| (12 + 32 * (k % 4), 12 + 32 * (k / 4)))
        .collect();
    let many = patches(128, 128, &centres, 7);
    assert!(many.level_counts()[0] > 3000, "{:?}", many.level_counts());
    let m = common::paper_material();
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let mut engine = Some(Engine::new(crate::common::gpu_context().unwrap()));
    let cases: [(&QuadMesh, f64, f64, f64, Option<u8>); 6] = [
        (&small, 3.0, 0.0, 0.3, None),
        (&small, 30.0, 2.2, 0.8, None),
        (&large, 3.0, 0.0, 0.3, None),
        (&large, 30.0, 2.2, 0.3, Some(0)),
        (&large, 30.0, 2.2, 0.3, Some(1)),
        (&many, 3.0, 0.0, 0.1, None),
    ];
    for (mesh, lambda, dir, zeros, empty_level) in cases {
        let (nx, ny) = (mesh.nx, mesh.ny);
        let p = params(lambda * A / TAU, dir);
        let kernel = SlidingKernel::new(&response(&m, p)).unwrap();
        let host = std::sync::Arc::new(LevelTables::new(&kernel, nx, ny, A, levels).unwrap());
        let mut op = AdaptiveOperator::new(host, mesh);
        let mut eng = engine.take().unwrap();
        let dev = GpuLevelTables::new(&mut eng, &response(&m, p), nx, ny, A, levels).unwrap();
        let mut g = GpuBackend::with_level_tables(eng, &dev, mesh).unwrap();
        let n = mesh.len();
        assert_eq!(g.grid_len(), n);
        let mut x = sparse_pressures(&mut rng, n, zeros);
        if let Some(l) = empty_level {
            for (v, c) in x.iter_mut().zip(&mesh.cells) {
                if c.level == l {
                    *v = 0.0;
                }
            }
        }
        let mut want = vec![0.0; n];
        op.apply(&x, &mut want);
        // A product before, so that stale sums of a pass without sources
        // would show.
        gpu_apply(&mut g, &sparse_pressures(&mut rng, n, 0.0));
        let got = gpu_apply(&mut g, &x);
        let e = rel_l2(&got, &want);
        println!(
            "level matvec, {n} cells, v tau/a = {lambda}, level without sources {empty_level:?}: relative L2 {e:.2e}"
        );
        assert!(
            e <= 1e-5,
            "{n} cells, v tau/a = {lambda}: relative L2 {e:.2e}"
        );
        engine = Some(g.into_engine());
    }
}
