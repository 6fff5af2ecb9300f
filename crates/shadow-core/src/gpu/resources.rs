//! The one vocabulary every GPU path declares its pipelines in: shader modules assembled from
//! WGSL parts ([`super::wgsl::resolve`]), bind group layouts ([`layout`] of the entries here and
//! in [`super::compute`]), pipeline layouts ([`pipeline_layout`]), compute pipelines
//! ([`compute_pipeline`], [`super::compute::compute_pipelines`], [`Kernel`]) and 2D (array)
//! textures. Render pipelines are wgpu descriptors over a [`pipeline_layout`].

use super::GpuContext;
use super::compute::compute_pipelines;

/// Non-filterable float textures (read with `textureLoad`).
pub const FLOAT: wgpu::TextureSampleType = wgpu::TextureSampleType::Float { filterable: false };

/// A shader module whose source is `parts` joined in order (shared WGSL first, then the file
/// that `// requires:` them).
pub fn wgsl_module(ctx: &GpuContext, label: &str, parts: &[&str]) -> wgpu::ShaderModule {
    ctx.device
        .create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some(label),
            source: wgpu::ShaderSource::Wgsl(parts.join("\n").into()),
        })
}

/// A bind group layout of `entries`.
pub fn layout(
    ctx: &GpuContext,
    label: &str,
    entries: &[wgpu::BindGroupLayoutEntry],
) -> wgpu::BindGroupLayout {
    ctx.device
        .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some(label),
            entries,
        })
}

/// A pipeline layout of `groups`, bind group 0 first.
pub fn pipeline_layout(
    ctx: &GpuContext,
    label: &str,
    groups: &[&wgpu::BindGroupLayout],
) -> wgpu::PipelineLayout {
    let groups: Vec<Option<&wgpu::BindGroupLayout>> = groups.iter().copied().map(Some).collect();
    ctx.device
        .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some(label),
            bind_group_layouts: &groups,
            immediate_size: 0,
        })
}

/// The compute pipeline of entry point `entry` of `module` with layout `pl`.
pub fn compute_pipeline(
    ctx: &GpuContext,
    module: &wgpu::ShaderModule,
    pl: &wgpu::PipelineLayout,
    entry: &str,
) -> wgpu::ComputePipeline {
    ctx.device
        .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some(entry),
            layout: Some(pl),
            module,
            entry_point: Some(entry),
            compilation_options: Default::default(),
            cache: None,
        })
}

/// A sampled-texture entry.
pub fn texture_entry(
    binding: u32,
    visibility: wgpu::ShaderStages,
    sample_type: wgpu::TextureSampleType,
    view_dimension: wgpu::TextureViewDimension,
) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility,
        ty: wgpu::BindingType::Texture {
            sample_type,
            view_dimension,
            multisampled: false,
        },
        count: None,
    }
}

/// A write-only storage-texture entry visible to compute.
pub fn storage_texture_entry(
    binding: u32,
    format: wgpu::TextureFormat,
    view_dimension: wgpu::TextureViewDimension,
) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::StorageTexture {
            access: wgpu::StorageTextureAccess::WriteOnly,
            format,
            view_dimension,
        },
        count: None,
    }
}

/// A `STORAGE | COPY_SRC` buffer of `bytes` (at least 4), from the context's pool
/// ([`GpuContext::buffer`]): its contents are undefined until written.
pub fn storage_buffer(ctx: &GpuContext, label: &str, bytes: u64) -> wgpu::Buffer {
    ctx.buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: bytes.max(4),
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    })
}

/// A square 2D texture of side `size` with `layers` array layers and `mips` mip levels, from the
/// context's pool ([`GpuContext::texture`]).
pub fn texture_2d(
    ctx: &GpuContext,
    label: &str,
    size: u32,
    (layers, mips): (u32, u32),
    format: wgpu::TextureFormat,
    usage: wgpu::TextureUsages,
) -> wgpu::Texture {
    ctx.texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width: size,
            height: size,
            depth_or_array_layers: layers,
        },
        mip_level_count: mips,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage,
        view_formats: &[],
    })
}

/// One compute kernel with its own bind group layout.
pub struct Kernel {
    /// Its bind group layout.
    pub layout: wgpu::BindGroupLayout,
    /// The pipeline.
    pub pipeline: wgpu::ComputePipeline,
}

impl Kernel {
    /// Entry point `entry` of the module built from `parts`, with a layout of `entries`.
    pub fn new(
        ctx: &GpuContext,
        label: &str,
        parts: &[&str],
        entry: &str,
        entries: &[wgpu::BindGroupLayoutEntry],
    ) -> Self {
        let m = wgsl_module(ctx, label, parts);
        let layout = layout(ctx, label, entries);
        let [pipeline] = compute_pipelines(ctx, label, &m, &layout, [entry]);
        Self { layout, pipeline }
    }
}
