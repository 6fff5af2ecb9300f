//! Generation by silhouette extrusion (section 3.1), CPU side; `silhouette.wgsl` is the GPU side.
//!
//! 1. Every face (front faces, and open surfaces' back faces, which occlude too) to the
//!    geometry depth (`geom`), nearest wins: an ordinary shadow map.
//! 2. Every silhouette edge (faces on its two sides face the light differently, or a mesh
//!    border) that outlines its caster ([`Ribbon::is_outline`]: not a fold whose outside the
//!    caster itself covers) becomes two ribbons in the map: an inner strip over the silhouette's
//!    inside and an outer strip on the outside, each extended past both ends to cover the
//!    corners (an inner strip's fragments land only over a caster, an outer strip's only where
//!    no caster lies on the plane of the edge's lit face: [`SAME_DEPTH`]), each as wide as the widest
//!    penumbra of that edge ([`Warp::ribbon_texels`]). A ribbon fragment at
//!    distance `d` texels from the edge *segment* carries `c` (the edge's depth at the nearest
//!    point) and `p_i = -/+ d * p_per_texel`; its depth-test key is the penumbra limit
//!    `c + |p_i|` scaled by [`KEY_SCALE`] into the depth range `[0, 1]`, and the smallest key
//!    wins ("highest penumbra limit wins"). Along a straight
//!    edge `p_i` is the exact plane of section 2, so bilinear interpolation is exact.
//! 3. Back faces to the lower limit, keeping only those deeper than the texel's `c` by more than
//!    `layer_gap` texels (a surface must not clip its own soft shadow).

use crate::combine::NO_EDGE;
use crate::warp::NONE_DEPTH;
use crate::warp::Warp;
use bytemuck::{Pod, Zeroable};
use glam::{Vec2, Vec3, Vec4};
use rayon::prelude::*;
use soft_shadow_core::pool::Pool;
use soft_shadow_core::raster::snapped::{SUB, SnappedTri};
use soft_shadow_core::raster::{DepthPass, DepthTest, Faces, depth_map_filtered};
use soft_shadow_core::{Map2D, MapParams, View};
use std::collections::{HashMap, HashSet};
use std::sync::{Arc, Mutex};

/// One mesh edge and the faces beside it, laid out as `Edge` in `silhouette.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable, PartialEq)]
pub(crate) struct Edge {
    /// One end (w = 1).
    pub a: [f32; 4],
    /// The other end (w = 1).
    pub b: [f32; 4],
    /// The vertex of face 0 opposite the edge (w = 1).
    pub o0: [f32; 4],
    /// The vertex of face 1 opposite the edge (w = 1), w = 0 on a border (one face).
    pub o1: [f32; 4],
    /// Unit normal of face 0 (its winding).
    pub n0: [f32; 4],
    /// Unit normal of face 1.
    pub n1: [f32; 4],
}

/// A vertex position's bits: welds bit-identical vertices.
type VertexKey = [u32; 3];

fn key(p: Vec3) -> VertexKey {
    p.to_array().map(f32::to_bits)
}

