// Influence coefficients between cells of different sizes, one invocation
// per (target point, source cell) pair (paper Eq. 4 and Eq. 6; physics.md
// section 3): K(d; s) = s T_s(d / s), T_s the unit-cell coefficient
// (`unit_coefficient`, shared/green.wgsl) with memory lengths l_k / s.
// pairs[t] = (X_x, X_y, size, 0): the offset d / s in source cells and the
// source side in the length unit of `terms`; out[t] = size * T_s(X), which
// the host multiplies by (1 - nu^2)/pi * (length unit) * (total compliance).
// P.i: (pairs, terms, 0, 0); P.f: (e_x, e_y, g, 0), g the glassy-plus-
// relaxed compliance fraction at the unit length.

@group(0) @binding(2) var<storage, read> pairs: array<vec4<f32>>;
fn pairs_load(i: u32) -> vec4<f32> { return pairs[i]; }
@group(0) @binding(3) var<storage, read_write> out: array<f32>;
fn out_store(i: u32, v: f32) { out[i] = v; }

const PWG: u32 = 64u;

@compute @workgroup_size(PWG)
fn main(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let t = (wid.y * nwg.x + wid.x) * PWG + lid;
    if (t >= P.i.x) {
        return;
    }
    let q = pairs_load(t);
    out_store(t, q.z * unit_coefficient(q.xy, P.f.xy, P.f.z, P.i.y, q.z));
}
