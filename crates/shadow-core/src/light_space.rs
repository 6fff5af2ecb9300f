//! Light-space projection shared by every depth-map technique: the per-map parameters that CPU
//! and GPU code read, the views of light samples, and the receiver biases against shadow acne.
//!
//! `gpu/light_space.wgsl` is the same code in WGSL (prepended to the shaders that use it by
//! [`crate::gpu::light_space_shader`]), so both backends project receivers identically.

use crate::coverage::Coverage;
use crate::light::{Light, LightPoint};
use crate::view::{ProjectionKind, View};
use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec2, Vec3, Vec4};

/// Per-map parameters, laid out as `MapView` in `light_space.wgsl`.
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
    /// Map side in texels.
    pub resolution: u32,
    /// Padding to 16 bytes.
    pub _pad: f32,
    /// The light sample: eye position with w = 1 (perspective) or direction to the light with w = 0.
    pub light: [f32; 4],
}

impl MapParams {
    /// Linear depth (distance along the map's axis) of a world point.
    pub fn linear_depth(&self, p: Vec3) -> f32 {
        Vec4::from(self.depth_row).dot(p.extend(1.0))
    }

    /// World size of one texel at linear depth `z`.
    pub fn texel_size(&self, z: f32) -> f32 {
        self.texel_a * z + self.texel_b
    }
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
    /// The view of one light point, covering `coverage` and looking along `axis`.
    pub fn new(q: LightPoint, weight: f32, axis: Vec3, coverage: &Coverage) -> Self {
        Self {
            view: View::fit_light(q, axis, coverage),
            weight,
            light: match q {
                LightPoint::Position(p) => p.extend(1.0),
                LightPoint::Direction(d) => d.normalize().extend(0.0),
            },
        }
    }

    /// The view of the light's centre, covering `coverage`.
    pub fn center(light: &Light, coverage: &Coverage) -> Self {
        Self::new(light.center(), 1.0, light.axis(coverage.center()), coverage)
    }

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
            resolution,
            _pad: 0.0,
            light: self.light.to_array(),
        }
    }
}

/// The views of `count` stratified light samples (1: the light's centre), covering `coverage`.
pub fn sample_views(light: &Light, coverage: &Coverage, count: u32) -> Vec<SampleView> {
    let center = coverage.center();
    let axis = light.axis(center);
    if count <= 1 {
        return vec![SampleView::center(light, coverage)];
    }
    light
        .stratified_samples(count, center)
        .into_iter()
        .map(|(q, w)| SampleView::new(q, w, axis, coverage))
        .collect()
}

/// Receiver biases against self-shadowing, in texels of the map at the receiver's depth.
///
/// The comparison depth of a tap at offset `d` texels is
/// `z(p + n * normal_offset * texel) - texel * (depth + slope * tan(theta) * (1 + |d|))`, with `theta`
/// the angle between the normal and the light (tan clamped to 10): a constant, a slope-scaled and a
/// receiver-plane bias, as engines combine them against acne. Laid out as `Bias` in WGSL.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable, PartialEq)]
pub struct Bias {
    /// Receiver offset along its normal.
    pub normal_offset: f32,
    /// Constant depth bias.
    pub depth: f32,
    /// Scale of the slope term.
    pub slope: f32,
    /// Padding to 16 bytes.
    pub _pad: f32,
}

impl Bias {
    /// A bias with the given normal offset, constant and slope terms.
    pub fn new(normal_offset: f32, depth: f32, slope: f32) -> Self {
        Self {
            normal_offset,
            depth,
            slope,
            _pad: 0.0,
        }
    }
}

impl Default for Bias {
    /// One texel of each term: no acne on the catalogue's `acne` scene at any resolution tested.
    fn default() -> Self {
        Self::new(1.0, 1.0, 1.0)
    }
}

/// A receiver in one map: position in texels, biased comparison depth, slope bias per texel of offset.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShadowCoord {
    /// Position in texels (texel centres at +0.5).
    pub st: Vec2,
    /// Biased linear depth to compare against the map.
    pub z: f32,
    /// Extra bias per texel of tap offset (receiver-plane term).
    pub slope: f32,
    /// Unbiased linear depth of the receiver.
    pub z_receiver: f32,
}

/// The receiver `p` with unit normal `n` in map `m`, or `None` outside the map (lit).
pub fn shadow_coord(m: &MapParams, bias: &Bias, p: Vec3, n: Vec3) -> Option<ShadowCoord> {
    let z = m.linear_depth(p);
    let texel = m.texel_size(z);
    let l = Vec4::from(m.light);
    let to_light = if l.w == 1.0 {
        l.truncate() - p
    } else {
        l.truncate()
    };
    let c = (n.dot(to_light) / to_light.length().max(1e-30))
        .abs()
        .max(0.1);
    let slope = bias.slope * texel * ((1.0 - c * c).max(0.0).sqrt() / c);
    let p2 = p + n * (bias.normal_offset * texel);
    let clip = Mat4::from_cols_array(&m.view_proj) * p2.extend(1.0);
    if clip.w <= 0.0 {
        return None;
    }
    let ndc = Vec2::new(clip.x / clip.w, clip.y / clip.w);
    if ndc.x.abs() > 1.0 || ndc.y.abs() > 1.0 {
        return None;
    }
    let res = m.resolution as f32;
    let st = Vec2::new((ndc.x * 0.5 + 0.5) * res, (0.5 - ndc.y * 0.5) * res);
    Some(ShadowCoord {
        st,
        z: m.linear_depth(p2) - bias.depth * texel - slope,
        slope,
        z_receiver: z,
    })
}
