#define_import_path occlusion_slices::sat_cols
#import occlusion_slices::frame::{Frame}

// The column scan that completes the summed-area table: S(i, j) = sum of row prefixes above j.

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var rows_in: texture_2d_array<u32>;
@group(0) @binding(2) var sat_out: texture_storage_2d_array<rgba32uint, write>;

@compute @workgroup_size(64)
fn sat_cols(@builtin(global_invocation_id) id: vec3<u32>) {
    let resolution = frame.resolution;
    let i = id.x;
    let g = i32(id.y);
    if i > resolution {
        return;
    }
    var s = vec4<u32>(0u);
    for (var r = 0u; r <= resolution; r++) {
        s += textureLoad(rows_in, vec2<u32>(i, r), g, 0);
        textureStore(sat_out, vec2<u32>(i, r), g, s);
    }
}
