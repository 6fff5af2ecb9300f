//! Light sampling stays on the light's extent (proptest over random lights and sample positions).

use glam::{Vec2, Vec3};
use proptest::prelude::*;
use soft_shadow_core::{DistantProfile, Light, LightPoint};

fn v3() -> impl Strategy<Value = Vec3> {
    (-5.0f32..5.0, -5.0f32..5.0, -5.0f32..5.0).prop_map(|(x, y, z)| Vec3::new(x, y, z))
}

fn pos(q: LightPoint) -> Vec3 {
    match q {
        LightPoint::Position(p) => p,
        LightPoint::Direction(_) => panic!("expected a position"),
    }
}

proptest! {
    #[test]
    fn rect_samples_lie_on_the_rect(c in v3(), a in 0.01f32..3.0, b in 0.01f32..3.0, u in 0.0f32..1.0, v in 0.0f32..1.0) {
        let l = Light::Rect { center: c, u_half: Vec3::X * a, v_half: Vec3::Z * b };
        let p = pos(l.sample(Vec2::new(u, v), Vec3::ZERO).0) - c;
        prop_assert!(p.x.abs() <= a * 1.0001 && p.z.abs() <= b * 1.0001 && p.y.abs() < 1e-5);
    }

    /// A triangle sample lies inside the triangle: its barycentric coordinates are in [0, 1]
    /// and it is in the triangle's plane.
    #[test]
    fn triangle_samples_lie_on_the_triangle(a in v3(), b in v3(), c in v3(), u in 0.0f32..1.0, v in 0.0f32..1.0) {
        let n = (b - a).cross(c - a);
        let longest = (b - a).length().max((c - b).length()).max((a - c).length());
        prop_assume!(n.length() > 0.05 * longest * longest);
        let l = Light::Triangle { a, b, c };
        let p = pos(l.sample(Vec2::new(u, v), Vec3::ZERO).0);
        // Barycentric coordinates from sub-triangle areas (signed along n).
        let bary = [(b, c), (c, a), (a, b)].map(|(x, y)| (x - p).cross(y - p).dot(n) / n.length_squared());
        for w in bary {
            prop_assert!((-1e-4..=1.0 + 1e-4).contains(&w), "{bary:?}");
        }
        prop_assert!(((p - a).dot(n.normalize())).abs() <= 1e-4 * (1.0 + longest));
    }

    #[test]
    fn disk_samples_lie_on_the_disk(c in v3(), n in v3(), r in 0.01f32..3.0, u in 0.0f32..1.0, v in 0.0f32..1.0) {
        prop_assume!(n.length() > 0.1);
        let n = n.normalize();
        let l = Light::Disk { center: c, normal: n, radius: r };
        let p = pos(l.sample(Vec2::new(u, v), Vec3::ZERO).0) - c;
        prop_assert!(p.length() <= r * 1.0001 + 1e-5);
        prop_assert!(p.dot(n).abs() <= 1e-4 * (1.0 + r));
    }

    /// A sphere sample lies on the silhouette disc: on the sphere's tangent cone from the receiver.
    #[test]
    fn sphere_samples_lie_within_the_silhouette_cone(c in v3(), r in 0.05f32..1.0, recv in v3(), u in 0.0f32..1.0, v in 0.0f32..1.0) {
        prop_assume!((recv - c).length() > 1.5 * r);
        let l = Light::Sphere { center: c, radius: r };
        let p = pos(l.sample(Vec2::new(u, v), recv).0);
        let d = (c - recv).length();
        let half = (r / d).asin();
        let ang = (p - recv).normalize().dot((c - recv).normalize()).clamp(-1.0, 1.0).acos();
        prop_assert!(ang <= half * 1.001 + 1e-4);
    }

    #[test]
    fn distant_samples_lie_in_the_cone(d in v3(), diam in 0.001f32..1.0, u in 0.0f32..1.0, v in 0.0f32..1.0, sun in any::<bool>()) {
        prop_assume!(d.length() > 0.1);
        let profile = if sun { DistantProfile::LimbDarkenedSun } else { DistantProfile::UniformDisk };
        let l = Light::Distant { direction: d.normalize(), angular_diameter: diam, profile };
        let (q, w) = l.sample(Vec2::new(u, v), Vec3::ZERO);
        let LightPoint::Direction(dir) = q else { panic!("direction expected") };
        // The angle in f64 by atan2: f32 `acos` near 1 is only good to about 3.5e-4 rad, more
        // than the tolerance (failed at diam 0.0011).
        let (a, b) = (dir.as_dvec3().normalize(), d.as_dvec3().normalize());
        let angle = a.cross(b).length().atan2(a.dot(b));
        prop_assert!(angle <= 0.5 * diam as f64 * 1.001 + 1e-6, "{angle} vs {diam}");
        prop_assert!(w > 0.0 && w <= 1.0);
    }
}

/// Stratified triangle samples are uniform in area: their mean is the centroid, and the
/// share falling in the corner sub-triangle at `a` (vertices `a`, `(a+b)/2`, `(a+c)/2`) is 1/4.
#[test]
fn triangle_samples_are_uniform_in_area() {
    let (a, b, c) = (
        Vec3::ZERO,
        Vec3::new(3.0, 0.0, 0.0),
        Vec3::new(0.5, 0.0, 2.0),
    );
    let l = Light::Triangle { a, b, c };
    let s = l.stratified_samples(4096, Vec3::Y);
    let pts: Vec<Vec3> = s.iter().map(|&(q, _)| pos(q)).collect();
    let mean = pts.iter().copied().sum::<Vec3>() / pts.len() as f32;
    assert!((mean - (a + b + c) / 3.0).length() < 2e-3, "{mean}");
    // Barycentric weight of `a` above 1/2: the corner sub-triangle at `a`, a quarter of the area.
    let n = (b - a).cross(c - a);
    let corner = pts
        .iter()
        .filter(|&&p| (b - p).cross(c - p).dot(n) / n.length_squared() > 0.5)
        .count() as f64
        / pts.len() as f64;
    assert!((corner - 0.25).abs() < 0.01, "{corner}");
}

/// The limb-darkened profile weighs the centre 1 and the limb `1 - u`.
#[test]
fn limb_darkening_weights_follow_the_linear_law() {
    let l = Light::Distant {
        direction: Vec3::Y,
        angular_diameter: 0.1,
        profile: DistantProfile::LimbDarkenedSun,
    };
    let (_, centre) = l.sample(Vec2::new(0.0, 0.3), Vec3::ZERO);
    let (_, limb) = l.sample(Vec2::new(1.0, 0.3), Vec3::ZERO);
    assert!((centre - 1.0).abs() < 1e-6);
    assert!(
        (limb - (1.0 - soft_shadow_core::light::SUN_LIMB_DARKENING_U)).abs() < 1e-3,
        "{limb}"
    );
}
