//! The GPU frame: after [`FramePipeline::run`](crate::FramePipeline::run) on the GPU backend,
//! [`record_visibility`] records every light's `V` over your G-buffer into your command encoder,
//! each light into its layer ([`VisibilityLayer`]) of a texture you own. Nothing is read back
//! (but the passes' timestamps and the lights' `V` at the sampled receivers, where you ask for
//! them with a [`crate::GpuTiming`] and a [`crate::ShadowProbe`]; [`submitted`] after you submit
//! the encoder asks for both back):
//! the maps stay where the pipeline keeps them (made again only for stale lights), and `V` is the
//! same function the CPU path evaluates for [`FrameReceivers`](crate::FrameReceivers) within the
//! light's influence; beyond it (`ShadowConfig::with_range`, where the light adds nothing) the
//! texels get the maps' `V` too where the CPU path writes 1.
//!
//! In a frame where no light's maps were made again, over the same visibility texture and the
//! same G-buffer views as the frame before (keep the view objects), [`record_visibility`]
//! makes no buffer, texture, texture view or bind group (and with
//! `FrameSettings::evaluate_receivers` off, neither does the pipeline's run): every light's
//! maps keep their bind groups (with the receivers' over your G-buffer), and the world keeps a
//! view of every layer of your visibility texture (holding the texture until a frame records
//! into another). The maps a light replaces when it makes
//! them again go back to the GPU context's pool, so the new ones take their textures from it:
//! submit each frame's encoder before the next [`FramePipeline::run`](crate::FramePipeline::run),
//! which may hand the maps it reads to a new generation. `run` submits each light's generation
//! on its own and waits for it; [`FramePipeline::run_into`](crate::FramePipeline::run_into)
//! records them into your encoder instead, before the `V` passes this records into it: the
//! frame's shadow work is then one encoder you submit, and nothing waits.
//!
//! The frame's `FrameReceivers` still bound what a light's maps cover (a few points of your
//! G-buffer, say its corners, or none where the casters' shadows fall within the casters'
//! bounds): the maps are fitted to the casters and those receivers. With its camera, a distant
//! light's cascades split the depth range those points span (give points at your G-buffer's
//! nearest and farthest depths), and each cascade's window holds its whole slice of the
//! camera's frustum within the scene's bounds, not only those points (`CascadeFit::Auto` on
//! the GPU backend; `CascadeFit::Receivers` fits them to the points where those are every
//! texel `V` is read at).

pub use crate::components::VisibilityLayer;
use crate::components::{LightState, RecordedTexels};
use crate::gpu_probe::ShadowProbe;
use crate::gpu_timing::GpuTiming;
use bevy_ecs::prelude::*;
use soft_shadow_core::gpu::visibility::ReceiverTextures;
use soft_shadow_core::{GpuContext, Result, ShadowError};

/// Your G-buffer and the texture every light's `V` goes to.
#[derive(Clone, Copy, Debug)]
pub struct FrameTextures<'a> {
    /// World positions in xyz, w > 0.5 where a surface covers the texel (as
    /// [`ReceiverTextures::positions`]).
    pub positions: &'a wgpu::TextureView,
    /// Unit normals facing the camera in xyz.
    pub normals: &'a wgpu::TextureView,
    /// `R32Float`, 2D with an array layer per [`VisibilityLayer`], usable as a storage binding
    /// (and as a copy destination for lights that shadow nothing); its width and height are
    /// the G-buffer's.
    pub visibility: &'a wgpu::Texture,
}