/// The edges of a triangle soup: vertices welded where bit-identical; an edge with exactly two
/// faces is one [`Edge`], an edge of one face or of three and more is a border of each face.
/// Zero-area triangles have no orientation and are skipped, and a triangle repeated with the
/// same winding (a duplicated mesh, coincident blockers) counts once: twice, the outline of a
/// blocker had two faces of the same facing on every edge, so it was no silhouette at all, and
/// its inner edges had four, so they were borders.
pub(crate) fn edges(tris: &[[Vec3; 3]]) -> Vec<Edge> {
    let mut by_edge: HashMap<(VertexKey, VertexKey), Vec<(usize, usize)>> = HashMap::new();
    let mut seen: HashSet<[VertexKey; 3]> = HashSet::new();
    let normal = |t: &[Vec3; 3]| (t[1] - t[0]).cross(t[2] - t[0]).normalize_or_zero();
    for (ti, t) in tris.iter().enumerate() {
        if normal(t) == Vec3::ZERO {
            continue;
        }
        // The vertex keys in winding order, starting from the smallest.
        let ks = t.map(key);
        let first = (0..3).min_by_key(|&i| ks[i]).unwrap_or(0);
        if !seen.insert([ks[first], ks[(first + 1) % 3], ks[(first + 2) % 3]]) {
            continue;
        }
        for k in 0..3 {
            let (ka, kb) = (key(t[k]), key(t[(k + 1) % 3]));
            let e = if ka <= kb { (ka, kb) } else { (kb, ka) };
            by_edge.entry(e).or_default().push((ti, k));
        }
    }
    let mut keys: Vec<_> = by_edge.keys().copied().collect();
    keys.sort_unstable();
    let v4 = |p: Vec3, w: f32| p.extend(w).to_array();
    let mut out = Vec::with_capacity(keys.len());
    for k in keys {
        let faces = &by_edge[&k];
        let side = |&(ti, e): &(usize, usize)| {
            let t = &tris[ti];
            (t[e], t[(e + 1) % 3], t[(e + 2) % 3], normal(t))
        };
        if faces.len() == 2 {
            let (a, b, o0, n0) = side(&faces[0]);
            let (_, _, o1, n1) = side(&faces[1]);
            out.push(Edge {
                a: v4(a, 1.0),
                b: v4(b, 1.0),
                o0: v4(o0, 1.0),
                o1: v4(o1, 1.0),
                n0: v4(n0, 0.0),
                n1: v4(n1, 0.0),
            });
        } else {
            for f in faces {
                let (a, b, o, n) = side(f);
                out.push(Edge {
                    a: v4(a, 1.0),
                    b: v4(b, 1.0),
                    o0: v4(o, 1.0),
                    o1: [0.0; 4],
                    n0: v4(n, 0.0),
                    n1: [0.0; 4],
                });
            }
        }
    }
    out
}

/// How many caster sets an [`EdgeCache`] keeps the edges of.
const CACHED_SETS: usize = 4;

/// How many bytes of triangles and edges an [`EdgeCache`] keeps at most: a few sets of the
/// bunny's size (69,451 triangles: 2.5 MB of triangles, 10 MB of edges); a larger set is built
/// on every call rather than kept.
const CACHED_BYTES: usize = 64 << 20;

/// One cached caster set: its triangles (as their bits) and its edges.
type CachedSet = (Arc<[u32]>, Arc<Vec<Edge>>);

/// [`edges`] of the caster sets seen last, newest first, kept in the caller's
/// [`soft_shadow_core::CpuContext`] (`cpu.cached(EdgeCache::default)`): the CPU generator's
/// counterpart of the GPU path's edges derived once per scene, so that a call on casters it has
/// seen (the same triangles, bit for bit) does not rebuild the adjacency. The last 4 sets
/// (`CACHED_SETS`) within 64 MiB (`CACHED_BYTES`) are kept; looking one up compares the
/// triangles' bits (a copy of them is kept with the edges).
#[derive(Default)]
pub(crate) struct EdgeCache {
    sets: Mutex<Vec<CachedSet>>,
}

/// Bytes an entry of the cache holds.
fn cached_bytes((bits, edges): &CachedSet) -> usize {
    size_of_val(&**bits) + edges.len() * size_of::<Edge>()
}

impl EdgeCache {
    /// [`edges`] of `tris`, built once per caster set (see the type).
    pub(crate) fn edges(&self, tris: &[[Vec3; 3]]) -> Arc<Vec<Edge>> {
        self.edges_within(tris, CACHED_SETS, CACHED_BYTES)
    }

    /// [`EdgeCache::edges`] keeping at most `sets` sets and `bytes` bytes.
    fn edges_within(&self, tris: &[[Vec3; 3]], sets: usize, bytes: usize) -> Arc<Vec<Edge>> {
        cached_edges_within(&self.sets, tris, sets, bytes)
    }
}

