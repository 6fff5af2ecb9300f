#![doc = include_str!("../README.md")]

mod attenuation;
mod cpu;
mod eval;
mod gpu;
mod gpu_jump_flood;
mod jump_flood;
mod occlusion;
mod params;
#[cfg(test)]
mod tests;
mod width;

pub use attenuation::{Falloff, FalloffKind, TABLE_SIZE_RANGE};
pub use cpu::CpuWidthMaps;
pub use gpu::{GpuWidthMaps, SHADERS, VISIBILITY};
pub use params::{DEFAULT_TABLE_SIZE, DepthLayer, Neighbours, ShadowWidth, Softness, WidthMethod};

use soft_shadow_core::gpu::GpuScene;
use soft_shadow_core::gpu::shader::VisibilityShader;
use soft_shadow_core::{
    Checked, CpuContext, Generation, GpuContext, Receivers, Result, ShadowTechnique,
};

impl ShadowTechnique for ShadowWidth {
    type CpuMaps = cpu::CpuWidthMaps;
    type GpuMaps = gpu::GpuWidthMaps;

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

    fn gpu_maps(
        &self,
        gpu: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        scene: &GpuScene,
        input: Checked<Generation<'_>>,
    ) -> Result<gpu::GpuWidthMaps> {
        gpu::generate(gpu, enc, self, scene, &input)
    }

    const VISIBILITY: &'static VisibilityShader = &gpu::VISIBILITY;

    fn recycle_maps(&self, gpu: &GpuContext, maps: gpu::GpuWidthMaps) {
        gpu.recycle_texture(maps.depth);
        gpu.recycle_buffer(maps.width);
    }

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
