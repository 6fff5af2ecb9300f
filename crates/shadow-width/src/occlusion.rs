//! The inverted occlusion map: which light-space texels belong to a shadow blocker.
//!
//! The paper renders blockers white and "other objects" black (section 4), which needs the scene
//! to say which objects only receive. Our scenes mark surfaces as casters and receivers, and most
//! surfaces are both (a ground plane casts onto nothing but is flagged as a caster). So a blocker is
//! taken from the geometry itself: a texel is *blocked* when some surface lies in front of the
//! farthest surface along its ray, by more than `layer_gap` texels at that depth. A lone ground
//! plane is one layer (not a blocker); a torus over it is two or more layers (a blocker); a
//! closed object seen where nothing lies behind it still has a front and a back (a blocker). This
//! needs one extra depth pass (farthest surface) and no per-object flags.

use shadow_core::view::NO_OCCLUDER;
use shadow_core::{Map2D, MapParams};

/// Whether a texel with nearest depth `near` and farthest depth `far` is blocked, for a map with
/// parameters `m` and the gap `layer_gap` in texels.
pub fn is_blocked(m: &MapParams, near: f32, far: f32, layer_gap: f32) -> bool {
    near != NO_OCCLUDER && far != NO_OCCLUDER && far - near > layer_gap * m.texel_size(near)
}

/// The inverted occlusion map (`true` = blocked) from the nearest and farthest depth maps.
pub fn occlusion_mask(
    m: &MapParams,
    near: &Map2D<f32>,
    far: &Map2D<f32>,
    layer_gap: f32,
) -> Map2D<bool> {
    let data = near
        .data()
        .iter()
        .zip(far.data())
        .map(|(&n, &f)| is_blocked(m, n, f, layer_gap))
        .collect();
    Map2D::from_vec(near.width(), near.height(), data).unwrap_or_else(|| Map2D::new(0, 0, false))
}
