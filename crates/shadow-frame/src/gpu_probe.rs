//! The GPU frame's missing shadows, measured as the CPU frame measures them.
//!
//! The shared budget weighs a light's missing shadow by what its own `V` says it would miss
//! ([`crate::budget::missing_shadow_255`]); a GPU frame that reads nothing back has no `V` to
//! read, so every light counts [`crate::budget::NO_SHADOW_255`]. With a [`ShadowProbe`] in the
//! world, [`crate::gpu_frame::record_visibility`] also records every light's `V` at the frame's
//! sampled receivers (every `k`-th, at most [`crate::RECEIVER_SAMPLES`], the ones the estimate
//! reads) into a small texture of its own and copies it into a buffer; after you submit,
//! [`crate::gpu_frame::submitted`] asks for it back, and a later [`crate::FramePipeline::run`] hands
//! it to the budget ([`ProbedVisibility`]) while the frame's receivers are still those it was
//! recorded for.
//!
//! The cost: one more `V` pass per light over at most 4096 texels, a copy of 16 KiB per light,
//! and one buffer mapped per frame. Nothing waits: a frame whose probe is still on its way
//! when every one of [`PROBE_FRAMES`] slots is taken goes unprobed.

use crate::budget::fingerprint;
use crate::components::{FrameReceivers, LightState, ProbedVisibility, VisibilityLayer};
use bevy_ecs::prelude::*;
use soft_shadow_core::gpu::resources::texture_2d;
use soft_shadow_core::gpu::visibility::ReceiverTextures;
use soft_shadow_core::{GpuContext, Result};
use std::collections::HashMap;
use std::sync::Arc;
use std::sync::atomic::{AtomicU8, Ordering};

/// A probe texture's texels, row by row.
type Texels = Vec<[f32; 4]>;

/// Frames whose probes can be on their way back at once.
pub const PROBE_FRAMES: usize = 3;

/// Side of the probe's square textures: [`crate::RECEIVER_SAMPLES`] texels.
const _: () = assert!((SIDE * SIDE) as usize == crate::RECEIVER_SAMPLES);
const SIDE: u32 = 64;

/// Bytes of one light's layer in the readback buffer (rows of 256 bytes, as copies want them).
const LAYER_BYTES: u64 = (SIDE * SIDE * 4) as u64;

/// Measures the GPU frame's lights' missing shadows (see the module docs): insert one into the
/// world to turn it on, and call [`crate::gpu_frame::submitted`] after each submission of an encoder
/// [`crate::gpu_frame::record_visibility`] recorded into. One encoder at a time: the sampled
/// receivers are uploaded with the queue's next submission, and an encoder recorded into but
/// never submitted leaves its slot holding no probe of this frame (it is read all the same).
#[derive(Resource, Default)]
pub struct ShadowProbe {
    /// The sampled receivers' textures and the probe's `V`, made for a device and a layer count.
    textures: Option<Textures>,
    /// The sampled receivers the textures hold, positions and normals.
    uploaded: Option<(Texels, Texels)>,
    slots: Vec<Slot>,
    /// The frame each light last made its maps in: a probe recorded before holds another
    /// shadow.
    made: HashMap<Entity, u64>,
}

struct Textures {
    device: wgpu::Device,
    positions: wgpu::Texture,
    normals: wgpu::Texture,
    visibility: wgpu::Texture,
}

#[derive(Default)]
enum SlotState {
    #[default]
    Free,
    /// Copied into an encoder not yet reported submitted.
    Recorded,
    /// Its readback asked for: 0 on the way, 1 mapped, 2 failed.
    Mapping(Arc<AtomicU8>),
}

struct Slot {
    buffer: wgpu::Buffer,
    state: SlotState,
    /// The frame's receivers (hash, count) and the sampled ones' indices' step.
    receivers: (u64, usize, usize),
    /// The lights recorded and their layers.
    lights: Vec<(Entity, u32)>,
    /// The order the probes were recorded in.
    order: u64,
    /// The frame it was recorded in ([`crate::FrameStats::frame`]).
    frame: u64,
}

