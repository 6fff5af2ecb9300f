//! The slicing pass on the CPU (section 3.4): the casters rasterized once from the COP, each
//! fragment keeping, in its slice's byte of the texel, its [`Frame::top_code`] (where in the slab
//! it lies) if it is the topmost there (and, with the thin-occluder fix, marking the next slice's
//! top), the software twin of `slicing.wgsl`'s `Max`-blended render targets.
//!
//! The masks the prefilters read ([`crate::filters::Filtered::build`]) follow: bit `k` of a
//! texel is set where slice `k`'s code is not 0, so the slices are never unpacked into one map
//! each; the codes are what the evaluation reads of the receiver's own slice
//! ([`crate::eval::slab_occlusion`]).
//!
//! A fragment's slice is [`Frame::slice_of`] its linear depth, which takes two divisions from the
//! rasterizer's NDC depth. Both steps are monotone in NDC depth, so [`NdcSlicer`] finds once, by
//! bisection over the `f32`s, the NDC depth where each slice begins, and a fragment compares
//! against those instead: the same slice, bit for bit.

use crate::frame::Frame;
use soft_shadow_core::View;
use soft_shadow_core::pool::Pool;
use soft_shadow_core::raster::rasterize_fold;
use soft_shadow_core::{Map2D, SceneGeometry};
use std::sync::Arc;

/// Most slices a frame has ([`crate::params::SLICE_RANGE`]).
pub(crate) const MAX_SLICES: usize = 16;

/// The slice of a fragment from its NDC depth `z` (reversed Z), equal to
/// `frame.slice_of(view.linear_depth_from_ndc(z))` for every `f32`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct NdcSlicer {
    /// For `z > 0` the slice is at least `k` exactly where `z <= at[k - 1]`; unused entries are
    /// `-inf`, which no positive `z` is below.
    at: [f32; MAX_SLICES],
    /// The slice of every `z <= 0` (the view's [`soft_shadow_core::view::NO_OCCLUDER`] depth).
    behind: u32,
}

