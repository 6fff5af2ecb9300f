//! Resources every GPU path makes: scratch buffers and 2D (array) textures from the context's
//! pool. Pipelines and their layouts come from [`super::shader`] declarations
//! ([`super::program`]).

use super::GpuContext;

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
