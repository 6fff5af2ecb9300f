//! Skins (section 3.2): the depth samples of one sample's map, triangulated as a grid, give
//! "phantom" triangles wherever they span a depth discontinuity. Those skins connect an occluder
//! edge to the receiver behind it, so, seen from a neighbouring sample, they cover exactly the
//! points that one sample sees and the other does not: the penumbra of the piece between them.
//!
//! Discontinuities are found with a Laplacian of *inverse* depth (the paper uses a 3x3
//! Laplacian-of-Gaussian of depth): `1 / z` is affine in the image over any plane, so planes,
//! however steep, give no response, and an edge is where `|laplacian(1/z)| > t / z`. A grid
//! triangle touching an edge texel is a skin when its farthest vertex lies beyond its nearest by
//! more than the fraction `t`. Its vertices take 0 on the occluder side (nearer than the
//! midpoint of the triangle's depth range) and 1 on the receiver side.
//!
//! `skins.wgsl` builds the same triangles in a vertex shader.

use glam::{Mat4, Vec3};
use rayon::prelude::*;
use soft_shadow_core::Map2D;
use soft_shadow_core::pool::Pool;
use soft_shadow_core::view::{NO_OCCLUDER, ProjectionKind, View};
use std::sync::Arc;

/// The triangles of the *grid* maps skins are built from: the casters plus every receiver that
/// does not cast.
///
/// Maps cover what casts, and the depth maps the shading tests hold casters only. But a skin
/// joins an occluder edge to the receiver *behind* it (section 3.2): over empty texels an edge
/// has no far end and no skin, and the penumbra reads as one flat step (V = 0.5 with 2 samples
/// across the whole penumbra of Heidrich's Figure 9 scene, rms 28.0 against 10 point samples'
/// 4.0). So skins and their warps read a second depth map per sample that also holds the
/// receivers; the shading test keeps the casters-only map, so a receiver-only mesh still casts
/// nothing.
pub(crate) fn grid_geometry(geometry: &soft_shadow_core::SceneGeometry) -> Vec<[Vec3; 3]> {
    geometry.surfaces()
}

/// One skin triangle: world positions and the Gouraud values of its vertices.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Skin {
    /// World-space vertices.
    pub vertices: [Vec3; 3],
    /// 0 on the occluder, 1 on the receiver.
    pub values: [f32; 3],
}

/// The grid triangles of a quad with top-left texel `(x, y)`: `(a, b, c)` and `(b, d, c)`.
pub(crate) const QUAD_TRIANGLES: [[(u32, u32); 3]; 2] =
    [[(0, 0), (1, 0), (0, 1)], [(1, 0), (1, 1), (0, 1)]];

/// Unprojects texel centres of a map rendered through a view.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Unproject {
    /// View to world.
    pub inv_view: Mat4,
    /// `x_view = ndc_x * z / sx` (perspective) or `ndc_x / sx` (orthographic).
    pub sx: f32,
    /// Same for y.
    pub sy: f32,
    /// Whether the view is orthographic.
    pub ortho: bool,
    /// Map side.
    pub resolution: u32,
}

impl Unproject {
    /// The unprojection of `view` for a `resolution`-wide map.
    pub(crate) fn new(view: &View, resolution: u32) -> Self {
        let p = view.projection();
        Self {
            inv_view: view.view.inverse(),
            sx: p.x_axis.x,
            sy: p.y_axis.y,
            ortho: matches!(view.kind, ProjectionKind::Orthographic { .. }),
            resolution,
        }
    }

    /// The world point of texel `(x, y)`'s centre at linear depth `z`.
    pub(crate) fn point(&self, x: u32, y: u32, z: f32) -> Vec3 {
        let r = self.resolution as f32;
        let nx = (x as f32 + 0.5) / r * 2.0 - 1.0;
        let ny = 1.0 - (y as f32 + 0.5) / r * 2.0;
        let (vx, vy) = if self.ortho {
            (nx / self.sx, ny / self.sy)
        } else {
            (nx * z / self.sx, ny * z / self.sy)
        };
        self.inv_view.transform_point3(Vec3::new(vx, vy, -z))
    }
}

