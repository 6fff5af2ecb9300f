//! Map coordinates in which every supported light is a distant light (the conclusion's
//! perspective warp), and the normalised depths the map stores.
//!
//! - **Distant light** (orthographic map): depth `zeta = z`, the linear depth along the light;
//!   horizontal units are world units; the light's half-angle `a` gives the depth rate
//!   `r = 1 / tan(a)` (section 3).
//! - **Local light** (perspective map from the light's centre): horizontal `X = x / z` (tangent
//!   units) and depth `zeta = -1 / z`. A light point at offset `a` in the eye plane sends rays
//!   that are straight lines `X = X0 - a zeta` here, so a disk of radius `R` facing the axis is
//!   exactly a distant light of "half-angle tangent" `R`: `r = 1 / R`. Straight world edges stay
//!   straight and planes stay planes (the map is a projective transform), so the straight-edge
//!   construction and its bilinear exactness carry over. Spheres (their silhouette disc) and
//!   rectangles (the disk of equal area) are modelled by a facing disk: an approximation. A
//!   sphere faces every receiver with its whole disc, which the map stretches away from its
//!   axis: a receiver's penumbra widens by [`sphere_spread_at`] ([`Warp::spread`]).
//!
//! Both share `r = 2 / size` with [`Light::size`] (`2 tan(a)` or `2 R`). Stored depths are
//! normalised: `n = (zeta - zeta(near)) / (zeta(far) - zeta(near)) * DEPTH_SPAN`, so every depth
//! inside the frustum lies in `[0, DEPTH_SPAN]` and 1 means "nothing" (no occluder, no limit).
//! The near plane is the frustum's (a distant light's starts just before the casters), moved
//! nearer where the frustum is shallower than [`MAX_P_PER_TEXEL`] allows.

use crate::storage::MAX_P;
use bytemuck::{Pod, Zeroable};
use glam::Vec3;
use soft_shadow_core::light_space::{sphere_spread, sphere_spread_at};
use soft_shadow_core::view::NO_OCCLUDER;
use soft_shadow_core::{Light, MapParams};

/// Normalised depth of the far plane; 1 is kept for "none".
pub(crate) const DEPTH_SPAN: f32 = 0.99;
/// Normalised "none": no geometry, edge or lower limit in a texel.
pub(crate) const NONE_DEPTH: f32 = 1.0;
/// Normalised depth of anything in front of the near plane, or at or behind a perspective
/// map's eye plane (linear depth `z <= 0`, where `-1/z` would wrap to the far side): nearer than
/// every occluder, so never shadowed by the map.
pub(crate) const FRONT_DEPTH: f32 = -1.0;
/// Largest ratio of a perspective map's far plane to the near plane its warp starts at. A caster
/// reaching the light's plane pulls the frustum's near plane towards 0, and `-1/z` then spends
/// almost all of the stored range on the first centimetres: every receiver's depth rounds to
/// the same f16 or 8-bit value and the map casts nothing. Depths nearer than `far /
/// MAX_DEPTH_RATIO` store at 0 (`Texel::encode` clamps every depth to `[0, 1]`): nearer than
/// every receiver.
pub(crate) const MAX_DEPTH_RATIO: f32 = 16.0;
/// Largest change of the normalised `p_i` from one texel to the next. `p_i` is stored clamped to
/// `[-MAX_P, MAX_P]`, and bilinear interpolation of clamped values moves an edge's zero crossing
/// by up to half a texel: the texels around an edge (up to a diagonal texel away) must keep their
/// `p_i` unclamped. A map whose depth range is shallower than the depth over which the penumbra
/// grows by a texel (a plate 5 cm over the ground under 25 cm texels) therefore normalises over
/// a deeper range, ending at the same far plane.
pub(crate) const MAX_P_PER_TEXEL: f32 = std::f32::consts::SQRT_2;
/// Most that [`MAX_P_PER_TEXEL`] deepens a map's stored range: a light so small that its
/// penumbra stays under a texel (a hard edge) would otherwise spend every stored step on depths
/// nothing occupies.
pub(crate) const MAX_RANGE_GROWTH: f32 = 16.0;
/// Most a sphere's penumbra widens in a map ([`Warp::spread`]): the stored `p_i` saturates at
/// [`MAX_P`], so a ribbon holds the widened penumbra of every receiver in the normalised range
/// ([`DEPTH_SPAN`]), and a covered texel's `-MAX_P` stays umbra for every receiver below it
/// (stored depths are at least 0), only up to `MAX_P / DEPTH_SPAN`.
pub(crate) const MAX_SPREAD: f32 = MAX_P / DEPTH_SPAN;
/// Depth rate used for a light of size 0 (a hard, antialiased edge).
pub(crate) const MAX_RATE: f32 = 1.0e30;

/// The warp of one map, laid out as `Warp` in the shaders.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable, PartialEq)]
pub(crate) struct Warp {
    /// 1 for an orthographic map (distant light).
    pub ortho: u32,
    /// `zeta` of the near plane.
    pub zeta_near: f32,
    /// `DEPTH_SPAN / (zeta(far) - zeta(near))`.
    pub zeta_scale: f32,
    /// Map units per texel.
    pub unit: f32,
    /// Depth rate `r = 2 / size` (zeta per map unit of horizontal distance from an edge).
    pub rate: f32,
    /// Normalised `p_i` per texel of distance from an edge: `unit * rate * zeta_scale`.
    pub p_per_texel: f32,
    /// Normalised depth of the far plane `zeta` (the deepest receiver).
    pub far_norm: f32,
    /// The most a sphere light's penumbra widens over the map: [`sphere_spread`] at its
    /// corners (1.42 to 2.01 for a cube face, whose corners lie 60 to 76 degrees off its axis),
    /// at most [`MAX_SPREAD`]. Ribbons reach that much farther, and each receiver's penumbra
    /// widens by its own [`sphere_spread_at`], at most this ([`Warp::spread_at`]). Exactly 1
    /// for other lights.
    pub spread: f32,
}

