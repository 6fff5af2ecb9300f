//! Exact Euclidean distance transform in linear time (Felzenszwalb & Huttenlocher, *Distance
//! Transforms of Sampled Functions*, 2012): per column the 1D distance to the nearest unblocked
//! texel (two sweeps), then per row the lower envelope of the parabolas `(x - q)² + g(q)²`.
//! `width.wgsl` runs the same two passes with one invocation per column, then per row.
//!
//! On the CPU both passes run in parallel: the column pass over strips of 64 columns
//! (each sweep walks the strip's rows in order, so memory is read in cache lines), the row pass
//! over rows with its scratch kept per thread. Rows without a blocked texel are written as 0
//! without an envelope.

use rayon::prelude::*;
use soft_shadow_core::Map2D;
use soft_shadow_core::pool::Pool;
use std::sync::Arc;

/// Column distance of a texel whose column has no unblocked texel. Column distances are `u16`
/// (every other one is below the map side), which halves the column pass's traffic.
const NONE: u16 = u16::MAX;
const _: () = assert!(soft_shadow_core::technique::MAX_CPU_RESOLUTION <= NONE as u32);

/// Columns per strip of the column pass.
const STRIP: usize = 64;

/// Column pass: for every texel, the vertical distance to the nearest unblocked texel of its
/// column ([`NONE`] when the column has none), as strips of [`STRIP`] columns: strip `s` holds
/// columns `s * STRIP ..` (the last one narrower), row-major.
fn columns(pool: &Pool, mask: &Map2D<bool>) -> Vec<Vec<u16>> {
    let (w, h) = (mask.width() as usize, mask.height() as usize);
    let m = mask.data();
    (0..w.div_ceil(STRIP))
        .into_par_iter()
        .map(|s| {
            let x0 = s * STRIP;
            let sw = STRIP.min(w - x0);
            // The downward sweep writes every texel: no clearing pass.
            let mut out = pool.overwrite(sw * h, NONE);
            let mut run = [NONE; STRIP];
            // Branch-free, so the sweeps vectorize: one more than above when blocked, else 0.
            let step = |r: &mut u16, blocked: bool| {
                *r = r.saturating_add(1) & (blocked as u16).wrapping_neg();
                *r
            };
            for (y, o) in out.chunks_exact_mut(sw).enumerate() {
                let cells = &m[y * w + x0..y * w + x0 + sw];
                for ((o, r), &b) in o.iter_mut().zip(&mut run).zip(cells) {
                    *o = step(r, b);
                }
            }
            run = [NONE; STRIP];
            for (y, o) in out.chunks_exact_mut(sw).enumerate().rev() {
                let cells = &m[y * w + x0..y * w + x0 + sw];
                for ((o, r), &b) in o.iter_mut().zip(&mut run).zip(cells) {
                    *o = (*o).min(step(r, b));
                }
            }
            out
        })
        .collect()
}

/// Scratch of the row pass, one per thread: the row's column distances, the envelope's
/// parabolas and the boundaries between them.
#[derive(Default)]
struct Envelope {
    g: Vec<u16>,
    v: Vec<usize>,
    z: Vec<Boundary>,
    d2: Vec<f64>,
}

/// Where parabola `q` overtakes parabola `p < q` of a row: `x = num / den` exactly, with
/// `num = f(q) - f(p)` and `den = 2 (q - p) > 0`, `f(q) = g(q)² + q²`. Comparisons cross-multiply
/// in `i64` (`|num| < 2^29`, `den <= 2^15` up to 16384² maps), so no division and no rounding.
#[derive(Clone, Copy)]
struct Boundary {
    num: i64,
    den: i64,
}

impl Boundary {
    /// Whether this boundary lies at or left of `other`.
    fn at_or_before(self, other: Boundary) -> bool {
        self.num * other.den <= other.num * self.den
    }
}

impl Envelope {
    /// Writes into `out` the distance of every texel of the row whose column distances are
    /// `self.g` ([`NONE`]: no parabola) to the nearest unblocked texel, capped at `cap`.
    fn row(&mut self, out: &mut [f32], cap: f32) {
        let (g, v, z) = (&self.g, &mut self.v, &mut self.z);
        let f = |q: usize| {
            let d = g[q] as i64;
            d * d + (q * q) as i64
        };
        v.clear();
        z.clear();
        let last = g.len().saturating_sub(1);
        for (q, &gq) in g.iter().enumerate() {
            // Inside a run of unblocked texels (0 on both sides) a parabola is never nearer than
            // the run's ends to a texel outside the run, and a texel inside reads 0 (below):
            // only the ends enter the envelope.
            let interior = gq == 0 && q > 0 && q < last && g[q - 1] == 0 && g[q + 1] == 0;
            if gq == NONE || interior {
                continue;
            }
            loop {
                let Some(&p) = v.last() else {
                    v.push(q);
                    // The first parabola's left boundary (minus infinity) is never read.
                    z.push(Boundary { num: 0, den: 1 });
                    break;
                };
                let s = Boundary {
                    num: f(q) - f(p),
                    den: 2 * (q - p) as i64,
                };
                if v.len() > 1 && s.at_or_before(z[z.len() - 1]) {
                    v.pop();
                    z.pop();
                    continue;
                }
                v.push(q);
                z.push(s);
                break;
            }
        }
        if v.is_empty() {
            out.fill(cap);
            return;
        }
        // Squared distances first, then the square roots in a loop of their own (it vectorizes).
        // Parabola `k` is the lowest from the first texel its left boundary lies strictly left
        // of (`floor(num / den) + 1`) to where the next one's begins: filled run by run, without
        // a test per texel.
        let n = out.len();
        let start = |k: usize| {
            let b = z[k];
            (b.num.div_euclid(b.den) + 1).clamp(0, n as i64) as usize
        };
        let d2 = &mut self.d2;
        d2.resize(n, 0.0);
        let mut from = 0;
        for (k, &q) in v.iter().enumerate() {
            let to = if k + 1 < v.len() {
                start(k + 1).max(from)
            } else {
                n
            };
            let gq2 = (g[q] as u64).pow(2);
            for (x, (d2, &gx)) in d2[from..to].iter_mut().zip(&g[from..to]).enumerate() {
                let d = (from + x).abs_diff(q) as u64;
                *d2 = if gx == 0 { 0.0 } else { (d * d + gq2) as f64 };
            }
            from = to;
        }
        for (o, &d2) in out.iter_mut().zip(d2.iter()) {
            *o = d2.sqrt().min(cap as f64) as f32;
        }
    }
}

/// The exact width map of `mask`, capped at [`super::cap`].
pub(crate) fn width(pool: &Arc<Pool>, mask: &Map2D<bool>) -> Map2D<f32> {
    let (w, h) = (mask.width() as usize, mask.height() as usize);
    let strips = columns(pool, mask);
    let cap = super::cap(mask.width());
    // Every row is written below: no clearing pass.
    let mut out = pool.overwrite(mask.data().len(), 0.0f32);
    out.par_chunks_mut(w.max(1))
        .enumerate()
        .for_each_init(Envelope::default, |e, (y, row)| {
            e.g.clear();
            for s in &strips {
                let sw = s.len() / h;
                e.g.extend_from_slice(&s[y * sw..(y + 1) * sw]);
            }
            if e.g.iter().all(|&d| d == 0) {
                row.fill(0.0);
            } else {
                e.row(row, cap);
            }
        });
    strips.into_iter().for_each(|s| pool.give(s));
    Map2D::from_vec(mask.width(), mask.height(), out)
        .unwrap_or_else(|| Map2D::new(0, 0, 0.0))
        .returning_to(pool)
}
