//! The `ShadowTechnique` trait every technique and baseline implements, on CPU and on GPU.

use crate::error::{Result, ShadowError};
use crate::geometry::SceneGeometry;
use crate::gpu::visibility::{self, ReceiverTextures};
use crate::gpu::{GpuContext, GpuScene};
use crate::light::{Light, LightKind};
use glam::Vec3;
use std::any::Any;

/// Largest map side the CPU paths accept (a 16384² f32 map is 1 GiB).
pub const MAX_CPU_RESOLUTION: u32 = 16384;

/// Where a step runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Backend {
    /// Plain Rust (rayon where it pays).
    Cpu,
    /// wgpu render and compute passes (WGSL).
    Gpu,
}

impl Backend {
    /// `"cpu"` or `"gpu"`, as in reports.
    pub fn name(self) -> &'static str {
        match self {
            Backend::Cpu => "cpu",
            Backend::Gpu => "gpu",
        }
    }
}

/// A batch of world-space receiver points with unit normals, the input of evaluation.
#[derive(Clone, Copy, Debug)]
pub struct Receivers<'a> {
    /// World-space positions.
    pub positions: &'a [Vec3],
    /// Unit normals facing the viewer (same length as `positions`).
    pub normals: &'a [Vec3],
}

impl Receivers<'_> {
    /// Checks equal lengths and finite values.
    pub fn validate(&self) -> Result<()> {
        if self.positions.len() != self.normals.len() {
            return Err(ShadowError::InvalidReceivers(format!(
                "{} positions but {} normals",
                self.positions.len(),
                self.normals.len()
            )));
        }
        if let Some(i) = self
            .positions
            .iter()
            .chain(self.normals)
            .position(|p| !p.is_finite())
        {
            return Err(ShadowError::InvalidReceivers(format!(
                "entry {i} is not finite"
            )));
        }
        Ok(())
    }
}

