// As spectral_product.wgsl with the kernel spectrum stored in half
// precision: one u32 per entry holding (re, im) as two IEEE binary16 of the
// spectrum divided by its largest component. The halves are decoded with
// integer arithmetic (no f16 shader capability needed).
// P.i.x: mx my; P.f.x: that scale.

@group(0) @binding(1) var<storage, read_write> spec: array<vec2<f32>>;
fn spec_load(i: u32) -> vec2<f32> { return spec[i]; }
fn spec_store(i: u32, v: vec2<f32>) { spec[i] = v; }
@group(0) @binding(2) var<storage, read> kernel: array<u32>;
fn kernel_load(i: u32) -> u32 { return kernel[i]; }

fn half_to_f32(h: u32) -> f32 {
    let sign = select(1.0, -1.0, (h & 0x8000u) != 0u);
    let e = (h >> 10u) & 0x1fu;
    let m = h & 0x3ffu;
    if (e == 0u) {
        // Subnormal: m 2^-24.
        return sign * f32(m) * 5.9604644775390625e-8;
    }
    return sign * bitcast<f32>(((e + 112u) << 23u) | (m << 13u));
}

@compute @workgroup_size(WG)
fn main(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let t = linear_id(wid, nwg, lid);
    if (t < P.i.x) {
        let k = kernel_load(t);
        let z = vec2<f32>(half_to_f32(k & 0xffffu), half_to_f32(k >> 16u));
        spec_store(t, cmul(spec_load(t), P.f.x * z));
    }
}
