//! The pipelines of the GPU path, built once per context: the slicing render pipelines
//! (`slicing.wgsl`, one per number of targets), the prefiltering kernels (`sat_rows.wgsl`,
//! `sat_cols.wgsl`, `levels.wgsl`) and evaluation (`visibility.wgsl`), each declared once with
//! its bindings.

use super::{EvalParams, LevelParams};
use crate::frame::Frame;
use soft_shadow_core::GpuContext;
use soft_shadow_core::gpu::Kernel;
use soft_shadow_core::gpu::shader::{
    Group, Library, Program, ShaderModule, VisibilityShader, float_texture, storage_texture,
    uint_texture, uniform,
};

/// Format of the occlusion textures: four slices per RGBA8 texel.
pub(crate) const OCCUPANCY_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;
/// Format of the summed-area tables: four slices of `u32` counts per texel.
pub(crate) const SAT_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Uint;
/// Format of N-Buffer and mipmap levels (the paper's RGBA8).
pub(crate) const LEVEL_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;

const ARRAY: wgpu::TextureViewDimension = wgpu::TextureViewDimension::D2Array;

/// The crate's WGSL: the slicing frame, the slicing pass, the prefiltering kernels and the
/// visibility module.
pub static SHADERS: Library = Library {
    name: "occlusion-slices",
    modules: &[
        ShaderModule {
            path: "occlusion_slices::frame",
            source: include_str!("../frame.wgsl"),
        },
        ShaderModule {
            path: "occlusion_slices::slicing",
            source: include_str!("../slicing.wgsl"),
        },
        ShaderModule {
            path: "occlusion_slices::sat_rows",
            source: include_str!("../sat_rows.wgsl"),
        },
        ShaderModule {
            path: "occlusion_slices::sat_cols",
            source: include_str!("../sat_cols.wgsl"),
        },
        ShaderModule {
            path: "occlusion_slices::levels",
            source: include_str!("../levels.wgsl"),
        },
        ShaderModule {
            path: "occlusion_slices::visibility",
            source: include_str!("../visibility.wgsl"),
        },
    ],
    depends: &[&soft_shadow_core::gpu::shader::SHADERS],
    programs: &[&SLICING, &SAT_ROWS, &SAT_COLS, &LEVELS],
};

/// `slicing.wgsl`: the frame, read by the vertex and fragment stages.
static SLICING: Program = Program {
    library: &SHADERS,
    module: "occlusion_slices::slicing",
    defs: &[],
    groups: &[Group {
        stages: wgpu::ShaderStages::VERTEX_FRAGMENT,
        bindings: &[uniform::<Frame>()],
    }],
};

/// `sat_rows.wgsl`: the frame, the occupancy, the row prefix sums.
static SAT_ROWS: Program = Program {
    library: &SHADERS,
    module: "occlusion_slices::sat_rows",
    defs: &[],
    groups: &[Group::compute(&[
        uniform::<Frame>(),
        float_texture(ARRAY),
        storage_texture(SAT_FORMAT, ARRAY),
    ])],
};

/// `sat_cols.wgsl`: the frame, the row prefix sums, the summed-area table.
static SAT_COLS: Program = Program {
    library: &SHADERS,
    module: "occlusion_slices::sat_cols",
    defs: &[],
    groups: &[Group::compute(&[
        uniform::<Frame>(),
        uint_texture(ARRAY),
        storage_texture(SAT_FORMAT, ARRAY),
    ])],
};

/// `levels.wgsl`: the frame, the table, the level's parameters, the level written.
static LEVELS: Program = Program {
    library: &SHADERS,
    module: "occlusion_slices::levels",
    defs: &[],
    groups: &[Group::compute(&[
        uniform::<Frame>(),
        uint_texture(ARRAY),
        uniform::<LevelParams>(),
        storage_texture(LEVEL_FORMAT, ARRAY),
    ])],
};

/// Evaluation: the frame, the parameters, the table, the level texture and the slices' top
/// codes.
pub static VISIBILITY: VisibilityShader = VisibilityShader {
    library: &SHADERS,
    module: "occlusion_slices::visibility",
    maps: Group::compute(&[
        uniform::<Frame>(),
        uniform::<EvalParams>(),
        uint_texture(ARRAY),
        float_texture(ARRAY),
        float_texture(ARRAY),
    ]),
};

/// The slicing pass: `pipelines[g - 1]` draws into `g` targets.
pub(crate) struct SlicingPipelines {
    /// Bind group layout: the frame uniform.
    pub layout: wgpu::BindGroupLayout,
    /// One pipeline per target count 1..=4.
    pub pipelines: [wgpu::RenderPipeline; 4],
}

impl SlicingPipelines {
    /// Builds the pipelines.
    pub(crate) fn new(ctx: &GpuContext) -> Self {
        let program = ctx.program(&SLICING);
        let (m, pl) = (&program.module, &program.pipeline_layout);
        let layout = program.layouts[0].clone();
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
                    layout: Some(pl),
                    vertex: wgpu::VertexState {
                        module: m,
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
                        module: m,
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
pub(crate) struct PrefilterPipelines {
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
    pub(crate) fn new(ctx: &GpuContext) -> Self {
        Self {
            sat_rows: Kernel::new(ctx, &SAT_ROWS, "sat_rows"),
            sat_cols: Kernel::new(ctx, &SAT_COLS, "sat_cols"),
            nbuffer_level: Kernel::new(ctx, &LEVELS, "nbuffer_level"),
            mip_level: Kernel::new(ctx, &LEVELS, "mip_level"),
        }
    }
}
