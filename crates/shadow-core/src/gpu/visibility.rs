//! A technique's visibility as one WGSL function, for the caller's own shaders.
//!
//! Every technique's GPU evaluation is a module (its [`VisibilityShader`]) that defines
//! `fn visibility(world_pos: vec3<f32>, normal: vec3<f32>) -> f32` over bindings in
//! `@group(#{MAPS_GROUP})` ([`super::shader::MAPS_GROUP`]), whose layout is
//! [`VisibilityPipelines::maps_layout`] and whose bind group is
//! [`crate::ShadowTechnique::maps_bind_group`]. Two shared entry points import it (as
//! `soft_shadow_core::technique`) with the receivers in `@group(1)` and how a receiver picks the
//! light's view in `@group(2)` (`views.wgsl`; one dispatch per view, each adding the share of
//! the receivers it holds): a batch of points (`evaluate_receivers.wgsl`, the blocking
//! evaluation) and a G-buffer the caller owns (`evaluate_texels.wgsl`,
//! [`crate::ShadowTechnique::record_visibility`]). A renderer may
//! instead call it from its own shader: flattened to WGSL
//! ([`crate::ShadowTechnique::visibility_wgsl`]) or imported through its own naga_oil composer
//! ([`super::shader::Library::add_to`]).

use super::GpuContext;
use super::compute::{ReceiverBuffers, bind_group};
use super::program::{compose, layout, pipeline_layout, shader_module};
use super::shader::{
    self, Group, MAPS_GROUP, VisibilityShader, float_texture, read_write_texture, storage, uniform,
};
use crate::error::Result;
use crate::receivers::Receivers;
use crate::views::{LightViews, ViewSelect};
use std::sync::{Arc, Mutex};

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

/// `@group(1)` of `evaluate_texels`: position and normal textures, the `R32Float` output
/// (read-write: every view after the first adds its share).
const RECEIVER_TEXTURES: Group = Group::compute(&[
    float_texture(wgpu::TextureViewDimension::D2),
    float_texture(wgpu::TextureViewDimension::D2),
    read_write_texture(
        wgpu::TextureFormat::R32Float,
        wgpu::TextureViewDimension::D2,
    ),
]);

/// `@group(2)` of both entry points: how a receiver picks its view, and the view of the pass.
const VIEW_SELECT: Group = Group::compute(&[uniform::<ViewSelect>()]);

