//! The renderer's shading, in WGSL (`shade.wgsl`, `lamps.wgsl`) and here in Rust for the CPU
//! comparison:
//!
//! - one light ([`ShadeUniform`]): Lambert, the light sampled at up to 64 points (rectangles
//!   and triangles at the centres of an 8x8 grid warped onto them, disks on a polar grid,
//!   segments along their length; points and spheres at their centre; a distant light as one
//!   direction), each sample's term clipped to the receiver's horizon and to the light's front,
//!   times the technique's `V`;
//! - many lamps ([`LampShade`]): each lamp's irradiance as the frame pipeline's summed output
//!   weighs it ([`shadow_frame::lighting::LightRecord`], `shadow_frame::lighting` in WGSL),
//!   times its own `V`, summed.

use bytemuck::{Pod, Zeroable};
use glam::Vec3;
use shadow_frame::lighting::LightRecord;
use soft_shadow_core::{Light, LightPoint, Result};

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
/// Irradiance of a distant light on a surface facing it (before albedo).
pub const DISTANT_IRRADIANCE: f32 = 0.9;
/// Emitting area a point light and a segment's unit length stand for, m² (a point light is
/// as bright as a 0.6 m square).
pub const POINT_AREA: f32 = 0.36;

/// The shading pass's uniform, laid out as `Shade` in `shade.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct ShadeUniform {
    /// Light sample positions (xyz, w = 1), or for a distant light the unit direction towards
    /// it (w = 0).
    pub samples: [[f32; 4]; 64],
    /// Emission normal (xyz; zero where the light emits the same way in every direction),
    /// sample count (w).
    pub light_normal: [f32; 4],
    /// Radiance times area over count, ambient, albedo, background.
    pub terms: [f32; 4],
}

/// Sample points of `light` (xyz, w = 1 for a position, 0 for a direction), its emitting area
/// (or what stands for it) and its emission normal (zero: every direction).
fn light_samples(light: &Light) -> (Vec<[f32; 4]>, f32, Vec3) {
    let grid = |f: &dyn Fn(f32, f32) -> Vec3| -> Vec<[f32; 4]> {
        (0..GRID * GRID)
            .map(|k| {
                let (i, j) = (k % GRID, k / GRID);
                let (s, t) = (
                    (i as f32 + 0.5) / GRID as f32,
                    (j as f32 + 0.5) / GRID as f32,
                );
                f(s, t).extend(1.0).to_array()
            })
            .collect()
    };
    match *light {
        Light::Rect {
            center,
            u_half,
            v_half,
        } => (
            grid(&|s, t| center + (2.0 * s - 1.0) * u_half + (2.0 * t - 1.0) * v_half),
            4.0 * u_half.cross(v_half).length(),
            u_half.cross(v_half).normalize(),
        ),
        Light::Triangle { a, b, c } => (
            grid(&|s, t| {
                let r = s.sqrt();
                a * (1.0 - r) + b * (r * (1.0 - t)) + c * (r * t)
            }),
            0.5 * (b - a).cross(c - a).length(),
            (b - a).cross(c - a).normalize(),
        ),
        Light::Disk {
            center,
            normal,
            radius,
        } => {
            let (u, v) = normal.any_orthonormal_pair();
            (
                grid(&|s, t| {
                    let (r, a) = (radius * s.sqrt(), std::f32::consts::TAU * t);
                    center + r * (a.cos() * u + a.sin() * v)
                }),
                std::f32::consts::PI * radius * radius,
                normal,
            )
        }
        Light::Linear { a, b } => (
            (0..GRID * GRID)
                .map(|k| {
                    let s = (k as f32 + 0.5) / (GRID * GRID) as f32;
                    a.lerp(b, s).extend(1.0).to_array()
                })
                .collect(),
            POINT_AREA * (b - a).length(),
            Vec3::ZERO,
        ),
        Light::Point { position } => (
            vec![position.extend(1.0).to_array()],
            POINT_AREA,
            Vec3::ZERO,
        ),
        Light::Sphere { center, radius } => (
            vec![center.extend(1.0).to_array()],
            std::f32::consts::PI * radius * radius,
            Vec3::ZERO,
        ),
        Light::Distant { direction, .. } => (
            vec![direction.normalize().extend(0.0).to_array()],
            DISTANT_IRRADIANCE / RADIANCE,
            Vec3::ZERO,
        ),
        // A kind added later: shaded as a point at its centre (or the sun along its direction).
        other => match other.center() {
            LightPoint::Position(p) => (vec![p.extend(1.0).to_array()], POINT_AREA, Vec3::ZERO),
            LightPoint::Direction(d) => (
                vec![d.extend(0.0).to_array()],
                DISTANT_IRRADIANCE / RADIANCE,
                Vec3::ZERO,
            ),
        },
    }
}

