// Matrix-free influence operator of a quadtree mesh from its level tables
// (paper Eq. 7; physics.md section 7; CPU twin: AdaptiveOperator in
// src/operator/adaptive.rs), the pass for the sources of one level l: one
// invocation per target cell T adds
//   yout[T] (+)= c0 sum_S K_l(h_T - h_S) x_S / 4^l
// over the nonzero sources S of level l, with x_S = p_S 4^l the unknown
// (force in fine-cell units) and K_l the dimensionless coefficient of a
// level-l cell (level_table.wgsl, level_box_sum.wgsl) at the centre-to-centre
// offset in half fine sides. That offset has the parity q ^ p_S (q: 1 for a
// fine target, p_S: 1 for a fine source), picking the integer (binding 1) or
// half-integer (binding 2) table; entry k of a table stands for the offset
// 2k + parity, so k = k_T - k_S - [q = 0 and p_S = 1] with k = floor(h / 2).
// Cells (targets and sources alike) are in level order, a permutation of
// the mesh's (level_tables.rs gathers and scatters), and the compacted
// nonzero sources (index, ascending) keep that order: the sources of level
// l are one run of index, found by two binary searches. The workgroup
// stages WG sources at a time in workgroup memory; each invocation sums
// them (Kahan-compensated) for its target. The first level's pass writes,
// later ones add.
// cells[i] = (k_x, k_y, parity, level) as i32; P.i: (cells, chunks of the
// compaction, level | first << 8, w_even | w_odd << 16) with w the tables'
// row widths; P.j: (kmin_x, kmin_y) of the integer table, then of the
// half-integer one, as i32 bits; P.f.w = c0 = (1 - nu^2)/pi a (total
// compliance).

// The tables, cells and vectors are reached through accessors, so that
// each may be bound as several windows (backend::gpu::split).
@group(0) @binding(1) var<storage, read> even: array<f32>;
fn even_load(i: u32) -> f32 { return even[i]; }
@group(0) @binding(2) var<storage, read> odd: array<f32>;
fn odd_load(i: u32) -> f32 { return odd[i]; }
@group(0) @binding(3) var<storage, read> cells: array<vec4<i32>>;
fn cells_load(i: u32) -> vec4<i32> { return cells[i]; }
@group(0) @binding(4) var<storage, read> xin: array<f32>;
fn xin_load(i: u32) -> f32 { return xin[i]; }
@group(0) @binding(5) var<storage, read> index: array<u32>;
fn index_load(i: u32) -> u32 { return index[i]; }
@group(0) @binding(6) var<storage, read> offsets: array<u32>;
@group(0) @binding(7) var<storage, read_write> yout: array<f32>;
fn yout_load(i: u32) -> f32 { return yout[i]; }
fn yout_store(i: u32, v: f32) { yout[i] = v; }

var<workgroup> tile_cell: array<vec4<i32>, WG>;
var<workgroup> tile_x: array<f32, WG>;

// First position j < count of index whose cell has a level >= level (0 ..
// count; the levels along index do not decrease).
fn first_of_level(level: i32, count: u32) -> u32 {
    var lo = 0u;
    var hi = count;
    loop {
        if (lo >= hi) {
            break;
        }
        let mid = (lo + hi) / 2u;
        if (cells_load(index_load(mid)).w < level) {
            lo = mid + 1u;
        } else {
            hi = mid;
        }
    }
    return lo;
}

@compute @workgroup_size(WG)
fn main(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let n = P.i.x;
    let t = linear_id(wid, nwg, lid);
    let first = (P.i.z >> 8u) == 1u;
    let level = i32(P.i.z & 255u);
    // Every invocation reads the same entries: lo and hi are uniform.
    let count = offsets[P.i.y];
    let lo = first_of_level(level, count);
    let hi = first_of_level(level + 1, count);
    let live = t < n;
    var tgt = vec4<i32>(0, 0, 0, 0);
    if (live) {
        tgt = cells_load(t);
    }
    let w_even = i32(P.i.w & 65535u);
    let w_odd = i32(P.i.w >> 16u);
    let kmin_even = vec2<i32>(bitcast<i32>(P.j.x), bitcast<i32>(P.j.y));
    let kmin_odd = vec2<i32>(bitcast<i32>(P.j.z), bitcast<i32>(P.j.w));
    let area = f32(1u << (2u * u32(level)));
    var sum = 0.0;
    var comp = 0.0;
    for (var base = lo; base < hi; base = base + WG) {
        let j = base + lid;
        if (j < hi) {
            let s = index_load(j);
            tile_cell[lid] = cells_load(s);
            tile_x[lid] = xin_load(s) / area;
        }
        workgroupBarrier();
        let m = min(WG, hi - base);
        if (live) {
            for (var k = 0u; k < m; k = k + 1u) {
                let src = tile_cell[k];
                let corr = select(0, 1, tgt.z == 0 && src.z == 1);
                let kx = tgt.x - src.x - corr;
                let ky = tgt.y - src.y - corr;
                var c: f32;
                if ((tgt.z ^ src.z) == 1) {
                    c = odd_load(u32((kx - kmin_odd.x) * w_odd + ky - kmin_odd.y));
                } else {
                    c = even_load(u32((kx - kmin_even.x) * w_even + ky - kmin_even.y));
                }
                let term = c * tile_x[k] - comp;
                let next = sum + term;
                comp = (next - sum) - term;
                sum = next;
            }
        }
        workgroupBarrier();
    }
    if (live) {
        let v = P.f.w * sum;
        if (first) {
            yout_store(t, v);
        } else {
            yout_store(t, yout_load(t) + v);
        }
    }
}
