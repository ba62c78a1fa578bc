//! The adaptive-mesh operators with their large arrays bound in windows:
//! the level tables of a quadtree mesh and its matvec (tables, cells and
//! vectors), the pairwise operator (its partial sums, cells and vectors)
//! and the pair coefficients, on a device with a lowered binding limit,
//! against the same computation on whole buffers (equal: each entry is
//! computed by the same arithmetic, only its address differs) and against
//! the CPU twins with the bounds of `tests/gpu/adaptive.rs`.

use crate::adaptive::{
    dense, gpu_apply, offsets, pair_error, params, rel_l2, response, ring_mesh, sparse_pressures,
    table_error, DenseCells, A, TAU,
};
use crate::common;

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use viscoslide::internals::backend::gpu::adaptive::pair_coefficients;
use viscoslide::internals::backend::gpu::engine::Engine;
use viscoslide::internals::backend::gpu::{GpuBackend, GpuLevelTables};
use viscoslide::internals::kernel::SlidingKernel;
use viscoslide::internals::mesh::QuadMesh;
use viscoslide::internals::operator::{AdaptiveOperator, GridOperator, LevelTables};

/// Level tables and the level matvec of a 52 x 52 quadtree (levels 0-2:
/// fine cells but for a 16 x 16 block of level-1 and one of level-2
/// cells, 2,272 cells) under an 8 KiB binding: each level-0 table (`110 x
/// 110` f32, 48 KiB) in six windows, the cells (36 KiB) in five, the
/// vectors (9 KiB) in two; 24 bindings in the matvec. Tables and products
/// equal the unsplit device's; against the host's f64 `LevelTables` and
/// `AdaptiveOperator` the bounds of `gpu_level_tables_match_the_host` and
/// `gpu_level_matvec_matches_the_host_operator`: relative error <= 1e-5
/// per table entry above 1e-6 of the lattice's maximum, relative L2 <=
/// 1e-5 for the product (f32 entries, Kahan-compensated sums).
#[test]
fn split_level_tables_and_matvec_equal_unsplit() {
    let Some(full) = crate::common::gpu_context() else {
        return;
    };
    let small = crate::common::gpu_context_with_limits(Some(8 << 10), None).unwrap();
    let (nx, ny, levels) = (52usize, 52usize, 2u8);
    let allowed: Vec<u8> = (0..nx * ny)
        .map(|f| match (f / ny, f % ny) {
            (i, j) if i < 16 && j < 16 => 2,
            (i, j) if (32..48).contains(&i) && j < 16 => 1,
            _ => 0,
        })
        .collect();
    let mesh = QuadMesh::from_levels(nx, ny, A, levels, &allowed).unwrap();
    let n = mesh.len();
    assert_eq!(mesh.level_counts(), vec![2704 - 512, 64, 16]);
    let es = Engine::new(small.clone());
    assert_eq!(
        es.windows(4 * 110 * 110),
        6,
        "the level-0 tables must split"
    );
    assert_eq!(es.windows(16 * n as u64), 5);
    assert_eq!(es.windows(4 * n as u64), 2, "the vectors must split");
    let m = common::paper_material();
    let p = params(3.0 * A / TAU, 0.4);
    let kernel = SlidingKernel::new(&response(&m, p)).unwrap();
    let host = std::sync::Arc::new(LevelTables::new(&kernel, nx, ny, A, levels).unwrap());
    let mut ef = Engine::new(full);
    let mut es = es;
    let t0 = std::time::Instant::now();
    let ts = GpuLevelTables::new(&mut es, &response(&m, p), nx, ny, A, levels).unwrap();
    let tf = GpuLevelTables::new(&mut ef, &response(&m, p), nx, ny, A, levels).unwrap();
    let mut worst = 0.0f64;
    for level in 0..=levels {
        for parity in 0..2usize {
            let read = ts.read(&mut es, level, parity);
            assert_eq!(read, tf.read(&mut ef, level, parity));
            worst = worst.max(table_error(&host, level, parity, &read).0);
        }
    }
    assert!(worst <= 1e-5, "level tables: {worst:.2e}");
    let mut gs = GpuBackend::with_level_tables(es, &ts, &mesh).unwrap();
    let mut gf = GpuBackend::with_level_tables(ef, &tf, &mesh).unwrap();
    let mut op = AdaptiveOperator::new(host, &mesh);
    let mut rng = ChaCha8Rng::seed_from_u64(17);
    for zeros in [0.3, 0.8] {
        let x = sparse_pressures(&mut rng, n, zeros);
        let got = gpu_apply(&mut gs, &x);
        assert_eq!(got, gpu_apply(&mut gf, &x), "zeros {zeros}");
        let mut want = vec![0.0; n];
        op.apply(&x, &mut want);
        let e = rel_l2(&got, &want);
        println!(
            "split level tables (worst entry {worst:.2e}) and matvec of {n} cells, {zeros} zeros: relative L2 {e:.2e}"
        );
        assert!(e <= 1e-5, "zeros {zeros}: {e:.2e}");
    }
    println!("{:.1} s", t0.elapsed().as_secs_f64());
}