/// Records `V` of every texel of `targets`' G-buffer, for every light with a
/// [`VisibilityLayer`], into that layer of `targets.visibility`, into `enc`; returns how many
/// lights were recorded. A light whose maps are on the GPU records its visibility pass; a light
/// without usable maps (no caster reaches it, it lights nothing the camera sees, or the frame
/// left it an error: see [`LightState::error`]) gets `V = 1` in its layer, a copy recorded into
/// `enc` from a buffer of ones the world keeps between frames (made once per texture size and
/// device).
///
/// Submit `enc` before the next [`FramePipeline::run`](crate::FramePipeline::run) (or
/// [`FramePipeline::run_into`](crate::FramePipeline::run_into)): that run may give the maps it
/// reads to a new generation.
///
/// Checked before anything is recorded: the texture's format and usage, every layer within it and no layer given to two
/// lights ([`ShadowError::InvalidParameter`]); maps made on the CPU backend are
/// [`ShadowError::MapsMismatch`].
pub fn record_visibility(
    world: &mut World,
    gpu: &GpuContext,
    enc: &mut wgpu::CommandEncoder,
    targets: &FrameTextures,
) -> Result<usize> {
    let texture = targets.visibility;
    storage_target(texture, "visibility", None)?;
    let size = (texture.width(), texture.height());
    let layers = texture.depth_or_array_layers();
    let mut query = world.query::<(&VisibilityLayer, &LightState)>();
    let mut taken = vec![false; layers as usize];
    for (layer, _) in query.iter(world) {
        let Some(t) = taken.get_mut(layer.0 as usize) else {
            return Err(ShadowError::InvalidParameter(format!(
                "visibility layer {} of a texture with {layers}",
                layer.0
            )));
        };
        if std::mem::replace(t, true) {
            return Err(ShadowError::InvalidParameter(format!(
                "visibility layer {} is given to two lights",
                layer.0
            )));
        }
    }
    gpu_maps_only(world)?;
    let needs_ones = query
        .iter(world)
        .any(|(_, s)| s.maps.is_none() || s.error.is_some());
    if needs_ones {
        if !texture.usage().contains(wgpu::TextureUsages::COPY_DST) {
            return Err(ShadowError::InvalidParameter(
                "a light that shadows nothing writes V = 1 by a copy: give the visibility \
                 texture COPY_DST"
                    .into(),
            ));
        }
        if world
            .get_resource::<Ones>()
            .is_none_or(|o| o.size != size || o.device != gpu.device)
        {
            let ones = Ones::new(gpu, size);
            world.insert_resource(ones);
        }
    }
    let ones = world.get_resource::<Ones>().map(|o| o.buffer.clone());
    // Out of the world while the lights are recorded (they read the world), then back.
    let layer_views = match world.remove_resource::<LayerViews>() {
        Some(v) if v.texture == *texture => v,
        _ => LayerViews::new(texture),
    };
    let recorded = timed_lights(world, enc, size, |world, enc, timing| {
        record_layers(world, gpu, enc, targets, (&layer_views.views, ones), timing)
    });
    world.insert_resource(layer_views);
    // Where a `ShadowProbe` asks for it, every light's `V` at the frame's sampled receivers.
    if recorded.is_ok()
        && let Some(mut probe) = world.remove_resource::<ShadowProbe>()
    {
        let probed = probe.record(world, gpu, enc, layers);
        world.insert_resource(probe);
        probed?;
    }
    recorded
}

/// Call after each submission of an encoder [`record_visibility`] recorded into, in the order
/// you submit them: asks for what that frame recorded to be read back, without waiting: the
/// passes' timestamps where the world holds a [`GpuTiming`], and the lights' `V` at the sampled
/// receivers where it holds a [`ShadowProbe`] (with neither, it does nothing). A later
/// [`crate::FramePipeline::run`] takes what has arrived. A frame recorded but never reported
/// submitted holds a slot of each until its readback is asked for: with every slot held, frames
/// go untimed ([`GpuTiming::untimed`]) and unprobed.
pub fn submitted(world: &mut World) {
    if let Some(mut timing) = world.get_resource_mut::<GpuTiming>() {
        timing.ask_back();
    }
    if let Some(mut probe) = world.get_resource_mut::<ShadowProbe>() {
        probe.ask_back();
    }
}

