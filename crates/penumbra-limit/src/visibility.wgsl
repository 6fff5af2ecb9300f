#define_import_path penumbra_limit::visibility
#import soft_shadow_core::light_space::{Bias, MapView, bilinear_taps, shadow_coord}
#import penumbra_limit::warp::{DEPTH_SPAN, Warp, receiver_depth, spread_at}

// Evaluation as `visibility(world_pos, normal)`; mirrors penumbra_limit::eval: project the
// receiver, bilinear (c, g, p_i) and each tap's lower limit, equation 2, then the
// visibility-to-illumination table.

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

// The four taps around st and their bilinear weights.
struct Taps4 {
    a: vec4<f32>,
    b: vec4<f32>,
    c: vec4<f32>,
    d: vec4<f32>,
    w: vec4<f32>,
};

fn taps4(st: vec2<f32>) -> Taps4 {
    let taps = bilinear_taps(st);
    let f = taps.f;
    let x0 = taps.base.x;
    let y0 = taps.base.y;
    let w = vec4<f32>((1.0 - f.x) * (1.0 - f.y), f.x * (1.0 - f.y), (1.0 - f.x) * f.y, f.x * f.y);
    return Taps4(texel(x0, y0), texel(x0 + 1, y0), texel(x0, y0 + 1), texel(x0 + 1, y0 + 1), w);
}

fn sat(x: f32) -> f32 {
    return clamp(x, 0.0, 1.0);
}

// Below the lower limit inside the silhouette: the lower layer's inner penumbra (visibility()
// calls it only there; lower_shadow then limits both sides); see
// penumbra_limit::visibility::lower_visibility.
fn lower_visibility(z: f32, b: f32, p: f32) -> f32 {
    if z <= b {
        return 1.0;
    }
    if p < 0.0 {
        return sat(0.5 + 0.5 * p / max(z - b, 1.0e-30));
    }
    return 0.0;
}

// Equation 2 with the lower limit's visibility l_b given; see
// penumbra_limit::visibility::limited_visibility.
fn limited_visibility(z: f32, c: f32, g: f32, p: f32, l_b: f32) -> f32 {
    let l = sat(0.5 + 0.5 * p / max(z - c, 1.0e-30));
    let k = 4.0 * f32(z < g) - 2.0 * f32(z < c);
    return sat(min(l, l_b) + k);
}

fn lookup(l: f32) -> f32 {
    let n = prm.table_size;
    let s = clamp(l, 0.0, 1.0) * f32(n - 1u);
    let i = min(u32(floor(s)), n - 2u);
    let a = s - f32(i);
    return table[i] * (1.0 - a) + table[i + 1u] * a;
}

const LOWER_TAPS: u32 = 32u;

// (cos a, sin a, s) of each tap of lower_shadow's Vogel spiral, as the CPU computes them:
// penumbra_limit::eval::LOWER_SPIRAL, the same table.
var<private> LOWER_SPIRAL: array<vec3<f32>, 32> = array<vec3<f32>, 32>(
    vec3<f32>(1.0, 0.0, 0.125),
    vec3<f32>(-0.73736864, 0.67549056, 0.21650635),
    vec3<f32>(0.087425075, -0.9961711, 0.2795085),
    vec3<f32>(0.6084396, 0.79360014, 0.3307189),
    vec3<f32>(-0.98471373, -0.17418066, 0.375),
    vec3<f32>(0.84375465, -0.53672904, 0.4145781),
    vec3<f32>(-0.2596024, 0.9657156, 0.4506939),
    vec3<f32>(-0.4609095, -0.8874472, 0.48412293),
    vec3<f32>(0.9393222, 0.34303617, 0.5153882),
    vec3<f32>(-0.9243446, 0.3815587, 0.5448624),
    vec3<f32>(0.4238439, -0.90573525, 0.572822),
    vec3<f32>(0.29928777, 0.9541629, 0.59947896),
    vec3<f32>(-0.86521316, -0.50140417, 0.625),
    vec3<f32>(0.976675, -0.21472313, 0.649519),
    vec3<f32>(-0.5751249, 0.81806564, 0.6731456),
    vec3<f32>(-0.12851603, -0.99170744, 0.69597054),
    vec3<f32>(0.7646524, 0.644443, 0.7180703),
    vec3<f32>(-0.99914587, 0.041322917, 0.73951),
    vec3<f32>(0.70882595, -0.7053834, 0.76034534),
    vec3<f32>(-0.046186656, 0.99893284, 0.78062475),
    vec3<f32>(-0.64071274, -0.7677807, 0.80039054),
    vec3<f32>(0.9910705, 0.13333875, 0.8196798),
    vec3<f32>(-0.82085365, 0.57113856, 0.8385255),
    vec3<f32>(0.21947356, -0.9756184, 0.85695684),
    vec3<f32>(0.4971877, 0.867643, 0.875),
    vec3<f32>(-0.95269513, -0.30392763, 0.89267856),
    vec3<f32>(0.907788, -0.4194294, 0.91001374),
    vec3<f32>(-0.38605073, 0.92247754, 0.9270248),
    vec3<f32>(-0.3384627, -0.9409798, 0.9437293),
    vec3<f32>(0.88519454, 0.46522108, 0.9601432),
    vec3<f32>(-0.9669673, 0.2549006, 0.9762812),
    vec3<f32>(0.54082876, -0.8411327, 0.99215674),
);