fn cached_edges_within(
    cache: &Mutex<Vec<CachedSet>>,
    tris: &[[Vec3; 3]],
    sets: usize,
    bytes: usize,
) -> Arc<Vec<Edge>> {
    let bits: &[u32] = bytemuck::cast_slice(tris);
    let lock = || cache.lock().unwrap_or_else(|e| e.into_inner());
    {
        let mut cache = lock();
        if let Some(i) = cache.iter().position(|(key, _)| **key == *bits) {
            let hit = cache.remove(i);
            let edges = hit.1.clone();
            cache.insert(0, hit);
            return edges;
        }
    }
    let built = Arc::new(edges(tris));
    let mut cache = lock();
    cache.insert(0, (Arc::from(bits), built.clone()));
    // The newest sets that fit, at most `sets` of them.
    let mut kept = 0;
    let fits = cache
        .iter()
        .take(sets)
        .take_while(|e| {
            kept += cached_bytes(e);
            kept <= bytes
        })
        .count();
    cache.truncate(fits);
    built
}

/// An edge projected into the map, as the ribbon fragments need it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Ribbon {
    /// Ends in texel coordinates.
    pub a: Vec2,
    /// See `a`.
    pub b: Vec2,
    /// Normalised depths of the ends.
    pub ca: f32,
    /// See `ca`.
    pub cb: f32,
    /// Unit normal towards the outside, in texels.
    pub out: Vec2,
    /// Half-widths in texels at the ends.
    pub ha: f32,
    /// See `ha`.
    pub hb: f32,
    /// The normalised depth's change per texel on the plane of the edge's lit face (face 0 of a
    /// border): `ca + grad . (q - a)` is that plane's depth at `q` (a plane's normalised depth
    /// is affine in the map's texels, `-1/z` in perspective); zero where that face is seen
    /// edge-on or its third vertex lies behind the eye (the edge's own depth then stands in).
    pub grad: Vec2,
    /// [`SAME_DEPTH`] along the ribbon, normalised: the smaller of its ends' (`depth_gap` is
    /// monotonic in the depth, and `c` lies between the ends').
    pub same: f32,
}

/// Whether a face with normal `n` through `p` faces the light of map `m`.
fn faces_light(m: &MapParams, n: Vec3, p: Vec3) -> bool {
    let l = Vec4::from(m.light);
    let to_light = if l.w == 1.0 {
        l.truncate() - p
    } else {
        l.truncate()
    };
    n.dot(to_light) > 0.0
}

/// Distance (texels) from the edge's line within which a face counts as seen edge-on.
pub(crate) const MIN_FACE_TEXELS: f32 = 1.0e-3;

/// The ribbon of `e` in map `m`, or `None` when it is not a silhouette edge, lies behind the
/// light, or is seen end-on.
pub(crate) fn ribbon(m: &MapParams, warp: &Warp, e: &Edge) -> Option<Ribbon> {
    let v = |a: [f32; 4]| Vec4::from(a).truncate();
    let (a, b) = (v(e.a), v(e.b));
    let border = e.o1[3] == 0.0;
    if !border && faces_light(m, v(e.n0), a) == faces_light(m, v(e.n1), a) {
        return None;
    }
    let (sa, sb) = (m.project(a)?.truncate(), m.project(b)?.truncate());
    let d = sb - sa;
    let len = d.length();
    if len.partial_cmp(&1e-6) != Some(std::cmp::Ordering::Greater) {
        return None;
    }
    // The inside is where the faces project (both on one side of a silhouette edge); the
    // opposite vertex farther from the edge's line decides, and a face seen edge-on (both
    // within MIN_FACE_TEXELS of the line) casts no area, so no ribbon.
    let side = |o: [f32; 4]| {
        m.project(v(o))
            .map_or(0.0, |so| d.perp_dot(so.truncate() - sa) / len)
    };
    let s0 = side(e.o0);
    let s1 = if border { 0.0 } else { side(e.o1) };
    let s = if s0.abs() >= s1.abs() { s0 } else { s1 };
    if s.abs().partial_cmp(&MIN_FACE_TEXELS) != Some(std::cmp::Ordering::Greater) {
        return None;
    }
    let mut out = Vec2::new(-d.y, d.x) / len;
    if s > 0.0 {
        out = -out;
    }
    let (ca, cb) = (
        warp.normalized(m.linear_depth(a)),
        warp.normalized(m.linear_depth(b)),
    );
    let lit = if border || faces_light(m, v(e.n0), a) {
        e.o0
    } else {
        e.o1
    };
    let grad = m.project(v(lit)).map_or(Vec2::ZERO, |so| {
        let w = so.truncate() - sa;
        let det = d.perp_dot(w);
        if det.abs().partial_cmp(&(MIN_FACE_TEXELS * len)) != Some(std::cmp::Ordering::Greater) {
            return Vec2::ZERO;
        }
        // grad . d = cb - ca and grad . w = co - ca.
        let (dc, dw) = (cb - ca, warp.normalized(so.z) - ca);
        Vec2::new(dc * w.y - d.y * dw, d.x * dw - dc * w.x) / det
    });
    let cap = 2.0 * m.resolution as f32;
    Some(Ribbon {
        a: sa,
        b: sb,
        ca,
        cb,
        out,
        ha: warp.ribbon_texels(ca).min(cap),
        hb: warp.ribbon_texels(cb).min(cap),
        grad,
        same: warp
            .depth_gap(warp.linear(ca), SAME_DEPTH)
            .min(warp.depth_gap(warp.linear(cb), SAME_DEPTH)),
    })
}

