//! What a light brings a receiver, unshadowed, as the frame's summed output weighs it: the
//! shadowed irradiance summed over the lights, `Σ E V`, on the CPU ([`shadowed_irradiance`])
//! and on the GPU ([`crate::gpu_irradiance::record_irradiance`], `irradiance.wgsl`, which
//! mirrors [`LightRecord::irradiance`]).
//!
//! A light's `E` is [`crate::budget::irradiance_estimate`] (a point of radiant intensity at the
//! light's centre, as engines weigh lights) faded to 0 at its range ([`range_window`]), so that a
//! ranged light draws no edge where it stops.

use crate::components::{FrameReceivers, LightState, ShadowConfig};
use crate::scene::LightSource;
use bevy_ecs::prelude::*;
use glam::Vec3;
use soft_shadow_core::{Light, LightPoint};

/// How a light's irradiance fades to 0 at its range: `(1 - x²)²` of `x`, the squared distance
/// over the squared range (engines' windowed falloff), 0 from `x = 1` on: 1 at the light, no
/// step at the range, and within 1% of the unwindowed light within a quarter of the range.
pub fn range_window(x: f32) -> f32 {
    let w = (1.0 - x * x).max(0.0);
    w * w
}

/// One light as the GPU frame's irradiance pass reads it (`LightRecord` in `irradiance.wgsl`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct LightRecord {
    /// Centre and 1; for a distant light the unit direction towards it and 0.
    pub position: [f32; 4],
    /// Unit emission normal of a one-sided light (zero: every direction), and the light's size
    /// squared (the least squared distance its irradiance takes).
    pub front: [f32; 4],
    /// Radiant intensity (a distant light's irradiance), one over the range squared (0: no
    /// range), the pass's mode (set by the pass), unused.
    pub terms: [f32; 4],
}

impl LightRecord {
    /// `light` of radiant `intensity` (a distant light: irradiance at normal incidence), faded
    /// to 0 at `range` from its centre (a distant light, or an infinite range, is not; a local
    /// light whose range is 0, negative or not a number reaches nothing, as in the pipeline).
    pub fn new(light: &Light, intensity: f32, range: f32) -> Self {
        match light.center() {
            LightPoint::Direction(d) => Self {
                position: d.normalize().extend(0.0).to_array(),
                front: [0.0; 4],
                terms: [intensity, 0.0, 0.0, 0.0],
            },
            LightPoint::Position(c) => {
                let (intensity, inverse_range2) = match range {
                    r if r == f32::INFINITY => (intensity, 0.0),
                    r if r > 0.0 => (intensity, 1.0 / (r * r)),
                    _ => (0.0, 0.0),
                };
                Self {
                    position: c.extend(1.0).to_array(),
                    front: light
                        .front()
                        .map_or(Vec3::ZERO, |(_, n)| n.normalize())
                        .extend(light.size() * light.size())
                        .to_array(),
                    terms: [intensity, inverse_range2, 0.0, 0.0],
                }
            }
        }
    }

    /// The light of `config` for `light`.
    pub fn of(light: &Light, config: &ShadowConfig) -> Self {
        Self::new(light, config.intensity, config.range)
    }

    /// Its unshadowed irradiance at `p` with unit normal `n` (`light_irradiance` in
    /// `irradiance.wgsl`): [`crate::budget::irradiance_estimate`] times [`range_window`] of
    /// the squared distance over the squared range.
    pub fn irradiance(&self, p: Vec3, n: Vec3) -> f32 {
        let intensity = self.terms[0];
        let position = Vec3::from_slice(&self.position[..3]);
        if self.position[3] == 0.0 {
            return intensity * n.dot(position).max(0.0);
        }
        let d = position - p;
        let d2 = d.length_squared();
        let x = d2 * self.terms[1];
        if x >= 1.0 {
            return 0.0;
        }
        let r2 = d2.max(self.front[3]).max(1e-6);
        let l = d / r2.sqrt();
        let front = Vec3::from_slice(&self.front[..3]);
        let at_light = if front == Vec3::ZERO {
            1.0
        } else {
            (-front.dot(l)).max(0.0)
        };
        intensity * n.dot(l).max(0.0) * at_light / r2 * range_window(x)
    }
}

