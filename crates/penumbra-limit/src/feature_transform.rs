//! The exact nearest-seed map in linear time (a feature transform: Meijster, Roerdink &
//! Hesselink, *A General Algorithm for Computing Distance Transforms in Linear Time*, 2000): for
//! every texel of a square map, the seed texel nearest to it in Euclidean distance.
//!
//! 1. **Columns.** Per column, two sweeps give every texel the row of the nearest seed of its
//!    column.
//! 2. **Rows.** Per row, the lower envelope of the parabolas `f(x, i) = (x - i)² + g(i)²`, where
//!    `g(i)` is the distance from the row to column `i`'s seed of step 1, over the columns that
//!    have one; every texel takes the seed of the parabola below it. The envelope's breakpoints
//!    are Meijster's `Sep`, a floor division of integers, so there is no rounding: the seed is
//!    the nearest one exactly.
//!
//! **Ties.** Of equally near seeds a texel takes the one of least *key* (a value per seed texel
//! the caller may give, such as its depth), then the leftmost, then the uppermost. With keys,
//! each step compares `(distance, key)` in that order: the envelope of the parabolas lowered by
//! an infinitesimal multiple of their keys, which Meijster's algorithm builds as it builds any
//! envelope; a breakpoint moves one texel left where the two parabolas tie on a texel and the
//! right one has the lesser key.
//!
//! Unlike jump flooding, which takes `log2` of the side passes over every texel and may end a
//! texel one seed off the nearest, this is two sweeps of each column and one pass along each
//! row, whatever the seeds. `feature_transform.wgsl` runs the same two steps in the same integer
//! arithmetic ([`crate::gpu::feature_transform`]), so both backends give the same seeds.

use rayon::prelude::*;
use soft_shadow_core::pool::Pool;
use soft_shadow_core::seeds::{NONE, pack};

/// Columns per strip of step 1: each sweep walks the strip's rows in order, so memory is read in
/// cache lines.
const STRIP: usize = 64;

/// No seed in the column (step 1's output). Step 1's rows are `u16`, half the traffic of
/// `u32`: every row of a map [`pack`] can address is below this.
const NO_ROW: u16 = u16::MAX;

/// The seeds' tie-breaking keys: one per texel of the map, or none (every key equal).
#[derive(Clone, Copy)]
struct Keys<'a> {
    keys: Option<&'a [f32]>,
    resolution: usize,
}

impl Keys<'_> {
    /// Whether the seed at `(x, a)` has a lesser key than the seed at `(y, b)` (rows and
    /// columns of seeds, never [`NO_ROW`]).
    #[inline(always)]
    fn less(self, (x, a): (u32, u32), (y, b): (u32, u32)) -> bool {
        self.keys.is_some_and(|k| {
            k[a as usize * self.resolution + x as usize]
                < k[b as usize * self.resolution + y as usize]
        })
    }
}

/// Step 1 over a `resolution`-wide square map: for every texel the row of the nearest seed of its
/// column ([`NO_ROW`] when the column has none; of two equally near the one of lesser key, else
/// the upper one), as strips of [`STRIP`] columns, strip `s` holding columns `s * STRIP ..` (the
/// last one narrower), row-major.
fn columns(pool: &Pool, seeds: &[u32], keys: Keys) -> Vec<Vec<u16>> {
    let resolution = keys.resolution;
    (0..resolution.div_ceil(STRIP))
        .into_par_iter()
        .map(|s| {
            let x0 = s * STRIP;
            let sw = STRIP.min(resolution - x0);
            // The downward sweep writes every texel: no clearing pass.
            let mut out = pool.overwrite(sw * resolution, NO_ROW);
            // Downwards: the nearest seed at or above.
            let mut above = [NO_ROW; STRIP];
            for (y, o) in out.chunks_exact_mut(sw).enumerate() {
                let cells = &seeds[y * resolution + x0..y * resolution + x0 + sw];
                for ((o, a), &c) in o.iter_mut().zip(&mut above).zip(cells) {
                    if c != NONE {
                        *a = y as u16;
                    }
                    *o = *a;
                }
            }
            // Upwards: the nearest seed below replaces the one above where nearer, or as near
            // with a lesser key.
            let mut below = [NO_ROW; STRIP];
            for (y, o) in out.chunks_exact_mut(sw).enumerate().rev() {
                let cells = &seeds[y * resolution + x0..y * resolution + x0 + sw];
                let y = y as u16;
                // Branch-free, so the sweep vectorizes; equally near seeds above and below
                // (`tied`) are decided by their keys after it.
                let mut tied = false;
                for ((o, b), &c) in o.iter_mut().zip(&mut below).zip(cells) {
                    *b = if c != NONE { y } else { *b };
                    // No seed below or above: `u16::MAX`, beyond every distance in the map.
                    let down = if *b == NO_ROW { u16::MAX } else { *b - y };
                    let up = if *o == NO_ROW { u16::MAX } else { y - *o };
                    tied |= down == up && *b != NO_ROW;
                    *o = if down < up { *b } else { *o };
                }
                if tied && keys.keys.is_some() {
                    for (l, (o, &b)) in o.iter_mut().zip(&below).enumerate() {
                        let x = (x0 + l) as u32;
                        if b != NO_ROW
                            && *o != NO_ROW
                            && b - y == y - *o
                            && keys.less((x, b as u32), (x, *o as u32))
                        {
                            *o = b;
                        }
                    }
                }
            }
            out
        })
        .collect()
}