impl ShadowProbe {
    /// The probe's half of [`crate::gpu_frame::submitted`], which calls it with the timing's.
    #[deprecated(
        note = "call `gpu_frame::submitted(world)`, which asks back the probe's `V` and the \
                timestamps together"
    )]
    pub fn submitted(&mut self) {
        self.ask_back();
    }

    /// After a submission of an encoder `record_visibility` recorded into: asks for the oldest
    /// recorded probe back.
    pub(crate) fn ask_back(&mut self) {
        let oldest = self
            .slots
            .iter_mut()
            .filter(|s| matches!(s.state, SlotState::Recorded))
            .min_by_key(|s| s.order);
        if let Some(slot) = oldest {
            let all = 0..slot.buffer.size();
            slot.state = SlotState::Mapping(crate::gpu_timing::map_read(&slot.buffer, all));
        }
    }

    /// The probe textures for `layers` layers on `gpu`'s device, made again where they differ.
    fn textures(&mut self, gpu: &GpuContext, layers: u32) -> &Textures {
        let fits = self.textures.as_ref().is_some_and(|t| {
            t.device == gpu.device && t.visibility.depth_or_array_layers() == layers
        });
        if !fits {
            let texture = |label: &str, format, usage, layers| {
                texture_2d(gpu, label, SIDE, (layers, 1), format, usage)
            };
            let input = wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST;
            let f = wgpu::TextureFormat::Rgba32Float;
            self.textures = Some(Textures {
                device: gpu.device.clone(),
                positions: texture("probe positions", f, input, 1),
                normals: texture("probe normals", f, input, 1),
                visibility: texture(
                    "probe visibility",
                    wgpu::TextureFormat::R32Float,
                    wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::COPY_SRC,
                    layers,
                ),
            });
            self.uploaded = None;
            self.slots.clear();
        }
        self.textures.as_ref().expect("made above")
    }

    /// Records every light's `V` at the frame's sampled receivers into `enc` and its copy into
    /// a free slot (none free: this frame goes unprobed). `layers`: the visibility texture's.
    pub(crate) fn record(
        &mut self,
        world: &mut World,
        gpu: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        layers: u32,
    ) -> Result<()> {
        let Some(frame) = world.get_resource::<FrameReceivers>() else {
            return Ok(());
        };
        let n = frame.positions.len().min(frame.normals.len());
        if n == 0 {
            return Ok(());
        }
        let step = FrameReceivers::sample_step(n);
        let hash = fingerprint(frame);
        let frame_number = world
            .get_resource::<crate::FrameStats>()
            .map_or(0, |s| s.frame);
        let texels = |v: &[glam::Vec3], w: f32| -> Vec<[f32; 4]> {
            let mut t: Vec<[f32; 4]> = (0..n)
                .step_by(step)
                .map(|i| v[i].extend(w).into())
                .collect();
            t.resize((SIDE * SIDE) as usize, [0.0; 4]);
            t
        };
        let (positions, normals) = (texels(&frame.positions, 1.0), texels(&frame.normals, 0.0));
        self.textures(gpu, layers);
        if self.slots.len() < PROBE_FRAMES {
            self.slots.push(Slot {
                buffer: gpu.device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("probe readback"),
                    size: LAYER_BYTES * u64::from(layers.max(1)),
                    usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                }),
                state: SlotState::Free,
                receivers: (0, 0, 1),
                lights: Vec::new(),
                order: 0,
                frame: 0,
            });
        }
        let order = self.slots.iter().map(|s| s.order).max().unwrap_or(0) + 1;
        let Some(slot) = self
            .slots
            .iter()
            .position(|s| matches!(s.state, SlotState::Free))
        else {
            return Ok(());
        };
        let t = self.textures.as_ref().expect("made above");
        let sampled = (positions, normals);
        if self.uploaded.as_ref() != Some(&sampled) {
            for (texture, data) in [(&t.positions, &sampled.0), (&t.normals, &sampled.1)] {
                gpu.queue.write_texture(
                    texture.as_image_copy(),
                    bytemuck::cast_slice(data),
                    wgpu::TexelCopyBufferLayout {
                        offset: 0,
                        bytes_per_row: Some(SIDE * 16),
                        rows_per_image: Some(SIDE),
                    },
                    texture.size(),
                );
            }
            self.uploaded = Some(sampled);
        }
        let (pv, nv) = (
            t.positions.create_view(&Default::default()),
            t.normals.create_view(&Default::default()),
        );
        let mut lights = Vec::new();
        let mut query = world.query::<(Entity, &VisibilityLayer, &LightState)>();
        for (light, layer, state) in query.iter(world) {
            let Some(maps) = state.maps.as_ref().filter(|_| state.error.is_none()) else {
                continue;
            };
            let view = t.visibility.create_view(&wgpu::TextureViewDescriptor {
                label: Some("probe layer"),
                dimension: Some(wgpu::TextureViewDimension::D2),
                base_array_layer: layer.0,
                array_layer_count: Some(1),
                mip_level_count: Some(1),
                ..Default::default()
            });
            maps.record_visibility(
                gpu,
                enc,
                &ReceiverTextures {
                    positions: &pv,
                    normals: &nv,
                    visibility: &view,
                    size: (SIDE, SIDE),
                },
            )?;
            enc.copy_texture_to_buffer(
                wgpu::TexelCopyTextureInfo {
                    texture: &t.visibility,
                    mip_level: 0,
                    origin: wgpu::Origin3d {
                        x: 0,
                        y: 0,
                        z: layer.0,
                    },
                    aspect: wgpu::TextureAspect::All,
                },
                wgpu::TexelCopyBufferInfo {
                    buffer: &self.slots[slot].buffer,
                    layout: wgpu::TexelCopyBufferLayout {
                        offset: LAYER_BYTES * u64::from(layer.0),
                        bytes_per_row: Some(SIDE * 4),
                        rows_per_image: Some(SIDE),
                    },
                },
                wgpu::Extent3d {
                    width: SIDE,
                    height: SIDE,
                    depth_or_array_layers: 1,
                },
            );
            lights.push((light, layer.0));
        }
        let s = &mut self.slots[slot];
        s.state = SlotState::Recorded;
        s.receivers = (hash, n, step);
        s.lights = lights;
        s.order = order;
        s.frame = frame_number;
        Ok(())
    }

    /// Takes the probes that have arrived: the newest becomes `world`'s [`ProbedVisibility`].
    fn take(&mut self, gpu: &GpuContext) -> Option<ProbedVisibility> {
        let _ = gpu.device.poll(wgpu::PollType::Poll);
        let mut newest: Option<(u64, ProbedVisibility)> = None;
        let made = &self.made;
        for slot in &mut self.slots {
            let SlotState::Mapping(flag) = &slot.state else {
                continue;
            };
            match flag.load(Ordering::Acquire) {
                0 => continue,
                1 => {
                    let (hash, n, step) = slot.receivers;
                    let mut probed = ProbedVisibility {
                        receivers: hash,
                        lights: HashMap::new(),
                    };
                    if let Ok(bytes) = slot.buffer.get_mapped_range(..) {
                        let v: &[f32] = bytemuck::cast_slice(&bytes);
                        let current =
                            |light: &Entity| made.get(light).is_none_or(|&f| f <= slot.frame);
                        for &(light, layer) in slot.lights.iter().filter(|(l, _)| current(l)) {
                            let at = (LAYER_BYTES / 4 * u64::from(layer)) as usize;
                            // Unsampled receivers hold no measurement (NaN: the estimate
                            // skips them, and never falls back to them).
                            let mut all = vec![f32::NAN; n];
                            for (k, i) in (0..n).step_by(step).enumerate() {
                                all[i] = v.get(at + k).copied().unwrap_or(1.0);
                            }
                            probed.lights.insert(light, all);
                        }
                    }
                    slot.buffer.unmap();
                    if newest.as_ref().is_none_or(|(o, _)| *o < slot.order) {
                        newest = Some((slot.order, probed));
                    }
                }
                _ => {}
            }
            slot.state = SlotState::Free;
        }
        newest.map(|(_, p)| p)
    }
}

