//! The paper's shadow-width propagation (Kirsch & Döllner 2003, section 4), as on its GPU path:
//! every pass replaces a texel by the minimum of itself and its neighbours at distance `step`
//! plus the distance travelled, reading only the previous pass (ping-pong), with the step doubling
//! from 1 until it reaches the map side. The paper adds one "difference value" per step whatever
//! the direction; we add the offset's length (`step` or `step √2`), which makes the 8-neighbour
//! variant a closer approximation of the Euclidean distance. The paper's hardware loop sampled
//! 3 or 6 directions (120 or 60 degrees apart); those offsets are rounded to the nearest texel
//! at each step and cost their rounded length. `width.wgsl` reads the same table ([`offsets`]).

use crate::params::Neighbours;
use rayon::prelude::*;
use soft_shadow_core::Map2D;

/// Value of a blocked texel before propagation reaches it.
pub(crate) const UNREACHED: f32 = 1.0e9;
/// √2, the diagonal offset length.
pub(crate) const SQRT_2: f32 = std::f32::consts::SQRT_2;

/// Offsets `(dx, dy)` in texels of the pass with step `step`, and the distance each adds.
pub(crate) fn offsets(n: Neighbours, step: u32) -> Vec<(i32, i32, f32)> {
    const GRID: [(i32, i32, f32); 8] = [
        (1, 0, 1.0),
        (-1, 0, 1.0),
        (0, 1, 1.0),
        (0, -1, 1.0),
        (1, 1, SQRT_2),
        (-1, 1, SQRT_2),
        (1, -1, SQRT_2),
        (-1, -1, SQRT_2),
    ];
    let s = step as i32;
    match n {
        Neighbours::Four | Neighbours::Eight => GRID[..n.count() as usize]
            .iter()
            .map(|&(dx, dy, len)| (dx * s, dy * s, step as f32 * len))
            .collect(),
        Neighbours::Three | Neighbours::Six => (0..n.count())
            .map(|k| {
                // In f64, so that the rounding of the 120/240 degree offsets is well defined.
                let a = std::f64::consts::TAU * k as f64 / n.count() as f64;
                let (dx, dy) = (
                    (step as f64 * a.cos()).round(),
                    (step as f64 * a.sin()).round(),
                );
                (dx as i32, dy as i32, dx.hypot(dy) as f32)
            })
            .collect(),
    }
}

/// The steps of the passes: 1, 2, 4, ... below the map side.
pub(crate) fn steps(resolution: u32) -> Vec<u32> {
    let mut v = Vec::new();
    let mut s = 1u32;
    while s < resolution {
        v.push(s);
        s *= 2;
    }
    v
}

/// Texels per chunk of a row that a pass skips when it is 0 throughout.
const CHUNK: usize = 64;

/// Per chunk of [`CHUNK`] texels of each row (row-major, `resolution.div_ceil(CHUNK)` a row), whether
/// every texel of it is +0 in a buffer. A texel at 0 (unblocked, or reached at no distance)
/// stays 0: every candidate adds a positive length to a value of at least 0.
fn zero_chunks(buf: &[f32], resolution: u32, zero: &mut [bool]) {
    let w = resolution as usize;
    let per_row = w.div_ceil(CHUNK);
    zero.par_chunks_mut(per_row.max(1))
        .zip(buf.par_chunks(w.max(1)))
        .for_each(|(z, row)| {
            for (z, c) in z.iter_mut().zip(row.chunks(CHUNK)) {
                *z = all_zero(c);
            }
        });
}

/// Whether every texel of `texels` is +0 (bit for bit: a chunk written as 0 reads back the same).
fn all_zero(texels: &[f32]) -> bool {
    texels.iter().all(|&v| v.to_bits() == 0)
}

/// One pass with step `step`: reads `src`, writes `dst`. Each row starts from its own texels
/// and takes one offset at a time over a chunk of the row (the source row shifted by `dx`,
/// clipped to the map): the same minimum per texel as offset by offset per texel, in a loop that
/// vectorizes; a chunk of 64 texels at 0 in `src` is 0 in `dst` too.
#[cfg(test)]
pub fn pass(src: &[f32], dst: &mut [f32], resolution: u32, step: u32, n: Neighbours) {
    let chunks = (resolution as usize).div_ceil(CHUNK) * resolution as usize;
    let (mut src_zero, mut dst_zero) = (vec![false; chunks], vec![false; chunks]);
    zero_chunks(src, resolution, &mut src_zero);
    pass_chunks(src, dst, resolution, step, n, &src_zero, &mut dst_zero);
}

