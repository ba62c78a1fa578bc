// Workgroup tree reduction of four f32 lanes at once. Every invocation of
// the workgroup must call it (it contains barriers); the sum is valid in
// invocation 0.

var<workgroup> red: array<vec4<f32>, WG>;

fn workgroup_sum4(lid: u32, v: vec4<f32>) -> vec4<f32> {
    red[lid] = v;
    workgroupBarrier();
    for (var s = WG / 2u; s > 0u; s = s >> 1u) {
        if (lid < s) {
            red[lid] = red[lid] + red[lid + s];
        }
        workgroupBarrier();
    }
    return red[0];
}
