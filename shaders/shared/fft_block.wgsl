// Workgroup-memory Stockham FFT blocks (fft_radix.wgsl,
// fft_radix_product.wgsl; plan: backend::gpu::fft_plan; CPU twin:
// backend::gpu::fft_twin, which mirrors every index below).
//
// A pass of a length-N transform with span Ns (the product of the radices
// done so far) and radix R = 2^log2r splits each transform into N / R
// groups j; group j holds the R elements j + r N / R, pre-multiplied by
// exp(-2 pi i r k / (Ns R)) with k = j mod Ns, and its R-point DFT V[q]
// goes to (j - k) R + k + q Ns. One workgroup holds t groups (at most
// FFT_SHARED / R) in workgroup memory and runs the R-point DFTs as log2r
// radix-2 stages there, two per barrier (decimation in frequency: natural
// order in, bit-reversed out), so each pass reads and writes global memory
// once.
//
// Operands are f32 arrays: element pos of transform b is at
// b bsf + pos esf (real, then imaginary part); component c exists when
// 2 pos + c < lim. A real row of ny values is thus a complex row of
// ceil(ny / 2) (even and odd entries), and rows or columns of a padded
// array beyond lim are zero on load and dropped on store.
//
// P.i: (N, Ns, log2r, batches); P.j: (flags | log2 t << 8, input bsf, esf,
// lim), t the groups per workgroup (at most FFT_SHARED / R);
// P.f (bit patterns of u32): (output bsf, esf, lim, log2 L).
// Twiddles: w[t] = exp(-2 pi i t / L), t < L, of the axis length L (computed
// on the host in f64); every denominator used divides L. All sizes but the
// batch count are powers of two, so the index arithmetic is shifts and
// masks.

// Complex elements of the workgroup block; the engine sets this line to
// the adapter's workgroup storage (backend::gpu::fft_plan::shared_elements).
const FFT_SHARED: u32 = 2048u;

// Flags (backend::gpu::fft_plan).
const FFT_BATCH_FAST: u32 = 1u;
const FFT_INVERSE: u32 = 2u;
const FFT_SPLIT: u32 = 4u;
const FFT_MERGE: u32 = 8u;

// The operands are reached through accessors only, so that an operand
// larger than one storage binding can be bound as several windows
// (backend::gpu::split).
@group(0) @binding(1) var<storage, read> src: array<f32>;
fn src_load(i: u32) -> f32 { return src[i]; }
@group(0) @binding(2) var<storage, read_write> dst: array<f32>;
fn dst_store(i: u32, v: f32) { dst[i] = v; }
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
    log2ns: u32,
    log2r: u32,
    r: u32,
    batches: u32,
    flags: u32,
    // Groups per workgroup (t) and per transform (groups), powers of two;
    // size = t R entries of the block are in use.
    t: u32,
    log2t: u32,
    size: u32,
    groups: u32,
    log2groups: u32,
    // Workgroups per group index of a batch-fast pass.
    tiles: u32,
    input: FftLayout,
    output: FftLayout,
}

fn fft_pass() -> FftPass {
    var p: FftPass;
    p.n = P.i.x;
    p.ns = P.i.y;
    p.log2ns = countTrailingZeros(P.i.y);
    p.log2r = P.i.z;
    p.r = 1u << P.i.z;
    p.batches = P.i.w;
    p.flags = P.j.x;
    p.input = FftLayout(P.j.y, P.j.z, P.j.w);
    p.output = FftLayout(bitcast<u32>(P.f.x), bitcast<u32>(P.f.y), bitcast<u32>(P.f.z));
    p.log2t = (P.j.x >> 8u) & 0xffu;
    p.t = 1u << p.log2t;
    p.size = p.t << p.log2r;
    p.log2groups = countTrailingZeros(p.n) - p.log2r;
    p.groups = 1u << p.log2groups;
    p.tiles = (p.batches + p.t - 1u) >> p.log2t;
    return p;
}

