//! The CPU path: one depth map per sample ([`soft_shadow_core::raster`]), skins from each map
//! ([`crate::skins`]), warped into the neighbours' views ([`crate::warp`]) to build their
//! visibility channels, and the `shade()` loop ([`crate::eval`]).

use crate::eval::visibility;
use crate::params::LinearLight;
use crate::samples::{lit_share, neighbours, piece_share, sample_views};
use crate::segments::Segment;
use crate::skins::skins;
use crate::warp::{Source, warp};
use rayon::prelude::*;
use soft_shadow_core::raster::depth_map;
use soft_shadow_core::{CpuContext, Generation, Map2D, MapParams, Receivers, SampleView};

/// The maps of one light: `N` samples per segment, segment after segment.
#[derive(Clone, Debug)]
pub struct CpuLinearMaps {
    /// One view per sample (`weight` is the lit share times the segment's weight).
    pub(crate) views: Vec<SampleView>,
    /// Their shader-side parameters.
    pub(crate) params: Vec<MapParams>,
    /// Linear depth per sample.
    pub(crate) depth: Vec<Map2D<f32>>,
    /// Visibility channel per sample, scaled by its segment's weight.
    pub(crate) channel: Vec<Map2D<f32>>,
}

impl CpuLinearMaps {
    /// The visibility channel of every sample, scaled by its segment's weight (the GPU maps'
    /// [`crate::GpuLinearMaps::read_channels`]).
    pub fn channels(&self) -> &[Map2D<f32>] {
        &self.channel
    }
}

/// Builds the maps for `segments` (inputs already checked), their storage from `cpu`'s pool.
pub(crate) fn generate(
    t: &LinearLight,
    cpu: &CpuContext,
    input: &Generation,
    segments: &[Segment],
) -> CpuLinearMaps {
    let mut all = CpuLinearMaps {
        views: Vec::new(),
        params: Vec::new(),
        depth: Vec::new(),
        channel: Vec::new(),
    };
    for s in segments {
        let m = generate_segment(t, cpu, input, s);
        all.views.extend(m.views);
        all.params.extend(m.params);
        all.depth.extend(m.depth);
        all.channel.extend(m.channel);
    }
    all
}

/// The maps of one segment, its shares scaled by its weight.
fn generate_segment(
    t: &LinearLight,
    cpu: &CpuContext,
    input: &Generation,
    seg: &Segment,
) -> CpuLinearMaps {
    let (geometry, resolution) = (input.geometry, input.resolution);
    let n = t.samples;
    let (a, b, w) = (seg.a, seg.b, seg.weight);
    // The grid maps hold the receivers too: a cube face starts before the nearest of either.
    let coverage = input.coverage_with_receivers_of(&soft_shadow_core::Light::Linear { a, b });
    let views = sample_views(a, b, n, seg.axis, &coverage, w);
    let params: Vec<MapParams> = views.iter().map(|v| v.params(resolution)).collect();
    let pool = cpu.pool();
    let depth: Vec<Map2D<f32>> = views
        .iter()
        .map(|v| depth_map(pool, &v.view, resolution, &geometry.casters))
        .collect();
    // Skins and their warps read the grid maps (casters and receivers, see `grid_geometry`).
    let all = crate::skins::grid_geometry(geometry);
    let grid: Vec<Map2D<f32>> = views
        .iter()
        .map(|v| depth_map(pool, &v.view, resolution, &all))
        .collect();
    let skin_sets: Vec<_> = views
        .iter()
        .zip(&grid)
        .map(|(v, d)| skins(pool, &v.view, d, t.edge_threshold_at(resolution)))
        .collect();
    let s = w * piece_share(n);
    let channel = (0..n)
        .map(|i| {
            let mut c = Map2D::pooled(pool, resolution, resolution, w * lit_share(i, n));
            for j in neighbours(i, n) {
                let (i, j) = (i as usize, j as usize);
                let src = Source {
                    params: &params[j],
                    depth: &grid[j],
                    threshold: t.edge_threshold_at(resolution),
                    piece: s,
                };
                warp(pool, &skin_sets[j], &views[i].view, &grid[i], &src, &mut c);
            }
            c
        })
        .collect();
    CpuLinearMaps {
        views,
        params,
        depth,
        channel,
    }
}

/// `V` per receiver (inputs already checked).
pub(crate) fn evaluate(t: &LinearLight, maps: &CpuLinearMaps, r: &Receivers) -> Vec<f32> {
    r.positions
        .par_iter()
        .zip(r.normals.par_iter())
        .map(|(&p, &n)| {
            visibility(
                &maps.params,
                &t.bias,
                p,
                n,
                |k, x, y| *maps.depth[k].get(x, y),
                |k, x, y| *maps.channel[k].get(x, y),
            )
        })
        .collect()
}
