//! The slicing pass on the CPU (section 3.4): the casters rasterized once from the COP, each
//! fragment marking the slice of its depth (and, with the thin-occluder fix, the next one) in a
//! per-texel bit mask, the software twin of `slicing.wgsl`'s `Max`-blended render targets.
//!
//! The masks are what the prefilters read ([`crate::filters::Filtered::build`]): bit `k` of a
//! texel is slice `k`, so the slices are never unpacked into one map each.

use crate::frame::Frame;
use shadow_core::raster::rasterize_fold;
use shadow_core::{Map2D, SceneGeometry};

/// The slice masks of `geometry`: `res²` texels, bit `k` set where slice `k` is occupied.
pub fn slice(frame: &Frame, geometry: &SceneGeometry) -> Map2D<u32> {
    let res = frame.resolution;
    let n = frame.slices;
    if frame.occupied == 0 {
        return Map2D::new(res, res, 0);
    }
    let view = frame.view();
    rasterize_fold(&view, res, &geometry.casters, 0u32, |mask, z| {
        let k = frame.slice_of(z);
        *mask |= 1 << k;
        if frame.thin_fix != 0 && k + 1 < n {
            *mask |= 1 << (k + 1);
        }
    })
}

/// Slice `k` of `masks` as one flag per texel, row-major (tests and images).
pub fn unpack(masks: &Map2D<u32>, k: u32) -> Vec<bool> {
    masks.data().iter().map(|m| m & (1 << k) != 0).collect()
}
