#define_import_path linear_light::sample
#import soft_shadow_core::light_space::{MapView}

// One light sample of the linear light: its map (MapView), the unprojection of its texel
// centres (skins.rs::Unproject) and the shares of samples.rs, imported by the crate's other
// shaders.

struct Sample {
    map: MapView,
    inv_view: mat4x4<f32>,
    sx: f32,
    sy: f32,
    edge_threshold: f32,
    piece: f32,
};

// Unproject::point: the world point of texel (x, y)'s centre at linear depth z.
fn unproject(s: Sample, x: u32, y: u32, z: f32) -> vec3<f32> {
    let r = f32(s.map.resolution);
    let nx = (f32(x) + 0.5) / r * 2.0 - 1.0;
    let ny = 1.0 - (f32(y) + 0.5) / r * 2.0;
    var v = vec2<f32>(nx * z / s.sx, ny * z / s.sy);
    if s.map.ortho == 1u {
        v = vec2<f32>(nx / s.sx, ny / s.sy);
    }
    return (s.inv_view * vec4<f32>(v, -z, 1.0)).xyz;
}
