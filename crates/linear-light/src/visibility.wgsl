#define_import_path linear_light::visibility
#import soft_shadow_core::light_space::{Bias, bilinear_taps, linear_from_ndc, receiver_plane_depth, shadow_coord}
#import linear_light::sample::{Sample}

// The shade() loop of section 3 (eval.rs) as `visibility(world_pos, normal)`.

struct EvalParams {
    bias: Bias,
    samples_n: u32,
    _pad_c: u32,
    _pad_a: u32,
    _pad_b: u32,
};

@group(#{MAPS_GROUP}) @binding(0) var<uniform> ep: EvalParams;
@group(#{MAPS_GROUP}) @binding(1) var<storage, read> samples: array<Sample>;
@group(#{MAPS_GROUP}) @binding(2) var depth_maps: texture_depth_2d_array;
@group(#{MAPS_GROUP}) @binding(3) var channels: texture_2d_array<f32>;

fn visibility(p: vec3<f32>, n: vec3<f32>) -> f32 {
    var v = 0.0;
    for (var k = 0u; k < ep.samples_n; k++) {
        let m = samples[k].map;
        let c = shadow_coord(m, ep.bias, p, n);
        if !c.inside {
            v += m.weight;
            continue;
        }
        let last = i32(m.resolution) - 1;
        let bt = bilinear_taps(c.st);
        let t = bt.f;
        let taps = array<vec3<f32>, 4>(
            vec3<f32>(0.0, 0.0, (1.0 - t.x) * (1.0 - t.y)),
            vec3<f32>(1.0, 0.0, t.x * (1.0 - t.y)),
            vec3<f32>(0.0, 1.0, (1.0 - t.x) * t.y),
            vec3<f32>(1.0, 1.0, t.x * t.y),
        );
        for (var i = 0; i < 4; i++) {
            let xy = clamp(bt.base + vec2<i32>(taps[i].xy), vec2<i32>(0), vec2<i32>(last));
            let d = linear_from_ndc(m, textureLoad(depth_maps, xy, i32(k), 0));
            // The receiver's own plane at the tap's centre (receiver-plane bias).
            let z = receiver_plane_depth(c, vec2<f32>(xy) + vec2<f32>(0.5) - c.st);
            if z <= d {
                v += taps[i].z * textureLoad(channels, xy, i32(k), 0).x;
            }
        }
    }
    return clamp(v, 0.0, 1.0);
}

