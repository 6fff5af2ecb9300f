//! Shadow-width maps on the CPU: for each blocked texel of the inverted occlusion map, the distance
//! in texels (between texel centres) to the nearest unblocked texel; 0 on unblocked texels.
//!
//! Three ways, as the harness compares their cost and accuracy: the paper's iterative
//! propagation ([`propagate`]), the exact linear-time Euclidean distance transform ([`edt`]) and
//! jump flooding ([`jfa`]). Every one is mirrored in `width.wgsl`, so CPU and GPU build the same map.

pub(crate) mod edt;
pub(crate) mod jfa;
pub(crate) mod propagate;

use crate::params::WidthMethod;
use soft_shadow_core::Map2D;
use soft_shadow_core::pool::Pool;
use std::sync::Arc;

/// Width given to texels with no reachable unblocked texel: twice the map side (beyond any
/// distance inside the map).
pub(crate) fn cap(resolution: u32) -> f32 {
    2.0 * resolution as f32
}

/// The shadow-width map of `mask` (`true` = blocked; square) by `method`, in texels, capped at
/// [`cap`], its storage and scratch from `pool`.
pub(crate) fn width_map(pool: &Arc<Pool>, mask: &Map2D<bool>, method: WidthMethod) -> Map2D<f32> {
    match method {
        WidthMethod::Propagate { neighbours } => propagate::width(pool, mask, neighbours),
        WidthMethod::Exact => edt::width(pool, mask),
        WidthMethod::JumpFlood => jfa::width(pool, mask),
    }
}
