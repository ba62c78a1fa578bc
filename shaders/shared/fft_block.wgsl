// Workgroup-memory Stockham FFT blocks (fft_radix.wgsl,
// fft_radix_product.wgsl; plan: backend::gpu::fft_plan; CPU twin:
// backend::gpu::fft_twin, which mirrors every index below).
//
// A pass of a length-N transform with span Ns (the product of the radices
// done so far) and radix R = 2^log2r splits each transform into N / R
// groups j; group j holds the R elements j + r N / R, pre-multiplied by
// exp(-2 pi i r k / (Ns R)) with k = j mod Ns, and its R-point DFT V[q]
// goes to (j - k) R + k + q Ns. One workgroup holds FFT_SHARED / R groups
// in workgroup memory and runs the R-point DFTs as log2r radix-2 stages
// there (decimation in frequency: natural order in, bit-reversed out), so
// each pass reads and writes global memory once.
//
// Operands are f32 arrays: element pos of transform b is at
// b bsf + pos esf (real, then imaginary part); component c exists when
// 2 pos + c < lim. A real row of ny values is thus a complex row of
// ceil(ny / 2) (even and odd entries), and rows or columns of a padded
// array beyond lim are zero on load and dropped on store.
//
// P.i: (N, Ns, log2r, batches); P.j: (flags, input bsf, esf, lim);
// P.f (bit patterns of u32): (output bsf, esf, lim, -).
// Twiddles: w[t] = exp(-2 pi i t / L), t < L, of the axis length L (computed
// on the host in f64); every denominator used divides L.

// Complex elements of the workgroup block; the engine sets this line to
// the adapter's workgroup storage (backend::gpu::fft_plan::shared_elements).
const FFT_SHARED: u32 = 2048u;

// Flags (backend::gpu::fft_plan).
const FFT_BATCH_FAST: u32 = 1u;
const FFT_INVERSE: u32 = 2u;
const FFT_SPLIT: u32 = 4u;
const FFT_MERGE: u32 = 8u;

@group(0) @binding(1) var<storage, read> src: array<f32>;
@group(0) @binding(2) var<storage, read_write> dst: array<f32>;
@group(0) @binding(3) var<storage, read> twiddle: array<vec2<f32>>;

var<workgroup> fft_buf: array<vec2<f32>, FFT_SHARED>;

struct FftLayout {
    bsf: u32,
    esf: u32,
    lim: u32,
}

struct FftPass {
    n: u32,
    ns: u32,
    log2r: u32,
    r: u32,
    batches: u32,
    flags: u32,
    // Groups per workgroup and per transform.
    t: u32,
    groups: u32,
    input: FftLayout,
    output: FftLayout,
}

fn fft_pass() -> FftPass {
    var p: FftPass;
    p.n = P.i.x;
    p.ns = P.i.y;
    p.log2r = P.i.z;
    p.r = 1u << P.i.z;
    p.batches = P.i.w;
    p.flags = P.j.x;
    p.input = FftLayout(P.j.y, P.j.z, P.j.w);
    p.output = FftLayout(bitcast<u32>(P.f.x), bitcast<u32>(P.f.y), bitcast<u32>(P.f.z));
    p.t = FFT_SHARED >> p.log2r;
    p.groups = p.n >> p.log2r;
    return p;
}

fn fft_mul(a: vec2<f32>, b: vec2<f32>) -> vec2<f32> {
    return vec2<f32>(a.x * b.x - a.y * b.y, a.x * b.y + a.y * b.x);
}

// exp(-2 pi i num / den), conjugated when `inverse`.
fn fft_twiddle(num: u32, den: u32, inverse: bool) -> vec2<f32> {
    var w = twiddle[num * (arrayLength(&twiddle) / den)];
    if (inverse) {
        w.y = -w.y;
    }
    return w;
}

fn fft_bitrev(s: u32, log2r: u32) -> u32 {
    if (log2r == 0u) {
        return 0u;
    }
    return reverseBits(s) >> (32u - log2r);
}

fn fft_read(l: FftLayout, b: u32, pos: u32) -> vec2<f32> {
    let at = b * l.bsf + pos * l.esf;
    var v = vec2<f32>(0.0, 0.0);
    if (2u * pos < l.lim) {
        v.x = src[at];
    }
    if (2u * pos + 1u < l.lim) {
        v.y = src[at + 1u];
    }
    return v;
}

fn fft_write(l: FftLayout, b: u32, pos: u32, v: vec2<f32>) {
    let at = b * l.bsf + pos * l.esf;
    if (2u * pos < l.lim) {
        dst[at] = v.x;
    }
    if (2u * pos + 1u < l.lim) {
        dst[at + 1u] = v.y;
    }
}

// Transform b and group j of the block's group t; valid = inside the pass.
struct FftGroup {
    b: u32,
    j: u32,
    valid: bool,
}

fn fft_group(p: FftPass, wg: u32, t: u32) -> FftGroup {
    let q = wg * p.t + t;
    var g: FftGroup;
    if ((p.flags & FFT_BATCH_FAST) != 0u) {
        g.b = q % p.batches;
        g.j = q / p.batches;
    } else {
        g.j = q % p.groups;
        g.b = q / p.groups;
    }
    g.valid = q < p.batches * p.groups;
    return g;
}

