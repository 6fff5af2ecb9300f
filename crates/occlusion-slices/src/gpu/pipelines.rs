//! The pipelines of the GPU path, built once per context: the slicing render pipelines
//! (`slicing.wgsl`, one per number of targets), the prefiltering kernels (`sat_rows.wgsl`,
//! `sat_cols.wgsl`, `levels.wgsl`) and evaluation (`evaluate.wgsl`).

use soft_shadow_core::GpuContext;
use soft_shadow_core::gpu::compute::uniform_entry;
use soft_shadow_core::gpu::resources::{
    FLOAT, Kernel, layout, pipeline_layout, storage_texture_entry, texture_entry, wgsl_module,
};

/// The crate's WGSL files, for [`soft_shadow_core::gpu::wgsl::resolve`].
pub const WGSL: &[(&str, &str)] = &[
    ("frame.wgsl", include_str!("../frame.wgsl")),
    ("slicing.wgsl", include_str!("../slicing.wgsl")),
    ("sat_rows.wgsl", include_str!("../sat_rows.wgsl")),
    ("sat_cols.wgsl", include_str!("../sat_cols.wgsl")),
    ("levels.wgsl", include_str!("../levels.wgsl")),
    ("evaluate.wgsl", include_str!("../evaluate.wgsl")),
];

/// File `name` of [`WGSL`] after the files it requires.
pub fn source(name: &str) -> String {
    soft_shadow_core::gpu::wgsl::source(name, WGSL)
}

/// Format of the occlusion textures: four slices per RGBA8 texel.
pub const OCCUPANCY_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;
/// Format of the summed-area tables: four slices of `u32` counts per texel.
pub const SAT_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Uint;
/// Format of N-Buffer and mipmap levels (the paper's RGBA8).
pub const LEVEL_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;

const UINT: wgpu::TextureSampleType = wgpu::TextureSampleType::Uint;

fn texture_array(binding: u32, sample_type: wgpu::TextureSampleType) -> wgpu::BindGroupLayoutEntry {
    texture_entry(
        binding,
        wgpu::ShaderStages::COMPUTE,
        sample_type,
        wgpu::TextureViewDimension::D2Array,
    )
}

fn storage_array(binding: u32, format: wgpu::TextureFormat) -> wgpu::BindGroupLayoutEntry {
    storage_texture_entry(binding, format, wgpu::TextureViewDimension::D2Array)
}

/// The slicing pass: `pipelines[g - 1]` draws into `g` targets.
pub struct SlicingPipelines {
    /// Bind group layout: the frame uniform.
    pub layout: wgpu::BindGroupLayout,
    /// One pipeline per target count 1..=4.
    pub pipelines: [wgpu::RenderPipeline; 4],
}

impl SlicingPipelines {
    /// Builds the pipelines.
    pub fn new(ctx: &GpuContext) -> Self {
        let m = wgsl_module(ctx, "slicing", &[&source("slicing.wgsl")]);
        let mut uniform = uniform_entry(0);
        uniform.visibility = wgpu::ShaderStages::VERTEX_FRAGMENT;
        let layout = layout(ctx, "slicing", &[uniform]);
        let pl = pipeline_layout(ctx, "slicing", &[&layout]);
        let max = wgpu::BlendComponent {
            src_factor: wgpu::BlendFactor::One,
            dst_factor: wgpu::BlendFactor::One,
            operation: wgpu::BlendOperation::Max,
        };
        let target = Some(wgpu::ColorTargetState {
            format: OCCUPANCY_FORMAT,
            blend: Some(wgpu::BlendState {
                color: max,
                alpha: max,
            }),
            write_mask: wgpu::ColorWrites::ALL,
        });
        let pipelines = [1usize, 2, 3, 4].map(|g| {
            let mut targets = vec![None; 4];
            for t in targets.iter_mut().take(g) {
                *t = target.clone();
            }
            ctx.device
                .create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                    label: Some("slicing"),
                    layout: Some(&pl),
                    vertex: wgpu::VertexState {
                        module: &m,
                        entry_point: Some("vs_slice"),
                        compilation_options: Default::default(),
                        buffers: &[Some(wgpu::VertexBufferLayout {
                            array_stride: 12,
                            step_mode: wgpu::VertexStepMode::Vertex,
                            attributes: &wgpu::vertex_attr_array![0 => Float32x3],
                        })],
                    },
                    primitive: wgpu::PrimitiveState {
                        cull_mode: None,
                        ..Default::default()
                    },
                    depth_stencil: None,
                    multisample: Default::default(),
                    fragment: Some(wgpu::FragmentState {
                        module: &m,
                        entry_point: Some("fs_slice"),
                        compilation_options: Default::default(),
                        targets: &targets,
                    }),
                    multiview_mask: None,
                    cache: None,
                })
        });
        Self { layout, pipelines }
    }
}

/// The prefiltering kernels.
pub struct PrefilterPipelines {
    /// Occupancy to row prefix sums.
    pub sat_rows: Kernel,
    /// Row prefix sums to the summed-area table.
    pub sat_cols: Kernel,
    /// One N-Buffer level from the table.
    pub nbuffer_level: Kernel,
    /// One mip level from the table.
    pub mip_level: Kernel,
}

impl PrefilterPipelines {
    /// Builds the kernels.
    pub fn new(ctx: &GpuContext) -> Self {
        let levels = source("levels.wgsl");
        let level_entries = [
            uniform_entry(0),
            texture_array(1, UINT),
            uniform_entry(2),
            storage_array(3, LEVEL_FORMAT),
        ];
        Self {
            sat_rows: Kernel::new(
                ctx,
                "sat rows",
                &[&source("sat_rows.wgsl")],
                "sat_rows",
                &[
                    uniform_entry(0),
                    texture_array(1, FLOAT),
                    storage_array(2, SAT_FORMAT),
                ],
            ),
            sat_cols: Kernel::new(
                ctx,
                "sat cols",
                &[&source("sat_cols.wgsl")],
                "sat_cols",
                &[
                    uniform_entry(0),
                    texture_array(1, UINT),
                    storage_array(2, SAT_FORMAT),
                ],
            ),
            nbuffer_level: Kernel::new(
                ctx,
                "nbuffer level",
                &[&levels],
                "nbuffer_level",
                &level_entries,
            ),
            mip_level: Kernel::new(ctx, "mip level", &[&levels], "mip_level", &level_entries),
        }
    }
}

/// Evaluation's bindings: frame, parameters, the table and the level texture.
pub fn eval_entries() -> Vec<wgpu::BindGroupLayoutEntry> {
    vec![
        uniform_entry(0),
        uniform_entry(1),
        texture_array(2, UINT),
        texture_array(3, FLOAT),
    ]
}
