//! The baselines on the GPU: depth maps rendered by `soft_shadow_core`'s rasterizer into one
//! reversed-Z texture array, filters evaluated by `visibility()` in `visibility.wgsl`.

use crate::filters::EvalParams;
use crate::strata::{Stratum, texel_strata};
use glam::Vec3;
use soft_shadow_core::gpu::compute::{bind_group, depth_array_view};
use soft_shadow_core::gpu::shader::{
    DEPTH_ARRAY, Group, Library, ShaderModule, VisibilityShader, storage, uniform,
};
use soft_shadow_core::gpu::{GpuRasterizer, GpuScene};
use soft_shadow_core::{GpuContext, Light, Map2D, MapParams, Result, SampleView, ShadowError};

/// Depth maps kept on the GPU.
pub struct GpuShadowMaps {
    /// `Depth32Float` array, one layer per light sample.
    pub(crate) texture: wgpu::Texture,
    /// The samples' views.
    pub(crate) views: Vec<SampleView>,
    /// Map side.
    pub(crate) resolution: u32,
    /// The light the maps are of (its size and shape set PCSS's kernels).
    pub(crate) light: Light,
    /// Each sample's cell in texels ([`crate::strata::texel_strata`]).
    pub(crate) strata: Vec<Stratum>,
}

impl GpuShadowMaps {
    /// Records one depth layer per view of `light`'s samples as `sample_from` sees them, of
    /// `scene`'s casters, into `enc`.
    pub fn record(
        ctx: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        light: &Light,
        sample_from: Vec3,
        views: &[SampleView],
        scene: &GpuScene,
        resolution: u32,
    ) -> Result<Self> {
        let raster = ctx.cached(GpuRasterizer::new);
        let texture = GpuRasterizer::depth_array(ctx, resolution, views.len() as u32)?;
        for (layer, v) in views.iter().enumerate() {
            raster.encode_depth(ctx, enc, scene.casters(), &v.view, &texture, layer as u32);
        }
        Ok(Self {
            texture,
            views: views.to_vec(),
            resolution,
            light: *light,
            strata: texel_strata(light, sample_from, views, resolution),
        })
    }

    /// Reads layer `layer` back as a linear depth map.
    pub fn read_layer(&self, ctx: &GpuContext, layer: u32) -> Result<Map2D<f32>> {
        let raster = ctx.cached(GpuRasterizer::new);
        let view = self
            .views
            .get(layer as usize)
            .ok_or_else(|| ShadowError::MapsMismatch(format!("no layer {layer}")))?;
        raster.read_depth(ctx, &self.texture, layer, &view.view)
    }
}

/// The crate's WGSL: `shadow_maps::visibility`, the filters' `visibility()`.
pub static SHADERS: Library = Library {
    name: "shadow-maps",
    modules: &[ShaderModule {
        path: "shadow_maps::visibility",
        source: include_str!("visibility.wgsl"),
    }],
    depends: &[&soft_shadow_core::gpu::shader::SHADERS],
    programs: &[],
};

/// The filters' `visibility()` over the parameters, the map views and the depth array.
pub static VISIBILITY: VisibilityShader = VisibilityShader {
    library: &SHADERS,
    module: "shadow_maps::visibility",
    maps: Group::compute(&[
        uniform::<EvalParams>(),
        storage::<MapParams>(true),
        DEPTH_ARRAY,
        storage::<Stratum>(true),
    ]),
};

/// The bind group of `maps` filtered as `prm` says.
pub(crate) fn bind_maps(
    ctx: &GpuContext,
    layout: &wgpu::BindGroupLayout,
    prm: &EvalParams,
    maps: &GpuShadowMaps,
) -> wgpu::BindGroup {
    let params: Vec<MapParams> = maps
        .views
        .iter()
        .map(|v| v.params(maps.resolution))
        .collect();
    let u = ctx.uniform_buffer("eval params", bytemuck::bytes_of(prm));
    let vb = ctx.storage_buffer("map views", bytemuck::cast_slice(&params));
    let sb = ctx.storage_buffer("map strata", bytemuck::cast_slice(&maps.strata));
    let tv = depth_array_view(&maps.texture);
    bind_group(
        ctx,
        "shadow map eval",
        layout,
        &[
            u.as_entire_binding(),
            vb.as_entire_binding(),
            wgpu::BindingResource::TextureView(&tv),
            sb.as_entire_binding(),
        ],
    )
}
