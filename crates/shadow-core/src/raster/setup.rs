//! Triangle setup of the CPU rasterizer: clip-space triangles clipped to the reversed-Z depth
//! range and a guard band, projected, snapped to the sub-texel grid ([`super::snapped`]) and
//! given their interpolation planes, in pooled chunks ([`Screen`]).

use super::Faces;
use super::snapped::{self, SnappedTri};
use crate::pool::Pool;
use crate::view::View;
use glam::{Vec3, Vec4};
use rayon::prelude::*;
use std::sync::Arc;

const SUB: f64 = snapped::SUB as f64;
const GUARD_BAND: f32 = 64.0;

#[derive(Clone, Copy)]
struct ClipVertex {
    pos: Vec4,
    bary: Vec3,
}

/// A triangle on the target: its coverage (snapped) and its interpolation planes (unsnapped).
pub(super) struct ScreenTri {
    /// Coverage: the snapped vertices.
    pub(super) snap: SnappedTri,
    /// Texel rectangle `(x0, x1, y0, y1)` whose centres the bounding box holds.
    pub(super) texels: (i64, i64, i64, i64),
    /// The walk down the rows' spans from row `y0` of `texels`.
    pub(super) rows: snapped::Rows,
    pub(super) fx: [f64; 3],
    pub(super) fy: [f64; 3],
    pub(super) farea: f64,
    /// Whether the float area is usable for interpolation (else the snapped weights).
    pub(super) planar: bool,
    /// Change of the barycentric weights per pixel to the right.
    pub(super) slope: [f64; 3],
    /// NDC depth's plane: its change per pixel right and down.
    pub(super) dz: [f64; 2],
    pub(super) z: [f64; 3],
    pub(super) inv_w: [f64; 3],
    pub(super) bary: [Vec3; 3],
    pub(super) triangle: u32,
}

/// A convex polygon of at most 3 + 6 vertices (a triangle clipped by six planes).
#[derive(Clone, Copy)]
struct Poly {
    v: [ClipVertex; 10],
    n: usize,
}

impl Poly {
    fn clip(&self, dist: impl Fn(Vec4) -> f32) -> Poly {
        let mut out = Poly { v: self.v, n: 0 };
        for i in 0..self.n {
            let (a, b) = (self.v[i], self.v[(i + 1) % self.n]);
            let (da, db) = (dist(a.pos), dist(b.pos));
            if da >= 0.0 {
                out.v[out.n] = a;
                out.n += 1;
            }
            if (da >= 0.0) != (db >= 0.0) {
                let t = da / (da - db);
                out.v[out.n] = ClipVertex {
                    pos: a.pos.lerp(b.pos, t),
                    bary: a.bary.lerp(b.bary, t),
                };
                out.n += 1;
            }
        }
        out
    }
}

/// Input triangles set up together, in submission order: one chunk's screen triangles are one
/// allocation, large enough for the [`Pool`] to keep between passes (no page faulted in per
/// pass, nothing copied to concatenate).
const CHUNK: usize = crate::pool::MIN_BYTES.div_ceil(size_of::<ScreenTri>());
/// Screen triangles one input triangle can become: its clipped polygon's fan.
const FAN_MAX: usize = 8;

/// The screen triangles of a pass, in submission order: [`CHUNK`] input triangles' worth per
/// chunk, addressed by `chunk * CHUNK * FAN_MAX + index in the chunk`.
pub(super) struct Screen {
    chunks: Vec<Vec<ScreenTri>>,
    pool: Arc<Pool>,
}

impl Drop for Screen {
    fn drop(&mut self) {
        self.chunks.drain(..).for_each(|c| self.pool.give(c));
    }
}

impl Screen {
    #[inline]
    pub(super) fn get(&self, i: u32) -> &ScreenTri {
        let i = i as usize;
        &self.chunks[i / (CHUNK * FAN_MAX)][i % (CHUNK * FAN_MAX)]
    }

    /// Every triangle with its address, in submission order.
    pub(super) fn iter(&self) -> impl Iterator<Item = (u32, &ScreenTri)> {
        self.chunks.iter().enumerate().flat_map(|(c, chunk)| {
            let base = (c * CHUNK * FAN_MAX) as u32;
            chunk
                .iter()
                .enumerate()
                .map(move |(j, t)| (base + j as u32, t))
        })
    }
}

/// Screen triangles of `count` triangles whose clip-space vertices `clip(i)` gives.
fn setup(
    pool: &Arc<Pool>,
    count: usize,
    clip: impl Fn(usize) -> [Vec4; 3] + Sync,
    width: u32,
    height: u32,
    faces: Faces,
) -> Screen {
    let (w, h) = (width as f64, height as f64);
    let chunks = (0..count.div_ceil(CHUNK))
        .into_par_iter()
        .map(|c| {
            let indices = c * CHUNK..(c * CHUNK + CHUNK).min(count);
            let mut out = pool.take(CHUNK);
            indices.for_each(|index| set_up(index, clip(index), (w, h), faces, &mut out));
            out
        })
        .collect();
    Screen {
        chunks,
        pool: pool.clone(),
    }
}

