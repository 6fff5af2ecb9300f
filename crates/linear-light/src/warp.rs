//! Warping skins into a neighbouring sample's view (section 3.2), on the CPU.
//!
//! The skins are rasterized through the destination view with a nearest-surface depth test, and
//! a skin fragment counts only where it lies in front of (or on) the destination's own depth map:
//! that map is the depth buffer the warped non-skin triangles of the source would approximate,
//! without rasterizing the source's `2 (resolution - 1)²` surface triangles. The value is interpolated
//! linearly in screen space (as `@interpolate(linear)` does in `skins.wgsl`), so across a
//! receiver parallel to the map's image plane the transition is exactly linear.
//!
//! A skin ends on the first receiver texel centre past the edge in the source map, so it can
//! overhang by up to a texel onto points the source does see, which would count their piece
//! twice. So the channel takes the skin only where the source does not see the texel's surface
//! point, with the same four-tap depth test evaluation applies ([`lit_fraction`]): the texel
//! adds `(s v - s / 2) (1 - lit)` for a piece of share `s`, and the piece sums to `s` across the
//! source's shadow edge.

use crate::skins::{Skin, Unproject};
use glam::{DVec2, Vec3};
use rayon::prelude::*;
use soft_shadow_core::map2d::bilinear_texels;
use soft_shadow_core::pool::Pool;
use soft_shadow_core::raster::rasterize_nearest;
use soft_shadow_core::view::{NO_OCCLUDER, View};
use soft_shadow_core::{Map2D, MapParams};
use std::sync::Arc;

/// Relative depth tolerance of a skin fragment against the destination's depth map.
pub(crate) const SKIN_DEPTH_TOLERANCE: f32 = 1e-3;

/// Where no skin covers a texel of the GPU warp's output (changes lie in `[-1/2, 1/2]`).
#[cfg(feature = "gpu")]
pub(crate) const NO_SKIN: f32 = -1.0;

/// The fraction of the four bilinear taps around world point `p` in map `m` (linear depths
/// `depth`) that it passes, with the relative depth tolerance `t`; 1 outside the map, as
/// evaluation counts it. `skins.wgsl`'s `lit_fraction`.
pub(crate) fn lit_fraction(m: &MapParams, depth: &Map2D<f32>, p: Vec3, t: f32) -> f32 {
    let clip = glam::Mat4::from_cols_array(&m.view_proj) * p.extend(1.0);
    if clip.w <= 0.0 {
        return 1.0;
    }
    let (nx, ny) = (clip.x / clip.w, clip.y / clip.w);
    if nx.abs() > 1.0 || ny.abs() > 1.0 {
        return 1.0;
    }
    let r = m.resolution as f32;
    let st = glam::Vec2::new((nx * 0.5 + 0.5) * r, (0.5 - ny * 0.5) * r);
    let z = m.linear_depth(p);
    let mut lit = 0.0;
    for (x, y, w) in bilinear_texels(st, m.resolution, m.resolution) {
        if z <= *depth.get(x, y) * (1.0 + t) {
            lit += w;
        }
    }
    lit
}

/// The map a skin came from: its parameters, linear depths and the discontinuity threshold.
pub(crate) struct Source<'a> {
    /// The source's map parameters.
    pub params: &'a MapParams,
    /// The source's linear depths.
    pub depth: &'a Map2D<f32>,
    /// The relative depth tolerance of [`lit_fraction`].
    pub threshold: f32,
    /// Share `s` of the piece between the source and the destination.
    pub piece: f32,
}

/// Adds to `channel` (the `resolution`-wide map of `view` whose linear depths are `depth`) the change
/// `(s v - s / 2) (1 - lit)` at each texel a skin covers; the others keep their value. (The GPU
/// warps into a texture cleared to `NO_SKIN` and adds it where it holds a change, which is
/// never `NO_SKIN`: the same sums.)
pub(crate) fn warp(
    pool: &Arc<Pool>,
    skins: &[Skin],
    view: &View,
    depth: &Map2D<f32>,
    src: &Source,
    channel: &mut Map2D<f32>,
) {
    let resolution = depth.width();
    let un = Unproject::new(view, resolution);
    let tris: Vec<[Vec3; 3]> = skins.iter().map(|s| s.vertices).collect();
    let frags = rasterize_nearest(pool, view, resolution, resolution, &tris);
    let vp = view.view_projection();
    let r = resolution as f64;
    let screen = |p: Vec3| {
        let c = vp * p.extend(1.0);
        let w = c.w as f64;
        DVec2::new(
            (c.x as f64 / w * 0.5 + 0.5) * r,
            (0.5 - c.y as f64 / w * 0.5) * r,
        )
    };
    // Each skin's screen corners and doubled area, once per skin rather than per texel.
    let corners: Vec<([DVec2; 3], f64)> = skins
        .par_iter()
        .map(|s| {
            let [a, b, c] = s.vertices.map(screen);
            ([a, b, c], (b - a).perp_dot(c - a))
        })
        .collect();
    let w = (resolution as usize).max(1);
    channel
        .data_mut()
        .par_chunks_mut(w)
        .zip(frags.data().par_chunks(w))
        .enumerate()
        .for_each(|(y, (row, frags))| {
            let y = y as u32;
            for ((x, o), f) in (0u32..).zip(row.iter_mut()).zip(frags) {
                if !f.is_covered() {
                    continue;
                }
                let z = view.linear_depth_from_ndc(f.z_ndc);
                let d = *depth.get(x, y);
                if d < NO_OCCLUDER && z > d * (1.0 + SKIN_DEPTH_TOLERANCE) {
                    continue;
                }
                let unseen = if d < NO_OCCLUDER {
                    1.0 - lit_fraction(src.params, src.depth, un.point(x, y, d), src.threshold)
                } else {
                    1.0
                };
                let s = &skins[f.triangle as usize];
                let ([a, b, c], area) = corners[f.triangle as usize];
                let p = DVec2::new(x as f64 + 0.5, y as f64 + 0.5);
                let value = if area.abs() > 1e-12 {
                    let l1 = (c - b).perp_dot(p - b) / area;
                    let l2 = (a - c).perp_dot(p - c) / area;
                    let l3 = 1.0 - l1 - l2;
                    (l1 * s.values[0] as f64 + l2 * s.values[1] as f64 + l3 * s.values[2] as f64)
                        as f32
                } else {
                    s.values[0]
                };
                let v = value.clamp(0.0, 1.0);
                *o += (src.piece * v - 0.5 * src.piece) * unseen;
            }
        });
}
