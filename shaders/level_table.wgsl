// Level-0 influence coefficients of a quadtree mesh on one offset lattice
// (paper Eq. 4 and Eq. 6; physics.md sections 3 and 7; CPU twin:
// LevelTables in src/operator/adaptive.rs): entry (r, c) is the
// dimensionless coefficient T(X) of a unit source cell at the offset
//   X = (kmin_x + r + parity / 2, kmin_y + c + parity / 2)
// in fine-cell sides: integer offsets (parity 0: centre to centre of two
// fine cells) or half-integer ones (parity 1: a fine cell's centre to a
// coarse cell's centre, which sits on a vertex of the fine grid). One
// invocation per entry, row-major with `w` entries per row; the host
// multiplies by (1 - nu^2)/pi * a * (total compliance).
// P.i: (w, h, active terms, parity); P.j: (kmin_x, kmin_y) as i32 bits;
// P.f: (e_x, e_y, g, 0). terms (binding 1, shared/green.wgsl).

@group(0) @binding(2) var<storage, read_write> table: array<f32>;
fn table_store(i: u32, v: f32) { table[i] = v; }

const LWG: u32 = 64u;

@compute @workgroup_size(LWG)
fn main(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let w = P.i.x;
    let t = (wid.y * nwg.x + wid.x) * LWG + lid;
    if (t >= w * P.i.y) {
        return;
    }
    let half = 0.5 * f32(P.i.w);
    let kx = bitcast<i32>(P.j.x) + i32(t / w);
    let ky = bitcast<i32>(P.j.y) + i32(t % w);
    let x = vec2<f32>(f32(kx) + half, f32(ky) + half);
    table_store(t, unit_coefficient(x, P.f.xy, P.f.z, P.i.z, 1.0));
}
