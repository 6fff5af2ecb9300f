//! The CPU path: slicing ([`crate::slicing`]), prefiltering ([`crate::filters`]) and evaluation
//! ([`crate::eval`]) over plain Rust data.

use crate::eval::visibility;
use crate::filters::Filtered;
use crate::frame::Frame;
use crate::params::OcclusionSlices;
use crate::slicing::{MAX_SLICES, Slices, slice};
use rayon::prelude::*;
use soft_shadow_core::{CpuContext, Generation, Map2D, Receivers};

/// The prefiltered occlusion textures of one light.
#[derive(Clone, Debug)]
pub struct CpuSliceMaps {
    /// The slicing frame.
    pub(crate) frame: Frame,
    /// The binary slices packed per texel: bit `k` is slice `k` ([`crate::slicing::slice`]).
    pub(crate) masks: Map2D<u32>,
    /// Per texel and slice, the topmost fragment's [`Frame::top_code`].
    pub(crate) tops: Map2D<[u8; MAX_SLICES]>,
    /// The filtered form the evaluation reads.
    pub(crate) filtered: Filtered,
}

/// Slices and prefilters (inputs already checked), the storage from `cpu`'s pool.
pub(crate) fn generate(t: &OcclusionSlices, cpu: &CpuContext, input: &Generation) -> CpuSliceMaps {
    let (geometry, resolution) = (input.geometry, input.resolution);
    let frame = Frame::fit(input.light, geometry, t, resolution, input.region);
    let Slices { masks, tops } = slice(cpu.pool(), &frame, geometry);
    let filtered = Filtered::build(cpu.pool(), t.filter, resolution, masks.data(), frame.slices);
    CpuSliceMaps {
        frame,
        masks,
        tops,
        filtered,
    }
}

impl CpuSliceMaps {
    /// The binary slices, `resolution²` flags each, row-major (tests and images).
    pub fn slices(&self) -> Vec<Vec<bool>> {
        (0..self.frame.slices)
            .map(|k| crate::slicing::unpack(&self.masks, k))
            .collect()
    }
}

/// `V` per receiver (inputs already checked).
pub(crate) fn evaluate(t: &OcclusionSlices, maps: &CpuSliceMaps, r: &Receivers) -> Vec<f32> {
    r.positions
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
                top,
            )
        })
        .collect()
}
