//! Arrays larger than one storage binding (backend::gpu::split): the FFT
//! work buffers (both paths), the kernel spectrum, the coefficient table
//! and the arrays of the adaptive-mesh operators are bound in windows. A device opened with a lowered binding limit
//! (`GpuContext::open_with_limits`) makes small grids split, and
//! every result is compared with the same computation on the adapter's own
//! limits (one binding each) and with the CPU. The limit checks are pure
//! functions of the device limits and are tested without a device. Device
//! tests skip with a reason without an adapter and fail under
//! `REQUIRE_GPU=1`.

use crate::common;
use crate::conformance::paper_table;
use crate::refine::differing_cells;
use viscoslide::response::{Grid, SlidingResponse};

mod adaptive;
mod radix2;

use viscoslide::internals::backend::gpu::engine::{Engine, Kernel};
use viscoslide::internals::backend::gpu::fft::check_device;
use viscoslide::internals::backend::gpu::fft_plan::Path as FftPath;
use viscoslide::internals::backend::gpu::{
    self, coefficients, FftChoice, GpuBackend, GpuError, GpuOptions,
};
use viscoslide::internals::backend::gpu::{shaders, split};
use viscoslide::internals::backend::{Backend, CpuBackend};
use viscoslide::internals::kernel::SlidingKernel;
use viscoslide::internals::operator::{OffsetTable, ToeplitzFft};
use viscoslide::internals::solver::Silent;
use viscoslide::problem::{Executor, Problem};

/// The binding limit of the split tests: 64 KiB, so that a 128^2 grid
/// vector (64 KiB) still fits one binding while its padded FFT (`256 x
/// 129` complex, 258 KiB) spans five windows.
const SMALL: u64 = 64 << 10;

fn lavapipe_limits() -> wgpu::Limits {
    wgpu::Limits {
        max_storage_buffer_binding_size: 128 << 20,
        max_buffer_size: (1 << 31) - 1,
        min_storage_buffer_offset_alignment: 256,
        max_storage_buffers_per_shader_stage: 64,
        ..wgpu::Limits::default()
    }
}

fn shared() -> FftPath {
    FftPath::for_limits(32 << 10)
}

/// On lavapipe's limits a 2048^2 FFT fits one binding (`4096 x 2049 x 8`
/// bytes, 64 MiB), 2049^2 .. 4096^2 (`8192 x 4097 x 8` = 256 MiB) span
/// three windows of 128 MiB, 4097^2 (1 GiB) nine; 8193^2 (4 GiB) exceeds
/// one buffer and a device with too few bindings per kernel refuse with a
/// one-line reason. The radix-2 path (complex `mx x my` buffers) splits as
/// well: 2048^2 (`4096^2 x 8` bytes, 128 MiB) fits one binding, 2049^2
/// (512 MiB) spans four windows, its load binding the input vector and
/// both work buffers (nine bindings); 4097^2 (2 GiB) exceeds one buffer.
#[test]
fn limits_split_or_refuse() {
    let l = lavapipe_limits();
    assert_eq!(
        check_device(&l, "x", 2048, 2048, shared()).unwrap(),
        (8 * 4096 * 2049, 1)
    );
    let (bytes, windows) = check_device(&l, "x", 2049, 2049, shared()).unwrap();
    assert_eq!((bytes, windows), (8 * 8192 * 4097, 3));
    assert_eq!(check_device(&l, "x", 4096, 4096, shared()).unwrap().1, 3);
    assert_eq!(check_device(&l, "x", 4097, 4097, shared()).unwrap().1, 9);
    let e = check_device(&l, "x", 8193, 8193, shared()).unwrap_err();
    assert!(
        matches!(
            e,
            GpuError::TooLarge {
                per: "per buffer",
                ..
            }
        ),
        "{e}"
    );
    assert!(e.to_string().contains("--backend cpu"), "{e}");
    assert_eq!(
        check_device(&l, "x", 2048, 2048, FftPath::Radix2).unwrap(),
        (8 * 4096 * 4096, 1)
    );
    assert_eq!(
        check_device(&l, "x", 2049, 2049, FftPath::Radix2).unwrap(),
        (8 * 8192 * 8192, 4)
    );
    let e = check_device(&l, "x", 4097, 4097, FftPath::Radix2).unwrap_err();
    assert!(
        matches!(
            e,
            GpuError::TooLarge {
                per: "per buffer",
                ..
            }
        ),
        "{e}"
    );
    let few = wgpu::Limits {
        max_storage_buffers_per_shader_stage: 8,
        ..l
    };
    let e = check_device(&few, "x", 2049, 2049, shared()).unwrap_err();
    assert!(
        matches!(e, GpuError::TooManyBindings { need: 10, .. }),
        "{e}"
    );
    println!("{e}");
    let e = check_device(&few, "x", 2049, 2049, FftPath::Radix2).unwrap_err();
    assert!(
        matches!(e, GpuError::TooManyBindings { need: 9, .. }),
        "{e}"
    );
    println!("{e}");
}

