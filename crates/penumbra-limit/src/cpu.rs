//! The CPU path: the generators of [`crate::silhouette`] and [`crate::depth_image`] through
//! `soft_shadow_core`'s rasterizer, [`crate::combine`], and evaluation with rayon.

use crate::combine::{Layers, combine};
use crate::eval::{EvalParams, shade};
use crate::params::{Generator, PenumbraLimit};
use crate::storage::Texel;
use crate::table::IlluminationTable;
use crate::warp::Warp;
use crate::{depth_image, silhouette};
use rayon::prelude::*;
use soft_shadow_core::raster::{DepthPass, depth_map_pass_then};
use soft_shadow_core::{CpuContext, Generation, Map2D, MapParams, Receivers, SampleView};

/// The penumbra limit map of one light, built on the CPU.
pub struct CpuPenumbraMaps {
    /// Its shader-side parameters.
    pub(crate) params: MapParams,
    /// Depth warp and normalisation of the map.
    pub(crate) warp: Warp,
    /// The four channels, quantised as the storage format keeps them.
    pub(crate) map: Map2D<Texel>,
    /// The visibility-to-illumination table for the light.
    pub(crate) table: IlluminationTable,
}

impl CpuPenumbraMaps {
    /// The four channels as the storage format keeps them (the GPU maps'
    /// [`crate::GpuPenumbraMaps::read_map`]).
    pub fn map(&self) -> &Map2D<Texel> {
        &self.map
    }
}

/// The generators' layers before combination (inputs already checked), their storage from
/// `cpu`'s pool.
pub(crate) fn layers(
    t: &PenumbraLimit,
    cpu: &CpuContext,
    view: &SampleView,
    warp: &Warp,
    tris: &[[glam::Vec3; 3]],
    resolution: u32,
) -> Layers {
    let params = view.params(resolution);
    let pool = cpu.pool();
    let geom = depth_map_pass_then(
        pool,
        &view.view,
        resolution,
        tris,
        DepthPass::NEAREST,
        |z| warp.normalized(z),
    );
    let (edge, lower) = match t.generator {
        Generator::Silhouette => {
            let ribbons: Vec<_> = cpu
                .cached(silhouette::EdgeCache::default)
                .edges(tris)
                .iter()
                .filter_map(|e| silhouette::ribbon(&params, warp, e))
                .filter(|r| {
                    r.is_outline(&geom, |c| warp.depth_gap(warp.linear(c), t.transition_gap))
                })
                .collect();
            let edge = silhouette::rasterize_ribbons(pool, &ribbons, &geom, warp.p_per_texel);
            let lower = silhouette::lower_limit(pool, &view.view, warp, tris, &edge, t.layer_gap);
            (edge, lower)
        }
        Generator::DepthImage => depth_image::limits(pool, &geom, warp, t.layer_gap),
    };
    Layers { geom, edge, lower }
}

/// Builds the map of the input's light at its resolution (inputs already checked).
pub(crate) fn generate(t: &PenumbraLimit, cpu: &CpuContext, input: &Generation) -> CpuPenumbraMaps {
    let (geometry, light, resolution) = (input.geometry, input.light, input.resolution);
    let view = SampleView::center(light, &input.coverage());
    let params = view.params(resolution);
    let warp = Warp::new(&params, light);
    let l = layers(t, cpu, &view, &warp, &geometry.casters, resolution);
    CpuPenumbraMaps {
        params,
        warp,
        map: combine(cpu.pool(), &l, &warp, t.transition_gap, t.storage),
        table: IlluminationTable::new(t.profile.for_light(light), t.table_size),
    }
}

/// `V` for every receiver.
pub(crate) fn evaluate(t: &PenumbraLimit, maps: &CpuPenumbraMaps, r: &Receivers) -> Vec<f32> {
    let prm = EvalParams::new(
        maps.params,
        t.bias,
        maps.warp,
        t.storage,
        maps.table.values.len() as u32,
    );
    r.positions
        .par_iter()
        .zip(r.normals.par_iter())
        .map(|(p, n)| shade(&prm, &maps.map, &maps.table, *p, *n))
        .collect()
}
