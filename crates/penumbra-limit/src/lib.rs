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
use soft_shadow_core::{Checked, CpuContext, Generation, Receivers, Result, ShadowTechnique};

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

/// Registers this technique with a frame pipeline: its system set (which runs only while a
/// light uses it) and its standard variants, which `Auto` choices may pick (feature `frame`).
#[cfg(feature = "frame")]
pub fn add_to(frame: &mut shadow_frame::FramePipeline) {
    frame.add_technique(
        "penumbra-limit",
        PenumbraLimit::standard_set()
            .into_iter()
            .map(|t| std::sync::Arc::new(t) as std::sync::Arc<dyn soft_shadow_core::DynTechnique>)
            .collect(),
    );
}
