//! One receiver's shadow rays, traced together. Every ray of a receiver leaves the same origin
//! towards the light, so the casters that may block any of them are found once
//! ([`Hull::near_of`]: those near the hull of the origin and the light's outline) and
//! binned by the directions they cover seen from the origin: a grid over the central projection
//! onto a plane across the light's axis. A ray then tests only its cell's triangles, eight at a
//! time.
//!
//! The test is `obvhs`'s own: [`Triangle::intersect`] (Möller-Trumbore) and the any-hit rule of
//! [`obvhs::cwbvh::CwBvh::ray_traverse_miss`] (`t_min <= t <= t_max` and `t < t_max`), operation
//! for operation in the same order, lane by lane, so a ray's answer is the one the BVH gives
//! ([`RayTracer::unoccluded`]); a test holds the two equal on every catalogue scene. Two ways
//! they could part, neither seen: the BVH never tests a triangle whose box a ray misses, which a
//! hit just outside the box by rounding would need; and a build with FMA (`-C
//! target-cpu=native`) makes `glam` fuse the BVH path's cross product `d x c`, which the lanes
//! compute unfused.
//!
//! Binning is conservative: a triangle goes to no cell when every ray moves away from its plane
//! (a receiver's own triangle), else to every cell its projected bounds (widened by a margin far
//! above rounding) touch. One that reaches behind the origin is bounded by its part inside the
//! cone of the rays (the planes through the origin and the outline's edges, widened), and goes
//! to every cell when that part cannot be bounded. A ray whose projection is undefined tests
//! every candidate.

use super::RayTracer;
use super::certify::Hull;
use glam::{Vec3, Vec3A};
use obvhs::bvh2::Bvh2;
use obvhs::triangle::Triangle;
use soft_shadow_core::LightPoint;

/// Triangles per block: the lanes one test runs over.
const LANES: usize = 8;

/// Most cells per side of the direction grid.
const MAX_SIDE: usize = 16;

/// Eight triangles in the form the intersection needs, lane by lane: `c = v0 - origin`,
/// `e1 = v0 - v1`, `e2 = v2 - v0`, `n = e1 x e2`, `nc = n . c`. Unused lanes have `nc = NaN`,
/// which no comparison accepts.
#[derive(Clone, Copy)]
#[repr(C, align(32))]
struct Block {
    c: [[f32; LANES]; 3],
    e1: [[f32; LANES]; 3],
    e2: [[f32; LANES]; 3],
    n: [[f32; LANES]; 3],
    nc: [f32; LANES],
}

impl Block {
    const EMPTY: Block = Block {
        c: [[0.0; LANES]; 3],
        e1: [[0.0; LANES]; 3],
        e2: [[0.0; LANES]; 3],
        n: [[0.0; LANES]; 3],
        nc: [f32::NAN; LANES],
    };

    /// Whether the ray from the origin along `d` hits a triangle of the block within
    /// `[t_min, t_max]` and before `t_max` ([`Triangle::intersect`] lane by lane).
    #[inline(always)]
    fn any_hit(&self, d: [f32; 3], t_min: f32, t_max: f32) -> bool {
        let mut hit = [0u32; LANES];
        for (l, hit) in hit.iter_mut().enumerate() {
            let (cx, cy, cz) = (self.c[0][l], self.c[1][l], self.c[2][l]);
            // r = d x c
            let rx = d[1] * cz - d[2] * cy;
            let ry = d[2] * cx - d[0] * cz;
            let rz = d[0] * cy - d[1] * cx;
            let det = self.n[0][l] * d[0] + self.n[1][l] * d[1] + self.n[2][l] * d[2];
            let inv_det = 1.0 / det;
            let u = (rx * self.e2[0][l] + ry * self.e2[1][l] + rz * self.e2[2][l]) * inv_det;
            let v = (rx * self.e1[0][l] + ry * self.e1[1][l] + rz * self.e1[2][l]) * inv_det;
            let w = 1.0 - u - v;
            let inside = (u.to_bits() | v.to_bits() | w.to_bits()) & 0x8000_0000 == 0;
            let t = self.nc[l] * inv_det;
            let ok = inv_det != 0.0 && inside && t >= t_min && t <= t_max && t < t_max;
            *hit = ok as u32;
        }
        hit.iter().fold(0, |a, &h| a | h) != 0
    }
}