/// Edge flags of a linear depth map: `|4 w - sum of the 4 neighbours' w| > t w` with `w = 1/z`
/// (empty texels have `w = 0`). A neighbour beyond the border is extrapolated linearly from the
/// other side (`2 w - w_opposite`), so a plane stays free of edges up to the border.
pub(crate) fn edges(pool: &Arc<Pool>, depth: &Map2D<f32>, t: f32) -> Map2D<bool> {
    let (w, h) = (depth.width() as usize, depth.height() as usize);
    let rows = w.max(1);
    // `w = 1/z` once per texel (its five readers share it).
    let mut inv = pool.overwrite(w * h, 0.0f32);
    inv.par_chunks_mut(rows)
        .zip(depth.data().par_chunks(rows))
        .for_each(|(o, d)| {
            for (o, &z) in o.iter_mut().zip(d) {
                *o = if z >= NO_OCCLUDER { 0.0 } else { 1.0 / z };
            }
        });
    let mut data = pool.overwrite(w * h, false);
    // The flag from a texel's `w` and its neighbours' sums along x and y.
    let edge = |c: f32, sx: f32, sy: f32| {
        let lap = 4.0 * c - sx - sy;
        c > 0.0 && lap.abs() > t * c
    };
    data.par_chunks_mut(rows).enumerate().for_each(|(y, row)| {
        let line = |y: usize| &inv[y * w..(y + 1) * w];
        let here = line(y);
        // Both neighbours inside: their sum; one missing: extrapolated, the sum is 2c.
        let sy = |x: usize| 2.0 * here[x];
        let ends = [0, w - 1];
        if y > 0 && y + 1 < h {
            let (up, down) = (line(y - 1), line(y + 1));
            // The interior of the row: both sums of neighbours, in slices (no branch).
            for (((e, c), u), d) in row[1..]
                .iter_mut()
                .zip(here.windows(3))
                .zip(&up[1..])
                .zip(&down[1..])
            {
                *e = edge(c[1], c[0] + c[2], u + d);
            }
            for x in ends {
                row[x] = edge(here[x], 2.0 * here[x], up[x] + down[x]);
            }
        } else {
            for (x, (e, c)) in row[1..].iter_mut().zip(here.windows(3)).enumerate() {
                *e = edge(c[1], c[0] + c[2], sy(x + 1));
            }
            for x in ends {
                row[x] = edge(here[x], 2.0 * here[x], sy(x));
            }
        }
    });
    pool.give(inv);
    Map2D::from_vec(w as u32, h as u32, data)
        .unwrap_or_else(|| Map2D::new(0, 0, false))
        .returning_to(pool)
}

/// The Gouraud values of a grid triangle with linear depths `z`, or `None` when it spans no
/// discontinuity: `(max - min) > t * min`, vertices beyond the midpoint are the receiver (1).
pub(crate) fn skin_values(z: [f32; 3], t: f32) -> Option<[f32; 3]> {
    let lo = z[0].min(z[1]).min(z[2]);
    let hi = z[0].max(z[1]).max(z[2]);
    if hi - lo <= t * lo {
        return None;
    }
    let mid = 0.5 * (lo + hi);
    Some(z.map(|v| if v > mid { 1.0 } else { 0.0 }))
}

/// Every skin of the map `depth` seen through `view`.
pub(crate) fn skins(pool: &Arc<Pool>, view: &View, depth: &Map2D<f32>, t: f32) -> Vec<Skin> {
    let resolution = depth.width();
    if resolution < 2 {
        return Vec::new();
    }
    let un = Unproject::new(view, resolution);
    let edge = edges(pool, depth, t);
    let w = resolution as usize;
    (0..resolution - 1)
        .into_par_iter()
        .flat_map_iter(|y| {
            let mut row = Vec::new();
            // The quad of texels (x, y)..=(x + 1, y + 1) spans a skin when all four have a
            // surface and one is an edge: tested on the two rows as slices, without branches.
            let (d, e, y0) = (depth.data(), edge.data(), y as usize * w);
            let (d0, d1) = (&d[y0..y0 + w], &d[y0 + w..y0 + 2 * w]);
            let (e0, e1) = (&e[y0..y0 + w], &e[y0 + w..y0 + 2 * w]);
            for x in 0..resolution - 1 {
                let i = x as usize;
                let solid = (d0[i] < NO_OCCLUDER)
                    & (d0[i + 1] < NO_OCCLUDER)
                    & (d1[i] < NO_OCCLUDER)
                    & (d1[i + 1] < NO_OCCLUDER);
                let edged = e0[i] | e0[i + 1] | e1[i] | e1[i + 1];
                if !(solid & edged) {
                    continue;
                }
                for tri in &QUAD_TRIANGLES {
                    let t3 = tri.map(|(dx, dy)| (x + dx, y + dy));
                    let z = t3.map(|(u, v)| *depth.get(u, v));
                    if let Some(values) = skin_values(z, t) {
                        row.push(Skin {
                            vertices: [0, 1, 2].map(|k| un.point(t3[k].0, t3[k].1, z[k])),
                            values,
                        });
                    }
                }
            }
            row
        })
        .collect()
}
