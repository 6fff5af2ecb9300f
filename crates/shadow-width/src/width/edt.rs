//! Exact Euclidean distance transform in linear time (Felzenszwalb & Huttenlocher, *Distance
//! Transforms of Sampled Functions*, 2012): per column the 1D distance to the nearest unblocked
//! texel (two sweeps), then per row the lower envelope of the parabolas `(x - q)² + g(q)²`.
//! `width.wgsl` runs the same two passes with one invocation per column, then per row.

use rayon::prelude::*;
use shadow_core::Map2D;

/// Column pass: for every texel, the vertical distance to the nearest unblocked texel of its
/// column, or `None` when the column has none. Both sweeps walk whole rows (every column at once),
/// so memory is read in order.
pub fn columns(mask: &Map2D<bool>) -> Vec<Option<u32>> {
    let (w, h) = (mask.width() as usize, mask.height() as usize);
    let m = mask.data();
    let mut out: Vec<Option<u32>> = vec![None; w * h];
    let mut run: Vec<Option<u32>> = vec![None; w];
    for y in 0..h {
        for (r, &blocked) in run.iter_mut().zip(&m[y * w..(y + 1) * w]) {
            *r = if !blocked { Some(0) } else { r.map(|d| d + 1) };
        }
        out[y * w..(y + 1) * w].copy_from_slice(&run);
    }
    run.iter_mut().for_each(|r| *r = None);
    for y in (0..h).rev() {
        for (x, r) in run.iter_mut().enumerate() {
            let i = y * w + x;
            *r = if !m[i] { Some(0) } else { r.map(|d| d + 1) };
            out[i] = match (out[i], *r) {
                (Some(a), Some(b)) => Some(a.min(b)),
                (a, b) => a.or(b),
            };
        }
    }
    out
}

/// Squared distance to the nearest finite parabola of one row (`f[q]` = squared column distance
/// or `None`), for every `x` of the row; `None` when the row has no finite parabola.
pub fn row_envelope(f: &[Option<u32>]) -> Vec<Option<u64>> {
    let n = f.len();
    let mut v: Vec<usize> = Vec::with_capacity(n);
    let mut z: Vec<f64> = Vec::with_capacity(n + 1);
    let fv = |q: usize| {
        let g = f[q].unwrap_or(0) as f64;
        g * g + (q * q) as f64
    };
    for (q, fq) in f.iter().enumerate() {
        if fq.is_none() {
            continue;
        }
        loop {
            let Some(&p) = v.last() else {
                v.push(q);
                z.clear();
                z.push(f64::NEG_INFINITY);
                break;
            };
            let s = (fv(q) - fv(p)) / (2.0 * (q as f64 - p as f64));
            if s <= *z.last().unwrap_or(&f64::NEG_INFINITY) && v.len() > 1 {
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
        return vec![None; n];
    }
    let mut k = 0;
    (0..n)
        .map(|x| {
            while k + 1 < v.len() && z[k + 1] < x as f64 {
                k += 1;
            }
            let q = v[k];
            let g = f[q].unwrap_or(0) as u64;
            let d = x.abs_diff(q) as u64;
            Some(d * d + g * g)
        })
        .collect()
}

/// The exact width map of `mask`, capped at [`super::cap`].
pub fn width(mask: &Map2D<bool>) -> Map2D<f32> {
    let (w, h) = (mask.width() as usize, mask.height() as usize);
    let g = columns(mask);
    let cap = super::cap(mask.width());
    let mut out = shadow_core::pool::filled(w * h, 0.0f32);
    out.par_chunks_mut(w.max(1))
        .zip(g.par_chunks(w.max(1)))
        .for_each(|(row, f)| {
            for (o, d2) in row.iter_mut().zip(row_envelope(f)) {
                *o = d2.map_or(cap, |d2| (d2 as f64).sqrt() as f32).min(cap);
            }
        });
    Map2D::from_vec(mask.width(), mask.height(), out).unwrap_or_else(|| Map2D::new(0, 0, 0.0))
}
