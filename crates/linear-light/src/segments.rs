//! The segments a light is made of: a segment light is one; a triangle area light is its three
//! edges (section 4: "a really crude approximation", since the transition under an area light is
//! a quadratic rational function).
//!
//! Each segment gets its own `N` samples, skins and channels, scaled by its weight; the
//! channels of all segments are then shaded as one list ([`crate::eval`]), so `V` is the
//! weighted mean of the segments' visibilities. A triangle's edges weigh by length (each stands
//! for the strip of the triangle it bounds) and look along the triangle's emitting normal.

use glam::Vec3;
use soft_shadow_core::{Coverage, Light, SceneGeometry};

/// One segment of a light and what it contributes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Segment {
    /// One end.
    pub a: Vec3,
    /// The other end.
    pub b: Vec3,
    /// The direction its maps look along.
    pub axis: Vec3,
    /// Its share of `V`; the weights of a light sum to 1.
    pub weight: f32,
}

/// The segments of `light` (validated): one for a segment light, the three edges of a
/// triangle; none for the other kinds, which the technique does not model (its checks refuse
/// them before a kernel runs).
pub(crate) fn segments(light: &Light, geometry: &SceneGeometry) -> Vec<Segment> {
    let axis = light.axis(Coverage::new(geometry, light).center());
    match *light {
        Light::Linear { a, b } => vec![Segment {
            a,
            b,
            axis,
            weight: 1.0,
        }],
        Light::Triangle { a, b, c } => {
            let v = [a, b, c];
            let lens = [0, 1, 2].map(|k| (v[(k + 1) % 3] - v[k]).length());
            let total: f32 = lens.iter().sum();
            (0..3)
                .map(|k| Segment {
                    a: v[k],
                    b: v[(k + 1) % 3],
                    axis,
                    weight: lens[k] / total,
                })
                .collect()
        }
        _ => Vec::new(),
    }
}
