// Stream compaction of the contact set, pass 1 of 3 (CPU twin:
// CpuBackend::index_of): the number of cells with mask > 0.5 in each block
// of WG cells. One workgroup per block.
// P.i.x: grid length; P.i.y: blocks; P.i.z = 1: select the nonzero entries
// instead (the sources of adaptive_matvec.wgsl).

@group(0) @binding(1) var<storage, read> mask: array<f32>;
fn mask_load(i: u32) -> f32 { return mask[i]; }
@group(0) @binding(2) var<storage, read_write> counts: array<u32>;

@compute @workgroup_size(WG)
fn main(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let b = linear_group(wid, nwg);
    let i = b * WG + lid;
    var f = 0u;
    if (i < P.i.x && select(mask_load(i) > 0.5, mask_load(i) != 0.0, P.i.z == 1u)) {
        f = 1u;
    }
    let total = workgroup_inclusive_scan(lid, f);
    if (lid == WG - 1u && b < P.i.y) {
        counts[b] = total;
    }
}
