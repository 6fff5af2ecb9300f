//! A light recast as a kind a technique models, for the hard cases.
//!
//! occlusion-slices models area lights with a position (rect, disk, sphere) and linear-light
//! models segments only, so the hard cases lit by a distant or rect light would say nothing about
//! them. The stability suite and the report run such a technique under the nearest light it does
//! model, with its own reference:
//!
//! - **rect** from a distant light: a square of the same solid angle, facing the scene from
//!   [`DISTANCE_FACTOR`] scene diagonals along the light's direction; from a disk: the square of
//!   equal area in the disk's plane; from a sphere: that of its disc facing the scene; from a
//!   segment: a rect along it, 1% as wide as it is long; from a triangle: the square of equal
//!   area at its centroid in its plane; from a point: a 0.1 mm square (larger far
//!   from the origin, see `point_size`).
//! - **segment** from a rect: its longer mid-line; from a disk, sphere or triangle: the diameter
//!   (of the disc of equal area, for a triangle) across the
//!   direction to the scene; from a distant light: the segment of the same angular length across
//!   the direction, at [`DISTANCE_FACTOR`] scene diagonals; from a point: 0.1 mm long (or more).

use glam::Vec3;
use soft_shadow_core::light::orthonormal_basis;
use soft_shadow_core::{Aabb, Light, LightKind, LightPoint};

/// Distance of a recast distant light, in scene diagonals.
pub const DISTANCE_FACTOR: f32 = 10.0;

/// Side of the recast point light, world units.
const POINT_SIZE: f32 = 1e-4;

/// Side of the recast point light at `center`: [`POINT_SIZE`], or `1e-5` of the centre's largest
/// coordinate when that is larger, so that its ends stay distinct in `f32` far from the origin.
fn point_size(center: Vec3) -> f32 {
    POINT_SIZE.max(1e-5 * center.abs().max_element())
}

/// The kinds tried, in order, when the light's own kind is not modelled.
const PREFERENCE: [LightKind; 2] = [LightKind::Rect, LightKind::Linear];

/// `light` itself when `models(light.kind())`, else the first of rect and segment that `models`
/// accepts, recast as the module describes; `None` when neither is modelled.
pub fn relight(light: &Light, bounds: &Aabb, models: impl Fn(LightKind) -> bool) -> Option<Light> {
    if models(light.kind()) {
        return Some(*light);
    }
    PREFERENCE.iter().find(|&&k| models(k)).map(|&k| match k {
        LightKind::Rect => as_rect(light, bounds),
        _ => as_segment(light, bounds),
    })
}

/// The light's centre, a distant light placed at [`DISTANCE_FACTOR`] diagonals from `bounds`.
fn anchor(light: &Light, bounds: &Aabb) -> Vec3 {
    match *light {
        Light::Distant { direction, .. } => {
            bounds.center() + direction.normalize() * DISTANCE_FACTOR * bounds.diagonal().max(1e-3)
        }
        Light::Point { position } => position,
        Light::Linear { a, b } => 0.5 * (a + b),
        Light::Triangle { a, b, c } => (a + b + c) / 3.0,
        Light::Rect { center, .. } | Light::Disk { center, .. } | Light::Sphere { center, .. } => {
            center
        }
        other => match other.center() {
            LightPoint::Position(c) => c,
            LightPoint::Direction(d) => {
                bounds.center() + d * DISTANCE_FACTOR * bounds.diagonal().max(1e-3)
            }
        },
    }
}

/// Unit vector from the light's centre towards the scene.
fn towards_scene(light: &Light, bounds: &Aabb) -> Vec3 {
    light.axis(bounds.center()).normalize_or(Vec3::NEG_Y)
}

/// A square of half side `half` at `center`, emitting along `facing`.
fn square(center: Vec3, facing: Vec3, half: f32) -> Light {
    let (u, _) = orthonormal_basis(facing);
    // u x v = facing.
    let v = facing.cross(u);
    Light::Rect {
        center,
        u_half: u * half,
        v_half: v * half,
    }
}

fn as_rect(light: &Light, bounds: &Aabb) -> Light {
    let center = anchor(light, bounds);
    let facing = towards_scene(light, bounds);
    let sqrt_pi = std::f32::consts::PI.sqrt();
    match *light {
        Light::Distant {
            angular_diameter, ..
        } => {
            let distance = (center - bounds.center()).length();
            // A disc of radius r has the area of a square of half side r sqrt(pi) / 2.
            let r = distance * (0.5 * angular_diameter).tan();
            square(center, facing, 0.5 * sqrt_pi * r)
        }
        Light::Disk { radius, .. } | Light::Sphere { radius, .. } => {
            square(center, facing, 0.5 * sqrt_pi * radius)
        }
        // The square of equal area: `size` is the diameter of the disc of that area.
        Light::Triangle { .. } => square(center, facing, 0.25 * sqrt_pi * light.size()),
        Light::Linear { a, b } => {
            let along = (b - a).normalize_or(Vec3::X);
            let across = facing.cross(along).normalize_or(orthonormal_basis(along).0);
            let half = 0.5 * (b - a).length();
            // u x v must face the scene: along x (facing x along) = facing, for `facing`
            // across the segment.
            Light::Rect {
                center,
                u_half: along * half,
                v_half: across * (0.01 * half),
            }
        }
        Light::Point { .. } | Light::Rect { .. } => {
            square(center, facing, 0.5 * point_size(center))
        }
        // A kind added later: the square of its size.
        _ => square(
            center,
            facing,
            0.25 * std::f32::consts::PI.sqrt() * light.size(),
        ),
    }
}

