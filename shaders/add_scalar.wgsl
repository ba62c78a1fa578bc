// x[i] += alpha (CPU twin: CpuBackend::add_scalar).
// P.i.x: length; P.f.x: alpha.

@group(0) @binding(1) var<storage, read_write> x: array<f32>;
fn x_load(i: u32) -> f32 { return x[i]; }
fn x_store(i: u32, v: f32) { x[i] = v; }

@compute @workgroup_size(WG)
fn main(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let i = linear_id(wid, nwg, lid);
    if (i < P.i.x) {
        x_store(i, x_load(i) + P.f.x);
    }
}
