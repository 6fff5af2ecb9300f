//! The point samples along the segment (section 3.3) and their shares of the light.
//!
//! `N` samples split the segment into `N - 1` pieces of share `s = 1 / (N - 1)`. A point that
//! sees a whole piece gets `s / 2` from each of its two end samples, so an end sample carries
//! `s / 2` and an interior sample, shared by two pieces, `s`: a fully lit point sums to 1.

use glam::Vec3;
use soft_shadow_core::Coverage;
use soft_shadow_core::{LightPoint, SampleView};

/// Share `s = 1 / (N - 1)` of one piece of the segment.
pub(crate) fn piece_share(n: u32) -> f32 {
    1.0 / (n - 1) as f32
}

/// The fully lit share of sample `i` of `n`: `s / 2` at the ends, `s` inside.
pub(crate) fn lit_share(i: u32, n: u32) -> f32 {
    let s = piece_share(n);
    if i == 0 || i == n - 1 { 0.5 * s } else { s }
}

/// The neighbours of sample `i` of `n` along the segment.
pub(crate) fn neighbours(i: u32, n: u32) -> impl Iterator<Item = u32> {
    [i.checked_sub(1), (i + 1 < n).then_some(i + 1)]
        .into_iter()
        .flatten()
}

/// One perspective view per sample, `a + (b - a) i / (N - 1)`, all looking along `axis` and
/// covering `coverage`; the weight of a view is its lit share times `segment_weight` (the
/// segment's share of the light, [`crate::segments::Segment::weight`]).
pub(crate) fn sample_views(
    a: Vec3,
    b: Vec3,
    n: u32,
    axis: Vec3,
    coverage: &Coverage,
    segment_weight: f32,
) -> Vec<SampleView> {
    (0..n)
        .map(|i| {
            let q = a + (b - a) * (i as f32 / (n - 1) as f32);
            let weight = segment_weight * lit_share(i, n);
            SampleView::new(LightPoint::Position(q), weight, axis, coverage)
        })
        .collect()
}
