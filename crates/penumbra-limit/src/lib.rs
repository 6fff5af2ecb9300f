#![doc = include_str!("../README.md")]

mod combine;
mod cpu;
mod depth_image;
mod eval;
mod feature_transform;
#[cfg(feature = "gpu")]
mod gpu;
mod params;
mod silhouette;
mod storage;
mod table;
#[cfg(test)]
mod tests;
mod visibility;
mod warp;

pub use cpu::CpuPenumbraMaps;
#[cfg(feature = "gpu")]
pub use gpu::GpuPenumbraMaps;
#[cfg(feature = "gpu")]
pub use gpu::pipelines::VISIBILITY;
pub use params::{Generator, PenumbraLimit};
pub use storage::{Storage, Texel};
pub use table::{Profile, TABLE_SIZE_RANGE};

#[cfg(feature = "gpu")]
use soft_shadow_core::GpuContext;
#[cfg(feature = "gpu")]
use soft_shadow_core::gpu::GpuScene;
#[cfg(feature = "gpu")]
use soft_shadow_core::gpu::shader::VisibilityShader;
use soft_shadow_core::{
    Checked, CpuContext, Family, Generation, Receivers, Result, ShadowTechnique, Tier,
};

#[cfg(feature = "gpu")]
pub use gpu::pipelines::SHADERS;
pub use params::MAX_RESOLUTION;

impl ShadowTechnique for PenumbraLimit {
    type CpuMaps = cpu::CpuPenumbraMaps;
    #[cfg(feature = "gpu")]
    type GpuMaps = gpu::GpuPenumbraMaps;
    #[cfg(not(feature = "gpu"))]
    type GpuMaps = soft_shadow_core::NoGpuMaps;

    fn cpu_maps(&self, cpu: &CpuContext, input: Checked<Generation<'_>>) -> cpu::CpuPenumbraMaps {
        cpu::generate(self, cpu, &input)
    }

    fn cpu_visibility(
        &self,
        maps: &cpu::CpuPenumbraMaps,
        receivers: Checked<Receivers<'_>>,
    ) -> Result<Vec<f32>> {
        Ok(cpu::evaluate(self, maps, &receivers))
    }

    #[cfg(feature = "gpu")]
    fn gpu_maps(
        &self,
        gpu: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        scene: &GpuScene,
        input: Checked<Generation<'_>>,
    ) -> Result<gpu::GpuPenumbraMaps> {
        gpu::generate(gpu, enc, self, scene, &input)
    }

    #[cfg(feature = "gpu")]
    const VISIBILITY: &'static VisibilityShader = &gpu::pipelines::VISIBILITY;

    #[cfg(feature = "gpu")]
    fn recycle_maps(&self, gpu: &GpuContext, maps: gpu::GpuPenumbraMaps) {
        gpu.recycle_texture(maps.map);
    }

    #[cfg(feature = "gpu")]
    fn bind_maps(
        &self,
        gpu: &GpuContext,
        layout: &wgpu::BindGroupLayout,
        maps: &gpu::GpuPenumbraMaps,
    ) -> Result<wgpu::BindGroup> {
        Ok(gpu::bind_maps(gpu, layout, self, maps))
    }
}

/// This crate's technique for a [`Registry`](soft_shadow_core::Registry): one family, the default
/// (the silhouette generator, `PenumbraLimit::new(Generator::Silhouette)`) first, then
/// [`PenumbraLimit::standard_set`], all run by the quick report and wider ([`Tier::Quick`]).
pub fn families() -> Vec<Family> {
    vec![
        Family::new(PenumbraLimit::new(Generator::Silhouette), Tier::Quick)
            .with_all(PenumbraLimit::standard_set(), Tier::Quick),
    ]
}
