// Partial sums of x per workgroup to partials[slot * groups + wg] (CPU
// twin: CpuBackend::sum). P.i.x: length; P.i.y: slot; P.i.z: groups.

@group(0) @binding(1) var<storage, read> x: array<f32>;
fn x_load(i: u32) -> f32 { return x[i]; }
@group(0) @binding(2) var<storage, read_write> partials: array<f32>;
fn partials_store(i: u32, v: f32) { partials[i] = v; }

@compute @workgroup_size(WG)
fn main(@builtin(workgroup_id) wid: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let n = P.i.x;
    let groups = P.i.z;
    var acc = vec4<f32>(0.0);
    for (var i = wid.x * WG + lid; i < n; i = i + groups * WG) {
        acc.x = acc.x + x_load(i);
    }
    let t = workgroup_sum4(lid, acc);
    if (lid == 0u) {
        partials_store(P.i.y * groups + wid.x, t.x);
    }
}
