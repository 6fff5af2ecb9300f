#![doc = include_str!("../README.md")]

mod combine;
mod cpu;
mod eval;
mod filters;
mod frame;
#[cfg(feature = "gpu")]
mod gpu;
mod params;
mod slicing;
#[cfg(test)]
mod tests;

pub use cpu::CpuSliceMaps;
#[cfg(feature = "gpu")]
pub use gpu::GpuSliceMaps;
#[cfg(feature = "gpu")]
pub use gpu::pipelines::{SHADERS, VISIBILITY};
pub use params::{
    Combination, DEFAULT_FADE_TEXELS, MAX_RESOLUTION, OcclusionSlices, Prefilter, SLICE_RANGE,
};

#[cfg(feature = "gpu")]
use soft_shadow_core::GpuContext;
#[cfg(feature = "gpu")]
use soft_shadow_core::gpu::GpuScene;
#[cfg(feature = "gpu")]
use soft_shadow_core::gpu::shader::VisibilityShader;
use soft_shadow_core::{
    Checked, CpuContext, Family, Generation, Receivers, Result, ShadowTechnique, Tier,
};

impl ShadowTechnique for OcclusionSlices {
    type CpuMaps = cpu::CpuSliceMaps;
    #[cfg(feature = "gpu")]
    type GpuMaps = gpu::GpuSliceMaps;
    #[cfg(not(feature = "gpu"))]
    type GpuMaps = soft_shadow_core::NoGpuMaps;

    fn cpu_maps(&self, cpu: &CpuContext, input: Checked<Generation<'_>>) -> cpu::CpuSliceMaps {
        cpu::generate(self, cpu, &input)
    }

    fn cpu_visibility(
        &self,
        maps: &cpu::CpuSliceMaps,
        receivers: Checked<Receivers<'_>>,
    ) -> Result<Vec<f32>> {
        cpu::evaluate(self, maps, &receivers)
    }

    #[cfg(feature = "gpu")]
    fn gpu_maps(
        &self,
        gpu: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        scene: &GpuScene,
        input: Checked<Generation<'_>>,
    ) -> Result<gpu::GpuSliceMaps> {
        gpu::generate(gpu, enc, self, scene, &input)
    }

    #[cfg(feature = "gpu")]
    const VISIBILITY: &'static VisibilityShader = &gpu::pipelines::VISIBILITY;

    #[cfg(feature = "gpu")]
    fn recycle_maps(&self, gpu: &GpuContext, maps: gpu::GpuSliceMaps) {
        for t in [maps.occupancy, maps.sat, maps.filtered] {
            gpu.recycle_texture(t);
        }
    }

    #[cfg(feature = "gpu")]
    fn bind_maps(
        &self,
        gpu: &GpuContext,
        layout: &wgpu::BindGroupLayout,
        maps: &gpu::GpuSliceMaps,
    ) -> Result<wgpu::BindGroup> {
        gpu::bind_maps(gpu, layout, self, maps)
    }
}

/// This crate's technique for a [`Registry`](soft_shadow_core::Registry): one family, the default
/// (8 slices filtered by N-Buffers and chained,
/// `OcclusionSlices::new(8, Prefilter::NBuffer).with_combination(Combination::Chain)`: no light
/// lines through the umbra where a body crosses a slice plane) first, then
/// [`OcclusionSlices::standard_set`], all run by the quick report and wider ([`Tier::Quick`])
/// but the chained SAT slices, which the full report runs ([`Tier::Report`]: the quick one
/// stays under two minutes).
pub fn families() -> Vec<Family> {
    let chain = |f| OcclusionSlices::new(8, f).with_combination(Combination::Chain);
    let (full, quick): (Vec<_>, Vec<_>) = OcclusionSlices::standard_set()
        .into_iter()
        .partition(|t| *t == chain(Prefilter::Sat));
    vec![
        Family::new(chain(Prefilter::NBuffer), Tier::Quick)
            .with_all(quick, Tier::Quick)
            .with_all(full, Tier::Report),
    ]
}
