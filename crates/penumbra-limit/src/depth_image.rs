//! Generation from a depth image (the second generator), CPU side; `depth_image.wgsl`
//! is the GPU side. For scenes whose silhouettes are not worth enumerating (foliage).
//!
//! 1. **Edges.** In the nearest-geometry map `D` (normalised), texel `t` is on the *near side* of
//!    an occluder edge when a 4-neighbour `n` is deeper by more than
//!    `gap(t) = layer_gap texels + 2 |D(t) - D(t - (n - t))|`: the jump must beat the local
//!    slope (twice the step on the far side of `t`), so a steep but continuous surface is no
//!    edge. The neighbour `n` is then on the *far side*.
//! 2. **Propagation.** Jump flooding ([`shadow_core::jump_flood`]) gives every texel its nearest
//!    near-side seed `A` and far-side seed `B`. A texel nearer to `A` is inside the silhouette;
//!    the edge lies half a texel beyond the last seed, so the signed distance is
//!    `w = -(|B| - 1/2)` inside and `w = |A| - 1/2` outside (texels).
//! 3. **Limits.** `c = D(A)`, `p_i = w s r` (`s r` = [`Warp::p_per_texel`]) where `|w|` is within
//!    the edge's ribbon ([`Warp::ribbon_texels`]), and the lower limit is the geometry itself
//!    (plus `layer_gap` texels) where it lies deeper than `c` by more than the gap: a surface
//!    below the occluder hides what is under it.

use crate::combine::NO_EDGE;
use crate::storage::MAX_P;
use crate::warp::{NONE_DEPTH, Warp};
use rayon::prelude::*;
use shadow_core::jump_flood::{NONE, dist2, flood, pack};
use shadow_core::{Map2D, pool};

const NEIGHBOURS: [(i64, i64); 4] = [(-1, 0), (1, 0), (0, -1), (0, 1)];

/// Whether `t = (x, y)` is on the near side of an edge towards neighbour `(x, y) + d`.
#[inline(always)]
pub fn near_side(
    geom: &Map2D<f32>,
    warp: &Warp,
    layer_gap: f32,
    x: i64,
    y: i64,
    d: (i64, i64),
) -> bool {
    let (w, h) = (geom.width() as i64, geom.height() as i64);
    let (nx, ny) = (x + d.0, y + d.1);
    let outside = |x: i64, y: i64| x < 0 || y < 0 || x >= w || y >= h;
    if outside(x, y) || outside(nx, ny) {
        return false;
    }
    let dt = *geom.get(x as u32, y as u32);
    if dt >= NONE_DEPTH {
        return false;
    }
    let dn = *geom.get(nx as u32, ny as u32);
    let back = *geom.get_clamped(x - d.0, y - d.1);
    let slope = if back < NONE_DEPTH {
        (dt - back).abs()
    } else {
        0.0
    };
    dn - dt > warp.depth_gap(warp.linear(dt), layer_gap) + 2.0 * slope
}

/// The seeds of step 1: `(near side, far side)`, packed texel coordinates or [`NONE`].
pub fn seeds(geom: &Map2D<f32>, warp: &Warp, layer_gap: f32) -> (Vec<u32>, Vec<u32>) {
    let (w, h) = (geom.width(), geom.height());
    let n = (w * h) as usize;
    let (mut near, mut far) = (pool::take(n), pool::take(n));
    (0..w * h)
        .into_par_iter()
        .map(|i| {
            let (x, y) = ((i % w) as i64, (i / w) as i64);
            let a = NEIGHBOURS
                .iter()
                .any(|&d| near_side(geom, warp, layer_gap, x, y, d));
            let b = NEIGHBOURS
                .iter()
                .any(|&d| near_side(geom, warp, layer_gap, x + d.0, y + d.1, (-d.0, -d.1)));
            let me = pack(x as u32, y as u32);
            (if a { me } else { NONE }, if b { me } else { NONE })
        })
        .unzip_into_vecs(&mut near, &mut far);
    (near, far)
}

/// Steps 2 and 3 for one texel, from its nearest seeds: `([c, p_i], lower)`.
pub fn texel_limits(
    geom: &Map2D<f32>,
    warp: &Warp,
    layer_gap: f32,
    x: u32,
    y: u32,
    near: u32,
    far: u32,
) -> ([f32; 2], f32) {
    if near == NONE || far == NONE {
        return (NO_EDGE, NONE_DEPTH);
    }
    let (xi, yi) = (x as i32, y as i32);
    let da = (dist2(xi, yi, near) as f32).sqrt();
    let db = (dist2(xi, yi, far) as f32).sqrt();
    let w = if da < db { -(db - 0.5) } else { da - 0.5 };
    let c = *geom.get(near & 0xffff, near >> 16);
    if w.abs() > warp.ribbon_texels(c) {
        return (NO_EDGE, NONE_DEPTH);
    }
    let p = (w * warp.p_per_texel).clamp(-MAX_P, MAX_P);
    let d = *geom.get(x, y);
    let lower = if d < NONE_DEPTH && d > c + warp.depth_gap(warp.linear(c), layer_gap) {
        (d + warp.depth_gap(warp.linear(d), layer_gap)).min(NONE_DEPTH)
    } else {
        NONE_DEPTH
    };
    ([c, p], lower)
}

/// The edge and lower-limit layers from the geometry map.
pub fn limits(geom: &Map2D<f32>, warp: &Warp, layer_gap: f32) -> (Map2D<[f32; 2]>, Map2D<f32>) {
    let res = geom.width();
    let (a, b) = seeds(geom, warp, layer_gap);
    let (a, b) = (flood(a, res), flood(b, res));
    let n = (res * res) as usize;
    let (mut edge, mut lower) = (pool::take(n), pool::take(n));
    (0..res * res)
        .into_par_iter()
        .map(|i| {
            let (x, y) = (i % res, i / res);
            texel_limits(geom, warp, layer_gap, x, y, a[i as usize], b[i as usize])
        })
        .unzip_into_vecs(&mut edge, &mut lower);
    pool::give(a);
    pool::give(b);
    (
        Map2D::from_vec(res, res, edge).unwrap_or_else(|| Map2D::new(0, 0, NO_EDGE)),
        Map2D::from_vec(res, res, lower).unwrap_or_else(|| Map2D::new(0, 0, NONE_DEPTH)),
    )
}