/// One triangle seen from the origin, in a block's terms, with `obvhs`'s arithmetic.
struct Lanes {
    c: Vec3A,
    e1: Vec3A,
    e2: Vec3A,
    n: Vec3A,
    nc: f32,
}

impl Lanes {
    fn new(t: &Triangle, origin: Vec3A) -> Self {
        let e1 = t.v0 - t.v1;
        let e2 = t.v2 - t.v0;
        let n = e1.cross(e2);
        let c = t.v0 - origin;
        Lanes {
            c,
            e1,
            e2,
            n,
            nc: n.dot(c),
        }
    }

    /// Writes the triangle into lane `l` of `block`.
    fn put(&self, block: &mut Block, l: usize) {
        for k in 0..3 {
            block.c[k][l] = self.c[k];
            block.e1[k][l] = self.e1[k];
            block.e2[k][l] = self.e2[k];
            block.n[k][l] = self.n[k];
        }
        block.nc[l] = self.nc;
    }
}

/// The grid cells whose rays may hit a candidate (the catch-all cell holds every candidate).
#[derive(Clone, Copy)]
enum Cells {
    /// Every cell.
    Every,
    /// Columns `[0]..=[1]` of rows `[2]..=[3]`.
    Range([usize; 4]),
    /// None: no ray in the grid can reach it.
    Nowhere,
}

/// The shadow rays of one origin: its candidate casters, binned by direction.
pub struct OriginRays {
    /// The rays' origin and their `t_min` (the receiver's offset).
    origin: Vec3,
    eps: f32,
    /// Light axis and the two directions across it (orthonormal).
    axis: Vec3,
    across: [Vec3; 2],
    /// Grid: lower corner, cells per unit, cells per side (1 and 1: no grid).
    lo: [f32; 2],
    scale: [f32; 2],
    side: [usize; 2],
    /// Blocks of cell `k` (row-major, then one cell holding every candidate) are
    /// `blocks[first[k]..first[k + 1]]`.
    first: Vec<u32>,
    blocks: Vec<Block>,
}

