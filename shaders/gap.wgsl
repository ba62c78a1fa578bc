// out = g - delta + u: the gap of physics.md section 1 (CPU twin:
// CpuBackend::gap). P.i.x: length; P.f.x: delta.

@group(0) @binding(1) var<storage, read> g: array<f32>;
fn g_load(i: u32) -> f32 { return g[i]; }
@group(0) @binding(2) var<storage, read> u: array<f32>;
fn u_load(i: u32) -> f32 { return u[i]; }
@group(0) @binding(3) var<storage, read_write> out: array<f32>;
fn out_store(i: u32, v: f32) { out[i] = v; }

@compute @workgroup_size(WG)
fn main(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let i = linear_id(wid, nwg, lid);
    if (i < P.i.x) {
        out_store(i, (g_load(i) - P.f.x) + u_load(i));
    }
}
