// Stream compaction, pass 2 of 3: exclusive prefix sum of the block counts
// in place by one workgroup (each invocation scans a contiguous run of
// blocks); the total goes to counts[blocks].
// P.i.x: blocks.

@group(0) @binding(1) var<storage, read_write> counts: array<u32>;

@compute @workgroup_size(WG)
fn main(@builtin(local_invocation_index) lid: u32) {
    let nb = P.i.x;
    let per = (nb + WG - 1u) / WG;
    let start = min(lid * per, nb);
    let end = min(start + per, nb);
    var s = 0u;
    for (var b = start; b < end; b = b + 1u) {
        s = s + counts[b];
    }
    let inclusive = workgroup_inclusive_scan(lid, s);
    var run = inclusive - s;
    for (var b = start; b < end; b = b + 1u) {
        let c = counts[b];
        counts[b] = run;
        run = run + c;
    }
    if (lid == WG - 1u) {
        counts[nb] = inclusive;
    }
}
