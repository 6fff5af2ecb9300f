#define_import_path shadow_width::width
#import soft_shadow_core::light_space::{MapView, NO_OCCLUDER, linear_from_ndc}
#import soft_shadow_core::seeds::{NONE_SEED, seed_dist2, seed_pack}

// Shadow-width maps on the GPU (Kirsch & Döllner 2003, section 4, and two exact/fast
// alternatives). Mirrors shadow_width::occlusion and shadow_width::width::{propagate, jfa, edt}.

struct WidthParams {
    map: MapView,
    resolution: u32,
    step: u32,
    neighbours: u32,
    cap: f32,
    // Propagation offsets of this pass: (dx, dy, distance added, unused), `neighbours` of them
    // (shadow_width::width::propagate::offsets).
    offsets: array<vec4<f32>, 8>,
};

@group(0) @binding(0) var<uniform> prm: WidthParams;
@group(0) @binding(1) var depth: texture_depth_2d_array;
@group(0) @binding(2) var<storage, read> fsrc: array<f32>;
@group(0) @binding(3) var<storage, read_write> fdst: array<f32>;
@group(0) @binding(4) var<storage, read> usrc: array<u32>;
@group(0) @binding(5) var<storage, read_write> udst: array<u32>;
@group(0) @binding(6) var<storage, read_write> env_v: array<u32>;
@group(0) @binding(7) var<storage, read_write> env_z: array<f32>;

const UNREACHED: f32 = 1.0e9;

fn texel_index(gid: vec3<u32>) -> i32 {
    if gid.x >= prm.resolution || gid.y >= prm.resolution {
        return -1;
    }
    return i32(gid.y * prm.resolution + gid.x);
}

// Inverted occlusion map: UNREACHED where a caster covers the texel, else 0 (see occlusion.rs).
@compute @workgroup_size(8, 8)
fn mask(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = texel_index(gid);
    if i < 0 {
        return;
    }
    let xy = vec2<i32>(gid.xy);
    let blocked = linear_from_ndc(prm.map, textureLoad(depth, xy, 0, 0)) != NO_OCCLUDER;
    fdst[i] = select(0.0, UNREACHED, blocked);
}

// One propagation pass over prm.neighbours offsets (prm.offsets).
@compute @workgroup_size(8, 8)
fn propagate(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = texel_index(gid);
    if i < 0 {
        return;
    }
    let r = i32(prm.resolution);
    let x = i32(gid.x);
    let y = i32(gid.y);
    var w = fsrc[i];
    for (var k = 0u; k < prm.neighbours; k++) {
        let o = prm.offsets[k];
        let qx = x + i32(o.x);
        let qy = y + i32(o.y);
        if qx >= 0 && qy >= 0 && qx < r && qy < r {
            w = min(w, fsrc[qy * r + qx] + o.z);
        }
    }
    fdst[i] = w;
}

@compute @workgroup_size(8, 8)
fn cap_width(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = texel_index(gid);
    if i < 0 {
        return;
    }
    fdst[i] = min(fsrc[i], prm.cap);
}

// Jump flooding: seeds are the unblocked texels.
@compute @workgroup_size(8, 8)
fn jfa_init(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = texel_index(gid);
    if i < 0 {
        return;
    }
    udst[i] = select(NONE_SEED, seed_pack(gid.x, gid.y), fsrc[i] == 0.0);
}

// (The flood itself is soft_shadow_core's gpu/jump_flood.wgsl.)
@compute @workgroup_size(8, 8)
fn jfa_resolve(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = texel_index(gid);
    if i < 0 {
        return;
    }
    let s = usrc[i];
    if s == NONE_SEED {
        fdst[i] = prm.cap;
    } else {
        fdst[i] = min(sqrt(f32(seed_dist2(i32(gid.x), i32(gid.y), s))), prm.cap);
    }
}

// Exact EDT, pass 1: per column, the distance to the nearest unblocked texel (-1: none).
@compute @workgroup_size(64)
fn edt_columns(@builtin(global_invocation_id) gid: vec3<u32>) {
    let x = gid.x;
    let r = prm.resolution;
    if x >= r {
        return;
    }
    var last = -1.0;
    for (var y = 0u; y < r; y++) {
        let i = y * r + x;
        if fsrc[i] == 0.0 {
            last = 0.0;
        } else if last >= 0.0 {
            last = last + 1.0;
        }
        fdst[i] = last;
    }
    var next = -1.0;
    for (var yy = 0u; yy < r; yy++) {
        let y = r - 1u - yy;
        let i = y * r + x;
        if fsrc[i] == 0.0 {
            next = 0.0;
        } else if next >= 0.0 {
            next = next + 1.0;
        }
        let g = fdst[i];
        if next >= 0.0 && (g < 0.0 || next < g) {
            fdst[i] = next;
        }
    }
}

// Exact EDT, pass 2: per row, the lower envelope of the parabolas (x - q)^2 + g(q)^2.
@compute @workgroup_size(64)
fn edt_rows(@builtin(global_invocation_id) gid: vec3<u32>) {
    let y = gid.x;
    let r = prm.resolution;
    if y >= r {
        return;
    }
    let base = y * r;
    let zb = y * (r + 1u);
    var k = -1;
    for (var q = 0u; q < r; q++) {
        let gq = fsrc[base + q];
        if gq < 0.0 {
            continue;
        }
        let fq = gq * gq + f32(q * q);
        loop {
            if k < 0 {
                k = 0;
                env_v[base] = q;
                env_z[zb] = -3.0e38;
                break;
            }
            let p = env_v[base + u32(k)];
            let gp = fsrc[base + p];
            let fp = gp * gp + f32(p * p);
            let s = (fq - fp) / (2.0 * (f32(q) - f32(p)));
            if s <= env_z[zb + u32(k)] && k > 0 {
                k -= 1;
                continue;
            }
            k += 1;
            env_v[base + u32(k)] = q;
            env_z[zb + u32(k)] = s;
            break;
        }
    }
    if k < 0 {
        for (var x = 0u; x < r; x++) {
            fdst[base + x] = prm.cap;
        }
        return;
    }
    var j = 0;
    for (var x = 0u; x < r; x++) {
        while j < k && env_z[zb + u32(j + 1)] < f32(x) {
            j += 1;
        }
        let q = env_v[base + u32(j)];
        let g = fsrc[base + q];
        let d = f32(x) - f32(q);
        fdst[base + x] = min(sqrt(d * d + g * g), prm.cap);
    }
}
