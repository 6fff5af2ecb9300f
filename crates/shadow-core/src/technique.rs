//! The `ShadowTechnique` trait every technique and baseline implements, on CPU and on GPU.

use crate::error::{Result, ShadowError};
use crate::geometry::SceneGeometry;
use crate::gpu::GpuContext;
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
///   [`ShadowError::InvalidResolution`] for 0 or above the backend's limit. `generate_gpu` returns
///   after the GPU has finished, so timing it measures the GPU work.
/// - `evaluate_*` returns one visibility `V` per receiver, in `[0, 1]` and finite: the fraction of
///   the light the point sees under the light's emission profile (1 lit, 0 umbra).
/// - The GPU path computes the same function as the CPU path: RMS of `V * 255` below 1.0 on every
///   catalogue scene, checked by tests on a real Vulkan driver.
pub trait ShadowTechnique: Send + Sync {
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
    /// Builds the light-space maps on the GPU.
    fn generate_gpu(
        &self,
        gpu: &GpuContext,
        geometry: &SceneGeometry,
        light: &Light,
        resolution: u32,
    ) -> Result<Self::GpuMaps>;
    /// Visibility per receiver from GPU maps, computed on the GPU.
    fn evaluate_gpu(
        &self,
        gpu: &GpuContext,
        maps: &Self::GpuMaps,
        receivers: &Receivers,
    ) -> Result<Vec<f32>>;

    /// The common input checks: light valid and modelled, geometry non-empty, resolution in range.
    fn check_inputs(
        &self,
        geometry: &SceneGeometry,
        light: &Light,
        resolution: u32,
        max_resolution: u32,
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
    /// Evaluation on the backend that produced `maps`.
    fn evaluate(
        &self,
        gpu: Option<&GpuContext>,
        maps: &AnyMaps,
        receivers: &Receivers,
    ) -> Result<Vec<f32>>;
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
}