/// The shadowed irradiance `Σ E V` over the lights at every receiver of the frame's
/// [`FrameReceivers`], from the `V` the last [`crate::FramePipeline::run`] evaluated there
/// ([`LightState::visibility`]; a light without one, that shadowed nothing or was not run,
/// counts `V = 1`): what [`crate::gpu_irradiance::record_irradiance`] writes for the same
/// receivers on the GPU. Every light with a [`LightSource`] and a [`ShadowConfig`] counts.
pub fn shadowed_irradiance(world: &mut World) -> Vec<f32> {
    let Some(frame) = world.get_resource::<FrameReceivers>().cloned() else {
        return Vec::new();
    };
    let n = frame.positions.len().min(frame.normals.len());
    let mut sum = vec![0.0f32; n];
    let mut lights = world.query::<(&LightSource, &ShadowConfig, Option<&LightState>)>();
    for (light, config, state) in lights.iter(world) {
        let record = LightRecord::of(&light.0, config);
        let v = state.map_or(&[][..], |s| &s.visibility[..]);
        for (i, s) in sum.iter_mut().enumerate() {
            let e = record.irradiance(frame.positions[i], frame.normals[i]);
            if e > 0.0 {
                *s += e * v.get(i).copied().unwrap_or(1.0);
            }
        }
    }
    sum
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::budget::irradiance_estimate;

    /// The record's irradiance is the budget's estimate faded by the range window, for every
    /// kind of light, on both sides of its range and of its emitting plane.
    #[test]
    fn a_records_irradiance_is_the_estimate_faded_by_its_range() {
        let lights = [
            Light::Point {
                position: Vec3::new(0.3, 2.0, -0.2),
            },
            Light::Sphere {
                center: Vec3::new(-0.5, 1.5, 0.4),
                radius: 0.3,
            },
            Light::Rect {
                center: Vec3::new(0.0, 2.5, 0.0),
                u_half: Vec3::X * 0.4,
                v_half: Vec3::Z * 0.2,
            },
            Light::Disk {
                center: Vec3::new(1.0, 1.0, 0.0),
                normal: Vec3::new(-1.0, -1.0, 0.0),
                radius: 0.25,
            },
            Light::Linear {
                a: Vec3::new(-1.0, 2.0, 0.0),
                b: Vec3::new(1.0, 2.2, 0.5),
            },
            Light::Distant {
                direction: Vec3::new(0.3, 1.0, 0.2).normalize(),
                angular_diameter: 0.01,
                profile: soft_shadow_core::light::DistantProfile::UniformDisk,
            },
        ];
        let mut rng = soft_shadow_core::rng::SplitMix(7);
        let mut checked = (0, 0);
        for light in &lights {
            let (intensity, range) = (3.0, 4.0);
            let record = LightRecord::new(light, intensity, range);
            for _ in 0..2000 {
                let p = Vec3::new(
                    rng.next_f32() * 8.0 - 4.0,
                    rng.next_f32() * 3.0 - 1.0,
                    rng.next_f32() * 8.0 - 4.0,
                );
                let n = Vec3::new(
                    rng.next_f32() - 0.5,
                    rng.next_f32() - 0.5,
                    rng.next_f32() - 0.5,
                )
                .try_normalize()
                .unwrap_or(Vec3::Y);
                let window = match light.center() {
                    LightPoint::Position(c) => {
                        range_window(c.distance_squared(p) / (range * range))
                    }
                    LightPoint::Direction(_) => 1.0,
                };
                let want = irradiance_estimate(light, intensity, p, n) * window;
                let got = record.irradiance(p, n);
                assert!(
                    (got - want).abs() <= 1e-5 * want.abs().max(1.0),
                    "{light:?} at {p} facing {n}: {got} vs {want}"
                );
                checked.0 += usize::from(want > 0.0);
                checked.1 += usize::from(want == 0.0);
            }
        }
        // Lit and unlit receivers both.
        assert!(checked.0 > 2000 && checked.1 > 2000, "{checked:?}");
        // A local light whose range reaches nothing lights nothing.
        for range in [0.0, -1.0, f32::NAN] {
            let record = LightRecord::new(&lights[0], 3.0, range);
            assert_eq!(record.irradiance(Vec3::ZERO, Vec3::Y), 0.0, "range {range}");
        }
    }
}
