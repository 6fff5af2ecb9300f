//! The slicing frame of section 3.4: a centre of projection (COP) at distance `d` behind the
//! light, a frustum through the light's rectangle that contains the casters and the penumbra they
//! can throw on the scene, and `n` slice planes parallel to the light.
//!
//! Coordinates: `h` is the distance from the light's plane along its emission normal, `x` and
//! `y` run along the frustum's image axes from the light's centre. The frustum's half extents at
//! depth `h` are `a (d + h) / d`, so the light's rectangle is exactly its cross-section at `h = 0`.
//!
//! Slice planes sit at `p_k = near + k t`, `k = 0..n`, with `p_0` the nearest caster and
//! `p_{n-1}` the farthest. Slice `k` holds the geometry in `(p_{k-1}, p_k]`, projected through the
//! COP onto its lower plane `p_k` (the one farther from the light), so a planar occluder at the
//! nearest depth lands on its own plane and is filtered exactly (section 3.1).

use bytemuck::{Pod, Zeroable};
use glam::{Vec2, Vec3};
use soft_shadow_core::light::orthonormal_basis;
use soft_shadow_core::light_space::sphere_spread;
use soft_shadow_core::view::{ProjectionKind, View, look_to_up};
use soft_shadow_core::{Light, LightPoint, Region, SceneGeometry};

/// Fraction of a slice's thickness beyond a plane that still counts as on it (rasterized
/// depths carry rounding; a surface exactly on a plane must not flicker between two slices).
pub(crate) const SLICE_TOLERANCE: f32 = 1e-3;

/// The steps a slab's depth is kept in per texel ([`Frame::top_code`]): codes 1 to 255 in the
/// 8-bit channels the GPU slices are drawn into.
pub(crate) const TOP_STEPS: f32 = 254.0;

/// Casters nearer the light's plane than this fraction of the farthest caster do not widen the
/// frustum (a wall through the light's plane would otherwise ask for a 180-degree field of view);
/// the penumbra they throw from this depth on does (the casters' box clipped to it).
const FIT_FLOOR: f32 = 0.02;

/// The frustum's apex lies at least this fraction of the light's shorter half side behind the
/// light's plane (a half-angle of at most 89.4 degrees across it). Relative to the light, not
/// to the casters' depth: a 1 mm light 93 m above its casters needs its apex 2 mm behind it to
/// hold casters 30 m to the side, which a floor of 1e-4 of the depth (9 mm) pushed out of the
/// frustum.
const MIN_APEX: f32 = 0.01;

/// The slicing frame, laid out as `Frame` in `frame.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable, PartialEq)]
pub(crate) struct Frame {
    /// World to clip of the COP's view (reversed Z), column-major.
    pub view_proj: [f32; 16],
    /// Light centre (xyz).
    pub center: [f32; 4],
    /// Unit image x axis (xyz).
    pub axis_x: [f32; 4],
    /// Unit image y axis (xyz, up in the image).
    pub axis_y: [f32; 4],
    /// Unit emission normal (xyz), towards the scene; `w` is 1 for a sphere light, whose
    /// kernels widen off the normal ([`Frame::kernel`]), 0 otherwise.
    pub normal: [f32; 4],
    /// Light half extent along `axis_x`.
    pub half_x: f32,
    /// Light half extent along `axis_y`.
    pub half_y: f32,
    /// Distance of the COP behind the light's plane.
    pub d: f32,
    /// Depth `p_0` of the first slice plane.
    pub near: f32,
    /// Distance `t` between slice planes.
    pub spacing: f32,
    /// Number of slices.
    pub slices: u32,
    /// Texture side in texels.
    pub resolution: u32,
    /// 1 when the scene has casters in front of the light.
    pub occupied: u32,
    /// Near clip distance of the COP's view.
    pub clip_near: f32,
    /// Far clip distance of the COP's view.
    pub clip_far: f32,
    /// 1 with the thin-occluder fix: a fragment also fills the next slice.
    pub thin_fix: u32,
    /// [`crate::OcclusionSlices::fade_texels`].
    pub fade_texels: f32,
}

