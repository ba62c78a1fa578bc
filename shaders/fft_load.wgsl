// Zero-padded complex input of the Toeplitz matvec (physics.md section 3,
// "Discretisation": the linear convolution of paper Eq. 7 by a padded FFT):
// a[r my + c] = (x[r ny + c], 0) for r < nx, c < ny, else 0; the padding
// rows r >= nx of the ping-pong buffer b are zeroed too, so the row passes
// may skip them.
// P.i: (nx, ny, mx, my).

@group(0) @binding(1) var<storage, read> x: array<f32>;
fn x_load(i: u32) -> f32 { return x[i]; }
@group(0) @binding(2) var<storage, read_write> a: array<vec2<f32>>;
fn a_store(i: u32, v: vec2<f32>) { a[i] = v; }
@group(0) @binding(3) var<storage, read_write> b: array<vec2<f32>>;
fn b_store(i: u32, v: vec2<f32>) { b[i] = v; }

@compute @workgroup_size(WG)
fn main(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let nx = P.i.x;
    let ny = P.i.y;
    let mx = P.i.z;
    let my = P.i.w;
    let t = linear_id(wid, nwg, lid);
    if (t >= mx * my) {
        return;
    }
    let r = t / my;
    let c = t % my;
    var v = vec2<f32>(0.0, 0.0);
    if (r < nx && c < ny) {
        v.x = x_load(r * ny + c);
    }
    a_store(t, v);
    if (r >= nx) {
        b_store(t, vec2<f32>(0.0, 0.0));
    }
}
