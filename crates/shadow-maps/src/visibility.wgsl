#define_import_path shadow_maps::visibility
#import soft_shadow_core::light_space::{Bias, Coord, MapView, above_horizon, linear_from_ndc, receiver_plane_depth, shadow_coord}

// Baseline shadow-map filters (hard, PCF, PCSS, accumulation) over reversed-Z depth maps.
// Mirrors filters.rs (and strata.rs for the rotated pattern) line for line.

struct Params {
    map_count: u32,
    mode: u32,
    rotated: u32,
    pcf_radius: i32,
    light_size: f32,
    search_max: f32,
    filter_max: f32,
    disc: u32,
    bias: Bias,
};

@group(#{MAPS_GROUP}) @binding(0) var<uniform> prm: Params;
@group(#{MAPS_GROUP}) @binding(1) var<storage, read> views: array<MapView>;
@group(#{MAPS_GROUP}) @binding(2) var depth_maps: texture_depth_2d_array;
// Per map: the texels the lookup moves per unit of `parallax` for the 8 points of a 3 x 3 grid
// over the sample's cell other than its centre, two points a vec4 (a to d), the sample's move
// along the map's axis at the same points, four a vec4 (za, zb), and the principal point
// (strata.rs `Stratum`).
struct Stratum {
    a: vec4<f32>,
    b: vec4<f32>,
    c: vec4<f32>,
    d: vec4<f32>,
    za: vec4<f32>,
    zb: vec4<f32>,
    centre: vec4<f32>,
};
@group(#{MAPS_GROUP}) @binding(3) var<storage, read> strata: array<Stratum>;

// The linear depth stored in layer `layer` at the texel under `st + d` (clamped to the edge),
// and the receiver's own biased depth there: `c.z` moved along its plane to that texel's centre.
fn tap(m: MapView, layer: u32, c: Coord, d: vec2<f32>) -> vec2<f32> {
    let last = i32(m.resolution) - 1;
    let xy = clamp(vec2<i32>(floor(c.st + d)), vec2<i32>(0), vec2<i32>(last));
    let centre = vec2<f32>(xy) + vec2<f32>(0.5);
    return vec2<f32>(
        linear_from_ndc(m, textureLoad(depth_maps, xy, layer, 0)),
        receiver_plane_depth(c, centre - c.st),
    );
}

fn lit(m: MapView, layer: u32, c: Coord, d: vec2<f32>) -> f32 {
    let t = tap(m, layer, c, d);
    return select(0.0, 1.0, t.y <= t.x);
}

fn cone_radius(m: MapView, l: f32, z_block: f32, z_recv: f32) -> f32 {
    let world = 0.5 * l * (z_recv - z_block);
    if m.ortho == 1u {
        return world / m.texel_b;
    }
    return world / (m.texel_a * z_block * z_recv);
}

// Whether PCSS keeps the tap (i, j) of a grid of half-side n (`filters.rs` `pcss_tap`): every
// tap of the square, or where `prm.disc` those within its inscribed circle.
fn pcss_tap(i: i32, j: i32, n: i32) -> bool {
    return prm.disc == 0u || i * i + j * j <= n * n;
}

fn pcss(m: MapView, c: Coord) -> f32 {
    let z = c.z;
    let search = clamp(cone_radius(m, prm.light_size, m.near, z), 1.0, prm.search_max);
    var sum = 0.0;
    var count = 0.0;
    for (var j = -3; j <= 3; j++) {
        for (var i = -3; i <= 3; i++) {
            if !pcss_tap(i, j, 3) {
                continue;
            }
            let off = vec2<f32>(f32(i), f32(j)) * (search / 3.0);
            let t = tap(m, 0u, c, off);
            if t.x < t.y {
                sum += t.x;
                count += 1.0;
            }
        }
    }
    if count == 0.0 {
        return 1.0;
    }
    let blocker = sum / count;
    let radius = clamp(cone_radius(m, prm.light_size, blocker, z), 0.5, prm.filter_max);
    var s = 0.0;
    var taps = 0.0;
    for (var j = -4; j <= 4; j++) {
        for (var i = -4; i <= 4; i++) {
            if !pcss_tap(i, j, 4) {
                continue;
            }
            s += lit(m, 0u, c, vec2<f32>(f32(i), f32(j)) * (radius / 4.0));
            taps += 1.0;
        }
    }
    return s / taps;
}

fn parallax(m: MapView, z_block: f32, z_recv: f32) -> f32 {
    var g = 1.0 / z_block - 1.0 / z_recv;
    if m.ortho == 1u {
        g = z_recv - z_block;
    }
    return max(g, 0.0);
}

// A receiver's point in each sample's cell, in [-1/2, 1/2)^2: pcg3d of the position's bits,
// rotated by the R2 sequence per sample, in 24-bit fixed point.
fn cell_point(p: vec3<f32>, k: u32) -> vec2<f32> {
    var v = bitcast<vec3<u32>>(p) * 1664525u + 1013904223u;
    v.x += v.y * v.z;
    v.y += v.z * v.x;
    v.z += v.x * v.y;
    v ^= v >> vec3<u32>(16u);
    v.x += v.y * v.z;
    v.y += v.z * v.x;
    let u = ((v.xy >> vec2<u32>(8u)) + k * vec2<u32>(12664746u, 9560334u)) & vec2<u32>(0xffffffu);
    return vec2<f32>(u) / 16777216.0 - vec2<f32>(0.5);
}

fn lagrange(t: f32) -> vec3<f32> {
    let s = 2.0 * t;
    return vec3<f32>(0.5 * s * (s - 1.0), 1.0 - s * s, 0.5 * s * (s + 1.0));
}

// The quadratic through map `k`'s stratum at `cell`, for a receiver at texel `st` (strata.rs
// `moved`).
fn moved(k: u32, cell: vec2<f32>, st: vec2<f32>) -> vec2<f32> {
    let wx = lagrange(cell.x);
    let wy = lagrange(cell.y);
    let s = strata[k];
    let across = wy.x * (wx.x * s.a.xy + wx.y * s.a.zw + wx.z * s.b.xy)
        + wy.y * (wx.x * s.b.zw + wx.z * s.c.xy)
        + wy.z * (wx.x * s.c.zw + wx.y * s.d.xy + wx.z * s.d.zw);
    let along = wy.x * (wx.x * s.za.x + wx.y * s.za.y + wx.z * s.za.z)
        + wy.y * (wx.x * s.za.w + wx.z * s.zb.x)
        + wy.z * (wx.x * s.zb.y + wx.y * s.zb.z + wx.z * s.zb.w);
    return across - along * (st - s.centre.xy);
}

fn capped(d: vec2<f32>) -> vec2<f32> {
    return d * (prm.search_max / max(length(d), prm.search_max));
}

// The sample of map `k` moved by `step` texels per unit of parallax (see filters.rs `rotated`).
fn rotated(m: MapView, k: u32, c: Coord, step: vec2<f32>) -> f32 {
    let centre = tap(m, k, c, vec2<f32>(0.0));
    var block = centre.x;
    if centre.x >= centre.y {
        let probe = tap(m, k, c, capped(step * parallax(m, m.near, c.z_receiver)));
        if probe.x >= probe.y {
            return 1.0;
        }
        block = probe.x;
    }
    return lit(m, k, c, capped(step * parallax(m, block, c.z_receiver)));
}

fn visibility(p: vec3<f32>, n: vec3<f32>) -> f32 {
    if prm.mode == 3u {
        var sum = 0.0;
        var wsum = 0.0;
        for (var k = 0u; k < prm.map_count; k++) {
            let m = views[k];
            // Visibility v2: samples below the receiver's horizon do not reach it.
            if !above_horizon(m, p, n) {
                continue;
            }
            let c = shadow_coord(m, prm.bias, p, n);
            var v = 1.0;
            if c.inside {
                if prm.rotated == 1u {
                    v = rotated(m, k, c, moved(k, cell_point(p, k), c.st));
                } else {
                    v = lit(m, k, c, vec2<f32>(0.0));
                }
            }
            sum += m.weight * v;
            wsum += m.weight;
        }
        return select(1.0, sum / wsum, wsum > 0.0);
    }
    let m = views[0];
    let c = shadow_coord(m, prm.bias, p, n);
    if !c.inside {
        return 1.0;
    }
    if prm.mode == 0u {
        return lit(m, 0u, c, vec2<f32>(0.0));
    }
    if prm.mode == 1u {
        let r = prm.pcf_radius;
        var s = 0.0;
        for (var j = -r; j <= r; j++) {
            for (var i = -r; i <= r; i++) {
                s += lit(m, 0u, c, vec2<f32>(f32(i), f32(j)));
            }
        }
        return s / f32((2 * r + 1) * (2 * r + 1));
    }
    return pcss(m, c);
}
