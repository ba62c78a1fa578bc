//! The GPU context opens on whatever adapter exists (lavapipe in CI). With
//! `REQUIRE_GPU=1` a missing adapter fails instead of skipping.

use viscoslide::internals::backend::gpu;

#[test]
fn adapter_is_listed_and_device_opens() {
    let Some(ctx) = crate::common::gpu_context() else {
        return;
    };
    let listed = gpu::list_adapters();
    assert!(
        listed.iter().any(|a| a.name == ctx.adapter.name),
        "opened adapter {} not among {listed:?}",
        ctx.adapter.name
    );
    // Every adapter the engine may use must allow at least 128 MiB per
    // storage binding (the lavapipe cap the buffer layout is designed for).
    assert!(
        ctx.adapter.max_storage_binding >= 128 << 20,
        "{}",
        ctx.adapter
    );
}
