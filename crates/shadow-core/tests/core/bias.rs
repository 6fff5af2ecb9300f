//! Receiver biases: the cap against pushing through resolved gaps, and the signed
//! receiver-plane gradient, checked in closed form on a planar receiver under a distant light.

use glam::Vec3;
use proptest::prelude::*;
use soft_shadow_core::light_space::{DEPTH_SPREAD, MAX_TAN, shadow_coord};
use soft_shadow_core::{Aabb, Bias, Coverage, LightPoint, SampleView, ShadowError};

/// An orthographic map of a 4 m box at the origin for light coming from `to_light`.
fn map(to_light: Vec3, res: u32) -> soft_shadow_core::MapParams {
    let bounds = Aabb {
        min: Vec3::splat(-2.0),
        max: Vec3::splat(2.0),
    };
    SampleView::new(
        LightPoint::Direction(to_light),
        1.0,
        -to_light,
        &Coverage::whole(&bounds),
    )
    .params(res)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// For a planar receiver at angle `theta` to the light, the comparison depth sits in front of
    /// the receiver's own plane (where the map is read) by at least its depth spread across the
    /// texel (no acne) and by at most that spread plus `max_push` texels (no push through a gap
    /// the map resolves); the gradient is the plane's, `tan(theta)` texels of depth per texel.
    #[test]
    fn the_push_clears_the_spread_and_stops_at_the_cap(
        theta in 0.0f32..1.4,
        phi in 0.0f32..std::f32::consts::TAU,
        res in prop::sample::select(vec![16u32, 256, 2048]),
    ) {
        let to_light = Vec3::new(theta.sin() * phi.cos(), theta.cos(), theta.sin() * phi.sin());
        let m = map(to_light, res);
        let p = Vec3::new(0.1, 0.0, -0.2);
        let n = Vec3::Y;
        let c = shadow_coord(&m, &Bias::default(), p, n).expect("inside the map");
        let texel = m.texel_size(m.linear_depth(p));
        let tan = theta.tan().min(MAX_TAN);
        // The receiver's plane where the map is read: along the light from the offset point.
        let p2 = p + n * (Bias::default().normal_offset * texel);
        let plane = m.linear_depth(p2) + Bias::default().normal_offset * texel / theta.cos();
        let push = (plane - c.z) / texel;
        let tol = 1e-3 * (1.0 + tan);
        prop_assert!(push >= DEPTH_SPREAD * tan - tol, "push {push} below the spread");
        prop_assert!(push <= DEPTH_SPREAD * tan + Bias::MAX_PUSH + tol, "push {push} over the cap");
        let grad = c.grad.length() / texel;
        prop_assert!((grad - tan).abs() <= 1e-2 * (1.0 + tan), "gradient {grad} vs tan {tan}");
    }
}

#[test]
fn the_cap_is_what_bounds_the_default_push() {
    // Uncapped, the default terms push by 1/cos + 1 + tan texels: 6.7 at 70 degrees.
    let theta = 70f32.to_radians();
    let b = Bias::default();
    let uncapped = b.with_max_push(f32::INFINITY).push(1.0, theta.cos());
    assert!((uncapped - (1.0 / theta.cos() + 1.0 + theta.tan())).abs() < 1e-4);
    let capped = b.push(1.0, theta.cos());
    assert!((capped - (DEPTH_SPREAD * theta.tan() + Bias::MAX_PUSH)).abs() < 1e-4);
}

#[test]
fn bad_biases_are_named() {
    for (b, name) in [
        (Bias::new(f32::NAN, 1.0, 1.0), "normal_offset"),
        (Bias::new(1.0, -1.0, 1.0), "depth"),
        (Bias::new(1.0, 1.0, f32::INFINITY), "slope"),
        (Bias::default().with_max_push(-1.0), "max_push"),
    ] {
        match b.validate() {
            Err(ShadowError::InvalidParameter(m)) => assert!(m.contains(name), "{m}"),
            other => panic!("{name}: {other:?}"),
        }
    }
    assert!(
        Bias::default()
            .with_max_push(f32::INFINITY)
            .validate()
            .is_ok()
    );
}