/// A receiver seen from the light: `x, y` along the image axes, `h` along the normal.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct LightCoord {
    /// Along `axis_x`.
    pub x: f32,
    /// Along `axis_y`.
    pub y: f32,
    /// Distance from the light's plane.
    pub h: f32,
}

/// The rectangle a light is sliced with: centre, normal and two half axes. A disk becomes the
/// square of equal area, a sphere its silhouette disc facing the scene's centre, then that square,
/// a triangle the square of equal area at its centroid in its plane. For a cube face
/// ([`Region::Face`]) the rectangle faces the face's axis: a sphere's square, or the bounding
/// rectangle of the light's outline as the face's receivers see it: projected along the axis
/// for the face in front of a one-sided light, and for a face beside it along the direction
/// halfway through its lit part (67.5 degrees from the light's normal; a side face spans 45 to
/// 90 degrees), where the light is foreshortened to 0.38 of its width.
pub(crate) fn light_rect(
    light: &Light,
    scene_center: Vec3,
    region: Region,
) -> Option<(Vec3, Vec3, Vec3)> {
    let square = |center: Vec3, normal: Vec3, radius: f32| {
        let (t, b) = orthonormal_basis(normal);
        let half = 0.5 * radius * std::f32::consts::PI.sqrt();
        (center, t * half, b * half)
    };
    if let Region::Face { axis, up, .. } = region {
        let right = up.cross(axis);
        let LightPoint::Position(center) = light.center() else {
            return None;
        };
        if let Light::Sphere { radius, .. } = *light {
            let half = 0.5 * radius * std::f32::consts::PI.sqrt();
            return Some((center, right * half, up * half));
        }
        // The direction the face's receivers see the light along.
        let along = match light.front() {
            Some((_, n)) if n.normalize().dot(axis).abs() < 0.5 => {
                let t = 67.5f32.to_radians();
                axis * t.sin() + n.normalize() * t.cos()
            }
            _ => axis,
        };
        let (mut hx, mut hy) = (0.0f32, 0.0f32);
        for q in light.outline(center + axis) {
            if let LightPoint::Position(q) = q {
                let q = q - center;
                let q = q - along * (q.dot(axis) / along.dot(axis));
                hx = hx.max(q.dot(right).abs());
                hy = hy.max(q.dot(up).abs());
            }
        }
        let floor = 1e-3 * light.size().max(1e-6);
        return Some((center, right * hx.max(floor), up * hy.max(floor)));
    }
    match *light {
        Light::Rect {
            center,
            u_half,
            v_half,
        } => Some((center, u_half, v_half)),
        Light::Disk {
            center,
            normal,
            radius,
        } => Some(square(center, normal.normalize(), radius)),
        Light::Sphere { center, radius } => Some(square(center, light.axis(scene_center), radius)),
        Light::Triangle { a, b, c } => Some(square(
            (a + b + c) / 3.0,
            light.axis(scene_center),
            0.5 * light.size(),
        )),
        _ => None,
    }
}

