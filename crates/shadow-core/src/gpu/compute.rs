//! Helpers every technique's compute passes share: bind groups in binding order, depth-array
//! views, one-pass dispatches, and the receiver batch of an evaluation pass.

use super::GpuContext;
use crate::error::{Result, ShadowError};
use crate::receivers::Receivers;

/// Receivers per workgroup of the evaluation shaders (`@workgroup_size(64)`).
pub const EVAL_WORKGROUP: u32 = 64;

/// A view of every layer of a depth texture array, for a [`super::shader::DEPTH_ARRAY`] binding.
pub fn depth_array_view(texture: &wgpu::Texture) -> wgpu::TextureView {
    texture.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::D2Array),
        aspect: wgpu::TextureAspect::DepthOnly,
        ..Default::default()
    })
}

/// A bind group of `buffers`/resources in binding order 0, 1, 2, ...
pub fn bind_group(
    ctx: &GpuContext,
    label: &str,
    layout: &wgpu::BindGroupLayout,
    resources: &[wgpu::BindingResource<'_>],
) -> wgpu::BindGroup {
    let entries: Vec<wgpu::BindGroupEntry<'_>> = resources
        .iter()
        .enumerate()
        .map(|(i, r)| wgpu::BindGroupEntry {
            binding: i as u32,
            resource: r.clone(),
        })
        .collect();
    ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some(label),
        layout,
        entries: &entries,
    })
}

/// The receivers of one evaluation pass on the GPU: positions and normals as `vec4<f32>`
/// storage buffers, and the output visibility buffer.
pub struct ReceiverBuffers {
    /// Number of receivers.
    pub count: u32,
    /// Workgroups of [`EVAL_WORKGROUP`] to dispatch.
    pub groups: u32,
    /// `array<vec4<f32>>` positions (w = 1).
    pub positions: wgpu::Buffer,
    /// `array<vec4<f32>>` normals (w = 0).
    pub normals: wgpu::Buffer,
    /// `array<f32>` visibilities written by the shader.
    pub visibility: wgpu::Buffer,
}

impl ReceiverBuffers {
    /// Uploads `r`; `None` for an empty batch. Errors when the batch exceeds one dispatch or
    /// the device's storage binding size.
    pub fn new(ctx: &GpuContext, r: &Receivers) -> Result<Option<Self>> {
        let n = r.positions.len() as u32;
        if n == 0 {
            return Ok(None);
        }
        let groups = n.div_ceil(EVAL_WORKGROUP);
        let max_groups = ctx.device.limits().max_compute_workgroups_per_dimension;
        if groups > max_groups {
            return Err(ShadowError::InvalidReceivers(format!(
                "{n} receivers exceed one dispatch ({} at most)",
                max_groups as u64 * EVAL_WORKGROUP as u64
            )));
        }
        let limit = ctx.device.limits().max_storage_buffer_binding_size;
        if n as u64 * 16 > limit {
            return Err(ShadowError::InvalidReceivers(format!(
                "{n} receivers need {} bytes, above the device's {limit}-byte storage binding",
                n as u64 * 16
            )));
        }
        let pos: Vec<[f32; 4]> = r
            .positions
            .iter()
            .map(|p| p.extend(1.0).to_array())
            .collect();
        let nrm: Vec<[f32; 4]> = r.normals.iter().map(|p| p.extend(0.0).to_array()).collect();
        Ok(Some(Self {
            count: n,
            groups,
            positions: ctx.storage_buffer("receiver positions", bytemuck::cast_slice(&pos)),
            normals: ctx.storage_buffer("receiver normals", bytemuck::cast_slice(&nrm)),
            visibility: ctx.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("visibility"),
                size: n as u64 * 4,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            }),
        }))
    }
}

/// Records one compute pass (timed under [`GpuContext::gpu_time`] and
/// [`GpuContext::time_passes_into`]) that dispatches `groups`
/// workgroups of `pipeline` with `bind` at group 0.
pub fn dispatch(
    ctx: &GpuContext,
    enc: &mut wgpu::CommandEncoder,
    label: &str,
    pipeline: &wgpu::ComputePipeline,
    bind: &wgpu::BindGroup,
    groups: (u32, u32, u32),
) {
    let mut pass = ctx.begin_compute_pass(enc, label);
    pass.set_pipeline(pipeline);
    pass.set_bind_group(0, bind, &[]);
    pass.dispatch_workgroups(groups.0, groups.1, groups.2);
}
