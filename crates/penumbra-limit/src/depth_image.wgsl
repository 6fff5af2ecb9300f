#define_import_path penumbra_limit::depth_image
#import soft_shadow_core::light_space::{linear_from_ndc}
#import penumbra_limit::warp::{GenParams, MAX_P, NONE_DEPTH, depth_gap, linear, normalized, ribbon_texels}
#import soft_shadow_core::seeds::{NONE_SEED, seed_dist2, seed_pack}

// Generation from a depth image; mirrors penumbra_limit::depth_image (and the geometry layer of
// both generators): `geometry` normalises the nearest-surface depth map, `seeds` marks the near
// and far sides of depth discontinuities, the exact nearest-seed map (soft_shadow_core's
// feature_transform.wgsl) spreads them, `limits` writes each texel's edge (c, p_i) and lower
// limit.

@group(0) @binding(0) var<uniform> gp: GenParams;
@group(0) @binding(1) var depth: texture_depth_2d_array;
@group(0) @binding(2) var<storage, read_write> geom: array<f32>;
@group(0) @binding(3) var<storage, read_write> near_seeds: array<u32>;
@group(0) @binding(4) var<storage, read_write> far_seeds: array<u32>;
@group(0) @binding(5) var edge_out: texture_storage_2d<rg32float, write>;
@group(0) @binding(6) var lower_out: texture_storage_2d<r32float, write>;


fn index(x: i32, y: i32) -> u32 {
    return u32(y) * gp.resolution + u32(x);
}

fn geom_clamped(x: i32, y: i32) -> f32 {
    let r = i32(gp.resolution) - 1;
    return geom[index(clamp(x, 0, r), clamp(y, 0, r))];
}

@compute @workgroup_size(8, 8)
fn geometry(@builtin(global_invocation_id) gid: vec3<u32>) {
    if gid.x >= gp.resolution || gid.y >= gp.resolution {
        return;
    }
    let z = linear_from_ndc(gp.map, textureLoad(depth, vec2<i32>(gid.xy), 0, 0));
    geom[gid.y * gp.resolution + gid.x] = normalized(gp.warp, z);
}

fn near_side(x: i32, y: i32, d: vec2<i32>) -> bool {
    let r = i32(gp.resolution);
    let n = vec2<i32>(x, y) + d;
    if x < 0 || y < 0 || x >= r || y >= r || n.x < 0 || n.y < 0 || n.x >= r || n.y >= r {
        return false;
    }
    let dt = geom[index(x, y)];
    if dt >= NONE_DEPTH {
        return false;
    }
    let dn = geom[index(n.x, n.y)];
    let back = geom_clamped(x - d.x, y - d.y);
    var slope = 0.0;
    if back < NONE_DEPTH {
        slope = abs(dt - back);
    }
    return dn - dt > depth_gap(gp.warp, linear(gp.warp, dt), gp.layer_gap) + 2.0 * slope;
}

const NEIGHBOURS: array<vec2<i32>, 4> = array<vec2<i32>, 4>(
    vec2<i32>(-1, 0), vec2<i32>(1, 0), vec2<i32>(0, -1), vec2<i32>(0, 1));

@compute @workgroup_size(8, 8)
fn seeds(@builtin(global_invocation_id) gid: vec3<u32>) {
    if gid.x >= gp.resolution || gid.y >= gp.resolution {
        return;
    }
    let x = i32(gid.x);
    let y = i32(gid.y);
    var a = false;
    var b = false;
    for (var i = 0; i < 4; i++) {
        let d = NEIGHBOURS[i];
        a = a || near_side(x, y, d);
        b = b || near_side(x + d.x, y + d.y, -d);
    }
    let me = seed_pack(gid.x, gid.y);
    near_seeds[index(x, y)] = select(NONE_SEED, me, a);
    far_seeds[index(x, y)] = select(NONE_SEED, me, b);
}

fn seed_distance(x: i32, y: i32, s: u32) -> f32 {
    return sqrt(f32(seed_dist2(x, y, s)));
}

@compute @workgroup_size(8, 8)
fn limits(@builtin(global_invocation_id) gid: vec3<u32>) {
    if gid.x >= gp.resolution || gid.y >= gp.resolution {
        return;
    }
    let x = i32(gid.x);
    let y = i32(gid.y);
    let a = near_seeds[index(x, y)];
    let b = far_seeds[index(x, y)];
    var edge = vec2<f32>(NONE_DEPTH, MAX_P);
    var lower = NONE_DEPTH;
    if a != NONE_SEED && b != NONE_SEED {
        let da = seed_distance(x, y, a);
        let db = seed_distance(x, y, b);
        var w = da - 0.5;
        if da < db {
            w = -(db - 0.5);
        }
        let c = geom[index(i32(a & 0xffffu), i32(a >> 16u))];
        if abs(w) <= ribbon_texels(gp.warp, c) {
            edge = vec2<f32>(c, clamp(w * gp.warp.p_per_texel, -MAX_P, MAX_P));
            let d = geom[index(x, y)];
            let far_d = geom[index(i32(b & 0xffffu), i32(b >> 16u))];
            let gap_c = depth_gap(gp.warp, linear(gp.warp, c), gp.layer_gap);
            if d < NONE_DEPTH && d > c + gap_c {
                lower = min(d + depth_gap(gp.warp, linear(gp.warp, d), gp.layer_gap), NONE_DEPTH);
            } else if w < 0.0 && far_d < NONE_DEPTH && far_d > c + gap_c {
                // Inside an edge whose far side is geometry too: what lies below that far
                // surface is hidden by it as well.
                lower = min(
                    far_d + depth_gap(gp.warp, linear(gp.warp, far_d), gp.layer_gap),
                    NONE_DEPTH,
                );
            }
        }
    }
    textureStore(edge_out, vec2<i32>(x, y), vec4<f32>(edge, 0.0, 0.0));
    textureStore(lower_out, vec2<i32>(x, y), vec4<f32>(lower, 0.0, 0.0, 0.0));
}
