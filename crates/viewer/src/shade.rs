//! The renderer's shading, in WGSL (`shade.wgsl`) and here in Rust for the CPU comparison:
//! Lambert, one rectangular or triangular area light sampled at 64 stratified points (the
//! centres of an 8x8 grid, warped onto the triangle), each sample's term clipped to the
//! receiver's horizon and to the light's front, times the technique's `V`.

use bytemuck::{Pod, Zeroable};
use glam::Vec3;
use soft_shadow_core::{Light, Result, ShadowError};

/// Light samples per side of the grid.
pub const GRID: u32 = 8;
/// Radiance of the light.
pub const RADIANCE: f32 = 22.0;
/// Ambient term.
pub const AMBIENT: f32 = 0.08;
/// Surface albedo.
pub const ALBEDO: f32 = 0.9;
/// Value of pixels no surface covers.
pub const BACKGROUND: f32 = 0.15;

/// A point of the light from a point of the unit square.
type SquareToLight = Box<dyn Fn(f32, f32) -> Vec3>;

/// The shading pass's uniform, laid out as `Shade` in `shade.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct ShadeUniform {
    /// Light sample positions (xyz).
    pub samples: [[f32; 4]; 64],
    /// Emission normal (xyz), sample count (w).
    pub light_normal: [f32; 4],
    /// Radiance times area over count, ambient, albedo, background.
    pub terms: [f32; 4],
}

impl ShadeUniform {
    /// The uniform of a rectangular or triangular light; other kinds are
    /// [`ShadowError::UnsupportedLight`] (the renderer's shading, not the technique, samples the
    /// light).
    pub fn new(light: &Light) -> Result<Self> {
        light.validate()?;
        // A point of the light from a point of the unit square, its area, its front.
        let (point, area, front): (SquareToLight, f32, Vec3) = match *light {
            Light::Rect {
                center,
                u_half,
                v_half,
            } => (
                Box::new(move |s, t| center + (2.0 * s - 1.0) * u_half + (2.0 * t - 1.0) * v_half),
                4.0 * u_half.cross(v_half).length(),
                u_half.cross(v_half),
            ),
            Light::Triangle { a, b, c } => (
                Box::new(move |s, t| {
                    let r = s.sqrt();
                    a * (1.0 - r) + b * (r * (1.0 - t)) + c * (r * t)
                }),
                0.5 * (b - a).cross(c - a).length(),
                (b - a).cross(c - a),
            ),
            _ => {
                return Err(ShadowError::UnsupportedLight {
                    technique: "example-renderer shading".into(),
                    light: light.kind().name(),
                });
            }
        };
        let mut samples = [[0.0; 4]; 64];
        for j in 0..GRID {
            for i in 0..GRID {
                let (s, t) = (
                    (i as f32 + 0.5) / GRID as f32,
                    (j as f32 + 0.5) / GRID as f32,
                );
                samples[(j * GRID + i) as usize] = point(s, t).extend(1.0).to_array();
            }
        }
        let count = GRID * GRID;
        let normal = front.normalize();
        Ok(Self {
            samples,
            light_normal: normal.extend(count as f32).to_array(),
            terms: [RADIANCE * area / count as f32, AMBIENT, ALBEDO, BACKGROUND],
        })
    }

    /// The light's unshadowed irradiance at `p` with normal `n` (over radiance times area per
    /// sample), as `unshadowed` in `shade.wgsl`.
    pub fn unshadowed(&self, p: Vec3, n: Vec3) -> f32 {
        let ln = Vec3::from_slice(&self.light_normal[..3]);
        let count = (self.light_normal[3] as usize).min(64);
        self.samples[..count]
            .iter()
            .map(|s| {
                let d = Vec3::from_slice(&s[..3]) - p;
                let r2 = d.length_squared().max(1e-8);
                let l = d / r2.sqrt();
                n.dot(l).max(0.0) * (-ln.dot(l)).max(0.0) / r2
            })
            .sum()
    }

    /// The shaded value of a covered pixel (`shade` in `shade.wgsl`), before 8-bit storage.
    pub fn radiance(&self, p: Vec3, n: Vec3, v: f32) -> f32 {
        let [k, ambient, albedo, _] = self.terms;
        (albedo * (ambient + k * self.unshadowed(p, n) * v)).clamp(0.0, 1.0)
    }
}
