// y += alpha x (CPU twin: CpuBackend::axpy).
// P.i.x: length; P.f.x: alpha.

@group(0) @binding(1) var<storage, read> x: array<f32>;
fn x_load(i: u32) -> f32 { return x[i]; }
@group(0) @binding(2) var<storage, read_write> y: array<f32>;
fn y_load(i: u32) -> f32 { return y[i]; }
fn y_store(i: u32, v: f32) { y[i] = v; }

@compute @workgroup_size(WG)
fn main(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let i = linear_id(wid, nwg, lid);
    if (i < P.i.x) {
        y_store(i, fma(P.f.x, x_load(i), y_load(i)));
    }
}
