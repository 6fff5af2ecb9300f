//! Generation from a depth image (`Generator::DepthImage`), CPU side; `depth_image.wgsl`
//! is the GPU side. For scenes whose silhouettes are not worth enumerating (foliage).
//!
//! 1. **Edges.** In the nearest-geometry map `D` (normalised), texel `t` is on the *near side* of
//!    an occluder edge when a 4-neighbour `n` is deeper by more than
//!    `gap(t) = layer_gap texels + 2 |D(t) - D(t - (n - t))|`: the jump must beat the local
//!    slope (twice the step on the far side of `t`), so a steep but continuous surface is no
//!    edge. The neighbour `n` is then on the *far side*.
//! 2. **Propagation.** The exact nearest-seed map (`crate::feature_transform`) gives
//!    every texel its nearest near-side seed `A` and far-side seed `B`; of equally near
//!    near-side seeds, the one nearest the light (least `D`), whose occluder shades every
//!    receiver the farther one does. A texel nearer to `A` is inside the silhouette; the edge
//!    lies half a texel beyond the last seed, so the signed distance is `w = -(|B| - 1/2)`
//!    inside and `w = |A| - 1/2` outside (texels).
//! 3. **Limits.** `c = D(A)`, `p_i = w s r` (`s r` = [`Warp::p_per_texel`]) where `|w|` is within
//!    the edge's ribbon ([`Warp::ribbon_texels`]), and the lower limit is the geometry itself
//!    (plus `layer_gap` texels) where it lies deeper than `c` by more than the gap: a surface
//!    below the occluder hides what is under it. Inside the silhouette, where the edge's far
//!    side `B` is geometry deeper than `c` (an edge of a body over its own farther surface),
//!    the lower limit is `D(B)` (plus the gap): the far surface hides what lies below it too,
//!    so the ribbon's inner half does not light the ground under both (holes of light in the
//!    umbra under the bunny at 1280 x 720).

use crate::combine::NO_EDGE;
use crate::feature_transform::nearest;
use crate::storage::MAX_P;
use crate::warp::{NONE_DEPTH, Warp};
use rayon::prelude::*;
use soft_shadow_core::Map2D;
use soft_shadow_core::pool::Pool;
use soft_shadow_core::seeds::{NONE, dist2, pack};
use std::sync::Arc;

/// Whether `t = (x, y)` is on the near side of an edge towards neighbour `(x, y) + d`.
#[inline(always)]
#[cfg(test)]
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

/// Bits of an edge mask: which 4-neighbours of a texel (left `(-1, 0)`, right `(1, 0)`, up
/// `(0, -1)`, down `(0, 1)`) it is on the near side towards ([`near_side`]).
const LEFT: u8 = 1;
const RIGHT: u8 = 2;
const UP: u8 = 4;
const DOWN: u8 = 8;

/// [`near_side`] of every texel of row `y` towards each 4-neighbour, as a mask of the bits
/// above: the same comparison, with the texel's gap computed once instead of once per test.
fn edge_masks(geom: &Map2D<f32>, warp: &Warp, layer_gap: f32, y: usize, out: &mut [u8]) {
    let (w, h) = (geom.width() as usize, geom.height() as usize);
    let d = geom.data();
    let row = |y: usize| &d[y * w..(y + 1) * w];
    let here = row(y);
    // A missing neighbour row is never deeper (no edge towards it); a missing row behind the
    // texel is clamped to the texel's own row, as `get_clamped` does.
    let up = (y > 0).then(|| row(y - 1));
    let down = (y + 1 < h).then(|| row(y + 1));
    let (behind_up, behind_down) = (down.unwrap_or(here), up.unwrap_or(here));
    let edge = |dt: f32, gap: f32, dn: f32, back: f32| {
        let slope = if back < NONE_DEPTH {
            (dt - back).abs()
        } else {
            0.0
        };
        dn - dt > gap + 2.0 * slope
    };
    for (x, m) in out.iter_mut().enumerate() {
        let dt = here[x];
        if dt >= NONE_DEPTH {
            *m = 0;
            continue;
        }
        let gap = warp.depth_gap(warp.linear(dt), layer_gap);
        let (left, right) = (x.saturating_sub(1), (x + 1).min(w - 1));
        let mut mask = 0;
        if x > 0 && edge(dt, gap, here[left], here[right]) {
            mask |= LEFT;
        }
        if x + 1 < w && edge(dt, gap, here[right], here[left]) {
            mask |= RIGHT;
        }
        if let Some(up) = up
            && edge(dt, gap, up[x], behind_up[x])
        {
            mask |= UP;
        }
        if let Some(down) = down
            && edge(dt, gap, down[x], behind_down[x])
        {
            mask |= DOWN;
        }
        *m = mask;
    }
}