/// Depth, in texels of the map's width at the edge (`Warp::depth_gap`, at the ribbon's deeper
/// end), within which a caster under an outer ribbon fragment lies on the plane of the edge's
/// lit face ([`Ribbon::grad`]), extended past the edge: a coplanar caster continues that face,
/// so the edge outlines nothing there. The plane's depth is exact at the texel (affine in the
/// map's texels), so this is the rounding between it and the rasterized depth, well under any
/// gap between two casters that the map resolves (a caster a texel below the plane still
/// gets the edge's outer penumbra).
pub(crate) const SAME_DEPTH: f32 = 0.25;

/// Texels outside an edge, along its outward normal, at which [`Ribbon::is_outline`] reads the
/// geometry.
pub(crate) const OUTLINE_PROBE: f32 = 1.5;

impl Ribbon {
    /// Whether the edge outlines its caster against what lies beyond it: at its two ends and its
    /// middle, [`OUTLINE_PROBE`] texels outside, the map holds no caster or one deeper than the
    /// edge by more than `gap(c)` (normalised) at one point at least. An edge whose outside is
    /// covered everywhere by a caster at its depth or nearer the light is a fold inside the
    /// caster's outline (a bump on a surface, a crease): no receiver sees light past it, and its
    /// ribbon drew a penumbra there, light streaks inside the umbra and dark ones around them.
    pub(crate) fn is_outline(&self, geom: &Map2D<f32>, gap: impl Fn(f32) -> f32) -> bool {
        let (w, h) = (geom.width() as f32, geom.height() as f32);
        let probe = |p: Vec2, c: f32| {
            let q = p + self.out * OUTLINE_PROBE;
            if !(q.x >= 0.0 && q.y >= 0.0 && q.x < w && q.y < h) {
                return true;
            }
            let g = *geom.get(q.x as u32, q.y as u32);
            g >= NONE_DEPTH || g > c + gap(c)
        };
        let (mid, cm) = ((self.a + self.b) * 0.5, (self.ca + self.cb) * 0.5);
        probe(self.a, self.ca) || probe(mid, cm) || probe(self.b, self.cb)
    }

    /// The two quads (texel coordinates): the inner strip, then the outer strip, each with its
    /// caps (extended past both ends by its half-width, so that the strips of a curved outline
    /// leave no texel between them uncovered).
    pub(crate) fn quads(&self) -> [[Vec2; 4]; 2] {
        let t = (self.b - self.a).normalize_or_zero();
        let (a, b, o) = (self.a, self.b, self.out);
        [
            [
                a - t * self.ha,
                b + t * self.hb,
                b + t * self.hb - o * self.hb,
                a - t * self.ha - o * self.ha,
            ],
            [
                a - t * self.ha,
                b + t * self.hb,
                b + t * self.hb + o * self.hb,
                a - t * self.ha + o * self.ha,
            ],
        ]
    }

