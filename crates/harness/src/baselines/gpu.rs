//! The baselines on the GPU: depth maps rendered by `shadow_core`'s rasterizer into one
//! reversed-Z texture array, filters evaluated by the compute shader `shadow_map_eval.wgsl`.

use super::filters::EvalParams;
use super::maps::{MapParams, SampleView};
use glam::Vec3;
use shadow_core::gpu::{GpuRasterizer, GpuTriangles};
use shadow_core::{GpuContext, Map2D, Receivers, Result, ShadowError};

const WORKGROUP: u32 = 64;

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

fn storage_entry(binding: u32, read_only: bool) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

impl EvalPipeline {
    fn new(ctx: &GpuContext) -> Self {
        let d = &ctx.device;
        let module = d.create_shader_module(wgpu::include_wgsl!("shadow_map_eval.wgsl"));
        let layout = d.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("shadow map eval"),
            entries: &[
                wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    visibility: wgpu::ShaderStages::COMPUTE,
                    ty: wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Uniform,
                        has_dynamic_offset: false,
                        min_binding_size: None,
                    },
                    count: None,
                },
                storage_entry(1, true),
                wgpu::BindGroupLayoutEntry {
                    binding: 2,
                    visibility: wgpu::ShaderStages::COMPUTE,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Depth,
                        view_dimension: wgpu::TextureViewDimension::D2Array,
                        multisampled: false,
                    },
                    count: None,
                },
                storage_entry(3, true),
                storage_entry(4, true),
                storage_entry(5, false),
            ],
        });
        let pl = d.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("shadow map eval"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let pipeline = d.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("shadow map eval"),
            layout: Some(&pl),
            module: &module,
            entry_point: Some("main"),
            compilation_options: Default::default(),
            cache: None,
        });
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
    let n = r.positions.len() as u32;
    if n == 0 {
        return Ok(Vec::new());
    }
    let groups = n.div_ceil(WORKGROUP);
    let max_groups = ctx.device.limits().max_compute_workgroups_per_dimension;
    if groups > max_groups {
        return Err(ShadowError::InvalidReceivers(format!(
            "{n} receivers exceed one dispatch ({} at most)",
            max_groups * WORKGROUP
        )));
    }
    let limit = ctx.device.limits().max_storage_buffer_binding_size;
    if n as u64 * 16 > limit {
        return Err(ShadowError::InvalidReceivers(format!(
            "{n} receivers need {} bytes, above the device's {limit}-byte storage binding",
            n as u64 * 16
        )));
    }
    let pipe = ctx.cached(EvalPipeline::new);
    let params: Vec<MapParams> = maps
        .views
        .iter()
        .map(|v| v.params(maps.resolution))
        .collect();
    let pos: Vec<[f32; 4]> = r
        .positions
        .iter()
        .map(|p| p.extend(1.0).to_array())
        .collect();
    let nrm: Vec<[f32; 4]> = r.normals.iter().map(|p| p.extend(0.0).to_array()).collect();
    let u = ctx.uniform_buffer("eval params", bytemuck::bytes_of(prm));
    let vb = ctx.storage_buffer("map views", bytemuck::cast_slice(&params));
    let pb = ctx.storage_buffer("receiver positions", bytemuck::cast_slice(&pos));
    let nb = ctx.storage_buffer("receiver normals", bytemuck::cast_slice(&nrm));
    let out_size = n as u64 * 4;
    let ob = ctx.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("visibility"),
        size: out_size,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let tv = maps.texture.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::D2Array),
        aspect: wgpu::TextureAspect::DepthOnly,
        ..Default::default()
    });
    let bind = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("shadow map eval"),
        layout: &pipe.layout,
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: u.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: vb.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 2,
                resource: wgpu::BindingResource::TextureView(&tv),
            },
            wgpu::BindGroupEntry {
                binding: 3,
                resource: pb.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 4,
                resource: nb.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 5,
                resource: ob.as_entire_binding(),
            },
        ],
    });
    let mut enc = ctx.device.create_command_encoder(&Default::default());
    {
        let mut pass = enc.begin_compute_pass(&Default::default());
        pass.set_pipeline(&pipe.pipeline);
        pass.set_bind_group(0, &bind, &[]);
        pass.dispatch_workgroups(groups, 1, 1);
    }
    ctx.queue.submit([enc.finish()]);
    let bytes = ctx.read_buffer(&ob, out_size)?;
    Ok(bytemuck::pod_collect_to_vec(&bytes))
}
