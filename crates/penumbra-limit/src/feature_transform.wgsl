#define_import_path penumbra_limit::feature_transform
#import soft_shadow_core::seeds::{NONE_SEED, seed_pack}

// The exact nearest-seed map (feature transform) on the GPU. Mirrors
// penumbra_limit::feature_transform (feature_transform.rs) step by step, in the same integer arithmetic, so both backends
// give the same seeds.
//
// Of equally near seeds, the one of least key (`keys`, one f32 per texel, where `prm.keyed`),
// then the leftmost, then the uppermost.
//
// `ft_columns`: one invocation per column, from the seeds in `a` to the row of the nearest seed
// of the column in `b` (NO_ROW: none). `ft_rows`: one invocation per row, the lower envelope of
// the parabolas (x - i)^2 + g(i)^2 over the row's columns in `b`, kept as a stack in the row's
// own texels of `a` (column | start << 16), then overwritten by the result from right to left:
// entry k starts at or after texel k, so an entry is read before its texel is written.
//
// The i32 arithmetic is exact: on a map up to 32768 texels a side, every f and every numerator
// of Sep is at most 2 * 32767^2 < 2^31 in magnitude (the CPU computes in i64).

struct FtParams {
    resolution: u32,
    keyed: u32,
    _pad_b: u32,
    _pad_c: u32,
};

@group(0) @binding(0) var<uniform> prm: FtParams;
@group(0) @binding(1) var<storage, read_write> a: array<u32>;
@group(0) @binding(2) var<storage, read_write> b: array<u32>;
@group(0) @binding(3) var<storage, read> keys: array<f32>;

const NO_ROW: u32 = 0xffffffffu;

// Whether the seed at column x, row r has a lesser key than the one at column y, row s.
fn ft_less(x: u32, r: u32, y: u32, s: u32) -> bool {
    if prm.keyed == 0u {
        return false;
    }
    return keys[r * prm.resolution + x] < keys[s * prm.resolution + y];
}

@compute @workgroup_size(64)
fn ft_columns(@builtin(global_invocation_id) gid: vec3<u32>) {
    let x = gid.x;
    let r = prm.resolution;
    if x >= r {
        return;
    }
    // Downwards: the nearest seed at or above.
    var above = NO_ROW;
    for (var y = 0u; y < r; y++) {
        let i = y * r + x;
        if a[i] != NONE_SEED {
            above = y;
        }
        b[i] = above;
    }
    // Upwards: the nearest seed below replaces the one above where nearer, or as near with a
    // lesser key.
    var below = NO_ROW;
    for (var yy = 0u; yy < r; yy++) {
        let y = r - 1u - yy;
        let i = y * r + x;
        if a[i] != NONE_SEED {
            below = y;
        }
        if below == NO_ROW {
            continue;
        }
        let o = b[i];
        var up = 0xffffffffu;
        if o != NO_ROW {
            up = y - o;
        }
        let down = below - y;
        if down < up || (down == up && ft_less(x, below, x, o)) {
            b[i] = below;
        }
    }
}

// g(i)^2 of row y: the squared distance to the nearest seed of column i (which has one).
fn ft_g2(base: u32, y: u32, i: u32) -> i32 {
    let g = i32(b[base + i]) - i32(y);
    return g * g;
}

// (x - i)^2 + g(i)^2.
fn ft_f(base: u32, y: u32, x: u32, i: u32) -> i32 {
    let d = i32(x) - i32(i);
    return d * d + ft_g2(base, y, i);
}

// floor(n / d) for d > 0 (WGSL's division truncates).
fn ft_floor_div(n: i32, d: i32) -> i32 {
    let q = n / d;
    if n % d != 0 && n < 0 {
        return q - 1;
    }
    return q;
}

@compute @workgroup_size(64)
fn ft_rows(@builtin(global_invocation_id) gid: vec3<u32>) {
    let y = gid.x;
    let r = prm.resolution;
    if y >= r {
        return;
    }
    let base = y * r;
    // Index of the stack's last entry; -1: empty.
    var top = -1;
    for (var u = 0u; u < r; u++) {
        if b[base + u] == NO_ROW {
            continue;
        }
        // Drop the parabolas that `u` lies below where they begin (or on, with a lesser key).
        loop {
            if top < 0 {
                break;
            }
            let e = a[base + u32(top)];
            let i = e & 0xffffu;
            let fi = ft_f(base, y, e >> 16u, i);
            let fu = ft_f(base, y, e >> 16u, u);
            if fi > fu || (fi == fu && ft_less(u, b[base + u], i, b[base + i])) {
                top -= 1;
            } else {
                break;
            }
        }
        if top < 0 {
            top = 0;
            a[base] = u;
        } else {
            // Meijster's Sep(i, u): the last texel where `i`'s parabola is at most `u`'s; `u`
            // takes it too on a tie with the lesser key.
            let i = a[base + u32(top)] & 0xffffu;
            let n = i32(u * u) - i32(i * i) + ft_g2(base, y, u) - ft_g2(base, y, i);
            let d = 2 * (i32(u) - i32(i));
            let sep = ft_floor_div(n, d);
            // The parabolas meet on texel `sep` exactly when the division leaves nothing.
            var start = sep + 1;
            if n % d == 0 && ft_less(u, b[base + u], i, b[base + i]) {
                start = sep;
            }
            if start < i32(r) {
                top += 1;
                a[base + u32(top)] = u | (u32(start) << 16u);
            }
        }
    }
    if top < 0 {
        for (var x = 0u; x < r; x++) {
            a[base + x] = NONE_SEED;
        }
        return;
    }
    var e = a[base + u32(top)];
    for (var xx = 0u; xx < r; xx++) {
        let x = r - 1u - xx;
        let i = e & 0xffffu;
        a[base + x] = seed_pack(i, b[base + i]);
        if x == e >> 16u && top > 0 {
            top -= 1;
            e = a[base + u32(top)];
        }
    }
}
