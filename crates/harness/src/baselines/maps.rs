//! Light-space depth maps of the baselines: one per light sample, with the per-map parameters
//! that CPU and GPU evaluation share.

use bytemuck::{Pod, Zeroable};
use glam::{Vec3, Vec4};
use shadow_core::raster::depth_map;
use shadow_core::view::ProjectionKind;
use shadow_core::{Aabb, Light, LightPoint, Map2D, View};

/// Per-map parameters, laid out as `MapView` in `shadow_map_eval.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable, PartialEq)]
pub struct MapParams {
    /// World to clip, column-major.
    pub view_proj: [f32; 16],
    /// Linear depth of `p` is `dot(depth_row, (p, 1))`.
    pub depth_row: [f32; 4],
    /// Near plane.
    pub near: f32,
    /// Far plane.
    pub far: f32,
    /// Texel world size is `texel_a * z + texel_b`.
    pub texel_a: f32,
    /// See `texel_a`.
    pub texel_b: f32,
    /// 1 for orthographic maps.
    pub ortho: u32,
    /// Weight of this light sample.
    pub weight: f32,
    /// Padding to 16 bytes.
    pub _pad: [f32; 2],
    /// The light sample: eye position with w = 1 (perspective) or direction to the light with w = 0.
    pub light: [f32; 4],
}

/// One light sample's view and weight.
#[derive(Clone, Copy, Debug)]
pub struct SampleView {
    /// The light-space view.
    pub view: View,
    /// Emission weight of the sample.
    pub weight: f32,
    /// Eye position (w = 1) or unit direction towards the light (w = 0).
    pub light: Vec4,
}

impl SampleView {
    /// The shader-side parameters for a `resolution`-wide map.
    pub fn params(&self, resolution: u32) -> MapParams {
        let (a, b) = self.view.texel_scale(resolution);
        let row: Vec4 = -self.view.view.row(2);
        MapParams {
            view_proj: self.view.view_projection().to_cols_array(),
            depth_row: row.to_array(),
            near: self.view.near,
            far: self.view.far,
            texel_a: a,
            texel_b: b,
            ortho: matches!(self.view.kind, ProjectionKind::Orthographic { .. }) as u32,
            weight: self.weight,
            _pad: [0.0; 2],
            light: self.light.to_array(),
        }
    }
}

/// The views of `count` stratified light samples (1: the light's centre), fitted to `bounds`.
pub fn sample_views(light: &Light, bounds: &Aabb, count: u32) -> Vec<SampleView> {
    let center = bounds.center();
    let axis = light.axis(center);
    let make = |q: LightPoint, weight: f32| SampleView {
        view: View::fit_light(q, axis, bounds),
        weight,
        light: match q {
            LightPoint::Position(p) => p.extend(1.0),
            LightPoint::Direction(d) => d.normalize().extend(0.0),
        },
    };
    if count <= 1 {
        return vec![make(light.center(), 1.0)];
    }
    light
        .stratified_samples(count, center)
        .into_iter()
        .map(|(q, w)| make(q, w))
        .collect()
}

/// Depth maps rendered on the CPU.
pub struct CpuShadowMaps {
    /// One linear depth map per sample.
    pub maps: Vec<Map2D<f32>>,
    /// The samples' views.
    pub views: Vec<SampleView>,
    /// Map side.
    pub resolution: u32,
    /// [`Light::size`] of the light.
    pub light_size: f32,
}

impl CpuShadowMaps {
    /// Rasterizes one depth map per view; `light_size` is [`Light::size`], kept for PCSS.
    pub fn render(
        views: &[SampleView],
        casters: &[[Vec3; 3]],
        resolution: u32,
        light_size: f32,
    ) -> Self {
        let maps = views
            .iter()
            .map(|v| depth_map(&v.view, resolution, casters))
            .collect();
        Self {
            maps,
            views: views.to_vec(),
            resolution,
            light_size,
        }
    }
}
