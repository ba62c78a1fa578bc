// Output block of the padded convolution: y[r ny + c] = re spec[r my + c]
// for r < nx, c < ny. P.i: (nx, ny, mx, my).

@group(0) @binding(1) var<storage, read> spec: array<vec2<f32>>;
fn spec_load(i: u32) -> vec2<f32> { return spec[i]; }
@group(0) @binding(2) var<storage, read_write> y: array<f32>;
fn y_store(i: u32, v: f32) { y[i] = v; }

@compute @workgroup_size(WG)
fn main(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let ny = P.i.y;
    let t = linear_id(wid, nwg, lid);
    if (t < P.i.x * ny) {
        y_store(t, spec_load((t / ny) * P.i.w + t % ny).x);
    }
}