fn fft_mul(a: vec2<f32>, b: vec2<f32>) -> vec2<f32> {
    return vec2<f32>(a.x * b.x - a.y * b.y, a.x * b.y + a.y * b.x);
}

// exp(-2 pi i num / 2^log2den), conjugated when `inverse`; P.f.w holds the
// bit pattern of log2 of the table length.
fn fft_twiddle(num: u32, log2den: u32, inverse: bool) -> vec2<f32> {
    var w = twiddle[num << (bitcast<u32>(P.f.w) - log2den)];
    if (inverse) {
        w.y = -w.y;
    }
    return w;
}

// -i z (forward) or +i z (inverse): the twiddle of a quarter turn.
fn fft_quarter(z: vec2<f32>, inverse: bool) -> vec2<f32> {
    if (inverse) {
        return vec2<f32>(-z.y, z.x);
    }
    return vec2<f32>(z.y, -z.x);
}

// Workgroup slot of flat block index i = t R + r (element r of group t):
// r is rotated by t within the group, so that when consecutive invocations
// take consecutive groups at the same r (strided passes) they hit different
// memory banks; the radix stages, which take consecutive r, are unaffected.
fn fft_at(p: FftPass, i: u32) -> u32 {
    let mask = p.r - 1u;
    return (i & ~mask) | ((i + (i >> p.log2r)) & mask);
}

// The slots of the four block indices at + (0, d1, d2, d3) of one group.
fn fft_slots(p: FftPass, at: u32, d1: u32, d2: u32, d3: u32) -> vec4<u32> {
    let mask = p.r - 1u;
    let g = at & ~mask;
    let r = at + (at >> p.log2r);
    return vec4<u32>(g | (r & mask), g | ((r + d1) & mask), g | ((r + d2) & mask), g | ((r + d3) & mask));
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
        v.x = src_load(at);
    }
    if (2u * pos + 1u < l.lim) {
        v.y = src_load(at + 1u);
    }
    return v;
}

fn fft_write(l: FftLayout, b: u32, pos: u32, v: vec2<f32>) {
    let at = b * l.bsf + pos * l.esf;
    if (2u * pos < l.lim) {
        dst_store(at, v.x);
    }
    if (2u * pos + 1u < l.lim) {
        dst_store(at + 1u, v.y);
    }
}

// The workgroup's place in the pass: a batch-fast pass gives each
// workgroup t consecutive transforms b0 .. b0 + t of one group index j
// (one division per workgroup); otherwise t consecutive groups from q0
// (j fastest).
struct FftBlock {
    j: u32,
    b0: u32,
    q0: u32,
}

fn fft_block(p: FftPass, wg: u32) -> FftBlock {
    var k: FftBlock;
    if ((p.flags & FFT_BATCH_FAST) != 0u) {
        k.j = wg / p.tiles;
        k.b0 = (wg - k.j * p.tiles) << p.log2t;
    } else {
        k.q0 = wg << p.log2t;
    }
    return k;
}

// Transform b and group j of the block's group t; valid = inside the pass.
struct FftGroup {
    b: u32,
    j: u32,
    valid: bool,
}

fn fft_group(p: FftPass, k: FftBlock, t: u32) -> FftGroup {
    var g: FftGroup;
    if ((p.flags & FFT_BATCH_FAST) != 0u) {
        g.b = k.b0 + t;
        g.j = k.j;
    } else {
        let q = k.q0 + t;
        g.j = q & (p.groups - 1u);
        g.b = q >> p.log2groups;
    }
    g.valid = g.b < p.batches && g.j < p.groups;
    return g;
}

// Block entry e -> (group t, element r): consecutive invocations take
// consecutive r when that is contiguous in memory (`along`), else
// consecutive groups.
fn fft_entry(p: FftPass, e: u32, along: bool) -> vec2<u32> {
    if (along) {
        return vec2<u32>(e >> p.log2r, e & (p.r - 1u));
    }
    return vec2<u32>(e & (p.t - 1u), e >> p.log2t);
}

