//! The pipelines of the GPU path, built once per context: the skin warp render pipeline
//! (`skins.wgsl`), the channel combine kernel (`combine.wgsl`) and evaluation (`evaluate.wgsl`).

use soft_shadow_core::GpuContext;
use soft_shadow_core::gpu::compute::{storage_entry, uniform_entry};
use soft_shadow_core::gpu::raster::DEPTH_FORMAT;
use soft_shadow_core::gpu::resources::{
    FLOAT, Kernel, layout, pipeline_layout, storage_texture_entry, texture_entry, wgsl_module,
};

/// The crate's WGSL files, for [`soft_shadow_core::gpu::wgsl::resolve`].
pub const WGSL: &[(&str, &str)] = &[
    ("sample.wgsl", include_str!("../sample.wgsl")),
    ("grid.wgsl", include_str!("../grid.wgsl")),
    ("skins.wgsl", include_str!("../skins.wgsl")),
    ("find_skins.wgsl", include_str!("../find_skins.wgsl")),
    ("combine.wgsl", include_str!("../combine.wgsl")),
    ("evaluate.wgsl", include_str!("../evaluate.wgsl")),
];

/// Format of the warped skin values and of the visibility channels.
pub const VALUE_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Float;

/// File `name` of [`WGSL`] after the files it requires.
pub fn source(name: &str) -> String {
    soft_shadow_core::gpu::wgsl::source(name, WGSL)
}

/// Skins of one sample warped into a neighbour's view.
pub struct SkinPipeline {
    /// Pair uniform, samples, depth maps.
    pub layout: wgpu::BindGroupLayout,
    /// The render pipeline (R32Float value, reversed-Z depth).
    pub pipeline: wgpu::RenderPipeline,
}

impl SkinPipeline {
    /// Builds the pipeline.
    pub fn new(ctx: &GpuContext) -> Self {
        let m = wgsl_module(ctx, "skins", &[&source("skins.wgsl")]);
        let vf = wgpu::ShaderStages::VERTEX_FRAGMENT;
        let mut pair = uniform_entry(0);
        pair.visibility = vf;
        let samples = storage_entry_in(1, true, vf);
        let layout = layout(
            ctx,
            "skins",
            &[
                pair,
                samples,
                texture_entry(
                    2,
                    vf,
                    wgpu::TextureSampleType::Depth,
                    wgpu::TextureViewDimension::D2Array,
                ),
                storage_entry_in(3, true, vf),
            ],
        );
        let pl = pipeline_layout(ctx, "skins", &[&layout]);
        let pipeline = ctx
            .device
            .create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some("skins"),
                layout: Some(&pl),
                vertex: wgpu::VertexState {
                    module: &m,
                    entry_point: Some("vs_skin"),
                    compilation_options: Default::default(),
                    buffers: &[],
                },
                primitive: wgpu::PrimitiveState {
                    cull_mode: None,
                    ..Default::default()
                },
                depth_stencil: Some(wgpu::DepthStencilState {
                    format: DEPTH_FORMAT,
                    depth_write_enabled: Some(true),
                    depth_compare: Some(wgpu::CompareFunction::Greater),
                    stencil: Default::default(),
                    bias: Default::default(),
                }),
                multisample: Default::default(),
                fragment: Some(wgpu::FragmentState {
                    module: &m,
                    entry_point: Some("fs_skin"),
                    compilation_options: Default::default(),
                    targets: &[Some(wgpu::ColorTargetState {
                        format: VALUE_FORMAT,
                        blend: None,
                        write_mask: wgpu::ColorWrites::ALL,
                    })],
                }),
                multiview_mask: None,
                cache: None,
            });
        Self { layout, pipeline }
    }
}

fn storage_entry_in(
    binding: u32,
    read_only: bool,
    visibility: wgpu::ShaderStages,
) -> wgpu::BindGroupLayoutEntry {
    let mut e = storage_entry(binding, read_only);
    e.visibility = visibility;
    e
}

/// The kernel that lists a source map's skin quads for the indirect skin draw.
pub struct FindSkinsKernel(pub Kernel);

impl FindSkinsKernel {
    /// Builds the kernel.
    pub fn new(ctx: &GpuContext) -> Self {
        Self(Kernel::new(
            ctx,
            "find skins",
            &[&source("find_skins.wgsl")],
            "find_skins",
            &[
                uniform_entry(0),
                storage_entry(1, true),
                texture_entry(
                    2,
                    wgpu::ShaderStages::COMPUTE,
                    wgpu::TextureSampleType::Depth,
                    wgpu::TextureViewDimension::D2Array,
                ),
                storage_entry(3, false),
                storage_entry(4, false),
            ],
        ))
    }
}

/// The channel combine kernel.
pub struct CombineKernel(pub Kernel);

impl CombineKernel {
    /// Builds the kernel.
    pub fn new(ctx: &GpuContext) -> Self {
        let c = wgpu::ShaderStages::COMPUTE;
        Self(Kernel::new(
            ctx,
            "linear-light combine",
            &[&source("combine.wgsl")],
            "combine",
            &[
                uniform_entry(0),
                texture_entry(1, c, FLOAT, wgpu::TextureViewDimension::D2),
                texture_entry(2, c, FLOAT, wgpu::TextureViewDimension::D2),
                storage_texture_entry(3, VALUE_FORMAT, wgpu::TextureViewDimension::D2Array),
            ],
        ))
    }
}

/// Evaluation's bindings: parameters, samples, the depth array and the channels.
pub fn eval_entries() -> Vec<wgpu::BindGroupLayoutEntry> {
    let c = wgpu::ShaderStages::COMPUTE;
    vec![
        uniform_entry(0),
        storage_entry(1, true),
        texture_entry(
            2,
            c,
            wgpu::TextureSampleType::Depth,
            wgpu::TextureViewDimension::D2Array,
        ),
        texture_entry(3, c, FLOAT, wgpu::TextureViewDimension::D2Array),
    ]
}
