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

/// One pass with step `k` over a `res`-wide square map: reads `src`, writes `dst`. Each row
/// reads the three source rows `k` apart once, and the neighbours in the fixed order (rows
/// `y - k, y, y + k`, then columns `x - k, x, x + k`).
pub fn pass(src: &[u32], dst: &mut [u32], res: u32, k: u32) {
    let (n, k) = (res as usize, k as usize);
    dst.par_chunks_mut(n.max(1))
        .enumerate()
        .for_each(|(y, out)| {
            let rows = [y.checked_sub(k), Some(y), (y + k < n).then_some(y + k)]
                .map(|r| r.map(|r| &src[r * n..(r + 1) * n]));
            let centre = &src[y * n..(y + 1) * n];
            let yi = y as i32;
            for (x, o) in out.iter_mut().enumerate() {
                let xi = x as i32;
                let mut best = centre[x];
                let mut best_d = if best == NONE {
                    i64::MAX
                } else {
                    dist2(xi, yi, best)
                };
                let cols = [x.checked_sub(k), Some(x), (x + k < n).then_some(x + k)];
                for row in rows.iter().flatten() {
                    for &q in cols.iter().flatten() {
                        let s = row[q];
                        if s != NONE {
                            let d = dist2(xi, yi, s);
                            if d < best_d {
                                best = s;
                                best_d = d;
                            }
                        }
                    }
                }
                *o = best;
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
