// requires: frame.wgsl scan.wgsl
// The row scan of the summed-area table (section 3.2), four slices per texel: each row of the
// occupancy becomes its prefix sums of integer counts; row 0 of the table is all zeros.
// One workgroup per table row: every thread sums a chunk, a workgroup scan of the chunk sums
// gives each chunk its offset, then every thread writes its chunk's prefixes (scan.wgsl holds
// the shared scan). sat_cols.wgsl completes the table, levels.wgsl derives the levels.

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var occupancy: texture_2d_array<f32>;
@group(0) @binding(2) var rows_out: texture_storage_2d_array<rgba32uint, write>;

fn occupied(i: u32, r: u32, g: i32) -> vec4<u32> {
    if r == 0u {
        return vec4<u32>(0u);
    }
    return vec4<u32>(textureLoad(occupancy, vec2<u32>(i, r - 1u), g, 0) > vec4<f32>(0.5));
}

@compute @workgroup_size(256)
fn sat_rows(@builtin(workgroup_id) wg: vec3<u32>, @builtin(local_invocation_index) t: u32) {
    let res = frame.resolution;
    let r = wg.x;
    let g = i32(wg.y);
    let chunk = (res + SCAN_THREADS - 1u) / SCAN_THREADS;
    let i0 = min(t * chunk, res);
    let i1 = min(i0 + chunk, res);
    var s = vec4<u32>(0u);
    for (var i = i0; i < i1; i++) {
        s += occupied(i, r, g);
    }
    var run = exclusive_scan(s, t);
    if t == 0u {
        textureStore(rows_out, vec2<u32>(0u, r), g, vec4<u32>(0u));
    }
    for (var i = i0; i < i1; i++) {
        run += occupied(i, r, g);
        textureStore(rows_out, vec2<u32>(i + 1u, r), g, run);
    }
}
