//! The CPU path: depth passes through `soft_shadow_core`'s rasterizer, the occlusion mask, the width
//! map, and evaluation with rayon.

use crate::attenuation::{AttenuationTable, FalloffKind};
use crate::eval::{EvalParams, Shader, shade};
use crate::occlusion::occlusion_mask;
use crate::params::{DepthLayer, ShadowWidth};
use crate::width::width_map;
use rayon::prelude::*;
use soft_shadow_core::raster::{DepthPass, depth_map_pass};
use soft_shadow_core::{CpuContext, Generation, Map2D, MapParams, Receivers, SampleView};

/// The maps of one light, built on the CPU.
pub struct CpuWidthMaps {
    /// Its shader-side parameters.
    pub(crate) params: MapParams,
    /// Linear depth of the nearest caster: the shadow test, and `sd` without a back face.
    pub(crate) depth: Map2D<f32>,
    /// With [`DepthLayer::BackFaces`]: linear depth of the nearest back face ([`soft_shadow_core::view::NO_OCCLUDER`]
    /// where none), which `sd` is measured from where it lies in front of the receiver.
    pub(crate) back: Option<Map2D<f32>>,
    /// Shadow width in texels.
    pub(crate) width: Map2D<f32>,
    /// [`crate::params::softness_size`] of the light: its size over the fit factor.
    pub(crate) light_size: f32,
    /// Whether the light is a sphere, whose softness grows off the map's axis
    /// ([`soft_shadow_core::light_space::sphere_spread_at`]).
    pub(crate) sphere: bool,
}

impl CpuWidthMaps {
    /// The shadow-width map in texels (the GPU maps' [`crate::GpuWidthMaps::read_width`]).
    pub fn width(&self) -> &Map2D<f32> {
        &self.width
    }
}

/// Builds the depth, occlusion and width maps of the input's light at its resolution (inputs
/// already checked), their storage from `cpu`'s pool.
pub(crate) fn generate(t: &ShadowWidth, cpu: &CpuContext, input: &Generation) -> CpuWidthMaps {
    let (geometry, light, resolution) = (input.geometry, input.light, input.resolution);
    let view = SampleView::center(light, &input.coverage());
    let params = view.params(resolution);
    let tris = &geometry.casters;
    let pool = cpu.pool();
    let near = depth_map_pass(pool, &view.view, resolution, tris, DepthPass::NEAREST);
    let occlusion = occlusion_mask(&near);
    let width = width_map(pool, &occlusion, t.method);
    let back = (t.depth == DepthLayer::BackFaces)
        .then(|| depth_map_pass(pool, &view.view, resolution, tris, DepthPass::NEAREST_BACK));
    CpuWidthMaps {
        params,
        depth: near,
        back,
        width,
        light_size: crate::params::softness_size(light),
        sphere: matches!(light, soft_shadow_core::Light::Sphere { .. }),
    }
}

/// `V` for every receiver.
pub(crate) fn evaluate(t: &ShadowWidth, maps: &CpuWidthMaps, r: &Receivers) -> Vec<f32> {
    let table = t.table.map(|n| AttenuationTable::new(&t.falloff, n));
    let prm = EvalParams::new(
        t,
        maps.params,
        maps.light_size,
        maps.sphere,
        table.as_ref().map_or(0, |t| t.values.len() as u32),
    );
    let falloff: &FalloffKind = &t.falloff;
    let shader = match &table {
        Some(tab) => Shader::Table(tab),
        None => Shader::Direct(falloff),
    };
    r.positions
        .par_iter()
        .zip(r.normals.par_iter())
        .map(|(p, n)| {
            shade(
                &prm,
                &shader,
                &maps.depth,
                maps.back.as_ref(),
                &maps.width,
                *p,
                *n,
            )
        })
        .collect()
}
