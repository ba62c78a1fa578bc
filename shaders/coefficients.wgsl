// Influence-coefficient table of the steady-sliding Green's function in f32
// (paper Eq. 4 and Eq. 6; physics.md section 3), one invocation per cell
// offset X = (di, dj a_y / a_x), in units of the cell side along x
// (L(a X) = a L(X); rectangular cells of aspect a_y / a_x = P.f.w):
//   T(X) = g L(X) + sum_k w_k int_0^inf ds (1/l_k) exp(-s/l_k) L(X + s e_v),
// evaluated by `unit_coefficient` (shared/green.wgsl) with l_k = v tau_k / a.
// The host multiplies by (1 - nu^2)/pi * a * (total compliance). CPU twin:
// SlidingKernel::table.
// P.i: (nx, ny, active terms, 0); P.f: (e_x, e_y, g, a_y / a_x).
// terms (binding 1, shared/green.wgsl)[k] = (w_k, 1 / l_k).

@group(0) @binding(2) var<storage, read_write> table: array<f32>;
fn table_store(i: u32, v: f32) { table[i] = v; }

const CWG: u32 = 64u;

@compute @workgroup_size(CWG)
fn main(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let nx = P.i.x;
    let ny = P.i.y;
    let wy = 2u * ny - 1u;
    let t = (wid.y * nwg.x + wid.x) * CWG + lid;
    if (t >= (2u * nx - 1u) * wy) {
        return;
    }
    cell_aspect = P.f.w;
    let x = vec2<f32>(f32(i32(t / wy) - i32(nx) + 1), f32(i32(t % wy) - i32(ny) + 1) * cell_aspect);
    table_store(t, unit_coefficient(x, P.f.xy, P.f.z, P.i.z, 1.0));
}
