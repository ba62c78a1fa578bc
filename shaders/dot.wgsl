// Batched dot products x_c . w for up to four vectors per pass (CPU twin:
// CpuBackend::dots): partial sums per workgroup to
// partials[(slot + c) * groups + wg], finished on the host in f64.
// P.i.x: length; P.i.y: first slot; P.i.z: groups; P.i.w: vectors (1..4).

@group(0) @binding(1) var<storage, read> x0: array<f32>;
fn x0_load(i: u32) -> f32 { return x0[i]; }
@group(0) @binding(2) var<storage, read> x1: array<f32>;
fn x1_load(i: u32) -> f32 { return x1[i]; }
@group(0) @binding(3) var<storage, read> x2: array<f32>;
fn x2_load(i: u32) -> f32 { return x2[i]; }
@group(0) @binding(4) var<storage, read> x3: array<f32>;
fn x3_load(i: u32) -> f32 { return x3[i]; }
@group(0) @binding(5) var<storage, read> w: array<f32>;
fn w_load(i: u32) -> f32 { return w[i]; }
@group(0) @binding(6) var<storage, read_write> partials: array<f32>;
fn partials_store(i: u32, v: f32) { partials[i] = v; }

@compute @workgroup_size(WG)
fn main(@builtin(workgroup_id) wid: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let n = P.i.x;
    let groups = P.i.z;
    let count = P.i.w;
    var acc = vec4<f32>(0.0);
    for (var i = wid.x * WG + lid; i < n; i = i + groups * WG) {
        let wi = w_load(i);
        acc.x = fma(x0_load(i), wi, acc.x);
        if (count > 1u) {
            acc.y = fma(x1_load(i), wi, acc.y);
        }
        if (count > 2u) {
            acc.z = fma(x2_load(i), wi, acc.z);
        }
        if (count > 3u) {
            acc.w = fma(x3_load(i), wi, acc.w);
        }
    }
    let t = workgroup_sum4(lid, acc);
    if (lid == 0u) {
        for (var c = 0u; c < count; c = c + 1u) {
            partials_store((P.i.y + c) * groups + wid.x, t[c]);
        }
    }
}
