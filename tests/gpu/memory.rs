//! Device memory of the uniform-grid GPU solve, by array, from the
//! engine's allocations after a whole solve (the number BENCHMARKS.md
//! states as GPU bytes per cell). Prints the table with `--nocapture`.
//! Skips with a reason without an adapter; fails under `REQUIRE_GPU=1`.

use crate::common;

use viscoslide::internals::backend::gpu::{self, GpuBackend, GpuOptions};

/// `(label, buffers, bytes)` per array.
type Allocations = Vec<(String, usize, u64)>;

/// A rough-patch solve (3 kPa on L = 1 cm, rms slope 0.02, the paper's
/// material at xi = 1.17e-2) on an `n x n` device grid; the engine's
/// allocations afterwards.
fn allocations(ctx: gpu::GpuContext, n: usize) -> (Allocations, (usize, usize)) {
    let patch = common::rough_patch(n, 1.17e-2);
    let options = GpuOptions {
        preconditioner: true,
        ..Default::default()
    };
    let mut backend = GpuBackend::new(ctx, n, n, &patch.table, options).unwrap();
    patch.solve(&mut backend);
    let padded = backend.padded_shape();
    let work = match backend.fft_plan().unwrap().path {
        gpu::fft_plan::Path::Radix2 => padded.0 * padded.1,
        gpu::fft_plan::Path::Shared { .. } => padded.0 * (padded.1 / 2 + 1),
    };
    (backend.allocations(), (work, padded.0 * padded.1))
}

#[test]
fn device_memory_by_array() {
    let Some(ctx) = crate::common::gpu_context() else {
        return;
    };
    let mut vectors_per_grid = Vec::new();
    for n in [64, 128] {
        let (list, (work, _)) = allocations(ctx.clone(), n);
        let cells = (n * n) as f64;
        let total: u64 = list.iter().map(|(_, _, b)| b).sum();
        println!("{n} x {n}: {:.1} bytes per cell", total as f64 / cells);
        for (label, count, bytes) in &list {
            println!(
                "  {label:<36} {count:>3} buffers {:>12} bytes {:>8.2} bytes per cell",
                bytes,
                *bytes as f64 / cells
            );
        }
        let get = |l: &str| {
            list.iter()
                .find(|(label, _, _)| label == l)
                .map(|&(_, c, b)| (c, b))
                .unwrap_or_else(|| panic!("no {l} in {list:?}"))
        };
        // The two FFT work buffers and the two spectra (operator and
        // preconditioner, f32 complex) each hold `work` complex values.
        for l in [
            "viscoslide fft buffer a",
            "viscoslide fft buffer b",
            "viscoslide kernel spectrum f32",
            "viscoslide inverse spectrum f32",
        ] {
            assert_eq!(get(l), (1, 8 * work as u64), "{l}");
        }
        // Every grid vector is `4 n^2` bytes.
        let (count, bytes) = get("viscoslide grid vector");
        assert_eq!(bytes, count as u64 * 4 * (n * n) as u64);
        vectors_per_grid.push(count);
    }
    // The iteration holds the same number of vectors on both grids (the
    // GMRES basis of `restart + 1` and a fixed set of work vectors): the
    // vectors' bytes per cell do not grow with the grid.
    assert_eq!(
        vectors_per_grid[0], vectors_per_grid[1],
        "{vectors_per_grid:?}"
    );
}
