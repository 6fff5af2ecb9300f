//! The CPU path: slicing ([`crate::slicing`]), prefiltering ([`crate::filters`]) and evaluation
//! ([`crate::eval`]) over plain Rust data.

use crate::eval::visibility;
use crate::filters::Filtered;
use crate::frame::Frame;
use crate::params::OcclusionSlices;
use crate::slicing::{MAX_SLICES, Slices, slice};
use rayon::prelude::*;
use soft_shadow_core::{CpuContext, Generation, Map2D, Receivers, Result, ShadowError};

/// The prefiltered occlusion textures of one light.
#[derive(Clone, Debug)]
pub struct CpuSliceMaps {
    /// The slicing frame.
    pub(crate) frame: Frame,
    /// The binary slices packed per texel: bit `k` is slice `k` ([`crate::slicing::slice`]).
    pub(crate) masks: Map2D<u32>,
    /// Per texel and slice, the topmost fragment's [`Frame::top_code`].
    pub(crate) tops: Map2D<[u8; MAX_SLICES]>,
    /// The filtered form the evaluation reads: slice `k` at `k`, and with
    /// [`crate::Combination::Chain`] the union of slices `k - 1` and `k` at `slices + k`.
    pub(crate) filtered: Filtered,
    /// Whether `filtered` holds the unions.
    pub(crate) chained: bool,
}

/// Slices and prefilters (inputs already checked), the storage from `cpu`'s pool.
pub(crate) fn generate(t: &OcclusionSlices, cpu: &CpuContext, input: &Generation) -> CpuSliceMaps {
    let (geometry, resolution) = (input.geometry, input.resolution);
    let frame = Frame::fit(input.light, geometry, t, resolution, input.region);
    let Slices { masks, tops } = slice(cpu.pool(), &frame, geometry);
    let chained = t.combination.chained();
    let filtered = if chained {
        let n = frame.slices;
        let mut unions = cpu.pool().overwrite(masks.data().len(), 0u32);
        unions
            .par_iter_mut()
            .zip(masks.data().par_iter())
            .for_each(|(u, &m)| *u = with_unions(m, n));
        let filtered = Filtered::build(cpu.pool(), t.filter, resolution, &unions, 2 * n);
        cpu.pool().give(unions);
        filtered
    } else {
        Filtered::build(cpu.pool(), t.filter, resolution, masks.data(), frame.slices)
    };
    CpuSliceMaps {
        frame,
        masks,
        tops,
        filtered,
        chained,
    }
}

/// A texel's mask of `n` slices with, at bit `n + k`, the union of slices `k - 1` and `k`
/// (`sat_rows.wgsl`'s union layers).
pub(crate) fn with_unions(m: u32, n: u32) -> u32 {
    let all = (1u32 << n) - 1;
    let m = m & all;
    m | (((m | (m << 1)) & all) << n)
}

impl CpuSliceMaps {
    /// The binary slices, `resolution²` flags each, row-major (tests and images).
    pub fn slices(&self) -> Vec<Vec<bool>> {
        (0..self.frame.slices)
            .map(|k| crate::slicing::unpack(&self.masks, k))
            .collect()
    }
}

/// `V` per receiver (inputs already checked); maps made for another filter, slice count or
/// (without the unions the chain reads) combination are [`ShadowError::MapsMismatch`].
pub(crate) fn evaluate(
    t: &OcclusionSlices,
    maps: &CpuSliceMaps,
    r: &Receivers,
) -> Result<Vec<f32>> {
    check_maps(t, maps.filtered.filter(), maps.frame.slices, maps.chained)?;
    let slices = maps.frame.slices as usize;
    Ok(r.positions
        .par_iter()
        .zip(r.normals.par_iter())
        .map(|(&p, &n)| {
            let top = |k: usize, x: i64, y: i64| {
                let r = maps.frame.resolution as i64;
                let inside = (0..r).contains(&x) && (0..r).contains(&y);
                if inside {
                    maps.tops.get(x as u32, y as u32)[k]
                } else {
                    0
                }
            };
            visibility(
                t,
                &maps.frame,
                p,
                n,
                |k, c, s| maps.filtered.mean(k, c, s),
                |k, c, s| maps.filtered.mean(slices + k, c, s),
                top,
            )
        })
        .collect())
}

/// Whether `t` can read maps of `filter` and `slices` slices, with the unions of neighbouring
/// slices where `chained`: [`ShadowError::MapsMismatch`] where not (both backends).
pub(crate) fn check_maps(
    t: &OcclusionSlices,
    filter: crate::Prefilter,
    slices: u32,
    chained: bool,
) -> Result<()> {
    if filter != t.filter || slices != t.slices {
        return Err(ShadowError::MapsMismatch(format!(
            "maps hold {} {}-slice textures, the technique reads {} with {}",
            filter.name(),
            slices,
            t.filter.name(),
            t.slices
        )));
    }
    if t.combination.chained() && !chained {
        return Err(ShadowError::MapsMismatch(
            "the chain combination reads the unions of neighbouring slices, which these maps \
             (made for another combination) do not hold"
                .into(),
        ));
    }
    Ok(())
}