/// Takes the probes of `world`'s [`ShadowProbe`] that have arrived into its
/// [`ProbedVisibility`] (on the GPU backend, where it holds one; elsewhere the probed `V` goes).
pub(crate) fn begin_frame(world: &mut World) {
    let backend = world.resource::<crate::FrameBackend>();
    let gpu = backend
        .gpu
        .clone()
        .filter(|_| backend.backend == soft_shadow_core::Backend::Gpu);
    let Some((gpu, true)) = gpu.map(|g| (g, world.contains_resource::<ShadowProbe>())) else {
        world.remove_resource::<ProbedVisibility>();
        return;
    };
    let arrived = world.resource_mut::<ShadowProbe>().take(&gpu);
    if let Some(p) = arrived {
        world.insert_resource(p);
    }
}

/// After a frame: the lights that made their maps again (`stats`) leave the probed `V`, which
/// held their old shadow, and probes recorded before now no longer count for them.
pub(crate) fn end_frame(world: &mut World, stats: &crate::FrameStats) {
    let made: Vec<Entity> = stats
        .lights
        .iter()
        .filter(|l| l.views_generated > 0)
        .map(|l| l.light)
        .collect();
    if made.is_empty() {
        return;
    }
    if let Some(mut probe) = world.get_resource_mut::<ShadowProbe>() {
        for &e in &made {
            probe.made.insert(e, stats.frame);
        }
    }
    if let Some(mut probed) = world.get_resource_mut::<ProbedVisibility>() {
        for e in &made {
            probed.lights.remove(e);
        }
    }
}
