#define_import_path penumbra_limit::visibility
#import soft_shadow_core::light_space::{Bias, MapView, bilinear_taps, shadow_coord}
#import penumbra_limit::warp::{DEPTH_SPAN, Warp, receiver_depth}

// Evaluation as `visibility(world_pos, normal)`; mirrors penumbra_limit::eval: project the
// receiver, bilinear (c, g, b, p_i),
// equation 2, then the visibility-to-illumination table.

struct EvalParams {
    map: MapView,
    bias: Bias,
    warp: Warp,
    table_size: u32,
    _reserved: u32,
    tolerance: f32,
    _pad_a: f32,
};

@group(#{MAPS_GROUP}) @binding(0) var<uniform> prm: EvalParams;
@group(#{MAPS_GROUP}) @binding(1) var map: texture_2d<f32>;
@group(#{MAPS_GROUP}) @binding(2) var<storage, read> table: array<f32>;

fn texel(x: i32, y: i32) -> vec4<f32> {
    let r = i32(prm.map.resolution) - 1;
    let raw = textureLoad(map, vec2<i32>(clamp(x, 0, r), clamp(y, 0, r)), 0);
    return vec4<f32>(raw.xyz, (raw.w - 0.5) * 4.0);
}

struct Interpolated {
    // c, g, b, p_i bilinearly interpolated.
    t: vec4<f32>,
    // The lower limit the receiver takes; see penumbra_limit::eval::bilinear_texel.
    lower: f32,
};

// The four channels bilinearly interpolated, and the lower limit a receiver outside the
// silhouette takes (the mean b of the taps outside it); the taps are read once.
fn bilinear(st: vec2<f32>) -> Interpolated {
    let taps = bilinear_taps(st);
    let f = taps.f;
    let x0 = taps.base.x;
    let y0 = taps.base.y;
    let a = texel(x0, y0);
    let b = texel(x0 + 1, y0);
    let c = texel(x0, y0 + 1);
    let d = texel(x0 + 1, y0 + 1);
    let w = vec4<f32>((1.0 - f.x) * (1.0 - f.y), f.x * (1.0 - f.y), (1.0 - f.x) * f.y, f.x * f.y);
    let t = a * w.x + b * w.y + c * w.z + d * w.w;
    var out = Interpolated(t, t.z);
    if t.w >= 0.0 {
        let o = w * vec4<f32>(
            select(0.0, 1.0, a.w >= 0.0),
            select(0.0, 1.0, b.w >= 0.0),
            select(0.0, 1.0, c.w >= 0.0),
            select(0.0, 1.0, d.w >= 0.0),
        );
        let s = o.x + o.y + o.z + o.w;
        if s > 0.0 {
            out.lower = (a.z * o.x + b.z * o.y + c.z * o.z + d.z * o.w) / s;
        }
    }
    return out;
}

fn sat(x: f32) -> f32 {
    return clamp(x, 0.0, 1.0);
}

// Below the lower limit: the lower layer's inner penumbra inside the silhouette, the hard
// shadow outside it; see penumbra_limit::visibility::lower_visibility.
fn lower_visibility(z: f32, b: f32, p: f32) -> f32 {
    if z <= b {
        return 1.0;
    }
    if p < 0.0 {
        return sat(0.5 + 0.5 * p / max(z - b, 1.0e-30));
    }
    return 0.0;
}

// Equation 2 with the lower limit's visibility; see penumbra_limit::visibility.
fn clamped_visibility(z: f32, c: f32, g: f32, b: f32, p: f32) -> f32 {
    let l = sat(0.5 + 0.5 * p / max(z - c, 1.0e-30));
    let k = 4.0 * f32(z < g) - 2.0 * f32(z < c);
    return sat(min(l, lower_visibility(z, b, p)) + k);
}

fn lookup(l: f32) -> f32 {
    let n = prm.table_size;
    let s = clamp(l, 0.0, 1.0) * f32(n - 1u);
    let i = min(u32(floor(s)), n - 2u);
    let a = s - f32(i);
    return table[i] * (1.0 - a) + table[i + 1u] * a;
}

fn visibility(p: vec3<f32>, n: vec3<f32>) -> f32 {
    let co = shadow_coord(prm.map, prm.bias, p, n);
    var l = 1.0;
    if co.inside {
        let z = min(receiver_depth(prm.warp, co.z) - prm.tolerance, DEPTH_SPAN);
        let t = bilinear(co.st);
        l = clamped_visibility(z, t.t.x, t.t.y, t.lower, t.t.w);
    }
    return lookup(l);
}
