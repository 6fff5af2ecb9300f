//! The slicing pass on the CPU (section 3.4): the casters rasterized once from the COP, each
//! fragment marking the slice of its depth (and, with the thin-occluder fix, the next one) in a
//! per-texel bit mask, the software twin of `slicing.wgsl`'s `Max`-blended render targets.

use crate::frame::Frame;
use shadow_core::SceneGeometry;
use shadow_core::raster::rasterize_fold;

/// The binary slices of `geometry`: `slices` maps of `res²` flags, row-major.
pub fn slice(frame: &Frame, geometry: &SceneGeometry) -> Vec<Vec<bool>> {
    let res = frame.resolution;
    let n = frame.slices;
    let texels = res as usize * res as usize;
    if frame.occupied == 0 {
        return vec![vec![false; texels]; n as usize];
    }
    let view = frame.view();
    let masks = rasterize_fold(&view, res, &geometry.casters, 0u32, |mask, z| {
        let k = frame.slice_of(z);
        *mask |= 1 << k;
        if frame.thin_fix != 0 && k + 1 < n {
            *mask |= 1 << (k + 1);
        }
    });
    (0..n)
        .map(|k| {
            let mut s = shadow_core::pool::take(texels);
            s.extend(masks.data().iter().map(|m| m & (1 << k) != 0));
            s
        })
        .collect()
}