// The soft shadow of the casters below the edge a receiver reads: the
// fraction of LOWER_TAPS taps on a Vogel spiral (LOWER_SPIRAL) over the disc of radius
// (z - b) / ppt texels whose texel holds no caster above z; see
// penumbra_limit::eval::lower_shadow.
fn lower_shadow(st: vec2<f32>, z: f32, b: f32, ppt: f32) -> f32 {
    let radius = clamp((z - b) / max(ppt, 1.17549435e-38), 1.0, f32(prm.map.resolution));
    var lit = 0u;
    for (var i = 0u; i < LOWER_TAPS; i = i + 1u) {
        let tap = LOWER_SPIRAL[i];
        let q = floor(st + tap.xy * (radius * tap.z));
        let t = texel(i32(q.x), i32(q.y));
        let depth = select(t.z, t.y, t.w < 0.0);
        lit = lit + u32(depth >= z);
    }
    return f32(lit) / f32(LOWER_TAPS);
}

fn visibility(p: vec3<f32>, n: vec3<f32>) -> f32 {
    let co = shadow_coord(prm.map, prm.bias, p, n);
    if !co.inside {
        return lookup(1.0);
    }
    let z = min(receiver_depth(prm.warp, co.z) - prm.tolerance, DEPTH_SPAN);
    let q = taps4(co.st);
    var t = q.a * q.w.x + q.b * q.w.y + q.c * q.w.z + q.d * q.w.w;
    // A sphere's penumbra is wider here than the ribbons' (Warp::spread_at).
    let spread = spread_at(prm.warp, prm.map, p);
    t.w /= spread;
    // Inside the silhouette: each tap's lower limit, weighted as the taps are.
    let inside = t.w < 0.0;
    var lower = 1.0;
    if inside {
        lower = q.w.x * lower_visibility(z, q.a.z, t.w) + q.w.y * lower_visibility(z, q.b.z, t.w)
            + q.w.z * lower_visibility(z, q.c.z, t.w) + q.w.w * lower_visibility(z, q.d.z, t.w);
    }
    // No more than the soft shadow of the casters below the edge that the taps (outside the
    // silhouette: those outside it) hold above the receiver (penumbra_limit::eval::shade).
    let edge = lookup(limited_visibility(z, t.x, t.y, t.w, lower));
    let o = q.w * vec4<f32>(
        select(0.0, 1.0, (inside || q.a.w >= 0.0) && q.a.z < z),
        select(0.0, 1.0, (inside || q.b.w >= 0.0) && q.b.z < z),
        select(0.0, 1.0, (inside || q.c.w >= 0.0) && q.c.z < z),
        select(0.0, 1.0, (inside || q.d.w >= 0.0) && q.d.z < z),
    );
    let s = o.x + o.y + o.z + o.w;
    if s > 0.0 && z >= t.y && edge > 0.0 {
        let b = dot(o, vec4<f32>(q.a.z, q.b.z, q.c.z, q.d.z)) / s;
        return min(edge, lower_shadow(co.st, z, b, prm.warp.p_per_texel / spread));
    }
    return edge;
}
