#define_import_path occlusion_slices::visibility
#import occlusion_slices::frame::{Frame, TOP_STEPS, direction, fade, fade_length, kernel, light_coord, plane, spread, texel_size, texel_point, top_depth}

// Evaluation (sections 3.3-3.5) as `visibility(world_pos, normal)`: eval.rs, combine.rs and the
// lookups of filters/*.rs, operation for operation.

struct EvalParams {
    filter_kind: u32,
    combination: u32,
    levels: u32,
    // Slice index where the unions of neighbouring slices begin (the chain's).
    unions: u32,
    normal_offset: f32,
    groups: u32,
    _pad_a: u32,
    _pad_b: u32,
};

const FILTER_MIPMAP: u32 = 0u;
const FILTER_NBUFFER: u32 = 1u;
const FILTER_SAT: u32 = 2u;
const COMBINE_PRODUCT: u32 = 0u;
const COMBINE_SUM: u32 = 1u;
const COMBINE_MAX: u32 = 2u;
const COMBINE_CHAIN: u32 = 3u;

@group(#{MAPS_GROUP}) @binding(0) var<uniform> frame: Frame;
@group(#{MAPS_GROUP}) @binding(1) var<uniform> ep: EvalParams;
@group(#{MAPS_GROUP}) @binding(2) var sat: texture_2d_array<u32>;
@group(#{MAPS_GROUP}) @binding(3) var levels: texture_2d_array<f32>;
@group(#{MAPS_GROUP}) @binding(4) var tops: texture_2d_array<f32>;

// --- summed-area table (filters/sat.rs)

fn sat_get(i: i32, j: i32, k: u32) -> u32 {
    let r = i32(frame.resolution);
    let t = textureLoad(sat, vec2<i32>(clamp(i, 0, r), clamp(j, 0, r)), i32(k / 4u), 0);
    return t[k % 4u];
}

fn sat_count(x0: i32, y0: i32, x1: i32, y1: i32, k: u32) -> i32 {
    return bitcast<i32>(sat_get(x1, y1, k) - sat_get(x0, y1, k) - sat_get(x1, y0, k) + sat_get(x0, y0, k));
}

struct Split {
    a: vec3<i32>,
    b: vec3<i32>,
    w: vec3<f32>,
};

// The three column ranges of [a, b]: whole texels, the end texel, the start texel.
fn split(a: f32, b: f32) -> Split {
    let fa = floor(a);
    let fb = floor(b);
    let ia = i32(fa);
    let ib = i32(fb);
    var s: Split;
    s.a = vec3<i32>(ia + 1, ib, ia);
    s.b = vec3<i32>(ib, ib + 1, ia + 1);
    s.w = vec3<f32>(1.0, b - fb, 1.0 - (a - fa));
    return s;
}

fn sat_mean(c: vec2<f32>, size: f32, k: u32) -> f32 {
    let half = 0.5 * select(size, 1.0, size < 1.0);
    let lo = c - vec2<f32>(half);
    let hi = c + vec2<f32>(half);
    let area = (hi.x - lo.x) * (hi.y - lo.y);
    if !(area > 0.0 && area <= 3.0e38) {
        let x = i32(floor(c.x));
        let y = i32(floor(c.y));
        return f32(sat_count(x, y, x + 1, y + 1, k));
    }
    let sx = split(lo.x, hi.x);
    let sy = split(lo.y, hi.y);
    var total = 0.0;
    for (var j = 0; j < 3; j++) {
        var row = 0.0;
        for (var i = 0; i < 3; i++) {
            row += sx.w[i] * f32(sat_count(sx.a[i], sy.a[j], sx.b[i], sy.b[j], k));
        }
        total += sy.w[j] * row;
    }
    return clamp(total / area, 0.0, 1.0);
}

// --- N-Buffers (filters/nbuffer.rs)

fn floor_log2(x: f32) -> u32 {
    let e = (bitcast<u32>(x) >> 23u) & 0xffu;
    return select(0u, e - 127u, e >= 127u);
}

fn nbuffer_texel(l: u32, x: i32, y: i32, k: u32) -> f32 {
    let r = i32(frame.resolution);
    if x < 0 || y < 0 || x >= r || y >= r {
        return 0.0;
    }
    let layer = i32(l * ep.groups + k / 4u);
    return textureLoad(levels, vec2<i32>(x, y), layer, 0)[k % 4u];
}

fn nbuffer_sample(b: vec2<f32>, l: u32, k: u32) -> f32 {
    let f = floor(b);
    let x = i32(f.x);
    let y = i32(f.y);
    let t = b - f;
    let top = nbuffer_texel(l, x, y, k) * (1.0 - t.x) + nbuffer_texel(l, x + 1, y, k) * t.x;
    let bottom = nbuffer_texel(l, x, y + 1, k) * (1.0 - t.x) + nbuffer_texel(l, x + 1, y + 1, k) * t.x;
    return top * (1.0 - t.y) + bottom * t.y;
}

fn nbuffer_mean(c: vec2<f32>, size: f32, k: u32) -> f32 {
    let kk = max(size, 1.0);
    let l = min(floor_log2(kk), ep.levels - 1u);
    let s = f32(1u << l);
    let v0 = nbuffer_sample(c - vec2<f32>(0.5 * s), l, k);
    let t = clamp(kk / s - 1.0, 0.0, 1.0);
    if t <= 0.0 || l + 1u >= ep.levels {
        return v0;
    }
    let v1 = nbuffer_sample(c - vec2<f32>(s), l + 1u, k);
    return v0 + (v1 - v0) * t;
}

// --- mipmaps (filters/mipmap.rs)

fn mip_texel(l: u32, x: i32, y: i32, k: u32) -> f32 {
    let n = i32((frame.resolution + (1u << l) - 1u) >> l);
    if x < 0 || y < 0 || x >= n || y >= n {
        return 0.0;
    }
    return textureLoad(levels, vec2<i32>(x, y), i32(k / 4u), i32(l))[k % 4u];
}

fn mip_bilinear(c: vec2<f32>, l: u32, k: u32) -> f32 {
    let p = c / f32(1u << l) - vec2<f32>(0.5);
    let f = floor(p);
    let x = i32(f.x);
    let y = i32(f.y);
    let t = p - f;
    let top = mip_texel(l, x, y, k) * (1.0 - t.x) + mip_texel(l, x + 1, y, k) * t.x;
    let bottom = mip_texel(l, x, y + 1, k) * (1.0 - t.x) + mip_texel(l, x + 1, y + 1, k) * t.x;
    return top * (1.0 - t.y) + bottom * t.y;
}

fn mip_mean(c: vec2<f32>, size: f32, k: u32) -> f32 {
    let kk = max(size, 1.0);
    let l = floor_log2(kk);
    if l + 1u >= ep.levels {
        return mip_bilinear(c, ep.levels - 1u, k);
    }
    let t = clamp(log2(kk / f32(1u << l)), 0.0, 1.0);
    let v0 = mip_bilinear(c, l, k);
    let v1 = mip_bilinear(c, l + 1u, k);
    return v0 + (v1 - v0) * t;
}

fn filtered_mean(k: u32, c: vec2<f32>, size: f32) -> f32 {
    switch ep.filter_kind {
        case FILTER_MIPMAP: {
            return mip_mean(c, size, k);
        }
        case FILTER_NBUFFER: {
            return nbuffer_mean(c, size, k);
        }
        default: {
            return sat_mean(c, size, k);
        }
    }
}

// --- eval.rs::slab_occlusion: the own slab read unfiltered, depth-tested

const TAPS: u32 = 8u;
const SLAB_BIAS_TEXELS: f32 = 1.0;

// Texel (x, y)'s top code in slice k, 0 outside the map.
fn top_at(k: u32, x: i32, y: i32) -> u32 {
    let r = i32(frame.resolution);
    if x < 0 || y < 0 || x >= r || y >= r {
        return 0u;
    }
    let v = textureLoad(tops, vec2<i32>(x, y), i32(k / 4u), 0)[k % 4u];
    return u32(round(v * 255.0));
}

// eval.rs::Receiver: c and n in light coordinates, the margin and what its kernels widen by.
struct Receiver {
    c: vec3<f32>,
    n: vec3<f32>,
    margin: f32,
    widen: f32,
};

// Receiver::hidden_by.
fn hidden_by(r: Receiver, q: vec3<f32>) -> bool {
    return q.z < r.c.z - r.margin && dot(r.n, q - r.c) > r.margin;
}

fn slab_occlusion(r: Receiver, k: u32) -> f32 {
    let c = r.c;
    let upper = max(plane(frame, k) - frame.spacing, 0.0);
    let limit = c.z - r.margin;
    if !(limit > upper && c.z > 0.0) {
        return 0.0;
    }
    let a = kernel(frame, c, upper, r.widen);
    let b = kernel(frame, c, limit, r.widen);
    let lo = min(a.center - vec2<f32>(0.5 * a.size), b.center - vec2<f32>(0.5 * b.size));
    let hi = max(a.center + vec2<f32>(0.5 * a.size), b.center + vec2<f32>(0.5 * b.size));
    let extent = hi - lo;
    if !(abs(extent.x) <= 3.0e38 && abs(extent.y) <= 3.0e38) {
        return 0.0;
    }
    let nx = min(u32(max(ceil(extent.x), 1.0)), TAPS);
    let ny = min(u32(max(ceil(extent.y), 1.0)), TAPS);
    let step = extent / vec2<f32>(f32(nx), f32(ny));
    var sum = 0.0;
    for (var j = 0u; j < ny; j++) {
        for (var i = 0u; i < nx; i++) {
            let t0 = lo + step * vec2<f32>(f32(i), f32(j));
            let centre = t0 + 0.5 * step;
            let code = top_at(k, i32(floor(centre.x)), i32(floor(centre.y)));
            if code == 0u {
                continue;
            }
            let z = top_depth(frame, k, code);
            if z <= 0.0 || !hidden_by(r, texel_point(frame, centre, z)) {
                continue;
            }
            let ker = kernel(frame, c, z, r.widen);
            if !(ker.size > 0.0) {
                continue;
            }
            let hs = 0.5 * ker.size;
            let ox = max(min(t0.x + step.x, ker.center.x + hs) - max(t0.x, ker.center.x - hs), 0.0);
            let oy = max(min(t0.y + step.y, ker.center.y + hs) - max(t0.y, ker.center.y - hs), 0.0);
            sum += ox * oy / (ker.size * ker.size);
        }
    }
    return min(sum, 1.0);
}

// --- eval.rs::visibility with combine.rs::Accumulator

// combine.rs::given: the share of the light that passes a slice among what passed its
// neighbour nearer the light.
const CHAIN_EPSILON: f32 = 1.0 / 255.0;

fn given(union_occ: f32, nearer: f32) -> f32 {
    let u = clamp(union_occ, 0.0, 1.0);
    let b = clamp(nearer, 0.0, 1.0);
    return clamp(1.0 - (u - b) / max(1.0 - b, CHAIN_EPSILON), 0.0, 1.0);
}

fn visibility(p: vec3<f32>, n: vec3<f32>) -> f32 {
    if frame.occupied == 0u {
        return 1.0;
    }
    let h = light_coord(frame, p).z;
    let offset = ep.normal_offset * texel_size(frame, max(h, 0.0));
    let c = light_coord(frame, p + n * offset);
    let multiplies = ep.combination == COMBINE_PRODUCT || ep.combination == COMBINE_CHAIN;
    var acc = select(0.0, 1.0, multiplies);
    // Whether the previous slice was read filtered alone.
    var linked = false;
    let len = fade_length(frame, c.z);
    var r: Receiver;
    r.c = c;
    r.n = direction(frame, n);
    r.margin = SLAB_BIAS_TEXELS * texel_size(frame, max(c.z, 0.0)) + frame.spacing / TOP_STEPS;
    r.widen = spread(frame, c);
    for (var k = 0u; k < frame.slices; k++) {
        let w = fade(frame, k, c.z, len);
        var occ = 0.0;
        if w > 0.0 {
            let ker = kernel(frame, c, plane(frame, k), r.widen);
            if ep.combination == COMBINE_CHAIN && linked {
                // combine.rs::Accumulator::add_given.
                let u = filtered_mean(ep.unions + k, ker.center, ker.size);
                let nearer = filtered_mean(k - 1u, ker.center, ker.size);
                var s = 0.0;
                if w < 1.0 {
                    s = slab_occlusion(r, k);
                }
                acc *= w * given(u, nearer) + (1.0 - w) * (1.0 - clamp(s, 0.0, 1.0));
                linked = w >= 1.0;
                continue;
            }
            occ = w * filtered_mean(k, ker.center, ker.size);
        }
        if w < 1.0 {
            occ += (1.0 - w) * slab_occlusion(r, k);
        }
        let i = clamp(occ, 0.0, 1.0);
        switch ep.combination {
            case COMBINE_PRODUCT, COMBINE_CHAIN: {
                acc *= 1.0 - i;
            }
            case COMBINE_SUM: {
                acc += i;
            }
            default: {
                acc = max(acc, i);
            }
        }
        linked = w >= 1.0;
        if w <= 0.0 {
            break;
        }
    }
    if multiplies {
        return clamp(acc, 0.0, 1.0);
    }
    return 1.0 - clamp(acc, 0.0, 1.0);
}
