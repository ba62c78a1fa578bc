// Shared declarations of every viscoslide compute kernel: the parameter
// block (one 256-byte slot of the parameter ring, bound with a dynamic
// offset), the workgroup size and the linear invocation index of a 2-D
// dispatch (grids above 65535 workgroups spill into the y dimension).

struct Params {
    // Integer parameters; each kernel documents its use of the lanes.
    i: vec4<u32>,
    j: vec4<u32>,
    // Real parameters.
    f: vec4<f32>,
}

@group(0) @binding(0) var<uniform> P: Params;

const WG: u32 = 256u;

fn linear_id(wid: vec3<u32>, nwg: vec3<u32>, lid: u32) -> u32 {
    return (wid.y * nwg.x + wid.x) * WG + lid;
}

fn linear_group(wid: vec3<u32>, nwg: vec3<u32>) -> u32 {
    return wid.y * nwg.x + wid.x;
}
