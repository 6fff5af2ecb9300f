//! Kirsch & Döllner (2003), *Real-Time Soft Shadows Using a Single Light Sample*, on the CPU and
//! the GPU.
//!
//! From the light's centre the technique renders a depth map and an *inverted occlusion map*,
//! turns the latter into a *shadow-width map* `w` (distance from each blocked texel to the
//! nearest unblocked one), and shades a receiver at light-space `(x', y', z')` with
//!
//! - shadow depth `sd = z' - z(x', y')` (world units along the light axis),
//! - shadow width `sw = w(x', y')`: **world units** on the map plane for a distant light
//!   (orthographic map), an **angle in radians** at the light for local lights (perspective map:
//!   the texel distance times the texel's angular size on the map's tangent plane, exact to first
//!   order near the axis),
//! - `V = I(sd, sw) = f(c_scale * sw / sd)` ([`mod@attenuation`]).
//!
//! The technique only darkens inside the geometric (hard) shadow: the outer half of a penumbra
//! stays lit, as the paper says. Every light kind is modelled through its centre; the softness
//! follows the light's size ([`Softness::FromLight`]) or a constant.
//!
//! Modules, one concept each: [`params`] (configuration), [`mod@attenuation`] (`I`, falloffs,
//! lookup table), [`occlusion`] (which texels block), [`width`] (three width-map builders),
//! [`eval`] (per-receiver shading shared by both backends), [`cpu`] and [`gpu`] (the two
//! paths; `width.wgsl` and `evaluate.wgsl` beside them).
//!
//! ```no_run
//! use shadow_width::{ShadowWidth, WidthMethod};
//! use soft_shadow_core::{ShadowTechnique, Receivers};
//! # fn demo(geometry: &soft_shadow_core::SceneGeometry, light: &soft_shadow_core::Light,
//! #         positions: &[glam::Vec3], normals: &[glam::Vec3]) -> soft_shadow_core::Result<()> {
//! let technique = ShadowWidth::new(WidthMethod::Exact);
//! let maps = technique.generate_cpu(&soft_shadow_core::CpuContext::new(), geometry, light, 512)?;
//! let v = technique.evaluate_cpu(&maps, &Receivers { positions, normals })?;
//! # Ok(()) }
//! ```

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

pub use attenuation::{Falloff, FalloffKind};
pub use cpu::CpuWidthMaps;
pub use gpu::{GpuWidthMaps, SHADERS, VISIBILITY};
pub use params::{DepthLayer, Neighbours, ShadowWidth, Softness, WidthMethod};

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
        gpu::generate(gpu, enc, self, scene, input.light, input.resolution)
    }

    const VISIBILITY: &'static VisibilityShader = &gpu::VISIBILITY;

    fn recycle_gpu(&self, gpu: &GpuContext, maps: gpu::GpuWidthMaps) {
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
