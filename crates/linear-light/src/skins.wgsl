// requires: light_space.wgsl sample.wgsl
// Skins warped into a neighbour's view (section 3.2): skins.rs and warp.rs on the GPU. The vertex
// shader walks the grid triangles of the source map (6 vertices per quad); a triangle that spans
// no depth discontinuity collapses to a point outside the clip volume. The fragment shader keeps
// skin fragments in front of the destination's own depth map; the depth attachment keeps the
// nearest; the value is interpolated linearly in screen space, and the fragment writes the
// channel's change (s v - s / 2) (1 - lit) of warp.rs.

struct Pair {
    src: u32,
    dst: u32,
    _pad0: u32,
    _pad1: u32,
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
    let res = src.map.resolution;
    let tri = vi / 3u;
    let corner = vi % 3u;
    let quad = tri / 2u;
    let half = tri % 2u;
    let qx = i32(quad % (res - 1u));
    let qy = i32(quad / (res - 1u));
    // QUAD_TRIANGLES: (a, b, c) and (b, d, c).
    var offs = array<vec2<i32>, 3>(vec2<i32>(0, 0), vec2<i32>(1, 0), vec2<i32>(0, 1));
    if half == 1u {
        offs = array<vec2<i32>, 3>(vec2<i32>(1, 0), vec2<i32>(1, 1), vec2<i32>(0, 1));
    }
    let quad_z = vec4<f32>(depth_at(pair.src, qx, qy), depth_at(pair.src, qx + 1, qy), depth_at(pair.src, qx, qy + 1), depth_at(pair.src, qx + 1, qy + 1));
    if any(quad_z >= vec4<f32>(NO_OCCLUDER)) {
        return out;
    }
    if !(is_edge(qx, qy) || is_edge(qx + 1, qy) || is_edge(qx, qy + 1) || is_edge(qx + 1, qy + 1)) {
        return out;
    }
    var z: array<f32, 3>;
    for (var k = 0u; k < 3u; k++) {
        z[k] = depth_at(pair.src, qx + offs[k].x, qy + offs[k].y);
    }
    let lo = min(min(z[0], z[1]), z[2]);
    let hi = max(max(z[0], z[1]), z[2]);
    if hi - lo <= src.edge_threshold * lo {
        return out;
    }
    let mid = 0.5 * (lo + hi);
    let o = offs[corner];
    let world = unproject(src, u32(qx + o.x), u32(qy + o.y), z[corner]);
    out.clip = samples[pair.dst].map.view_proj * vec4<f32>(world, 1.0);
    out.value = select(0.0, 1.0, z[corner] > mid);
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
