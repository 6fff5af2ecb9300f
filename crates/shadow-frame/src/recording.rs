//! Where a frame's GPU generations go: each submitted on its own and waited for
//! ([`crate::FramePipeline::run`]), or recorded into the renderer's command encoder
//! ([`crate::FramePipeline::run_into`]), so that a GPU frame's shadow work, maps and `V`, is
//! one encoder the renderer submits with the rest of its frame.

use crate::components::FrameBackend;
use soft_shadow_core::technique::{AnyMaps, DynTechnique};
use soft_shadow_core::{Light, LightViews, SceneGeometry};

/// How a technique's system makes a light's maps this frame: in the backend's context, or
/// (on the GPU, in [`crate::FramePipeline::run_into`]) recorded into the renderer's encoder.
pub(crate) struct Recording<'a> {
    backend: &'a FrameBackend,
    #[cfg(feature = "gpu")]
    encoder: Option<&'a mut wgpu::CommandEncoder>,
}

impl<'a> Recording<'a> {
    /// Generations in `backend`'s context, a GPU one submitted and waited for.
    pub(crate) fn in_context(backend: &'a FrameBackend) -> Self {
        Self {
            backend,
            #[cfg(feature = "gpu")]
            encoder: None,
        }
    }

    /// GPU generations recorded into `encoder` where there is one and the backend is the GPU's.
    #[cfg(feature = "gpu")]
    pub(crate) fn into_encoder(
        backend: &'a FrameBackend,
        encoder: Option<&'a mut wgpu::CommandEncoder>,
    ) -> Self {
        Self { backend, encoder }
    }

    /// The encoder and GPU context a generation records into, where it records.
    #[cfg(feature = "gpu")]
    fn recorder(&mut self) -> Option<(&soft_shadow_core::GpuContext, &mut wgpu::CommandEncoder)> {
        let gpu = self.backend.gpu.as_deref()?;
        let enc = self.encoder.as_deref_mut()?;
        (self.backend.backend == soft_shadow_core::Backend::Gpu).then_some((gpu, enc))
    }

    /// `technique`'s maps of `views` of `light` over `geometry`.
    pub(crate) fn generate(
        &mut self,
        technique: &dyn DynTechnique,
        geometry: &SceneGeometry,
        light: &Light,
        views: &LightViews,
        resolution: u32,
    ) -> Result<AnyMaps, String> {
        #[cfg(feature = "gpu")]
        if let Some((gpu, enc)) = self.recorder() {
            return technique
                .record_in(gpu, enc, geometry, light, views, resolution)
                .map_err(|e| e.to_string());
        }
        self.backend.context().and_then(|ctx| {
            technique
                .generate_in(ctx, geometry, light, views, resolution)
                .map_err(|e| e.to_string())
        })
    }

    /// The views at `indices` of `maps` made again ([`AnyMaps::remake_views`]).
    pub(crate) fn remake_views(
        &mut self,
        maps: &mut AnyMaps,
        geometry: &SceneGeometry,
        light: &Light,
        resolution: u32,
        indices: &[usize],
    ) -> Result<(), String> {
        #[cfg(feature = "gpu")]
        if let Some((gpu, enc)) = self.recorder() {
            return maps
                .remake_views_into(gpu, enc, geometry, light, resolution, indices)
                .map_err(|e| e.to_string());
        }
        self.backend.context().and_then(|ctx| {
            maps.remake_views(ctx, geometry, light, resolution, indices)
                .map_err(|e| e.to_string())
        })
    }

    /// `maps` brought to the views `planned` ([`AnyMaps::follow`]).
    pub(crate) fn follow(
        &mut self,
        maps: &mut AnyMaps,
        geometry: &SceneGeometry,
        light: &Light,
        planned: &LightViews,
        resolution: u32,
    ) -> Result<Option<usize>, String> {
        #[cfg(feature = "gpu")]
        if let Some((gpu, enc)) = self.recorder() {
            return maps
                .follow_into(gpu, enc, geometry, light, planned, resolution)
                .map_err(|e| e.to_string());
        }
        self.backend.context().and_then(|ctx| {
            maps.follow(ctx, geometry, light, planned, resolution)
                .map_err(|e| e.to_string())
        })
    }
}

