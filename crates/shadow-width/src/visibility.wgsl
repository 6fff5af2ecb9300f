#define_import_path shadow_width::visibility
#import soft_shadow_core::light_space::{Bias, MapView, bilinear_taps, linear_from_ndc, shadow_coord, sphere_spread_at}

// Evaluation of Kirsch & Döllner's I(sd, sw) as `visibility(world_pos, normal)`. Mirrors
// shadow_width::eval::shade.

struct EvalParams {
    map: MapView,
    bias: Bias,
    use_table: u32,
    sphere: u32,
    from_light: u32,
    c_scale: f32,
    c_bias: f32,
    light_size: f32,
    table_size: u32,
    depth_layer: u32,
};

@group(#{MAPS_GROUP}) @binding(0) var<uniform> prm: EvalParams;
@group(#{MAPS_GROUP}) @binding(1) var depth: texture_depth_2d_array;
@group(#{MAPS_GROUP}) @binding(2) var<storage, read> width: array<f32>;
@group(#{MAPS_GROUP}) @binding(3) var<storage, read> table: array<f32>;

const MAX_C_SCALE: f32 = 1.0e30;

fn width_at(x: i32, y: i32) -> f32 {
    let last = i32(prm.map.resolution) - 1;
    let cx = clamp(x, 0, last);
    let cy = clamp(y, 0, last);
    return width[cy * i32(prm.map.resolution) + cx];
}

fn bilinear(st: vec2<f32>) -> f32 {
    let t = bilinear_taps(st);
    let a = t.f;
    let x = t.base.x;
    let y = t.base.y;
    let top = width_at(x, y) * (1.0 - a.x) + width_at(x + 1, y) * a.x;
    let bottom = width_at(x, y + 1) * (1.0 - a.x) + width_at(x + 1, y + 1) * a.x;
    return top * (1.0 - a.y) + bottom * a.y;
}

fn lookup(t: f32) -> f32 {
    let n = prm.table_size;
    let s = clamp(t, 0.0, 1.0) * f32(n - 1u);
    let i = min(u32(floor(s)), n - 2u);
    let a = s - f32(i);
    return table[i] * (1.0 - a) + table[i + 1u] * a;
}

fn visibility(p: vec3<f32>, n: vec3<f32>) -> f32 {
    let c = shadow_coord(prm.map, prm.bias, p, n);
    if !c.inside {
        return 1.0;
    }
    let last = i32(prm.map.resolution) - 1;
    let xy = clamp(vec2<i32>(floor(c.st)), vec2<i32>(0), vec2<i32>(last));
    // The shadow test is against the nearest caster (layer 0). With back faces (layer 1), `sd`
    // is measured from the nearest back face where one lies in front of the receiver; an open or
    // single-sided caster has none there (nor does a cleared texel: the far plane, no occluder),
    // and its front face stands in.
    var z_b = linear_from_ndc(prm.map, textureLoad(depth, xy, 0, 0));
    if prm.depth_layer != 0u {
        let z_back = linear_from_ndc(prm.map, textureLoad(depth, xy, 1, 0));
        if z_back < c.z {
            z_b = z_back;
        }
    }
    let sd = c.z - z_b;
    if !(sd > 0.0) {
        return 1.0;
    }
    var unit = prm.map.texel_a;
    if prm.map.ortho == 1u {
        unit = prm.map.texel_b;
    }
    let sw = bilinear(c.st) * unit;
    var cs = prm.c_scale;
    if prm.from_light == 1u {
        if prm.light_size <= 0.0 {
            return select(1.0, 0.0, sw > 0.0);
        }
        if prm.map.ortho == 1u {
            cs = 2.0 / prm.light_size;
        } else {
            var spread = 1.0;
            if prm.sphere == 1u {
                spread = sphere_spread_at(prm.map, p);
            }
            cs = 2.0 * z_b * c.z_receiver / (prm.light_size * spread);
        }
    }
    cs = min(cs, MAX_C_SCALE);
    if !(sw > 0.0) {
        return 1.0;
    }
    let num = cs * sw;
    if prm.use_table == 1u {
        return lookup(clamp(num / (num + sd), 0.0, 1.0));
    }
    if num >= (1.0 + prm.c_bias) * sd {
        return 0.0;
    }
    return clamp(1.0 + prm.c_bias - num / sd, 0.0, 1.0);
}
