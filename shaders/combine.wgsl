// y += c0 x0 + c1 x1 + c2 x2 + c3 x3, four basis vectors per pass
// (CPU twin: CpuBackend::combine; unused lanes have zero coefficients).
// P.i.x: length; P.f: coefficients.

@group(0) @binding(1) var<storage, read> x0: array<f32>;
fn x0_load(i: u32) -> f32 { return x0[i]; }
@group(0) @binding(2) var<storage, read> x1: array<f32>;
fn x1_load(i: u32) -> f32 { return x1[i]; }
@group(0) @binding(3) var<storage, read> x2: array<f32>;
fn x2_load(i: u32) -> f32 { return x2[i]; }
@group(0) @binding(4) var<storage, read> x3: array<f32>;
fn x3_load(i: u32) -> f32 { return x3[i]; }
@group(0) @binding(5) var<storage, read_write> y: array<f32>;
fn y_load(i: u32) -> f32 { return y[i]; }
fn y_store(i: u32, v: f32) { y[i] = v; }

@compute @workgroup_size(WG)
fn main(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let i = linear_id(wid, nwg, lid);
    if (i < P.i.x) {
        y_store(i, y_load(i) + dot(P.f, vec4<f32>(x0_load(i), x1_load(i), x2_load(i), x3_load(i))));
    }
}
