//! Shading one receiver (sections 3.4-3.5), shared by the CPU path; `visibility.wgsl` is the same
//! function on the GPU.
//!
//! For each slice plane `p_k` between the receiver and the light: the kernel of equation 4
//! (the pyramid from the receiver to the light cut by the plane), the filtered occlusion
//! `I_k`, weighted by the slice's fade ([`Frame::fade`]), combined by [`Accumulator`].
//!
//! The paper skips the receiver's own slice (section 3.4: its own surface is in it), which also
//! drops every caster within a slab above the receiver: a light ring on the ground around a body
//! resting on it. Here the own slice, and the one fading in above it, are read unfiltered
//! instead ([`slab_occlusion`]): each texel's topmost depth in the slab ([`Frame::top_code`])
//! is tested against the receiver's, so only what lies nearer the light hides it.

use crate::combine::Accumulator;
use crate::frame::{Frame, LightCoord, TOP_STEPS};
use crate::params::OcclusionSlices;
use glam::{Vec2, Vec3};

/// Most taps a side [`slab_occlusion`] reads (`TAPS²` per slab).
pub(crate) const TAPS: u32 = 8;

/// The depth-test margin, in texels of the frustum at the receiver: a slab's casters hide a
/// receiver only where they lie nearer the light than it by this much, and in front of its
/// tangent plane by this much (a texel's top is its topmost fragment, up to a texel's slope
/// away from the surface at the texel's centre).
pub(crate) const SLAB_BIAS_TEXELS: f32 = 1.0;

/// `V` at `p` (unit normal `n`) with `mean(k, centre, size)` the filtered occlusion of slice `k`,
/// `union(k, centre, size)` that of slices `k - 1` and `k` together (read by
/// [`crate::Combination::Chain`] only), and `top(k, x, y)` texel `(x, y)`'s [`Frame::top_code`]
/// in slice `k` (0 outside the map).
///
/// The chain links slice `k` to slice `k - 1` where the previous slice is read filtered alone
/// (weight 1): the filtered part of a slice that fades in is chained too, its unfiltered part
/// multiplies as in the product, so `V` has no step where the fade ends.
pub(crate) fn visibility(
    t: &OcclusionSlices,
    frame: &Frame,
    p: Vec3,
    n: Vec3,
    mean: impl Fn(usize, Vec2, f32) -> f32,
    union: impl Fn(usize, Vec2, f32) -> f32,
    top: impl Fn(usize, i64, i64) -> u8,
) -> f32 {
    if frame.occupied == 0 {
        return 1.0;
    }
    let h = frame.light_coord(p).h;
    let offset = t.normal_offset * frame.texel_size(h.max(0.0));
    let c = frame.light_coord(p + n * offset);
    let mut acc = Accumulator::new(t.combination);
    let fade_length = frame.fade_length(c.h);
    let receiver = Receiver::new(frame, c, n);
    let chained = t.combination.chained();
    // Whether the previous slice was read filtered alone.
    let mut linked = false;
    for k in 0..frame.slices {
        let w = frame.fade(k, c.h, fade_length);
        let mut i = 0.0;
        let slab = || slab_occlusion(frame, &receiver, k, &top);
        if w > 0.0 {
            let (center, size) = frame.kernel(c, frame.plane(k), receiver.widen);
            if chained && linked {
                let (u, nearer) = (
                    union(k as usize, center, size),
                    mean(k as usize - 1, center, size),
                );
                let s = if w < 1.0 { slab() } else { 0.0 };
                acc.add_given(u, nearer, w, s);
                linked = w >= 1.0;
                continue;
            }
            i = w * mean(k as usize, center, size);
        }
        if w < 1.0 {
            i += (1.0 - w) * slab();
        }
        acc.add(i);
        linked = w >= 1.0;
        if w <= 0.0 {
            break;
        }
    }
    acc.visibility()
}

