// Matrix-free influence operator of a quadtree mesh from its level tables
// (paper Eq. 7; physics.md section 7; CPU twin: AdaptiveOperator in
// src/operator/adaptive.rs), first pass for the sources of one level l:
// workgroup (T, c) adds the contributions of the nonzero sources
// S = index[j] of level l, j in chunk c = [c WG, (c + 1) WG), to target
// cell T, one source per invocation:
//   partials[c n + T] (+)= sum_S K_l(h_T - h_S) x_S / 4^l,
// with x_S = p_S 4^l the unknown (force in fine-cell units) and K_l the
// dimensionless coefficient of a level-l cell (level_table.wgsl,
// level_box_sum.wgsl) at the centre-to-centre offset in half fine sides.
// That offset has the parity q ^ p_S (q: 1 for a fine target, p_S: 1 for a
// fine source), picking the integer (binding 1) or half-integer (binding 2)
// table; entry k of a table stands for the offset 2k + parity, so
// k = k_T - k_S - [q = 0 and p_S = 1] with k = floor(h / 2).
// Cells (targets and sources alike) are in level order, a permutation of
// the mesh's (level_tables.rs gathers and scatters). The first level's pass
// writes, later ones add; adaptive_sum.wgsl scales by c0 and adds the
// chunks.
// cells[i] = (k_x, k_y, parity, level) as i32; P.i: (cells, chunks,
// level | first << 8, w_even | w_odd << 16) with w the tables' row widths;
// P.j: (kmin_x, kmin_y) of the integer table, then of the half-integer one,
// as i32 bits.

@group(0) @binding(1) var<storage, read> even: array<f32>;
@group(0) @binding(2) var<storage, read> odd: array<f32>;
@group(0) @binding(3) var<storage, read> cells: array<vec4<i32>>;
@group(0) @binding(4) var<storage, read> xin: array<f32>;
@group(0) @binding(5) var<storage, read> index: array<u32>;
@group(0) @binding(6) var<storage, read> offsets: array<u32>;
@group(0) @binding(7) var<storage, read_write> partials: array<f32>;

@compute @workgroup_size(WG)
fn main(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let n = P.i.x;
    let group = linear_group(wid, nwg);
    if (group >= n * P.i.y) {
        return;
    }
    let t = group % n;
    let chunk = group / n;
    let at = chunk * n + t;
    let first = (P.i.z >> 8u) == 1u;
    let level = i32(P.i.z & 255u);
    // Cells are sorted by level, so a chunk's sources span the levels of
    // its first and last entries: chunks past the nonzero sources, or
    // without a source of this level, leave at once (the test reads the
    // same entries in every invocation: uniform).
    let count = offsets[P.i.y];
    let j0 = chunk * WG;
    if (j0 >= count || level < cells[index[j0]].w || level > cells[index[min(j0 + WG, count) - 1u]].w) {
        if (first && lid == 0u) {
            partials[at] = 0.0;
        }
        return;
    }
    let j = j0 + lid;
    var v = 0.0;
    if (j < count) {
        let s = index[j];
        let src = cells[s];
        if (src.w == level) {
            let tgt = cells[t];
            let odd_table = (tgt.z ^ src.z) == 1;
            let corr = select(0, 1, tgt.z == 0 && src.z == 1);
            let kx = tgt.x - src.x - corr;
            let ky = tgt.y - src.y - corr;
            var k: f32;
            if (odd_table) {
                let w = i32(P.i.w >> 16u);
                k = odd[(kx - bitcast<i32>(P.j.z)) * w + ky - bitcast<i32>(P.j.w)];
            } else {
                let w = i32(P.i.w & 65535u);
                k = even[(kx - bitcast<i32>(P.j.x)) * w + ky - bitcast<i32>(P.j.y)];
            }
            v = k * xin[s] / f32(1u << (2u * u32(level)));
        }
    }
    let total = workgroup_sum4(lid, vec4<f32>(v, 0.0, 0.0, 0.0));
    if (lid == 0u) {
        if (first) {
            partials[at] = total.x;
        } else {
            partials[at] = partials[at] + total.x;
        }
    }
}
