//! The GPU frame's summed output: after [`FramePipeline::run`](crate::FramePipeline::run) (or
//! [`run_into`](crate::FramePipeline::run_into)) on the GPU backend, [`record_irradiance`]
//! records the shadowed irradiance summed over every light, `Σ E V`
//! ([`crate::lighting`]), over your G-buffer into one texture you own: the choice to
//! [`crate::gpu_frame::record_visibility`]'s layer per light, for a renderer that shades with
//! the sum. Its memory does not grow with the lights: each light's `V` goes to one texture the
//! world keeps, then a pass adds its `E V` into yours (a light without usable maps adds its
//! `E`). The CPU path computes the same sum for [`crate::FrameReceivers`]
//! ([`crate::lighting::shadowed_irradiance`]).
//!
//! As for the layers, nothing is read back but what a [`crate::GpuTiming`] asks for, and in a frame where no light's
//! maps were made again, over the same textures and views, it makes no buffer, texture, view or
//! bind group (the lights' records are written to buffers the world keeps, where they changed).
//! A [`crate::ShadowProbe`] probes only the layers. One encoder at a time: the records are
//! uploaded with the queue's next submission. Each light's `V` pass is timed as its evaluation,
//! as for the layers; the adding passes are not timed.

use crate::components::{LightState, ShadowConfig};
use crate::gpu_frame::{gpu_maps_only, record_light, storage_target, timed_lights};
use crate::lighting::LightRecord;
use crate::scene::LightSource;
use bevy_ecs::prelude::*;
use soft_shadow_core::Result;
use soft_shadow_core::gpu::compute::bind_group;
use soft_shadow_core::gpu::shader::{
    Group, Library, Program, ShaderModule, float_texture, read_write_texture, uniform,
};
use soft_shadow_core::gpu::{GpuContext, Kernel};

/// The crate's WGSL: `shadow_frame::lighting`, a light's `E` (no bindings: a renderer's own
/// shader may import it), and `shadow_frame::irradiance`, the pass that adds a light's `E V`.
pub static SHADERS: Library = Library {
    name: "shadow-frame",
    modules: &[
        ShaderModule {
            path: "shadow_frame::lighting",
            source: include_str!("lighting.wgsl"),
        },
        ShaderModule {
            path: "shadow_frame::irradiance",
            source: include_str!("irradiance.wgsl"),
        },
    ],
    depends: &[],
    programs: &[&IRRADIANCE],
};

/// `irradiance.wgsl`: the light, the G-buffer, the light's `V` and the sum.
static IRRADIANCE: Program = Program {
    library: &SHADERS,
    module: "shadow_frame::irradiance",
    defs: &[],
    groups: &[Group::compute(&[
        uniform::<LightRecord>(),
        float_texture(wgpu::TextureViewDimension::D2),
        float_texture(wgpu::TextureViewDimension::D2),
        float_texture(wgpu::TextureViewDimension::D2),
        read_write_texture(
            wgpu::TextureFormat::R32Float,
            wgpu::TextureViewDimension::D2,
        ),
    ])],
};

/// The pass's modes (`LightRecord::terms[2]`).
const CLEAR: f32 = 0.0;
const UNSHADOWED: f32 = 1.0;
const SHADOWED: f32 = 2.0;

/// Side of the pass's workgroups.
const WORKGROUP: u32 = 8;

/// Your G-buffer and the texture the lights' shadowed irradiance is summed into.
#[derive(Clone, Copy, Debug)]
pub struct IrradianceTextures<'a> {
    /// World positions in xyz, w > 0.5 where a surface covers the texel (as
    /// [`crate::gpu_frame::FrameTextures::positions`]).
    pub positions: &'a wgpu::TextureView,
    /// Unit normals facing the camera in xyz.
    pub normals: &'a wgpu::TextureView,
    /// `R32Float`, 2D with one layer, usable as a storage binding; its width and height are the
    /// G-buffer's. Every texel is written: `Σ E V` where a surface covers it, 0 elsewhere.
    pub irradiance: &'a wgpu::Texture,
}

