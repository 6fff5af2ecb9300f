//! A mipmap pyramid of a slice (Williams 1983): level `l` has `ceil(res / 2^l)` texels a side,
//! each the mean of its `2^l x 2^l` block of the slice (outside counts as empty), stored as
//! 8-bit unorm from exact counts, like the N-Buffers.

use super::nbuffer::floor_log2;
use super::sat::Sat;
use super::{bilinear, level_count, unorm8_pow2};
use glam::Vec2;
use rayon::prelude::*;

/// The pyramid of one slice.
#[derive(Clone, Debug, PartialEq)]
pub struct Mipmap {
    /// Side of level 0.
    pub res: u32,
    /// Level `l` at index `l`, `mip_size(res, l)²` bytes.
    pub levels: Vec<Vec<u8>>,
}

/// Side of mip level `l` of a `res`-wide slice.
pub fn mip_size(res: u32, l: u32) -> u32 {
    res.div_ceil(1 << l)
}

impl Drop for Mipmap {
    /// The levels' storage goes back to [`shadow_core::pool`].
    fn drop(&mut self) {
        self.levels.drain(..).for_each(shadow_core::pool::give);
    }
}

impl Mipmap {
    /// Every level down to 1x1, from the slice's table.
    pub fn new(sat: &Sat) -> Mipmap {
        let res = sat.res;
        let (r, w) = (res as usize, res as usize + 1);
        let levels = (0..level_count(res))
            .map(|l| {
                let n = mip_size(res, l) as usize;
                let s = 1usize << l;
                let shift = 2 * l;
                let mut out = shadow_core::pool::filled(n * n, 0u8);
                out.par_chunks_mut(n.max(1))
                    .enumerate()
                    .for_each(|(y, row)| {
                        // Block [x s, x s + s) x [y s, y s + s), clipped to the slice, from the
                        // table's rows.
                        let (y0, y1) = (y * s, (y * s + s).min(r));
                        let r0 = &sat.data[y0 * w..(y0 + 1) * w];
                        let r1 = &sat.data[y1 * w..(y1 + 1) * w];
                        for (x, v) in row.iter_mut().enumerate() {
                            let (x0, x1) = (x * s, (x * s + s).min(r));
                            let c = r1[x1]
                                .wrapping_sub(r0[x1])
                                .wrapping_sub(r1[x0])
                                .wrapping_add(r0[x0]);
                            *v = unorm8_pow2(c, shift);
                        }
                    });
                out
            })
            .collect();
        Mipmap { res, levels }
    }

    /// Texel `(x, y)` of level `l` in [0, 1]; 0 outside.
    pub fn texel(&self, l: u32, x: i64, y: i64) -> f32 {
        let n = mip_size(self.res, l) as i64;
        if x < 0 || y < 0 || x >= n || y >= n {
            return 0.0;
        }
        self.levels[l as usize][(y * n + x) as usize] as f32 / 255.0
    }

    /// Trilinear read for a kernel of side `size` texels at `c`: [`mip_mean`].
    pub fn mean(&self, c: Vec2, size: f32) -> f32 {
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
pub fn mip_mean(c: Vec2, size: f32, levels: u32, texel: impl Fn(u32, i64, i64) -> f32) -> f32 {
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