impl Warp {
    /// The warp of map `m` for `light`.
    pub(crate) fn new(m: &MapParams, light: &Light) -> Self {
        let ortho = m.ortho;
        let zeta = |z: f32| if ortho == 1 { z } else { -1.0 / z };
        let near = if ortho == 1 {
            m.near
        } else {
            m.near.max(m.far / MAX_DEPTH_RATIO)
        };
        let unit = if ortho == 1 { m.texel_b } else { m.texel_a };
        let size = light.size();
        let rate = if size > 2.0 / MAX_RATE {
            2.0 / size
        } else {
            MAX_RATE
        };
        let zeta_far = zeta(m.far);
        let fit = DEPTH_SPAN / (zeta_far - zeta(near)).max(f32::MIN_POSITIVE);
        // A map shallower than a texel's penumbra growth stores a deeper range (see
        // `MAX_P_PER_TEXEL`), at most `MAX_RANGE_GROWTH` times its own.
        let zeta_scale = if rate < MAX_RATE {
            fit.min(MAX_P_PER_TEXEL / (unit * rate).max(f32::MIN_POSITIVE))
                .max(fit / MAX_RANGE_GROWTH)
        } else {
            fit
        };
        let zeta_near = zeta_far - DEPTH_SPAN / zeta_scale;
        Self {
            ortho,
            zeta_near,
            zeta_scale,
            unit,
            rate,
            p_per_texel: (unit * rate * zeta_scale).min(MAX_RATE),
            far_norm: DEPTH_SPAN,
            spread: if matches!(light, Light::Sphere { .. }) {
                corner_spread(m)
            } else {
                1.0
            },
        }
    }

    /// How much wider than the map's ribbons model it the penumbra is at receiver `p`: a
    /// sphere's [`sphere_spread_at`], at most [`Warp::spread`]; 1 for other lights.
    pub(crate) fn spread_at(&self, m: &MapParams, p: Vec3) -> f32 {
        if self.spread > 1.0 {
            sphere_spread_at(m, p).min(self.spread)
        } else {
            1.0
        }
    }

    /// `zeta` of a linear depth.
    pub(crate) fn zeta(&self, z: f32) -> f32 {
        if self.ortho == 1 { z } else { -1.0 / z }
    }

    /// Normalised depth of a linear depth, at most [`NONE_DEPTH`] (a linear depth of
    /// [`soft_shadow_core::view::NO_OCCLUDER`] gives it). For caster depths, which lie beyond the near
    /// plane; a receiver's depth goes through [`Warp::receiver_depth`].
    pub(crate) fn normalized(&self, z: f32) -> f32 {
        if z >= NO_OCCLUDER {
            return NONE_DEPTH;
        }
        ((self.zeta(z) - self.zeta_near) * self.zeta_scale).min(NONE_DEPTH)
    }

    /// Normalised depth of a receiver's biased linear depth, in `[FRONT_DEPTH, NONE_DEPTH]`. On a
    /// perspective map a depth at or behind the eye's plane (`z <= 0`: a receiver beside the
    /// light, or pushed there by a bias) is in front of everything: [`FRONT_DEPTH`], not the far
    /// plane that `-1/z` would wrap it to (a false umbra).
    pub(crate) fn receiver_depth(&self, z: f32) -> f32 {
        if self.ortho == 0 && z <= 0.0 {
            return FRONT_DEPTH;
        }
        self.normalized(z).max(FRONT_DEPTH)
    }

    /// The linear depth of a normalised depth (inverse of [`Warp::normalized`] below 1).
    pub(crate) fn linear(&self, n: f32) -> f32 {
        let zeta = n / self.zeta_scale + self.zeta_near;
        if self.ortho == 1 { zeta } else { -1.0 / zeta }
    }

    /// Normalised depth difference that `texels` texels of world size make at linear depth `z`
    /// (tolerances: "near the edge", "a jump in depth").
    pub(crate) fn depth_gap(&self, z: f32, texels: f32) -> f32 {
        if self.ortho == 1 {
            texels * self.unit * self.zeta_scale
        } else {
            // d zeta = dz / z^2 and a texel is unit * z wide: unit / z per texel.
            texels * self.unit / z.max(f32::MIN_POSITIVE) * self.zeta_scale
        }
    }

    /// Half-width in texels of the ribbon of an edge at normalised depth `c`: the widest penumbra
    /// (at the far plane, widened by [`Warp::spread`]), plus two texels so bilinear neighbours
    /// of a penumbra texel carry it.
    pub(crate) fn ribbon_texels(&self, c: f32) -> f32 {
        let depth = (self.far_norm - c).max(0.0) * self.spread;
        (depth / self.p_per_texel.max(f32::MIN_POSITIVE)).min(1.0e6) + 2.0
    }
}

/// [`sphere_spread`] at a perspective map's corners (its square window's half side is
/// `texel_a * resolution / 2` at unit depth), at most [`MAX_SPREAD`]; 1 for an orthographic map.
fn corner_spread(m: &MapParams) -> f32 {
    if m.ortho == 1 {
        return 1.0;
    }
    let half = 0.5 * m.texel_a * m.resolution as f32;
    sphere_spread(1.0 / (1.0 + 2.0 * half * half).sqrt()).min(MAX_SPREAD)
}
