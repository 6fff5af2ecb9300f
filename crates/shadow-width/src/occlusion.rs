//! The inverted occlusion map: which light-space texels belong to a shadow blocker.
//!
//! The paper renders blockers white and "other objects" black (section 4), which needs the scene
//! to say which objects only receive. Ours does: the light-space maps hold the casters only (the
//! guide's "maps cover what casts"; a ground with nothing below it is a receiver, not a caster),
//! so a texel is *blocked* exactly when a caster covers it.

use soft_shadow_core::Map2D;
use soft_shadow_core::view::NO_OCCLUDER;

/// Whether a texel whose nearest caster lies at linear depth `near` is blocked.
pub(crate) fn is_blocked(near: f32) -> bool {
    near != NO_OCCLUDER
}

/// The inverted occlusion map (`true` = blocked) from the nearest depth map (storage from its
/// pool).
pub(crate) fn occlusion_mask(near: &Map2D<f32>) -> Map2D<bool> {
    near.map(|&d| is_blocked(d))
}
