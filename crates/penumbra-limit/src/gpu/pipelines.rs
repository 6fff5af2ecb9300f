//! The pipelines of the GPU path, built once per context: the ribbon and back-face render
//! pipelines (`silhouette.wgsl`), the depth-image kernels (`depth_image.wgsl`), one combine
//! kernel per storage format (`combine.wgsl`) and evaluation (`evaluate.wgsl`).

use crate::storage::Storage;
use soft_shadow_core::GpuContext;
use soft_shadow_core::gpu::compute::{
    compute_pipelines, depth_array_entry, storage_entry, uniform_entry,
};
use soft_shadow_core::gpu::raster::DEPTH_FORMAT;
use soft_shadow_core::gpu::resources::{
    FLOAT, layout, pipeline_layout, storage_texture_entry, texture_entry, wgsl_module,
};

/// The crate's WGSL files, for [`soft_shadow_core::gpu::wgsl::resolve`].
pub const WGSL: &[(&str, &str)] = &[
    ("warp.wgsl", include_str!("../warp.wgsl")),
    ("silhouette.wgsl", include_str!("../silhouette.wgsl")),
    ("depth_image.wgsl", include_str!("../depth_image.wgsl")),
    ("combine.wgsl", include_str!("../combine.wgsl")),
    ("evaluate.wgsl", include_str!("../evaluate.wgsl")),
];

/// File `name` of [`WGSL`] after the files it requires.
pub fn source(name: &str) -> String {
    soft_shadow_core::gpu::wgsl::source(name, WGSL)
}

/// Format of the edge layer `[c, p_i]`.
pub const EDGE_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rg32Float;
/// Format of the lower-limit layer.
pub const LOWER_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Float;

fn module(ctx: &GpuContext, label: &str, file: &str) -> wgpu::ShaderModule {
    wgsl_module(ctx, label, &[&source(file)])
}

fn texture(binding: u32, visibility: wgpu::ShaderStages) -> wgpu::BindGroupLayoutEntry {
    texture_entry(binding, visibility, FLOAT, wgpu::TextureViewDimension::D2)
}

fn storage_texture(binding: u32, format: wgpu::TextureFormat) -> wgpu::BindGroupLayoutEntry {
    storage_texture_entry(binding, format, wgpu::TextureViewDimension::D2)
}

/// Silhouette extrusion, steps 2 and 3.
pub struct SilhouettePipelines {
    /// Parameters, edges, edge texture.
    pub layout: wgpu::BindGroupLayout,
    /// Ribbons into the edge layer, depth = penumbra limit.
    pub ribbons: wgpu::RenderPipeline,
    /// Back faces into the lower layer.
    pub lower: wgpu::RenderPipeline,
}

impl SilhouettePipelines {
    /// Builds the pipelines.
    pub fn new(ctx: &GpuContext) -> Self {
        let m = module(ctx, "penumbra silhouette", "silhouette.wgsl");
        let vf = wgpu::ShaderStages::VERTEX | wgpu::ShaderStages::FRAGMENT;
        let mut uniform = uniform_entry(0);
        uniform.visibility = vf;
        let mut edges = storage_entry(1, true);
        edges.visibility = wgpu::ShaderStages::VERTEX;
        let layout = layout(
            ctx,
            "penumbra silhouette",
            &[uniform, edges, texture(2, wgpu::ShaderStages::FRAGMENT)],
        );
        let pl = pipeline_layout(ctx, "penumbra silhouette", &[&layout]);
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
                    layout: Some(&pl),
                    vertex: wgpu::VertexState {
                        module: &m,
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
                        module: &m,
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
pub struct DepthImagePipelines {
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
    pub fn new(ctx: &GpuContext) -> Self {
        let m = module(ctx, "penumbra depth image", "depth_image.wgsl");
        let layout = layout(
            ctx,
            "penumbra depth image",
            &[
                uniform_entry(0),
                depth_array_entry(1),
                storage_entry(2, false),
                storage_entry(3, false),
                storage_entry(4, false),
                storage_texture(5, EDGE_FORMAT),
                storage_texture(6, LOWER_FORMAT),
            ],
        );
        let [geometry, seeds, limits] = compute_pipelines(
            ctx,
            "penumbra depth image",
            &m,
            &layout,
            ["geometry", "seeds", "limits"],
        );
        Self {
            layout,
            geometry,
            seeds,
            limits,
        }
    }
}

/// One combine kernel per storage format.
pub struct CombinePipelines {
    /// Parameters, geometry, edge and lower textures, the map.
    pub layouts: Vec<wgpu::BindGroupLayout>,
    /// Indexed like [`Storage::ALL`].
    pub pipelines: Vec<wgpu::ComputePipeline>,
}

/// The WGSL name of a storage texture format.
fn wgsl_format(s: Storage) -> &'static str {
    match s {
        Storage::F32 => "rgba32float",
        Storage::F16 => "rgba16float",
        Storage::Rgba8 => "rgba8unorm",
    }
}

impl CombinePipelines {
    /// Builds the pipelines.
    pub fn new(ctx: &GpuContext) -> Self {
        let (mut layouts, mut pipelines) = (Vec::new(), Vec::new());
        for s in Storage::ALL {
            let mode = CombinePipelines::index(s);
            let src = source("combine.wgsl")
                .replace(
                    "texture_storage_2d<rgba32float, write>",
                    &format!("texture_storage_2d<{}, write>", wgsl_format(s)),
                )
                .replace(
                    "const STORAGE: u32 = 0u;",
                    &format!("const STORAGE: u32 = {mode}u;"),
                );
            let m = wgsl_module(ctx, "penumbra combine", &[&src]);
            let c = wgpu::ShaderStages::COMPUTE;
            let l = layout(
                ctx,
                "penumbra combine",
                &[
                    uniform_entry(0),
                    storage_entry(1, true),
                    texture(2, c),
                    texture(3, c),
                    storage_texture(4, s.texture_format()),
                ],
            );
            let [p] = compute_pipelines(ctx, "penumbra combine", &m, &l, ["combine"]);
            layouts.push(l);
            pipelines.push(p);
        }
        Self { layouts, pipelines }
    }

    /// The index of `s`.
    pub fn index(s: Storage) -> usize {
        Storage::ALL.iter().position(|&x| x == s).unwrap_or(0)
    }
}
