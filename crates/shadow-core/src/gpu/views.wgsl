#define_import_path soft_shadow_core::views

// How a receiver picks the view of a light whose shadow is a set of views (cube faces,
// cascades): laid out as `ViewSelect` in `views.rs`, whose `ViewSelect::weight` and
// `ViewSelect::total` are these functions in Rust.

struct ViewSelect {
    // The camera's depth row (cascades).
    depth_row: vec4<f32>,
    // The light's centre (cube faces).
    center: vec4<f32>,
    // The cube's basis (cube faces).
    basis: array<vec4<f32>, 3>,
    // Split depths: cascade i lies between splits[i] and splits[i + 1].
    splits: array<vec4<f32>, 2>,
    // The view of each cube face (2 k: +basis[k], 2 k + 1: -basis[k]), -1 where none.
    face_view: array<vec4<i32>, 2>,
    // 0: one view, 1: cube faces, 2: cascades.
    kind: u32,
    // The view this pass evaluates.
    index: u32,
    // How many views.
    count: u32,
    // Cascades: the share of a cascade's depth range that blends into the next; cube faces: the
    // share of the largest component within which a second face blends in.
    blend: f32,
}

fn split_at(s: ViewSelect, i: u32) -> f32 {
    return s.splits[i / 4u][i % 4u];
}

// The share of the cube face on axis k's side in p's direction (see `ViewSelect::faces`): 1
// inside a face, shared towards a seam, half and half on it.
fn face_share(s: ViewSelect, p: vec3<f32>, k: u32) -> f32 {
    let d = p - s.center.xyz;
    let c = vec3<f32>(dot(d, s.basis[0].xyz), dot(d, s.basis[1].xyz), dot(d, s.basis[2].xyz));
    let m = max(max(max(abs(c.x), abs(c.y)), abs(c.z)), 1e-30);
    let b = s.blend;
    let sh = clamp((abs(c) / m - vec3<f32>(1.0 - b)) / b, vec3<f32>(0.0), vec3<f32>(1.0));
    // At the light's centre no direction: no face (V is 1 there).
    return sh[k] / max(sh.x + sh.y + sh.z, 1e-30);
}

// The view of the cube face on axis k's side of p's direction, -1 where none.
fn face_view(s: ViewSelect, p: vec3<f32>, k: u32) -> i32 {
    let d = p - s.center.xyz;
    var f = 2u * k;
    if dot(d, s.basis[k].xyz) < 0.0 {
        f = f + 1u;
    }
    return s.face_view[f / 4u][f % 4u];
}

// Weight of view s.index at p.
fn view_weight(s: ViewSelect, p: vec3<f32>) -> f32 {
    if s.kind == 1u {
        var w = 0.0;
        for (var k = 0u; k < 3u; k = k + 1u) {
            if face_view(s, p, k) == i32(s.index) {
                w = w + face_share(s, p, k);
            }
        }
        return w;
    }
    if s.kind == 2u {
        let z = dot(s.depth_row, vec4<f32>(p, 1.0));
        let n = s.count;
        var i = 0u;
        while i + 1u < n && z >= split_at(s, i + 1u) {
            i = i + 1u;
        }
        var wi = 1.0;
        var wn = 0.0;
        if i + 1u < n {
            let band = s.blend * (split_at(s, i + 1u) - split_at(s, i));
            let start = split_at(s, i + 1u) - band;
            if z > start && band > 0.0 {
                wn = min((z - start) / band, 1.0);
                wi = 1.0 - wn;
            }
        }
        if s.index == i {
            return wi;
        }
        if s.index == i + 1u {
            return wn;
        }
        return 0.0;
    }
    return select(0.0, 1.0, s.index == 0u);
}

// The views' total weight at p: less than 1 only in a cube direction whose face holds no caster.
fn views_weight(s: ViewSelect, p: vec3<f32>) -> f32 {
    if s.kind == 1u {
        var w = 0.0;
        for (var k = 0u; k < 3u; k = k + 1u) {
            if face_view(s, p, k) >= 0 {
                w = w + face_share(s, p, k);
            }
        }
        return w;
    }
    return 1.0;
}
