// Matrix-free influence operator of a mesh of square cells of different
// sizes (paper Eq. 7 with coefficients of Eq. 4 and Eq. 6 evaluated on the
// fly), one workgroup per target cell T, its invocations striding over the
// source cells S:
//   y_T = c sum_S T_S((x_T - x_S) / s_S) x_S / s_S,
// i.e. y_T = sum_S K(x_T - x_S; s_S) x_S (a / s_S)^2 with K(d; s) = a c s T_s(d / s)
// and x_S = p_S s_S^2 / a^2 (force in units of a fine cell's area), sides in
// units of the fine side a. Sources with x_S = 0 (off the contact set) are
// skipped. Each invocation sums with Kahan compensation, then the workgroup
// adds the partial sums (tree reduction).
// cells[i] = (x_i / a, y_i / a, s_i / a, 0); P.i: (cells, terms, 0, 0);
// P.f: (e_x, e_y, g, c) with g the glassy-plus-relaxed compliance fraction at
// the fine side and c = (1 - nu^2)/pi (total compliance).

@group(0) @binding(2) var<storage, read> cells: array<vec4<f32>>;
@group(0) @binding(3) var<storage, read> xin: array<f32>;
@group(0) @binding(4) var<storage, read_write> yout: array<f32>;

@compute @workgroup_size(WG)
fn main(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let n = P.i.x;
    let target_cell = linear_group(wid, nwg);
    if (target_cell >= n) {
        return;
    }
    let xt = cells[target_cell].xy;
    var sum = 0.0;
    var comp = 0.0;
    for (var s = lid; s < n; s = s + WG) {
        let xs = xin[s];
        if (xs != 0.0) {
            let c = cells[s];
            let k = unit_coefficient((xt - c.xy) / c.z, P.f.xy, P.f.z, P.i.y, c.z);
            // Kahan step of sum += k x_S / s_S.
            let term = k * xs / c.z - comp;
            let next = sum + term;
            comp = (next - sum) - term;
            sum = next;
        }
    }
    let total = workgroup_sum4(lid, vec4<f32>(sum, -comp, 0.0, 0.0));
    if (lid == 0u) {
        yout[target_cell] = P.f.w * (total.x + total.y);
    }
}
