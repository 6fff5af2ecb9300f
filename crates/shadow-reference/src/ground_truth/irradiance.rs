//! The light's unshadowed irradiance `E0` at a receiver: what a white Lambertian surface there
//! would receive with nothing in the way, the weight of the image error
//! (the harness's `metrics::Shading`).
//!
//! `E0` integrates the emission over the light points that *reach* the receiver (visibility v2:
//! above its tangent plane, on the light's emitting side), with the cosine at the receiver, the
//! cosine at the light for the kinds with an emitting surface, and `1/r²` for local lights. Every
//! light emits one unit of radiance per unit of its measure (area, length, solid angle), so `E0`
//! compares receivers of one scene; the image error only uses `E0 / E0_max`.
//!
//! - **point**: `cos / r²`;
//! - **segment**: `∫ cos / r² dl` in closed form over the part above the tangent plane (a line
//!   of point lights, as Heidrich et al. model it);
//! - **rect, triangle**: Lambert's polygon formula, `½ Σ θ_i (n · γ_i)`, over the polygon clipped
//!   to the tangent plane (exact);
//! - **disk, sphere**: the same over a regular polygon of [`DISC_SIDES`] sides of equal area: the
//!   disk, or the sphere's silhouette disc seen from the receiver;
//! - **distant**: `∫ profile · cos dω` over the cone, [`CONE_SIDE`]² midpoint strata.

use glam::{Vec2, Vec3};
use soft_shadow_core::light::orthonormal_basis;
use soft_shadow_core::{Light, LightPoint};

/// Sides of the equal-area polygon that stands for a disk (0.04% below the disk's `E0` at
/// normal incidence on its axis, where the polygon's rim is farthest from the disk's).
pub const DISC_SIDES: usize = 48;

/// Strata per side of the cone of a distant light.
pub const CONE_SIDE: u32 = 16;

/// Unshadowed irradiance at `p` with unit normal `n` (0 where no light point reaches `p`).
pub fn irradiance(light: &Light, p: Vec3, n: Vec3) -> f32 {
    if !light.emits_towards(p) {
        return 0.0;
    }
    match *light {
        Light::Point { position } => {
            let d = position - p;
            let r2 = d.length_squared();
            if r2 > 0.0 {
                (n.dot(d) / r2.sqrt()).max(0.0) / r2
            } else {
                0.0
            }
        }
        Light::Linear { a, b } => segment(a, b, p, n),
        Light::Rect {
            center,
            u_half,
            v_half,
        } => polygon(
            &[
                center - u_half - v_half,
                center + u_half - v_half,
                center + u_half + v_half,
                center - u_half + v_half,
            ],
            p,
            n,
        ),
        Light::Triangle { a, b, c } => polygon(&[a, b, c], p, n),
        Light::Disk {
            center,
            normal,
            radius,
        } => polygon(&disc(center, normal.normalize(), radius), p, n),
        Light::Sphere { center, radius } => {
            let to_center = center - p;
            let dist = to_center.length();
            if dist <= radius {
                return 0.0;
            }
            let w = to_center / dist;
            let disc_center = center - w * (radius * radius / dist);
            let disc_radius = radius * (1.0 - (radius / dist).powi(2)).max(0.0).sqrt();
            polygon(&disc(disc_center, w, disc_radius), p, n)
        }
        Light::Distant {
            angular_diameter, ..
        } => {
            let solid_angle = std::f32::consts::TAU * 2.0 * (0.25 * angular_diameter).sin().powi(2);
            let count = CONE_SIDE * CONE_SIDE;
            let sum: f64 = (0..count)
                .map(|k| {
                    let u = Vec2::new(
                        ((k % CONE_SIDE) as f32 + 0.5) / CONE_SIDE as f32,
                        ((k / CONE_SIDE) as f32 + 0.5) / CONE_SIDE as f32,
                    );
                    match light.sample(u, p) {
                        (LightPoint::Direction(d), w) => (w * n.dot(d).max(0.0)) as f64,
                        (LightPoint::Position(_), _) => 0.0,
                    }
                })
                .sum();
            (sum / count as f64) as f32 * solid_angle
        }
        other => unreachable!(
            "no closed-form irradiance for {other:?}: a light kind added to soft-shadow-core needs one here"
        ),
    }
}

/// A regular polygon of [`DISC_SIDES`] sides with the area of the disc of centre `c`, unit
/// axis `w` and radius `r`.
fn disc(c: Vec3, w: Vec3, r: f32) -> Vec<Vec3> {
    let (t, b) = orthonormal_basis(w);
    let k = DISC_SIDES as f32;
    let angle = std::f32::consts::TAU / k;
    // Area of the inscribed polygon: k/2 R² sin(2π/k); equal to π r².
    let big = r * (std::f32::consts::TAU / (k * angle.sin())).sqrt();
    (0..DISC_SIDES)
        .map(|i| {
            let phi = angle * i as f32;
            c + (t * phi.cos() + b * phi.sin()) * big
        })
        .collect()
}

