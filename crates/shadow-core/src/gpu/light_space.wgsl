// Light-space projection shared by every depth-map technique; mirrors shadow_core::light_space.
// Prepended to the shaders that use it (a file starting with `// requires: light_space.wgsl`).

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
    _pad0: f32,
    light: vec4<f32>,
};

struct Bias {
    normal_offset: f32,
    depth: f32,
    slope: f32,
    _pad0: f32,
};

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
    slope: f32,
    z_receiver: f32,
};

fn shadow_coord(m: MapView, bias: Bias, p: vec3<f32>, n: vec3<f32>) -> Coord {
    var c: Coord;
    c.inside = false;
    let z = linear_depth(m, p);
    let texel = m.texel_a * z + m.texel_b;
    var to_light = m.light.xyz;
    if m.light.w == 1.0 {
        to_light = m.light.xyz - p;
    }
    let cs = max(abs(dot(n, to_light) / max(length(to_light), 1e-30)), 0.1);
    let slope = bias.slope * texel * (sqrt(max(1.0 - cs * cs, 0.0)) / cs);
    let p2 = p + n * (bias.normal_offset * texel);
    let clip = m.view_proj * vec4<f32>(p2, 1.0);
    if clip.w <= 0.0 {
        return c;
    }
    let ndc = vec2<f32>(clip.x / clip.w, clip.y / clip.w);
    if abs(ndc.x) > 1.0 || abs(ndc.y) > 1.0 {
        return c;
    }
    let res = f32(m.resolution);
    c.inside = true;
    c.st = vec2<f32>((ndc.x * 0.5 + 0.5) * res, (0.5 - ndc.y * 0.5) * res);
    c.z = linear_depth(m, p2) - bias.depth * texel - slope;
    c.slope = slope;
    c.z_receiver = z;
    return c;
}
