//! The baselines on the GPU: depth maps rendered by `shadow_core`'s rasterizer into one
//! reversed-Z texture array, filters evaluated by the compute shader `shadow_map_eval.wgsl`.

use crate::filters::EvalParams;
use glam::Vec3;
use shadow_core::gpu::compute::{
    ReceiverBuffers, bind_group, compute_pipelines, depth_array_entry, depth_array_view,
    storage_entry, uniform_entry,
};
use shadow_core::gpu::light_space_shader;
use shadow_core::gpu::{GpuRasterizer, GpuTriangles};
use shadow_core::{GpuContext, Map2D, MapParams, Receivers, Result, SampleView, ShadowError};

/// Depth maps kept on the GPU.
pub struct GpuShadowMaps {
    /// `Depth32Float` array, one layer per light sample.
    pub texture: wgpu::Texture,
    /// The samples' views.
    pub views: Vec<SampleView>,
    /// Map side.
    pub resolution: u32,
    /// [`shadow_core::Light::size`] of the light.
    pub light_size: f32,
}

struct Rasterizer(GpuRasterizer);

struct EvalPipeline {
    pipeline: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
}

impl EvalPipeline {
    fn new(ctx: &GpuContext) -> Self {
        let d = &ctx.device;
        let module = d.create_shader_module(light_space_shader(
            "shadow map eval",
            include_str!("shadow_map_eval.wgsl"),
        ));
        let layout = d.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("shadow map eval"),
            entries: &[
                uniform_entry(0),
                storage_entry(1, true),
                depth_array_entry(2),
                storage_entry(3, true),
                storage_entry(4, true),
                storage_entry(5, false),
            ],
        });
        let [pipeline] = compute_pipelines(ctx, "shadow map eval", &module, &layout, ["main"]);
        Self { pipeline, layout }
    }
}

impl GpuShadowMaps {
    /// Renders one depth layer per view and waits for the GPU.
    pub fn render(
        ctx: &GpuContext,
        views: &[SampleView],
        casters: &[[Vec3; 3]],
        resolution: u32,
        light_size: f32,
    ) -> Result<Self> {
        let raster = ctx.cached(|c| Rasterizer(GpuRasterizer::new(c)));
        let tris = GpuTriangles::new(ctx, casters)?;
        let texture = GpuRasterizer::depth_array(ctx, resolution, views.len() as u32)?;
        let mut enc = ctx.device.create_command_encoder(&Default::default());
        for (layer, v) in views.iter().enumerate() {
            raster
                .0
                .encode_depth(ctx, &mut enc, &tris, &v.view, &texture, layer as u32);
        }
        ctx.queue.submit([enc.finish()]);
        ctx.wait()?;
        Ok(Self {
            texture,
            views: views.to_vec(),
            resolution,
            light_size,
        })
    }

    /// Reads layer `layer` back as a linear depth map.
    pub fn read_layer(&self, ctx: &GpuContext, layer: u32) -> Result<Map2D<f32>> {
        let raster = ctx.cached(|c| Rasterizer(GpuRasterizer::new(c)));
        let view = self
            .views
            .get(layer as usize)
            .ok_or_else(|| ShadowError::MapsMismatch(format!("no layer {layer}")))?;
        raster.0.read_depth(ctx, &self.texture, layer, &view.view)
    }
}

/// Runs the filter compute shader over every receiver and reads the visibilities back.
pub fn evaluate(
    ctx: &GpuContext,
    prm: &EvalParams,
    maps: &GpuShadowMaps,
    r: &Receivers,
) -> Result<Vec<f32>> {
    let Some(rb) = ReceiverBuffers::new(ctx, r)? else {
        return Ok(Vec::new());
    };
    let pipe = ctx.cached(EvalPipeline::new);
    let params: Vec<MapParams> = maps
        .views
        .iter()
        .map(|v| v.params(maps.resolution))
        .collect();
    let u = ctx.uniform_buffer("eval params", bytemuck::bytes_of(prm));
    let vb = ctx.storage_buffer("map views", bytemuck::cast_slice(&params));
    let tv = depth_array_view(&maps.texture);
    let bind = bind_group(
        ctx,
        "shadow map eval",
        &pipe.layout,
        &[
            u.as_entire_binding(),
            vb.as_entire_binding(),
            wgpu::BindingResource::TextureView(&tv),
            rb.positions.as_entire_binding(),
            rb.normals.as_entire_binding(),
            rb.visibility.as_entire_binding(),
        ],
    );
    rb.run(ctx, &pipe.pipeline, &bind)
}
