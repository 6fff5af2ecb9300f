#define_import_path penumbra_limit::warp
#import soft_shadow_core::light_space::{MapView, NO_OCCLUDER, sphere_spread_at}

// Map depths of a penumbra limit map; mirrors warp.rs and the shared generation parameters,
// imported by the crate's other shaders.

struct Warp {
    ortho: u32,
    zeta_near: f32,
    zeta_scale: f32,
    unit: f32,
    rate: f32,
    p_per_texel: f32,
    far_norm: f32,
    spread: f32,
};

const DEPTH_SPAN: f32 = 0.99;
const NONE_DEPTH: f32 = 1.0;
const FRONT_DEPTH: f32 = -1.0;
const MAX_P: f32 = 2.0;

fn zeta(w: Warp, z: f32) -> f32 {
    if w.ortho == 1u {
        return z;
    }
    return -1.0 / z;
}

fn normalized(w: Warp, z: f32) -> f32 {
    if z >= NO_OCCLUDER {
        return NONE_DEPTH;
    }
    return min((zeta(w, z) - w.zeta_near) * w.zeta_scale, NONE_DEPTH);
}

// A receiver's biased depth: at or behind a perspective map's eye plane it is in front of
// everything (see Warp::receiver_depth in warp.rs).
fn receiver_depth(w: Warp, z: f32) -> f32 {
    if w.ortho == 0u && z <= 0.0 {
        return FRONT_DEPTH;
    }
    return max(normalized(w, z), FRONT_DEPTH);
}

fn linear(w: Warp, n: f32) -> f32 {
    let zt = n / w.zeta_scale + w.zeta_near;
    if w.ortho == 1u {
        return zt;
    }
    return -1.0 / zt;
}

fn depth_gap(w: Warp, z: f32, texels: f32) -> f32 {
    if w.ortho == 1u {
        return texels * w.unit * w.zeta_scale;
    }
    return texels * w.unit / max(z, 1.17549435e-38) * w.zeta_scale;
}

// Warp::spread_at.
fn spread_at(w: Warp, m: MapView, p: vec3<f32>) -> f32 {
    if w.spread > 1.0 {
        return min(sphere_spread_at(m, p), w.spread);
    }
    return 1.0;
}

fn ribbon_texels(w: Warp, c: f32) -> f32 {
    let depth = max(w.far_norm - c, 0.0) * w.spread;
    return min(depth / max(w.p_per_texel, 1.17549435e-38), 1.0e6) + 2.0;
}

fn has_edge(e: vec2<f32>) -> bool {
    return e.x < NONE_DEPTH;
}

// Generation parameters, laid out as `GenParams` in gpu.rs.
struct GenParams {
    map: MapView,
    warp: Warp,
    resolution: u32,
    layer_gap: f32,
    transition_gap: f32,
    _pad_a: f32,
};