    /// A key no fragment of this ribbon goes below: [`Ribbon::fragment`]'s `c` lies between the
    /// ends' depths (up to the rounding of its interpolation, which the margin covers) and
    /// `|p_i| >= 0`. A texel whose key is already at or below it keeps its value.
    pub(crate) fn key_floor(&self) -> f32 {
        let lo = self.ca.min(self.cb);
        let margin = 4.0 * f32::EPSILON * (self.ca.abs().max(self.cb.abs()) + 1.0);
        let f = (lo - margin) * KEY_SCALE;
        f - f.abs() * 4.0 * f32::EPSILON - f32::MIN_POSITIVE
    }

    /// The fragment at texel centre `q`: `(key, c, p_i)` with `p_i` per texel `ppt`.
    ///
    /// `sign` is the strip's: -1 for the inner strip, +1 for the outer one (a texel on the edge's
    /// line extension belongs to the strip that covers it, not to a rounding of its side).
    pub(crate) fn fragment(&self, q: Vec2, ppt: f32, sign: f32) -> (f32, f32, f32) {
        let d = self.b - self.a;
        let t = ((q - self.a).dot(d) / d.length_squared()).clamp(0.0, 1.0);
        let dist = (q - (self.a + d * t)).length();
        let c = self.ca + (self.cb - self.ca) * t;
        let p = (sign * dist * ppt).clamp(-crate::storage::MAX_P, crate::storage::MAX_P);
        ((c + p.abs()) * KEY_SCALE, c, p)
    }
}

/// A ribbon triangle snapped to the sub-texel grid as the GPU snaps it (from `f32` texel
/// coordinates), oriented; `None` for zero area.
fn snap(p: [Vec2; 3]) -> Option<SnappedTri> {
    let snap = |v: f32| (v * SUB as f32).round() as i64;
    SnappedTri::new(p.map(|q| snap(q.x)), p.map(|q| snap(q.y))).map(|(t, _)| t)
}

const BAND: u32 = 16;

/// Scale of the depth-test key `c + |p_i|` (at most `1 + MAX_P`) into a depth in `[0, 1]`;
/// 1 is "no ribbon" (the cleared depth), which a ribbon at `c = 1`, `|p_i| = MAX_P` never beats.
pub(crate) const KEY_SCALE: f32 = 1.0 / (1.0 + crate::storage::MAX_P);

/// One map row of a band while ribbons are rasterized: each texel's key and `[c, p_i]`.
struct Row<'a> {
    keys: &'a mut [f32],
    out: &'a mut [[f32; 2]],
    /// The row's geometry depths: an inner fragment lands only where a caster is, an outer one
    /// only where none continues the edge's lit face ([`Ribbon::grad`]).
    geom: &'a [f32],
    /// The row's texel centre y.
    y: f32,
}

/// Texels per block of a span: [`Ribbon::fragment`] of a block is computed lane by lane, which
/// vectorizes, and the block's keys and values stored whole (branch-free).
const LANES: usize = 8;

