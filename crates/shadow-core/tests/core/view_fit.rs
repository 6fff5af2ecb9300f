//! Light views fitted to what casts: the window and the depth range.

use glam::Vec3;
use soft_shadow_core::light::LightPoint;
use soft_shadow_core::view::View;
use soft_shadow_core::{Aabb, Coverage};

/// A distant light's map spends its depth range on the casters and what lies below them: the
/// near plane lies before every caster and within 1% of the range of the nearest one, the far
/// plane beyond every receiver. A 10 m ground under a 0.5 m box, straight down and tilted. Fitted
/// to the scene's bounding sphere, the near plane would lie 6.9 m above the box straight down
/// (the 8-bit penumbra limit map of Lawlor's Figure 10 reads 20.2 rms at 16² that way, 10.6
/// fitted to the casters, against the published 11.3).
#[test]
fn a_distant_lights_depth_range_starts_at_the_casters() {
    let casters = Aabb {
        min: Vec3::new(-0.25, 0.5, -0.25),
        max: Vec3::new(0.25, 1.0, 0.25),
    };
    let scene = Aabb {
        min: Vec3::new(-5.0, 0.0, -5.0),
        max: Vec3::new(5.0, 1.0, 5.0),
    };
    for dir in [Vec3::Y, Vec3::new(0.3, 1.0, -0.2).normalize()] {
        let coverage = Coverage {
            casters,
            scene,
            light: vec![LightPoint::Direction(dir)],
            region: soft_shadow_core::Region::Whole,
            texels: 0,
        };
        let view = View::fit_light(LightPoint::Direction(dir), -dir, &coverage);
        let depth = |p: Vec3| -view.view.transform_point3(p).z;
        let nearest = casters
            .corners()
            .map(depth)
            .into_iter()
            .fold(f32::MAX, f32::min);
        let deepest = scene
            .corners()
            .map(depth)
            .into_iter()
            .fold(f32::MIN, f32::max);
        assert!(
            view.near < nearest,
            "{dir}: near {} nearest caster {nearest}",
            view.near
        );
        assert!(
            nearest - view.near <= 0.01 * (view.far - nearest) + 1e-6,
            "{dir}: near {} nearest caster {nearest} far {}",
            view.near,
            view.far
        );
        assert!(
            view.far > deepest,
            "{dir}: far {} deepest {deepest}",
            view.far
        );
    }
}