/// Appends the screen triangles of input triangle `index` (clip-space vertices `tri`) on a
/// `w x h` target to `out`.
fn set_up(
    index: usize,
    tri: [Vec4; 3],
    (w, h): (f64, f64),
    faces: Faces,
    out: &mut Vec<ScreenTri>,
) {
    let cv = |k: usize, bary: Vec3| ClipVertex { pos: tri[k], bary };
    let corners = [cv(0, Vec3::X), cv(1, Vec3::Y), cv(2, Vec3::Z)];
    // Reversed Z: 0 <= z <= w; plus a guard band on x and y that keeps fixed point small.
    // Most triangles lie inside every plane and skip clipping.
    let inside = |p: Vec4| {
        p.z <= p.w && p.z >= 0.0 && p.x.abs() <= GUARD_BAND * p.w && p.y.abs() <= GUARD_BAND * p.w
    };
    let vert = |v: &ClipVertex| {
        let inv_w = 1.0 / v.pos.w as f64;
        let fx = (v.pos.x as f64 * inv_w * 0.5 + 0.5) * w;
        let fy = (0.5 - v.pos.y as f64 * inv_w * 0.5) * h;
        Vert {
            x: (fx * SUB).round() as i64,
            y: (fy * SUB).round() as i64,
            fx,
            fy,
            z: v.pos.z as f64 * inv_w,
            inv_w,
            bary: v.bary,
        }
    };
    if corners.iter().all(|v| inside(v.pos) && v.pos.w > 0.0) {
        if let Some(t) = screen_tri(corners.map(|v| vert(&v)), index as u32, faces) {
            out.push(t);
        }
        return;
    }
    let mut poly = Poly {
        v: [corners[0]; 10],
        n: 3,
    };
    poly.v[..3].copy_from_slice(&corners);
    poly = poly.clip(|p| p.w - p.z);
    poly = poly.clip(|p| p.z);
    for (sx, sy) in [(1.0, 0.0), (-1.0, 0.0), (0.0, 1.0), (0.0, -1.0)] {
        if poly.n < 3 {
            break;
        }
        poly = poly.clip(|p| GUARD_BAND * p.w - sx * p.x - sy * p.y);
    }
    if poly.n < 3 || poly.v[..poly.n].iter().any(|v| v.pos.w <= 0.0) {
        return;
    }
    let v0 = vert(&poly.v[0]);
    for k in 1..poly.n - 1 {
        if let Some(t) = screen_tri(
            [v0, vert(&poly.v[k]), vert(&poly.v[k + 1])],
            index as u32,
            faces,
        ) {
            out.push(t);
        }
    }
}

/// A projected vertex: snapped fixed-point position (coverage), float position (interpolation).
#[derive(Clone, Copy)]
struct Vert {
    x: i64,
    y: i64,
    fx: f64,
    fy: f64,
    z: f64,
    inv_w: f64,
    bary: Vec3,
}

fn screen_tri(v: [Vert; 3], triangle: u32, faces: Faces) -> Option<ScreenTri> {
    let mut v = v;
    let (snap, swapped) = SnappedTri::new(v.map(|v| v.x), v.map(|v| v.y))?;
    // y points down on screen, so a counter-clockwise (front) triangle in NDC is clockwise here
    // (negative area): swapped into the positive orientation.
    if faces == Faces::Back && swapped {
        return None;
    }
    if swapped {
        v.swap(1, 2);
    }
    let texels = snap.texel_box();
    let fx = [v[0].fx, v[1].fx, v[2].fx];
    let fy = [v[0].fy, v[1].fy, v[2].fy];
    let farea = (fx[1] - fx[0]) * (fy[2] - fy[0]) - (fy[1] - fy[0]) * (fx[2] - fx[0]);
    let z = [v[0].z, v[1].z, v[2].z];
    // Weight i is edge (i + 1, i + 2)'s function over the area.
    let edge = |i: usize| ((i + 1) % 3, (i + 2) % 3);
    let slope = [0, 1, 2].map(|i| {
        let (a, b) = edge(i);
        -(fy[b] - fy[a]) / farea
    });
    let down = [0, 1, 2].map(|i| {
        let (a, b) = edge(i);
        (fx[b] - fx[a]) / farea
    });
    let dz = [
        slope[0] * z[0] + slope[1] * z[1] + slope[2] * z[2],
        down[0] * z[0] + down[1] * z[1] + down[2] * z[2],
    ];
    Some(ScreenTri {
        snap,
        texels,
        rows: snap.rows(texels.2),
        fx,
        fy,
        farea,
        planar: farea.abs() > 1e-12,
        slope,
        dz,
        z,
        inv_w: [v[0].inv_w, v[1].inv_w, v[2].inv_w],
        bary: [v[0].bary, v[1].bary, v[2].bary],
        triangle,
    })
}

/// Screen triangles of world-space `tris` seen through `view`.
pub(super) fn setup_world(
    pool: &Arc<Pool>,
    view: &View,
    width: u32,
    height: u32,
    tris: &[[Vec3; 3]],
    faces: Faces,
) -> Screen {
    let vp = view.view_projection();
    setup(
        pool,
        tris.len(),
        |i| tris[i].map(|p| vp * p.extend(1.0)),
        width,
        height,
        faces,
    )
}
