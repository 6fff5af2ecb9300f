#define_import_path occlusion_slices::levels
#import occlusion_slices::frame::{Frame}

// N-Buffer and mipmap levels from the exact summed-area table: the mean of a 2^l box as 8-bit
// unorm, rounded in integers (filters::unorm8) so every backend stores the same bits.

struct Level {
    level: u32,
    groups: u32,
    size: u32,
    _pad: u32,
};

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var sat: texture_2d_array<u32>;
@group(0) @binding(2) var<uniform> lv: Level;
@group(0) @binding(3) var level_out: texture_storage_2d_array<rgba8unorm, write>;

fn sat_at(x: u32, y: u32, g: i32) -> vec4<u32> {
    let r = frame.resolution;
    return textureLoad(sat, vec2<u32>(min(x, r), min(y, r)), g, 0);
}

// The level-l mean of the box with top-left texel (x, y), as unorm8 / 255.
fn box_unorm(x: u32, y: u32, g: i32) -> vec4<f32> {
    let s = 1u << lv.level;
    let c = sat_at(x + s, y + s, g) - sat_at(x, y + s, g) - sat_at(x + s, y, g) + sat_at(x, y, g);
    let area = 1u << (2u * lv.level);
    let q = (c * 255u + vec4<u32>(area / 2u)) / area;
    return vec4<f32>(q) / 255.0;
}

// Level l of the N-Buffers: full resolution, array layer l * groups + g.
@compute @workgroup_size(8, 8)
fn nbuffer_level(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= lv.size || id.y >= lv.size {
        return;
    }
    let g = i32(id.z);
    textureStore(level_out, id.xy, i32(lv.level * lv.groups) + g, box_unorm(id.x, id.y, g));
}

// Mip level l (the bound view is that level): block (x, y) covers texels from (x, y) * 2^l.
@compute @workgroup_size(8, 8)
fn mip_level(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= lv.size || id.y >= lv.size {
        return;
    }
    let g = i32(id.z);
    let s = 1u << lv.level;
    textureStore(level_out, id.xy, g, box_unorm(id.x * s, id.y * s, g));
}