/// Every binding a kernel may split is reached through accessors that
/// [`split::split_source`] rewrites into valid WGSL (naga), three windows
/// each.
#[test]
fn split_shaders_validate() {
    for kernel in [
        Kernel::FftRadix,
        Kernel::FftRadixProduct,
        Kernel::FftSplit,
        Kernel::FftMerge,
        Kernel::FftLoad,
        Kernel::FftPass,
        Kernel::SpectralProduct,
        Kernel::SpectralProductF16,
        Kernel::FftExtract,
        Kernel::Coefficients,
        Kernel::AdaptiveCoefficients,
        Kernel::AdaptiveMatvec,
        Kernel::AdaptiveSum,
        Kernel::LevelTable,
        Kernel::LevelBoxSum,
        Kernel::LevelMatvec,
        Kernel::Axpy,
        Kernel::Combine,
        Kernel::Scale,
        Kernel::AddScalar,
        Kernel::Gather,
        Kernel::Scatter,
        Kernel::Gap,
        Kernel::ActiveSet,
        Kernel::Complementarity,
        Kernel::Dot,
        Kernel::Sum,
        Kernel::CompactCount,
        Kernel::CompactWrite,
    ] {
        let counts: Vec<u64> = kernel
            .splittable()
            .iter()
            .map(|&s| if s { 3 } else { 1 })
            .collect();
        let source = shaders::with_fft_shared(&shaders::compose(kernel.file()).unwrap(), 4096);
        let split = split::split_source(&source, &counts, 1 << 16)
            .unwrap_or_else(|e| panic!("{kernel:?}: {e}"));
        assert_ne!(split, source, "{kernel:?}");
        shaders::validate(&split).unwrap_or_else(|e| panic!("{kernel:?}: {e}"));
    }
}

fn matvec(ctx: gpu::GpuContext, n: usize, table: &[f64], fft: FftChoice, x: &[f64]) -> Vec<f64> {
    let options = GpuOptions {
        fft,
        ..GpuOptions::default()
    };
    matvec_with(ctx, n, table, options, x)
}

/// `L x` on an `n x n` grid with `options`, read back.
fn matvec_with(
    ctx: gpu::GpuContext,
    n: usize,
    table: &[f64],
    options: GpuOptions,
    x: &[f64],
) -> Vec<f64> {
    let mut g = GpuBackend::new(ctx, n, n, table, options).unwrap();
    let mut xv = g.zeros(x.len());
    g.upload(x, &mut xv);
    let mut yv = g.zeros(x.len());
    g.apply(&xv, &mut yv);
    let mut y = vec![0.0; x.len()];
    g.download(&yv, &mut y);
    y
}

/// A positive pressure field on an `n x n` grid (1e5 .. 2e5 Pa) and the
/// CPU Toeplitz FFT's product of it with `table`: the reference of the
/// matvec comparisons.
fn matvec_case(n: usize, table: &[f64]) -> (Vec<f64>, Vec<f64>) {
    let x: Vec<f64> = (0..n * n)
        .map(|k| 1e5 * (1.0 + ((k * 7919) % 1013) as f64 / 1013.0))
        .collect();
    let mut cpu = CpuBackend::new(ToeplitzFft::new(OffsetTable {
        nx: n,
        ny: n,
        values: table,
    }));
    let mut y_cpu = vec![0.0; n * n];
    cpu.apply(&x, &mut y_cpu);
    (x, y_cpu)
}

