#define_import_path shadow_width::jump_flood
#import soft_shadow_core::seeds::{NONE_SEED, seed_dist2}

// Jump flooding on the GPU: one pass with step `k`. Mirrors jump_flood.rs (`pass`), in the
// same neighbour order, so both backends keep the same nearest seed.

struct FloodParams {
    resolution: u32,
    step: u32,
    _pad_a: u32,
    _pad_b: u32,
};

@group(0) @binding(0) var<uniform> prm: FloodParams;
@group(0) @binding(1) var<storage, read> src: array<u32>;
@group(0) @binding(2) var<storage, read_write> dst: array<u32>;


@compute @workgroup_size(8, 8)
fn jfa_step(@builtin(global_invocation_id) gid: vec3<u32>) {
    if gid.x >= prm.resolution || gid.y >= prm.resolution {
        return;
    }
    let r = i32(prm.resolution);
    let k = i32(prm.step);
    let x = i32(gid.x);
    let y = i32(gid.y);
    let i = y * r + x;
    var best = src[i];
    var best_d = 0x7fffffff;
    if best != NONE_SEED {
        best_d = seed_dist2(x, y, best);
    }
    for (var dy = -1; dy <= 1; dy++) {
        for (var dx = -1; dx <= 1; dx++) {
            let qx = x + dx * k;
            let qy = y + dy * k;
            if qx < 0 || qy < 0 || qx >= r || qy >= r {
                continue;
            }
            let s = src[qy * r + qx];
            if s != NONE_SEED {
                let d = seed_dist2(x, y, s);
                if d < best_d {
                    best = s;
                    best_d = d;
                }
            }
        }
    }
    dst[i] = best;
}
