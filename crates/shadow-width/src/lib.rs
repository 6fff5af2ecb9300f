#![doc = include_str!("../README.md")]

mod attenuation;
mod cpu;
mod eval;
#[cfg(feature = "gpu")]
mod gpu;
#[cfg(feature = "gpu")]
mod gpu_jump_flood;
mod jump_flood;
mod occlusion;
mod params;
#[cfg(feature = "gpu")]
mod shaders;
#[cfg(test)]
mod tests;
mod width;

pub use attenuation::{Falloff, FalloffKind, TABLE_SIZE_RANGE};
pub use cpu::CpuWidthMaps;
#[cfg(feature = "gpu")]
pub use gpu::GpuWidthMaps;
pub use params::{DEFAULT_TABLE_SIZE, DepthLayer, Neighbours, ShadowWidth, Softness, WidthMethod};
#[cfg(feature = "gpu")]
pub use shaders::{SHADERS, VISIBILITY};

#[cfg(feature = "gpu")]
use soft_shadow_core::GpuContext;
#[cfg(feature = "gpu")]
use soft_shadow_core::gpu::GpuScene;
#[cfg(feature = "gpu")]
use soft_shadow_core::gpu::shader::VisibilityShader;
use soft_shadow_core::{
    Checked, CpuContext, Family, Generation, Receivers, Result, ShadowTechnique, Tier,
};

impl ShadowTechnique for ShadowWidth {
    type CpuMaps = cpu::CpuWidthMaps;
    #[cfg(feature = "gpu")]
    type GpuMaps = gpu::GpuWidthMaps;
    #[cfg(not(feature = "gpu"))]
    type GpuMaps = soft_shadow_core::NoGpuMaps;

    fn cpu_maps(&self, cpu: &CpuContext, input: Checked<Generation<'_>>) -> cpu::CpuWidthMaps {
        cpu::generate(self, cpu, &input)
    }

    fn cpu_visibility(
        &self,
        maps: &cpu::CpuWidthMaps,
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
    ) -> Result<gpu::GpuWidthMaps> {
        gpu::generate(gpu, enc, self, scene, &input)
    }

    #[cfg(feature = "gpu")]
    const VISIBILITY: &'static VisibilityShader = &shaders::VISIBILITY;

    #[cfg(feature = "gpu")]
    fn recycle_maps(&self, gpu: &GpuContext, maps: gpu::GpuWidthMaps) {
        gpu.recycle_texture(maps.depth);
        gpu.recycle_buffer(maps.width);
    }

    #[cfg(feature = "gpu")]
    fn bind_maps(
        &self,
        gpu: &GpuContext,
        layout: &wgpu::BindGroupLayout,
        maps: &gpu::GpuWidthMaps,
    ) -> Result<wgpu::BindGroup> {
        Ok(gpu::bind_maps(gpu, layout, self, maps))
    }
}

/// This crate's technique for a [`Registry`](soft_shadow_core::Registry): one family, the default
/// (the exact distance transform, `ShadowWidth::new(WidthMethod::Exact)`) first, then
/// [`ShadowWidth::standard_set`], all run by the quick report and wider ([`Tier::Quick`]).
pub fn families() -> Vec<Family> {
    vec![
        Family::new(ShadowWidth::new(WidthMethod::Exact), Tier::Quick)
            .with_all(ShadowWidth::standard_set(), Tier::Quick),
    ]
}