/// `(largest |split - full|, largest |full|, relative L2 distance of split
/// from cpu)`.
fn agreement(split: &[f64], full: &[f64], cpu: &[f64]) -> (f64, f64, f64) {
    let scale = full.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let diff = split
        .iter()
        .zip(full)
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    let num: f64 = split.iter().zip(cpu).map(|(a, b)| (a - b).powi(2)).sum();
    let den: f64 = cpu.iter().map(|b| b * b).sum();
    (diff, scale, (num / den).sqrt())
}

/// The padded-FFT matvec with its work buffers and spectrum in five
/// windows against the unsplit one and the CPU Toeplitz FFT, on the default
/// plan (rows, columns with the product, rows back) and on one of radix-4
/// passes (strided column passes that cross every window boundary).
#[test]
fn split_matvec_matches_unsplit_and_cpu() {
    let Some(full) = crate::common::gpu_context() else {
        return;
    };
    let small = crate::common::gpu_context_with_limits(Some(SMALL), None).unwrap();
    assert_eq!(small.adapter.max_storage_binding, SMALL);
    let n = 128;
    let table = paper_table(n, n, 1e-6, 1e-3);
    let (x, y_cpu) = matvec_case(n, &table);
    for fft in [FftChoice::Auto, FftChoice::SharedMaxRadix(4)] {
        let engine = Engine::new(small.clone());
        let windows = engine.windows(8 * 256 * 129);
        assert_eq!(windows, 5, "the work buffers must split");
        let y_split = matvec(small.clone(), n, &table, fft, &x);
        let y_full = matvec(full.clone(), n, &table, fft, &x);
        let (diff, scale, cpu_err) = agreement(&y_split, &y_full, &y_cpu);
        println!("{fft:?}: split vs unsplit max diff {diff:.3e} of {scale:.3e}; vs CPU rel L2 {cpu_err:.3e}");
        // The same kernels in the same order on the same values: only the
        // addressing differs, so the results agree to the last f32 bit
        // (allowing one f32 rounding of the largest value in case the
        // shader compiler contracts the two sources differently).
        assert!(
            diff <= 2.0 * f32::EPSILON as f64 * scale,
            "{diff} of {scale}"
        );
        // As the unsplit matvec's conformance test: f32 FFT, 1e-5 in L2.
        assert!(cpu_err <= 1e-5, "{cpu_err}");
    }
}

/// The coefficient table written through two windows (`129^2` f32 of a
/// 65^2 grid, 65 KiB) equals the one written to one binding (each entry is
/// computed independently; only the store address differs).
#[test]
fn split_coefficient_table_equals_unsplit() {
    let Some(full) = crate::common::gpu_context() else {
        return;
    };
    let small = crate::common::gpu_context_with_limits(Some(SMALL), None).unwrap();
    let n = 65;
    let m = common::paper_material();
    let response = SlidingResponse::new(&m, 1e-3, 0.0, None).unwrap();
    let grid = Grid::square(n, n, 1e-6).unwrap();
    let count = (2 * n - 1) * (2 * n - 1);
    let mut es = Engine::new(small);
    assert_eq!(es.windows(4 * count as u64), 2, "the table must split");
    let split = coefficients::coefficient_table(&mut es, &response, &grid).unwrap();
    let mut ef = Engine::new(full);
    let whole = coefficients::coefficient_table(&mut ef, &response, &grid).unwrap();
    assert_eq!(split, whole);
}

/// `configs/default.toml` with `overrides`.
fn problem(extra: &[&str]) -> Problem {
    let path = crate::common::source_dir().join("configs/default.toml");
    let overrides: Vec<String> = extra.iter().map(|s| s.to_string()).collect();
    let cfg = viscoslide::config::load(&path, &overrides).expect("config loads");
    Problem::from_config(&cfg).expect("problem builds")
}

