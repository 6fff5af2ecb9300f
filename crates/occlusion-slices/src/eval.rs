//! Shading one receiver (sections 3.4-3.5), shared by the CPU path; `visibility.wgsl` is the same
//! function on the GPU.
//!
//! For each slice plane `p_k` between the receiver and the light: the kernel of equation 4
//! (the pyramid from the receiver to the light cut by the plane), the filtered occlusion
//! `I_k`, weighted by the slice's fade ([`Frame::fade`]), combined by [`Accumulator`].

use crate::combine::Accumulator;
use crate::frame::Frame;
use crate::params::OcclusionSlices;
use glam::{Vec2, Vec3};

/// `V` at `p` (unit normal `n`) with `mean(k, centre, size)` the filtered occlusion of slice `k`.
pub(crate) fn visibility(
    t: &OcclusionSlices,
    frame: &Frame,
    p: Vec3,
    n: Vec3,
    mean: impl Fn(usize, Vec2, f32) -> f32,
) -> f32 {
    if frame.occupied == 0 {
        return 1.0;
    }
    let h = frame.light_coord(p).h;
    let offset = t.normal_offset * frame.texel_size(h.max(0.0));
    let c = frame.light_coord(p + n * offset);
    let mut acc = Accumulator::new(t.combination);
    let fade_length = frame.fade_length(c.h);
    for k in 0..frame.slices {
        let w = frame.fade(k, c.h, fade_length);
        if w <= 0.0 {
            break;
        }
        let (center, size) = frame.kernel(c, frame.plane(k));
        acc.add(w * mean(k as usize, center, size));
    }
    acc.visibility()
}
