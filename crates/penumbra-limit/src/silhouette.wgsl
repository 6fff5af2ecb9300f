#define_import_path penumbra_limit::silhouette
#import soft_shadow_core::light_space::{linear_depth}
#import penumbra_limit::warp::{GenParams, MAX_P, NONE_DEPTH, depth_gap, has_edge, linear, normalized, ribbon_texels}

// Silhouette extrusion (section 3.1), steps 2 and 3; mirrors penumbra_limit::silhouette.
// Step 2 pulls each edge from a storage buffer, 12 vertices per edge (inner strip, then the
// outer strip, each with its caps), degenerate when the edge is no silhouette or a fold inside
// the caster's outline; the fragment computes
// (key, c, p_i) from the distance to the edge segment and the strip's sign and writes key as its depth, so the depth
// test (Less, cleared to 1) keeps the highest penumbra limit. Step 3 renders back faces, keeping
// those deeper than the texel's edge by more than layer_gap texels; nearest wins (reversed Z).

struct Edge {
    a: vec4<f32>,
    b: vec4<f32>,
    o0: vec4<f32>,
    o1: vec4<f32>,
    n0: vec4<f32>,
    n1: vec4<f32>,
};

@group(0) @binding(0) var<uniform> gp: GenParams;
@group(0) @binding(1) var<storage, read> edges: array<Edge>;
@group(0) @binding(2) var edge_tex: texture_2d<f32>;
// Step 1's geometry depths (NONE_DEPTH where no caster).
@group(0) @binding(3) var<storage, read> geom: array<f32>;

struct Projected {
    ok: bool,
    q: vec2<f32>,
};

fn project(p: vec3<f32>) -> Projected {
    var r: Projected;
    let clip = gp.map.view_proj * vec4<f32>(p, 1.0);
    r.ok = clip.w > 0.0;
    let resolution = f32(gp.map.resolution);
    r.q = vec2<f32>((clip.x / clip.w * 0.5 + 0.5) * resolution, (0.5 - clip.y / clip.w * 0.5) * resolution);
    return r;
}

fn faces_light(n: vec3<f32>, p: vec3<f32>) -> bool {
    var to_light = gp.map.light.xyz;
    if gp.map.light.w == 1.0 {
        to_light = gp.map.light.xyz - p;
    }
    return dot(n, to_light) > 0.0;
}

const MIN_FACE_TEXELS: f32 = 1.0e-3;

// Texels of depth within which a caster lies on the plane of an edge's lit face (SAME_DEPTH).
const SAME_DEPTH: f32 = 0.25;

// Texels outside an edge at which is_outline reads the geometry (OUTLINE_PROBE).
const OUTLINE_PROBE: f32 = 1.5;

// The geometry depth of the texel under `q` (texel coordinates); NONE_DEPTH outside the map.
fn geom_at(q: vec2<f32>) -> f32 {
    let r = f32(gp.resolution);
    if !(q.x >= 0.0 && q.y >= 0.0 && q.x < r && q.y < r) {
        return NONE_DEPTH;
    }
    return geom[u32(q.y) * gp.resolution + u32(q.x)];
}

// Whether the map holds no caster `OUTLINE_PROBE` texels outside `q` along `o`, or one deeper
// than `c` by more than the transition gap (Ribbon::is_outline, one probe).
fn beyond(q: vec2<f32>, o: vec2<f32>, c: f32) -> bool {
    let g = geom_at(q + o * OUTLINE_PROBE);
    return g >= NONE_DEPTH || g > c + depth_gap(gp.warp, linear(gp.warp, c), gp.transition_gap);
}

// Signed distance (texels) of the projected vertex `o` from the edge's line; 0 behind the light.
fn side(o: vec3<f32>, sa: vec2<f32>, d: vec2<f32>, len: f32) -> f32 {
    let po = project(o);
    if !po.ok {
        return 0.0;
    }
    let w = po.q - sa;
    return (d.x * w.y - d.y * w.x) / len;
}

struct RibbonVarying {
    @builtin(position) pos: vec4<f32>,
    @location(0) @interpolate(flat) a: vec2<f32>,
    @location(1) @interpolate(flat) b: vec2<f32>,
    @location(2) @interpolate(flat) c: vec2<f32>,
    @location(3) @interpolate(flat) sign: f32,
    // Ribbon::grad: the normalised depth's change per texel on the lit face's plane.
    @location(4) @interpolate(flat) grad: vec2<f32>,
    // Ribbon::same: SAME_DEPTH at the ribbon's deeper end, normalised.
    @location(5) @interpolate(flat) same: f32,
};

const KEY_SCALE: f32 = 1.0 / (1.0 + MAX_P);

const CORNERS: array<u32, 6> = array<u32, 6>(0u, 1u, 2u, 0u, 2u, 3u);

