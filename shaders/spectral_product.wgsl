// Pointwise product with the kernel spectrum (the convolution theorem
// step of the Toeplitz matvec, physics.md section 3; CPU twin: the product
// loop of ToeplitzFft::apply). The spectrum carries the 1/(mx my) of the
// inverse transform. P.i.x: mx my.

@group(0) @binding(1) var<storage, read_write> spec: array<vec2<f32>>;
fn spec_load(i: u32) -> vec2<f32> { return spec[i]; }
fn spec_store(i: u32, v: vec2<f32>) { spec[i] = v; }
@group(0) @binding(2) var<storage, read> kernel: array<vec2<f32>>;
fn kernel_load(i: u32) -> vec2<f32> { return kernel[i]; }

@compute @workgroup_size(WG)
fn main(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let t = linear_id(wid, nwg, lid);
    if (t < P.i.x) {
        spec_store(t, cmul(spec_load(t), kernel_load(t)));
    }
}