/// A whole solve with the FFT buffers, spectrum and coefficient table split
/// into windows: the device's f32 answer equals the unsplit device answer
/// (friction, area and contact set identical, pressures to f32 rounding),
/// and the mixed answer (f32 products on the split device, f64 residuals on
/// the host) the CPU's f64 one as in `refine.rs`.
#[test]
fn split_solve_matches_unsplit_and_cpu() {
    split_solve(128, SMALL);
}

/// As [`split_solve_matches_unsplit_and_cpu`] with the grid vectors split
/// too: a 64^2 grid (16 KiB vectors) under an 8 KiB binding, vectors in two
/// windows, the FFT buffers in nine, the reduction partials in eight.
#[test]
fn split_vector_solve_matches_unsplit_and_cpu() {
    split_solve(64, 8 << 10);
}

fn split_solve(n: usize, binding: u64) {
    let Some(full) = crate::common::gpu_context() else {
        return;
    };
    let small = crate::common::gpu_context_with_limits(Some(binding), None).unwrap();
    let grid = format!("surface.generate.n={n}");
    let p = problem(&["solver.gpu_refine=false", &grid]);
    let a = p.solve(&Executor::Gpu(small.clone()), &mut Silent).unwrap();
    let b = p.solve(&Executor::Gpu(full), &mut Silent).unwrap();
    let (pa, pb) = (&a.fields.pressure, &b.fields.pressure);
    let scale = pb.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let diff = pa
        .iter()
        .zip(pb.iter())
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
    println!(
        "device answers: mu {:.9e} vs {:.9e}, area {} vs {}, {} vs {} matvecs, max pressure diff {diff:.3e} of {scale:.3e}",
        a.friction_coefficient,
        b.friction_coefficient,
        a.stats.contact_area_fraction,
        b.stats.contact_area_fraction,
        a.info.matvecs,
        b.info.matvecs
    );
    assert_eq!(differing_cells(&a, &b), 0, "contact sets differ");
    assert_eq!(a.stats.contact_area_fraction, b.stats.contact_area_fraction);
    assert_eq!(a.info.matvecs, b.info.matvecs);
    // Same iteration on the same f32 values; pressures are read back as f32
    // (relative rounding 6e-8), the friction summed from them in f64.
    assert!(
        diff <= 4.0 * f32::EPSILON as f64 * scale,
        "{diff} of {scale}"
    );
    let rel = (a.friction_coefficient - b.friction_coefficient).abs() / b.friction_coefficient;
    assert!(rel <= 1e-6, "friction {rel:.3e}");
    // The mixed split solve against the CPU's f64 answer (tolerances of
    // refine.rs: both solve the same f64 operator to 1e-8).
    let p = problem(&[&grid]);
    let cpu = p.solve(&Executor::Cpu, &mut Silent).unwrap();
    let gpu = p.solve(&Executor::Gpu(small), &mut Silent).unwrap();
    let rel =
        (gpu.friction_coefficient - cpu.friction_coefficient).abs() / cpu.friction_coefficient;
    println!("mixed split vs cpu: friction {rel:.3e}");
    assert!(rel <= 1e-7, "friction {rel:.3e}");
    assert_eq!(differing_cells(&gpu, &cpu), 0, "contact sets differ");
}

/// What cannot be split is refused before any allocation, with the
/// reason: here a 128^2 grid whose FFT work buffer (264,192 bytes) exceeds
/// a device's largest buffer of 256 KiB, while its vectors (64 KiB) split
/// into four 16 KiB windows.
#[test]
fn oversized_buffers_are_refused_clearly() {
    let Some(small) = crate::common::gpu_context_with_limits(Some(16 << 10), Some(256 << 10))
    else {
        return;
    };
    assert!(GpuBackend::check_fits(&small, 64, 64).is_ok());
    let e = GpuBackend::check_fits(&small, 128, 128).unwrap_err();
    assert!(
        matches!(
            e,
            GpuError::TooLarge {
                per: "per buffer",
                need: 264_192,
                ..
            }
        ),
        "{e}"
    );
    assert!(e.to_string().contains("--backend cpu"), "{e}");
    let table = paper_table(128, 128, 1e-6, 1e-3);
    let e = GpuBackend::new(small, 128, 128, &table, GpuOptions::default());
    assert!(matches!(e, Err(GpuError::TooLarge { .. })));
}

