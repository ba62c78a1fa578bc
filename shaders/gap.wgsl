// out = g - delta + u: the gap of physics.md section 1 (CPU twin:
// CpuBackend::gap). P.i.x: length; P.f.x: delta.

@group(0) @binding(1) var<storage, read> g: array<f32>;
@group(0) @binding(2) var<storage, read> u: array<f32>;
@group(0) @binding(3) var<storage, read_write> out: array<f32>;

@compute @workgroup_size(WG)
fn main(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let i = linear_id(wid, nwg, lid);
    if (i < P.i.x) {
        out[i] = (g[i] - P.f.x) + u[i];
    }
}