// Block entry e -> (group t, element r): consecutive invocations take
// consecutive r when that is contiguous in memory (`along`), else
// consecutive groups.
fn fft_entry(p: FftPass, e: u32, along: bool) -> vec2<u32> {
    if (along) {
        return vec2<u32>(e >> p.log2r, e & (p.r - 1u));
    }
    return vec2<u32>(e % p.t, e / p.t);
}

// Bin r of the complex row behind the real-row bins X[0..N] of transform
// b (the c2r merge): (X[r] + conj X[N-r]) + i (X[r] - conj X[N-r])
// exp(+2 pi i r / (2N)); its unscaled inverse DFT is (y[2m], y[2m+1]).
fn fft_merged(p: FftPass, b: u32, r: u32) -> vec2<f32> {
    let x = fft_read(p.input, b, r);
    let c0 = fft_read(p.input, b, p.n - r);
    let c = vec2<f32>(c0.x, -c0.y);
    let d = fft_mul(x - c, fft_twiddle(r, 2u * p.n, true));
    return x + c + vec2<f32>(-d.y, d.x);
}

// Load the block's groups, pre-multiplied by the pass twiddles.
fn fft_load(p: FftPass, wg: u32, lid: u32) {
    let inverse = (p.flags & FFT_INVERSE) != 0u;
    let along = (p.flags & FFT_BATCH_FAST) == 0u && p.groups < p.t;
    for (var e = lid; e < FFT_SHARED; e += WG) {
        let tr = fft_entry(p, e, along);
        let g = fft_group(p, wg, tr.x);
        var v = vec2<f32>(0.0, 0.0);
        if (g.valid) {
            if ((p.flags & FFT_MERGE) != 0u) {
                v = fft_merged(p, g.b, tr.y);
            } else {
                let k = g.j & (p.ns - 1u);
                v = fft_read(p.input, g.b, g.j + tr.y * p.groups);
                if (k != 0u) {
                    v = fft_mul(v, fft_twiddle(tr.y * k, p.ns * p.r, inverse));
                }
            }
        }
        fft_buf[tr.x * p.r + tr.y] = v;
    }
    workgroupBarrier();
}

// The R-point DFTs of the block, natural order in, bit-reversed out.
fn fft_dif(p: FftPass, lid: u32, inverse: bool) {
    let half_r = p.r >> 1u;
    for (var h = half_r; h >= 1u; h = h >> 1u) {
        for (var u = lid; u < FFT_SHARED / 2u; u += WG) {
            let uu = u & (half_r - 1u);
            let i = uu & (h - 1u);
            let at = (u >> (p.log2r - 1u)) * p.r + 2u * (uu - i) + i;
            let a = fft_buf[at];
            let b = fft_buf[at + h];
            fft_buf[at] = a + b;
            fft_buf[at + h] = fft_mul(a - b, fft_twiddle(i, 2u * h, inverse));
        }
        workgroupBarrier();
    }
}

// The R-point DFTs of the block, bit-reversed order in, natural out.
fn fft_dit(p: FftPass, lid: u32, inverse: bool) {
    let half_r = p.r >> 1u;
    for (var h = 1u; h <= half_r; h = h << 1u) {
        for (var u = lid; u < FFT_SHARED / 2u; u += WG) {
            let uu = u & (half_r - 1u);
            let i = uu & (h - 1u);
            let at = (u >> (p.log2r - 1u)) * p.r + 2u * (uu - i) + i;
            let a = fft_buf[at];
            let b = fft_mul(fft_buf[at + h], fft_twiddle(i, 2u * h, inverse));
            fft_buf[at] = a + b;
            fft_buf[at + h] = a - b;
        }
        workgroupBarrier();
    }
}

// Store the (bit-reversed) DFTs of the block at their Stockham positions.
fn fft_store(p: FftPass, wg: u32, lid: u32) {
    let along = (p.flags & FFT_BATCH_FAST) == 0u && p.ns < p.t;
    for (var e = lid; e < FFT_SHARED; e += WG) {
        let tq = fft_entry(p, e, along);
        let g = fft_group(p, wg, tq.x);
        if (g.valid) {
            let k = g.j & (p.ns - 1u);
            let v = fft_buf[tq.x * p.r + fft_bitrev(tq.y, p.log2r)];
            fft_write(p.output, g.b, (g.j - k) * p.r + k + tq.y * p.ns, v);
        }
    }
}

// Store the N + 1 bins of the real rows behind whole complex rows (the r2c
// split): with Z the row's DFT, X[k] = E + exp(-2 pi i k / (2N)) O,
// E = (Z[k] + conj Z[N-k]) / 2, O = (Z[k] - conj Z[N-k]) / (2i).
fn fft_store_split(p: FftPass, wg: u32, lid: u32) {
    let w = p.r + 1u;
    for (var e = lid; e < p.t * w; e += WG) {
        let t = e / w;
        let k = e % w;
        let g = fft_group(p, wg, t);
        if (g.valid) {
            let z = fft_buf[t * p.r + fft_bitrev(k & (p.r - 1u), p.log2r)];
            let c0 = fft_buf[t * p.r + fft_bitrev((p.r - k) & (p.r - 1u), p.log2r)];
            let c = vec2<f32>(c0.x, -c0.y);
            let even = 0.5 * (z + c);
            let d = 0.5 * (z - c);
            let odd = vec2<f32>(d.y, -d.x);
            fft_write(p.output, g.b, k, even + fft_mul(fft_twiddle(k, 2u * p.r, false), odd));
        }
    }
}
