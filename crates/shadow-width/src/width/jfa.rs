//! The width map by jump flooding ([`crate::jump_flood`]): the seeds are the unblocked
//! texels, so every blocked texel learns its nearest unblocked one. `width.wgsl` seeds and
//! resolves on the GPU, the jump-flood kernel floods, in the same order as here.

use crate::jump_flood::flood;
use soft_shadow_core::Map2D;
use soft_shadow_core::pool::Pool;
use soft_shadow_core::seeds::{NONE, dist2, pack};
use std::sync::Arc;

/// The jump-flooded width map of `mask`, capped at [`super::cap`].
pub(crate) fn width(pool: &Arc<Pool>, mask: &Map2D<bool>) -> Map2D<f32> {
    let resolution = mask.width();
    let mut seeds = pool.take(mask.data().len());
    seeds.extend(mask.data().iter().enumerate().map(|(i, &b)| {
        if b {
            NONE
        } else {
            pack(i as u32 % resolution, i as u32 / resolution)
        }
    }));
    let nearest = flood(pool, seeds, resolution);
    let cap = super::cap(resolution);
    let w = Map2D::from_par_fn(Some(pool), resolution, mask.height(), |i| {
        let s = nearest[i];
        if s == NONE {
            cap
        } else {
            let (x, y) = (i as u32 % resolution, i as u32 / resolution);
            (dist2(x as i32, y as i32, s) as f32).sqrt().min(cap)
        }
    });
    pool.give(nearest);
    w
}
