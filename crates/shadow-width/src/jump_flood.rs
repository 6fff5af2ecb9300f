//! Jump flooding (Rong & Tan 2006): for every texel of a square map, the nearest *seed* texel.
//!
//! Every texel keeps the nearest seed it has heard of; a pass with step `k` looks at the 3x3
//! texels `k` apart, in a fixed order, and keeps a strictly nearer seed. Steps `2^m .. 1` then one
//! more step of 1 (JFA+1). Approximate in rare configurations (a texel may end one seed off the
//! nearest); the techniques that use it report the resulting error. the exact nearest-seed map ([`crate::width::edt`] for widths)
//! gives the exact nearest seed in linear time.
//!
//! `gpu/jump_flood.wgsl` runs the same passes in the same order ([`crate::gpu_jump_flood`]), so
//! both backends give the same seeds.

use rayon::prelude::*;
use soft_shadow_core::seeds::NONE;

/// The steps: half the next power of two of the side, halving down to 1, then 1 again.
pub(crate) fn steps(resolution: u32) -> Vec<u32> {
    let mut v = Vec::new();
    let mut k = resolution.next_power_of_two() / 2;
    while k >= 1 {
        v.push(k);
        k /= 2;
    }
    v.push(1);
    v
}

/// Offsets beyond this many texels count as this many in the `i32` distance: no two texels of
/// a map up to [`soft_shadow_core::technique::MAX_CPU_RESOLUTION`] are farther apart, and [`NONE`] (texel
/// 65535, 65535) always is, so it never wins against a seed and ties with itself.
const CLAMP: i32 = 32767;
const _: () = assert!(soft_shadow_core::technique::MAX_CPU_RESOLUTION <= 16384);

/// The largest side whose squared texel distances (at most `2 (side - 1)²`) an `f32` holds
/// exactly (below 2^24): up to it a pass compares distances in `f32`, which SSE2 multiplies four
/// at a time; it has no 32-bit integer multiply.
pub(crate) const F32_EXACT_SIDE: u32 = 2896;
const _: () = assert!(2 * (F32_EXACT_SIDE as u64 - 1).pow(2) < 1 << 24);

/// A squared distance a pass compares: the same order on every pair of seeds of the map, so
/// both kinds pick the same seed; its default is the distance 0 of a texel to itself.
trait Dist2: Copy + PartialOrd + Send + Default {
    /// Squared distance from texel `(x, y)` to `seed`.
    fn of(x: i32, y: i32, seed: u32) -> Self;
}

/// Each offset clamped to [`CLAMP`] (at most `2 * 32767²`, which fits an `i32`): exact for every
/// pair of texels of a map.
impl Dist2 for i32 {
    #[inline(always)]
    fn of(x: i32, y: i32, seed: u32) -> i32 {
        let dx = ((seed & 0xffff) as i32 - x).abs().min(CLAMP);
        let dy = ((seed >> 16) as i32 - y).abs().min(CLAMP);
        dx * dx + dy * dy
    }
}

/// Exact between texels of a map up to [`F32_EXACT_SIDE`]; [`NONE`]'s (at least `2 * 62639²`
/// from such a texel, rounded) still exceeds every seed's and equals itself.
impl Dist2 for f32 {
    #[inline(always)]
    fn of(x: i32, y: i32, seed: u32) -> f32 {
        let dx = (seed & 0xffff) as i32 as f32 - x as f32;
        let dy = (seed >> 16) as i32 as f32 - y as f32;
        dx * dx + dy * dy
    }
}

/// Texels per block of a row: the 3x3 candidates of a block are compared in registers and the
/// block's seeds stored once.
const BLOCK: usize = 8;