/// A soft-shadow technique: parameters (the implementing value), a generation step that builds
/// light-space maps and an evaluation step that turns maps plus receivers into visibility.
///
/// # Contract
///
/// - `generate_*` takes the scene's plain geometry, one light and a map resolution. It validates
///   them and returns [`ShadowError::UnsupportedLight`] for a light kind that [`models`](Self::models)
///   rejects, [`ShadowError::InvalidLight`] for a bad light and
///   [`ShadowError::InvalidResolution`] for 0 or above the backend's limit.
/// - On the GPU, [`record_gpu`](Self::record_gpu) records generation into the caller's encoder
///   from geometry already on the GPU ([`GpuScene`]); the maps are ready once that encoder's
///   work has run. `generate_gpu` and `generate_gpu_on` are blocking wrappers that return after
///   the GPU has finished, so timing `generate_gpu_on` measures the GPU work without uploads.
/// - The GPU evaluation is one WGSL function, `visibility(world_pos, normal) -> f32`
///   ([`visibility_wgsl`](Self::visibility_wgsl), [`crate::gpu::visibility`]): the blocking
///   `evaluate_gpu`, the G-buffer pass [`record_visibility`](Self::record_visibility) and a
///   renderer's own shader all call it.
/// - `evaluate_*` returns one visibility `V` per receiver, in `[0, 1]` and finite: the fraction of
///   the light the point sees under the light's emission profile (1 lit, 0 umbra).
/// - The GPU path computes the same function as the CPU path: RMS of `V * 255` below 1.0 on every
///   catalogue scene, checked by tests on a real Vulkan driver.
pub trait ShadowTechnique: Send + Sync + 'static {
    /// Maps produced on the CPU.
    type CpuMaps: Send + Sync + 'static;
    /// Maps produced on (and kept on) the GPU.
    type GpuMaps: Send + Sync + 'static;

    /// Technique name as in reports (`"pcf"`, `"occlusion-slices"`, ...).
    fn name(&self) -> &'static str;
    /// Variant label of these parameters (`"r2"`, `"nbuffer-8"`, ...).
    fn variant(&self) -> String;
    /// Whether this technique models lights of `kind`.
    fn models(&self, kind: LightKind) -> bool;

    /// Builds the light-space maps on the CPU.
    fn generate_cpu(
        &self,
        geometry: &SceneGeometry,
        light: &Light,
        resolution: u32,
    ) -> Result<Self::CpuMaps>;
    /// Visibility per receiver from CPU maps.
    fn evaluate_cpu(&self, maps: &Self::CpuMaps, receivers: &Receivers) -> Result<Vec<f32>>;
    /// Records the generation of the light-space maps of `scene` into `enc` (nothing is
    /// submitted, mapped or uploaded beyond small parameter buffers): the maps hold their
    /// contents once the caller has submitted `enc`.
    fn record_gpu(
        &self,
        gpu: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        scene: &GpuScene,
        light: &Light,
        resolution: u32,
    ) -> Result<Self::GpuMaps>;

    /// WGSL that defines `fn visibility(world_pos: vec3<f32>, normal: vec3<f32>) -> f32` (the
    /// same function as [`evaluate_cpu`](Self::evaluate_cpu), with `normal` a unit normal
    /// facing the viewer) over bindings in `@group(0)` laid out by
    /// [`maps_layout_entries`](Self::maps_layout_entries). It depends on the type only, not on
    /// the parameters (those reach it through the bind group). Its other top-level names are the
    /// technique's helpers; a shader that includes it must not reuse them.
    fn visibility_wgsl() -> String
    where
        Self: Sized;

    /// Layout entries of the bindings [`visibility_wgsl`](Self::visibility_wgsl) reads, in
    /// binding order from 0 (their stage visibility is set by [`crate::gpu::visibility`]).
    fn maps_layout_entries() -> Vec<wgpu::BindGroupLayoutEntry>
    where
        Self: Sized;

    /// A bind group of `maps` (and these parameters) for `layout`, the layout of
    /// [`maps_layout_entries`](Self::maps_layout_entries). Maps made with other parameters
    /// than these are [`ShadowError::MapsMismatch`].
    fn bind_maps(
        &self,
        gpu: &GpuContext,
        layout: &wgpu::BindGroupLayout,
        maps: &Self::GpuMaps,
    ) -> Result<wgpu::BindGroup>;

    /// Gives `maps`' textures and buffers back to `gpu`'s pool ([`crate::gpu::pool`]) for the
    /// next generation of the same size: call it once the maps are no longer read (work already
    /// recorded with them still runs first). A renderer that recycles last frame's maps before
    /// recording the next allocates nothing per frame. Dropping the maps instead frees them.
    fn recycle_gpu(&self, gpu: &GpuContext, maps: Self::GpuMaps);

    /// Builds the light-space maps on the GPU and waits: uploads `geometry`, then
    /// [`generate_gpu_on`](Self::generate_gpu_on).
    fn generate_gpu(
        &self,
        gpu: &GpuContext,
        geometry: &SceneGeometry,
        light: &Light,
        resolution: u32,
    ) -> Result<Self::GpuMaps>
    where
        Self: Sized,
    {
        let scene = GpuScene::new(gpu, geometry)?;
        self.generate_gpu_on(gpu, &scene, light, resolution)
    }

    /// Records [`record_gpu`](Self::record_gpu) into a fresh encoder, submits it and waits for
    /// the GPU; wgpu validation and out-of-memory errors become [`ShadowError::Gpu`].
    fn generate_gpu_on(
        &self,
        gpu: &GpuContext,
        scene: &GpuScene,
        light: &Light,
        resolution: u32,
    ) -> Result<Self::GpuMaps>
    where
        Self: Sized,
    {
        gpu.checked(&format!("{} generation", self.name()), || {
            let mut enc = gpu.device.create_command_encoder(&Default::default());
            let maps = self.record_gpu(gpu, &mut enc, scene, light, resolution)?;
            gpu.queue.submit([enc.finish()]);
            gpu.wait()?;
            Ok(maps)
        })
    }

    /// The bind group a renderer's shader binds (at the group its
    /// [`visibility_wgsl`](Self::visibility_wgsl) was moved to) to call `visibility()`, with
    /// the layout [`crate::gpu::visibility::pipelines`] holds for this type.
    fn maps_bind_group(&self, gpu: &GpuContext, maps: &Self::GpuMaps) -> Result<wgpu::BindGroup>
    where
        Self: Sized,
    {
        let p = visibility::pipelines::<Self>(gpu);
        gpu.checked(&format!("{} maps", self.name()), || {
            self.bind_maps(gpu, &p.maps_layout, maps)
        })
    }

    /// Visibility per receiver from GPU maps, computed on the GPU and read back (blocking).
    fn evaluate_gpu(
        &self,
        gpu: &GpuContext,
        maps: &Self::GpuMaps,
        receivers: &Receivers,
    ) -> Result<Vec<f32>>
    where
        Self: Sized,
    {
        receivers.validate()?;
        gpu.checked(&format!("{} evaluation", self.name()), || {
            visibility::evaluate_buffers(self, gpu, maps, receivers)
        })
    }

    /// Records the evaluation of every texel of the caller's G-buffer `target` into `enc`, with
    /// the maps bound by `maps_bind` (from [`maps_bind_group`](Self::maps_bind_group)); no
    /// readback.
    fn record_visibility(
        &self,
        gpu: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        maps_bind: &wgpu::BindGroup,
        target: &ReceiverTextures,
    ) where
        Self: Sized,
    {
        visibility::record_texels::<Self>(gpu, enc, maps_bind, target);
    }

    /// Bytes one generation for `light` at `resolution` allocates (maps and scratch, about the
    /// same on both backends), checked against the budget before anything is allocated. The
    /// default counts one `f32` map; techniques with more layers or scratch say so.
    fn memory_estimate(&self, _light: &Light, resolution: u32) -> u64 {
        crate::memory::maps(1, resolution, 4)
    }

    /// The common input checks: light valid and modelled, geometry non-empty, resolution in
    /// range, [`memory_estimate`](Self::memory_estimate) within `memory_budget` bytes
    /// ([`crate::memory::cpu_budget`], [`crate::memory::gpu_budget`]).
    fn check_inputs(
        &self,
        geometry: &SceneGeometry,
        light: &Light,
        resolution: u32,
        max_resolution: u32,
        memory_budget: u64,
    ) -> Result<()> {
        light.validate()?;
        if !self.models(light.kind()) {
            return Err(ShadowError::UnsupportedLight {
                technique: self.name().to_string(),
                light: light.kind().name(),
            });
        }
        if resolution == 0 || resolution > max_resolution {
            return Err(ShadowError::InvalidResolution {
                requested: resolution,
                max: max_resolution,
            });
        }
        let need = self.memory_estimate(light, resolution);
        if need > memory_budget {
            return Err(ShadowError::OverBudget {
                what: format!("{} {} at {resolution}²", self.name(), self.variant()),
                need,
                budget: memory_budget,
            });
        }
        geometry.validate()
    }
}