/// Records into `enc` the shadowed irradiance `Σ E V` of every light (an entity with a
/// [`LightSource`] and a [`ShadowConfig`]) at every texel of `targets`'
/// G-buffer into `targets.irradiance`, and returns how many lights it summed. A light whose
/// maps are on the GPU records its `V` pass and adds `E V`; a light without usable maps (no
/// caster reaches it, it lights nothing the camera sees, the frame left it an error, or no
/// frame has run it yet) adds `E`. Submit `enc` before the next frame's run, as for
/// [`crate::gpu_frame::record_visibility`]. Record one of the two outputs in a frame, the sum
/// or the layers: each light's maps keep the bind group of one output's textures, and the
/// budget counts the texels of the last one recorded.
///
/// Checked before anything is recorded: the texture's format, usage and layers
/// ([`soft_shadow_core::ShadowError::InvalidParameter`]); maps made on the CPU backend are
/// [`soft_shadow_core::ShadowError::MapsMismatch`].
pub fn record_irradiance(
    world: &mut World,
    gpu: &GpuContext,
    enc: &mut wgpu::CommandEncoder,
    targets: &IrradianceTextures,
) -> Result<usize> {
    let texture = targets.irradiance;
    storage_target(texture, "irradiance", Some(1))?;
    gpu_maps_only(world)?;
    let size = (texture.width(), texture.height());
    // The lights in the query's order, each with its record and whether its maps are usable.
    let mut query = world.query::<(Entity, &LightSource, &ShadowConfig, Option<&LightState>)>();
    let mut records = vec![LightRecord {
        terms: [0.0, 0.0, CLEAR, 0.0],
        ..Default::default()
    }];
    let mut lights = Vec::new();
    for (entity, light, config, state) in query.iter(world) {
        let shadowed = state.is_some_and(|s| s.maps.is_some() && s.error.is_none());
        let mut record = LightRecord::of(&light.0, config);
        record.terms[2] = if shadowed { SHADOWED } else { UNSHADOWED };
        records.push(record);
        lights.push((entity, shadowed));
    }
    let mut summing = match world.remove_resource::<Summing>() {
        Some(s) if s.size == size && s.device == gpu.device => s,
        _ => Summing::new(gpu, size),
    };
    summing.bind(gpu, &records, targets);
    let recorded = timed_lights(world, enc, size, |world, enc, mut timing| {
        summing.pass(gpu, enc, 0);
        for (k, &(entity, shadowed)) in lights.iter().enumerate() {
            let state = world.get::<LightState>(entity);
            // The light's `V` (timed as its evaluation, as in the layers), then its `E V`; a
            // light without maps adds its `E`, untimed like a layer's copy of ones.
            if let Some(maps) = state.and_then(|s| s.maps.as_ref()).filter(|_| shadowed) {
                record_light(
                    gpu,
                    enc,
                    (entity, maps),
                    (targets.positions, targets.normals),
                    (&summing.scratch_view, size),
                    timing.as_deref_mut(),
                )?;
            }
            summing.pass(gpu, enc, k + 1);
        }
        Ok(lights.len())
    });
    world.insert_resource(summing);
    recorded
}

/// What the summing keeps between frames: the pass, a texture for one light's `V`, a record
/// buffer per light (the first clears) with the records they hold, and their bind groups over
/// the targets' views.
#[derive(Resource)]
struct Summing {
    device: wgpu::Device,
    size: (u32, u32),
    kernel: Kernel,
    /// One light's `V` at a time (`R32Float`, storage and sampled).
    scratch_view: wgpu::TextureView,
    buffers: Vec<wgpu::Buffer>,
    records: Vec<LightRecord>,
    /// The bind groups, made for these views (positions, normals, the sum's).
    groups: Vec<wgpu::BindGroup>,
    bound: Option<[wgpu::TextureView; 3]>,
    /// The view of the sum's texture, kept while the texture is.
    target: Option<(wgpu::Texture, wgpu::TextureView)>,
}

impl Summing {
    fn new(gpu: &GpuContext, size: (u32, u32)) -> Self {
        let scratch = gpu.device.create_texture(&wgpu::TextureDescriptor {
            label: Some("one light's visibility"),
            size: wgpu::Extent3d {
                width: size.0,
                height: size.1,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::R32Float,
            usage: wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        });
        Self {
            device: gpu.device.clone(),
            size,
            kernel: Kernel::new(gpu, &IRRADIANCE, "add_light"),
            scratch_view: scratch.create_view(&Default::default()),
            buffers: Vec::new(),
            records: Vec::new(),
            groups: Vec::new(),
            bound: None,
            target: None,
        }
    }

    /// Holds `records` in the record buffers (writing those that changed) and a bind group of
    /// each over `targets`.
    fn bind(&mut self, gpu: &GpuContext, records: &[LightRecord], targets: &IrradianceTextures) {
        if self
            .target
            .as_ref()
            .is_none_or(|(t, _)| t != targets.irradiance)
        {
            let view = targets.irradiance.create_view(&Default::default());
            self.target = Some((targets.irradiance.clone(), view));
        }
        let target = &self.target.as_ref().expect("made above").1;
        let views = [targets.positions, targets.normals, target];
        if self
            .bound
            .as_ref()
            .is_none_or(|b| !b.iter().eq(views.iter().copied()))
        {
            // Other views: every group is made again.
            self.groups.clear();
            self.bound = Some(views.map(Clone::clone));
        }
        while self.buffers.len() < records.len() {
            self.buffers
                .push(gpu.device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("light record"),
                    size: size_of::<LightRecord>() as u64,
                    usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                }));
        }
        for (k, r) in records.iter().enumerate() {
            if self.records.get(k) != Some(r) {
                gpu.queue
                    .write_buffer(&self.buffers[k], 0, bytemuck::bytes_of(r));
            }
        }
        self.records.clear();
        self.records.extend_from_slice(records);
        for k in self.groups.len()..records.len() {
            self.groups.push(bind_group(
                gpu,
                "light irradiance",
                &self.kernel.layout,
                &[
                    self.buffers[k].as_entire_binding(),
                    wgpu::BindingResource::TextureView(targets.positions),
                    wgpu::BindingResource::TextureView(targets.normals),
                    wgpu::BindingResource::TextureView(&self.scratch_view),
                    wgpu::BindingResource::TextureView(target),
                ],
            ));
        }
    }

    /// Records record `k`'s pass.
    fn pass(&self, gpu: &GpuContext, enc: &mut wgpu::CommandEncoder, k: usize) {
        let mut pass = gpu.begin_compute_pass(enc, "light irradiance");
        pass.set_pipeline(&self.kernel.pipeline);
        pass.set_bind_group(0, &self.groups[k], &[]);
        pass.dispatch_workgroups(
            self.size.0.div_ceil(WORKGROUP),
            self.size.1.div_ceil(WORKGROUP),
            1,
        );
    }
}