/// One parabola of a row's envelope (step 2): its column, the texel where it begins to be the
/// lowest, and `h = column² + g²` (the parabola is `f(x) = x² - 2 x column + h`).
#[derive(Clone, Copy)]
struct Parabola {
    column: u32,
    start: u32,
    h: i64,
}

/// Scratch of step 2, one per thread: the row's seed rows per column, and the envelope's
/// parabolas, left to right.
#[derive(Default)]
struct Envelope {
    rows: Vec<u16>,
    stack: Vec<Parabola>,
}

impl Envelope {
    /// Writes into `out` the nearest seed of every texel of row `y`, from `self.rows` (step 1's
    /// row of every column's nearest seed, or [`NO_ROW`]); [`NONE`] everywhere when no column
    /// has a seed.
    fn row(&mut self, y: u32, out: &mut [u32], keys: Keys) {
        let (rows, stack) = (&self.rows, &mut self.stack);
        // Column `i`'s seed row.
        let row = |i: u32| rows[i as usize] as u32;
        // f(x, i) = (x - i)² + g(i)² = x² - 2 x i + h(i), with h(i) = i² + g(i)²: comparing two
        // parabolas at one texel compares `h(i) - 2 x i`.
        let h = |i: u32| {
            let g = row(i).abs_diff(y) as i64;
            (i as i64) * (i as i64) + g * g
        };
        // Whether `u`'s seed has a lesser key than `i`'s.
        let less = |u: u32, i: u32| keys.less((u, row(u)), (i, row(i)));
        let m = out.len() as i64;
        stack.clear();
        for (u, &r) in rows.iter().enumerate() {
            if r == NO_ROW {
                continue;
            }
            let u = u as u32;
            let hu = h(u);
            // Drop the parabolas that `u` lies below where they begin (or on, with a lesser
            // key): they are below it nowhere. So the starts increase strictly, as the GPU's
            // stack, kept in the row's own texels, needs.
            while let Some(top) = stack.last() {
                let t2 = 2 * top.start as i64;
                let (fi, fu) = (top.h - t2 * top.column as i64, hu - t2 * u as i64);
                if fi > fu || (fi == fu && less(u, top.column)) {
                    stack.pop();
                } else {
                    break;
                }
            }
            let Some(top) = stack.last() else {
                stack.push(Parabola {
                    column: u,
                    start: 0,
                    h: hu,
                });
                continue;
            };
            // Meijster's Sep(i, u): the last texel where `i`'s parabola is at most `u`'s (at
            // or after where `i`'s begins, as `i` was kept); `u` takes it too on a tie with
            // the lesser key.
            let i = top.column;
            let (n, d) = (hu - top.h, 2 * (u as i64 - i as i64));
            let sep = n.div_euclid(d);
            // The parabolas meet on texel `sep` exactly when `d` divides `n` (`2 sep (u - i) = n`).
            let tie = sep * d == n && less(u, i);
            let start = sep + 1 - tie as i64;
            if start < m {
                stack.push(Parabola {
                    column: u,
                    start: start as u32,
                    h: hu,
                });
            }
        }
        if stack.is_empty() {
            out.fill(NONE);
            return;
        }
        // Each parabola's texels, filled run by run.
        let ends = stack
            .iter()
            .skip(1)
            .map(|p| p.start as usize)
            .chain([out.len()]);
        for (p, end) in stack.iter().zip(ends) {
            out[p.start as usize..end].fill(pack(p.column, row(p.column)));
        }
    }
}