/// The nearest of the 3x3 candidates for texels `x0 .. x0 + L` of row `y` (each texel's own seed
/// first, then the rows in order, each at columns `x - k, x, x + k`, keeping a strictly nearer
/// one; a candidate that cannot be strictly nearer is not compared). `rows[r]` is source row
/// `y - k, y, y + k` where it lies in the map; a texel outside the map offers [`NONE`], which
/// never wins: the same as offering nothing, so a candidate block wholly outside is skipped.
#[inline(always)]
fn block<const L: usize, D: Dist2>(
    rows: &[Option<&[u32]>; 3],
    centre: &[u32],
    out: &mut [u32],
    x0: usize,
    y: i32,
    k: usize,
) {
    let xs: [i32; L] = std::array::from_fn(|l| (x0 + l) as i32);
    let mut best: [u32; L] = std::array::from_fn(|l| centre[x0 + l]);
    let mut best_d: [D; L] = std::array::from_fn(|l| D::of(xs[l], y, best[l]));
    // Texels that are their own seeds (distance 0) cannot hear of a strictly nearer one: a
    // block of them (most of a map whose seeds are its unblocked texels) keeps its seeds.
    if best_d
        .iter()
        .fold(true, |all, d| all & (*d == D::default()))
    {
        out[x0..x0 + L].copy_from_slice(&best);
        return;
    }
    for (r, row) in rows.iter().enumerate() {
        let Some(row) = row else { continue };
        let n = row.len();
        for c in [0, k, 2 * k] {
            // The texel itself offers its own seed, never strictly nearer than the best.
            if r == 1 && c == k {
                continue;
            }
            // Columns `x0 + c - k ..` of the row, NONE outside the map.
            let (from, to) = (x0 + c, x0 + c + L);
            let cand: [u32; L] = if from >= k && to <= n + k {
                // Always `L` long.
                row[from - k..to - k].try_into().unwrap_or([NONE; L])
            } else if to <= k || from >= n + k {
                continue;
            } else {
                std::array::from_fn(|l| {
                    (from + l)
                        .checked_sub(k)
                        .and_then(|x| row.get(x))
                        .copied()
                        .unwrap_or(NONE)
                })
            };
            // Candidates equal to the best seeds are at the same distances: no change. Late
            // passes, inside one seed's region, skip most candidates this way.
            if cand
                .iter()
                .zip(&best)
                .fold(true, |all, (c, b)| all & (c == b))
            {
                continue;
            }
            for l in 0..L {
                let d = D::of(xs[l], y, cand[l]);
                let nearer = d < best_d[l];
                best_d[l] = if nearer { d } else { best_d[l] };
                best[l] = if nearer { cand[l] } else { best[l] };
            }
        }
    }
    out[x0..x0 + L].copy_from_slice(&best);
}

/// One pass with step `k` over a `resolution`-wide square map: reads `src`, writes `dst`. Every texel
/// starts from its own seed and is offered the 3x3 texels `k` apart in a fixed order (rows
/// `y - k, y, y + k`, then columns `x - k, x, x + k`), keeping a strictly nearer seed. Texels go
/// in blocks of 8 whose candidates are compared in registers, branch-free over seeds.
/// Distances are compared in `f32` up to [`F32_EXACT_SIDE`], in `i32` beyond: the same seeds
/// either way.
pub(crate) fn pass(src: &[u32], dst: &mut [u32], resolution: u32, k: u32) {
    if resolution <= F32_EXACT_SIDE {
        pass_in::<f32>(src, dst, resolution, k)
    } else {
        pass_in::<i32>(src, dst, resolution, k)
    }
}

fn pass_in<D: Dist2>(src: &[u32], dst: &mut [u32], resolution: u32, k: u32) {
    let (n, k) = (resolution as usize, (k as usize).min(resolution as usize));
    dst.par_chunks_mut(n.max(1))
        .enumerate()
        .for_each(|(y, out)| {
            let centre = &src[y * n..(y + 1) * n];
            let sources = [y.checked_sub(k), Some(y), (y + k < n).then_some(y + k)];
            let rows = sources.map(|r| r.map(|r| &src[r * n..(r + 1) * n]));
            let yi = y as i32;
            let whole = n / BLOCK * BLOCK;
            for x0 in (0..whole).step_by(BLOCK) {
                block::<BLOCK, D>(&rows, centre, out, x0, yi, k);
            }
            for x0 in whole..n {
                block::<1, D>(&rows, centre, out, x0, yi, k);
            }
        });
}

