//! Row-major 2D maps with clamp-to-edge sampling and texel centres at +0.5.

use crate::pool::Pool;
use glam::Vec2;
use std::sync::Arc;

/// A row-major `width x height` grid of `T`; row 0 is the top row (v = 0).
///
/// A map made in a context ([`Map2D::pooled`], [`Map2D::returning_to`]) takes its texels from
/// the context's [`Pool`] and gives them back when it is dropped, so the next map of the same
/// size and texel type reuses pages already faulted in.
#[derive(Clone, Debug)]
pub struct Map2D<T: Send + 'static> {
    width: u32,
    height: u32,
    data: Vec<T>,
    pool: Option<Arc<Pool>>,
}

impl<T: Send + PartialEq + 'static> PartialEq for Map2D<T> {
    fn eq(&self, other: &Self) -> bool {
        (self.width, self.height) == (other.width, other.height) && self.data == other.data
    }
}

impl<T: Send + 'static> Drop for Map2D<T> {
    fn drop(&mut self) {
        if let Some(pool) = &self.pool {
            pool.give(std::mem::take(&mut self.data));
        }
    }
}

impl<T: Clone + Send + 'static> Map2D<T> {
    /// A map filled with `value`.
    pub fn new(width: u32, height: u32, value: T) -> Self {
        Self {
            width,
            height,
            data: vec![value; width as usize * height as usize],
            pool: None,
        }
    }

    /// A map filled with `value`, its texels from `pool` and given back there when dropped.
    pub fn pooled(pool: &Arc<Pool>, width: u32, height: u32, value: T) -> Self {
        Self {
            width,
            height,
            data: pool.filled(width as usize * height as usize, value),
            pool: Some(pool.clone()),
        }
    }

    /// A map of unspecified texels from `pool` ([`Pool::overwrite`]; `fill` where fresh), for a
    /// caller that writes every texel before anything reads it.
    pub(crate) fn for_overwrite(pool: &Arc<Pool>, width: u32, height: u32, fill: T) -> Self {
        Self {
            width,
            height,
            data: pool.overwrite(width as usize * height as usize, fill),
            pool: Some(pool.clone()),
        }
    }
}

impl<T: Clone + Send + Sync + 'static> Map2D<T> {
    /// A map whose texel `i` (row-major) is `f(i)`, computed in parallel, rows at a time (the
    /// loop over a row's texels vectorizes where `f` does), into storage from `pool` where one
    /// is given ([`Pool::overwrite`]: no clearing pass).
    pub fn from_par_fn(
        pool: Option<&Arc<Pool>>,
        width: u32,
        height: u32,
        f: impl Fn(usize) -> T + Sync + Send,
    ) -> Self {
        use rayon::prelude::*;
        let n = width as usize * height as usize;
        if n == 0 {
            return Self {
                width,
                height,
                data: Vec::new(),
                pool: None,
            };
        }
        let mut data = match pool {
            Some(p) => p.overwrite(n, f(0)),
            None => vec![f(0); n],
        };
        let rows = (width as usize).max(1) * 16;
        data.par_chunks_mut(rows)
            .enumerate()
            .for_each(|(c, chunk)| {
                for (j, o) in chunk.iter_mut().enumerate() {
                    *o = f(c * rows + j);
                }
            });
        Self {
            width,
            height,
            data,
            pool: pool.cloned(),
        }
    }
}

