// Workgroup inclusive prefix sum of one u32 per invocation
// (Hillis-Steele). Every invocation must call it (it contains barriers).

var<workgroup> scan_buf: array<u32, WG>;

fn workgroup_inclusive_scan(lid: u32, v: u32) -> u32 {
    scan_buf[lid] = v;
    workgroupBarrier();
    for (var off = 1u; off < WG; off = off << 1u) {
        var left = 0u;
        if (lid >= off) {
            left = scan_buf[lid - off];
        }
        workgroupBarrier();
        scan_buf[lid] = scan_buf[lid] + left;
        workgroupBarrier();
    }
    return scan_buf[lid];
}