/// [`ShadowError::InvalidParameter`] naming `what` unless `texture` is a 2D `R32Float` texture
/// usable as a storage binding (of `layers` layers where given), what the GPU frame's passes
/// write.
pub(crate) fn storage_target(
    texture: &wgpu::Texture,
    what: &str,
    layers: Option<u32>,
) -> Result<()> {
    if texture.format() != wgpu::TextureFormat::R32Float
        || !texture
            .usage()
            .contains(wgpu::TextureUsages::STORAGE_BINDING)
        || texture.dimension() != wgpu::TextureDimension::D2
        || layers.is_some_and(|n| texture.depth_or_array_layers() != n)
    {
        return Err(ShadowError::InvalidParameter(format!(
            "the {what} texture must be a 2D R32Float storage texture{}, not {:?} {:?} {:?} of \
             {} layers",
            match layers {
                None => String::new(),
                Some(1) => " of one layer".into(),
                Some(n) => format!(" of {n} layers"),
            },
            texture.dimension(),
            texture.format(),
            texture.usage(),
            texture.depth_or_array_layers()
        )));
    }
    Ok(())
}

/// [`ShadowError::MapsMismatch`] where a light's usable maps were made on the CPU backend
/// (checked before anything is recorded).
pub(crate) fn gpu_maps_only(world: &mut World) -> Result<()> {
    let mut query = world.query::<&LightState>();
    if query.iter(world).any(|s| {
        s.error.is_none()
            && s.maps
                .as_ref()
                .is_some_and(|m| m.backend() != soft_shadow_core::Backend::Gpu)
    }) {
        return Err(ShadowError::MapsMismatch(
            "CPU maps write no GPU texture: run the frame on the GPU backend".into(),
        ));
    }
    Ok(())
}

/// Records the lights' passes over a G-buffer of `size` texels with `record` (given the
/// world's [`GpuTiming`], out of the world meanwhile): where a `GpuTiming` asks for it, every
/// light's `V` passes write timestamps, resolved into `enc` after the last of them; the
/// texels go to [`RecordedTexels`].
pub(crate) fn timed_lights(
    world: &mut World,
    enc: &mut wgpu::CommandEncoder,
    size: (u32, u32),
    record: impl FnOnce(&mut World, &mut wgpu::CommandEncoder, Option<&mut GpuTiming>) -> Result<usize>,
) -> Result<usize> {
    let mut timing = world.remove_resource::<GpuTiming>();
    let recorded = record(world, enc, timing.as_mut());
    let texels = size.0 as usize * size.1 as usize;
    if let Some(mut t) = timing {
        if recorded.is_ok() {
            t.resolve(enc, texels);
        }
        world.insert_resource(t);
    }
    if recorded.is_ok() && world.get_resource::<RecordedTexels>() != Some(&RecordedTexels(texels)) {
        // A new count shares the budget again (the predictions count texels).
        world.insert_resource(RecordedTexels(texels));
    }
    recorded
}

/// Records light `light`'s `V` from `maps` over `positions` and `normals` into `visibility`
/// (a texture of `size` texels), its passes timed where `timing` is given.
pub(crate) fn record_light(
    gpu: &GpuContext,
    enc: &mut wgpu::CommandEncoder,
    (light, maps): (Entity, &soft_shadow_core::technique::AnyMaps),
    (positions, normals): (&wgpu::TextureView, &wgpu::TextureView),
    (visibility, size): (&wgpu::TextureView, (u32, u32)),
    timing: Option<&mut GpuTiming>,
) -> Result<()> {
    let mut work = || {
        maps.record_visibility(
            gpu,
            enc,
            &ReceiverTextures {
                positions,
                normals,
                visibility,
                size,
            },
        )
    };
    match timing {
        Some(t) => t.time_visibility(gpu, light, work),
        None => work(),
    }
}

