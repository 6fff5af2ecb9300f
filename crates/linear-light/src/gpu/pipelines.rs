//! The pipelines of the GPU path, built once per context: the skin warp render pipeline
//! (`skins.wgsl`), the skin search (`find_skins.wgsl`), the channel combine kernel
//! (`combine.wgsl`) and evaluation (`visibility.wgsl`), each declared once with its bindings.

use super::{CombineParams, EvalParams, Pair, SampleGpu};
use soft_shadow_core::GpuContext;
use soft_shadow_core::gpu::Kernel;
use soft_shadow_core::gpu::raster::DEPTH_FORMAT;
use soft_shadow_core::gpu::shader::{
    Binding, DEPTH_ARRAY, Group, Library, Program, ShaderModule, VisibilityShader, float_texture,
    storage, storage_texture, uniform,
};

/// Format of the warped skin values and of the visibility channels.
pub(crate) const VALUE_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Float;

/// The crate's WGSL: the sample views, the skin grid, the skin search and warp, the channel
/// combine kernel and the visibility module.
pub static SHADERS: Library = Library {
    name: "linear-light",
    modules: &[
        ShaderModule {
            path: "linear_light::sample",
            source: include_str!("../sample.wgsl"),
        },
        ShaderModule {
            path: "linear_light::grid",
            source: include_str!("../grid.wgsl"),
        },
        ShaderModule {
            path: "linear_light::skins",
            source: include_str!("../skins.wgsl"),
        },
        ShaderModule {
            path: "linear_light::find_skins",
            source: include_str!("../find_skins.wgsl"),
        },
        ShaderModule {
            path: "linear_light::combine",
            source: include_str!("../combine.wgsl"),
        },
        ShaderModule {
            path: "linear_light::visibility",
            source: include_str!("../visibility.wgsl"),
        },
    ],
    depends: &[&soft_shadow_core::gpu::shader::SHADERS],
    programs: &[&SKINS, &FIND_SKINS, &COMBINE],
};

/// The grid's bindings (`grid.wgsl`): the sample pair, the samples, their depth maps.
const GRID: [Binding; 3] = [uniform::<Pair>(), storage::<SampleGpu>(true), DEPTH_ARRAY];

/// `skins.wgsl`: the grid's bindings and the listed quads, read by both stages.
static SKINS: Program = Program {
    library: &SHADERS,
    module: "linear_light::skins",
    defs: &[],
    groups: &[Group {
        stages: wgpu::ShaderStages::VERTEX_FRAGMENT,
        bindings: &[GRID[0], GRID[1], GRID[2], storage::<u32>(true)],
    }],
};

/// `find_skins.wgsl`: the grid's bindings, the quads listed and the indirect draw's arguments.
static FIND_SKINS: Program = Program {
    library: &SHADERS,
    module: "linear_light::find_skins",
    defs: &[],
    groups: &[Group::compute(&[
        GRID[0],
        GRID[1],
        GRID[2],
        storage::<u32>(false),
        storage::<[u32; 4]>(false),
    ])],
};

/// `combine.wgsl`: parameters, the warped values of the previous and next samples, the
/// channels.
static COMBINE: Program = Program {
    library: &SHADERS,
    module: "linear_light::combine",
    defs: &[],
    groups: &[Group::compute(&[
        uniform::<CombineParams>(),
        float_texture(wgpu::TextureViewDimension::D2),
        float_texture(wgpu::TextureViewDimension::D2),
        storage_texture(VALUE_FORMAT, wgpu::TextureViewDimension::D2Array),
    ])],
};

/// Evaluation: parameters, samples, the depth array and the channels.
pub static VISIBILITY: VisibilityShader = VisibilityShader {
    library: &SHADERS,
    module: "linear_light::visibility",
    maps: Group::compute(&[
        uniform::<EvalParams>(),
        storage::<SampleGpu>(true),
        DEPTH_ARRAY,
        float_texture(wgpu::TextureViewDimension::D2Array),
    ]),
};

/// Skins of one sample warped into a neighbour's view.
pub(crate) struct SkinPipeline {
    /// Pair uniform, samples, depth maps.
    pub layout: wgpu::BindGroupLayout,
    /// The render pipeline (R32Float value, reversed-Z depth).
    pub pipeline: wgpu::RenderPipeline,
}

impl SkinPipeline {
    /// Builds the pipeline.
    pub(crate) fn new(ctx: &GpuContext) -> Self {
        let program = ctx.program(&SKINS);
        let (m, pl) = (&program.module, &program.pipeline_layout);
        let layout = program.layouts[0].clone();
        let pipeline = ctx
            .device
            .create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some("skins"),
                layout: Some(pl),
                vertex: wgpu::VertexState {
                    module: m,
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
                    module: m,
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

/// The kernel that lists a source map's skin quads for the indirect skin draw.
pub(crate) struct FindSkinsKernel(pub Kernel);

impl FindSkinsKernel {
    /// Builds the kernel.
    pub(crate) fn new(ctx: &GpuContext) -> Self {
        Self(Kernel::new(ctx, &FIND_SKINS, "find_skins"))
    }
}

/// The channel combine kernel.
pub(crate) struct CombineKernel(pub Kernel);

impl CombineKernel {
    /// Builds the kernel.
    pub(crate) fn new(ctx: &GpuContext) -> Self {
        Self(Kernel::new(ctx, &COMBINE, "combine"))
    }
}
