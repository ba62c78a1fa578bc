// Primal-dual active-set update (physics.md section 4; CPU twin:
// CpuBackend::update_active_set): a cell in the set stays iff p > 0, a cell
// outside joins iff gap < 0. Per-workgroup partial counts of changes and of
// the new set size go to partials[slot * groups + wg] and
// partials[(slot + 1) * groups + wg].
// P.i.x: length; P.i.y: slot; P.i.z: groups (grid-stride workgroups).

@group(0) @binding(1) var<storage, read> p: array<f32>;
fn p_load(i: u32) -> f32 { return p[i]; }
@group(0) @binding(2) var<storage, read> gap: array<f32>;
fn gap_load(i: u32) -> f32 { return gap[i]; }
@group(0) @binding(3) var<storage, read_write> mask: array<f32>;
fn mask_load(i: u32) -> f32 { return mask[i]; }
fn mask_store(i: u32, v: f32) { mask[i] = v; }
@group(0) @binding(4) var<storage, read_write> partials: array<f32>;
fn partials_store(i: u32, v: f32) { partials[i] = v; }

@compute @workgroup_size(WG)
fn main(@builtin(workgroup_id) wid: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let n = P.i.x;
    let groups = P.i.z;
    var acc = vec4<f32>(0.0);
    for (var i = wid.x * WG + lid; i < n; i = i + groups * WG) {
        let was = mask_load(i) > 0.5;
        var now = gap_load(i) < 0.0;
        if (was) {
            now = p_load(i) > 0.0;
        }
        mask_store(i, select(0.0, 1.0, now));
        acc.x = acc.x + select(0.0, 1.0, was != now);
        acc.y = acc.y + select(0.0, 1.0, now);
    }
    let t = workgroup_sum4(lid, acc);
    if (lid == 0u) {
        partials_store(P.i.y * groups + wid.x, t.x);
        partials_store((P.i.y + 1u) * groups + wid.x, t.y);
    }
}
