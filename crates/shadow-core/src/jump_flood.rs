//! Jump flooding (Rong & Tan 2006): for every texel of a square map, the nearest *seed* texel.
//!
//! Every texel keeps the nearest seed it has heard of; a pass with step `k` looks at the 3x3
//! texels `k` apart, in a fixed order, and keeps a strictly nearer seed. Steps `2^m .. 1` then one
//! more step of 1 (JFA+1). Approximate in rare configurations (a texel may end one seed off the
//! nearest); the techniques that use it report the resulting error.
//!
//! `gpu/jump_flood.wgsl` runs the same passes in the same order ([`crate::gpu::jump_flood`]), so
//! both backends give the same seeds.

use rayon::prelude::*;

/// No seed heard of yet.
pub const NONE: u32 = u32::MAX;

/// Packs texel coordinates (each below 65536) into one seed value.
pub fn pack(x: u32, y: u32) -> u32 {
    x | (y << 16)
}

/// The texel coordinates of a packed seed.
pub fn unpack(seed: u32) -> (u32, u32) {
    (seed & 0xffff, seed >> 16)
}

/// Squared distance in texels from `(x, y)` to `seed`.
pub fn dist2(x: i32, y: i32, seed: u32) -> i64 {
    let dx = (seed & 0xffff) as i64 - x as i64;
    let dy = (seed >> 16) as i64 - y as i64;
    dx * dx + dy * dy
}

/// The steps: half the next power of two of the side, halving down to 1, then 1 again.
pub fn steps(resolution: u32) -> Vec<u32> {
    let mut v = Vec::new();
    let mut k = resolution.next_power_of_two() / 2;
    while k >= 1 {
        v.push(k);
        k /= 2;
    }
    v.push(1);
    v
}

/// One pass with step `k` over a `res`-wide square map: reads `src`, writes `dst`.
pub fn pass(src: &[u32], dst: &mut [u32], res: u32, k: u32) {
    let r = res as i32;
    let k = k as i32;
    dst.par_chunks_mut(res as usize)
        .enumerate()
        .for_each(|(y, row)| {
            let y = y as i32;
            for (x, out) in row.iter_mut().enumerate() {
                let x = x as i32;
                let mut best = src[(y * r + x) as usize];
                let mut best_d = if best == NONE {
                    i64::MAX
                } else {
                    dist2(x, y, best)
                };
                for dy in -1..=1 {
                    for dx in -1..=1 {
                        let (qx, qy) = (x + dx * k, y + dy * k);
                        if qx < 0 || qy < 0 || qx >= r || qy >= r {
                            continue;
                        }
                        let s = src[(qy * r + qx) as usize];
                        if s != NONE {
                            let d = dist2(x, y, s);
                            if d < best_d {
                                best = s;
                                best_d = d;
                            }
                        }
                    }
                }
                *out = best;
            }
        });
}

/// Floods `seeds` (one value per texel of a `res`-wide square map: [`pack`]ed coordinates of the
/// texel itself for a seed, [`NONE`] otherwise) and returns the nearest seed of every texel.
pub fn flood(seeds: Vec<u32>, res: u32) -> Vec<u32> {
    let mut a = seeds;
    let mut b = vec![NONE; a.len()];
    for k in steps(res) {
        pass(&a, &mut b, res, k);
        std::mem::swap(&mut a, &mut b);
    }
    a
}
