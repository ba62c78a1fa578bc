// y += c0 x0 + c1 x1 + c2 x2 + c3 x3, four basis vectors per pass
// (CPU twin: CpuBackend::combine; unused lanes have zero coefficients).
// P.i.x: length; P.f: coefficients.

@group(0) @binding(1) var<storage, read> x0: array<f32>;
@group(0) @binding(2) var<storage, read> x1: array<f32>;
@group(0) @binding(3) var<storage, read> x2: array<f32>;
@group(0) @binding(4) var<storage, read> x3: array<f32>;
@group(0) @binding(5) var<storage, read_write> y: array<f32>;

@compute @workgroup_size(WG)
fn main(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let i = linear_id(wid, nwg, lid);
    if (i < P.i.x) {
        y[i] = y[i] + dot(P.f, vec4<f32>(x0[i], x1[i], x2[i], x3[i]));
    }
}
