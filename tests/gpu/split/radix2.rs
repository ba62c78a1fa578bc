//! The radix-2 FFT (the fallback path, and the path of the f16 spectrum)
//! with its work buffers and spectra bound in windows: the matvec and a
//! whole solve against the same computation on whole buffers and against
//! the CPU.

use super::{agreement, matvec_case, matvec_with, SMALL};
use crate::common;
use crate::conformance::paper_table;

use viscoslide::internals::backend::gpu::engine::Engine;
use viscoslide::internals::backend::gpu::fft_plan::Path as FftPath;
use viscoslide::internals::backend::gpu::{
    self, FftChoice, GpuBackend, GpuOptions, SpectrumPrecision,
};
use viscoslide::internals::backend::Backend;
use viscoslide::internals::solver;

/// The radix-2 matvec of a 128^2 grid under a 64 KiB binding: the complex
/// `256 x 256` work buffers and the f32 spectrum (512 KiB) in eight
/// windows, the f16 spectrum (256 KiB) in four, so every pass (strided
/// column passes included) crosses window boundaries. Against the unsplit
/// device and the CPU Toeplitz FFT, with the f32 spectrum and with the f16
/// one.
#[test]
fn split_radix2_matvec_matches_unsplit_and_cpu() {
    let Some(full) = crate::common::gpu_context() else {
        return;
    };
    let small = crate::common::gpu_context_with_limits(Some(SMALL), None).unwrap();
    let n = 128;
    let engine = Engine::new(small.clone());
    assert_eq!(
        engine.windows(8 * 256 * 256),
        8,
        "the work buffers must split"
    );
    assert_eq!(
        engine.windows(4 * 256 * 256),
        4,
        "the f16 spectrum must split"
    );
    assert_eq!(engine.windows(4 * 128 * 128), 1);
    let table = paper_table(n, n, 1e-6, 1e-3);
    let (x, y_cpu) = matvec_case(n, &table);
    // Bounds against the CPU: those of the unsplit matvec's conformance
    // tests, 1e-5 relative L2 for the f32 spectrum (a few hundred f32
    // roundings per entry) and 5e-3 for the f16 one (its 11-bit mantissa,
    // relative rounding 4.9e-4, times the spread of the spectrum).
    for (spectrum, bound) in [
        (SpectrumPrecision::F32, 1e-5),
        (SpectrumPrecision::F16, 5e-3),
    ] {
        let options = GpuOptions {
            fft: FftChoice::Radix2,
            spectrum,
            ..GpuOptions::default()
        };
        let g = GpuBackend::new(small.clone(), n, n, &table, options).unwrap();
        assert_eq!(g.fft_plan().unwrap().path, FftPath::Radix2);
        drop(g);
        let y_split = matvec_with(small.clone(), n, &table, options, &x);
        let y_full = matvec_with(full.clone(), n, &table, options, &x);
        let (diff, scale, cpu_err) = agreement(&y_split, &y_full, &y_cpu);
        println!(
            "radix-2 {spectrum:?}: split vs unsplit max diff {diff:.3e} of {scale:.3e}; vs CPU rel L2 {cpu_err:.3e}"
        );
        // Same kernels, same order, same values: only the addressing
        // differs (one f32 rounding of the largest value allowed in case
        // the compiler contracts the two sources differently).
        assert!(
            diff <= 2.0 * f32::EPSILON as f64 * scale,
            "{spectrum:?}: {diff} of {scale}"
        );
        assert!(cpu_err <= bound, "{spectrum:?}: {cpu_err:.3e}");
    }
}

/// One preconditioned rough-patch solve (3 kPa nominal on L = 0.01 m, rms
/// slope 0.02, paper material, v tau / L = 1.17e-2) on the radix-2 path,
/// 64^2 grid under a 16 KiB binding: work buffers, spectrum and inverse
/// spectrum (`128^2` complex, 128 KiB) in eight windows. The same f32
/// iteration as on whole buffers: contact set, area, friction and
/// iteration counts identical, pressures to f32 rounding.
#[test]
fn split_radix2_solve_equals_unsplit() {
    let Some(full) = crate::common::gpu_context() else {
        return;
    };
    let small = crate::common::gpu_context_with_limits(Some(16 << 10), None).unwrap();
    assert_eq!(Engine::new(small.clone()).windows(8 * 128 * 128), 8);
    let n = 64;
    let speed = 1.17e-2;
    let patch = common::rough_patch(n, speed);
    let options = GpuOptions {
        fft: FftChoice::Radix2,
        preconditioner: true,
        ..GpuOptions::default()
    };
    let run = |ctx: gpu::GpuContext| {
        let t0 = std::time::Instant::now();
        let mut b = GpuBackend::new(ctx, n, n, &patch.table, options).unwrap();
        assert_eq!(b.fft_plan().unwrap().path, FftPath::Radix2);
        assert!(b.has_preconditioner());
        let (s, info) = patch.solve(&mut b);
        let (mu, _) = common::friction(&patch.kernel, &patch.material, &s, n, patch.a, speed);
        (s, info, mu, t0.elapsed().as_secs_f64())
    };
    let (sa, ia, mu_a, ta) = run(small);
    let (sb, ib, mu_b, tb) = run(full);
    let area = |s: &solver::ContactSolution| s.contact.iter().filter(|&&c| c > 0.5).count();
    let scale = sb.pressure.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let diff = sa
        .pressure
        .iter()
        .zip(&sb.pressure)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
    println!(
        "radix-2 solve 64^2: mu {mu_a:.9e} (split) vs {mu_b:.9e}, contact cells {} vs {}, {} vs {} matvecs, max pressure diff {diff:.3e} of {scale:.3e}; {ta:.1} s vs {tb:.1} s",
        area(&sa),
        area(&sb),
        ia.matvecs,
        ib.matvecs
    );
    assert_eq!(sa.contact, sb.contact, "contact sets differ");
    assert_eq!(ia.matvecs, ib.matvecs);
    assert_eq!(ia.iterations, ib.iterations);
    // The same f32 iteration; pressures are read back as f32 (relative
    // rounding 6e-8) and the friction is summed from them in f64.
    assert!(
        diff <= 4.0 * f32::EPSILON as f64 * scale,
        "{diff} of {scale}"
    );
    assert!(
        (mu_a - mu_b).abs() <= 1e-6 * mu_b.abs(),
        "friction {mu_a} vs {mu_b}"
    );
}
