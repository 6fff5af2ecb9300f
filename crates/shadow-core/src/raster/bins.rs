//! Binning of a pass's screen triangles into bands of [`BAND_ROWS`] rows: per band, the
//! triangles whose box reaches it and a mask of the 16-column blocks those boxes reach, so a band
//! visits only its own triangles and clears and finishes only its reached columns.

use super::BAND_ROWS;
use super::setup::Screen;

/// Columns per bit of a [`Bin`]'s column mask: 16 texels, a cache line of `f32`.
const COLUMN_BLOCK: usize = 16;

/// One band of [`BAND_ROWS`] rows: the triangles whose box reaches it and the columns those
/// boxes span.
pub(super) struct Bin {
    /// The band's triangles (addresses in the [`Screen`]), in submission order.
    pub(super) order: Vec<u32>,
    /// Bit `b` (of word `b / 64`) is set when some triangle's box in the band reaches a column of
    /// block `b` (columns `b * COLUMN_BLOCK..`); no fragment of the band lies in the others.
    columns: Vec<u64>,
}

impl Bin {
    /// Sets the bits of blocks `first..=last`.
    fn reach(&mut self, first: usize, last: usize) {
        for word in first / 64..=last / 64 {
            let lo = if word == first / 64 { first % 64 } else { 0 };
            let hi = if word == last / 64 { last % 64 } else { 63 };
            self.columns[word] |= (u64::MAX >> (63 - hi)) & (u64::MAX << lo);
        }
    }

    /// The row's columns (of `width`) in maximal runs: each run and whether a triangle's box
    /// reaches it, left to right.
    pub(super) fn runs(
        &self,
        width: usize,
    ) -> impl Iterator<Item = (std::ops::Range<usize>, bool)> + '_ {
        let blocks = width.div_ceil(COLUMN_BLOCK);
        // The first block at or after `b` whose bit differs from `set` (or `blocks`).
        let next_change = move |b: usize, set: bool| {
            let flip = if set { u64::MAX } else { 0 };
            let mut word = b / 64;
            let mut bits = (self.columns[word] ^ flip) & (u64::MAX << (b % 64));
            while bits == 0 {
                word += 1;
                if word * 64 >= blocks {
                    return blocks;
                }
                bits = self.columns[word] ^ flip;
            }
            (word * 64 + bits.trailing_zeros() as usize).min(blocks)
        };
        let mut b = 0;
        std::iter::from_fn(move || {
            if b >= blocks {
                return None;
            }
            let set = self.columns[b / 64] >> (b % 64) & 1 == 1;
            let start = b;
            b = next_change(b, set);
            Some((start * COLUMN_BLOCK..(b * COLUMN_BLOCK).min(width), set))
        })
    }
}

/// Per band of [`BAND_ROWS`] rows of a `width x height` target, its [`Bin`]: each band then
/// visits only its own triangles instead of all of them (a 2048² map of the 69,451-triangle bunny
/// has 128 bands), and only the columns they reach.
pub(super) fn bins(tris: &Screen, width: u32, height: u32) -> Vec<Bin> {
    let bands = (height as usize).div_ceil(BAND_ROWS);
    let words = (width as usize).div_ceil(COLUMN_BLOCK).div_ceil(64);
    let mut bins: Vec<Bin> = (0..bands)
        .map(|_| Bin {
            order: Vec::new(),
            columns: vec![0; words],
        })
        .collect();
    for (i, t) in tris.iter() {
        let (x0, x1, y0, y1) = t.texels;
        let (first, last) = (y0.max(0), y1.min(height as i64 - 1));
        if first > last || x1 < 0 || x0 >= width as i64 {
            continue;
        }
        let (c0, c1) = (x0.max(0) as usize, x1.min(width as i64 - 1) as usize);
        for bin in &mut bins[first as usize / BAND_ROWS..=last as usize / BAND_ROWS] {
            bin.order.push(i);
            bin.reach(c0 / COLUMN_BLOCK, c1 / COLUMN_BLOCK);
        }
    }
    bins
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A band's runs split its row into maximal runs, left to right, each reached exactly where
    /// some range given to [`Bin::reach`] holds one of its blocks: random ranges over rows of
    /// one to three mask words, with widths that end inside a block.
    #[test]
    fn column_runs_are_the_reached_blocks() {
        let mut rng = crate::rng::SplitMix(2);
        let mut next = |n: usize| rng.below(n as u64) as usize;
        for case in 0..2000 {
            let width = 1 + next(3 * 64 * COLUMN_BLOCK);
            let blocks = width.div_ceil(COLUMN_BLOCK);
            let mut bin = Bin {
                order: Vec::new(),
                columns: vec![0; blocks.div_ceil(64)],
            };
            let mut reached = vec![false; blocks];
            for _ in 0..case % 5 {
                let (a, b) = (next(blocks), next(blocks));
                let (first, last) = (a.min(b), a.max(b));
                bin.reach(first, last);
                reached[first..=last].iter_mut().for_each(|r| *r = true);
            }
            let runs: Vec<_> = bin.runs(width).collect();
            let mut end = 0;
            for (k, (columns, set)) in runs.iter().enumerate() {
                assert_eq!(columns.start, end, "case {case}: runs {runs:?}");
                assert!(!columns.is_empty(), "case {case}: runs {runs:?}");
                assert!(
                    k == 0 || runs[k - 1].1 != *set,
                    "case {case}: runs {runs:?}"
                );
                for x in columns.clone() {
                    assert_eq!(reached[x / COLUMN_BLOCK], *set, "case {case}: column {x}");
                }
                end = columns.end;
            }
            assert_eq!(end, width, "case {case}: runs {runs:?}");
        }
    }
}