/// Floods `seeds` (one value per texel of a `resolution`-wide square map: [`pack`]ed coordinates of the
/// texel itself for a seed, [`NONE`] otherwise) and returns the nearest seed of every texel (up
/// to jump flooding's rare misses; the exact nearest-seed map ([`crate::width::edt`] for widths) is exact). The scratch buffer
/// comes from `pool` and goes back there; so may the result, once read
/// ([`soft_shadow_core::pool::Pool::give`]).
///
/// [`pack`]: soft_shadow_core::seeds::pack
pub(crate) fn flood(
    pool: &soft_shadow_core::pool::Pool,
    seeds: Vec<u32>,
    resolution: u32,
) -> Vec<u32> {
    let mut a = seeds;
    // Each pass writes every texel of its destination: no clearing pass.
    let mut b = pool.overwrite(a.len(), NONE);
    for k in steps(resolution) {
        pass(&a, &mut b, resolution, k);
        std::mem::swap(&mut a, &mut b);
    }
    pool.give(b);
    a
}

#[cfg(test)]
mod tests {
    use super::*;
    use soft_shadow_core::seeds::{dist2, pack};

    /// The pass by its definition, texel by texel: own seed first, then rows `y - k, y, y + k`,
    /// each at columns `x - k, x, x + k` (inside the map), keeping a strictly nearer seed by the
    /// exact `i64` distance; only rows `y % every == 0` (the others stay [`NONE`]).
    fn reference_pass(src: &[u32], n: u32, k: u32, every: usize) -> Vec<u32> {
        let (n, k) = (n as i64, k as i64);
        let at = |x: i64, y: i64| src[(y * n + x) as usize];
        let mut out = vec![NONE; src.len()];
        let rows = out.par_chunks_mut(n as usize).enumerate();
        rows.filter(|(y, _)| y % every == 0).for_each(|(y, row)| {
            let y = y as i64;
            for (x, o) in (0..n).zip(row) {
                let d = |s: u32| {
                    if s == NONE {
                        i64::MAX
                    } else {
                        dist2(x as i32, y as i32, s)
                    }
                };
                *o = at(x, y);
                for cy in [y - k, y, y + k].into_iter().filter(|c| (0..n).contains(c)) {
                    for cx in [x - k, x, x + k].into_iter().filter(|c| (0..n).contains(c)) {
                        if d(at(cx, cy)) < d(*o) {
                            *o = at(cx, cy);
                        }
                    }
                }
            }
        });
        out
    }

    /// Every pass of a flood equals the texel-by-texel definition: in `f32` at the largest side
    /// it is used for (a lattice of seeds, whose ties the fixed order decides, sparse random
    /// seeds and the two far corners, so the longest distances of
    /// the map are compared; every 8th row checked) and at a side whose rows end in a partial
    /// block, and in `i32` there; and seeds everywhere but in holes, where whole blocks of texels
    /// are their own seeds.
    #[test]
    fn passes_follow_the_definition() {
        for (n, kind, every, dense) in [
            (F32_EXACT_SIDE, "f32", 8, false),
            (1003, "f32", 1, false),
            (1003, "i32", 1, false),
            (1003, "f32", 1, true),
        ] {
            let mut rng = soft_shadow_core::rng::SplitMix(7);
            let mut a: Vec<u32> = (0..n * n)
                .map(|i| {
                    let s = rng.next_u64();
                    let (x, y) = (i % n, i / n);
                    // A lattice (many texels equidistant from two seeds: ties) and noise.
                    let lattice = x % 96 == 5 && y % 88 == 7;
                    // Or seeds everywhere but in holes (a width map's unblocked texels): whole
                    // blocks of texels at distance 0 next to blocks that are not.
                    let hole = (x / 37 + y / 29) % 3 == 0 || s.is_multiple_of(7);
                    if (dense && !hole) || lattice || s.is_multiple_of(40_000) {
                        pack(x, y)
                    } else {
                        NONE
                    }
                })
                .collect();
            a[0] = pack(0, 0);
            a[(n * n - 1) as usize] = pack(n - 1, n - 1);
            let mut b = vec![NONE; a.len()];
            for k in steps(n) {
                match kind {
                    "f32" => pass_in::<f32>(&a, &mut b, n, k),
                    _ => pass_in::<i32>(&a, &mut b, n, k),
                }
                let expect = reference_pass(&a, n, k, every);
                let mut rows = b
                    .chunks(n as usize)
                    .zip(expect.chunks(n as usize))
                    .step_by(every);
                assert!(rows.all(|(b, e)| b == e), "{kind} side {n} step {k}");
                std::mem::swap(&mut a, &mut b);
            }
            assert!(a.iter().all(|&s| s != NONE), "side {n}: flooded");
        }
    }
}