fn random(n: usize, seed: u64) -> Vec<f64> {
    let mut s = seed;
    (0..n)
        .map(|_| {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((s >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
        })
        .collect()
}

/// Every vector kernel of the backend on vectors in two 32 KiB windows
/// (a 100 x 90 grid, 36,000 bytes; the FFT buffers in nine, within
/// lavapipe's 32 bindings per kernel) against the same kernels on whole
/// buffers: element-wise, reductions, compaction, gather and scatter, the
/// matvec. Same arithmetic in the same order, so the results are equal.
#[test]
fn split_vector_kernels_equal_unsplit() {
    let Some(full) = crate::common::gpu_context() else {
        return;
    };
    let small = crate::common::gpu_context_with_limits(Some(32 << 10), None).unwrap();
    let (nx, ny) = (100, 90);
    let n = nx * ny;
    assert_eq!(Engine::new(small.clone()).windows(4 * n as u64), 2);
    let table = {
        let k = SlidingKernel::new(
            &SlidingResponse::new(&common::paper_material(), 1e-3, 0.0, None).unwrap(),
        )
        .unwrap();
        k.table(&Grid::square(nx, ny, 1e-6).unwrap())
            .unwrap()
            .values
    };
    let run = |ctx: gpu::GpuContext| -> Vec<Vec<f64>> {
        let mut g = GpuBackend::new(ctx, nx, ny, &table, GpuOptions::default()).unwrap();
        let mut out = Vec::new();
        let up = |g: &mut GpuBackend, h: &[f64]| {
            let mut v = g.zeros(h.len());
            g.upload(h, &mut v);
            v
        };
        let down = |g: &mut GpuBackend, v: &gpu::GpuVector| {
            let mut h = vec![0.0; v.len()];
            g.download(v, &mut h);
            h
        };
        let basis: Vec<gpu::GpuVector> = (0..5).map(|k| up(&mut g, &random(n, k))).collect();
        let mut y = up(&mut g, &random(n, 10));
        g.axpy(0.7, &basis[0], &mut y);
        g.combine(&[0.1, -0.2, 0.3, 0.4, -0.5], &basis, &mut y);
        g.scale(1.5, &mut y);
        g.add_scalar(0.25, &mut y);
        out.push(down(&mut g, &y));
        let mut d = vec![0.0; 5];
        g.dots(&basis, &y, &mut d);
        d.push(g.sum(&y));
        let mut gap = g.zeros(n);
        g.gap(&basis[1], &basis[2], 0.1, &mut gap);
        out.push(down(&mut g, &gap));
        let mut mask = up(
            &mut g,
            &random(n, 11)
                .iter()
                .map(|v| f64::from(*v > 0.0))
                .collect::<Vec<_>>(),
        );
        let (changed, active) = g.update_active_set(&basis[3], &gap, &mut mask);
        let (r, p) = g.complementarity(&basis[3], &gap, 2.0);
        d.extend([changed as f64, active as f64, r, p]);
        out.push(d);
        out.push(down(&mut g, &mask));
        let index = g.index_of(&mask);
        let mut short = g.zeros(g.index_len(&index));
        g.gather(&index, &basis[4], &mut short);
        out.push(down(&mut g, &short));
        let mut back = g.zeros(n);
        g.scatter(&index, &short, &mut back);
        out.push(down(&mut g, &back));
        let mut u = g.zeros(n);
        g.apply(&basis[0], &mut u);
        out.push(down(&mut g, &u));
        out
    };
    let (a, b) = (run(small), run(full));
    for (k, (x, y)) in a.iter().zip(&b).enumerate() {
        assert_eq!(x, y, "result {k} differs");
    }
    println!("{} results equal; active cells {}", a.len(), a[2][6]);
}
