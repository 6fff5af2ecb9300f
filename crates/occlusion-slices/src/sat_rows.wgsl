#define_import_path occlusion_slices::sat_rows
#import occlusion_slices::frame::{Frame}

// The row scan of the summed-area table (section 3.2), four slices per texel: one invocation
// per table row sums its occupancy row into integer prefixes; row 0 of the table is all zeros.
// sat_cols.wgsl completes the table, levels.wgsl derives the N-Buffers and mipmaps from it.
// (A workgroup-parallel scan measured no faster on an H100, where fresh-texture allocation
// dominates, and several times slower on lavapipe, where barriers are costly.)

@group(0) @binding(0) var<uniform> frame: Frame;

// --- sat_rows: occupancy -> row prefix sums, row 0 of the table all zeros.
@group(0) @binding(1) var occupancy: texture_2d_array<f32>;
@group(0) @binding(2) var rows_out: texture_storage_2d_array<rgba32uint, write>;

// Table layers past the slices' `ceil(slices / 4)` (made for the chain combination) hold the
// unions of neighbouring slices: channel c of union layer u is slice 4u + c or the slice before
// it (cpu.rs's `with_unions`).
fn occupied(x: u32, y: u32, g: u32) -> vec4<u32> {
    let groups = (frame.slices + 3u) / 4u;
    if g < groups {
        return vec4<u32>(textureLoad(occupancy, vec2<u32>(x, y), g, 0) > vec4<f32>(0.0));
    }
    let u = g - groups;
    let o = textureLoad(occupancy, vec2<u32>(x, y), u, 0) > vec4<f32>(0.0);
    var before = false;
    if u > 0u {
        before = textureLoad(occupancy, vec2<u32>(x, y), u - 1u, 0).w > 0.0;
    }
    let previous = vec4<bool>(before, o.x, o.y, o.z);
    return vec4<u32>(o | previous);
}

@compute @workgroup_size(64)
fn sat_rows(@builtin(global_invocation_id) id: vec3<u32>) {
    let resolution = frame.resolution;
    let r = id.x;
    let g = id.y;
    if r > resolution {
        return;
    }
    var s = vec4<u32>(0u);
    textureStore(rows_out, vec2<u32>(0u, r), g, s);
    for (var i = 0u; i < resolution; i++) {
        if r > 0u {
            s += occupied(i, r - 1u, g);
        }
        textureStore(rows_out, vec2<u32>(i + 1u, r), g, s);
    }
}
