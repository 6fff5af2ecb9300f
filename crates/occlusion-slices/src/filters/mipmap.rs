//! A mipmap pyramid of a slice (Williams 1983): level `l` has `ceil(resolution / 2^l)` texels a side,
//! each the mean of its `2^l x 2^l` block of the slice (outside counts as empty), stored as
//! 8-bit unorm from exact counts, like the N-Buffers.

use super::nbuffer::floor_log2;
use super::{bilinear, level_count, unorm8_pow2};
use glam::Vec2;
use rayon::prelude::*;
use soft_shadow_core::pool::Pool;
use std::sync::Arc;

/// The pyramid of one slice.
#[derive(Clone, Debug)]
pub(crate) struct Mipmap {
    /// Side of level 0.
    pub resolution: u32,
    /// Level `l` at index `l`, `mip_size(resolution, l)²` bytes.
    pub levels: Vec<Vec<u8>>,
    pool: Arc<Pool>,
}

impl PartialEq for Mipmap {
    fn eq(&self, other: &Self) -> bool {
        (self.resolution, &self.levels) == (other.resolution, &other.levels)
    }
}

/// Side of mip level `l` of a `resolution`-wide slice.
pub(crate) fn mip_size(resolution: u32, l: u32) -> u32 {
    resolution.div_ceil(1 << l)
}

impl Drop for Mipmap {
    /// The levels' storage goes back to the pool it came from.
    fn drop(&mut self) {
        self.levels.drain(..).for_each(|l| self.pool.give(l));
    }
}

impl Mipmap {
    /// Every level down to 1x1 of a `resolution x resolution` binary slice (`occupied(x, y)`, row-major).
    #[cfg(test)]
    pub fn new(pool: &Arc<Pool>, resolution: u32, occupied: &[bool]) -> Mipmap {
        Mipmap::build(pool, resolution, occupied, |&o| o as u32)
    }

    /// Every level of slice `k` of the slice masks (bit `k` of each texel,
    /// [`crate::slicing::slice`]).
    #[cfg(test)]
    pub fn from_masks(pool: &Arc<Pool>, resolution: u32, masks: &[u32], k: u32) -> Mipmap {
        Mipmap::build(pool, resolution, masks, |&m| (m >> k) & 1)
    }

    /// The pyramid of exact counts, each level the sums of 2x2 blocks of the one below (a
    /// missing row or column beyond an odd side counts as empty), each count stored as
    /// [`unorm8_pow2`] of its block's area: the same bits as counting each block directly.
    #[cfg(test)]
    fn build<T: Sync>(
        pool: &Arc<Pool>,
        resolution: u32,
        cells: &[T],
        bit: impl Fn(&T) -> u32 + Sync,
    ) -> Mipmap {
        let (n, half) = (resolution as usize, (resolution as usize).div_ceil(2));
        let (mut level0, mut counts) = Self::base_storage(pool, n);
        level0
            .par_chunks_mut(2 * n.max(1))
            .zip(counts.par_chunks_mut(half.max(1)))
            .enumerate()
            .for_each(|(y, (rows, out))| base_row(n, cells, &bit, y, rows, out));
        Self::from_base(pool, resolution, level0, counts)
    }

    /// The pyramids of slices `ks` of the slice masks, their bases built together: one pass
    /// down the rows reads each pair of rows of masks once for all of them, where
    /// [`Mipmap::from_masks`] per slice reads the whole mask map (16 MiB at 2048²) per slice.
    /// Equal to `from_masks` of each.
    pub(crate) fn from_masks_together(
        pool: &Arc<Pool>,
        resolution: u32,
        masks: &[u32],
        ks: std::ops::Range<u32>,
    ) -> Vec<Mipmap> {
        let (n, half) = (resolution as usize, (resolution as usize).div_ceil(2));
        let mut bases: Vec<(Vec<u8>, Vec<u32>)> =
            ks.clone().map(|_| Self::base_storage(pool, n)).collect();
        for y in 0..half {
            let rows = 2 * y * n..((2 * y + 2) * n).min(n * n);
            for (k, (level0, counts)) in ks.clone().zip(&mut bases) {
                let out = &mut counts[y * half..(y + 1) * half];
                base_row(
                    n,
                    masks,
                    |&m| (m >> k) & 1,
                    y,
                    &mut level0[rows.clone()],
                    out,
                );
            }
        }
        bases
            .into_iter()
            .map(|(level0, counts)| Self::from_base(pool, resolution, level0, counts))
            .collect()
    }

    /// Storage for level 0 of an `n x n` slice and the counts of level 1, every entry written by
    /// [`base_row`].
    fn base_storage(pool: &Pool, n: usize) -> (Vec<u8>, Vec<u32>) {
        let half = n.div_ceil(2);
        (
            pool.overwrite(n * n, 0u8),
            pool.overwrite(half * half, 0u32),
        )
    }

