//! Jump flooding (Rong & Tan 2006) on the CPU, exactly as `width.wgsl` runs it: every texel keeps
//! the nearest seed (unblocked texel) it has heard of; a pass with step `k` looks at the 3x3
//! texels `k` apart, in a fixed order, and keeps a strictly nearer seed. Steps `2^m .. 1` then one
//! more step of 1 (JFA+1). Approximate in rare configurations; the harness reports its error.

use rayon::prelude::*;
use shadow_core::Map2D;

/// No seed heard of yet.
pub const NONE: u32 = u32::MAX;

/// Packs texel coordinates (each below 65536).
pub fn pack(x: u32, y: u32) -> u32 {
    x | (y << 16)
}

fn dist2(x: i32, y: i32, seed: u32) -> i64 {
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

/// One pass with step `k`: reads `src`, writes `dst`.
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

/// The jump-flooded width map of `mask`, capped at [`super::cap`].
pub fn width(mask: &Map2D<bool>) -> Map2D<f32> {
    let res = mask.width();
    let mut a: Vec<u32> = mask
        .data()
        .iter()
        .enumerate()
        .map(|(i, &b)| {
            if b {
                NONE
            } else {
                pack(i as u32 % res, i as u32 / res)
            }
        })
        .collect();
    let mut b = vec![NONE; a.len()];
    for k in steps(res) {
        pass(&a, &mut b, res, k);
        std::mem::swap(&mut a, &mut b);
    }
    let cap = super::cap(res);
    let w = a
        .iter()
        .enumerate()
        .map(|(i, &s)| {
            if s == NONE {
                cap
            } else {
                let (x, y) = (i as u32 % res, i as u32 / res);
                (dist2(x as i32, y as i32, s) as f32).sqrt().min(cap)
            }
        })
        .collect();
    Map2D::from_vec(res, mask.height(), w).unwrap_or_else(|| Map2D::new(0, 0, 0.0))
}