/// Lambert's formula for a polygon of unit radiance, clipped to the half-space above `p`'s
/// tangent plane.
fn polygon(vertices: &[Vec3], p: Vec3, n: Vec3) -> f32 {
    // Sutherland-Hodgman against n . (x - p) > 0, in coordinates relative to p (f64: a
    // receiver near the light's plane has long, nearly parallel vectors).
    let rel: Vec<[f64; 3]> = vertices
        .iter()
        .map(|v| (*v - p).to_array().map(f64::from))
        .collect();
    let nd = n.to_array().map(f64::from);
    let h = |v: &[f64; 3]| v[0] * nd[0] + v[1] * nd[1] + v[2] * nd[2];
    let mut clipped: Vec<[f64; 3]> = Vec::with_capacity(rel.len() + 2);
    for i in 0..rel.len() {
        let (a, b) = (rel[i], rel[(i + 1) % rel.len()]);
        let (ha, hb) = (h(&a), h(&b));
        if ha > 0.0 {
            clipped.push(a);
        }
        if (ha > 0.0) != (hb > 0.0) {
            let t = ha / (ha - hb);
            clipped.push([
                a[0] + (b[0] - a[0]) * t,
                a[1] + (b[1] - a[1]) * t,
                a[2] + (b[2] - a[2]) * t,
            ]);
        }
    }
    if clipped.len() < 3 {
        return 0.0;
    }
    let unit = |v: [f64; 3]| {
        let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        [v[0] / l, v[1] / l, v[2] / l]
    };
    let units: Vec<[f64; 3]> = clipped
        .into_iter()
        .filter(|v| v.iter().any(|c| *c != 0.0))
        .map(unit)
        .collect();
    let mut sum = 0.0f64;
    for i in 0..units.len() {
        let (a, b) = (units[i], units[(i + 1) % units.len()]);
        let cross = [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ];
        let s = (cross[0] * cross[0] + cross[1] * cross[1] + cross[2] * cross[2]).sqrt();
        if s <= 0.0 {
            continue;
        }
        let c = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
        let theta = s.atan2(c);
        sum += theta * h(&cross) / s;
    }
    (0.5 * sum.abs()) as f32
}

/// `∫ cos / r² dl` over the part of the segment `a b` above `p`'s tangent plane.
fn segment(a: Vec3, b: Vec3, p: Vec3, n: Vec3) -> f32 {
    let (a, b) = ((a - p).as_dvec3(), (b - p).as_dvec3());
    let n = n.as_dvec3();
    let (ha, hb) = (n.dot(a), n.dot(b));
    if ha <= 0.0 && hb <= 0.0 {
        return 0.0;
    }
    // Clip to the tangent plane.
    let cut = |x: glam::DVec3, y: glam::DVec3, hx: f64, hy: f64| x + (y - x) * (hx / (hx - hy));
    let (a, b) = match (ha > 0.0, hb > 0.0) {
        (true, true) => (a, b),
        (true, false) => (a, cut(a, b, ha, hb)),
        _ => (cut(a, b, ha, hb), b),
    };
    let len = (b - a).length();
    if len <= 0.0 {
        return 0.0;
    }
    let d = (b - a) / len;
    // x(t) = a + t d, t in [0, len]; with s = t + d.a and q = |a|² - (d.a)²:
    // ∫ n.x / |x|³ dt = [(n.a - (n.d)(d.a)) s / (q sqrt(s² + q)) - (n.d) / sqrt(s² + q)].
    let da = d.dot(a);
    let q = (a.length_squared() - da * da).max(1e-300);
    let (h0, hd) = (n.dot(a), n.dot(d));
    let f = |s: f64| {
        let root = (s * s + q).sqrt();
        (h0 - hd * da) * s / (q * root) - hd / root
    };
    (f(len + da) - f(da)).max(0.0) as f32
}

#[cfg(test)]
mod tests {
    use super::*;
    use soft_shadow_core::DistantProfile;

    /// Midpoint-rule `E0` over `side²` points of the light (or `side²` along a segment), for
    /// the closed forms above.
    fn brute(light: &Light, p: Vec3, n: Vec3, side: u32) -> f64 {
        let (measure, normal) = match *light {
            Light::Rect { u_half, v_half, .. } => (
                4.0 * u_half.length() * v_half.length(),
                Some(u_half.cross(v_half).normalize()),
            ),
            Light::Triangle { a, b, c } => (
                0.5 * (b - a).cross(c - a).length(),
                Some((b - a).cross(c - a).normalize()),
            ),
            Light::Linear { a, b } => ((b - a).length(), None),
            _ => unreachable!(),
        };
        let count = side * side;
        let mut sum = 0.0f64;
        for k in 0..count {
            let u = if light.sample_dimension() == 1 {
                Vec2::new((k as f32 + 0.5) / count as f32, 0.5)
            } else {
                Vec2::new(
                    ((k % side) as f32 + 0.5) / side as f32,
                    ((k / side) as f32 + 0.5) / side as f32,
                )
            };
            let LightPoint::Position(q) = light.sample(u, p).0 else {
                unreachable!()
            };
            let d = q - p;
            let r = d.length();
            let cos_r = n.dot(d) / r;
            let cos_l = normal.map_or(1.0, |m| m.dot(-d) / r);
            if cos_r > 0.0 && cos_l > 0.0 {
                sum += (cos_r * cos_l / (r * r)) as f64;
            }
        }
        sum * measure as f64 / count as f64
    }

