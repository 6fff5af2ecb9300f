// requires: frame.wgsl scan.wgsl
// The column scan that completes the summed-area table: S(i, j) = sum of the row prefixes above
// j. One workgroup per column, chunked like sat_rows.wgsl.

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var rows_in: texture_2d_array<u32>;
@group(0) @binding(2) var sat_out: texture_storage_2d_array<rgba32uint, write>;

@compute @workgroup_size(256)
fn sat_cols(@builtin(workgroup_id) wg: vec3<u32>, @builtin(local_invocation_index) t: u32) {
    let n = frame.resolution + 1u;
    let i = wg.x;
    let g = i32(wg.y);
    let chunk = (n + SCAN_THREADS - 1u) / SCAN_THREADS;
    let r0 = min(t * chunk, n);
    let r1 = min(r0 + chunk, n);
    var s = vec4<u32>(0u);
    for (var r = r0; r < r1; r++) {
        s += textureLoad(rows_in, vec2<u32>(i, r), g, 0);
    }
    var run = exclusive_scan(s, t);
    for (var r = r0; r < r1; r++) {
        run += textureLoad(rows_in, vec2<u32>(i, r), g, 0);
        textureStore(sat_out, vec2<u32>(i, r), g, run);
    }
}
