//! Which texel centres a triangle covers, as a GPU decides it: vertices snapped to a
//! 1/[`SUB`]-texel grid, exact integer edge functions, the top-left fill rule. One definition for
//! the depth rasterizer ([`super`]) and every other CPU pass that must fill what the GPU fills
//! (penumbra-limit's ribbons).

/// Sub-texel precision of vertex snapping (8 bits, as GPUs use).
pub const SUBPIXEL_BITS: u32 = 8;
/// Sub-texel units per texel.
pub const SUB: i64 = 1 << SUBPIXEL_BITS;

/// A triangle with vertices in 1/[`SUB`] texel units (y down), ordered so that its edge
/// functions are positive inside, with its top-left edges; only [`SnappedTri::new`] makes one.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SnappedTri {
    /// Vertex x in sub-texel units.
    pub(crate) x: [i64; 3],
    /// Vertex y in sub-texel units (down).
    pub(crate) y: [i64; 3],
    /// Twice the (positive) area in sub-texel units squared.
    pub(crate) area: i64,
    /// Edge `i` (from vertex `i + 1` to `i + 2`) is a top or left edge: texel centres exactly on
    /// it are covered.
    pub(crate) top_left: [bool; 3],
}

impl SnappedTri {
    /// The triangle over snapped vertices, and whether vertices 1 and 2 were swapped to orient
    /// it: true when the signed area `(v1 - v0) x (v2 - v0)` is negative in this y-down space,
    /// which is a counter-clockwise (front) triangle in NDC's y-up. `None` for zero area.
    pub fn new(mut x: [i64; 3], mut y: [i64; 3]) -> Option<(Self, bool)> {
        let area = (x[1] - x[0]) * (y[2] - y[0]) - (y[1] - y[0]) * (x[2] - x[0]);
        if area == 0 {
            return None;
        }
        let swapped = area < 0;
        if swapped {
            x.swap(1, 2);
            y.swap(1, 2);
        }
        let mut top_left = [false; 3];
        for (i, tl) in top_left.iter_mut().enumerate() {
            let (a, b) = ((i + 1) % 3, (i + 2) % 3);
            // Top: horizontal with the interior below, going right; left: going up (y down).
            *tl = (y[a] == y[b] && x[b] > x[a]) || y[b] < y[a];
        }
        let area = area.abs();
        Some((
            Self {
                x,
                y,
                area,
                top_left,
            },
            swapped,
        ))
    }

    /// Edge function `i` at the sub-texel point `(cx, cy)`: positive inside.
    pub fn edge(&self, i: usize, cx: i64, cy: i64) -> i64 {
        let (a, b) = ((i + 1) % 3, (i + 2) % 3);
        (self.x[b] - self.x[a]) * (cy - self.y[a]) - (self.y[b] - self.y[a]) * (cx - self.x[a])
    }

    /// Whether the centre of texel `(px, py)` is covered: every edge function positive, or zero
    /// on a top or left edge. The definition [`SnappedTri::span`] is tested against.
    pub fn covers(&self, px: i64, py: i64) -> bool {
        let (cx, cy) = (px * SUB + SUB / 2, py * SUB + SUB / 2);
        (0..3).all(|i| {
            let e = self.edge(i, cx, cy);
            e > 0 || (e == 0 && self.top_left[i])
        })
    }

    /// The texels of row `py` within `[x0, x1]` whose centres are covered: the same set as
    /// [`SnappedTri::covers`] (each edge's condition is a half-line along the row, solved in
    /// integers), as one inclusive range; `None` when empty.
    pub fn span(&self, py: i64, x0: i64, x1: i64) -> Option<(i64, i64)> {
        let cy = py * SUB + SUB / 2;
        let (mut lo, mut hi) = (x0, x1);
        for i in 0..3 {
            // e(px) = e0 + d px at the centre of texel px; covered where e(px) >= t.
            let e0 = self.edge(i, SUB / 2, cy);
            let (a, b) = ((i + 1) % 3, (i + 2) % 3);
            let d = -(self.y[b] - self.y[a]) * SUB;
            let t = if self.top_left[i] { 0 } else { 1 };
            let k = t - e0;
            match d.cmp(&0) {
                std::cmp::Ordering::Greater => lo = lo.max(-(-k).div_euclid(d)),
                std::cmp::Ordering::Less => hi = hi.min((-k).div_euclid(-d)),
                std::cmp::Ordering::Equal if e0 < t => return None,
                std::cmp::Ordering::Equal => {}
            }
        }
        (lo <= hi).then_some((lo, hi))
    }

    /// A walk down the rows from `py`: [`Rows::span`] gives the same spans as
    /// [`SnappedTri::span`] for `py`, `py + 1`, ... with the divisions done once per walk, not
    /// per row (each edge's bound is a quotient whose numerator grows by a constant per row).
    pub fn rows(&self, py: i64) -> Rows {
        let cy = py * SUB + SUB / 2;
        let bounds = std::array::from_fn(|i| {
            let (a, b) = ((i + 1) % 3, (i + 2) % 3);
            let t = if self.top_left[i] { 0 } else { 1 };
            // Covered where e0 + d px >= t along the row: px >= ceil(k / d) for d > 0, px <=
            // floor(k / d) for d < 0 (k = t - e0), both from q = floor((e0 - t) / |d|).
            let n = self.edge(i, SUB / 2, cy) - t;
            let d = -(self.y[b] - self.y[a]) * SUB;
            let step = (self.x[b] - self.x[a]) * SUB;
            let den = d.abs().max(1);
            EdgeBound {
                rising: d.signum(),
                q: n.div_euclid(den),
                r: n.rem_euclid(den),
                dq: step.div_euclid(den),
                dr: step.rem_euclid(den),
                den,
            }
        });
        Rows { bounds }
    }