/// Type-erased maps of either backend, as [`DynTechnique`] hands them around.
pub struct AnyMaps {
    backend: Backend,
    maps: Box<dyn Any + Send + Sync>,
}

impl AnyMaps {
    /// The backend that produced these maps.
    pub fn backend(&self) -> Backend {
        self.backend
    }
}

/// Object-safe view of a [`ShadowTechnique`], so harnesses can hold a list of techniques.
pub trait DynTechnique: Send + Sync {
    /// See [`ShadowTechnique::name`].
    fn name(&self) -> &'static str;
    /// See [`ShadowTechnique::variant`].
    fn variant(&self) -> String;
    /// See [`ShadowTechnique::models`].
    fn models(&self, kind: LightKind) -> bool;
    /// Generation on `backend`; `gpu` is required for [`Backend::Gpu`].
    fn generate(
        &self,
        backend: Backend,
        gpu: Option<&GpuContext>,
        geometry: &SceneGeometry,
        light: &Light,
        resolution: u32,
    ) -> Result<AnyMaps>;
    /// GPU generation from a scene already on the GPU (nothing uploaded but parameters).
    fn generate_gpu_on(
        &self,
        gpu: &GpuContext,
        scene: &GpuScene,
        light: &Light,
        resolution: u32,
    ) -> Result<AnyMaps>;
    /// See [`ShadowTechnique::visibility_wgsl`].
    fn visibility_wgsl(&self) -> String;
    /// Evaluation on the backend that produced `maps`.
    fn evaluate(
        &self,
        gpu: Option<&GpuContext>,
        maps: &AnyMaps,
        receivers: &Receivers,
    ) -> Result<Vec<f32>>;
    /// Gives GPU maps back to `gpu`'s pool ([`ShadowTechnique::recycle_gpu`]); CPU maps (and
    /// maps of another technique) are dropped, their storage going back to [`crate::pool`].
    fn recycle(&self, gpu: Option<&GpuContext>, maps: AnyMaps);
}