impl Row<'_> {
    /// Offers `ribbon`'s fragments to texels `x0..=x1`, keeping a strictly smaller key.
    fn fill(mut self, ribbon: &Ribbon, sign: f32, ppt: f32, x0: usize, x1: usize) {
        let floor = ribbon.key_floor();
        let mut x = x0;
        while x + LANES <= x1 + 1 {
            // A block whose every key is at or below anything this ribbon can offer keeps
            // its values: its fragments are not computed.
            let kmax = self.keys[x..x + LANES]
                .iter()
                .fold(f32::MIN, |a, &k| a.max(k));
            if kmax > floor {
                self.block::<LANES>(ribbon, sign, ppt, x);
            }
            x += LANES;
        }
        for x in x..=x1 {
            self.block::<1>(ribbon, sign, ppt, x);
        }
    }

    #[inline(always)]
    fn block<const L: usize>(&mut self, ribbon: &Ribbon, sign: f32, ppt: f32, x: usize) {
        let f: [(f32, f32, f32); L] = std::array::from_fn(|l| {
            ribbon.fragment(Vec2::new((x + l) as f32 + 0.5, self.y), ppt, sign)
        });
        // The lit face's plane at this row, and its tolerance, as locals the lanes share.
        let (same, grad) = (ribbon.same, ribbon.grad);
        let row = ribbon.ca + grad.y * (self.y - ribbon.a.y);
        let mut keys: [f32; L] = std::array::from_fn(|l| self.keys[x + l]);
        let mut out: [[f32; 2]; L] = std::array::from_fn(|l| self.out[x + l]);
        for l in 0..L {
            // An inner fragment over no caster: past a corner of the outline (an inner strip's
            // cap) or past a part thinner than the penumbra.
            let g = self.geom[x + l];
            let outside = (sign < 0.0) & (g >= NONE_DEPTH);
            // An outer fragment over a caster on the plane of the edge's lit face (within
            // `Ribbon::same`): a coplanar caster continues that face past the edge (overlapping plates,
            // a mesh in parts), so the edge outlines nothing there and no light passes; its
            // outer penumbra drew a lit band inside the umbra.
            let plane = row + grad.x * ((x + l) as f32 + 0.5 - ribbon.a.x);
            let continued = (sign > 0.0) & (g < NONE_DEPTH) & ((g - plane).abs() <= same);
            let nearer = (f[l].0 < keys[l]) & !outside & !continued;
            keys[l] = if nearer { f[l].0 } else { keys[l] };
            out[l] = if nearer { [f[l].1, f[l].2] } else { out[l] };
        }
        self.keys[x..x + L].copy_from_slice(&keys);
        self.out[x..x + L].copy_from_slice(&out);
    }
}

/// Step 2 on the CPU: the winning `[c, p_i]` per texel ([`NO_EDGE`] where no ribbon reaches).
pub(crate) fn rasterize_ribbons(
    pool: &Arc<Pool>,
    ribbons: &[Ribbon],
    geom: &Map2D<f32>,
    ppt: f32,
) -> Map2D<[f32; 2]> {
    let resolution = geom.width();
    // Each quad as the GPU draws it: triangles (0, 1, 2) and (0, 2, 3), inner strip first.
    let tris: Vec<(usize, SnappedTri, f32)> = ribbons
        .iter()
        .enumerate()
        .flat_map(|(i, r)| {
            let [inner, outer] = r.quads();
            [(inner, -1.0), (outer, 1.0)]
                .into_iter()
                .flat_map(move |(q, sign)| {
                    [[q[0], q[1], q[2]], [q[0], q[2], q[3]]]
                        .into_iter()
                        .filter_map(move |t| snap(t).map(|t| (i, t, sign)))
                })
        })
        .collect();
    let boxes: Vec<_> = tris.iter().map(|(_, t, _)| t.texel_box()).collect();
    // Each band clears its own rows (in cache) before its ribbons: no clearing pass.
    let mut data = pool.overwrite(resolution as usize * resolution as usize, NO_EDGE);
    let w = resolution as usize;
    data.par_chunks_mut(w * BAND as usize)
        .enumerate()
        .for_each(|(band, rows)| {
            let y0 = band as u32 * BAND;
            let y1 = (y0 + BAND).min(resolution);
            rows.fill(NO_EDGE);
            let mut keys = vec![1.0f32; rows.len()];
            for ((i, t, sign), &(bx0, bx1, by0, by1)) in tris.iter().zip(&boxes) {
                let (rx0, rx1) = (bx0.max(0), bx1.min(resolution as i64 - 1));
                let (ry0, ry1) = (by0.max(y0 as i64), by1.min(y1 as i64 - 1));
                for y in ry0..=ry1 {
                    let Some((sx0, sx1)) = t.span(y, rx0, rx1) else {
                        continue;
                    };
                    let at = (y as usize - y0 as usize) * w;
                    let row = Row {
                        keys: &mut keys[at..at + w],
                        out: &mut rows[at..at + w],
                        geom: &geom.data()[y as usize * w..(y as usize + 1) * w],
                        y: y as f32 + 0.5,
                    };
                    row.fill(&ribbons[*i], *sign, ppt, sx0 as usize, sx1 as usize);
                }
            }
        });
    Map2D::from_vec(resolution, resolution, data)
        .unwrap_or_else(|| Map2D::new(0, 0, NO_EDGE))
        .returning_to(pool)
}

