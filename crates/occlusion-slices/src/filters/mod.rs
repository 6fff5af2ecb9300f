//! The three box filters of section 3.2 over binary slices: [`mipmap`], [`nbuffer`] and the exact
//! [`sat`]. Each stores exact integer counts (the N-Buffers read them from the slice's
//! summed-area table, the mipmap sums them level by level) and answers the mean occupancy over
//! a square kernel; `visibility.wgsl` holds the same lookups.

pub(crate) mod mipmap;
pub(crate) mod nbuffer;
pub(crate) mod sat;

use glam::Vec2;
pub(crate) use mipmap::Mipmap;
pub(crate) use nbuffer::NBuffer;
use rayon::prelude::*;
pub(crate) use sat::Sat;
use soft_shadow_core::pool::Pool;
use std::sync::Arc;

/// How an occlusion texture is box-filtered (section 3.2).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum Prefilter {
    /// A mipmap pyramid (dyadic 2x2 means), read trilinearly at the kernel's level.
    Mipmap,
    /// N-Buffers: level `l` holds the normalised `2^l x 2^l` box filter at full resolution; a
    /// kernel between two levels interpolates linearly in its size.
    NBuffer,
    /// A summed-area table of integer counts: the exact box filter of the binary slice.
    Sat,
}

impl Prefilter {
    /// Every filter.
    pub const ALL: [Prefilter; 3] = [Prefilter::Mipmap, Prefilter::NBuffer, Prefilter::Sat];

    /// Short name used in variant labels.
    pub fn name(self) -> &'static str {
        match self {
            Prefilter::Mipmap => "mipmap",
            Prefilter::NBuffer => "nbuffer",
            Prefilter::Sat => "sat",
        }
    }

    /// Index shared with the shaders (`FILTER_*` in `frame.wgsl`).
    pub fn index(self) -> u32 {
        match self {
            Prefilter::Mipmap => 0,
            Prefilter::NBuffer => 1,
            Prefilter::Sat => 2,
        }
    }
}

/// Number of levels (mipmap or N-Buffer) of a `resolution`-wide slice: up to the first box of side
/// `>= resolution`.
pub(crate) fn level_count(resolution: u32) -> u32 {
    32 - resolution.max(1).saturating_sub(1).leading_zeros() + 1
}

/// `count / area` rounded to the nearest 8-bit unorm (ties up), in integers: the same bits on
/// every backend. `count * 255 + area / 2` fits `u32` for areas up to `2^24` (4096² texels).
#[cfg(test)]
pub fn unorm8(count: u32, area: u64) -> u8 {
    ((count as u64 * 255 + area / 2) / area) as u8
}

/// [`unorm8`] for an area of `1 << shift` texels, as a shift (the same value; the level
/// builders' inner loop).
#[inline]
pub(crate) fn unorm8_pow2(count: u32, shift: u32) -> u8 {
    ((count as u64 * 255 + ((1u64 << shift) >> 1)) >> shift) as u8
}

/// Largest shift [`unorm8_pow2_u32`] takes: `255 * 2^22 + 2^21 < 2^32`.
pub(crate) const U32_SHIFT_MAX: u32 = 22;

/// [`unorm8_pow2`] in `u32` arithmetic (which vectorizes where `u64` does not), for a `count` of
/// at most `1 << shift` and a `shift` of at most [`U32_SHIFT_MAX`]: the same value.
#[inline]
pub(crate) fn unorm8_pow2_u32(count: u32, shift: u32) -> u8 {
    ((count * 255 + ((1u32 << shift) >> 1)) >> shift) as u8
}

#[cfg(test)]
mod tests {
    #[test]
    fn unorm8_pow2_is_unorm8() {
        for shift in 0..24 {
            let area = 1u64 << shift;
            for count in [0, 1, 2, 3, area / 2, area / 2 + 1, area - 1, area] {
                let c = count as u32;
                assert_eq!(
                    super::unorm8_pow2(c, shift),
                    super::unorm8(c, area),
                    "{c}/{area}"
                );
                if shift <= super::U32_SHIFT_MAX {
                    assert_eq!(super::unorm8_pow2_u32(c, shift), super::unorm8(c, area));
                }
            }
        }
    }
}

/// Bilinear interpolation of `texel(x, y)` (0 outside, the caller's choice) at the continuous
/// index position `p`: `texel(floor(p))` has weight 1 at `p = floor(p)`. The N-Buffer reads at
/// box starts, the mipmap at `c / 2^l - 1/2` (texel centres).
pub(crate) fn bilinear(p: Vec2, texel: impl Fn(i64, i64) -> f32) -> f32 {
    let f = p.floor();
    let (x, y) = (f.x as i64, f.y as i64);
    let t = p - f;
    let top = texel(x, y) * (1.0 - t.x) + texel(x + 1, y) * t.x;
    let bottom = texel(x, y + 1) * (1.0 - t.x) + texel(x + 1, y + 1) * t.x;
    top * (1.0 - t.y) + bottom * t.y
}

/// The prefiltered slices of one light, in the form the filter reads.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Filtered {
    /// One pyramid per slice.
    Mipmap(Vec<Mipmap>),
    /// One set of levels per slice.
    NBuffer(Vec<NBuffer>),
    /// One table per slice.
    Sat(Vec<Sat>),
}

impl Filtered {
    /// Prefilters the `slices` binary slices packed in `masks` (`resolution²` texels, bit `k` for
    /// slice `k`: [`crate::slicing::slice`]) with `filter`, the slices in parallel, their
    /// storage from `pool`.
    pub(crate) fn build(
        pool: &Arc<Pool>,
        filter: Prefilter,
        resolution: u32,
        masks: &[u32],
        slices: u32,
    ) -> Filtered {
        let each = (0..slices).into_par_iter();
        match filter {
            Prefilter::Sat => Filtered::Sat(
                each.map(|k| Sat::from_masks(pool, resolution, masks, k))
                    .collect(),
            ),
            Prefilter::NBuffer => Filtered::NBuffer(
                each.map(|k| NBuffer::new(pool, &Sat::from_masks(pool, resolution, masks, k)))
                    .collect(),
            ),
            Prefilter::Mipmap => {
                // One group of slices per thread, each group's bases built together.
                let group = slices.div_ceil(rayon::current_num_threads() as u32).max(1);
                let groups: Vec<Vec<Mipmap>> = (0..slices.div_ceil(group))
                    .into_par_iter()
                    .map(|g| {
                        let ks = g * group..((g + 1) * group).min(slices);
                        Mipmap::from_masks_together(pool, resolution, masks, ks)
                    })
                    .collect();
                Filtered::Mipmap(groups.into_iter().flatten().collect())
            }
        }
    }

    /// The filter these slices were prefiltered with.
    pub(crate) fn filter(&self) -> Prefilter {
        match self {
            Filtered::Mipmap(_) => Prefilter::Mipmap,
            Filtered::NBuffer(_) => Prefilter::NBuffer,
            Filtered::Sat(_) => Prefilter::Sat,
        }
    }

    /// Mean occupancy of slice `k` over the square of side `size` texels centred at `c`.
    pub(crate) fn mean(&self, k: usize, c: Vec2, size: f32) -> f32 {
        match self {
            Filtered::Mipmap(m) => m[k].mean(c, size),
            Filtered::NBuffer(n) => n[k].mean(c, size),
            Filtered::Sat(s) => s[k].mean(c, size),
        }
    }
}