impl Frame {
    /// Fits the frame of `t` (its slices, fix and fade) to `geometry`'s casters for `light` (a
    /// rect, disk or sphere) at texture side `resolution`, within one view's `region`: a cube
    /// face's frustum is no wider than the face's window.
    pub(crate) fn fit(
        light: &Light,
        geometry: &SceneGeometry,
        t: &crate::OcclusionSlices,
        resolution: u32,
        region: Region,
    ) -> Frame {
        let slices = t.slices;
        let (center, u_half, v_half) = light_rect(
            light,
            soft_shadow_core::Coverage::new(geometry, light).center(),
            region,
        )
        .unwrap_or((Vec3::ZERO, Vec3::X, Vec3::Z));
        let normal = u_half.cross(v_half).normalize();
        let up = v_half.normalize();
        let look = look_to_up(center, normal, up);
        let axis_x = look.row(0).truncate();
        let axis_y = look.row(1).truncate();
        let half_x = u_half.dot(axis_x).abs() + v_half.dot(axis_x).abs();
        let half_y = u_half.dot(axis_y).abs() + v_half.dot(axis_y).abs();
        let depth = |p: Vec3| (p - center).dot(normal);
        let (mut lo, mut hi) = (f32::INFINITY, f32::NEG_INFINITY);
        for t in &geometry.casters {
            let h = t.map(depth);
            let max = h[0].max(h[1]).max(h[2]);
            if max > 0.0 {
                hi = hi.max(max);
                lo = lo.min(h[0].min(h[1]).min(h[2]));
            }
        }
        let occupied = hi > 0.0 && hi.is_finite();
        let (near, far) = if occupied {
            (lo.max(1e-4 * hi), hi)
        } else {
            (1.0, 2.0)
        };
        let spacing = ((far - near) / (slices - 1) as f32).max(1e-6 * far);
        // The penumbra on the receivers: from every corner of the casters' box, away from every
        // corner of the light's rectangle, down to the deepest geometry, clamped into the scene.
        // A receiver outside the frustum has kernels that leave the slices (section 3.1's
        // pyramid only stays inside for points inside the frustum), so it must be covered too.
        // A sphere's kernels widen off the normal (`Frame::kernel`) beyond this outline: their
        // outer edge can reach past the frustum, where the slices read empty.
        let casters = soft_shadow_core::Aabb::of_triangles(&geometry.casters);
        let scene = geometry.bounds;
        let deepest = scene.corners().iter().map(|c| depth(*c)).fold(hi, f32::max);
        let mut penumbra = Vec::new();
        if occupied && !scene.is_empty() {
            // The casters' box clipped to the floor: where it crosses the plane `FIT_FLOOR *
            // far`, the points on its edges there cast too (a wall through the light's plane
            // shadows the ground behind it from just below that plane).
            let corners = casters.corners();
            let floor = FIT_FLOOR * far;
            let mut sources = corners.to_vec();
            for (i, a) in corners.iter().enumerate() {
                for b in &corners[i + 1..] {
                    let (ha, hb) = (depth(*a), depth(*b));
                    let one_axis = (*a - *b).abs().cmpgt(Vec3::ZERO).bitmask().count_ones() == 1;
                    if one_axis && (ha - floor) * (hb - floor) < 0.0 {
                        sources.push(a.lerp(*b, (floor - ha) / (hb - ha)));
                    }
                }
            }
            for c in sources {
                for (su, sv) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                    let dir = c - (center + su * u_half + sv * v_half);
                    let down = dir.dot(normal);
                    if down > 1e-6 * dir.length() {
                        let x = c + dir * ((deepest - depth(c)).max(0.0) / down);
                        penumbra.push(x.clamp(scene.min, scene.max));
                    }
                }
            }
        }
        // The largest d that keeps every caster vertex (beyond the floor) and the penumbra's
        // extent inside the frustum.
        let mut d = 100.0 * far;
        for p in geometry.casters.iter().flatten().chain(&penumbra) {
            let h = depth(*p);
            if h < FIT_FLOOR * far {
                continue;
            }
            let q = *p - center;
            for (a, c) in [(half_x, q.dot(axis_x).abs()), (half_y, q.dot(axis_y).abs())] {
                if c > a {
                    d = d.min(a * h / (c - a));
                }
            }
        }
        // A cube face: no wider than its window (what lies beyond is another face's).
        if let Region::Face { half_angle, .. } = region {
            d = d.max(half_x.max(half_y) / half_angle.tan());
        }
        let mut frame = Frame {
            view_proj: [0.0; 16],
            center: center.extend(1.0).to_array(),
            axis_x: axis_x.extend(0.0).to_array(),
            axis_y: axis_y.extend(0.0).to_array(),
            normal: normal
                .extend(if matches!(light, Light::Sphere { .. }) {
                    1.0
                } else {
                    0.0
                })
                .to_array(),
            half_x,
            half_y,
            d: (0.98 * d).max(MIN_APEX * half_x.min(half_y)),
            near,
            spacing,
            slices,
            resolution,
            occupied: occupied as u32,
            clip_near: 0.0,
            clip_far: 0.0,
            thin_fix: t.thin_fix as u32,
            fade_texels: t.fade_texels,
        };
        let first = (near - spacing).max(0.0);
        frame.clip_near = (frame.d + first) * 0.999;
        frame.clip_far = (frame.d + far + spacing) * 1.001;
        frame.view_proj = frame.view().view_projection().to_cols_array();
        frame
    }

    /// The COP's view, as the slicing pass rasterizes it.
    pub(crate) fn view(&self) -> View {
        let normal = Vec3::from_slice(&self.normal[..3]);
        let cop = Vec3::from_slice(&self.center[..3]) - normal * self.d;
        View {
            view: look_to_up(cop, normal, Vec3::from_slice(&self.axis_y[..3])),
            kind: ProjectionKind::Perspective {
                fov: 2.0 * (self.half_y / self.d).atan(),
            },
            near: self.clip_near,
            far: self.clip_far,
            aspect: self.half_x / self.half_y,
        }
    }

    /// Depth `p_k` of slice plane `k`.
    pub(crate) fn plane(&self, k: u32) -> f32 {
        self.near + k as f32 * self.spacing
    }

    /// The slice of a fragment at COP view depth `z` (`z = d + h`).
    pub(crate) fn slice_of(&self, z: f32) -> u32 {
        let h = z - self.d;
        let v = (h - self.near) / self.spacing - SLICE_TOLERANCE;
        // ceil(v) clamped to [0, slices - 1] (NaN: 0), without `f32::ceil`: SSE2 has no rounding
        // instruction, so that is a libm call per fragment. Below `last`, `v as u32` is floor(v).
        let last = self.slices - 1;
        if v.is_nan() || v <= 0.0 {
            return 0;
        }
        if v >= last as f32 {
            return last;
        }
        let t = v as u32;
        t + ((t as f32) < v) as u32
    }

    /// The top code of a fragment at depth `h` in slice `k`: where in the slab it lies, 255 at
    /// the slab's upper plane `p_k - t` down to 1 at its lower plane `p_k` (0 is an empty
    /// texel), rounded down the slab so that [`Frame::top_depth`] puts no surface nearer the
    /// light than it is (but by the slice's tolerance, [`SLICE_TOLERANCE`], where a fragment
    /// just beyond the lower plane is clamped onto it). The larger of two codes is the nearer fragment: the slicing pass's
    /// `Max` blend keeps each texel's topmost fragment per slice.
    pub(crate) fn top_code(&self, k: u32, h: f32) -> u8 {
        let u = ((h - (self.plane(k) - self.spacing)) / self.spacing).clamp(0.0, 1.0);
        // `u` NaN (a NaN depth): the top of the slab, as the thin-occluder fix marks.
        let steps = (u * TOP_STEPS).ceil();
        if steps.is_nan() {
            255
        } else {
            255 - steps as u8
        }
    }

    /// The depth a [`Frame::top_code`] of slice `k` stands for (at or below the fragment's).
    pub(crate) fn top_depth(&self, k: u32, code: u8) -> f32 {
        self.plane(k) - self.spacing + (255 - code) as f32 / TOP_STEPS * self.spacing
    }

    /// A world point in light coordinates.
    pub(crate) fn light_coord(&self, p: Vec3) -> LightCoord {
        let q = self.direction(p - Vec3::from_slice(&self.center[..3]));
        LightCoord {
            x: q.x,
            y: q.y,
            h: q.z,
        }
    }

    /// A world direction in light coordinates (`x, y, h` as [`LightCoord`]).
    pub(crate) fn direction(&self, v: Vec3) -> Vec3 {
        Vec3::new(
            v.dot(Vec3::from_slice(&self.axis_x[..3])),
            v.dot(Vec3::from_slice(&self.axis_y[..3])),
            v.dot(Vec3::from_slice(&self.normal[..3])),
        )
    }

    /// The point at depth `h` that the COP projects to continuous texel position `t` (the
    /// inverse of [`Frame::kernel`]'s centre), in light coordinates.
    pub(crate) fn texel_point(&self, t: Vec2, h: f32) -> LightCoord {
        let resolution = self.resolution as f32;
        let scale = 2.0 * (self.d + h) / self.d;
        LightCoord {
            x: (t.x / resolution - 0.5) * scale * self.half_x,
            y: (0.5 - t.y / resolution) * scale * self.half_y,
            h,
        }
    }

    /// World size of a texel of the frustum at depth `h`.
    pub(crate) fn texel_size(&self, h: f32) -> f32 {
        2.0 * self.half_x * (self.d + h) / (self.d * self.resolution as f32)
    }

    /// The kernel of section 3.1 for a receiver at `c` on plane depth `p < c.h`: the centre in
    /// continuous texel coordinates (texel `i` covers `[i, i + 1)`) and the side in texels of the
    /// intersection of the plane with the pyramid from the receiver to the light, widened by
    /// `widen`, the receiver's [`Frame::spread`] (computed once per receiver).
    pub(crate) fn kernel(&self, c: LightCoord, p: f32, widen: f32) -> (Vec2, f32) {
        let along = p / c.h;
        let z = self.d + p;
        let resolution = self.resolution as f32;
        let sx = self.d / (self.half_x * z);
        let sy = self.d / (self.half_y * z);
        let center = Vec2::new(
            (c.x * along * sx * 0.5 + 0.5) * resolution,
            (0.5 - c.y * along * sy * 0.5) * resolution,
        );
        (center, (1.0 - along) * self.d / z * resolution * widen)
    }

    /// How much wider than the light's rectangle a receiver at `c` sees the light: a sphere's
    /// square faces the normal, and the receiver sees the sphere's whole disc facing it, so its
    /// kernels grow by [`sphere_spread`] of its angle off the normal; 1 for the other lights.
    pub(crate) fn spread(&self, c: LightCoord) -> f32 {
        let length = (c.x * c.x + c.y * c.y + c.h * c.h).sqrt();
        if self.normal[3] == 1.0 && length > 0.0 {
            sphere_spread(c.h / length)
        } else {
            1.0
        }
    }

    /// Weight of slice `k` for a receiver at depth `h`: 0 while the receiver lies above the
    /// slice's lower plane (in it or nearer the light), rising linearly to 1 at `len` beyond it,
    /// with `len` the receiver's [`Frame::fade_length`] (computed once per receiver, not per
    /// slice).
    pub(crate) fn fade(&self, k: u32, h: f32, len: f32) -> f32 {
        let beyond = h - self.plane(k);
        if len > 0.0 {
            (beyond / len).clamp(0.0, 1.0)
        } else if beyond > 0.0 {
            1.0
        } else {
            0.0
        }
    }

    /// The depth over which a slice fades in for a receiver at depth `h`: `fade_texels` texels
    /// of the frustum there, at most one slice.
    pub(crate) fn fade_length(&self, h: f32) -> f32 {
        self.spacing
            .min(self.fade_texels * self.texel_size(h.max(0.0)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A top code stands for a depth in its slab at or below the fragment's, less than one step
    /// (a 254th of the slab) below it, 255 at the upper plane and 1 at the lower; and
    /// `texel_point` inverts the kernel's centre.
    #[test]
    fn top_codes_round_down_the_slab_and_texel_points_invert_the_projection() {
        let frame = Frame {
            d: 1.5,
            near: 0.4,
            spacing: 0.125,
            slices: 8,
            half_x: 0.5,
            half_y: 0.25,
            resolution: 512,
            ..Frame::zeroed()
        };
        for k in 0..frame.slices {
            let upper = frame.plane(k) - frame.spacing;
            assert_eq!(frame.top_code(k, upper), 255);
            assert_eq!(frame.top_code(k, frame.plane(k)), 1);
            for i in 0..=1000 {
                let h = upper + frame.spacing * i as f32 / 1000.0;
                let code = frame.top_code(k, h);
                let back = frame.top_depth(k, code);
                let step = frame.spacing / TOP_STEPS;
                assert!(
                    back >= h - 1e-6 && back < h + step + 1e-6,
                    "slice {k}: {h} -> code {code} -> {back}"
                );
            }
        }
        for (x, y, h) in [(0.3f32, -0.2f32, 2.0f32), (-1.1, 0.7, 0.9), (0.0, 0.0, 3.5)] {
            // The kernel at depth `h` of a receiver on the line from the light's centre through
            // (x, y, h) is centred on the texel of (x, y, h).
            let along = 10.0 / h;
            let receiver = LightCoord {
                x: x * along,
                y: y * along,
                h: 10.0,
            };
            let (centre, _) = frame.kernel(receiver, h, 1.0);
            let p = frame.texel_point(centre, h);
            assert!(
                (p.x - x).abs() < 1e-4 && (p.y - y).abs() < 1e-4 && p.h == h,
                "{p:?} against ({x}, {y}, {h})"
            );
        }
    }

    /// A slice fades in linearly from its lower plane over `fade_texels` texels of the frustum
    /// at the receiver's depth, at most one slice; `fade_texels = 0` is a step at the plane.
    #[test]
    fn fade_rises_over_the_fade_length_beyond_the_plane() {
        let mut frame = Frame {
            d: 2.0,
            near: 0.25,
            spacing: 0.1,
            slices: 8,
            half_x: 0.5,
            resolution: 256,
            fade_texels: 4.0,
            ..Frame::zeroed()
        };
        let fade = |f: &Frame, h: f32| f.fade(3, h, f.fade_length(h));
        let p = frame.plane(3);
        let texel = frame.texel_size(p);
        // 4 texels of about 0.0045 m: shorter than the slice.
        let len = frame.fade_length(p);
        assert!(
            (len - 4.0 * texel).abs() < 1e-3 * len && len < frame.spacing,
            "{len}"
        );
        assert_eq!(fade(&frame, p - 0.01), 0.0);
        assert_eq!(fade(&frame, p), 0.0);
        let half = fade(&frame, p + 0.5 * len);
        assert!((half - 0.5).abs() < 0.01, "{half}");
        assert_eq!(fade(&frame, p + 1.01 * len), 1.0);
        // Never longer than a slice.
        frame.fade_texels = 1e6;
        assert_eq!(frame.fade_length(p), frame.spacing);
        assert!((fade(&frame, p + 0.5 * frame.spacing) - 0.5).abs() < 1e-4);
        // A step.
        frame.fade_texels = 0.0;
        assert_eq!(fade(&frame, p), 0.0);
        assert_eq!(fade(&frame, p + 1e-6), 1.0);
    }

    /// `slice_of` is `ceil((h - near) / spacing - tolerance)` clamped to the slices (the
    /// definition `frame.wgsl` also follows), exactly: on every slice plane, a step either
    /// side of it, far outside the range, and NaN.
    #[test]
    fn slice_of_is_the_clamped_ceiling() {
        let frame = Frame {
            d: 2.0,
            near: 0.25,
            spacing: 0.1,
            slices: 24,
            ..Frame::zeroed()
        };
        let definition = |z: f32| {
            let k = ((z - frame.d - frame.near) / frame.spacing - SLICE_TOLERANCE).ceil();
            k.clamp(0.0, (frame.slices - 1) as f32) as u32
        };
        let mut zs = vec![f32::NAN, f32::INFINITY, f32::NEG_INFINITY, -1e30, 1e30, 0.0];
        for k in -3..30 {
            let h = frame.near + k as f32 * frame.spacing;
            for z in [h + frame.d, (h + SLICE_TOLERANCE * frame.spacing) + frame.d] {
                zs.extend([z, z.next_up(), z.next_down(), z + 0.03, z - 0.03]);
            }
        }
        let mut hit = std::collections::BTreeSet::new();
        for z in zs {
            assert_eq!(frame.slice_of(z), definition(z), "z = {z}");
            hit.insert(frame.slice_of(z));
        }
        assert_eq!(hit.len(), frame.slices as usize, "every slice reached");
    }
}