/// [`pass`] given `src_zero` and `dst_zero`, the [`zero_chunks`] of the two buffers: a chunk at
/// 0 in `src` is written only if `dst` does not hold 0s there already (from two passes before);
/// `dst_zero` is brought up to date.
fn pass_chunks(
    src: &[f32],
    dst: &mut [f32],
    resolution: u32,
    step: u32,
    n: Neighbours,
    src_zero: &[bool],
    dst_zero: &mut [bool],
) {
    let (r, w) = (resolution as i64, resolution as usize);
    let per_row = w.div_ceil(CHUNK).max(1);
    let offs = offsets(n, step);
    dst.par_chunks_mut(w.max(1))
        .zip(dst_zero.par_chunks_mut(per_row))
        .enumerate()
        .for_each(|(y, (row, zero))| {
            let src_row = &src[y * w..(y + 1) * w];
            for (c, dst_is_zero) in zero.iter_mut().enumerate() {
                let (lo, hi) = (c * CHUNK, ((c + 1) * CHUNK).min(w));
                if src_zero[y * per_row + c] {
                    if !*dst_is_zero {
                        row[lo..hi].fill(0.0);
                        *dst_is_zero = true;
                    }
                    continue;
                }
                let out = &mut row[lo..hi];
                out.copy_from_slice(&src_row[lo..hi]);
                let (lo, hi) = (lo as i64, hi as i64);
                for &(dx, dy, len) in &offs {
                    let qy = y as i64 + dy as i64;
                    if qy < 0 || qy >= r {
                        continue;
                    }
                    // Texels x of the chunk with 0 <= x + dx < resolution.
                    let dx = dx as i64;
                    let (x0, x1) = ((-dx).clamp(lo, hi), (r - dx).clamp(lo, hi));
                    if x0 >= x1 {
                        continue;
                    }
                    let from = (qy * r + x0 + dx) as usize;
                    let shifted = &src[from..from + (x1 - x0) as usize];
                    let part = &mut out[(x0 - lo) as usize..(x1 - lo) as usize];
                    for (o, &v) in part.iter_mut().zip(shifted) {
                        let c = v + len;
                        *o = if c < *o { c } else { *o };
                    }
                }
                *dst_is_zero = all_zero(out);
            }
        });
}

/// The propagated width map of `mask`, capped at [`super::cap`].
pub(crate) fn width(
    pool: &std::sync::Arc<soft_shadow_core::pool::Pool>,
    mask: &Map2D<bool>,
    n: Neighbours,
) -> Map2D<f32> {
    let resolution = mask.width();
    let rows = (resolution as usize).max(1);
    // The start and each pass write every texel of their destination: no clearing pass.
    let mut a = pool.overwrite(mask.data().len(), 0.0f32);
    a.par_chunks_mut(rows)
        .zip(mask.data().par_chunks(rows))
        .for_each(|(a, m)| {
            for (a, &b) in a.iter_mut().zip(m) {
                *a = if b { UNREACHED } else { 0.0 };
            }
        });
    let mut b = pool.overwrite(a.len(), 0.0f32);
    let chunks = rows.div_ceil(CHUNK) * mask.height() as usize;
    let mut a_zero = vec![false; chunks];
    zero_chunks(&a, resolution, &mut a_zero);
    // `b` holds no known 0s yet.
    let mut b_zero = vec![false; chunks];
    for step in steps(resolution) {
        pass_chunks(&a, &mut b, resolution, step, n, &a_zero, &mut b_zero);
        std::mem::swap(&mut a, &mut b);
        std::mem::swap(&mut a_zero, &mut b_zero);
    }
    pool.give(b);
    let cap = super::cap(resolution);
    a.par_chunks_mut(rows)
        .for_each(|row| row.iter_mut().for_each(|w| *w = w.min(cap)));
    Map2D::from_vec(resolution, mask.height(), a)
        .unwrap_or_else(|| Map2D::new(0, 0, 0.0))
        .returning_to(pool)
}