/// [`record_visibility`]'s recording, every layer checked: each light into its view of
/// `layer_views`, a light without maps copied from `ones`.
fn record_layers(
    world: &mut World,
    gpu: &GpuContext,
    enc: &mut wgpu::CommandEncoder,
    targets: &FrameTextures,
    (layer_views, ones): (&[wgpu::TextureView], Option<wgpu::Buffer>),
    mut timing: Option<&mut GpuTiming>,
) -> Result<usize> {
    let texture = targets.visibility;
    let size = (texture.width(), texture.height());
    let mut query = world.query::<(Entity, &VisibilityLayer, &LightState)>();
    let mut recorded = 0;
    for (light, layer, state) in query.iter(world) {
        let usable = state.maps.as_ref().filter(|_| state.error.is_none());
        let view = &layer_views[layer.0 as usize];
        match usable {
            Some(maps) => record_light(
                gpu,
                enc,
                (light, maps),
                (targets.positions, targets.normals),
                (view, size),
                timing.as_deref_mut(),
            )?,
            None => match &ones {
                Some(buffer) => unshadowed(enc, buffer, texture, layer.0),
                None => unreachable!("a light without maps made the buffer of ones"),
            },
        }
        recorded += 1;
    }
    Ok(recorded)
}

/// A view of every layer of the visibility texture, kept in the world between frames: a frame
/// over the same texture makes none (and the maps' bind group of the receivers, which these
/// views are part of, is kept too: [`soft_shadow_core::gpu::visibility::MapsBinding`]).
#[derive(Resource)]
struct LayerViews {
    /// The texture they view.
    texture: wgpu::Texture,
    /// Layer `k`'s view at `k`.
    views: Vec<wgpu::TextureView>,
}

impl LayerViews {
    fn new(texture: &wgpu::Texture) -> Self {
        let views = (0..texture.depth_or_array_layers())
            .map(|layer| {
                texture.create_view(&wgpu::TextureViewDescriptor {
                    label: Some("light visibility layer"),
                    dimension: Some(wgpu::TextureViewDimension::D2),
                    base_array_layer: layer,
                    array_layer_count: Some(1),
                    mip_level_count: Some(1),
                    ..Default::default()
                })
            })
            .collect();
        Self {
            texture: texture.clone(),
            views,
        }
    }
}

/// A buffer of `V = 1` texels the size of the visibility texture, its rows padded to the copy
/// alignment, kept in the world between frames.
#[derive(Resource)]
struct Ones {
    /// The device it lives on.
    device: wgpu::Device,
    /// The texture's width and height.
    size: (u32, u32),
    /// The ones.
    buffer: wgpu::Buffer,
}

impl Ones {
    /// Bytes per padded row of `width` texels.
    fn row_bytes(width: u32) -> u32 {
        (4 * width).next_multiple_of(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT)
    }

    fn new(gpu: &GpuContext, size: (u32, u32)) -> Self {
        let ones = vec![1.0f32; (Self::row_bytes(size.0) / 4 * size.1) as usize];
        let buffer = gpu.buffer_with(
            "visibility ones",
            bytemuck::cast_slice(&ones),
            wgpu::BufferUsages::COPY_SRC,
        );
        Self {
            device: gpu.device.clone(),
            size,
            buffer,
        }
    }
}

/// Records `V = 1` into layer `layer` of `texture`, copied from `ones` ([`Ones`]).
fn unshadowed(
    enc: &mut wgpu::CommandEncoder,
    ones: &wgpu::Buffer,
    texture: &wgpu::Texture,
    layer: u32,
) {
    let (w, h) = (texture.width(), texture.height());
    enc.copy_buffer_to_texture(
        wgpu::TexelCopyBufferInfo {
            buffer: ones,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(Ones::row_bytes(w)),
                rows_per_image: Some(h),
            },
        },
        wgpu::TexelCopyTextureInfo {
            texture,
            mip_level: 0,
            origin: wgpu::Origin3d {
                x: 0,
                y: 0,
                z: layer,
            },
            aspect: wgpu::TextureAspect::All,
        },
        wgpu::Extent3d {
            width: w,
            height: h,
            depth_or_array_layers: 1,
        },
    );
}
