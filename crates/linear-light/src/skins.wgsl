#define_import_path linear_light::skins
#import soft_shadow_core::light_space::{NO_OCCLUDER, linear_depth, linear_from_ndc}
#import linear_light::sample::{unproject}
#import linear_light::grid::{SKIN_DEPTH_TOLERANCE, depth_at, grid_triangle, pair, quad_offset, samples}

// Skins warped into a neighbour's view (section 3.2): skins.rs and warp.rs on the GPU. The draw is
// indirect: find_skins.wgsl listed the source's quads that hold a skin, 6 vertices each; a
// triangle of such a quad that spans no discontinuity collapses outside the clip volume. The
// fragment shader keeps skin fragments in front of the destination's own depth map; the depth
// attachment keeps the nearest; the value is interpolated linearly in screen space, and the
// fragment writes the channel's change (s v - s / 2) (1 - lit) of warp.rs.

@group(0) @binding(3) var<storage, read> quads: array<u32>;

struct Varying {
    @builtin(position) clip: vec4<f32>,
    @location(0) @interpolate(linear) value: f32,
};

@vertex
fn vs_skin(@builtin(vertex_index) vi: u32) -> Varying {
    var out: Varying;
    out.clip = vec4<f32>(0.0, 0.0, -1.0, 1.0);
    out.value = 0.0;
    let src = samples[pair.src];
    let resolution = src.map.resolution;
    let quad = quads[vi / 6u];
    let half = (vi % 6u) / 3u;
    let corner = vi % 3u;
    let qx = i32(quad % (resolution - 1u));
    let qy = i32(quad / (resolution - 1u));
    let t = grid_triangle(qx, qy, half);
    if !t.skin {
        return out;
    }
    let o = quad_offset(half, corner);
    let world = unproject(src, u32(qx + o.x), u32(qy + o.y), t.z[corner]);
    out.clip = samples[pair.dst].map.view_proj * vec4<f32>(world, 1.0);
    out.value = select(0.0, 1.0, t.z[corner] > t.mid);
    return out;
}

// warp::lit_fraction: the fraction of the four bilinear taps of sample k's map that world
// point p passes; 1 outside the map.
fn lit_fraction(k: u32, p: vec3<f32>, t: f32) -> f32 {
    let m = samples[k].map;
    let clip = m.view_proj * vec4<f32>(p, 1.0);
    if clip.w <= 0.0 {
        return 1.0;
    }
    let ndc = clip.xy / clip.w;
    if abs(ndc.x) > 1.0 || abs(ndc.y) > 1.0 {
        return 1.0;
    }
    let r = f32(m.resolution);
    let b = vec2<f32>((ndc.x * 0.5 + 0.5) * r - 0.5, (0.5 - ndc.y * 0.5) * r - 0.5);
    let f = floor(b);
    let w = b - f;
    let z = linear_depth(m, p);
    let taps = array<vec3<f32>, 4>(
        vec3<f32>(0.0, 0.0, (1.0 - w.x) * (1.0 - w.y)),
        vec3<f32>(1.0, 0.0, w.x * (1.0 - w.y)),
        vec3<f32>(0.0, 1.0, (1.0 - w.x) * w.y),
        vec3<f32>(1.0, 1.0, w.x * w.y),
    );
    var lit = 0.0;
    for (var i = 0; i < 4; i++) {
        let xy = vec2<i32>(f + taps[i].xy);
        if z <= depth_at(k, xy.x, xy.y) * (1.0 + t) {
            lit += taps[i].z;
        }
    }
    return lit;
}

@fragment
fn fs_skin(v: Varying) -> @location(0) vec4<f32> {
    let dst = samples[pair.dst];
    let z = linear_from_ndc(dst.map, v.clip.z);
    let x = u32(v.clip.x);
    let y = u32(v.clip.y);
    let d = depth_at(pair.dst, i32(x), i32(y));
    if d < NO_OCCLUDER && z > d * (1.0 + SKIN_DEPTH_TOLERANCE) {
        discard;
    }
    var unseen = 1.0;
    if d < NO_OCCLUDER {
        unseen = 1.0 - lit_fraction(pair.src, unproject(dst, x, y, d), samples[pair.src].edge_threshold);
    }
    let s = samples[pair.src].piece;
    let value = clamp(v.value, 0.0, 1.0);
    return vec4<f32>((s * value - 0.5 * s) * unseen, 0.0, 0.0, 0.0);
}
