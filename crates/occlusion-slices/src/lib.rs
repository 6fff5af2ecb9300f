//! Eisemann & Décoret (2006), *Plausible Image Based Soft Shadows Using Occlusion Textures*, on
//! the CPU and the GPU.
//!
//! The scene is cut into 4 to 16 slices parallel to a rectangular light, each projected from a
//! centre of projection behind the light onto a binary *occlusion texture* ([`frame`],
//! [`slicing`]). A point `P` sees, through each slice between it and the light, the box of side
//! `s(P) = d(P, slice) / d(P, light) * size(light)` (equation 4); its mean occupancy `I_k` is one
//! prefiltered lookup ([`filters`]: mipmaps, N-Buffers or an exact summed-area table), and the
//! slices combine by the probabilistic product `V = prod(1 - I_k)` (equation 5, [`combine`]).
//! For a single planar occluder parallel to the light this is exact (section 3.1).
//!
//! - Lights: rectangles as in the paper. A disk or a triangle is modelled as the square of
//!   equal area, a sphere as its silhouette disc facing the scene, then that square (documented
//!   approximations). Point, segment and distant lights are
//!   [`soft_shadow_core::ShadowError::UnsupportedLight`]: the frustum is fitted to the light's area.
//! - Self-shadowing (section 3.4): the slice containing `P` is not used, and the slice above it
//!   fades in linearly with `P`'s distance below that slice's lower plane ([`Frame::fade`]), so
//!   `V` stays continuous where a surface crosses a plane and a receiver lying on a plane is not
//!   shadowed by its own projection.
//! - The thin-occluder fix (a fragment also fills the next slice) is an option.
//!
//! Modules, one concept each: [`params`], [`frame`] (COP, frustum, slice planes, kernels),
//! [`slicing`] (CPU slicing pass), [`filters`] (the three box filters), [`combine`]
//! (equation 5 and its alternatives), [`eval`] (shading one receiver), [`cpu`] and [`gpu`].
//!
//! ```no_run
//! use occlusion_slices::{Prefilter, OcclusionSlices};
//! use soft_shadow_core::{Receivers, ShadowTechnique};
//! # fn demo(geometry: &soft_shadow_core::SceneGeometry, light: &soft_shadow_core::Light,
//! #         positions: &[glam::Vec3], normals: &[glam::Vec3]) -> soft_shadow_core::Result<()> {
//! let technique = OcclusionSlices::new(8, Prefilter::NBuffer);
//! let maps = technique.generate_cpu(&soft_shadow_core::CpuContext::new(), geometry, light, 256)?;
//! let v = technique.evaluate_cpu(&maps, &Receivers { positions, normals })?;
//! # Ok(()) }
//! ```

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
pub use params::{Combination, Prefilter, MAX_RESOLUTION, OcclusionSlices};

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
        gpu::generate(gpu, enc, self, scene, input.light, input.resolution)
    }

    const VISIBILITY: &'static VisibilityShader = &gpu::pipelines::VISIBILITY;

    fn recycle_gpu(&self, gpu: &GpuContext, maps: gpu::GpuSliceMaps) {
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

/// This crate's rows of the frame pipeline's built-in profile (what `Auto` picks from without
/// a `report.json`), registered by [`add_to`]: `report --quick`, 2 cores, map resolution 256.
#[cfg(feature = "frame")]
pub const PROFILE_DEFAULTS: &[shadow_frame::profile::DefaultCost] = &[
    (
        "occlusion-slices",
        "sat-8",
        soft_shadow_core::LightKind::Rect,
        3.5,
        13.6,
    ),
    (
        "occlusion-slices",
        "nbuffer-8",
        soft_shadow_core::LightKind::Rect,
        7.3,
        14.3,
    ),
    (
        "occlusion-slices",
        "sat-16",
        soft_shadow_core::LightKind::Sphere,
        7.9,
        9.3,
    ),
    (
        "occlusion-slices",
        "sat-8",
        soft_shadow_core::LightKind::Triangle,
        3.9,
        4.4,
    ),
];

/// Registers this technique with a frame pipeline: its system set (which runs only while a
/// light uses it) and its standard variants, which `Auto` choices may pick (feature `frame`).
#[cfg(feature = "frame")]
pub fn add_to(frame: &mut shadow_frame::FramePipeline) {
    frame.add_profile_defaults(PROFILE_DEFAULTS);
    frame.add_technique(
        "occlusion-slices",
        OcclusionSlices::standard_set()
            .into_iter()
            .map(|t| std::sync::Arc::new(t) as std::sync::Arc<dyn soft_shadow_core::DynTechnique>)
            .collect(),
    );
}