/// The two evaluation entry points of a technique, as the validation test composes them: the
/// import path of each and its bind groups (the maps', the receivers', the view selection).
pub fn entry_points(technique: &VisibilityShader) -> [(&'static str, [Group; 3]); 2] {
    let maps = Group {
        stages: MAPS_STAGES,
        ..technique.maps
    };
    [
        (
            "soft_shadow_core::evaluate_receivers",
            [maps, RECEIVER_BUFFERS, VIEW_SELECT],
        ),
        (
            "soft_shadow_core::evaluate_texels",
            [maps, RECEIVER_TEXTURES, VIEW_SELECT],
        ),
    ]
}

/// The bind groups of a light's maps, per view: the technique's maps (what a renderer's own
/// shader binds to call `visibility()`) and the view's selection (what the evaluation passes
/// read to add each receiver's share). Made by [`crate::ShadowTechnique::maps_bind_group`].
///
/// Keep it while the maps serve: it also keeps the bind group of the last receiver textures
/// [`crate::ShadowTechnique::record_visibility`] recorded over (and so those views alive until
/// other views replace them), so a renderer that records over the same G-buffer every frame
/// makes no bind group, buffer or view after the first.
pub struct MapsBinding {
    views: Vec<(wgpu::BindGroup, wgpu::BindGroup)>,
    receivers: Mutex<Option<ReceiverGroup>>,
}

/// A receiver textures' bind group with the views it binds (positions, normals, visibility).
type ReceiverGroup = ([wgpu::TextureView; 3], wgpu::BindGroup);

impl MapsBinding {
    /// The maps' bind group of view `index`, laid out as the technique's
    /// [`VisibilityPipelines::maps_layout`].
    pub fn maps(&self, index: usize) -> Option<&wgpu::BindGroup> {
        self.views.get(index).map(|(m, _)| m)
    }

    /// How many views.
    pub fn len(&self) -> usize {
        self.views.len()
    }

    /// Whether it binds no view (never: maps have at least one).
    pub fn is_empty(&self) -> bool {
        self.views.is_empty()
    }
}

/// The binding of `views` with the maps' bind group of each view, in order.
pub(crate) fn binding(
    ctx: &GpuContext,
    p: &VisibilityPipelines,
    views: &LightViews,
    maps: Vec<wgpu::BindGroup>,
) -> MapsBinding {
    MapsBinding {
        views: maps
            .into_iter()
            .enumerate()
            .map(|(i, m)| {
                let select = views.gpu_select(i as u32);
                let u = ctx.uniform_buffer("view select", bytemuck::bytes_of(&select));
                let g = bind_group(
                    ctx,
                    "view select",
                    &p.select_layout,
                    &[u.as_entire_binding()],
                );
                (m, g)
            })
            .collect(),
        receivers: Mutex::new(None),
    }
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
    select_layout: wgpu::BindGroupLayout,
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
    let select_layout = layout(ctx, "view select", &VIEW_SELECT, VIEW_SELECT.stages);
    // One entry point over the maps' layout (shared by both), its receivers' group and the
    // view selection.
    let entry = |path: &str, entry: &str, receivers: &Group| {
        let module = compose(
            ctx,
            &shader::SHADERS,
            path,
            &[(MAPS_GROUP, 0)],
            Some(technique),
        );
        let receivers_layout = layout(ctx, path, receivers, receivers.stages);
        let pl = pipeline_layout(
            ctx,
            label,
            &[&maps_layout, &receivers_layout, &select_layout],
        );
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
    let [
        (receivers, [_, buffer_group, _]),
        (texels, [_, texel_group, _]),
    ] = entry_points(technique);
    let (buffers_layout, buffers) = entry(receivers, "evaluate_receivers", &buffer_group);
    let (texels_layout, texels) = entry(texels, "evaluate_texels", &texel_group);
    VisibilityPipelines {
        maps_layout,
        select_layout,
        buffers_layout,
        texels_layout,
        buffers,
        texels,
    }
}

/// The blocking evaluation: uploads `r`, runs `evaluate_receivers` once per view of `binding`
/// and reads `V` back.
pub(crate) fn evaluate_buffers(
    ctx: &GpuContext,
    p: &VisibilityPipelines,
    binding: &MapsBinding,
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
        pass.set_bind_group(1, &recv, &[]);
        for (maps, select) in &binding.views {
            pass.set_bind_group(0, maps, &[]);
            pass.set_bind_group(2, select, &[]);
            pass.dispatch_workgroups(rb.groups, 1, 1);
        }
    }
    ctx.queue.submit([enc.finish()]);
    let bytes = ctx.read_buffer(&rb.visibility, rb.count as u64 * 4)?;
    Ok(bytemuck::pod_collect_to_vec(&bytes))
}

/// Records `evaluate_texels` over `target`, once per view of `binding`.
pub(crate) fn record_texels(
    ctx: &GpuContext,
    p: &VisibilityPipelines,
    enc: &mut wgpu::CommandEncoder,
    binding: &MapsBinding,
    target: &ReceiverTextures,
) {
    let views = [target.positions, target.normals, target.visibility];
    let recv = {
        let mut last = binding.receivers.lock().unwrap_or_else(|e| e.into_inner());
        match last.as_ref() {
            Some((bound, group)) if bound.iter().eq(views) => group.clone(),
            _ => {
                let group = bind_group(
                    ctx,
                    "receiver textures",
                    &p.texels_layout,
                    &[
                        wgpu::BindingResource::TextureView(target.positions),
                        wgpu::BindingResource::TextureView(target.normals),
                        wgpu::BindingResource::TextureView(target.visibility),
                    ],
                );
                *last = Some((views.map(Clone::clone), group.clone()));
                group
            }
        }
    };
    let mut pass = ctx.begin_compute_pass(enc, "evaluate texels");
    pass.set_pipeline(&p.texels);
    pass.set_bind_group(1, &recv, &[]);
    for (maps, select) in &binding.views {
        pass.set_bind_group(0, maps, &[]);
        pass.set_bind_group(2, select, &[]);
        pass.dispatch_workgroups(
            target.size.0.div_ceil(TEXEL_WORKGROUP),
            target.size.1.div_ceil(TEXEL_WORKGROUP),
            1,
        );
    }
}