impl NdcSlicer {
    /// The slicer of `frame` through `view`, or `None` where the slice is not monotone in NDC
    /// depth (a view whose far plane is not beyond its near one, a spacing that is not positive).
    pub(crate) fn new(frame: &Frame, view: &View) -> Option<Self> {
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
    pub(crate) fn slice(&self, z: f32) -> u32 {
        // Both sides computed, one chosen: no branch in the rasterizer's span loop.
        let above: u32 = self.at.iter().map(|&t| (z <= t) as u32).sum();
        if z <= 0.0 { self.behind } else { above }
    }
}

/// The sliced casters: per texel, which slices are occupied and how high in each slab.
#[derive(Clone, Debug)]
pub(crate) struct Slices {
    /// Bit `k` set where slice `k` is occupied.
    pub masks: Map2D<u32>,
    /// Per slice, the [`Frame::top_code`] of the texel's topmost fragment in it (0: empty).
    pub tops: Map2D<[u8; MAX_SLICES]>,
}

/// The slices of `geometry`: `resolution²` texels, each with its occupied slices and the topmost depth
/// of each.
pub(crate) fn slice(pool: &Arc<Pool>, frame: &Frame, geometry: &SceneGeometry) -> Slices {
    let resolution = frame.resolution;
    let n = frame.slices;
    if frame.occupied == 0 {
        return Slices {
            masks: Map2D::pooled(pool, resolution, resolution, 0),
            tops: Map2D::pooled(pool, resolution, resolution, [0; MAX_SLICES]),
        };
    }
    let view = frame.view();
    // A fragment of slice k keeps its top code in k, and with the thin-occluder fix marks the
    // top of k + 1 as well (the sheet lies above all of it).
    let thin = frame.thin_fix != 0;
    let mark = move |tops: &mut [u8; MAX_SLICES], k: u32, code: u8| {
        let k = k as usize & (MAX_SLICES - 1);
        tops[k] = tops[k].max(code);
        if thin && (k as u32) + 1 < n {
            tops[k + 1] = 255;
        }
    };
    let h = move |z: f32| view.linear_depth_from_ndc(z) - frame.d;
    let tops = match NdcSlicer::new(frame, &view) {
        // The slice and the code are monotone in NDC depth, so a span whose ends share both
        // holds them throughout.
        Some(slicer) => rasterize_fold(
            pool,
            &view,
            resolution,
            &geometry.casters,
            [0u8; MAX_SLICES],
            |tops, depths| {
                let Some(last) = tops.len().checked_sub(1) else {
                    return;
                };
                let (z0, z1) = (depths.at(0), depths.at(last));
                let first = slicer.slice(z0);
                let code = frame.top_code(first, h(z0));
                if depths.monotone()
                    && slicer.slice(z1) == first
                    && frame.top_code(first, h(z1)) == code
                {
                    tops.iter_mut().for_each(|t| mark(t, first, code));
                } else {
                    depths.each(tops, |t, z| {
                        let k = slicer.slice(z);
                        mark(t, k, frame.top_code(k, h(z)))
                    });
                }
            },
        ),
        None => rasterize_fold(
            pool,
            &view,
            resolution,
            &geometry.casters,
            [0u8; MAX_SLICES],
            |tops, depths| {
                depths.each(tops, |t, z| {
                    let k = frame.slice_of(view.linear_depth_from_ndc(z));
                    mark(t, k, frame.top_code(k, h(z)))
                })
            },
        ),
    };
    let masks = tops.map(|t| {
        t.iter()
            .enumerate()
            .fold(0u32, |m, (k, &c)| m | (((c != 0) as u32) << k))
    });
    Slices { masks, tops }
}

/// Slice `k` of `masks` as one flag per texel, row-major (tests and images).
pub(crate) fn unpack(masks: &Map2D<u32>, k: u32) -> Vec<bool> {
    masks.data().iter().map(|m| m & (1 << k) != 0).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use bytemuck::Zeroable;
    use glam::Vec3;
    use soft_shadow_core::view::{ProjectionKind, look_to_up};

    /// The masks mark every fragment by its own slice, [`Frame::slice_of`] its linear depth, and
    /// each slice keeps its topmost fragment's [`Frame::top_code`], though a span whose ends
    /// share a slice and a code is marked whole: on two steep triangles that cross
    /// every slice and 400 small ones at random depths and slants, for 4 to 16 slices, with and
    /// without the thin-occluder fix, at a resolution where spans are long.
    #[test]
    fn slice_masks_mark_every_fragment_by_its_depth() {
        use soft_shadow_core::{Aabb, Light};
        let light = Light::Rect {
            center: Vec3::new(0.0, 4.0, 0.0),
            u_half: Vec3::X * 0.5,
            v_half: Vec3::Z * 0.5,
        };
        let mut casters = vec![
            [
                Vec3::new(-1.0, 0.1, -1.0),
                Vec3::new(1.0, 3.0, -1.0),
                Vec3::new(1.0, 0.1, 1.0),
            ],
            [
                Vec3::new(-1.0, 3.0, 1.0),
                Vec3::new(1.0, 0.1, 1.0),
                Vec3::new(-1.0, 0.1, -1.0),
            ],
        ];
        let mut rng = soft_shadow_core::rng::SplitMix(6);
        let mut next = || rng.next_f32();
        for _ in 0..400 {
            let c = Vec3::new(2.0 * next() - 1.0, 0.1 + 2.9 * next(), 2.0 * next() - 1.0);
            let mut corner = || c + (Vec3::new(next(), next(), next()) - 0.5) * 0.6;
            casters.push([corner(), corner(), corner()]);
        }
        let geometry = SceneGeometry {
            bounds: Aabb::of_triangles(&casters),
            casters,
            receivers: Vec::new(),
        };
        for (slices, thin_fix) in [(4, false), (8, true), (16, false), (16, true)] {
            let t =
                crate::OcclusionSlices::new(slices, crate::Prefilter::Sat).with_thin_fix(thin_fix);
            let frame = Frame::fit(&light, &geometry, &t, 256, soft_shadow_core::Region::Whole);
            let view = frame.view();
            assert!(NdcSlicer::new(&frame, &view).is_some());
            let pool = Arc::new(Pool::new(1 << 30));
            let expected = rasterize_fold(
                &pool,
                &view,
                256,
                &geometry.casters,
                0u32,
                |masks, depths| {
                    depths.each(masks, |m, z| {
                        let k = frame.slice_of(view.linear_depth_from_ndc(z));
                        *m |= 1 << k;
                        if thin_fix && k + 1 < slices {
                            *m |= 1 << (k + 1);
                        }
                    })
                },
            );
            // Per fragment, its top code where it is the slice's topmost.
            let expected_tops = rasterize_fold(
                &pool,
                &view,
                256,
                &geometry.casters,
                [0u8; MAX_SLICES],
                |tops, depths| {
                    depths.each(tops, |t, z| {
                        let linear = view.linear_depth_from_ndc(z);
                        let k = frame.slice_of(linear);
                        let code = frame.top_code(k, linear - frame.d);
                        t[k as usize] = t[k as usize].max(code);
                        if thin_fix && k + 1 < slices {
                            t[k as usize + 1] = 255;
                        }
                    })
                },
            );
            let Slices { masks, tops } = slice(&pool, &frame, &geometry);
            assert!(tops.data() == expected_tops.data(), "{slices} slices' tops");
            let codes: std::collections::BTreeSet<u8> =
                tops.data().iter().flatten().copied().collect();
            assert!(codes.len() > 200, "{slices} slices: {} codes", codes.len());
            let marked: u32 = expected.data().iter().map(|m| m.count_ones()).sum();
            let used: u32 = expected.data().iter().fold(0, |a, m| a | m);
            assert!(
                marked > 40_000 && used.count_ones() >= slices - 1,
                "{marked}, {used:b}"
            );
            assert!(masks.data() == expected.data(), "{slices} slices");
        }
    }

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
