// The r2c split of rows too long for one workgroup block: rows of N complex
// (the DFT Z of the even and odd entries of a real row, stride N) to the
// N + 1 bins X[k] = E + exp(-2 pi i k / (2N)) O of the real row (stride
// N + 1), E = (Z[k] + conj Z[N-k]) / 2, O = (Z[k] - conj Z[N-k]) / (2i).
// As fft_store_split in shared/fft_block.wgsl; CPU twin:
// backend::gpu::fft_twin. P.i: (rows, N).

@group(0) @binding(1) var<storage, read> z: array<vec2<f32>>;
fn z_load(i: u32) -> vec2<f32> { return z[i]; }
@group(0) @binding(2) var<storage, read_write> x: array<vec2<f32>>;
fn x_store(i: u32, v: vec2<f32>) { x[i] = v; }
@group(0) @binding(3) var<storage, read> twiddle: array<vec2<f32>>;

@compute @workgroup_size(WG)
fn main(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let n = P.i.y;
    let t = linear_id(wid, nwg, lid);
    if (t >= P.i.x * (n + 1u)) {
        return;
    }
    let b = t / (n + 1u);
    let k = t % (n + 1u);
    let a = z_load(b * n + (k & (n - 1u)));
    let c0 = z_load(b * n + ((n - k) & (n - 1u)));
    let c = vec2<f32>(c0.x, -c0.y);
    let even = 0.5 * (a + c);
    let d = 0.5 * (a - c);
    let odd = vec2<f32>(d.y, -d.x);
    let w = twiddle[k * (arrayLength(&twiddle) / (2u * n))];
    x_store(t, even + cmul(w, odd));
}
