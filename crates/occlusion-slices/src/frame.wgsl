#define_import_path occlusion_slices::frame
#import soft_shadow_core::light_space::sphere_spread

// The slicing frame (frame.rs): COP view, light axes, slice planes, imported by the crate's
// other shaders.

struct Frame {
    view_proj: mat4x4<f32>,
    center: vec4<f32>,
    axis_x: vec4<f32>,
    axis_y: vec4<f32>,
    normal: vec4<f32>,
    half_x: f32,
    half_y: f32,
    d: f32,
    near: f32,
    spacing: f32,
    slices: u32,
    resolution: u32,
    occupied: u32,
    clip_near: f32,
    clip_far: f32,
    thin_fix: u32,
    fade_texels: f32,
};

const SLICE_TOLERANCE: f32 = 1e-3;

// Frame::slice_of: the slice of a fragment at COP view depth z.
fn slice_of(f: Frame, z: f32) -> u32 {
    let h = z - f.d;
    let k = ceil((h - f.near) / f.spacing - SLICE_TOLERANCE);
    return u32(clamp(k, 0.0, f32(f.slices - 1u)));
}

// Frame::plane.
fn plane(f: Frame, k: u32) -> f32 {
    return f.near + f32(k) * f.spacing;
}

const TOP_STEPS: f32 = 254.0;

// Frame::top_code: 255 at slice k's upper plane down to 1 at its lower plane.
fn top_code(f: Frame, k: u32, h: f32) -> u32 {
    let u = clamp((h - (plane(f, k) - f.spacing)) / f.spacing, 0.0, 1.0);
    return 255u - u32(ceil(u * TOP_STEPS));
}

// Frame::top_depth.
fn top_depth(f: Frame, k: u32, code: u32) -> f32 {
    return plane(f, k) - f.spacing + f32(255u - code) / TOP_STEPS * f.spacing;
}

// Frame::fade, with len = fade_length(f, h).
fn fade(f: Frame, k: u32, h: f32, len: f32) -> f32 {
    let beyond = h - plane(f, k);
    if len > 0.0 {
        return clamp(beyond / len, 0.0, 1.0);
    }
    return select(0.0, 1.0, beyond > 0.0);
}

// Frame::fade_length.
fn fade_length(f: Frame, h: f32) -> f32 {
    return min(f.spacing, f.fade_texels * texel_size(f, max(h, 0.0)));
}

// Frame::texel_point: the point at depth h the COP projects to texel position t.
fn texel_point(f: Frame, t: vec2<f32>, h: f32) -> vec3<f32> {
    let resolution = f32(f.resolution);
    let scale = 2.0 * (f.d + h) / f.d;
    return vec3<f32>((t.x / resolution - 0.5) * scale * f.half_x, (0.5 - t.y / resolution) * scale * f.half_y, h);
}

// Frame::texel_size.
fn texel_size(f: Frame, h: f32) -> f32 {
    return 2.0 * f.half_x * (f.d + h) / (f.d * f32(f.resolution));
}

// Frame::direction: a world direction in light coordinates.
fn direction(f: Frame, v: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(dot(v, f.axis_x.xyz), dot(v, f.axis_y.xyz), dot(v, f.normal.xyz));
}

// Frame::light_coord: (x, y, h).
fn light_coord(f: Frame, p: vec3<f32>) -> vec3<f32> {
    return direction(f, p - f.center.xyz);
}

struct Kernel {
    center: vec2<f32>,
    size: f32,
};

// Frame::spread.
fn spread(f: Frame, c: vec3<f32>) -> f32 {
    let l = length(c);
    if f.normal.w == 1.0 && l > 0.0 {
        return sphere_spread(c.z / l);
    }
    return 1.0;
}

// Frame::kernel: the pyramid from c to the light cut by plane depth p, in texels, widened by
// the receiver's spread.
fn kernel(f: Frame, c: vec3<f32>, p: f32, widen: f32) -> Kernel {
    let along = p / c.z;
    let z = f.d + p;
    let resolution = f32(f.resolution);
    let sx = f.d / (f.half_x * z);
    let sy = f.d / (f.half_y * z);
    var k: Kernel;
    k.center = vec2<f32>((c.x * along * sx * 0.5 + 0.5) * resolution, (0.5 - c.y * along * sy * 0.5) * resolution);
    k.size = (1.0 - along) * f.d / z * resolution * widen;
    return k;
}
