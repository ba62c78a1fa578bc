// One workgroup-memory Stockham pass (shared/fft_block.wgsl): load the
// block's groups (or merge real-row bins on load, FFT_MERGE), R-point DFTs
// in workgroup memory, store at the Stockham positions (or split whole
// complex rows into real-row bins, FFT_SPLIT). Forward or, with
// FFT_INVERSE, unscaled inverse. CPU twin: backend::gpu::fft_twin.

@compute @workgroup_size(WG)
fn main(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let p = fft_pass();
    let k = fft_block(p, linear_group(wid, nwg));
    fft_load(p, k, lid);
    fft_dif(p, lid, (p.flags & FFT_INVERSE) != 0u);
    if ((p.flags & FFT_SPLIT) != 0u) {
        fft_store_split(p, k, lid);
    } else {
        fft_store(p, k, lid);
    }
}
