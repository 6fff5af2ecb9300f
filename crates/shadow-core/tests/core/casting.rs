//! What casts onto what a camera sees (`coverage::can_shadow`, `coverage::casting_onto`),
//! against the closed form of a box's penumbra reach.

use glam::Vec3;
use soft_shadow_core::coverage::{can_shadow, casting_onto};
use soft_shadow_core::{Aabb, DistantProfile, Light};

/// A 1 m box from 1 m to 2 m over the ground.
fn raised_box() -> Aabb {
    Aabb {
        min: Vec3::new(-0.5, 1.0, -0.5),
        max: Vec3::new(0.5, 2.0, 0.5),
    }
}

/// The triangles of `b`'s faces.
fn triangles(b: &Aabb) -> Vec<[Vec3; 3]> {
    let c = b.corners();
    // Two triangles per face (winding does not matter here), corners indexed by bits x, y, z.
    let quads = [
        [0, 1, 3, 2],
        [4, 5, 7, 6],
        [0, 1, 5, 4],
        [2, 3, 7, 6],
        [0, 2, 6, 4],
        [1, 3, 7, 5],
    ];
    quads
        .iter()
        .flat_map(|q| [[c[q[0]], c[q[1]], c[q[2]]], [c[q[0]], c[q[2]], c[q[3]]]])
        .collect()
}

/// Under a sun straight overhead of angular diameter `a`, the box's shadow on the ground reaches
/// `2 tan(a / 2)` m beyond its outline (from its top, 2 m up). Points within that reach can be
/// shadowed; points beyond it, by more than the test's conservative margin (the octagon around
/// the sun's cone: 1 / cos(pi / 8)), cannot; nor can the box's own top face, turned to the sun.
/// The same for a 0.5 m sphere light 4 m over the box's centre: the reach follows similar
/// triangles through the box's top edge.
#[test]
fn a_box_shadows_what_its_penumbra_reaches_and_nothing_else() {
    let b = raised_box();
    let a = 0.2f32;
    let sun = Light::Distant {
        direction: Vec3::Y,
        angular_diameter: a,
        profile: DistantProfile::UniformDisk,
    };
    let reach = 2.0 * (0.5 * a).tan();
    let margin = 1.0 / (std::f32::consts::PI / 8.0).cos();
    let ground = |x: f32| Vec3::new(0.5 + x, 0.0, 0.0);
    assert!(can_shadow(&sun, &b, ground(-0.3), 0.0), "under the box");
    assert!(
        can_shadow(&sun, &b, ground(0.99 * reach), 0.0),
        "inside the reach"
    );
    assert!(
        !can_shadow(&sun, &b, ground(1.01 * reach * margin), 0.0),
        "beyond the reach"
    );
    assert!(
        !can_shadow(&sun, &b, Vec3::new(0.1, 2.0, 0.1), 0.0),
        "the lit top face"
    );
    assert!(
        can_shadow(&sun, &b, Vec3::new(0.1, 1.0, 0.1), 0.0),
        "the bottom face"
    );
    // A receiver's ball: beyond the reach by less than its radius counts.
    assert!(can_shadow(&sun, &b, ground(reach * margin + 0.2), 0.25));

    let sphere = Light::Sphere {
        center: Vec3::new(0.0, 6.0, 0.0),
        radius: 0.5,
    };
    // The ray from the light's far rim (x = -0.5 at y = 6) over the box's top edge (x = 0.5,
    // y = 2) meets the ground at x = 0.5 + 1 * 2 / 4 = 1.0.
    let local_reach = 0.5;
    assert!(can_shadow(&sphere, &b, ground(0.99 * local_reach), 0.0));
    assert!(!can_shadow(&sphere, &b, ground(1.2 * local_reach), 0.0));
    assert!(!can_shadow(&sphere, &b, Vec3::new(0.1, 2.0, 0.1), 0.0));
}

/// `huge-depth-range`'s case: a 2 cm box near the camera and a 200 m box 5 km away, under a
/// sun; the camera sees the ground around the near box and the far box's face turned to it
/// (lit). Only the near box casts onto what is seen, and the bounds hold it and the ground its
/// shadow reaches, not the far box (before, the maps spanned 5 km and the near box's shadow was
/// a hundredth of a texel at 2048²).
#[test]
fn only_the_casters_that_shadow_what_is_seen_are_kept() {
    let near = Aabb {
        min: Vec3::new(-0.01, 0.0, -0.16),
        max: Vec3::new(0.01, 0.02, -0.14),
    };
    let far = Aabb {
        min: Vec3::new(-100.0, 0.0, -5100.0),
        max: Vec3::new(100.0, 200.0, -4900.0),
    };
    let sun = Light::Distant {
        direction: Vec3::new(0.5, 1.0, 0.3).normalize(),
        angular_diameter: 0.05,
        profile: DistantProfile::UniformDisk,
    };
    let ground = |x: f32, z: f32| {
        [
            Vec3::new(x, 0.0, z),
            Vec3::new(x + 0.05, 0.0, z),
            Vec3::new(x, 0.0, z - 0.05),
        ]
    };
    let receivers: Vec<[Vec3; 3]> = (0..20)
        .flat_map(|i| (0..20).map(move |j| ground(-0.5 + 0.05 * i as f32, -0.05 * j as f32)))
        .collect();
    let seen: Vec<Vec3> = receivers
        .iter()
        .map(|t| (t[0] + t[1] + t[2]) / 3.0)
        // The ground just beside the near box, away from the sun: in its shadow.
        .chain([Vec3::new(-0.015, 0.0, -0.16)])
        .chain((0..10).map(|i| Vec3::new(-90.0 + 20.0 * i as f32, 100.0, -4900.0)))
        .collect();
    let g = casting_onto(&sun, &[triangles(&far), triangles(&near)], receivers, &seen);
    assert_eq!(
        g.casters,
        triangles(&near),
        "only the near box casts onto what is seen"
    );
    assert!(
        g.bounds.diagonal() < 0.3,
        "the bounds hold the near box and the ground by it: {:?}",
        g.bounds
    );
}
