//! N-Buffers (Décoret 2005) of a slice: level `l` holds, at full resolution, the mean of the
//! `2^l x 2^l` box whose top-left texel is the texel itself (outside the slice counts as empty).
//!
//! Each level is computed from the exact summed-area table (four reads per texel, like the
//! paper's doubling construction) and stored as 8-bit unorm, the paper's RGBA8 texels: the only
//! error of a stored value is its rounding, at every level.

use super::sat::Sat;
use super::{U32_SHIFT_MAX, bilinear, level_count, unorm8_pow2, unorm8_pow2_u32};
use glam::Vec2;
use rayon::prelude::*;
use soft_shadow_core::pool::Pool;
use std::sync::Arc;

/// Rows per band of the construction.
const BAND_ROWS: usize = 16;

/// Every level of one slice, `resolution²` bytes each.
#[derive(Clone, Debug)]
pub(crate) struct NBuffer {
    /// Side in texels.
    pub resolution: u32,
    /// Level `l` at index `l`.
    pub levels: Vec<Vec<u8>>,
    pool: Arc<Pool>,
}

impl PartialEq for NBuffer {
    fn eq(&self, other: &Self) -> bool {
        (self.resolution, &self.levels) == (other.resolution, &other.levels)
    }
}

impl Drop for NBuffer {
    /// The levels' storage goes back to the pool it came from.
    fn drop(&mut self) {
        self.levels.drain(..).for_each(|l| self.pool.give(l));
    }
}

impl NBuffer {
    /// The levels `0..level_count(resolution)` of the slice whose table is `sat`, their storage from
    /// `pool`.
    ///
    /// Bands of rows in parallel, every level of a row at once: the table row `y` that each
    /// level reads is read once for all of them, and the rows `y + 2^l` below it are read
    /// while neighbouring output rows still have them in cache (a pass per level re-read the
    /// whole 16 MiB table at 2048² for each of the 12 levels).
    pub(crate) fn new(pool: &Arc<Pool>, sat: &Sat) -> NBuffer {
        let resolution = sat.resolution;
        let n = resolution as usize;
        let w = n + 1;
        let count = level_count(resolution) as usize;
        // Every texel is written below: no clearing pass.
        let mut levels: Vec<Vec<u8>> = (0..count).map(|_| pool.overwrite(n * n, 0u8)).collect();
        // Per band of rows, that band of every level.
        let band = BAND_ROWS * n.max(1);
        let mut bands: Vec<Vec<&mut [u8]>> =
            (0..n.div_ceil(BAND_ROWS)).map(|_| Vec::new()).collect();
        for level in &mut levels {
            for (b, rows) in level.chunks_mut(band).enumerate() {
                bands[b].push(rows);
            }
        }
        bands.into_par_iter().enumerate().for_each(|(b, mut band)| {
            for r in 0..BAND_ROWS.min(n - b * BAND_ROWS) {
                let y = b * BAND_ROWS + r;
                let r0 = &sat.data[y * w..(y + 1) * w];
                for (l, level) in band.iter_mut().enumerate() {
                    let row = &mut level[r * n..(r + 1) * n];
                    let s = 1usize << l;
                    let shift = 2 * l as u32;
                    // The box [x, x + s) x [y, y + s), clipped to the slice: table rows y and
                    // min(y + s, n), columns x and min(x + s, n).
                    let y1 = (y + s).min(n);
                    let r1 = &sat.data[y1 * w..(y1 + 1) * w];
                    // Texels whose box lies inside the row read columns x and x + s, the rest
                    // columns x and n; the count of a box is at most its area 4^l.
                    // (Where the box is wider than the row, no texel is inner: the columns
                    // from `s.min(n)` are an empty run, in the table row of n + 1 entries.)
                    let (inner, sx) = (n.saturating_sub(s), s.min(n));
                    let boxes = |(x, x1): (usize, usize)| {
                        r1[x1]
                            .wrapping_sub(r0[x1])
                            .wrapping_sub(r1[x])
                            .wrapping_add(r0[x])
                    };
                    let (lo, hi) = row.split_at_mut(inner);
                    if shift <= U32_SHIFT_MAX {
                        let counts = (r0[..inner].iter().zip(&r0[sx..sx + inner]))
                            .zip(r1[..inner].iter().zip(&r1[sx..sx + inner]));
                        for (v, ((&a, &b), (&c, &d))) in lo.iter_mut().zip(counts) {
                            let count = d.wrapping_sub(b).wrapping_sub(c).wrapping_add(a);
                            *v = unorm8_pow2_u32(count, shift);
                        }
                    } else {
                        for (x, v) in lo.iter_mut().enumerate() {
                            *v = unorm8_pow2(boxes((x, x + s)), shift);
                        }
                    }
                    for (x, v) in hi.iter_mut().enumerate() {
                        *v = unorm8_pow2(boxes((inner + x, n)), shift);
                    }
                }
            }
        });
        NBuffer {
            resolution,
            levels,
            pool: pool.clone(),
        }
    }

    /// Texel `(x, y)` of level `l` as a value in [0, 1]; 0 outside.
    pub(crate) fn texel(&self, l: u32, x: i64, y: i64) -> f32 {
        let r = self.resolution as i64;
        if x < 0 || y < 0 || x >= r || y >= r {
            return 0.0;
        }
        self.levels[l as usize][(y * r + x) as usize] as f32 / 255.0
    }

    /// The mean occupancy over the square of side `size` texels centred at `c`:
    /// [`nbuffer_mean`] over these levels.
    pub(crate) fn mean(&self, c: Vec2, size: f32) -> f32 {
        nbuffer_mean(c, size, self.levels.len() as u32, |l, x, y| {
            self.texel(l, x, y)
        })
    }
}

/// Linear interpolation of level `l` at the box start `b` (level texels are boxes anchored at
/// their top-left corner).
fn sample(b: Vec2, l: u32, texel: &impl Fn(u32, i64, i64) -> f32) -> f32 {
    bilinear(b, |x, y| texel(l, x, y))
}

/// `floor(log2(x))` for `x >= 1`, exact (read from the exponent bits, as the shader does).
pub(crate) fn floor_log2(x: f32) -> u32 {
    ((x.to_bits() >> 23) & 0xff).saturating_sub(127)
}

/// The N-Buffer lookup of section 3.2 (`WGSL: nbuffer_mean`): the two levels whose box sizes
/// bracket `size`, each read at the box's start, interpolated linearly in the size.
pub(crate) fn nbuffer_mean(
    c: Vec2,
    size: f32,
    levels: u32,
    texel: impl Fn(u32, i64, i64) -> f32,
) -> f32 {
    let k = size.max(1.0);
    let l = floor_log2(k).min(levels - 1);
    let s = (1u32 << l) as f32;
    let v0 = sample(c - Vec2::splat(0.5 * s), l, &texel);
    let t = (k / s - 1.0).clamp(0.0, 1.0);
    if t <= 0.0 || l + 1 >= levels {
        return v0;
    }
    let v1 = sample(c - Vec2::splat(s), l + 1, &texel);
    v0 + (v1 - v0) * t
}
