#![doc = include_str!("../README.md")]

mod cpu;
mod eval;
#[cfg(feature = "gpu")]
mod gpu;
mod params;
mod samples;
mod segments;
mod skins;
#[cfg(test)]
mod tests;
mod warp;

pub use cpu::CpuLinearMaps;
#[cfg(feature = "gpu")]
pub use gpu::GpuLinearMaps;
#[cfg(feature = "gpu")]
pub use gpu::pipelines::{SHADERS, VISIBILITY};
pub use params::{LinearLight, SAMPLE_RANGE};

use segments::segments;
#[cfg(feature = "gpu")]
use soft_shadow_core::GpuContext;
#[cfg(feature = "gpu")]
use soft_shadow_core::gpu::GpuScene;
#[cfg(feature = "gpu")]
use soft_shadow_core::gpu::shader::VisibilityShader;
use soft_shadow_core::{
    Checked, CpuContext, Family, Generation, Receivers, Result, ShadowTechnique, Tier,
};

impl ShadowTechnique for LinearLight {
    type CpuMaps = cpu::CpuLinearMaps;
    #[cfg(feature = "gpu")]
    type GpuMaps = gpu::GpuLinearMaps;
    #[cfg(not(feature = "gpu"))]
    type GpuMaps = soft_shadow_core::NoGpuMaps;

    fn cpu_maps(&self, cpu: &CpuContext, input: Checked<Generation<'_>>) -> cpu::CpuLinearMaps {
        let segs = segments(input.light, input.geometry);
        cpu::generate(self, cpu, &input, &segs)
    }

    fn cpu_visibility(
        &self,
        maps: &cpu::CpuLinearMaps,
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
    ) -> Result<gpu::GpuLinearMaps> {
        let segs = segments(input.light, input.geometry);
        gpu::generate(gpu, enc, self, scene, &input, &segs)
    }

    #[cfg(feature = "gpu")]
    const VISIBILITY: &'static VisibilityShader = &gpu::pipelines::VISIBILITY;

    #[cfg(feature = "gpu")]
    fn recycle_maps(&self, gpu: &GpuContext, maps: gpu::GpuLinearMaps) {
        gpu.recycle_texture(maps.depth);
        gpu.recycle_texture(maps.channel);
    }

    #[cfg(feature = "gpu")]
    fn bind_maps(
        &self,
        gpu: &GpuContext,
        layout: &wgpu::BindGroupLayout,
        maps: &gpu::GpuLinearMaps,
    ) -> Result<wgpu::BindGroup> {
        Ok(gpu::bind_maps(gpu, layout, self, maps))
    }
}

/// This crate's technique for a [`Registry`](soft_shadow_core::Registry): one family, the default
/// (the paper's 3 samples, `LinearLight::new(3)`) first, then [`LinearLight::standard_set`], all
/// run by the quick report and wider ([`Tier::Quick`]).
pub fn families() -> Vec<Family> {
    vec![
        Family::new(LinearLight::new(3), Tier::Quick)
            .with_all(LinearLight::standard_set(), Tier::Quick),
    ]
}