// Bin r of the complex row behind the real-row bins X[0..N] of transform
// b (the c2r merge): (X[r] + conj X[N-r]) + i (X[r] - conj X[N-r])
// exp(+2 pi i r / (2N)); its unscaled inverse DFT is (y[2m], y[2m+1]).
fn fft_merged(p: FftPass, b: u32, r: u32) -> vec2<f32> {
    let x = fft_read(p.input, b, r);
    let c0 = fft_read(p.input, b, p.n - r);
    let c = vec2<f32>(c0.x, -c0.y);
    let d = fft_mul(x - c, fft_twiddle(r, p.log2r + 1u, true));
    return x + c + vec2<f32>(-d.y, d.x);
}

// Load the block's groups, pre-multiplied by the pass twiddles.
fn fft_load(p: FftPass, k: FftBlock, lid: u32) {
    let inverse = (p.flags & FFT_INVERSE) != 0u;
    let along = (p.flags & FFT_BATCH_FAST) == 0u && p.groups < p.t;
    for (var e = lid; e < p.size; e += WG) {
        let tr = fft_entry(p, e, along);
        let g = fft_group(p, k, tr.x);
        var v = vec2<f32>(0.0, 0.0);
        if (g.valid) {
            if ((p.flags & FFT_MERGE) != 0u) {
                v = fft_merged(p, g.b, tr.y);
            } else {
                let kk = g.j & (p.ns - 1u);
                v = fft_read(p.input, g.b, g.j + (tr.y << p.log2groups));
                if (kk != 0u) {
                    v = fft_mul(v, fft_twiddle(tr.y * kk, p.log2ns + p.log2r, inverse));
                }
            }
        }
        fft_buf[fft_at(p, (tr.x << p.log2r) + tr.y)] = v;
    }
    workgroupBarrier();
}

// The R-point DFTs of the block, natural order in, bit-reversed out:
// radix-2 decimation-in-frequency stages of half-span h = R/2, R/4, .., 1,
// two at a time (one radix-4 step per invocation and barrier), the last
// one alone when log2r is odd.
fn fft_dif(p: FftPass, lid: u32, inverse: bool) {
    var s = p.log2r;
    for (; s >= 2u; s -= 2u) {
        // Stages h = 2^(s-1) and h / 2.
        let h = 1u << (s - 1u);
        let q = h >> 1u;
        for (var u = lid; u < (p.size >> 2u); u += WG) {
            let i = u & (q - 1u);
            let at = ((u >> (s - 2u)) << s) + i;
            let w1 = fft_twiddle(i, s, inverse);
            let w2 = fft_twiddle(i, s - 1u, inverse);
            let sl = fft_slots(p, at, q, h, h + q);
            let x0 = fft_buf[sl.x];
            let x1 = fft_buf[sl.y];
            let x2 = fft_buf[sl.z];
            let x3 = fft_buf[sl.w];
            let a0 = x0 + x2;
            let a2 = fft_mul(x0 - x2, w1);
            let a1 = x1 + x3;
            let a3 = fft_quarter(fft_mul(x1 - x3, w1), inverse);
            fft_buf[sl.x] = a0 + a1;
            fft_buf[sl.y] = fft_mul(a0 - a1, w2);
            fft_buf[sl.z] = a2 + a3;
            fft_buf[sl.w] = fft_mul(a2 - a3, w2);
        }
        workgroupBarrier();
    }
    if (s == 1u) {
        for (var u = lid; u < (p.size >> 1u); u += WG) {
            let sl = fft_slots(p, 2u * u, 1u, 1u, 1u);
            let a = fft_buf[sl.x];
            let b = fft_buf[sl.y];
            fft_buf[sl.x] = a + b;
            fft_buf[sl.y] = a - b;
        }
        workgroupBarrier();
    }
}

