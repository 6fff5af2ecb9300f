//! Light-space depth maps of the baselines, one per light sample, rendered on the CPU.

use crate::strata::{Stratum, texel_strata};
use glam::Vec3;
use soft_shadow_core::raster::depth_map;
use soft_shadow_core::{CpuContext, Light, Map2D, SampleView};

/// Depth maps rendered on the CPU.
pub struct CpuShadowMaps {
    /// One linear depth map per sample.
    pub(crate) maps: Vec<Map2D<f32>>,
    /// The samples' views.
    pub(crate) views: Vec<SampleView>,
    /// Map side.
    pub(crate) resolution: u32,
    /// The light the maps are of (its size and shape set PCSS's kernels).
    pub(crate) light: Light,
    /// Each sample's cell in texels ([`crate::strata::texel_strata`]).
    pub(crate) strata: Vec<Stratum>,
}

impl CpuShadowMaps {
    /// Rasterizes one depth map per view of `light`'s samples as `sample_from` sees them
    /// (storage from `cpu`'s pool).
    pub fn render(
        cpu: &CpuContext,
        light: &Light,
        sample_from: Vec3,
        views: &[SampleView],
        casters: &[[Vec3; 3]],
        resolution: u32,
    ) -> Self {
        let maps = views
            .iter()
            .map(|v| depth_map(cpu.pool(), &v.view, resolution, casters))
            .collect();
        Self {
            maps,
            views: views.to_vec(),
            resolution,
            light: *light,
            strata: texel_strata(light, sample_from, views, resolution),
        }
    }
}
