#define_import_path linear_light::grid
#import soft_shadow_core::light_space::{NO_OCCLUDER, linear_from_ndc}
#import linear_light::sample::{Sample}

// The grid of one sample's depth map (skins.rs), shared by find_skins.wgsl and skins.wgsl:
// linear depths, edge texels (Laplacian of inverse depth) and the skin test of a grid triangle.

struct Pair {
    src: u32,
    dst: u32,
    _pad_a: u32,
    _pad_b: u32,
};

const SKIN_DEPTH_TOLERANCE: f32 = 1e-3;

@group(0) @binding(0) var<uniform> pair: Pair;
@group(0) @binding(1) var<storage, read> samples: array<Sample>;
@group(0) @binding(2) var depth_maps: texture_depth_2d_array;

fn depth_at(k: u32, x: i32, y: i32) -> f32 {
    let last = i32(samples[k].map.resolution) - 1;
    let xy = clamp(vec2<i32>(x, y), vec2<i32>(0), vec2<i32>(last));
    return linear_from_ndc(samples[k].map, textureLoad(depth_maps, xy, i32(k), 0));
}

fn inv_depth(k: u32, x: i32, y: i32) -> f32 {
    let z = depth_at(k, x, y);
    return select(1.0 / z, 0.0, z >= NO_OCCLUDER);
}

// skins::edges at texel (x, y) of the source (a missing neighbour is extrapolated: the pair
// sums to 2c).
fn is_edge(x: i32, y: i32) -> bool {
    let k = pair.src;
    let last = i32(samples[k].map.resolution) - 1;
    let c = inv_depth(k, x, y);
    var sx = 2.0 * c;
    if x > 0 && x < last {
        sx = inv_depth(k, x - 1, y) + inv_depth(k, x + 1, y);
    }
    var sy = 2.0 * c;
    if y > 0 && y < last {
        sy = inv_depth(k, x, y - 1) + inv_depth(k, x, y + 1);
    }
    let lap = 4.0 * c - sx - sy;
    return c > 0.0 && abs(lap) > samples[k].edge_threshold * c;
}

// QUAD_TRIANGLES: (a, b, c) and (b, d, c), texel offsets from the quad's top-left texel.
fn quad_offset(half: u32, corner: u32) -> vec2<i32> {
    var offs = array<vec2<i32>, 3>(vec2<i32>(0, 0), vec2<i32>(1, 0), vec2<i32>(0, 1));
    if half == 1u {
        offs = array<vec2<i32>, 3>(vec2<i32>(1, 0), vec2<i32>(1, 1), vec2<i32>(0, 1));
    }
    return offs[corner];
}

// Whether quad (qx, qy) of the source is covered and touches an edge texel.
fn quad_touches_edge(qx: i32, qy: i32) -> bool {
    let k = pair.src;
    let z = vec4<f32>(depth_at(k, qx, qy), depth_at(k, qx + 1, qy), depth_at(k, qx, qy + 1), depth_at(k, qx + 1, qy + 1));
    if any(z >= vec4<f32>(NO_OCCLUDER)) {
        return false;
    }
    return is_edge(qx, qy) || is_edge(qx + 1, qy) || is_edge(qx, qy + 1) || is_edge(qx + 1, qy + 1);
}

struct Triangle {
    z: array<f32, 3>,
    skin: bool,
    mid: f32,
};

// skins::skin_values for triangle `half` of quad (qx, qy).
fn grid_triangle(qx: i32, qy: i32, half: u32) -> Triangle {
    var t: Triangle;
    for (var c = 0u; c < 3u; c++) {
        let o = quad_offset(half, c);
        t.z[c] = depth_at(pair.src, qx + o.x, qy + o.y);
    }
    let lo = min(min(t.z[0], t.z[1]), t.z[2]);
    let hi = max(max(t.z[0], t.z[1]), t.z[2]);
    t.skin = hi - lo > samples[pair.src].edge_threshold * lo;
    t.mid = 0.5 * (lo + hi);
    return t;
}
