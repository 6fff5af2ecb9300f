#![doc = include_str!("../README.md")]

mod combine;
mod cpu;
mod eval;
mod filters;
mod frame;
mod gpu;
mod params;
mod slicing;
#[cfg(test)]
mod tests;

pub use cpu::CpuSliceMaps;
pub use gpu::GpuSliceMaps;
pub use gpu::pipelines::{SHADERS, VISIBILITY};
pub use params::{
    Combination, DEFAULT_FADE_TEXELS, MAX_RESOLUTION, OcclusionSlices, Prefilter, SLICE_RANGE,
};

use soft_shadow_core::gpu::GpuScene;
use soft_shadow_core::gpu::shader::VisibilityShader;
use soft_shadow_core::{
    Checked, CpuContext, Generation, GpuContext, Receivers, Result, ShadowTechnique,
};

impl ShadowTechnique for OcclusionSlices {
    type CpuMaps = cpu::CpuSliceMaps;
    type GpuMaps = gpu::GpuSliceMaps;

    fn cpu_maps(&self, cpu: &CpuContext, input: Checked<Generation<'_>>) -> cpu::CpuSliceMaps {
        cpu::generate(self, cpu, &input)
    }

    fn cpu_visibility(
        &self,
        maps: &cpu::CpuSliceMaps,
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
    ) -> Result<gpu::GpuSliceMaps> {
        gpu::generate(gpu, enc, self, scene, &input)
    }

    const VISIBILITY: &'static VisibilityShader = &gpu::pipelines::VISIBILITY;

    fn recycle_maps(&self, gpu: &GpuContext, maps: gpu::GpuSliceMaps) {
        for t in [maps.occupancy, maps.sat, maps.filtered] {
            gpu.recycle_texture(t);
        }
    }

    fn bind_maps(
        &self,
        gpu: &GpuContext,
        layout: &wgpu::BindGroupLayout,
        maps: &gpu::GpuSliceMaps,
    ) -> Result<wgpu::BindGroup> {
        gpu::bind_maps(gpu, layout, self, maps)
    }
}

/// Registers this technique with a frame pipeline: its system set (which runs only while a
/// light uses it) and its standard variants, which `Auto` choices may pick (feature `frame`).
#[cfg(feature = "frame")]
pub fn add_to(frame: &mut shadow_frame::FramePipeline) {
    frame.add_technique(
        "occlusion-slices",
        OcclusionSlices::standard_set()
            .into_iter()
            .map(|t| std::sync::Arc::new(t) as std::sync::Arc<dyn soft_shadow_core::DynTechnique>)
            .collect(),
    );
}
