//! The pipelines of the GPU path, built once per context: the ribbon and back-face render
//! pipelines (`silhouette.wgsl`), the depth-image kernels (`depth_image.wgsl`), one combine
//! kernel per storage format (`combine.wgsl`, its shader def `STORAGE`) and evaluation
//! (`visibility.wgsl`), each declared once with its bindings.

use super::GenParams;
use crate::eval::EvalParams;
use crate::silhouette::Edge;
use crate::storage::Storage;
use bytemuck::{Pod, Zeroable};
use soft_shadow_core::GpuContext;
use soft_shadow_core::gpu::raster::DEPTH_FORMAT;
use soft_shadow_core::gpu::shader::{
    Binding, DEPTH_ARRAY, Group, Library, Program, ShaderModule, VisibilityShader, float_texture,
    storage, storage_texture, uniform,
};

const D2: wgpu::TextureViewDimension = wgpu::TextureViewDimension::D2;

/// The crate's WGSL: the depth warp, both generators, the combine kernel and the visibility
/// module.
pub static SHADERS: Library = Library {
    name: "penumbra-limit",
    modules: &[
        ShaderModule {
            path: "penumbra_limit::warp",
            source: include_str!("../warp.wgsl"),
        },
        ShaderModule {
            path: "penumbra_limit::silhouette",
            source: include_str!("../silhouette.wgsl"),
        },
        ShaderModule {
            path: "penumbra_limit::depth_image",
            source: include_str!("../depth_image.wgsl"),
        },
        ShaderModule {
            path: "penumbra_limit::combine",
            source: include_str!("../combine.wgsl"),
        },
        ShaderModule {
            path: "penumbra_limit::visibility",
            source: include_str!("../visibility.wgsl"),
        },
        ShaderModule {
            path: "penumbra_limit::feature_transform",
            source: include_str!("../feature_transform.wgsl"),
        },
    ],
    depends: &[&soft_shadow_core::gpu::shader::SHADERS],
    programs: &[
        &SILHOUETTE,
        &DEPTH_IMAGE,
        &COMBINE[0],
        &COMBINE[1],
        &COMBINE[2],
        &FEATURE_TRANSFORM,
    ],
};

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
/// The feature transform's parameters (`feature_transform.wgsl`).
pub(crate) struct FtParams {
    pub(crate) resolution: u32,
    pub(crate) keyed: u32,
    pub(crate) _pad: [u32; 2],
}

/// `feature_transform.wgsl`: parameters, the seeds and the scratch buffer (`u32`), the keys.
pub(crate) static FEATURE_TRANSFORM: Program = Program {
    library: &SHADERS,
    module: "penumbra_limit::feature_transform",
    defs: &[],
    groups: &[Group::compute(&[
        uniform::<FtParams>(),
        storage::<u32>(false),
        storage::<u32>(false),
        storage::<f32>(true),
    ])],
};

/// `silhouette.wgsl`: parameters, the edges (vertex stage), the edge layer (fragment stage),
/// the geometry depths (both).
static SILHOUETTE: Program = Program {
    library: &SHADERS,
    module: "penumbra_limit::silhouette",
    defs: &[],
    groups: &[Group {
        stages: wgpu::ShaderStages::VERTEX_FRAGMENT,
        bindings: &[
            uniform::<GenParams>(),
            storage::<Edge>(true),
            float_texture(D2),
            storage::<f32>(true),
        ],
    }],
};

/// `depth_image.wgsl`: parameters, the depth map, the geometry layer, the near and far seeds,
/// the edge and lower-limit layers.
static DEPTH_IMAGE: Program = Program {
    library: &SHADERS,
    module: "penumbra_limit::depth_image",
    defs: &[],
    groups: &[Group::compute(&[
        uniform::<GenParams>(),
        DEPTH_ARRAY,
        storage::<f32>(false),
        storage::<u32>(false),
        storage::<u32>(false),
        storage_texture(EDGE_FORMAT, D2),
        storage_texture(LOWER_FORMAT, D2),
    ])],
};

/// `combine.wgsl`'s bindings writing a map of `format`: parameters, the geometry layer, the
/// edge and lower layers, the map.
const fn combine_bindings(format: wgpu::TextureFormat) -> [Binding; 5] {
    [
        uniform::<GenParams>(),
        storage::<f32>(true),
        float_texture(D2),
        float_texture(D2),
        storage_texture(format, D2),
    ]
}

const COMBINE_F32: [Binding; 5] = combine_bindings(wgpu::TextureFormat::Rgba32Float);
const COMBINE_F16: [Binding; 5] = combine_bindings(wgpu::TextureFormat::Rgba16Float);
const COMBINE_RGBA8: [Binding; 5] = combine_bindings(wgpu::TextureFormat::Rgba8Unorm);

/// `combine.wgsl` for each storage format, indexed like [`Storage::ALL`]: the shader def
/// `STORAGE` picks the map's format.
static COMBINE: [Program; 3] = [
    Program {
        library: &SHADERS,
        module: "penumbra_limit::combine",
        defs: &[("STORAGE", 0)],
        groups: &[Group::compute(&COMBINE_F32)],
    },
    Program {
        library: &SHADERS,
        module: "penumbra_limit::combine",
        defs: &[("STORAGE", 1)],
        groups: &[Group::compute(&COMBINE_F16)],
    },
    Program {
        library: &SHADERS,
        module: "penumbra_limit::combine",
        defs: &[("STORAGE", 2)],
        groups: &[Group::compute(&COMBINE_RGBA8)],
    },
];

