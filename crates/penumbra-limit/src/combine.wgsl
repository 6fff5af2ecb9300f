#define_import_path penumbra_limit::combine
#import penumbra_limit::warp::{GenParams, MAX_P, NONE_DEPTH, depth_gap, has_edge, linear}

// The stored texel (c, g, b, p_i / 4 + 1/2); mirrors penumbra_limit::combine::combine (its per-texel `texel`).
// The shader def STORAGE picks the map's format: 0 rgba32float, 1 rgba16float, 2 rgba8unorm.
// Values are rounded to the format here (to nearest, ties to even, as penumbra_limit::storage
// does), so the hardware's conversion, whose rounding mode varies between drivers, only ever
// stores exactly representable values.

@group(0) @binding(0) var<uniform> gp: GenParams;
@group(0) @binding(1) var<storage, read> geom: array<f32>;
@group(0) @binding(2) var edge_tex: texture_2d<f32>;
@group(0) @binding(3) var lower_tex: texture_2d<f32>;
#if STORAGE == 2
@group(0) @binding(4) var map_out: texture_storage_2d<rgba8unorm, write>;
#else if STORAGE == 1
@group(0) @binding(4) var map_out: texture_storage_2d<rgba16float, write>;
#else
@group(0) @binding(4) var map_out: texture_storage_2d<rgba32float, write>;
#endif

// 0: f32, 1: f16, 2: 8-bit unorm.
const STORAGE: u32 = #{STORAGE}u;

fn quantize(v: f32) -> f32 {
    if STORAGE == 1u {
        if v < 6.103515625e-5 {
            return round(v * 16777216.0) / 16777216.0;
        }
        let b = bitcast<u32>(v);
        return bitcast<f32>((b + 0xfffu + ((b >> 13u) & 1u)) & 0xffffe000u);
    }
    if STORAGE == 2u {
        return round(v * 255.0) / 255.0;
    }
    return v;
}

fn edge_at(x: i32, y: i32) -> vec2<f32> {
    let r = i32(gp.resolution) - 1;
    return textureLoad(edge_tex, vec2<i32>(clamp(x, 0, r), clamp(y, 0, r)), 0).xy;
}

@compute @workgroup_size(8, 8)
fn combine(@builtin(global_invocation_id) gid: vec3<u32>) {
    if gid.x >= gp.resolution || gid.y >= gp.resolution {
        return;
    }
    let x = i32(gid.x);
    let y = i32(gid.y);
    let g0 = geom[gid.y * gp.resolution + gid.x];
    let lower = textureLoad(lower_tex, vec2<i32>(x, y), 0).x;
    let e = edge_at(x, y);
    var t = vec4<f32>(g0, g0, lower, select(MAX_P, -MAX_P, g0 < NONE_DEPTH));
    if has_edge(e) {
        let c = e.x;
        let p = e.y;
        let gap = depth_gap(gp.warp, linear(gp.warp, c), gp.transition_gap);
        var transition = false;
        var straddles = false;
        let ds = array<vec2<i32>, 4>(vec2<i32>(-1, 0), vec2<i32>(1, 0), vec2<i32>(0, -1), vec2<i32>(0, 1));
        for (var i = 0; i < 4; i++) {
            let n = edge_at(x + ds[i].x, y + ds[i].y);
            transition = transition || (has_edge(n) && abs(n.x - c) > gap);
            straddles = straddles || (has_edge(n) && n.y < 0.0 && abs(n.x - c) <= gap);
        }
        straddles = straddles && !transition;
        var g = g0;
        if p >= 0.0 {
            if straddles {
                g = min(g0, c);
            } else {
                g = min(g0, c + p);
            }
        }
        let covered = p >= 0.0 && g0 < NONE_DEPTH && abs(g0 - c) > gap;
        t = vec4<f32>(c, g, select(lower, g0, transition || covered), p);
    }
    let raw = clamp(vec4<f32>(t.xyz, clamp(t.w, -MAX_P, MAX_P) * 0.25 + 0.5), vec4<f32>(0.0), vec4<f32>(1.0));
    let q = vec4<f32>(quantize(raw.x), quantize(raw.y), quantize(raw.z), quantize(raw.w));
    textureStore(map_out, vec2<i32>(x, y), q);
}
