// Coefficients of the next quadtree level (physics.md section 7; CPU twin:
// LatticeTable::box_sum in src/operator/adaptive.rs): a cell of level l is
// its four children of level l - 1 under the same uniform pressure, so
//   out(r, c) = in(r, c) + in(r, c + d) + in(r + d, c) + in(r + d, c + d)
// where the output lattice starts `lo` entries inside the input's and the
// children lie `d` entries apart (the offset algebra is on the host). All
// four terms are positive: nothing cancels.
// P.i: (w_out, h_out, w_in, d).

@group(0) @binding(1) var<storage, read> input: array<f32>;
fn input_load(i: u32) -> f32 { return input[i]; }
@group(0) @binding(2) var<storage, read_write> output: array<f32>;
fn output_store(i: u32, v: f32) { output[i] = v; }

@compute @workgroup_size(WG)
fn main(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let w = P.i.x;
    let t = linear_id(wid, nwg, lid);
    if (t >= w * P.i.y) {
        return;
    }
    let r = t / w;
    let c = t % w;
    let wi = P.i.z;
    let d = P.i.w;
    let base = r * wi + c;
    output_store(t, (input_load(base) + input_load(base + d)) + (input_load(base + d * wi) + input_load(base + d * wi + d)));
}