// The R-point DFTs of the block, bit-reversed order in, natural out:
// radix-2 decimation-in-time stages of half-span h = 1, 2, .., R/2, the
// first alone when log2r is odd, then two at a time.
fn fft_dit(p: FftPass, lid: u32, inverse: bool) {
    var s = 0u;
    if ((p.log2r & 1u) == 1u) {
        for (var u = lid; u < (p.size >> 1u); u += WG) {
            let sl = fft_slots(p, 2u * u, 1u, 1u, 1u);
            let a = fft_buf[sl.x];
            let b = fft_buf[sl.y];
            fft_buf[sl.x] = a + b;
            fft_buf[sl.y] = a - b;
        }
        workgroupBarrier();
        s = 1u;
    }
    for (; s + 2u <= p.log2r; s += 2u) {
        // Stages h = 2^s and 2h.
        let h = 1u << s;
        for (var u = lid; u < (p.size >> 2u); u += WG) {
            let i = u & (h - 1u);
            let at = ((u >> s) << (s + 2u)) + i;
            let w1 = fft_twiddle(i, s + 1u, inverse);
            let w2 = fft_twiddle(i, s + 2u, inverse);
            let sl = fft_slots(p, at, h, 2u * h, 3u * h);
            let x0 = fft_buf[sl.x];
            let x1 = fft_mul(fft_buf[sl.y], w1);
            let x2 = fft_buf[sl.z];
            let x3 = fft_mul(fft_buf[sl.w], w1);
            let a0 = x0 + x1;
            let a1 = x0 - x1;
            let a2 = fft_mul(x2 + x3, w2);
            let a3 = fft_quarter(fft_mul(x2 - x3, w2), inverse);
            fft_buf[sl.x] = a0 + a2;
            fft_buf[sl.z] = a0 - a2;
            fft_buf[sl.y] = a1 + a3;
            fft_buf[sl.w] = a1 - a3;
        }
        workgroupBarrier();
    }
}

// Store the (bit-reversed) DFTs of the block at their Stockham positions.
fn fft_store(p: FftPass, k: FftBlock, lid: u32) {
    let along = (p.flags & FFT_BATCH_FAST) == 0u && p.ns < p.t;
    for (var e = lid; e < p.size; e += WG) {
        let tq = fft_entry(p, e, along);
        let g = fft_group(p, k, tq.x);
        if (g.valid) {
            let kk = g.j & (p.ns - 1u);
            let v = fft_buf[fft_at(p, (tq.x << p.log2r) + fft_bitrev(tq.y, p.log2r))];
            fft_write(p.output, g.b, ((g.j - kk) << p.log2r) + kk + (tq.y << p.log2ns), v);
        }
    }
}

// Store the N + 1 bins of the real rows behind whole complex rows (the r2c
// split): with Z the row's DFT, X[k] = E + exp(-2 pi i k / (2N)) O,
// E = (Z[k] + conj Z[N-k]) / 2, O = (Z[k] - conj Z[N-k]) / (2i).
fn fft_store_split(p: FftPass, k: FftBlock, lid: u32) {
    let w = p.r + 1u;
    for (var e = lid; e < p.t * w; e += WG) {
        let t = e / w;
        let kk = e - t * w;
        let g = fft_group(p, k, t);
        if (g.valid) {
            let z = fft_buf[fft_at(p, (t << p.log2r) + fft_bitrev(kk & (p.r - 1u), p.log2r))];
            let c0 = fft_buf[fft_at(p, (t << p.log2r) + fft_bitrev((p.r - kk) & (p.r - 1u), p.log2r))];
            let c = vec2<f32>(c0.x, -c0.y);
            let even = 0.5 * (z + c);
            let d = 0.5 * (z - c);
            let odd = vec2<f32>(d.y, -d.x);
            fft_write(p.output, g.b, kk, even + fft_mul(fft_twiddle(kk, p.log2r + 1u, false), odd));
        }
    }
}
