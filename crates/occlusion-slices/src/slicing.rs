//! The slicing pass on the CPU (section 3.4): the casters rasterized once from the COP, each
//! fragment marking the slice of its depth (and, with the thin-occluder fix, the next one) in a
//! per-texel bit mask, the software twin of `slicing.wgsl`'s `Max`-blended render targets.
//!
//! The masks are what the prefilters read ([`crate::filters::Filtered::build`]): bit `k` of a
//! texel is slice `k`, so the slices are never unpacked into one map each.
//!
//! A fragment's slice is [`Frame::slice_of`] its linear depth, which takes two divisions from the
//! rasterizer's NDC depth. Both steps are monotone in NDC depth, so [`NdcSlicer`] finds once, by
//! bisection over the `f32`s, the NDC depth where each slice begins, and a fragment compares
//! against those instead: the same slice, bit for bit.

use crate::frame::Frame;
use shadow_core::View;
use shadow_core::raster::rasterize_fold;
use shadow_core::{Map2D, SceneGeometry};

/// Most slices a frame has ([`crate::params::SLICE_RANGE`]).
const MAX_SLICES: usize = 16;

/// The slice of a fragment from its NDC depth `z` (reversed Z), equal to
/// `frame.slice_of(view.linear_depth_from_ndc(z))` for every `f32`.
#[derive(Clone, Copy, Debug)]
pub struct NdcSlicer {
    /// For `z > 0` the slice is at least `k` exactly where `z <= at[k - 1]`; unused entries are
    /// `-inf`, which no positive `z` is below.
    at: [f32; MAX_SLICES],
    /// The slice of every `z <= 0` (the view's [`shadow_core::view::NO_OCCLUDER`] depth).
    behind: u32,
}

impl NdcSlicer {
    /// The slicer of `frame` through `view`, or `None` where the slice is not monotone in NDC
    /// depth (a view whose far plane is not beyond its near one, a spacing that is not positive).
    pub fn new(frame: &Frame, view: &View) -> Option<Self> {
        let monotone = view.near > 0.0
            && view.far > view.near
            && view.far.is_finite()
            && frame.spacing > 0.0
            && (frame.slices as usize) <= MAX_SLICES;
        if !monotone {
            return None;
        }
        // Non-increasing in `z > 0`: linear depth falls as reversed-Z NDC depth rises, and the
        // slice rises with linear depth; each f32 operation on the way is monotone.
        let slice = |bits: u32| frame.slice_of(view.linear_depth_from_ndc(f32::from_bits(bits)));
        // Positive f32s in order of their bits: the smallest subnormal up to +inf.
        let (first, last) = (1u32, f32::INFINITY.to_bits());
        let mut at = [f32::NEG_INFINITY; MAX_SLICES];
        for k in 1..frame.slices {
            if slice(first) < k {
                continue;
            }
            if slice(last) >= k {
                at[k as usize - 1] = f32::INFINITY;
                continue;
            }
            // slice(lo) >= k > slice(hi).
            let (mut lo, mut hi) = (first, last);
            while hi - lo > 1 {
                let mid = lo + (hi - lo) / 2;
                if slice(mid) >= k {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            at[k as usize - 1] = f32::from_bits(lo);
        }
        Some(Self {
            at,
            behind: frame.slice_of(view.linear_depth_from_ndc(0.0)),
        })
    }

    /// The slice of NDC depth `z` (NaN: slice 0, as [`Frame::slice_of`] gives NaN).
    #[inline(always)]
    pub fn slice(&self, z: f32) -> u32 {
        if z <= 0.0 {
            return self.behind;
        }
        self.at.iter().map(|&t| (z <= t) as u32).sum()
    }
}

/// The slice masks of `geometry`: `res²` texels, bit `k` set where slice `k` is occupied.
pub fn slice(frame: &Frame, geometry: &SceneGeometry) -> Map2D<u32> {
    let res = frame.resolution;
    let n = frame.slices;
    if frame.occupied == 0 {
        return Map2D::new(res, res, 0);
    }
    let view = frame.view();
    let mark = move |mask: &mut u32, k: u32| {
        *mask |= 1 << k;
        if frame.thin_fix != 0 && k + 1 < n {
            *mask |= 1 << (k + 1);
        }
    };
    match NdcSlicer::new(frame, &view) {
        Some(slicer) => rasterize_fold(&view, res, &geometry.casters, 0u32, |mask, z| {
            mark(mask, slicer.slice(z))
        }),
        None => rasterize_fold(&view, res, &geometry.casters, 0u32, |mask, z| {
            mark(mask, frame.slice_of(view.linear_depth_from_ndc(z)))
        }),
    }
}

/// Slice `k` of `masks` as one flag per texel, row-major (tests and images).
pub fn unpack(masks: &Map2D<u32>, k: u32) -> Vec<bool> {
    masks.data().iter().map(|m| m & (1 << k) != 0).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use bytemuck::Zeroable;
    use glam::Vec3;
    use shadow_core::view::{ProjectionKind, look_to_up};

    /// The slicer gives [`Frame::slice_of`] of the linear depth on every slice's threshold and
    /// the 64 `f32`s either side of it, on 20,000 NDC depths spread over every binade of
    /// (0, 1], and on 0, the negatives, NaN and the infinities, for frames of 4 to 16 slices
    /// whose planes fall inside and outside the view's depth range.
    #[test]
    fn the_slicer_gives_the_slice_of_the_linear_depth() {
        let mut checked = 0;
        for (slices, near, spacing, clip) in [
            (4u32, 0.5f32, 0.25f32, (0.1f32, 3.0f32)),
            (8, 0.25, 0.1, (0.01, 10.0)),
            (16, 0.001, 0.07, (0.5, 2.5)),
            (13, -0.3, 0.4, (1e-3, 1e4)),
        ] {
            let frame = Frame {
                d: 0.8,
                near,
                spacing,
                slices,
                ..Frame::zeroed()
            };
            let view = View {
                view: look_to_up(Vec3::ZERO, Vec3::Z, Vec3::Y),
                kind: ProjectionKind::Perspective { fov: 1.0 },
                near: clip.0,
                far: clip.1,
                aspect: 1.0,
            };
            let slicer = NdcSlicer::new(&frame, &view).expect("monotone");
            let want = |z: f32| frame.slice_of(view.linear_depth_from_ndc(z));
            let mut zs = vec![
                0.0,
                -0.0,
                -1.0,
                f32::NAN,
                f32::INFINITY,
                f32::NEG_INFINITY,
                f32::MIN_POSITIVE,
                f32::from_bits(1),
            ];
            for t in slicer.at.iter().filter(|t| t.is_finite()) {
                for d in 0..64 {
                    zs.push(f32::from_bits(t.to_bits() + d));
                    zs.push(f32::from_bits(t.to_bits().saturating_sub(d)));
                }
            }
            let mut x = 0x9E37_79B9u32;
            for _ in 0..20_000 {
                x ^= x << 13;
                x ^= x >> 17;
                x ^= x << 5;
                // Any positive f32 up to 1 (the bits of 1.0 are 0x3f80_0000).
                zs.push(f32::from_bits(x % 0x3f80_0001));
            }
            let mut reached = std::collections::BTreeSet::new();
            for z in zs {
                assert_eq!(slicer.slice(z), want(z), "{slices} slices, z = {z:e}");
                reached.insert(want(z));
                checked += 1;
            }
            assert!(reached.len() >= 3, "{slices} slices: only {reached:?}");
        }
        assert!(checked > 80_000);
    }
}
