//! Light-space depth maps of the baselines, one per light sample, rendered on the CPU.

use glam::Vec3;
use soft_shadow_core::raster::depth_map;
use soft_shadow_core::{CpuContext, Map2D, SampleView};

/// Depth maps rendered on the CPU.
pub struct CpuShadowMaps {
    /// One linear depth map per sample.
    pub(crate) maps: Vec<Map2D<f32>>,
    /// The samples' views.
    pub(crate) views: Vec<SampleView>,
    /// Map side.
    pub(crate) resolution: u32,
    /// [`soft_shadow_core::Light::size`] of the light.
    pub(crate) light_size: f32,
}

impl CpuShadowMaps {
    /// Rasterizes one depth map per view (storage from `cpu`'s pool); `light_size` is [`soft_shadow_core::Light::size`], kept for PCSS.
    pub fn render(
        cpu: &CpuContext,
        views: &[SampleView],
        casters: &[[Vec3; 3]],
        resolution: u32,
        light_size: f32,
    ) -> Self {
        let maps = views
            .iter()
            .map(|v| depth_map(cpu.pool(), &v.view, resolution, casters))
            .collect();
        Self {
            maps,
            views: views.to_vec(),
            resolution,
            light_size,
        }
    }
}