@vertex
fn vs_ribbon(@builtin(vertex_index) vi: u32) -> RibbonVarying {
    var v: RibbonVarying;
    v.pos = vec4<f32>(2.0, 2.0, 2.0, 1.0);
    let e = edges[vi / 12u];
    let k = vi % 12u;
    let a = e.a.xyz;
    let b = e.b.xyz;
    let border = e.o1.w == 0.0;
    if !border && faces_light(e.n0.xyz, a) == faces_light(e.n1.xyz, a) {
        return v;
    }
    let pa = project(a);
    let pb = project(b);
    if !(pa.ok && pb.ok) {
        return v;
    }
    let sa = pa.q;
    let sb = pb.q;
    let d = sb - sa;
    let len = length(d);
    if !(len > 1e-6) {
        return v;
    }
    let s0 = side(e.o0.xyz, sa, d, len);
    var s1 = 0.0;
    if !border {
        s1 = side(e.o1.xyz, sa, d, len);
    }
    let s = select(s1, s0, abs(s0) >= abs(s1));
    if !(abs(s) > MIN_FACE_TEXELS) {
        return v;
    }
    var o = vec2<f32>(-d.y, d.x) / len;
    if s > 0.0 {
        o = -o;
    }
    let ca = normalized(gp.warp, linear_depth(gp.map, a));
    let cb = normalized(gp.warp, linear_depth(gp.map, b));
    let cap = 2.0 * f32(gp.map.resolution);
    // The lit face's plane (face 0 of a border), as Ribbon::grad; zero where it is edge-on.
    var lit = e.o1.xyz;
    if border || faces_light(e.n0.xyz, a) {
        lit = e.o0.xyz;
    }
    var grad = vec2<f32>(0.0);
    let pl = project(lit);
    if pl.ok {
        let w = pl.q - sa;
        let det = d.x * w.y - d.y * w.x;
        if abs(det) > MIN_FACE_TEXELS * len {
            let dc = cb - ca;
            let dw = normalized(gp.warp, linear_depth(gp.map, lit)) - ca;
            grad = vec2<f32>(dc * w.y - d.y * dw, d.x * dw - dc * w.x) / det;
        }
    }
    let ha = min(ribbon_texels(gp.warp, ca), cap);
    let hb = min(ribbon_texels(gp.warp, cb), cap);
    // A fold inside the caster's outline (its outside covered at its depth or nearer): no ribbon.
    if !(beyond(sa, o, ca) || beyond((sa + sb) * 0.5, o, (ca + cb) * 0.5) || beyond(sb, o, cb)) {
        return v;
    }
    let t = d / len;
    var quad: array<vec2<f32>, 4>;
    if k < 6u {
        quad = array<vec2<f32>, 4>(sa - t * ha, sb + t * hb, sb + t * hb - o * hb, sa - t * ha - o * ha);
    } else {
        quad = array<vec2<f32>, 4>(sa - t * ha, sb + t * hb, sb + t * hb + o * hb, sa - t * ha + o * ha);
    }
    let q = quad[CORNERS[k % 6u]];
    let resolution = f32(gp.map.resolution);
    v.pos = vec4<f32>(q.x / resolution * 2.0 - 1.0, 1.0 - q.y / resolution * 2.0, 0.5, 1.0);
    v.a = sa;
    v.b = sb;
    v.c = vec2<f32>(ca, cb);
    v.sign = select(1.0, -1.0, k < 6u);
    v.grad = grad;
    v.same = min(
        depth_gap(gp.warp, linear(gp.warp, ca), SAME_DEPTH),
        depth_gap(gp.warp, linear(gp.warp, cb), SAME_DEPTH),
    );
    return v;
}

struct RibbonFragment {
    @location(0) edge: vec2<f32>,
    @builtin(frag_depth) key: f32,
};

@fragment
fn fs_ribbon(v: RibbonVarying) -> RibbonFragment {
    let q = v.pos.xy;
    let d = v.b - v.a;
    let t = clamp(dot(q - v.a, d) / dot(d, d), 0.0, 1.0);
    let dist = length(q - (v.a + d * t));
    let c = v.c.x + (v.c.y - v.c.x) * t;
    let p = clamp(v.sign * dist * gp.warp.p_per_texel, -MAX_P, MAX_P);
    // An inner fragment lands only over a caster (past a corner, an inner strip's cap is outside).
    if v.sign < 0.0 && geom[u32(q.y) * gp.resolution + u32(q.x)] >= NONE_DEPTH {
        discard;
    }
    // An outer one not over a caster that continues the edge's lit face, coplanar (Ribbon::grad,
    // Ribbon::same).
    let g = geom_at(q);
    if v.sign > 0.0 && g < NONE_DEPTH && abs(g - (v.c.x + dot(v.grad, q - v.a))) <= v.same {
        discard;
    }
    var f: RibbonFragment;
    f.edge = vec2<f32>(c, p);
    f.key = (c + abs(p)) * KEY_SCALE;
    return f;
}

struct LowerVarying {
    @builtin(position) pos: vec4<f32>,
    @location(0) world: vec3<f32>,
};

@vertex
fn vs_lower(@location(0) position: vec3<f32>) -> LowerVarying {
    var v: LowerVarying;
    v.pos = gp.map.view_proj * vec4<f32>(position, 1.0);
    v.world = position;
    return v;
}

@fragment
fn fs_lower(v: LowerVarying) -> @location(0) vec4<f32> {
    let e = textureLoad(edge_tex, vec2<i32>(v.pos.xy), 0).xy;
    let z = normalized(gp.warp, linear_depth(gp.map, v.world));
    if !has_edge(e) || !(z > e.x + depth_gap(gp.warp, linear(gp.warp, e.x), gp.layer_gap)) {
        discard;
    }
    return vec4<f32>(z, 0.0, 0.0, 1.0);
}