/// The pairwise operator of a 360-cell ring mesh (a 12 x 12 fine patch
/// with rings of 2a and 4a cells) under a 1 KiB binding: its partial sums
/// (two source chunks, 2,880 bytes) in three windows, the cells in six,
/// the vectors in two; about 290 nonzero sources, so both chunks are
/// summed. At rest (v = 0: the instantaneous compliance, the cheapest
/// coefficient; the speeds are covered unsplit by
/// `adaptive_matvec_matches_dense_cpu`). Equal to the unsplit product;
/// against the dense CPU matrix relative L2 <= 1e-5 (that test's bound).
#[test]
fn split_pairwise_matvec_equals_unsplit() {
    let Some(full) = crate::common::gpu_context() else {
        return;
    };
    let small = crate::common::gpu_context_with_limits(Some(1 << 10), None).unwrap();
    let cells = ring_mesh(6, 3);
    let n = cells.len();
    assert_eq!(n, 360);
    let es = Engine::new(small);
    assert_eq!(es.windows(4 * n as u64 * 2), 3, "the partials must split");
    assert_eq!(es.windows(4 * n as u64), 2, "the vectors must split");
    let m = common::paper_material();
    let p = params(0.0, 0.0);
    let mat = dense(&cells, &SlidingKernel::new(&response(&m, p)).unwrap());
    let mut gs = GpuBackend::with_adaptive(es, &response(&m, p), &cells).unwrap();
    let ef = Engine::new(full);
    let mut gf = GpuBackend::with_adaptive(ef, &response(&m, p), &cells).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let x = sparse_pressures(&mut rng, n, 0.2);
    let nonzero = x.iter().filter(|&&v| v != 0.0).count();
    assert!(nonzero > 256, "{nonzero} nonzero sources fill one chunk");
    let got = gpu_apply(&mut gs, &x);
    assert_eq!(got, gpu_apply(&mut gf, &x));
    let mut want = vec![0.0; n];
    DenseCells { n, m: mat }.apply(&x, &mut want);
    let e = rel_l2(&got, &want);
    println!("split pairwise matvec of {n} cells ({nonzero} nonzero): relative L2 {e:.2e}");
    assert!(e <= 1e-5, "{e:.2e}");
}

/// Pair coefficients (248 pairs: sources of sides a .. 8a, targets inside,
/// on the edges, near and far) under a 512-byte binding: the pairs (3,968
/// bytes) in eight windows, the coefficients in two. Equal to the unsplit
/// device's; against `SlidingKernel::coefficient` relative error <= 1e-5
/// where |K| >= 1e-6 max |K| (`pair_coefficients_match_cpu_sls`).
#[test]
fn split_pair_coefficients_equal_unsplit() {
    let Some(full) = crate::common::gpu_context() else {
        return;
    };
    let small = crate::common::gpu_context_with_limits(Some(512), None).unwrap();
    let m = common::paper_material();
    let p = params(3.0 * A / TAU, 0.3);
    let mut targets = Vec::new();
    let mut sources = Vec::new();
    for level in 0..4 {
        let s = A * (1 << level) as f64;
        for (dx, dy) in offsets(s) {
            targets.push((dx - 1.3 * A, dy + 0.2 * A));
            sources.push((-1.3 * A, 0.2 * A, s));
        }
    }
    let count = targets.len() as u64;
    let mut es = Engine::new(small);
    assert_eq!(es.windows(16 * count), 8, "the pairs must split");
    assert_eq!(es.windows(4 * count), 2);
    let mut ef = Engine::new(full);
    let split = pair_coefficients(&mut es, &response(&m, p), &targets, &sources).unwrap();
    let whole = pair_coefficients(&mut ef, &response(&m, p), &targets, &sources).unwrap();
    assert_eq!(split, whole);
    let e = pair_error(&mut es, &m, p);
    println!("split pair coefficients ({count} pairs): worst relative error {e:.2e}");
    assert!(e <= 1e-5, "{e:.2e}");
}

/// What cannot be split is refused before any work, in one line naming
/// the array: a 200 x 200 grid's level-0 table (`406 x 406` f32, 659,344
/// bytes) beyond a 256 KiB buffer; a 52 x 52 grid's (48,400 bytes) in 48
/// windows of 1 KiB, beyond the adapter's storage bindings per kernel
/// (lavapipe: 32) when it has fewer than the 49 the level-0 kernel needs.
#[test]
fn adaptive_arrays_beyond_the_limits_are_refused_clearly() {
    use viscoslide::internals::backend::gpu::GpuError;
    let Some(ctx) = crate::common::gpu_context_with_limits(Some(16 << 10), Some(256 << 10)) else {
        return;
    };
    let m = common::paper_material();
    let p = params(3.0 * A / TAU, 0.0);
    let mut engine = Engine::new(ctx);
    let e = GpuLevelTables::new(&mut engine, &response(&m, p), 200, 200, A, 2).unwrap_err();
    println!("{e}");
    assert!(
        matches!(
            &e,
            GpuError::TooLarge {
                per: "per buffer",
                need: 659_344,
                ..
            }
        ),
        "{e}"
    );
    assert!(e.to_string().contains("level table"), "{e}");
    let ctx = crate::common::gpu_context_with_limits(Some(1 << 10), None).unwrap();
    let limit = ctx.device.limits().max_storage_buffers_per_shader_stage as u64;
    let mut engine = Engine::new(ctx);
    assert_eq!(engine.windows(48_400), 48);
    match GpuLevelTables::new(&mut engine, &response(&m, p), 52, 52, A, 2) {
        Err(e) => {
            println!("{e}");
            assert!(
                matches!(e, GpuError::TooManyBindings { need: 49, .. }),
                "{e}"
            );
            assert!(limit < 49);
        }
        Ok(_) => assert!(limit >= 49 * 2, "the level sums bind two tables"),
    }
}