impl OriginRays {
    /// The rays from `origin` (a receiver's, offset by `eps`, which is also their `t_min`) to
    /// the points of `outline` (positions whose convex hull holds every light point): the casters
    /// of `tris` near their hull, found through `bvh`, binned.
    pub fn new(origin: Vec3, eps: f32, outline: &[Vec3], bvh: &Bvh2, tris: &[Triangle]) -> Self {
        let mut ids = Vec::new();
        Hull::new(origin, outline).near_of(bvh, tris, &mut ids);
        let o = Vec3A::from(origin);
        // The axis: towards the outline's centroid; a grid only where every outline point lies
        // well in front (then so does every light point, a convex combination of them).
        let centroid = outline.iter().copied().sum::<Vec3>() / outline.len() as f32;
        let axis = (centroid - origin).normalize_or_zero();
        let front = outline.iter().all(|&q| {
            let w = q - origin;
            axis.dot(w) > 0.1 * w.length()
        });
        let side = if front && axis != Vec3::ZERO {
            (((ids.len() as f32).sqrt() / 1.5).ceil() as usize).clamp(1, MAX_SIDE)
        } else {
            1
        };
        let (t, b) = axis.any_orthonormal_pair();
        let mut rays = OriginRays {
            origin,
            eps,
            axis,
            across: [t, b],
            lo: [0.0; 2],
            scale: [0.0; 2],
            side: [1; 2],
            first: Vec::new(),
            blocks: Vec::new(),
        };
        // The cells of every candidate.
        let cone = Self::cone(origin, outline, axis);
        if side > 1 {
            let mut lo = [f32::INFINITY; 2];
            let mut hi = [f32::NEG_INFINITY; 2];
            for &q in outline {
                let p = rays.project(q - origin).unwrap_or([0.0; 2]);
                for k in 0..2 {
                    lo[k] = lo[k].min(p[k]);
                    hi[k] = hi[k].max(p[k]);
                }
            }
            // A segment light projects to a line: one cell across it.
            let widest = (hi[0] - lo[0]).max(hi[1] - lo[1]);
            for k in 0..2 {
                let extent = hi[k] - lo[k];
                rays.side[k] = if extent > 0.05 * widest { side } else { 1 };
                rays.lo[k] = lo[k];
                rays.scale[k] = rays.side[k] as f32 / extent.max(1e-6);
            }
        }
        let grid = rays.side[0] * rays.side[1] > 1;
        let ranges: Vec<Cells> = ids
            .iter()
            .map(|&i| {
                let t = &tris[i as usize];
                let w = [t.v0, t.v1, t.v2].map(|v| Vec3::from(v) - origin);
                if Self::receding(w, outline, origin) {
                    return Cells::Nowhere;
                }
                if !grid {
                    return Cells::Every;
                }
                // A triangle reaching behind the origin: only its part inside the cone of the
                // rays can be hit, which lies in front.
                let behind = w.iter().any(|&w| rays.axis.dot(w) <= 1e-6 * w.length());
                let bounds = if behind {
                    rays.clipped_bounds(w, &cone)
                } else {
                    rays.bounds(&w)
                };
                let Some((lo, hi)) = bounds else {
                    return Cells::Every;
                };
                if lo[0] > hi[0] {
                    return Cells::Nowhere;
                }
                let mut r = [0; 4];
                for k in 0..2 {
                    let margin = 1e-3 * (hi[k] - lo[k]) + 1e-4 * lo[k].abs().max(hi[k].abs());
                    r[2 * k] = rays.cell(k, lo[k] - margin);
                    r[2 * k + 1] = rays.cell(k, hi[k] + margin);
                }
                Cells::Range(r)
            })
            .collect();
        // Each cell's triangles, then the catch-all cell's (every candidate), packed into
        // blocks of `LANES`: count, place, fill.
        let cells = rays.side[0] * rays.side[1];
        let columns = rays.side[0];
        let covered = |r: &Cells, f: &mut dyn FnMut(usize)| {
            match *r {
                Cells::Range([x0, x1, y0, y1]) => {
                    for y in y0..=y1 {
                        for x in x0..=x1 {
                            f(y * columns + x);
                        }
                    }
                }
                Cells::Every => (0..cells).for_each(&mut *f),
                Cells::Nowhere => {}
            }
            f(cells);
        };
        let mut count = vec![0u32; cells + 1];
        for r in &ranges {
            covered(r, &mut |k| count[k] += 1);
        }
        rays.first = Vec::with_capacity(cells + 2);
        let mut total = 0u32;
        for &c in &count {
            rays.first.push(total);
            total += c.div_ceil(LANES as u32);
        }
        rays.first.push(total);
        rays.blocks = vec![Block::EMPTY; total as usize];
        let mut fill = vec![0u32; cells + 1];
        for (&i, r) in ids.iter().zip(&ranges) {
            let lanes = Lanes::new(&tris[i as usize], o);
            covered(r, &mut |k| {
                let at = fill[k] as usize;
                fill[k] += 1;
                let block = &mut rays.blocks[rays.first[k] as usize + at / LANES];
                lanes.put(block, at % LANES);
            });
        }
        rays
    }

    /// The inward unit normals of the planes through `origin` that bound the cone of its rays
    /// to a convex `outline` of 3 or more points (empty for fewer: no cone to clip by).
    fn cone(origin: Vec3, outline: &[Vec3], axis: Vec3) -> Vec<Vec3> {
        if outline.len() < 3 {
            return Vec::new();
        }
        (0..outline.len())
            .filter_map(|i| {
                let a = outline[i] - origin;
                let b = outline[(i + 1) % outline.len()] - origin;
                let n = a.cross(b).normalize_or_zero();
                (n != Vec3::ZERO).then(|| if n.dot(axis) < 0.0 { -n } else { n })
            })
            .collect()
    }

    /// Whether every ray moves away from the plane of the triangle `w` (offsets from the origin):
    /// the origin and every outline point lie on one side of it, each outline point farther
    /// than the origin, all by a margin far above rounding (`1e-4` of their distances to the
    /// triangle's first vertex). A receiver's own triangle, lit from above its tangent plane, is
    /// the common case.
    fn receding(w: [Vec3; 3], outline: &[Vec3], origin: Vec3) -> bool {
        let n = (w[1] - w[0]).cross(w[2] - w[0]).normalize_or_zero();
        if n == Vec3::ZERO {
            return false;
        }
        // Heights above the plane: the origin's, then each outline point's.
        let h_o = -n.dot(w[0]);
        let n = if h_o < 0.0 { -n } else { n };
        let h_o = h_o.abs();
        // False for NaN too.
        let clear = h_o > 1e-4 * w[0].length();
        if !clear {
            return false;
        }
        outline.iter().all(|&q| {
            let to = q - origin - w[0];
            n.dot(to) > h_o + 1e-4 * (to.length() + w[0].length())
        })
    }

