#define_import_path soft_shadow_core::light_space

// Light-space projection shared by every depth-map technique; mirrors the crate's light_space
// module. Imported by the shaders that use it (`#import soft_shadow_core::light_space::{...}`).

struct MapView {
    view_proj: mat4x4<f32>,
    depth_row: vec4<f32>,
    near: f32,
    far: f32,
    texel_a: f32,
    texel_b: f32,
    ortho: u32,
    weight: f32,
    resolution: u32,
    _pad_a: f32,
    light: vec4<f32>,
};

struct Bias {
    normal_offset: f32,
    depth: f32,
    slope: f32,
    max_push: f32,
};

// Half a texel's diagonal, in texels (`DEPTH_SPREAD` in light_space.rs).
const DEPTH_SPREAD: f32 = 0.70710678;

const NO_OCCLUDER: f32 = 3.40282347e38;

fn linear_depth(m: MapView, p: vec3<f32>) -> f32 {
    return dot(m.depth_row, vec4<f32>(p, 1.0));
}

// Linear depth of a reversed-Z NDC depth; the cleared value 0 means no occluder.
fn linear_from_ndc(m: MapView, z_ndc: f32) -> f32 {
    if z_ndc <= 0.0 {
        return NO_OCCLUDER;
    }
    if m.ortho == 1u {
        return m.far - z_ndc * (m.far - m.near);
    }
    return m.near * m.far / (z_ndc * (m.far - m.near) + m.near);
}

struct Coord {
    inside: bool,
    st: vec2<f32>,
    z: f32,
    // Signed receiver-plane depth change per texel of offset (`ShadowCoord::grad`).
    grad: vec2<f32>,
    z_receiver: f32,
    // The receiver faces this light sample (`ShadowCoord::facing`).
    facing: bool,
};

// `ShadowCoord::receiver_plane_depth`: the receiver's biased depth at offset `d` texels from `c.st`.
fn receiver_plane_depth(c: Coord, d: vec2<f32>) -> f32 {
    if c.facing {
        return c.z + dot(c.grad, d);
    }
    return c.z - length(c.grad) * length(d);
}

// Largest tan(theta) the biases use (`MAX_TAN`).
const MAX_TAN: f32 = 10.0;

// `above_horizon` in light_space.rs.
fn above_horizon(m: MapView, p: vec3<f32>, n: vec3<f32>) -> bool {
    var to_light = m.light.xyz;
    if m.light.w == 1.0 {
        to_light = m.light.xyz - p;
    }
    return dot(n, to_light) > 0.0;
}

const SPHERE_SPREAD_MIN_COS: f32 = 0.05;

// `sphere_spread` in light_space.rs.
fn sphere_spread(cos_theta: f32) -> f32 {
    return 1.0 / sqrt(min(max(cos_theta, SPHERE_SPREAD_MIN_COS), 1.0));
}

// `sphere_spread_at` in light_space.rs.
fn sphere_spread_at(m: MapView, p: vec3<f32>) -> f32 {
    if m.ortho == 1u {
        return 1.0;
    }
    let d = length(p - m.light.xyz);
    if d <= 0.0 {
        return 1.0;
    }
    return sphere_spread(linear_depth(m, p) / d);
}

// Map position in texels and linear depth of `q` (w < 0: at or behind the eye).
fn map_project(m: MapView, q: vec3<f32>) -> vec4<f32> {
    let clip = m.view_proj * vec4<f32>(q, 1.0);
    if clip.w <= 0.0 {
        return vec4<f32>(0.0, 0.0, 0.0, -1.0);
    }
    let resolution = f32(m.resolution);
    return vec4<f32>(
        (clip.x / clip.w * 0.5 + 0.5) * resolution,
        (0.5 - clip.y / clip.w * 0.5) * resolution,
        linear_depth(m, q),
        1.0,
    );
}

// `plane_gradient` in light_space.rs.
fn plane_gradient(m: MapView, p: vec3<f32>, n: vec3<f32>, texel: f32) -> vec2<f32> {
    var t1 = cross(n, vec3<f32>(1.0, 0.0, 0.0));
    if abs(n.x) > 0.9 {
        t1 = cross(n, vec3<f32>(0.0, 1.0, 0.0));
    }
    t1 = normalize(t1);
    let t2 = cross(n, t1);
    let a = map_project(m, p);
    let b = map_project(m, p + t1 * texel);
    let c = map_project(m, p + t2 * texel);
    if a.w < 0.0 || b.w < 0.0 || c.w < 0.0 {
        return vec2<f32>(0.0);
    }
    let u = b.xyz - a.xyz;
    let v = c.xyz - a.xyz;
    let det = u.x * v.y - v.x * u.y;
    if abs(det) < 1e-6 {
        return vec2<f32>(0.0);
    }
    let g = vec2<f32>(u.z * v.y - v.z * u.y, v.z * u.x - u.z * v.x) / det;
    let len = length(g);
    if len > MAX_TAN * texel {
        return g * (MAX_TAN * texel / len);
    }
    return g;
}

fn shadow_coord(m: MapView, bias: Bias, p: vec3<f32>, n: vec3<f32>) -> Coord {
    var c: Coord;
    c.inside = false;
    let z = linear_depth(m, p);
    let texel = m.texel_a * z + m.texel_b;
    var to_light = m.light.xyz;
    if m.light.w == 1.0 {
        to_light = m.light.xyz - p;
    }
    let cos_signed = dot(n, to_light) / max(length(to_light), 1e-30);
    let cs = max(abs(cos_signed), 1.0 / sqrt(1.0 + MAX_TAN * MAX_TAN));
    let tan_theta = sqrt(max(1.0 - cs * cs, 0.0)) / cs;
    let slope = bias.slope * texel * tan_theta;
    let p2 = p + n * (bias.normal_offset * texel);
    let cap = texel * (DEPTH_SPREAD * tan_theta + bias.max_push);
    let a = map_project(m, p2);
    let resolution = f32(m.resolution);
    if a.w < 0.0 || a.x < 0.0 || a.y < 0.0 || a.x > resolution || a.y > resolution {
        return c;
    }
    c.inside = true;
    c.st = a.xy;
    // The receiver's own plane where the map is read lies `normal_offset / cs` texels beyond the
    // offset point. Facing away from the sample (attached shadow, the lighting's job): no cap.
    c.z = a.z - bias.depth * texel - slope;
    if cos_signed > 0.0 {
        c.z = max(c.z, a.z + bias.normal_offset * texel / cs - cap);
    }
    c.grad = plane_gradient(m, p2, n, texel);
    c.z_receiver = z;
    c.facing = cos_signed > 0.0;
    return c;
}

// The bilinear footprint of texel coordinate `st` (Map2D::bilinear_taps): the top-left texel of
// the 2x2 taps and the weights' fractions.
struct Taps {
    base: vec2<i32>,
    f: vec2<f32>,
};

fn bilinear_taps(st: vec2<f32>) -> Taps {
    let u = st - vec2<f32>(0.5);
    let i = floor(u);
    return Taps(vec2<i32>(i), u - i);
}
