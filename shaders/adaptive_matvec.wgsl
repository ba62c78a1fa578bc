// Matrix-free influence operator of a mesh of square cells of different
// sizes (paper Eq. 7 with coefficients of Eq. 4 and Eq. 6 evaluated on the
// fly), first pass: workgroup (T, c) adds the contributions of the nonzero
// sources S = index[j], j in chunk c = [c WG, (c + 1) WG), to target cell T,
// one source per invocation, and writes the partial sum to
// partials[c n + T]:
//   y_T = c0 sum_S T_S((x_T - x_S) / s_S) x_S / s_S,
// i.e. y_T = sum_S K(x_T - x_S; s_S) x_S (a / s_S)^2 with
// K(d; s) = a c0 s T_s(d / s), T_s the unit-cell coefficient
// (shared/green.wgsl) and x_S = p_S s_S^2 / a^2 (force in units of a fine
// cell's area), sides in units of the fine side a. index lists the sources
// with x_S != 0 (off the contact set x_S = 0), offsets[chunks] their count
// (compact_*.wgsl with P.i.z = 1), so the cost is about targets x nonzero
// sources coefficients. One coefficient per invocation: on lavapipe,
// invocations that loop over many sources stopped accumulating early.
// adaptive_sum.wgsl adds the partials of each target and scales by c0.
// cells[i] = (x_i / a, y_i / a, s_i / a, 0); P.i: (cells, terms, chunks, 0);
// P.f: (e_x, e_y, g, 0) with g the glassy-plus-relaxed compliance fraction
// at the fine side.

@group(0) @binding(2) var<storage, read> cells: array<vec4<f32>>;
fn cells_load(i: u32) -> vec4<f32> { return cells[i]; }
@group(0) @binding(3) var<storage, read> xin: array<f32>;
fn xin_load(i: u32) -> f32 { return xin[i]; }
@group(0) @binding(4) var<storage, read> index: array<u32>;
fn index_load(i: u32) -> u32 { return index[i]; }
@group(0) @binding(5) var<storage, read> offsets: array<u32>;
@group(0) @binding(6) var<storage, read_write> partials: array<f32>;
fn partials_store(i: u32, v: f32) { partials[i] = v; }

@compute @workgroup_size(WG)
fn main(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let n = P.i.x;
    let group = linear_group(wid, nwg);
    if (group >= n * P.i.z) {
        return;
    }
    let t = group % n;
    let chunk = group / n;
    let j = chunk * WG + lid;
    var v = 0.0;
    if (j < offsets[P.i.z]) {
        let s = index_load(j);
        let c = cells_load(s);
        let k = unit_coefficient((cells_load(t).xy - c.xy) / c.z, P.f.xy, P.f.z, P.i.y, c.z);
        v = k * xin_load(s) / c.z;
    }
    let total = workgroup_sum4(lid, vec4<f32>(v, 0.0, 0.0, 0.0));
    if (lid == 0u) {
        partials_store(chunk * n + t, total.x);
    }
}