    /// Bounds of the projections of the offsets `w` from the origin (`None`: one does not
    /// project).
    fn bounds(&self, w: &[Vec3]) -> Option<([f32; 2], [f32; 2])> {
        let mut lo = [f32::INFINITY; 2];
        let mut hi = [f32::NEG_INFINITY; 2];
        for &w in w {
            let p = self.project(w)?;
            for k in 0..2 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        Some((lo, hi))
    }

    /// Bounds of the projection of the part of the triangle `w` (offsets from the origin) inside
    /// the cone of the rays (`cone`: [`OriginRays::cone`]), each plane widened by `1e-4` of the
    /// triangle's reach so that rounding only adds; `Some` of empty bounds where no part is
    /// inside, `None` where the part cannot be bounded (no cone, or it comes near the origin).
    fn clipped_bounds(&self, w: [Vec3; 3], cone: &[Vec3]) -> Option<([f32; 2], [f32; 2])> {
        if cone.is_empty() {
            return None;
        }
        let reach = w.iter().fold(0.0f32, |m, v| m.max(v.length()));
        let slack = 1e-4 * reach;
        let mut poly = w.to_vec();
        for &n in cone {
            let mut next = Vec::with_capacity(poly.len() + 1);
            for (i, &a) in poly.iter().enumerate() {
                let b = poly[(i + 1) % poly.len()];
                let (da, db) = (n.dot(a) + slack, n.dot(b) + slack);
                if da >= 0.0 {
                    next.push(a);
                }
                if (da >= 0.0) != (db >= 0.0) {
                    next.push(a + (b - a) * (da / (da - db)));
                }
            }
            poly = next;
            if poly.is_empty() {
                return Some(([f32::INFINITY; 2], [f32::NEG_INFINITY; 2]));
            }
        }
        // Every vertex well in front (false for NaN too), so that it projects stably.
        let in_front = |v: &Vec3| self.axis.dot(*v) > 1e-3 * reach;
        if !poly.iter().all(in_front) {
            return None;
        }
        self.bounds(&poly)
    }

    /// Central projection of the offset `w` from the origin onto the plane one unit along the
    /// axis (`None` when it does not lie in front).
    fn project(&self, w: Vec3) -> Option<[f32; 2]> {
        let s = self.axis.dot(w);
        let r = 1.0 / s;
        let p = [self.across[0].dot(w) * r, self.across[1].dot(w) * r];
        (s > 0.0 && p[0].is_finite() && p[1].is_finite()).then_some(p)
    }

    /// The grid column (`k = 0`) or row (`k = 1`) of coordinate `x`, clamped to the grid.
    fn cell(&self, k: usize, x: f32) -> usize {
        // The saturating cast floors a non-negative value and sends NaN and negatives to 0.
        (((x - self.lo[k]) * self.scale[k]) as usize).min(self.side[k] - 1)
    }

    /// Whether the origin sees the light point `q`: the answer of
    /// [`RayTracer::sees_with`] for the receiver these rays were made for.
    pub fn sees(&self, q: LightPoint) -> bool {
        RayTracer::shadow_ray(self.origin, self.eps, q)
            .is_none_or(|(dir, t_max)| self.unoccluded(dir, self.eps, t_max))
    }

    /// Whether the ray from the origin along unit `dir` hits no candidate within
    /// `[t_min, t_max)`: the answer of [`RayTracer::unoccluded`] from the origin, for a ray
    /// that stays in the hull of the origin and the outline.
    pub fn unoccluded(&self, dir: Vec3, t_min: f32, t_max: f32) -> bool {
        let cells = self.side[0] * self.side[1];
        let cell = if cells > 1 {
            match self.project(dir) {
                Some(p) => self.cell(1, p[1]) * self.side[0] + self.cell(0, p[0]),
                None => cells,
            }
        } else {
            0
        };
        let blocks = &self.blocks[self.first[cell] as usize..self.first[cell + 1] as usize];
        let d = dir.to_array();
        !blocks.iter().any(|b| b.any_hit(d, t_min, t_max))
    }
}
