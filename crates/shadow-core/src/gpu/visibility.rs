//! A technique's visibility as one WGSL function, for the caller's own shaders.
//!
//! Every technique's GPU evaluation is a module that defines
//! `fn visibility(world_pos: vec3<f32>, normal: vec3<f32>) -> f32` over bindings in
//! `@group(0)` ([`crate::ShadowTechnique::visibility_wgsl`]), whose layout is
//! [`VisibilityPipelines::maps_layout`] and whose bind group is
//! [`crate::ShadowTechnique::maps_bind_group`]. Two shared entry points call it with the
//! receivers in `@group(1)`: a batch of points ([`RECEIVERS_WGSL`], the blocking evaluation) and
//! a G-buffer the caller owns ([`RECEIVER_TEXTURES_WGSL`],
//! [`crate::ShadowTechnique::record_visibility`]). A renderer may instead include the module in
//! its own fragment or compute shader ([`in_group`] moves its bindings to a free group).

use super::GpuContext;
use super::compute::{ReceiverBuffers, bind_group, storage_entry};
use super::resources::{
    FLOAT, compute_pipeline, layout, pipeline_layout, storage_texture_entry, texture_entry,
    wgsl_module,
};
use crate::error::Result;
use crate::receivers::Receivers;
use std::marker::PhantomData;
use std::sync::Arc;

/// The batch entry point `evaluate_receivers`: positions and normals (`array<vec4<f32>>`) in,
/// `array<f32>` out, at `@group(1)` bindings 0, 1, 2.
pub const RECEIVERS_WGSL: &str = include_str!("receivers.wgsl");

/// The G-buffer entry point `evaluate_texels`: position (xyz, w > 0.5 where covered) and
/// normal textures in, an `r32float` storage texture out, at `@group(1)` bindings 0, 1, 2.
pub const RECEIVER_TEXTURES_WGSL: &str = include_str!("receiver_textures.wgsl");

/// Workgroup side of `evaluate_texels` (`@workgroup_size(8, 8)`).
pub const TEXEL_WORKGROUP: u32 = 8;

/// `wgsl` (a technique's [`visibility_wgsl`](crate::ShadowTechnique::visibility_wgsl)) with
/// its bindings moved from `@group(0)` to `@group(group)`, for a shader whose group 0 is taken.
pub fn in_group(wgsl: &str, group: u32) -> String {
    wgsl.replace("@group(0)", &format!("@group({group})"))
}

/// Where [`crate::ShadowTechnique::record_visibility`] reads receivers and writes `V`: views of
/// textures the caller owns, all `size` texels.
pub struct ReceiverTextures<'a> {
    /// World position in xyz, w > 0.5 where a surface covers the texel (`Rgba32Float` or
    /// another float format, bound as a non-filterable `texture_2d<f32>`).
    pub positions: &'a wgpu::TextureView,
    /// Unit world normal facing the camera in xyz (same binding type).
    pub normals: &'a wgpu::TextureView,
    /// `R32Float` with `STORAGE_BINDING`: `V` per texel, 1 where nothing is covered.
    pub visibility: &'a wgpu::TextureView,
    /// Width and height in texels.
    pub size: (u32, u32),
}

/// One technique type's bind group layout and its two evaluation pipelines, built once per
/// device.
pub struct VisibilityPipelines {
    /// Layout of the technique's own bindings (`@group(0)` of its module), visible to compute
    /// and fragment shaders.
    pub maps_layout: wgpu::BindGroupLayout,
    buffers_layout: wgpu::BindGroupLayout,
    texels_layout: wgpu::BindGroupLayout,
    buffers: wgpu::ComputePipeline,
    texels: wgpu::ComputePipeline,
}

struct Cached<K>(Arc<VisibilityPipelines>, PhantomData<fn() -> K>);

/// The pipelines of the technique type `K` on this device (built on first use from its
/// visibility module `wgsl` and its maps' layout `entries`, then cached).
pub fn pipelines<K: 'static>(
    ctx: &GpuContext,
    name: &str,
    wgsl: impl FnOnce() -> String,
    entries: impl FnOnce() -> Vec<wgpu::BindGroupLayoutEntry>,
) -> Arc<VisibilityPipelines> {
    ctx.cached(|c| Cached::<K>(Arc::new(build(c, name, wgsl(), entries())), PhantomData))
        .0
        .clone()
}