fn as_segment(light: &Light, bounds: &Aabb) -> Light {
    let center = anchor(light, bounds);
    let facing = towards_scene(light, bounds);
    let half = match *light {
        Light::Rect { u_half, v_half, .. } => {
            let long = if u_half.length() >= v_half.length() {
                u_half
            } else {
                v_half
            };
            return Light::Linear {
                a: center - long,
                b: center + long,
            };
        }
        Light::Disk { radius, .. } | Light::Sphere { radius, .. } => radius,
        Light::Triangle { .. } => 0.5 * light.size(),
        Light::Distant {
            angular_diameter, ..
        } => (center - bounds.center()).length() * (0.5 * angular_diameter).tan(),
        Light::Point { .. } | Light::Linear { .. } => 0.5 * point_size(center),
        // A kind added later: a segment of its size.
        _ => 0.5 * light.size().max(point_size(center)),
    };
    let (across, _) = orthonormal_basis(facing);
    Light::Linear {
        a: center - across * half,
        b: center + across * half,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit_box() -> Aabb {
        Aabb {
            min: Vec3::splat(-1.0),
            max: Vec3::splat(1.0),
        }
    }

    /// `l` recast as a rect over `b`, valid: its centre and half sides.
    fn as_rect_of(l: &Light, b: &Aabb) -> (Vec3, Vec3, Vec3) {
        let r = relight(l, b, |k| k == LightKind::Rect).unwrap();
        r.validate().unwrap();
        let Light::Rect {
            center,
            u_half,
            v_half,
        } = r
        else {
            panic!("{r:?}")
        };
        (center, u_half, v_half)
    }

    #[test]
    fn a_modelled_light_is_kept() {
        let l = Light::Sphere {
            center: Vec3::Y * 3.0,
            radius: 0.2,
        };
        assert_eq!(relight(&l, &unit_box(), |_| true), Some(l));
        assert_eq!(relight(&l, &unit_box(), |_| false), None);
    }

    #[test]
    fn a_distant_light_becomes_a_square_of_the_same_solid_angle_facing_the_scene() {
        let dir = Vec3::new(1.0, 1.0, 0.0).normalize();
        let theta = 0.05f32;
        let l = Light::Distant {
            direction: dir,
            angular_diameter: theta,
            profile: soft_shadow_core::DistantProfile::UniformDisk,
        };
        let b = unit_box();
        let (center, u_half, v_half) = as_rect_of(&l, &b);
        let d = (center - b.center()).length();
        assert!((d - DISTANCE_FACTOR * b.diagonal()).abs() < 1e-3 * d);
        assert!(u_half.cross(v_half).normalize().dot(-dir) > 0.9999);
        // Solid angle of the square (area / d^2) against the cone's pi (theta / 2)^2.
        let omega = 4.0 * u_half.length() * v_half.length() / (d * d);
        let cone = std::f32::consts::PI * (0.5 * theta).tan().powi(2);
        assert!((omega / cone - 1.0).abs() < 1e-3, "{omega} vs {cone}");
    }

    /// At 3e4 m from the origin a 0.1 mm segment collapses in `f32` (the random-scenes failure
    /// at scale 9.7e3: "segment length must be positive, got 0").
    #[test]
    fn a_point_far_from_the_origin_stays_a_valid_light() {
        let l = Light::Point {
            position: Vec3::new(969.0, 29084.0, -1939.0),
        };
        for k in [LightKind::Linear, LightKind::Rect] {
            relight(&l, &unit_box(), |m| m == k)
                .unwrap()
                .validate()
                .unwrap();
        }
    }

    /// A segment over the scene becomes a thin rect along it that emits towards the scene (it
    /// faced away, lighting nothing: every random scene under a segment light recast to a rect).
    #[test]
    fn a_segment_becomes_a_thin_rect_facing_the_scene() {
        let l = Light::Linear {
            a: Vec3::new(-0.5, 3.0, 0.2),
            b: Vec3::new(0.5, 3.0, 0.2),
        };
        let b = unit_box();
        let (center, u_half, v_half) = as_rect_of(&l, &b);
        let towards = (b.center() - center).normalize();
        assert!(
            u_half.cross(v_half).normalize().dot(towards) > 0.99,
            "the rect emits away from the scene: {u_half} x {v_half}"
        );
        assert!((u_half.length() - 0.5).abs() < 1e-6);
        assert!(v_half.length() < 0.01);
    }

    #[test]
    fn a_rect_becomes_its_longer_mid_line() {
        let l = Light::Rect {
            center: Vec3::Y * 3.0,
            u_half: Vec3::X * 0.5,
            v_half: Vec3::Z * 0.2,
        };
        let s = relight(&l, &unit_box(), |k| k == LightKind::Linear).unwrap();
        assert_eq!(
            s,
            Light::Linear {
                a: Vec3::new(-0.5, 3.0, 0.0),
                b: Vec3::new(0.5, 3.0, 0.0)
            }
        );
    }
}
