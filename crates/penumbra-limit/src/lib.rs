//! Lawlor (2006), *Interpolation-Friendly Soft Shadow Maps*: penumbra limit maps, on the CPU and
//! the GPU.
//!
//! One map from the light's centre stores four channels per texel: the occluder edge depth `c`,
//! the geometry upper limit `g`, the lower limit `b` and the signed penumbra limit `p_i`. A
//! receiver at map depth `z` sees the fraction `l_g` of the light's diameter given by equation 2
//! ([`visibility::clamped_visibility`]), and the visibility-to-illumination table of appendix A
//! ([`table`]) turns that into the fraction of the light's power. Along a straight edge every
//! channel is linear in the map plane, so the map survives bilinear interpolation: that is the
//! paper's point, and why coarse maps stay smooth.
//!
//! - Two generators ([`Generator`]): silhouette extrusion in the paper's three steps
//!   ([`silhouette`], GPU: `silhouette.wgsl`), and propagation from a depth image
//!   ([`depth_image`], GPU: `depth_image.wgsl`).
//! - Three storage formats ([`Storage`]): f32, f16 and the paper's RGBA8 packing.
//! - Lights: distant lights as in the paper; disk, sphere and rect lights through the perspective
//!   warp the conclusion proposes ([`warp`]; a sphere is its facing disc, a rect the disk of equal
//!   area); a point light gives an antialiased hard shadow. A segment light is
//!   [`soft_shadow_core::ShadowError::UnsupportedLight`]: its penumbra depends on the edge's direction,
//!   which one scalar `p_i` per texel cannot hold.
//!
//! Modules, one concept each: [`visibility`] (equations 1 and 2), [`table`] (section A),
//! [`storage`] (formats and packing), [`warp`] (map depths and local lights), [`params`],
//! [`silhouette`] and [`depth_image`] (generators), [`combine`] (the stored texel), [`eval`]
//! (per-receiver shading shared by both backends), [`cpu`] and [`gpu`].
//!
//! ```no_run
//! use penumbra_limit::{Generator, PenumbraLimit};
//! use soft_shadow_core::{Receivers, ShadowTechnique};
//! # fn demo(geometry: &soft_shadow_core::SceneGeometry, light: &soft_shadow_core::Light,
//! #         positions: &[glam::Vec3], normals: &[glam::Vec3]) -> soft_shadow_core::Result<()> {
//! let technique = PenumbraLimit::new(Generator::Silhouette);
//! let maps = technique.generate_cpu(&soft_shadow_core::CpuContext::new(), geometry, light, 256)?;
//! let v = technique.evaluate_cpu(&maps, &Receivers { positions, normals })?;
//! # Ok(()) }
//! ```

mod combine;
mod cpu;
mod depth_image;
mod eval;
mod feature_transform;
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
pub use gpu::GpuPenumbraMaps;
pub use gpu::pipelines::VISIBILITY;
pub use params::{Generator, PenumbraLimit};
pub use storage::{Storage, Texel};
pub use table::Profile;

use soft_shadow_core::gpu::GpuScene;
use soft_shadow_core::gpu::shader::VisibilityShader;
use soft_shadow_core::{
    Checked, CpuContext, Generation, GpuContext, Receivers, Result, ShadowTechnique,
};

pub use gpu::pipelines::SHADERS;
pub use params::MAX_RESOLUTION;

impl ShadowTechnique for PenumbraLimit {
    type CpuMaps = cpu::CpuPenumbraMaps;
    type GpuMaps = gpu::GpuPenumbraMaps;

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

    fn gpu_maps(
        &self,
        gpu: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        scene: &GpuScene,
        input: Checked<Generation<'_>>,
    ) -> Result<gpu::GpuPenumbraMaps> {
        gpu::generate(gpu, enc, self, scene, input.light, input.resolution)
    }

    const VISIBILITY: &'static VisibilityShader = &gpu::pipelines::VISIBILITY;

    fn recycle_gpu(&self, gpu: &GpuContext, maps: gpu::GpuPenumbraMaps) {
        gpu.recycle_texture(maps.map);
    }

    fn bind_maps(
        &self,
        gpu: &GpuContext,
        layout: &wgpu::BindGroupLayout,
        maps: &gpu::GpuPenumbraMaps,
    ) -> Result<wgpu::BindGroup> {
        Ok(gpu::bind_maps(gpu, layout, self, maps))
    }
}

/// This crate's rows of the frame pipeline's built-in profile (what `Auto` picks from without
/// a `report.json`), registered by [`add_to`]: `report --quick`, 2 cores, map resolution 256.
#[cfg(feature = "frame")]
pub const PROFILE_DEFAULTS: &[shadow_frame::profile::DefaultCost] = &[
    (
        "penumbra-limit",
        "silhouette-f32",
        soft_shadow_core::LightKind::Disk,
        105.6,
        20.5,
    ),
    (
        "penumbra-limit",
        "silhouette-f32",
        soft_shadow_core::LightKind::Distant,
        2.2,
        4.4,
    ),
    (
        "penumbra-limit",
        "silhouette-f32",
        soft_shadow_core::LightKind::Triangle,
        3.8,
        11.6,
    ),
];

/// Registers this technique with a frame pipeline: its system set (which runs only while a
/// light uses it) and its standard variants, which `Auto` choices may pick (feature `frame`).
#[cfg(feature = "frame")]
pub fn add_to(frame: &mut shadow_frame::FramePipeline) {
    frame.add_profile_defaults(PROFILE_DEFAULTS);
    frame.add_technique(
        "penumbra-limit",
        PenumbraLimit::standard_set()
            .into_iter()
            .map(|t| std::sync::Arc::new(t) as std::sync::Arc<dyn soft_shadow_core::DynTechnique>)
            .collect(),
    );
}