/// The nearest seed of every texel of a `resolution`-wide square map, exactly: `seeds` holds one value
/// per texel, a seed's own [`pack`]ed coordinates or [`NONE`] (only whether it is [`NONE`] is
/// read); `keys`, where given, one per texel, decides between equally near seeds (the least
/// wins; it is read at seeds only). The result holds the nearest seed's packed coordinates (of
/// equally near ones, the one of least key, then the leftmost, then the uppermost), or [`NONE`]
/// everywhere when there is no seed. Step 1's strips come from `pool` and go back there; so
/// may the result, once read ([`Pool::give`]), which reuses `seeds`' storage.
///
/// # Panics
///
/// If `seeds` (or `keys`, where given) does not hold `resolution²` values, or `resolution` is 65536 or more
/// (beyond what [`pack`] holds).
pub(crate) fn nearest(
    pool: &Pool,
    seeds: Vec<u32>,
    resolution: u32,
    keys: Option<&[f32]>,
) -> Vec<u32> {
    let n = resolution as usize;
    assert!(resolution < 1 << 16 && seeds.len() == n * n && keys.is_none_or(|k| k.len() == n * n));
    let keys = Keys {
        keys,
        resolution: n,
    };
    let strips = columns(pool, &seeds, keys);
    let mut out = seeds;
    out.par_chunks_mut(n.max(1))
        .enumerate()
        .for_each_init(Envelope::default, |e, (y, row)| {
            e.rows.clear();
            for s in &strips {
                let sw = s.len() / n;
                e.rows.extend_from_slice(&s[y * sw..(y + 1) * sw]);
            }
            e.row(y as u32, row, keys);
        });
    strips.into_iter().for_each(|s| pool.give(s));
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use soft_shadow_core::seeds::dist2;

    /// Random seeds at several densities, with a lattice (many texels equidistant from two or
    /// four seeds) and a map without a seed; keys from a handful of values, so that many
    /// equally near seeds have equal keys and many do not.
    fn maps() -> Vec<(u32, Vec<u32>, Vec<f32>)> {
        let mut rng = soft_shadow_core::rng::SplitMix(11);
        let mut out = Vec::new();
        for (n, every) in [
            (1u32, 1u64),
            (2, 2),
            (7, 3),
            (64, 50),
            (129, 400),
            (200, 7),
            (67, 0),
        ] {
            let v = (0..n * n)
                .map(|i| {
                    let (x, y) = (i % n, i / n);
                    let lattice = n == 200 && x % 10 == 3 && y % 6 == 1;
                    let random = every > 0 && rng.next_u64().is_multiple_of(every);
                    if lattice || random { pack(x, y) } else { NONE }
                })
                .collect();
            let keys = (0..n * n).map(|_| (rng.next_u64() % 3) as f32).collect();
            out.push((n, v, keys));
        }
        out
    }

    /// Every texel gets a seed at the least distance to any seed (by brute force); of the
    /// equally near ones the one of least key (with keys), then the leftmost, then the
    /// uppermost; no seed anywhere gives [`NONE`].
    #[test]
    fn nearest_is_the_exact_nearest_seed() {
        for (n, seeds, keys) in maps() {
            let list: Vec<u32> = seeds.iter().copied().filter(|&s| s != NONE).collect();
            for keyed in [false, true] {
                let key = |s: u32| {
                    if keyed {
                        keys[((s >> 16) * n + (s & 0xffff)) as usize]
                    } else {
                        0.0
                    }
                };
                let got = nearest(
                    &soft_shadow_core::pool::Pool::new(1 << 30),
                    seeds.clone(),
                    n,
                    keyed.then_some(&keys[..]),
                );
                for (i, &g) in got.iter().enumerate() {
                    let (x, y) = ((i as u32 % n) as i32, (i as u32 / n) as i32);
                    let want = list.iter().copied().min_by(|&a, &b| {
                        let order = |s: u32| (dist2(x, y, s), s & 0xffff, s >> 16);
                        let (da, db) = (dist2(x, y, a), dist2(x, y, b));
                        da.cmp(&db)
                            .then(key(a).total_cmp(&key(b)))
                            .then(order(a).cmp(&order(b)))
                    });
                    assert_eq!(
                        g,
                        want.unwrap_or(NONE),
                        "side {n} keyed {keyed} texel ({x}, {y})"
                    );
                }
            }
        }
    }
}
