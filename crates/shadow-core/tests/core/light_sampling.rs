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

/// A sphere's map samples (`Light::map_sample`) lie inside its ball, keep the disc facing
/// `toward` along the axis (the grid's stratification), and over uniform `u` and `s` project
/// along any direction onto the uniform disc: the share inside radius `rho` of the projection
/// is `rho²` (the closed form of a uniform disc) within 0.01, at 0 to 80 degrees off the axis,
/// where the disc facing the axis (`Light::sample`) projects onto the foreshortened ellipse (at
/// 35 degrees 0.60 of it within 0.7 against the disc's 0.49; at 55 degrees 0.95 within 0.9
/// against 0.81; at 80 degrees 0.60 within 0.5 against 0.25).
#[test]
fn a_spheres_map_samples_fill_its_ball_and_project_onto_the_uniform_disc() {
    let (center, radius) = (Vec3::new(0.3, 2.0, -0.4), 0.5);
    let light = Light::Sphere { center, radius };
    let toward = center + Vec3::new(0.4, -3.0, 0.2);
    let w = (center - toward).normalize();
    // `(u, s)` from the R3 sequence (Roberts: the additive recurrence of the plastic number's
    // generalisation), evenly spread in the unit cube.
    let g = 1.220_744_1_f64;
    let alpha = [1.0 / g, 1.0 / (g * g), 1.0 / (g * g * g)];
    let mut points = Vec::new();
    for n in 0..40_000u32 {
        let x = |i: usize| (0.5 + alpha[i] * f64::from(n)).fract() as f32;
        let u = Vec2::new(x(0), x(1));
        let p = pos(light.map_sample(u, x(2), toward).0);
        assert!(
            (p - center).length() <= radius * 1.0001,
            "{p} outside the ball"
        );
        // Along the axis the point is its cell's point of the disc facing `toward`, as seen
        // from far along the same axis (where that disc is the ball's own).
        let flat = pos(light.sample(u, center - w * 1e4).0);
        let across = (p - center) - w * w.dot(p - center);
        let flat_across = (flat - center) - w * w.dot(flat - center);
        assert!((across - flat_across).length() < 1e-3 * radius);
        points.push(p - center);
    }
    let (t, _) = soft_shadow_core::light::orthonormal_basis(w);
    for degrees in [0.0f32, 35.0, 55.0, 80.0] {
        let a = degrees.to_radians();
        // A direction `degrees` off the axis; the projection onto the plane across it.
        let d = w * a.cos() + t * a.sin();
        let (e1, e2) = soft_shadow_core::light::orthonormal_basis(d);
        for rho in [0.3f32, 0.5, 0.7, 0.9] {
            let share = |pts: &mut dyn Iterator<Item = Vec3>| {
                let (mut inside, mut all) = (0usize, 0usize);
                for q in pts {
                    let r = Vec2::new(q.dot(e1), q.dot(e2)).length() / radius;
                    inside += (r <= rho) as usize;
                    all += 1;
                }
                inside as f64 / all as f64
            };
            let ball = share(&mut points.iter().copied());
            let expected = f64::from(rho * rho);
            assert!(
                (ball - expected).abs() < 0.01,
                "{degrees} degrees off the axis: {ball:.4} of the points within {rho} of the \
                 centre, the uniform disc {expected:.4}"
            );
        }
    }
}

/// `map_sample_depth` visits every stratum of `[0, 1)` once for any number of samples, so a
/// set of sphere samples has no lift towards either side (its lifts sum to zero up to the
/// cells' own weights).
#[test]
fn map_sample_depths_are_a_permutation_of_the_strata() {
    for n in 1..=300u32 {
        let mut seen = vec![false; n as usize];
        for k in 0..n {
            let s = soft_shadow_core::light_space::map_sample_depth(k, n);
            let stratum = (s * n as f32 - 0.5).round();
            assert!(
                ((stratum + 0.5) / n as f32 - s).abs() < 1e-6,
                "n {n}: {s} is no stratum's midpoint"
            );
            let stratum = stratum as usize;
            assert!(!seen[stratum], "n {n}: stratum {stratum} twice");
            seen[stratum] = true;
        }
    }
}
