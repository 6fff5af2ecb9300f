// A workgroup-wide exclusive prefix sum of vec4<u32> (Hillis-Steele over shared memory), used
// by the summed-area table scans. Integer sums: the result is exact whatever the order.

const SCAN_THREADS: u32 = 256u;

var<workgroup> partial: array<vec4<u32>, 256>;

// The sum of `v` over the invocations before `t` in the workgroup.
fn exclusive_scan(v: vec4<u32>, t: u32) -> vec4<u32> {
    partial[t] = v;
    workgroupBarrier();
    for (var off = 1u; off < SCAN_THREADS; off = off * 2u) {
        var x = partial[t];
        if t >= off {
            x += partial[t - off];
        }
        workgroupBarrier();
        partial[t] = x;
        workgroupBarrier();
    }
    var before = vec4<u32>(0u);
    if t > 0u {
        before = partial[t - 1u];
    }
    return before;
}