/// A receiver as [`slab_occlusion`] tests casters against it.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Receiver {
    /// Its point (offset along its normal) in light coordinates.
    pub c: LightCoord,
    /// Its unit normal in light coordinates.
    pub n: Vec3,
    /// [`SLAB_BIAS_TEXELS`] at its depth, in world units, and one step of [`Frame::top_code`].
    pub margin: f32,
    /// What its kernels widen by ([`Frame::spread`]).
    pub widen: f32,
}

impl Receiver {
    /// The receiver at `c` with world normal `n`.
    pub(crate) fn new(frame: &Frame, c: LightCoord, n: Vec3) -> Self {
        Self {
            c,
            n: frame.direction(n),
            margin: SLAB_BIAS_TEXELS * frame.texel_size(c.h.max(0.0)) + frame.spacing / TOP_STEPS,
            widen: frame.spread(c),
        }
    }

    /// Whether a caster at `q` can hide part of the light from the receiver: nearer the light
    /// and in front of its tangent plane, each by the margin (what lies behind the tangent
    /// plane is the lighting's horizon, not a shadow).
    fn hidden_by(&self, q: LightCoord) -> bool {
        let (c, n) = (self.c, self.n);
        let front = n.x * (q.x - c.x) + n.y * (q.y - c.y) + n.z * (q.h - c.h);
        q.h < c.h - self.margin && front > self.margin
    }
}

/// The share of the light that slice `k`'s casters hide from `r`, read from their top codes:
/// up to [`TAPS`]² taps over the pyramid from the receiver to the light between the slab's upper
/// plane and the receiver; a tap whose texel's top can hide it ([`Receiver::hidden_by`]) hides
/// the part of the pyramid's cross-section at that depth its footprint covers. Taps are summed
/// (a slab's casters rarely hide one part of the light twice), at most 1.
pub(crate) fn slab_occlusion(
    frame: &Frame,
    r: &Receiver,
    k: u32,
    top: impl Fn(usize, i64, i64) -> u8,
) -> f32 {
    let c = r.c;
    let upper = (frame.plane(k) - frame.spacing).max(0.0);
    let limit = c.h - r.margin;
    if !(limit > upper && c.h > 0.0) {
        return 0.0;
    }
    let (a, sa) = frame.kernel(c, upper, r.widen);
    let (b, sb) = frame.kernel(c, limit, r.widen);
    let lo = (a - Vec2::splat(0.5 * sa)).min(b - Vec2::splat(0.5 * sb));
    let hi = (a + Vec2::splat(0.5 * sa)).max(b + Vec2::splat(0.5 * sb));
    let extent = hi - lo;
    if !(extent.x.is_finite() && extent.y.is_finite()) {
        return 0.0;
    }
    let taps = |e: f32| (e.ceil().max(1.0) as u32).min(TAPS);
    let (nx, ny) = (taps(extent.x), taps(extent.y));
    let step = extent / Vec2::new(nx as f32, ny as f32);
    let overlap = |a0: f32, a1: f32, b0: f32, b1: f32| (a1.min(b1) - a0.max(b0)).max(0.0);
    let mut sum = 0.0;
    for j in 0..ny {
        for i in 0..nx {
            let t0 = lo + step * Vec2::new(i as f32, j as f32);
            let centre = t0 + 0.5 * step;
            let code = top(k as usize, centre.x.floor() as i64, centre.y.floor() as i64);
            if code == 0 {
                continue;
            }
            let z = frame.top_depth(k, code);
            // A fragment at or behind the light's plane (slice 0 reaches just past it) hides
            // nothing.
            if z <= 0.0 || !r.hidden_by(frame.texel_point(centre, z)) {
                continue;
            }
            let (kc, ks) = frame.kernel(c, z, r.widen);
            if ks.is_nan() || ks <= 0.0 {
                continue;
            }
            let h = 0.5 * ks;
            let ox = overlap(t0.x, t0.x + step.x, kc.x - h, kc.x + h);
            let oy = overlap(t0.y, t0.y + step.y, kc.y - h, kc.y + h);
            sum += ox * oy / (ks * ks);
        }
    }
    sum.min(1.0)
}