/// The seeds of step 1: `(near side, far side)`, packed texel coordinates or [`NONE`]. A texel
/// is a near-side seed when it is on the near side of an edge towards some 4-neighbour
/// ([`near_side`]), a far-side seed when some 4-neighbour is on the near side towards it; both
/// from one mask per texel of its [`near_side`] tests.
pub(crate) fn seeds(
    pool: &Pool,
    geom: &Map2D<f32>,
    warp: &Warp,
    layer_gap: f32,
) -> (Vec<u32>, Vec<u32>) {
    let (w, h) = (geom.width() as usize, geom.height() as usize);
    let n = w * h;
    let mut masks: Vec<u8> = pool.overwrite(n, 0);
    masks
        .par_chunks_mut(w.max(1))
        .enumerate()
        .for_each(|(y, out)| edge_masks(geom, warp, layer_gap, y, out));
    let (mut near, mut far): (Vec<u32>, Vec<u32>) =
        (pool.overwrite(n, NONE), pool.overwrite(n, NONE));
    near.par_chunks_mut(w.max(1))
        .zip(far.par_chunks_mut(w.max(1)))
        .enumerate()
        .for_each(|(y, (near, far))| {
            let row = |y: usize| &masks[y * w..(y + 1) * w];
            let here = row(y);
            let up = (y > 0).then(|| row(y - 1));
            let down = (y + 1 < h).then(|| row(y + 1));
            for x in 0..w {
                let me = pack(x as u32, y as u32);
                near[x] = if here[x] != 0 { me } else { NONE };
                // A neighbour on the near side towards this texel: the left one's right bit,
                // and so on.
                let seen = (x > 0 && here[x - 1] & RIGHT != 0)
                    || (x + 1 < w && here[x + 1] & LEFT != 0)
                    || up.is_some_and(|up| up[x] & DOWN != 0)
                    || down.is_some_and(|down| down[x] & UP != 0);
                far[x] = if seen { me } else { NONE };
            }
        });
    pool.give(masks);
    (near, far)
}

/// How far (texels) from its nearest seeds a texel can lie and still be in a ribbon: where
/// either seed is farther, step 3 writes [`NO_EDGE`] without reading depths or taking square
/// roots. A texel's `|w|` is the larger of its two seeds' distances less 1/2 (step 2), and the
/// widest ribbon is an edge's at the nearest depth, [`Warp::ribbon_texels`] at 0 (seeds are
/// casters' texels, at or beyond the near plane), so a texel with a seed more than
/// `ribbon_texels(0) + 1/2` away is in no ribbon. One more texel covers the rounding of depths
/// at the near plane.
pub(crate) fn ribbon_reach(warp: &Warp) -> u32 {
    // Saturating: a light too small for its ribbons to fit the map skips no texel.
    (warp.ribbon_texels(0.0) + 1.5).ceil() as u32
}

/// Steps 2 and 3 for one texel, from its nearest seeds: `([c, p_i], lower)`.
pub(crate) fn texel_limits(
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
    let far_d = *geom.get(far & 0xffff, far >> 16);
    let gap_c = warp.depth_gap(warp.linear(c), layer_gap);
    let lower = if d < NONE_DEPTH && d > c + gap_c {
        (d + warp.depth_gap(warp.linear(d), layer_gap)).min(NONE_DEPTH)
    } else if w < 0.0 && far_d < NONE_DEPTH && far_d > c + gap_c {
        // Inside an edge whose far side is geometry too (a body over its own farther surface):
        // what lies below that far surface is hidden by it as well.
        (far_d + warp.depth_gap(warp.linear(far_d), layer_gap)).min(NONE_DEPTH)
    } else {
        NONE_DEPTH
    };
    ([c, p], lower)
}

/// The edge and lower-limit layers from the geometry map.
pub(crate) fn limits(
    pool: &Arc<Pool>,
    geom: &Map2D<f32>,
    warp: &Warp,
    layer_gap: f32,
) -> (Map2D<[f32; 2]>, Map2D<f32>) {
    let resolution = geom.width();
    let (a, b) = seeds(pool, geom, warp, layer_gap);
    // Ties between near-side seeds to the nearer depth (step 2); only the far side's distance
    // is read.
    let (a, b) = (
        nearest(pool, a, resolution, Some(geom.data())),
        nearest(pool, b, resolution, None),
    );
    let n = (resolution * resolution) as usize;
    // Every texel is written below: no clearing pass.
    let (mut edge, mut lower) = (pool.overwrite(n, NO_EDGE), pool.overwrite(n, NONE_DEPTH));
    // Beyond the reach no texel is in a ribbon: skip the square roots and the depth reads there.
    let reach2 = (ribbon_reach(warp) as i64).pow(2);
    // Row by row: a texel's coordinates come from its row and place in it, not from a
    // division of its index (a division per texel measured 18.6 ms against 11.3 for the whole
    // step on `torus` at 2048²).
    let w = (resolution as usize).max(1);
    edge.par_chunks_mut(w)
        .zip(lower.par_chunks_mut(w))
        .enumerate()
        .for_each(|(y, (edge, lower))| {
            let seeds = a[y * w..].iter().zip(&b[y * w..]);
            for (x, ((e, l), (&near, &far))) in edge.iter_mut().zip(lower).zip(seeds).enumerate() {
                let (x, y) = (x as u32, y as u32);
                let beyond = |s: u32| dist2(x as i32, y as i32, s) > reach2;
                (*e, *l) = if near == NONE || far == NONE || beyond(near) || beyond(far) {
                    (NO_EDGE, NONE_DEPTH)
                } else {
                    texel_limits(geom, warp, layer_gap, x, y, near, far)
                };
            }
        });
    pool.give(a);
    pool.give(b);
    (
        Map2D::from_vec(resolution, resolution, edge)
            .unwrap_or_else(|| Map2D::new(0, 0, NO_EDGE))
            .returning_to(pool),
        Map2D::from_vec(resolution, resolution, lower)
            .unwrap_or_else(|| Map2D::new(0, 0, NONE_DEPTH))
            .returning_to(pool),
    )
}