fn build(
    ctx: &GpuContext,
    name: &str,
    source: String,
    entries: Vec<wgpu::BindGroupLayoutEntry>,
) -> VisibilityPipelines {
    let stages = wgpu::ShaderStages::COMPUTE | wgpu::ShaderStages::FRAGMENT;
    let entries: Vec<wgpu::BindGroupLayoutEntry> = entries
        .into_iter()
        .map(|e| wgpu::BindGroupLayoutEntry {
            visibility: stages,
            ..e
        })
        .collect();
    let maps_layout = layout(ctx, name, &entries);
    let c = wgpu::ShaderStages::COMPUTE;
    let buffers_layout = layout(
        ctx,
        "receivers",
        &[
            storage_entry(0, true),
            storage_entry(1, true),
            storage_entry(2, false),
        ],
    );
    let texels_layout = layout(
        ctx,
        "receiver textures",
        &[
            texture_entry(0, c, FLOAT, wgpu::TextureViewDimension::D2),
            texture_entry(1, c, FLOAT, wgpu::TextureViewDimension::D2),
            storage_texture_entry(
                2,
                wgpu::TextureFormat::R32Float,
                wgpu::TextureViewDimension::D2,
            ),
        ],
    );
    let pipeline = |tail: &str, entry: &str, receivers: &wgpu::BindGroupLayout| {
        let module = wgsl_module(ctx, name, &[&source, tail]);
        let pl = pipeline_layout(ctx, name, &[&maps_layout, receivers]);
        compute_pipeline(ctx, &module, &pl, entry)
    };
    let buffers = pipeline(RECEIVERS_WGSL, "evaluate_receivers", &buffers_layout);
    let texels = pipeline(RECEIVER_TEXTURES_WGSL, "evaluate_texels", &texels_layout);
    VisibilityPipelines {
        maps_layout,
        buffers_layout,
        texels_layout,
        buffers,
        texels,
    }
}

/// The blocking evaluation: uploads `r`, runs `evaluate_receivers` with the maps bound by
/// `maps_bind` and reads `V` back.
pub(crate) fn evaluate_buffers(
    ctx: &GpuContext,
    p: &VisibilityPipelines,
    maps_bind: &wgpu::BindGroup,
    r: &Receivers,
) -> Result<Vec<f32>> {
    let Some(rb) = ReceiverBuffers::new(ctx, r)? else {
        return Ok(Vec::new());
    };
    let recv = bind_group(
        ctx,
        "receivers",
        &p.buffers_layout,
        &[
            rb.positions.as_entire_binding(),
            rb.normals.as_entire_binding(),
            rb.visibility.as_entire_binding(),
        ],
    );
    let mut enc = ctx.device.create_command_encoder(&Default::default());
    {
        let mut pass = ctx.begin_compute_pass(&mut enc, "evaluate");
        pass.set_pipeline(&p.buffers);
        pass.set_bind_group(0, maps_bind, &[]);
        pass.set_bind_group(1, &recv, &[]);
        pass.dispatch_workgroups(rb.groups, 1, 1);
    }
    ctx.queue.submit([enc.finish()]);
    let bytes = ctx.read_buffer(&rb.visibility, rb.count as u64 * 4)?;
    Ok(bytemuck::pod_collect_to_vec(&bytes))
}

/// Records `evaluate_texels` over `target` with the maps bound by `maps_bind`.
pub(crate) fn record_texels(
    ctx: &GpuContext,
    p: &VisibilityPipelines,
    enc: &mut wgpu::CommandEncoder,
    maps_bind: &wgpu::BindGroup,
    target: &ReceiverTextures,
) {
    let recv = bind_group(
        ctx,
        "receiver textures",
        &p.texels_layout,
        &[
            wgpu::BindingResource::TextureView(target.positions),
            wgpu::BindingResource::TextureView(target.normals),
            wgpu::BindingResource::TextureView(target.visibility),
        ],
    );
    let mut pass = ctx.begin_compute_pass(enc, "evaluate texels");
    pass.set_pipeline(&p.texels);
    pass.set_bind_group(0, maps_bind, &[]);
    pass.set_bind_group(1, &recv, &[]);
    pass.dispatch_workgroups(
        target.size.0.div_ceil(TEXEL_WORKGROUP),
        target.size.1.div_ceil(TEXEL_WORKGROUP),
        1,
    );
}