    /// The texel rectangle `(x0, x1, y0, y1)`, inclusive, whose centres lie in the bounding box
    /// (empty, `x0 > x1` or `y0 > y1`, when none does).
    pub fn texel_box(&self) -> (i64, i64, i64, i64) {
        let min = |v: &[i64; 3]| v.iter().copied().min().unwrap_or(0);
        let max = |v: &[i64; 3]| v.iter().copied().max().unwrap_or(0);
        // Centre p * SUB + SUB / 2 in [lo, hi]: p from ceil((lo - SUB/2) / SUB) to
        // floor((hi - SUB/2) / SUB).
        let first = |lo: i64| -(-(lo - SUB / 2)).div_euclid(SUB);
        let last = |hi: i64| (hi - SUB / 2).div_euclid(SUB);
        (
            first(min(&self.x)),
            last(max(&self.x)),
            first(min(&self.y)),
            last(max(&self.y)),
        )
    }
}

/// One edge's bound on a row's span, walked down the rows (see [`SnappedTri::rows`]).
#[derive(Clone, Copy, Debug)]
struct EdgeBound {
    /// The sign of the edge function's change along a row: 1 bounds the span below, -1 above,
    /// 0 (a horizontal edge) covers the whole row or none of it.
    rising: i64,
    /// `floor(n / den)` and its remainder.
    q: i64,
    r: i64,
    /// `floor(step / den)` and its remainder: the change of `q` and `r` per row.
    dq: i64,
    dr: i64,
    /// `|d|`, or 1 for a horizontal edge (whose `q` is then the edge function minus its
    /// threshold, the same on the whole row).
    den: i64,
}

/// The spans of consecutive rows of a [`SnappedTri`], from [`SnappedTri::rows`].
#[derive(Clone, Copy, Debug)]
pub struct Rows {
    bounds: [EdgeBound; 3],
}

impl Rows {
    /// The walk `m` rows further down, without visiting the rows between.
    pub fn skipped(&self, m: u32) -> Rows {
        let m = m as i64;
        Rows {
            bounds: self.bounds.map(|e| {
                let r = e.r + m * e.dr;
                // No division for the first band a triangle meets (most of them).
                let (carry, r) = if r < e.den {
                    (0, r)
                } else {
                    (r.div_euclid(e.den), r.rem_euclid(e.den))
                };
                EdgeBound {
                    q: e.q + m * e.dq + carry,
                    r,
                    ..e
                }
            }),
        }
    }

    /// The current row's covered texels within `[x0, x1]` (as [`SnappedTri::span`]); the walk
    /// then moves to the next row.
    #[inline]
    pub fn span(&mut self, x0: i64, x1: i64) -> Option<(i64, i64)> {
        let (mut lo, mut hi, mut any) = (x0, x1, true);
        for e in &mut self.bounds {
            match e.rising {
                1 => lo = lo.max(-e.q),
                -1 => hi = hi.min(e.q),
                _ => any &= e.q >= 0,
            }
            e.q += e.dq;
            e.r += e.dr;
            if e.r >= e.den {
                e.r -= e.den;
                e.q += 1;
            }
        }
        (any && lo <= hi).then_some((lo, hi))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A row's span is exactly the texels `covers` accepts, walking down the rows (row by row,
    /// or skipping to a row) gives the same spans, and the texel box holds every covered texel,
    /// on random snapped triangles (slivers, axis-aligned and shared edges made common by the
    /// small coordinate range).
    #[test]
    fn spans_are_the_covered_texels() {
        let mut rng = crate::rng::SplitMix(1);
        let mut next = |n: i64| rng.below((n * SUB) as u64) as i64 - 2 * SUB;
        let mut checked = 0;
        for case in 0..4000 {
            // Small ranges make ties with texel centres and horizontal edges common.
            let n = if case % 2 == 0 { 12 } else { 40 };
            let mut p = [0; 6].map(|_| next(n));
            if case % 3 == 0 {
                // On the half-texel grid: edges through texel centres.
                p = p.map(|v| v.div_euclid(SUB / 2) * (SUB / 2));
            }
            let Some((t, _)) = SnappedTri::new([p[0], p[1], p[2]], [p[3], p[4], p[5]]) else {
                continue;
            };
            let (bx0, bx1, by0, by1) = t.texel_box();
            let mut rows = t.rows(-3);
            let skipped = t.rows(-3);
            for y in -3..40 {
                let mut at = skipped.skipped((y + 3) as u32);
                assert_eq!(at.span(0, 39), t.span(y, 0, 39), "{p:?} row {y} skipped to");
                let span = t.span(y, 0, 39);
                assert_eq!(rows.span(0, 39), span, "{p:?} row {y} walked");
                for x in -3..40 {
                    let covered = t.covers(x, y);
                    if (0..40).contains(&x) {
                        let inside = span.is_some_and(|(a, b)| (a..=b).contains(&x));
                        assert_eq!(inside, covered, "{p:?} texel ({x}, {y})");
                    }
                    if covered {
                        assert!((bx0..=bx1).contains(&x) && (by0..=by1).contains(&y));
                    }
                    checked += covered as usize;
                }
            }
        }
        assert!(checked > 10_000, "{checked} covered texels checked");
    }
}
