// full[index[k]] = short[k] on a zeroed grid vector (CPU twin:
// CpuBackend::scatter; the zeroing is a buffer clear recorded before).
// P.i.x: index length.

@group(0) @binding(1) var<storage, read> index: array<u32>;
fn index_load(i: u32) -> u32 { return index[i]; }
@group(0) @binding(2) var<storage, read> short: array<f32>;
fn short_load(i: u32) -> f32 { return short[i]; }
@group(0) @binding(3) var<storage, read_write> full: array<f32>;
fn full_store(i: u32, v: f32) { full[i] = v; }

@compute @workgroup_size(WG)
fn main(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let k = linear_id(wid, nwg, lid);
    if (k < P.i.x) {
        full_store(index_load(k), short_load(k));
    }
}
