// One radix-2 Stockham pass of a batch of complex FFTs of power-of-two
// length N along a strided axis (rows: stride 1; columns: stride my). The
// twiddles w[t] = exp(-2 pi i t / N), t < N/2, are computed on the host in
// f64; the inverse transform uses their conjugates (unscaled).
// Pass with half-span Ns: for j < N/2, k = j mod Ns,
//   a = src[j], b = src[j + N/2] w^(k N / (2 Ns)),
//   dst[2 (j - k) + k] = a + b, dst[2 (j - k) + k + Ns] = a - b.
// P.i: (N, Ns, element stride, batch stride); P.j.x: batches;
// P.f.x: +1 forward, -1 inverse.

@group(0) @binding(1) var<storage, read> src: array<vec2<f32>>;
fn src_load(i: u32) -> vec2<f32> { return src[i]; }
@group(0) @binding(2) var<storage, read_write> dst: array<vec2<f32>>;
fn dst_store(i: u32, v: vec2<f32>) { dst[i] = v; }
@group(0) @binding(3) var<storage, read> twiddle: array<vec2<f32>>;

@compute @workgroup_size(WG)
fn main(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let n = P.i.x;
    let ns = P.i.y;
    let es = P.i.z;
    let half_n = n >> 1u;
    let t = linear_id(wid, nwg, lid);
    if (t >= P.j.x * half_n) {
        return;
    }
    let batch = t / half_n;
    let j = t % half_n;
    let base = batch * P.i.w;
    let k = j & (ns - 1u);
    var w = twiddle[k * (half_n / ns)];
    w.y = w.y * P.f.x;
    let a = src_load(base + j * es);
    let b = cmul(src_load(base + (j + half_n) * es), w);
    let d = 2u * (j - k) + k;
    dst_store(base + d * es, a + b);
    dst_store(base + (d + ns) * es, a - b);
}