#[cfg(feature = "gpu")]
pub(crate) use encoder::FrameEncoder;

#[cfg(feature = "gpu")]
mod encoder {
    use crate::components::{FrameBackend, FrameSettings};
    use crate::{FramePipeline, FrameStats};
    use bevy_ecs::prelude::*;
    use soft_shadow_core::{Backend, Result, ShadowError};

    /// The renderer's encoder while [`FramePipeline::run_into`] runs.
    #[derive(Resource)]
    pub(crate) struct FrameEncoder(pub(crate) wgpu::CommandEncoder);

    /// An encoder the world keeps to stand in the renderer's while that one is in the world:
    /// made once, never recorded into, never finished.
    #[derive(Resource)]
    struct SpareEncoder(wgpu::CommandEncoder);

    impl FramePipeline {
        /// One frame on the GPU backend, as [`FramePipeline::run`] runs it, but every light's
        /// generation is recorded into `enc` instead of being submitted on its own and waited
        /// for: nothing is submitted, waited for or read back (the casters a generation
        /// reads and its small parameter buffers are uploaded with the queue's next
        /// submission). Record the lights' `V` into the same encoder after it
        /// ([`crate::gpu_frame::record_visibility`]), submit it, and submit each frame's
        /// encoder before the next frame's `run_into` (which may give the maps it reads to a
        /// new generation). Until you submit `enc`, submit nothing else through the same
        /// [`soft_shadow_core::GpuContext`] (its pool may hand textures whose work still waits
        /// in `enc` to that submission).
        ///
        /// A generation that fails as it records (a texture the device cannot make) leaves
        /// its light a [`crate::LightState::error`], but what it recorded stays in `enc`, so
        /// `enc` fails as a whole when it is finished; a wgpu error wgpu reports only then
        /// surfaces there, not in the light's error. (The pipeline checks each configuration
        /// against the device's limits and the context's memory budget before it records.)
        /// `Auto` measures a recorded generation only by its device time: with a
        /// [`crate::GpuTiming`] its budget holds, without one it keeps its pick.
        ///
        /// Refused before anything runs ([`ShadowError::InvalidParameter`]) where the world's
        /// [`FrameBackend`] is not the GPU backend with a context, or its [`FrameSettings`]
        /// evaluate the receivers (that reads `V` back from maps `enc` has not made yet).
        pub fn run_into(
            &mut self,
            world: &mut World,
            enc: &mut wgpu::CommandEncoder,
        ) -> Result<FrameStats> {
            let gpu = match world.get_resource::<FrameBackend>() {
                Some(FrameBackend {
                    backend: Backend::Gpu,
                    gpu: Some(gpu),
                    ..
                }) => gpu.clone(),
                _ => {
                    return Err(ShadowError::InvalidParameter(
                        "run_into records GPU work: the world's FrameBackend must be the GPU \
                         backend with a context"
                            .into(),
                    ));
                }
            };
            if world
                .get_resource::<FrameSettings>()
                .copied()
                .unwrap_or_default()
                .evaluate_receivers
            {
                return Err(ShadowError::InvalidParameter(
                    "run_into reads nothing back: turn FrameSettings::evaluate_receivers off"
                        .into(),
                ));
            }
            let spare = world.remove_resource::<SpareEncoder>().map_or_else(
                || {
                    gpu.device
                        .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                            label: Some("shadow-frame spare encoder"),
                        })
                },
                |s| s.0,
            );
            world.insert_resource(FrameEncoder(std::mem::replace(enc, spare)));
            let stats =
                std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| self.run_frame(world)));
            // Your encoder back, whatever the frame did.
            if let Some(FrameEncoder(recorded)) = world.remove_resource() {
                world.insert_resource(SpareEncoder(std::mem::replace(enc, recorded)));
            }
            let stats = stats.unwrap_or_else(|panic| std::panic::resume_unwind(panic));
            // The wall time of a recorded generation is its recording.
            crate::gpu_timing::forget_wall_times(world);
            Ok(stats)
        }
    }
}
