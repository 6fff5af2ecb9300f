//! The visible fraction of the light: equation 1 (inside a soft shadow), the piecewise
//! geometry-clamped `l_g` of section 2.1 and its branch-free form, equation 2.
//!
//! Depths here are the map's normalised depths (see [`crate::warp`]): `z` the receiver, `c` the
//! occluder edge, `g` the upper and `b` the lower geometry limit, `p` the signed penumbra limit
//! `p_i` (negative inside the silhouette, positive outside).

/// Smallest `z - c` divided by; keeps `p / (z - c)` finite at `z = c` (a normal f32 on every GPU).
pub(crate) const MIN_DEPTH_GAP: f32 = 1.0e-30;

/// `sat(x)`: clamp to `[0, 1]`.
pub(crate) fn sat(x: f32) -> f32 {
    x.clamp(0.0, 1.0)
}

/// Equation 1, saturated: `sat(1/2 + 1/2 p / (z - c))`, the fraction of the light's diameter
/// visible at depth `z` below an edge at depth `c` with signed penumbra limit `p`.
///
/// Only meaningful for `z >= c`. At `z = c` it is the limit from below the edge: 1 outside
/// (`p > 0`), 0 inside (`p < 0`) and 1/2 on the edge (`p = 0`).
pub(crate) fn edge_visibility(z: f32, c: f32, p: f32) -> f32 {
    sat(0.5 + 0.5 * p / (z - c).max(MIN_DEPTH_GAP))
}

/// Below the lower limit `b`: inside the silhouette (`p < 0`) the lower layer casts the same
/// inner penumbra from its own depth, `sat(1/2 + 1/2 p / (z - b))`, which is 0 at `b` and
/// opens below it as the edge's own does; outside it (`p >= 0`), the hard shadow 0 (the
/// evaluation does not take that branch: outside the silhouette it softens the lower caster's
/// shadow, `eval::lower_shadow`). At or above `b`, 1 (no limit).
///
/// The paper clamps every receiver below `b` to 0, which assumes that whatever lies below an
/// occluder's back face is in its umbra. A thin occluder under a wide light breaks that: the
/// ground below the bunny's ears, whose back faces lie more than `layer_gap` texels below their
/// edges at 1024², read 0 where the reference reads 0.64-0.68 (dark outlines around the ears'
/// shadows).
pub(crate) fn lower_visibility(z: f32, b: f32, p: f32) -> f32 {
    if z <= b {
        1.0
    } else if p < 0.0 {
        edge_visibility(z, b, p)
    } else {
        0.0
    }
}

/// `l_g` case by case: 1 above the geometry, 0 between it and the edge, otherwise equation 1
/// limited by [`lower_visibility`].
#[cfg(test)]
pub fn clamped_visibility_piecewise(z: f32, c: f32, g: f32, b: f32, p: f32) -> f32 {
    if z < g {
        1.0
    } else if z < c {
        0.0
    } else {
        edge_visibility(z, c, p).min(lower_visibility(z, b, p))
    }
}

/// Equation 2: `sat(min(sat(l), l_b) + 4 (z < g) - 2 (z < c))`, with `l_b` the lower limit's
/// [`lower_visibility`] where the paper has the step `(z <= b) - 1`.
#[cfg(test)]
pub(crate) fn clamped_visibility(z: f32, c: f32, g: f32, b: f32, p: f32) -> f32 {
    limited_visibility(z, c, g, p, lower_visibility(z, b, p))
}

/// Equation 2 with the lower limit's visibility `l_b` given (the evaluation weighs each tap's).
///
/// The step terms are summed first (an exact small integer `k`), so `sat(l + k)` is exactly
/// `l`, 0 or 1 in floating point too: summed left to right, `l + 4` would round `l` away.
pub(crate) fn limited_visibility(z: f32, c: f32, g: f32, p: f32, l_b: f32) -> f32 {
    let step = |t: bool| t as u32 as f32;
    let k = 4.0 * step(z < g) - 2.0 * step(z < c);
    sat(edge_visibility(z, c, p).min(l_b) + k)
}
