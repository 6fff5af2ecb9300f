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

/// Offsets beyond this many texels count as this many in [`pass`]: no two texels of a map up to
/// [`crate::technique::MAX_CPU_RESOLUTION`] are farther apart, and [`NONE`] (texel 65535,
/// 65535) always is, so it never wins against a seed and ties with itself.
const CLAMP: i32 = 32767;
const _: () = assert!(crate::technique::MAX_CPU_RESOLUTION <= 16384);

/// Squared distance from texel `(x, y)` to `seed`, each offset clamped to [`CLAMP`] (at most
/// `2 * 32767²`, which fits an `i32`).
#[inline(always)]
fn clamped_dist2(x: i32, y: i32, seed: u32) -> i32 {
    let dx = ((seed & 0xffff) as i32 - x).abs().min(CLAMP);
    let dy = ((seed >> 16) as i32 - y).abs().min(CLAMP);
    dx * dx + dy * dy
}

/// Offers `cand[i]` to texel `x0 + i` of row `y` for every `i`, keeping a strictly nearer one.
#[inline(always)]
fn offer(out: &mut [u32], best_d: &mut [i32], cand: &[u32], x0: usize, y: i32) {
    for (i, ((o, bd), &s)) in out.iter_mut().zip(best_d.iter_mut()).zip(cand).enumerate() {
        let d = clamped_dist2((x0 + i) as i32, y, s);
        let nearer = d < *bd;
        *bd = if nearer { d } else { *bd };
        *o = if nearer { s } else { *o };
    }
}

/// One pass with step `k` over a `res`-wide square map: reads `src`, writes `dst`. Every texel
/// starts from its own seed and is offered the 3x3 texels `k` apart in a fixed order (rows
/// `y - k, y, y + k`, then columns `x - k, x, x + k`), keeping a strictly nearer seed. Each row
/// runs candidate by candidate over the whole row (the same order per texel) and branch-free
/// over seeds: a third faster than texel by texel with a test for [`NONE`].
pub fn pass(src: &[u32], dst: &mut [u32], res: u32, k: u32) {
    let (n, k) = (res as usize, (k as usize).min(res as usize));
    dst.par_chunks_mut(n.max(1)).enumerate().for_each_init(
        || vec![0i32; n],
        |best_d, (y, out)| {
            let rows = [y.checked_sub(k), Some(y), (y + k < n).then_some(y + k)]
                .map(|r| r.map(|r| &src[r * n..(r + 1) * n]));
            let centre = &src[y * n..(y + 1) * n];
            let yi = y as i32;
            out.copy_from_slice(centre);
            for (x, (d, &s)) in best_d.iter_mut().zip(centre).enumerate() {
                *d = clamped_dist2(x as i32, yi, s);
            }
            for row in rows.iter().flatten() {
                // Column x - k for x in k..n, then x, then x + k for x in 0..n - k.
                offer(&mut out[k..], &mut best_d[k..], &row[..n - k], k, yi);
                offer(out, best_d, row, 0, yi);
                offer(&mut out[..n - k], &mut best_d[..n - k], &row[k..], 0, yi);
            }
        },
    );
}

/// Floods `seeds` (one value per texel of a `res`-wide square map: [`pack`]ed coordinates of the
/// texel itself for a seed, [`NONE`] otherwise) and returns the nearest seed of every texel.
/// The scratch buffer comes from [`crate::pool`] and goes back there; so may the result, once
/// read ([`crate::pool::give`]).
pub fn flood(seeds: Vec<u32>, res: u32) -> Vec<u32> {
    let mut a = seeds;
    let mut b = crate::pool::filled(a.len(), NONE);
    for k in steps(res) {
        pass(&a, &mut b, res, k);
        std::mem::swap(&mut a, &mut b);
    }
    crate::pool::give(b);
    a
}