    #[test]
    fn a_disk_on_its_axis_is_pi_r2_over_h2_plus_r2() {
        let (r, h) = (0.7f32, 1.3f32);
        let light = Light::Disk {
            center: Vec3::new(0.0, h, 0.0),
            normal: Vec3::NEG_Y,
            radius: r,
        };
        let e = irradiance(&light, Vec3::ZERO, Vec3::Y);
        let exact = std::f32::consts::PI * r * r / (h * h + r * r);
        assert!((e / exact - 1.0).abs() < 1e-3, "{e} vs {exact}");
        // Behind the disk's emitting side: nothing.
        assert_eq!(
            irradiance(&light, Vec3::new(0.0, 2.0, 0.0), Vec3::NEG_Y),
            0.0
        );
    }

    #[test]
    fn a_sphere_is_its_silhouette_disc() {
        // A uniform sphere of radius R at distance D on the normal: E = π R² / D².
        let (r, d) = (0.5f32, 3.0f32);
        let light = Light::Sphere {
            center: Vec3::new(0.0, d, 0.0),
            radius: r,
        };
        let e = irradiance(&light, Vec3::ZERO, Vec3::Y);
        let exact = std::f32::consts::PI * r * r / (d * d);
        assert!((e / exact - 1.0).abs() < 1e-3, "{e} vs {exact}");
    }

    #[test]
    fn a_distant_cone_on_the_normal_is_pi_sin2() {
        let half = 0.2f32;
        let light = Light::Distant {
            direction: Vec3::Y,
            angular_diameter: 2.0 * half,
            profile: DistantProfile::UniformDisk,
        };
        let e = irradiance(&light, Vec3::ZERO, Vec3::Y);
        let exact = std::f32::consts::PI * half.sin().powi(2);
        assert!((e / exact - 1.0).abs() < 1e-3, "{e} vs {exact}");
        // Seen at 60 degrees, the cosine.
        let tilted = Vec3::new(60f32.to_radians().sin(), 60f32.to_radians().cos(), 0.0);
        let e60 = irradiance(&light, Vec3::ZERO, tilted);
        assert!((e60 / (0.5 * exact) - 1.0).abs() < 1e-2, "{e60}");
    }

    #[test]
    fn polygons_and_segments_match_the_midpoint_rule_clipped_at_the_horizon() {
        // u x v = X x Z = -Y: emits downwards, towards the receivers.
        let rect = Light::Rect {
            center: Vec3::new(0.3, 1.0, -0.2),
            u_half: Vec3::new(0.6, 0.0, 0.0),
            v_half: Vec3::new(0.0, 0.0, 0.4),
        };
        let tri = Light::Triangle {
            a: Vec3::new(-0.5, 1.2, 0.0),
            b: Vec3::new(0.5, 1.2, 0.0),
            c: Vec3::new(0.0, 1.0, 0.8),
        };
        let tri = if tri.emits_towards(Vec3::ZERO) {
            tri
        } else {
            let Light::Triangle { a, b, c } = tri else {
                unreachable!()
            };
            Light::Triangle { a, b: c, c: b }
        };
        let seg = Light::Linear {
            a: Vec3::new(-1.0, 0.8, 0.1),
            b: Vec3::new(1.2, 1.1, -0.3),
        };
        // Receivers: facing the light, tilted so the horizon cuts it, and nearly grazing.
        let normals = [
            Vec3::Y,
            Vec3::new(0.9, 0.4, 0.0).normalize(),
            Vec3::new(0.0, 0.15, 1.0).normalize(),
            Vec3::new(-1.0, 0.05, 0.2).normalize(),
        ];
        for light in [rect, tri, seg] {
            for n in normals {
                let p = Vec3::new(0.1, 0.0, 0.05);
                let e = irradiance(&light, p, n) as f64;
                let b = brute(&light, p, n, 400);
                assert!(
                    (e - b).abs() <= 2e-3 * b.max(1e-3),
                    "{light:?} n {n}: {e} vs midpoint {b}"
                );
            }
        }
    }

    #[test]
    fn nothing_below_the_horizon() {
        let light = Light::Point {
            position: Vec3::new(0.0, -1.0, 0.0),
        };
        assert_eq!(irradiance(&light, Vec3::ZERO, Vec3::Y), 0.0);
        let seg = Light::Linear {
            a: Vec3::new(-1.0, -0.5, 0.0),
            b: Vec3::new(1.0, -0.2, 0.0),
        };
        assert_eq!(irradiance(&seg, Vec3::ZERO, Vec3::Y), 0.0);
    }
}