impl<T: Send + 'static> Map2D<T> {
    /// A map over existing row-major data; `None` when the length is not `width * height`.
    pub fn from_vec(width: u32, height: u32, data: Vec<T>) -> Option<Self> {
        (data.len() == width as usize * height as usize).then_some(Self {
            width,
            height,
            data,
            pool: None,
        })
    }

    /// The same map, giving its texels to `pool` when dropped (for storage that came from it).
    pub fn returning_to(mut self, pool: &Arc<Pool>) -> Self {
        self.pool = Some(pool.clone());
        self
    }

    /// The pool this map gives its texels back to, if any.
    pub fn pool(&self) -> Option<&Arc<Pool>> {
        self.pool.as_ref()
    }

    /// Width in texels.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height in texels.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// The texels, row-major.
    pub fn data(&self) -> &[T] {
        &self.data
    }

    /// The texels, row-major, mutable.
    pub fn data_mut(&mut self) -> &mut [T] {
        &mut self.data
    }

    /// Consumes the map, returning its texels.
    pub fn into_vec(mut self) -> Vec<T> {
        std::mem::take(&mut self.data)
    }

    /// The texel at `(x, y)`, clamped to the edge.
    pub fn get_clamped(&self, x: i64, y: i64) -> &T {
        let x = x.clamp(0, self.width as i64 - 1) as usize;
        let y = y.clamp(0, self.height as i64 - 1) as usize;
        &self.data[y * self.width as usize + x]
    }

    /// The texel at `(x, y)`; panics when out of range (internal indexing).
    pub fn get(&self, x: u32, y: u32) -> &T {
        &self.data[y as usize * self.width as usize + x as usize]
    }

    /// Sets the texel at `(x, y)`.
    pub fn set(&mut self, x: u32, y: u32, value: T) {
        let w = self.width as usize;
        self.data[y as usize * w + x as usize] = value;
    }

    /// The texel containing map coordinate `uv` (in `[0, 1]²`, clamp-to-edge).
    pub fn sample_nearest(&self, uv: Vec2) -> &T {
        let x = (uv.x * self.width as f32).floor() as i64;
        let y = (uv.y * self.height as f32).floor() as i64;
        self.get_clamped(x, y)
    }

    /// The four texels around texel coordinate `st` (texel centres at +0.5, clamp-to-edge) with
    /// their bilinear weights, top-left first.
    pub fn bilinear_taps(&self, st: Vec2) -> [(&T, f32); 4] {
        bilinear_texels(st, self.width, self.height).map(|(x, y, w)| (self.get(x, y), w))
    }

    /// Maps every texel, in parallel (into storage from this map's pool, if it has one).
    pub fn map<U: Clone + Send + Sync + 'static>(
        &self,
        f: impl Fn(&T) -> U + Sync + Send,
    ) -> Map2D<U>
    where
        T: Sync,
    {
        let d = &self.data;
        Map2D::from_par_fn(self.pool.as_ref(), self.width, self.height, |i| f(&d[i]))
    }
}

impl Map2D<f32> {
    /// Bilinear sample at `uv` with texel centres at +0.5 and clamp-to-edge.
    pub fn sample_bilinear(&self, uv: Vec2) -> f32 {
        let x = uv.x * self.width as f32 - 0.5;
        let y = uv.y * self.height as f32 - 0.5;
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let (x0, y0) = (x0 as i64, y0 as i64);
        let t = |dx, dy| *self.get_clamped(x0 + dx, y0 + dy);
        let top = t(0, 0) * (1.0 - fx) + t(1, 0) * fx;
        let bottom = t(0, 1) * (1.0 - fx) + t(1, 1) * fx;
        top * (1.0 - fy) + bottom * fy
    }
}

/// The four texels around texel coordinate `st` of a `width x height` map (texel centres at
/// +0.5, clamped to the edge) with their bilinear weights, top-left first.
pub fn bilinear_texels(st: Vec2, width: u32, height: u32) -> [(u32, u32, f32); 4] {
    let u = st - Vec2::splat(0.5);
    let i = u.floor();
    let (fx, fy) = (u.x - i.x, u.y - i.y);
    let (x0, y0) = (i.x as i64, i.y as i64);
    let cx = |x: i64| x.clamp(0, width as i64 - 1) as u32;
    let cy = |y: i64| y.clamp(0, height as i64 - 1) as u32;
    [
        (cx(x0), cy(y0), (1.0 - fx) * (1.0 - fy)),
        (cx(x0 + 1), cy(y0), fx * (1.0 - fy)),
        (cx(x0), cy(y0 + 1), (1.0 - fx) * fy),
        (cx(x0 + 1), cy(y0 + 1), fx * fy),
    ]
}