    /// The pyramid from its level 0 and the counts of level 1.
    fn from_base(
        pool: &Arc<Pool>,
        resolution: u32,
        level0: Vec<u8>,
        mut counts: Vec<u32>,
    ) -> Mipmap {
        let mut levels = vec![level0];
        for l in 1..level_count(resolution) {
            let (src, dst) = (
                mip_size(resolution, l - 1) as usize,
                mip_size(resolution, l) as usize,
            );
            if l > 1 {
                let c = &counts;
                let next = sum_blocks(pool, src, dst, |y| &c[y * src..(y + 1) * src], |&c| c);
                pool.give(std::mem::replace(&mut counts, next));
            }
            let mut out = pool.overwrite(dst * dst, 0u8);
            out.par_iter_mut()
                .zip(counts.par_iter())
                .for_each(|(o, &c)| *o = unorm8_pow2(c, 2 * l));
            levels.push(out);
        }
        pool.give(counts);
        Mipmap {
            resolution,
            levels,
            pool: pool.clone(),
        }
    }

    /// Texel `(x, y)` of level `l` in [0, 1]; 0 outside.
    pub(crate) fn texel(&self, l: u32, x: i64, y: i64) -> f32 {
        let n = mip_size(self.resolution, l) as i64;
        if x < 0 || y < 0 || x >= n || y >= n {
            return 0.0;
        }
        self.levels[l as usize][(y * n + x) as usize] as f32 / 255.0
    }

    /// Trilinear read for a kernel of side `size` texels at `c`: [`mip_mean`].
    pub(crate) fn mean(&self, c: Vec2, size: f32) -> f32 {
        mip_mean(c, size, self.levels.len() as u32, |l, x, y| {
            self.texel(l, x, y)
        })
    }
}

/// Bilinear read of level `l` at level-0 texel position `c` (texel centres at +0.5).
fn level_bilinear(c: Vec2, l: u32, texel: &impl Fn(u32, i64, i64) -> f32) -> f32 {
    bilinear(c / (1u32 << l) as f32 - Vec2::splat(0.5), |x, y| {
        texel(l, x, y)
    })
}

/// Trilinear mipmapping (`WGSL: mip_mean`): level of detail `log2(size)`, bilinear in the two
/// nearest levels, linear between them. The kernel is square in texels, so the isotropic
/// pyramid needs no anisotropic taps.
pub(crate) fn mip_mean(
    c: Vec2,
    size: f32,
    levels: u32,
    texel: impl Fn(u32, i64, i64) -> f32,
) -> f32 {
    let k = size.max(1.0);
    let l = floor_log2(k);
    if l + 1 >= levels {
        return level_bilinear(c, levels - 1, &texel);
    }
    let t = (k / (1u32 << l) as f32).log2().clamp(0.0, 1.0);
    let v0 = level_bilinear(c, l, &texel);
    let v1 = level_bilinear(c, l + 1, &texel);
    v0 + (v1 - v0) * t
}

/// Row pair `y` of the base of an `n x n` slice: level 0's rows `2y` and `2y + 1` (each cell's
/// bit as 0 or 255; one row where `2y + 1` is past the side) into `rows`, and row `y` of the
/// counts of level 1 (the [`sum_blocks`] of the bits) into `out`, reading each cell once.
fn base_row<T>(
    n: usize,
    cells: &[T],
    bit: impl Fn(&T) -> u32,
    y: usize,
    rows: &mut [u8],
    out: &mut [u32],
) {
    out.fill(0);
    for (r, row) in rows.chunks_mut(n).enumerate() {
        let sy = 2 * y + r;
        let src = &cells[sy * n..(sy + 1) * n];
        let pairs = row.chunks_exact_mut(2).zip(src.chunks_exact(2));
        for (o, (b, c)) in out.iter_mut().zip(pairs) {
            let (b0, b1) = (bit(&c[0]), bit(&c[1]));
            b[0] = (b0 * 255) as u8;
            b[1] = (b1 * 255) as u8;
            *o += b0 + b1;
        }
        if n % 2 == 1 {
            let b = bit(&src[n - 1]);
            row[n - 1] = (b * 255) as u8;
            out[out.len() - 1] += b;
        }
    }
}

/// The `dst x dst` sums of the 2x2 blocks of a `src x src` grid whose row `y` is `row(y)`, each
/// cell counting `value(cell)`; cells beyond `src` count 0.
fn sum_blocks<'a, S: Sync + 'a>(
    pool: &Pool,
    src: usize,
    dst: usize,
    row: impl Fn(usize) -> &'a [S] + Sync,
    value: impl Fn(&S) -> u32 + Sync,
) -> Vec<u32> {
    let mut out = pool.overwrite(dst * dst, 0u32);
    out.par_chunks_mut(dst.max(1))
        .enumerate()
        .for_each(|(y, out)| {
            out.fill(0);
            for sy in [2 * y, 2 * y + 1].into_iter().filter(|&sy| sy < src) {
                let cells = row(sy);
                let pairs = cells.chunks_exact(2);
                let odd = pairs.remainder().first();
                for (o, p) in out.iter_mut().zip(pairs) {
                    *o += value(&p[0]) + value(&p[1]);
                }
                if let (Some(c), Some(o)) = (odd, out.last_mut()) {
                    *o += value(c);
                }
            }
        });
    out
}