/// Evaluation: the parameters, the stored map, the illumination table.
pub static VISIBILITY: VisibilityShader = VisibilityShader {
    library: &SHADERS,
    module: "penumbra_limit::visibility",
    maps: Group::compute(&[
        uniform::<EvalParams>(),
        float_texture(D2),
        storage::<f32>(true),
    ]),
};

/// Format of the edge layer `[c, p_i]`.
pub(crate) const EDGE_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rg32Float;
/// Format of the lower-limit layer.
pub(crate) const LOWER_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Float;

/// Silhouette extrusion, steps 2 and 3.
pub(crate) struct SilhouettePipelines {
    /// Parameters, edges, edge texture, geometry depths.
    pub layout: wgpu::BindGroupLayout,
    /// Ribbons into the edge layer, depth = penumbra limit.
    pub ribbons: wgpu::RenderPipeline,
    /// Back faces into the lower layer.
    pub lower: wgpu::RenderPipeline,
}

impl SilhouettePipelines {
    /// Builds the pipelines.
    pub(crate) fn new(ctx: &GpuContext) -> Self {
        let program = ctx.program(&SILHOUETTE);
        let (m, pl) = (&program.module, &program.pipeline_layout);
        let layout = program.layouts[0].clone();
        let pipeline = |label: &str,
                        vs: &str,
                        fs: &str,
                        buffers: &[Option<wgpu::VertexBufferLayout>],
                        format: wgpu::TextureFormat,
                        cull: Option<wgpu::Face>,
                        compare: wgpu::CompareFunction| {
            ctx.device
                .create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                    label: Some(label),
                    layout: Some(pl),
                    vertex: wgpu::VertexState {
                        module: m,
                        entry_point: Some(vs),
                        compilation_options: Default::default(),
                        buffers,
                    },
                    primitive: wgpu::PrimitiveState {
                        cull_mode: cull,
                        ..Default::default()
                    },
                    depth_stencil: Some(wgpu::DepthStencilState {
                        format: DEPTH_FORMAT,
                        depth_write_enabled: Some(true),
                        depth_compare: Some(compare),
                        stencil: Default::default(),
                        bias: Default::default(),
                    }),
                    multisample: Default::default(),
                    fragment: Some(wgpu::FragmentState {
                        module: m,
                        entry_point: Some(fs),
                        compilation_options: Default::default(),
                        targets: &[Some(format.into())],
                    }),
                    multiview_mask: None,
                    cache: None,
                })
        };
        let positions = [Some(wgpu::VertexBufferLayout {
            array_stride: 12,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &wgpu::vertex_attr_array![0 => Float32x3],
        })];
        Self {
            ribbons: pipeline(
                "penumbra ribbons",
                "vs_ribbon",
                "fs_ribbon",
                &[],
                EDGE_FORMAT,
                None,
                wgpu::CompareFunction::Less,
            ),
            lower: pipeline(
                "penumbra lower limit",
                "vs_lower",
                "fs_lower",
                &positions,
                LOWER_FORMAT,
                Some(wgpu::Face::Front),
                wgpu::CompareFunction::Greater,
            ),
            layout,
        }
    }
}

/// The geometry layer and the depth-image generator.
pub(crate) struct DepthImagePipelines {
    /// Parameters, depth map, geometry, seeds, edge and lower outputs.
    pub layout: wgpu::BindGroupLayout,
    /// Normalised nearest depth.
    pub geometry: wgpu::ComputePipeline,
    /// Near- and far-side seeds.
    pub seeds: wgpu::ComputePipeline,
    /// Edge and lower limit from the nearest seeds.
    pub limits: wgpu::ComputePipeline,
}

impl DepthImagePipelines {
    /// Builds the pipelines.
    pub(crate) fn new(ctx: &GpuContext) -> Self {
        let p = ctx.program(&DEPTH_IMAGE);
        Self {
            layout: p.layouts[0].clone(),
            geometry: p.compute(ctx, "geometry"),
            seeds: p.compute(ctx, "seeds"),
            limits: p.compute(ctx, "limits"),
        }
    }
}

/// One combine kernel per storage format.
pub(crate) struct CombinePipelines {
    /// Parameters, geometry, edge and lower textures, the map; indexed like [`Storage::ALL`].
    pub layouts: Vec<wgpu::BindGroupLayout>,
    /// Indexed like [`Storage::ALL`].
    pub pipelines: Vec<wgpu::ComputePipeline>,
}

impl CombinePipelines {
    /// Builds the pipelines.
    pub(crate) fn new(ctx: &GpuContext) -> Self {
        let built: Vec<_> = COMBINE.iter().map(|p| ctx.program(p)).collect();
        Self {
            layouts: built.iter().map(|p| p.layouts[0].clone()).collect(),
            pipelines: built.iter().map(|p| p.compute(ctx, "combine")).collect(),
        }
    }

    /// The index of `s`.
    pub(crate) fn index(s: Storage) -> usize {
        Storage::ALL.iter().position(|&x| x == s).unwrap_or(0)
    }
}