/// Step 3 on the CPU: normalised depth of the nearest back face deeper than the texel's edge
/// depth by more than `layer_gap` texels ([`crate::warp::NONE_DEPTH`] where none).
pub(crate) fn lower_limit(
    pool: &Arc<Pool>,
    view: &View,
    warp: &Warp,
    tris: &[[Vec3; 3]],
    edge: &Map2D<[f32; 2]>,
    layer_gap: f32,
) -> Map2D<f32> {
    let pass = DepthPass {
        test: DepthTest::Nearest,
        faces: Faces::Back,
    };
    depth_map_filtered(
        pool,
        view,
        edge.width(),
        tris,
        pass,
        |x, y, z| {
            let e = *edge.get(x, y);
            crate::combine::has_edge(e) && deeper_than_edge(warp, e[0], z, layer_gap)
        },
        |z| warp.normalized(z),
    )
}

/// Whether linear depth `z` lies more than `layer_gap` texels below the edge at normalised `c`.
pub(crate) fn deeper_than_edge(warp: &Warp, c: f32, z: f32, layer_gap: f32) -> bool {
    let zc = warp.linear(c);
    warp.normalized(z) > c + warp.depth_gap(zc, layer_gap)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The cached edges are those of the casters asked for: the same set again is served the
    /// same edges without a rebuild, a set that differs in one bit (-0.0 for 0.0, which welds
    /// differently) gets its own, and a set pushed out past [`CACHED_SETS`] or the byte bound
    /// is built anew.
    #[test]
    fn cached_edges_are_the_edges_of_the_casters_asked_for() {
        let quad = |z: f32| {
            let p = [
                Vec3::new(0.0, z, 0.0),
                Vec3::new(1.0, z, 0.0),
                Vec3::new(1.0, z, 1.0),
                Vec3::new(0.0, z, 1.0),
            ];
            vec![[p[0], p[1], p[2]], [p[0], p[2], p[3]]]
        };
        let cache = EdgeCache::default();
        let cached_edges = |t: &[[Vec3; 3]]| cache.edges(t);
        let cached_edges_within = |t: &[[Vec3; 3]], s: usize, b: usize| cache.edges_within(t, s, b);
        let a = quad(0.25);
        let first = cached_edges(&a);
        assert_eq!(*first, edges(&a));
        assert!(
            Arc::ptr_eq(&first, &cached_edges(&a)),
            "served again, not rebuilt"
        );
        // One vertex of the second triangle at -0.0 instead of 0.0: no longer welded.
        let mut b = quad(0.0);
        b[1][0].x = -0.0;
        let (eb, e0) = (cached_edges(&b), cached_edges(&quad(0.0)));
        assert_eq!(*eb, edges(&b));
        assert_eq!(*e0, edges(&quad(0.0)));
        assert_ne!(eb.len(), e0.len(), "{} edges for both", eb.len());
        for z in 1..=CACHED_SETS {
            cached_edges(&quad(z as f32));
        }
        let again = cached_edges(&a);
        assert!(!Arc::ptr_eq(&first, &again), "evicted, so rebuilt");
        assert_eq!(*again, edges(&a));
        // Within a byte bound that holds one quad's set but not two, the older one goes, and a
        // set over the bound is not kept at all.
        let one = cached_bytes(&cache.sets.lock().unwrap()[0]);
        let b = quad(7.0);
        let kept_b = cached_edges_within(&b, CACHED_SETS, one);
        cached_edges_within(&a, CACHED_SETS, one);
        assert!(!Arc::ptr_eq(
            &kept_b,
            &cached_edges_within(&b, CACHED_SETS, one)
        ));
        let big = cached_edges_within(&quad(8.0), CACHED_SETS, one - 1);
        assert!(!Arc::ptr_eq(
            &big,
            &cached_edges_within(&quad(8.0), CACHED_SETS, one - 1)
        ));
        assert!(cache.sets.lock().unwrap().is_empty());
    }
}
