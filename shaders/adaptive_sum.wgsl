// Second pass of the adaptive-mesh operator (paper Eq. 7;
// adaptive_matvec.wgsl): y_T = c0 sum_c partials[c n + T], one invocation
// per target cell, Kahan-compensated over the source chunks that hold
// nonzero sources (offsets[chunks] of them).
// P.i: (cells, chunks, 0, 0); P.f.w = c0 = (1 - nu^2)/pi a (total compliance).

@group(0) @binding(1) var<storage, read> partials: array<f32>;
fn partials_load(i: u32) -> f32 { return partials[i]; }
@group(0) @binding(2) var<storage, read> offsets: array<u32>;
@group(0) @binding(3) var<storage, read_write> yout: array<f32>;
fn yout_store(i: u32, v: f32) { yout[i] = v; }

@compute @workgroup_size(WG)
fn main(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let n = P.i.x;
    let t = linear_id(wid, nwg, lid);
    if (t >= n) {
        return;
    }
    var sum = 0.0;
    var comp = 0.0;
    let used = (offsets[P.i.y] + WG - 1u) / WG;
    for (var c = 0u; c < used; c = c + 1u) {
        let term = partials_load(c * n + t) - comp;
        let next = sum + term;
        comp = (next - sum) - term;
        sum = next;
    }
    yout_store(t, P.f.w * sum);
}
