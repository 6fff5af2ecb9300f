//! Exact Euclidean distance transform in linear time (Felzenszwalb & Huttenlocher, *Distance
//! Transforms of Sampled Functions*, 2012): per column the 1D distance to the nearest unblocked
//! texel (two sweeps), then per row the lower envelope of the parabolas `(x - q)² + g(q)²`.
//! `width.wgsl` runs the same two passes with one invocation per column, then per row.

use rayon::prelude::*;
use shadow_core::Map2D;

/// Column pass: for every texel, the vertical distance to the nearest unblocked texel of its
/// column, or `None` when the column has none.
pub fn columns(mask: &Map2D<bool>) -> Vec<Option<u32>> {
    let (w, h) = (mask.width() as usize, mask.height() as usize);
    let cols: Vec<Vec<Option<u32>>> = (0..w)
        .into_par_iter()
        .map(|x| {
            let mut g = vec![None; h];
            let mut last: Option<u32> = None;
            for (y, gy) in g.iter_mut().enumerate() {
                last = if !mask.data()[y * w + x] {
                    Some(0)
                } else {
                    last.map(|d| d + 1)
                };
                *gy = last;
            }
            let mut next: Option<u32> = None;
            for y in (0..h).rev() {
                next = if !mask.data()[y * w + x] {
                    Some(0)
                } else {
                    next.map(|d| d + 1)
                };
                g[y] = match (g[y], next) {
                    (Some(a), Some(b)) => Some(a.min(b)),
                    (a, b) => a.or(b),
                };
            }
            g
        })
        .collect();
    let mut out = vec![None; w * h];
    for (x, c) in cols.iter().enumerate() {
        for (y, g) in c.iter().enumerate() {
            out[y * w + x] = *g;
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
    let mut out = vec![0.0f32; w * h];
    out.par_chunks_mut(w.max(1))
        .zip(g.par_chunks(w.max(1)))
        .for_each(|(row, f)| {
            for (o, d2) in row.iter_mut().zip(row_envelope(f)) {
                *o = d2.map_or(cap, |d2| (d2 as f64).sqrt() as f32).min(cap);
            }
        });
    Map2D::from_vec(mask.width(), mask.height(), out).unwrap_or_else(|| Map2D::new(0, 0, 0.0))
}
