// The c2r merge of rows too long for one workgroup block: the N + 1 bins X
// of a real row (stride N + 1) to the N complex values
// (X[k] + conj X[N-k]) + i (X[k] - conj X[N-k]) exp(+2 pi i k / (2N))
// (stride N), whose unscaled inverse DFT is (y[2m], y[2m+1]). As
// fft_merged in shared/fft_block.wgsl; CPU twin: backend::gpu::fft_twin.
// P.i: (rows, N).

@group(0) @binding(1) var<storage, read> x: array<vec2<f32>>;
fn x_load(i: u32) -> vec2<f32> { return x[i]; }
@group(0) @binding(2) var<storage, read_write> z: array<vec2<f32>>;
fn z_store(i: u32, v: vec2<f32>) { z[i] = v; }
@group(0) @binding(3) var<storage, read> twiddle: array<vec2<f32>>;

@compute @workgroup_size(WG)
fn main(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let n = P.i.y;
    let t = linear_id(wid, nwg, lid);
    if (t >= P.i.x * n) {
        return;
    }
    let b = t / n;
    let k = t % n;
    let a = x_load(b * (n + 1u) + k);
    let c0 = x_load(b * (n + 1u) + n - k);
    let c = vec2<f32>(c0.x, -c0.y);
    var w = twiddle[k * (arrayLength(&twiddle) / (2u * n))];
    w.y = -w.y;
    let d = cmul(a - c, w);
    z_store(t, a + c + vec2<f32>(-d.y, d.x));
}
