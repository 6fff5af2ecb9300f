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
#[cfg(test)]
mod tests;
mod width;

pub use attenuation::{Falloff, FalloffKind, TABLE_SIZE_RANGE};
pub use cpu::CpuWidthMaps;
#[cfg(feature = "gpu")]
pub use gpu::{GpuWidthMaps, SHADERS, VISIBILITY};
pub use params::{DEFAULT_TABLE_SIZE, DepthLayer, Neighbours, ShadowWidth, Softness, WidthMethod};

#[cfg(feature = "gpu")]
use soft_shadow_core::GpuContext;
#[cfg(feature = "gpu")]
use soft_shadow_core::gpu::GpuScene;
#[cfg(feature = "gpu")]
use soft_shadow_core::gpu::shader::VisibilityShader;
use soft_shadow_core::{Checked, CpuContext, Generation, Receivers, Result, ShadowTechnique};

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
    const VISIBILITY: &'static VisibilityShader = &gpu::VISIBILITY;

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

/// Registers this technique with a frame pipeline: its system set (which runs only while a
/// light uses it) and its standard variants, which `Auto` choices may pick (feature `frame`).
#[cfg(feature = "frame")]
pub fn add_to(frame: &mut shadow_frame::FramePipeline) {
    frame.add_technique(
        "shadow-width",
        ShadowWidth::standard_set()
            .into_iter()
            .map(|t| std::sync::Arc::new(t) as std::sync::Arc<dyn soft_shadow_core::DynTechnique>)
            .collect(),
    );
}