impl ShadeUniform {
    /// The uniform of `light` (an invalid light is the light's own error).
    pub fn new(light: &Light) -> Result<Self> {
        light.validate()?;
        let (points, area, normal) = light_samples(light);
        let mut samples = [[0.0; 4]; 64];
        samples[..points.len()].copy_from_slice(&points);
        let count = points.len() as f32;
        Ok(Self {
            samples,
            light_normal: normal.extend(count).to_array(),
            terms: [RADIANCE * area / count, AMBIENT, ALBEDO, BACKGROUND],
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
                if s[3] == 0.0 {
                    return n.dot(Vec3::from_slice(&s[..3])).max(0.0);
                }
                let d = Vec3::from_slice(&s[..3]) - p;
                let r2 = d.length_squared().max(1e-8);
                let l = d / r2.sqrt();
                let front = if ln == Vec3::ZERO {
                    1.0
                } else {
                    (-ln.dot(l)).max(0.0)
                };
                n.dot(l).max(0.0) * front / r2
            })
            .sum()
    }

    /// The shaded value of a covered pixel (`shade` in `shade.wgsl`), before 8-bit storage.
    pub fn radiance(&self, p: Vec3, n: Vec3, v: f32) -> f32 {
        let [k, ambient, albedo, _] = self.terms;
        (albedo * (ambient + k * self.unshadowed(p, n) * v)).clamp(0.0, 1.0)
    }
}

/// Ambient term of the lamps' shading.
pub const LAMP_AMBIENT: f32 = 0.04;

/// The brightness the exposure gives the 95th percentile of the unshadowed lighting.
pub const EXPOSED: f32 = 0.85;

/// The lamps pass's display uniform, laid out as `LampsDisplay` in `lamps.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct LampsDisplay {
    /// Lamps in the lamps buffer.
    pub count: u32,
    /// 0: shaded; 1: the lamps' `V` weighed by their light.
    pub mode: u32,
    /// Padding.
    pub pad: [u32; 2],
    /// Exposure, ambient, albedo, background.
    pub terms: [f32; 4],
}

/// The lamps' shading (`lamps.wgsl`), in Rust for the CPU comparison.
#[derive(Clone, Debug, PartialEq)]
pub struct LampShade {
    /// Every lamp, in layer order.
    pub lamps: Vec<LightRecord>,
    /// What the summed lighting is multiplied by before albedo.
    pub exposure: f32,
}

impl LampShade {
    /// The lighting at `p` with normal `n`, unshadowed and with lamp `k` shadowed by `v(k)`.
    pub fn lighting(&self, p: Vec3, n: Vec3, v: impl Fn(usize) -> f32) -> (f32, f32) {
        let (mut lit, mut shadowed) = (0.0, 0.0);
        for (k, lamp) in self.lamps.iter().enumerate() {
            let e = lamp.irradiance(p, n);
            if e > 0.0 {
                lit += e;
                shadowed += e * v(k);
            }
        }
        (lit, shadowed)
    }

    /// The shaded value of a covered pixel, before 8-bit storage.
    pub fn radiance(&self, p: Vec3, n: Vec3, v: impl Fn(usize) -> f32) -> f32 {
        let (_, shadowed) = self.lighting(p, n, v);
        (ALBEDO * (LAMP_AMBIENT + self.exposure * shadowed)).clamp(0.0, 1.0)
    }

    /// The exposure that shows the 95th percentile of the unshadowed lighting over `frame`'s
    /// receivers (`positions` and `normals`) at [`EXPOSED`] (1 where nothing is lit).
    pub fn expose(&mut self, positions: &[Vec3], normals: &[Vec3]) {
        let mut lit: Vec<f32> = positions
            .iter()
            .zip(normals)
            .map(|(&p, &n)| self.lighting(p, n, |_| 1.0).0)
            .filter(|&e| e > 0.0)
            .collect();
        lit.sort_by(f32::total_cmp);
        self.exposure = match lit.get(lit.len() * 95 / 100) {
            Some(&e) if e > 0.0 => EXPOSED / e,
            _ => 1.0,
        };
    }
}
