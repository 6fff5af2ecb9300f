//! The width map by jump flooding ([`shadow_core::jump_flood`]): the seeds are the unblocked
//! texels, so every blocked texel learns its nearest unblocked one. `width.wgsl` seeds and
//! resolves on the GPU, `shadow_core`'s jump-flood kernel floods, in the same order as here.

use shadow_core::Map2D;
use shadow_core::jump_flood::{NONE, dist2, flood, pack};

/// The jump-flooded width map of `mask`, capped at [`super::cap`].
pub fn width(mask: &Map2D<bool>) -> Map2D<f32> {
    let res = mask.width();
    let seeds: Vec<u32> = mask
        .data()
        .iter()
        .enumerate()
        .map(|(i, &b)| {
            if b {
                NONE
            } else {
                pack(i as u32 % res, i as u32 / res)
            }
        })
        .collect();
    let nearest = flood(seeds, res);
    let cap = super::cap(res);
    let w = nearest
        .iter()
        .enumerate()
        .map(|(i, &s)| {
            if s == NONE {
                cap
            } else {
                let (x, y) = (i as u32 % res, i as u32 / res);
                (dist2(x as i32, y as i32, s) as f32).sqrt().min(cap)
            }
        })
        .collect();
    Map2D::from_vec(res, mask.height(), w).unwrap_or_else(|| Map2D::new(0, 0, 0.0))
}
