// The last forward pass of the column transforms, the product with the
// kernel spectrum (the convolution theorem step of the Toeplitz matvec,
// physics.md section 3; it carries the 1 / (mx my) of the inverse) and the
// first inverse pass, in one dispatch (shared/fft_block.wgsl): the last
// forward pass (Ns R = N) leaves group j's DFT at j + q Ns, exactly the
// elements the first inverse pass (span 1) gathers into its group j, so
// the block stays in workgroup memory: forward DIF (bit-reversed out),
// product, inverse DIT (bit-reversed in, natural out), stored at j R + r.
// The spectrum has the layout of the input operand. CPU twin:
// backend::gpu::fft_twin.

@group(0) @binding(4) var<storage, read> spectrum: array<vec2<f32>>;
fn spectrum_load(i: u32) -> vec2<f32> { return spectrum[i]; }

@compute @workgroup_size(WG)
fn main(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let p = fft_pass();
    let blk = fft_block(p, linear_group(wid, nwg));
    fft_load(p, blk, lid);
    fft_dif(p, lid, false);
    let sb = p.input.bsf / 2u;
    let se = p.input.esf / 2u;
    for (var e = lid; e < p.size; e += WG) {
        let g = fft_group(p, blk, e >> p.log2r);
        if (g.valid) {
            let k = g.j & (p.ns - 1u);
            let q = fft_bitrev(e & (p.r - 1u), p.log2r);
            let pos = ((g.j - k) << p.log2r) + k + (q << p.log2ns);
            fft_buf[fft_at(p, e)] = fft_mul(fft_buf[fft_at(p, e)], spectrum_load(g.b * sb + pos * se));
        }
    }
    workgroupBarrier();
    fft_dit(p, lid, true);
    let along = (p.flags & FFT_BATCH_FAST) == 0u;
    for (var e = lid; e < p.size; e += WG) {
        let tr = fft_entry(p, e, along);
        let g = fft_group(p, blk, tr.x);
        if (g.valid) {
            fft_write(p.output, g.b, (g.j << p.log2r) + tr.y, fft_buf[fft_at(p, (tr.x << p.log2r) + tr.y)]);
        }
    }
}
