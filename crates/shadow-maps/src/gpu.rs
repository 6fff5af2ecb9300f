//! The baselines on the GPU: depth maps rendered by `soft_shadow_core`'s rasterizer into one
//! reversed-Z texture array, filters evaluated by `visibility()` in `shadow_map_eval.wgsl`.

use crate::filters::EvalParams;
use soft_shadow_core::gpu::compute::{
    bind_group, depth_array_entry, depth_array_view, storage_entry, uniform_entry,
};
use soft_shadow_core::gpu::{GpuRasterizer, GpuScene};
use soft_shadow_core::{GpuContext, Map2D, MapParams, Result, SampleView, ShadowError};

/// Depth maps kept on the GPU.
pub struct GpuShadowMaps {
    /// `Depth32Float` array, one layer per light sample.
    pub texture: wgpu::Texture,
    /// The samples' views.
    pub views: Vec<SampleView>,
    /// Map side.
    pub resolution: u32,
    /// [`soft_shadow_core::Light::size`] of the light.
    pub light_size: f32,
}

impl GpuShadowMaps {
    /// Records one depth layer per view of `scene`'s casters into `enc`.
    pub fn record(
        ctx: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        views: &[SampleView],
        scene: &GpuScene,
        resolution: u32,
        light_size: f32,
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
            light_size,
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

/// The crate's WGSL files, for [`soft_shadow_core::gpu::wgsl::resolve`].
pub const WGSL: &[(&str, &str)] = &[("shadow_map_eval.wgsl", include_str!("shadow_map_eval.wgsl"))];

/// The filters' `visibility()` (`shadow_map_eval.wgsl` after the light-space helpers).
pub fn visibility_wgsl() -> String {
    soft_shadow_core::gpu::wgsl::source("shadow_map_eval.wgsl", WGSL)
}

/// Parameters, map views, the depth array.
pub fn maps_layout_entries() -> Vec<wgpu::BindGroupLayoutEntry> {
    vec![
        uniform_entry(0),
        storage_entry(1, true),
        depth_array_entry(2),
    ]
}

/// The bind group of `maps` filtered as `prm` says.
pub fn bind_maps(
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
    let tv = depth_array_view(&maps.texture);
    bind_group(
        ctx,
        "shadow map eval",
        layout,
        &[
            u.as_entire_binding(),
            vb.as_entire_binding(),
            wgpu::BindingResource::TextureView(&tv),
        ],
    )
}
