//! A technique's visibility as one WGSL function, for the caller's own shaders.
//!
//! Every technique's GPU evaluation is a module (its [`VisibilityShader`]) that defines
//! `fn visibility(world_pos: vec3<f32>, normal: vec3<f32>) -> f32` over bindings in
//! `@group(#{MAPS_GROUP})` ([`super::shader::MAPS_GROUP`]), whose layout is
//! [`VisibilityPipelines::maps_layout`] and whose bind group is
//! [`crate::ShadowTechnique::maps_bind_group`]. Two shared entry points import it (as
//! `soft_shadow_core::technique`) with the receivers in `@group(1)`: a batch of points
//! (`evaluate_receivers.wgsl`, the blocking evaluation) and a G-buffer the caller owns
//! (`evaluate_texels.wgsl`, [`crate::ShadowTechnique::record_visibility`]). A renderer may
//! instead call it from its own shader: flattened to WGSL
//! ([`crate::ShadowTechnique::visibility_wgsl`]) or imported through its own naga_oil composer
//! ([`super::shader::Library::add_to`]).

use super::GpuContext;
use super::compute::{ReceiverBuffers, bind_group};
use super::program::{compose, layout, pipeline_layout, shader_module};
use super::shader::{
    self, Group, MAPS_GROUP, VisibilityShader, float_texture, storage, storage_texture,
};
use crate::error::Result;
use crate::receivers::Receivers;
use std::sync::Arc;

/// Workgroup side of `evaluate_texels` (`@workgroup_size(8, 8)`).
pub const TEXEL_WORKGROUP: u32 = 8;

/// The stages a technique's maps are visible to: compute (the evaluation entry points) and
/// fragment (a renderer's own shading).
pub const MAPS_STAGES: wgpu::ShaderStages =
    wgpu::ShaderStages::COMPUTE.union(wgpu::ShaderStages::FRAGMENT);

/// `@group(1)` of `evaluate_receivers`: positions and normals (`vec4<f32>` each), `V` out.
const RECEIVER_BUFFERS: Group = Group::compute(&[
    storage::<[f32; 4]>(true),
    storage::<[f32; 4]>(true),
    storage::<f32>(false),
]);

/// `@group(1)` of `evaluate_texels`: position and normal textures, the `R32Float` output.
const RECEIVER_TEXTURES: Group = Group::compute(&[
    float_texture(wgpu::TextureViewDimension::D2),
    float_texture(wgpu::TextureViewDimension::D2),
    storage_texture(
        wgpu::TextureFormat::R32Float,
        wgpu::TextureViewDimension::D2,
    ),
]);

/// The two evaluation entry points of a technique, as the validation test composes them: the
/// import path of each and its bind groups (the maps' first).
pub fn entry_points(technique: &VisibilityShader) -> [(&'static str, [Group; 2]); 2] {
    let maps = Group {
        stages: MAPS_STAGES,
        ..technique.maps
    };
    [
        (
            "soft_shadow_core::evaluate_receivers",
            [maps, RECEIVER_BUFFERS],
        ),
        (
            "soft_shadow_core::evaluate_texels",
            [maps, RECEIVER_TEXTURES],
        ),
    ]
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

/// One technique's bind group layout and its two evaluation pipelines, built once per device.
pub struct VisibilityPipelines {
    /// Layout of the technique's own bindings (its maps' group), visible to compute and
    /// fragment shaders ([`MAPS_STAGES`]).
    pub maps_layout: wgpu::BindGroupLayout,
    buffers_layout: wgpu::BindGroupLayout,
    texels_layout: wgpu::BindGroupLayout,
    buffers: wgpu::ComputePipeline,
    texels: wgpu::ComputePipeline,
}

/// The evaluation pipelines of `technique` on this device (built on first use, then cached).
pub fn pipelines(
    ctx: &GpuContext,
    technique: &'static VisibilityShader,
) -> Arc<VisibilityPipelines> {
    #[derive(Default)]
    struct Cache(std::sync::Mutex<std::collections::HashMap<usize, Arc<VisibilityPipelines>>>);
    let cache = ctx.cached(|_| Cache::default());
    let key = technique as *const VisibilityShader as usize;
    if let Some(p) = cache.0.lock().unwrap_or_else(|e| e.into_inner()).get(&key) {
        return p.clone();
    }
    let built = Arc::new(build_pipelines(ctx, technique));
    cache
        .0
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .insert(key, built.clone());
    built
}

fn build_pipelines(ctx: &GpuContext, technique: &'static VisibilityShader) -> VisibilityPipelines {
    let label = technique.module;
    let maps_layout = layout(ctx, label, &technique.maps, MAPS_STAGES);
    // One entry point over the maps' layout (shared by both) and its receivers' group.
    let entry = |path: &str, entry: &str, receivers: &Group| {
        let module = compose(
            ctx,
            &shader::SHADERS,
            path,
            &[(MAPS_GROUP, 0)],
            Some(technique),
        );
        let receivers_layout = layout(ctx, path, receivers, receivers.stages);
        let pl = pipeline_layout(ctx, label, &[&maps_layout, &receivers_layout]);
        let module = shader_module(ctx, label, module);
        let pipeline = ctx
            .device
            .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(entry),
                layout: Some(&pl),
                module: &module,
                entry_point: Some(entry),
                compilation_options: Default::default(),
                cache: None,
            });
        (receivers_layout, pipeline)
    };
    let [(receivers, [_, buffer_group]), (texels, [_, texel_group])] = entry_points(technique);
    let (buffers_layout, buffers) = entry(receivers, "evaluate_receivers", &buffer_group);
    let (texels_layout, texels) = entry(texels, "evaluate_texels", &texel_group);
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
