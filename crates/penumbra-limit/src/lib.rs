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
//! - Two generators ([`Generation`]): silhouette extrusion in the paper's three steps
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
//! use penumbra_limit::{Generation, PenumbraLimit};
//! use soft_shadow_core::{Receivers, ShadowTechnique};
//! # fn demo(geometry: &soft_shadow_core::SceneGeometry, light: &soft_shadow_core::Light,
//! #         positions: &[glam::Vec3], normals: &[glam::Vec3]) -> soft_shadow_core::Result<()> {
//! let technique = PenumbraLimit::new(Generation::Silhouette);
//! let maps = technique.generate_cpu(geometry, light, 256)?;
//! let v = technique.evaluate_cpu(&maps, &Receivers { positions, normals })?;
//! # Ok(()) }
//! ```

pub mod combine;
pub mod cpu;
pub mod depth_image;
pub mod eval;
pub mod gpu;
pub mod params;
pub mod silhouette;
pub mod storage;
pub mod table;
pub mod visibility;
pub mod warp;

pub use params::{Generation, PenumbraLimit};
pub use storage::{Storage, Texel};
pub use table::{IlluminationTable, Profile};

use soft_shadow_core::gpu::GpuScene;
use soft_shadow_core::technique::MAX_CPU_RESOLUTION;
use soft_shadow_core::{
    GpuContext, Light, LightKind, Receivers, Result, SceneGeometry, ShadowTechnique,
};

/// Largest map side: packed seed coordinates of the depth-image generator are 16-bit.
pub const MAX_RESOLUTION: u32 = 65535;

impl ShadowTechnique for PenumbraLimit {
    type CpuMaps = cpu::CpuPenumbraMaps;
    type GpuMaps = gpu::GpuPenumbraMaps;

    fn name(&self) -> &'static str {
        "penumbra-limit"
    }

    fn variant(&self) -> String {
        self.label()
    }

    /// Every light but a segment (see the crate docs).
    fn models(&self, kind: LightKind) -> bool {
        kind != LightKind::Linear
    }

    fn generate_cpu(
        &self,
        geometry: &SceneGeometry,
        light: &Light,
        resolution: u32,
    ) -> Result<cpu::CpuPenumbraMaps> {
        self.validate()?;
        self.check_inputs(
            geometry,
            light,
            resolution,
            MAX_CPU_RESOLUTION.min(MAX_RESOLUTION),
            soft_shadow_core::memory::cpu_budget(),
        )?;
        Ok(cpu::generate(self, geometry, light, resolution))
    }

    fn evaluate_cpu(&self, maps: &cpu::CpuPenumbraMaps, receivers: &Receivers) -> Result<Vec<f32>> {
        self.validate()?;
        receivers.validate()?;
        Ok(cpu::evaluate(self, maps, receivers))
    }

    /// The stored map plus the depth, geometry, edge, lower-limit and seed layers.
    fn memory_estimate(&self, _light: &Light, resolution: u32) -> u64 {
        let stored = match self.storage {
            Storage::F32 => 16,
            Storage::F16 => 8,
            Storage::Rgba8 => 4,
        };
        soft_shadow_core::memory::maps(1, resolution, stored + 40)
    }

    fn record_gpu(
        &self,
        gpu: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        scene: &GpuScene,
        light: &Light,
        resolution: u32,
    ) -> Result<gpu::GpuPenumbraMaps> {
        self.validate()?;
        self.check_inputs(
            scene.geometry(),
            light,
            resolution,
            gpu.max_texture_size().min(MAX_RESOLUTION),
            soft_shadow_core::memory::gpu_budget(),
        )?;
        gpu::generate(gpu, enc, self, scene, light, resolution)
    }

    fn visibility_wgsl() -> String {
        gpu::visibility_wgsl()
    }

    fn maps_layout_entries() -> Vec<wgpu::BindGroupLayoutEntry> {
        gpu::maps_layout_entries()
    }

    fn recycle_gpu(&self, gpu: &GpuContext, maps: gpu::GpuPenumbraMaps) {
        gpu.recycle_texture(maps.map);
    }

    fn bind_maps(
        &self,
        gpu: &GpuContext,
        layout: &wgpu::BindGroupLayout,
        maps: &gpu::GpuPenumbraMaps,
    ) -> Result<wgpu::BindGroup> {
        self.validate()?;
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
        LightKind::Disk,
        105.6,
        20.5,
    ),
    (
        "penumbra-limit",
        "silhouette-f32",
        LightKind::Distant,
        2.2,
        4.4,
    ),
    (
        "penumbra-limit",
        "silhouette-f32",
        LightKind::Triangle,
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
