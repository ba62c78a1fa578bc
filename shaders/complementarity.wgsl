// Complementarity residual of the LCP (physics.md section 4; CPU twin:
// CpuBackend::complementarity): partial sums of min(p, k gap)^2 and p^2 to
// partials[slot * groups + wg] and partials[(slot + 1) * groups + wg].
// P.i.x: length; P.i.y: slot; P.i.z: groups; P.f.x: k.

@group(0) @binding(1) var<storage, read> p: array<f32>;
fn p_load(i: u32) -> f32 { return p[i]; }
@group(0) @binding(2) var<storage, read> gap: array<f32>;
fn gap_load(i: u32) -> f32 { return gap[i]; }
@group(0) @binding(3) var<storage, read_write> partials: array<f32>;
fn partials_store(i: u32, v: f32) { partials[i] = v; }

@compute @workgroup_size(WG)
fn main(@builtin(workgroup_id) wid: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let n = P.i.x;
    let groups = P.i.z;
    var acc = vec4<f32>(0.0);
    for (var i = wid.x * WG + lid; i < n; i = i + groups * WG) {
        let pi = p_load(i);
        let r = min(pi, P.f.x * gap_load(i));
        acc.x = fma(r, r, acc.x);
        acc.y = fma(pi, pi, acc.y);
    }
    let t = workgroup_sum4(lid, acc);
    if (lid == 0u) {
        partials_store(P.i.y * groups + wid.x, t.x);
        partials_store((P.i.y + 1u) * groups + wid.x, t.y);
    }
}