fn need_gpu(gpu: Option<&GpuContext>) -> Result<&GpuContext> {
    gpu.ok_or_else(|| {
        ShadowError::NoAdapter("the GPU backend was asked for without a GPU context".into())
    })
}

impl<T: ShadowTechnique> DynTechnique for T {
    fn name(&self) -> &'static str {
        ShadowTechnique::name(self)
    }
    fn variant(&self) -> String {
        ShadowTechnique::variant(self)
    }
    fn models(&self, kind: LightKind) -> bool {
        ShadowTechnique::models(self, kind)
    }
    fn generate(
        &self,
        backend: Backend,
        gpu: Option<&GpuContext>,
        geometry: &SceneGeometry,
        light: &Light,
        resolution: u32,
    ) -> Result<AnyMaps> {
        let maps: Box<dyn Any + Send + Sync> = match backend {
            Backend::Cpu => Box::new(self.generate_cpu(geometry, light, resolution)?),
            Backend::Gpu => {
                Box::new(self.generate_gpu(need_gpu(gpu)?, geometry, light, resolution)?)
            }
        };
        Ok(AnyMaps { backend, maps })
    }
    fn generate_gpu_on(
        &self,
        gpu: &GpuContext,
        scene: &GpuScene,
        light: &Light,
        resolution: u32,
    ) -> Result<AnyMaps> {
        Ok(AnyMaps {
            backend: Backend::Gpu,
            maps: Box::new(ShadowTechnique::generate_gpu_on(
                self, gpu, scene, light, resolution,
            )?),
        })
    }
    fn visibility_wgsl(&self) -> String {
        T::visibility_wgsl()
    }
    fn evaluate(
        &self,
        gpu: Option<&GpuContext>,
        maps: &AnyMaps,
        receivers: &Receivers,
    ) -> Result<Vec<f32>> {
        receivers.validate()?;
        let mismatch = || {
            ShadowError::MapsMismatch(format!(
                "maps were not produced by {}",
                ShadowTechnique::name(self)
            ))
        };
        match maps.backend {
            Backend::Cpu => {
                self.evaluate_cpu(maps.maps.downcast_ref().ok_or_else(mismatch)?, receivers)
            }
            Backend::Gpu => self.evaluate_gpu(
                need_gpu(gpu)?,
                maps.maps.downcast_ref().ok_or_else(mismatch)?,
                receivers,
            ),
        }
    }
    fn recycle(&self, gpu: Option<&GpuContext>, maps: AnyMaps) {
        if let (Backend::Gpu, Some(gpu)) = (maps.backend, gpu)
            && let Ok(m) = maps.maps.downcast::<T::GpuMaps>()
        {
            self.recycle_gpu(gpu, *m);
        }
    }
}
