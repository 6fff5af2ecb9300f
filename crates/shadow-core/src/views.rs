//! A light's shadow as a set of views: one frustum where it holds the casters, cube faces around
//! a local light that surrounds them, cascades along the camera's depth for a distant light.
//!
//! [`LightViews::plan`] chooses the views from the light, what its maps cover and (for
//! cascades) what the camera sees; every technique generates its maps once per view
//! ([`crate::Generation::region`]) and evaluates a receiver in the view [`LightViews::weight`]
//! picks for it, on the CPU and in WGSL (`views.wgsl`, the same arithmetic). What engines do:
//!
//! - **Cube faces** (every engine's point-light shadows): a face holds the directions whose
//!   largest component, in the cube's basis, is its axis. A face is kept only when a caster
//!   crosses its pyramid (Unreal's per-face culling). Faces overlap: each face's window reaches
//!   [`LightViews::plan`]'s guard angle beyond its directions, wide enough for the penumbra of a
//!   caster as near the light as the nearest one (a caster at distance `d` from a light of radius
//!   `r` shadows directions up to `asin(r / d)` from its own), plus the filter margin
//!   [`crate::coverage::MARGIN`]. So a filter footprint and a penumbra that cross the seam read
//!   the face's own texels there: the faces overlap rather than read each other. Near a seam
//!   (within [`FACE_BLEND`]) a receiver blends both faces, half and half on the seam: the
//!   techniques whose maps approximate the light differently per face (occlusion slices, whose
//!   slabs are parallel to the face) meet without a step.
//! - **Cascades** (every engine's sun): split along the camera's view depth over the depth range
//!   of what it sees (the G-buffer's, the sample-distribution idea) by the practical split
//!   between logarithmic and uniform ([`CASCADE_LAMBDA`]); each cascade is an orthographic
//!   window fitted to the receivers the camera sees in its depth range where they are given
//!   ([`LightViews::plan_seen`]: Lauritzen's sample distribution shadow maps fit each cascade to
//!   the G-buffer's samples), else to its slice of the camera frustum within the scene's bounds
//!   (at most the slice's bounding sphere, whose size does not change as the camera turns), its
//!   size in steps of `2^(1/8)` and centred on whole texels in the light's basis so that a
//!   moving camera does not make shadows shimmer; the last [`CASCADE_BLEND`] of each cascade's
//!   depth blends into the next.
//!
//! The penumbra keeps its size across views: every technique sizes its penumbra from the
//! light's world size (or angular diameter) and each view's own texel size.

pub use crate::coverage::Region;
use crate::coverage::{Coverage, MARGIN, face_planes};
use crate::error::Result;
use crate::geometry::SceneGeometry;
use crate::light::{Light, LightPoint, orthonormal_basis};
use crate::receivers::Receivers;
use crate::view::View;
use bytemuck::{Pod, Zeroable};
use glam::{Vec3, Vec4};

/// Largest half-angle of one frustum around a local light's casters (degrees): beyond it the
/// light gets cube faces. A perspective map's texels at angle `t` off its axis are
/// `1 / cos²(t)` times larger along the radius than at its centre (7x at 68 degrees, 30x at
/// 80). Measured where that starts to cost: a 2 m bunny under a 0.6 m square light 3 m up needs
/// 65-68 degrees, and one frustum and the cube faces read the same error there (V rms within 0.7
/// of each other at 256² and 1024² for the hard map, PCSS, shadow-width and penumbra-limit;
/// occlusion slices 4.4 better in one frustum); `light-plane`'s wall needs 81 degrees, where the
/// faces are better (at 16², the hard map's image error 9.81 in one frustum against 8.53 on the
/// faces, PCSS 9.51 against 7.42).
pub const SINGLE_VIEW_MAX_DEGREES: f32 = 75.0;

/// Largest guard angle of a cube face beyond its 45 degrees (degrees).
pub const FACE_GUARD_MAX_DEGREES: f32 = 20.0;

/// Where neighbouring cube faces blend: the directions whose second largest component (in the
/// cube's basis) is within this share of the largest take both faces, half and half on the seam
/// (42 to 48 degrees from a face's axis, inside the guard), so that `V` has no step there.
pub const FACE_BLEND: f32 = 0.1;

/// Most cascades of a distant light.
pub const MAX_CASCADES: usize = 4;

/// A distant light gets one cascade per this factor of the seen depth range (far / near).
pub const CASCADE_RATIO: f32 = 4.0;

/// Least weight of the logarithmic split in the practical split (the rest: uniform). Over a
/// deep range the weight rises so that the uniform part at most doubles the first cascade
/// ([`LightViews::plan`]).
pub const CASCADE_LAMBDA: f32 = 0.9;

/// Cascades are used only where one view's window is at least this many times the first
/// cascade's (the near field's texels that much finer).
pub const CASCADE_GAIN_MIN: f32 = 2.0;

/// Share of each cascade's depth range, at its far end, that blends into the next cascade.
pub const CASCADE_BLEND: f32 = 0.1;

/// What a camera sees, for cascades: its view and the depth range of the receivers it sees
/// along its axis (a G-buffer's nearest and farthest depth).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SeenDepth {
    /// The camera's view (its projection gives the frustum's slices).
    pub camera: View,
    /// Nearest seen depth along the camera's axis.
    pub near: f32,
    /// Farthest seen depth along the camera's axis.
    pub far: f32,
}

impl SeenDepth {
    /// The depth range of `points` seen by `camera` (points behind it are ignored); `None` when
    /// none lies in front of it.
    pub fn of_points(camera: View, points: &[Vec3]) -> Option<Self> {
        let (mut near, mut far) = (f32::INFINITY, 0.0f32);
        for p in points {
            let z = camera.linear_depth(*p);
            if z > 0.0 && z.is_finite() {
                near = near.min(z);
                far = far.max(z);
            }
        }
        let near = near.max(camera.near);
        (far > 0.0).then_some(Self {
            camera,
            near,
            far: far.max(near),
        })
    }

    /// This depth range widened to whole steps of `2^(1/8)` (the near depth down, not below the
    /// camera's near plane; the far depth up), so that a camera that moved a little plans
    /// cascades at the same split depths: what a pipeline that keeps cascades across frames
    /// plans with ([`LightViews::moved`]).
    pub fn quantized(self) -> Self {
        let step = |x: f32, up: bool| {
            let l = 8.0 * x.max(1e-6).log2();
            2f32.powf(if up { l.ceil() } else { l.floor() } / 8.0)
        };
        let near = step(self.near, false).max(self.camera.near);
        Self {
            near,
            far: step(self.far, true).max(near),
            ..self
        }
    }
}

/// How a receiver picks its view.
#[derive(Clone, Debug, PartialEq)]
enum Select {
    /// One view for every receiver.
    One,
    /// The cube face of the receiver's direction from `center`, in `basis`; `face_view[f]` is
    /// the view of face `f` (`2 k` for `+basis[k]`, `2 k + 1` for `-basis[k]`), or -1 where the
    /// face holds no caster (nothing shadows those directions).
    Cube {
        center: Vec3,
        basis: [Vec3; 3],
        face_view: [i32; 6],
    },
    /// The cascade of the receiver's depth along the camera (`depth_row . (p, 1)`) between
    /// `splits[i]` and `splits[i + 1]`, blending into the next over its last [`CASCADE_BLEND`].
    /// `direction` is the light's (towards it): the cascades' windows snap to its basis.
    Cascades {
        depth_row: Vec4,
        splits: Vec<f32>,
        direction: Vec3,
    },
}

/// A light's views: the region of each (what a technique fits one generation to) and how a
/// receiver picks its view.
#[derive(Clone, Debug, PartialEq)]
pub struct LightViews {
    regions: Vec<Region>,
    select: Select,
}

/// Laid out as `ViewSelect` in `views.wgsl`: how a receiver picks its view, and the view one
/// evaluation pass adds (`index`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable, PartialEq)]
pub struct ViewSelect {
    /// The camera's depth row (cascades).
    pub depth_row: [f32; 4],
    /// The light's centre (cube faces).
    pub center: [f32; 4],
    /// The cube's basis (cube faces).
    pub basis: [[f32; 4]; 3],
    /// Split depths (cascades): `splits[i]` and `splits[i + 1]` bound cascade `i`.
    pub splits: [f32; 8],
    /// The view of each cube face, -1 where none (cube faces).
    pub face_view: [i32; 8],
    /// 0: one view, 1: cube faces, 2: cascades.
    pub kind: u32,
    /// The view this pass evaluates.
    pub index: u32,
    /// How many views.
    pub count: u32,
    /// [`CASCADE_BLEND`] for cascades, [`FACE_BLEND`] for cube faces.
    pub blend: f32,
}

impl LightViews {
    /// One view of the whole coverage (what [`View::fit_light`] fits).
    pub fn single() -> Self {
        Self {
            regions: vec![Region::Whole],
            select: Select::One,
        }
    }

    /// The views of `light` over `geometry` (what its maps cover: [`crate::coverage`]),
    /// with what a camera sees where one is given:
    ///
    /// - a local light: one view where one frustum of at most [`SINGLE_VIEW_MAX_DEGREES`]
    ///   half-angle holds its casters and their penumbrae; otherwise the cube faces that hold
    ///   casters (a one-sided light: never the face behind it);
    /// - a distant light: with `seen`, one cascade per [`CASCADE_RATIO`] of the seen depth
    ///   range (far / near), at most [`MAX_CASCADES`], where the first cascade's window is at
    ///   most 1 / [`CASCADE_GAIN_MIN`] of one view's, split by the practical split with the
    ///   logarithmic weight `max(CASCADE_LAMBDA, 1 / (1 + n r^(1/n - 1)))` (`n` cascades over
    ///   the ratio `r`), which keeps the uniform part from more than doubling the first
    ///   cascade; one view without.
    ///
    /// Each cascade's window is fitted to its slice of the camera frustum within the scene's
    /// bounds; [`LightViews::plan_seen`] fits it to the receivers the camera sees there.
    pub fn plan(light: &Light, geometry: &SceneGeometry, seen: Option<&SeenDepth>) -> Self {
        Self::plan_seen(light, geometry, seen, &[])
    }

    /// The views [`LightViews::plan`] chooses, with each cascade's window fitted to the points
    /// of `receivers` (what the camera sees: its G-buffer's positions) whose depth along the
    /// camera lies in the cascade's range, across the light, grown by the penumbra's reach (the
    /// sample-distribution idea: no texel is spent on what no receiver reads), out to whole
    /// steps of a sixteenth to an eighth of its size so that a camera that moves a little
    /// seldom moves it (its size then in steps of `2^(1/8)`, its centre on whole texels, as
    /// every cascade's). A cascade none of them reads where a shadow can fall is fitted as
    /// [`LightViews::plan`] fits it; so is every cascade when `receivers` is empty. Receivers
    /// behind the camera or not finite are left out (no camera sees them).
    ///
    /// `V` read elsewhere than at `receivers` (at texels of a G-buffer they only sample) may
    /// lie outside every window: give every point `V` is read at, or use [`LightViews::plan`].
    pub fn plan_seen(
        light: &Light,
        geometry: &SceneGeometry,
        seen: Option<&SeenDepth>,
        receivers: &[Vec3],
    ) -> Self {
        if geometry.casters.is_empty() || geometry.bounds.is_empty() {
            return Self::single();
        }
        match light.center() {
            LightPoint::Position(c) => Self::local(light, geometry, c),
            LightPoint::Direction(d) => match seen {
                Some(seen) => Self::cascades(light, geometry, d, seen, receivers),
                None => Self::single(),
            },
        }
    }

    fn local(light: &Light, geometry: &SceneGeometry, c: Vec3) -> Self {
        let coverage = Coverage::new(geometry, light);
        let tan = View::window_tan(c, light.axis(coverage.center()), &coverage);
        if tan.atan() <= SINGLE_VIEW_MAX_DEGREES.to_radians() {
            return Self::single();
        }
        let front = light.front().map(|(_, n)| n.normalize());
        let basis = match front {
            Some(n) => {
                let (t, b) = orthonormal_basis(n);
                [t, b, n]
            }
            None => [Vec3::X, Vec3::Y, Vec3::Z],
        };
        // The guard: the penumbra of the nearest caster, and the filters' margin.
        let r = crate::coverage::light_radius(light, c);
        let nearest = geometry
            .casters
            .iter()
            .map(|t| closest_on_triangle(c, t).distance(c))
            .fold(f32::INFINITY, f32::min);
        let guard = (r / nearest.max(1e-30))
            .min(FACE_GUARD_MAX_DEGREES.to_radians().sin())
            .asin();
        // The face's own directions reach `atan(1 / (1 - FACE_BLEND))` from its axis where it
        // blends with its neighbour.
        let reach = (1.0 / (1.0 - FACE_BLEND)).atan();
        let half_angle = ((reach + guard).tan() * (1.0 + 2.0 * MARGIN)).atan();
        let mut regions = Vec::new();
        let mut face_view = [-1i32; 6];
        for (f, view) in face_view.iter_mut().enumerate() {
            let (k, sign) = (f / 2, if f % 2 == 0 { 1.0 } else { -1.0 });
            let axis = basis[k] * sign;
            if front.is_some_and(|n| axis.dot(n) < -0.5) {
                continue;
            }
            let up = basis[(k + 1) % 3];
            let planes = face_planes(axis, up, half_angle);
            let holds = geometry.casters.iter().any(|t| {
                let in_front = front.is_none_or(|n| t.iter().any(|v| (*v - c).dot(n) > 0.0));
                in_front
                    && planes
                        .iter()
                        .all(|pl| t.iter().any(|v| (*v - c).dot(*pl) >= 0.0))
            });
            if holds {
                *view = regions.len() as i32;
                regions.push(Region::Face {
                    axis,
                    up,
                    half_angle,
                });
            }
        }
        if regions.is_empty() {
            return Self::single();
        }
        Self {
            regions,
            select: Select::Cube {
                center: c,
                basis,
                face_view,
            },
        }
    }

    fn cascades(
        light: &Light,
        geometry: &SceneGeometry,
        dir: Vec3,
        seen: &SeenDepth,
        receivers: &[Vec3],
    ) -> Self {
        let near = seen.near.max(1e-6);
        let far = seen.far.max(near);
        let count = ((far / near).ln() / CASCADE_RATIO.ln())
            .ceil()
            .clamp(1.0, MAX_CASCADES as f32) as usize;
        if count <= 1 {
            return Self::single();
        }
        // The uniform part of the first split, (1 - l)(far - near) / count, stays within its
        // logarithmic part, l near (far / near)^(1 / count): over a deep range a few percent of
        // uniform would make the first cascade as deep as the scene.
        let ratio = far / near;
        let n = count as f32;
        let lambda = CASCADE_LAMBDA.max(1.0 / (1.0 + n * ratio.powf(1.0 / n - 1.0)));
        let splits: Vec<f32> = (0..=count)
            .map(|i| {
                let s = i as f32 / n;
                let log = near * ratio.powf(s);
                let uniform = near + (far - near) * s;
                lambda * log + (1.0 - lambda) * uniform
            })
            .collect();
        // A caster shadows what lies below it within the light's cone: the window grows by the
        // cone's spread over the geometry's depth.
        let spread = match *light {
            Light::Distant {
                angular_diameter, ..
            } => (0.5 * angular_diameter).tan() / (std::f32::consts::PI / 8.0).cos(),
            _ => 0.0,
        };
        let bounds = &geometry.bounds;
        let depth = |p: Vec3| p.dot(dir);
        let (lo, hi) = bounds
            .corners()
            .iter()
            .fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), c| {
                (lo.min(depth(*c)), hi.max(depth(*c)))
            });
        let grow = spread * (hi - lo).max(0.0);
        let basis = crate::view::look_to_up(Vec3::ZERO, -dir, up_for(-dir));
        // Where the casters' shadows can fall, across the light: their box grown by the
        // penumbra's spread (what one view's window holds, [`View::fit_light`]).
        let casters = crate::mesh::Aabb::of_triangles(&geometry.casters);
        let (mut shade_lo, mut shade_hi) = (Vec3::splat(f32::INFINITY), Vec3::NEG_INFINITY);
        for c in casters.corners() {
            let v = basis.transform_point3(c);
            shade_lo = shade_lo.min(v - Vec3::splat(grow));
            shade_hi = shade_hi.max(v + Vec3::splat(grow));
        }
        let shade = (shade_lo, shade_hi);
        let from = |i: usize| {
            if i == 0 {
                splits[0]
            } else {
                splits[i] - CASCADE_BLEND * (splits[i] - splits[i - 1])
            }
        };
        let ranges: Vec<(f32, f32)> = (0..count).map(|i| (from(i), splits[i + 1])).collect();
        let fits = receivers_fit(&seen.camera, &ranges, receivers, &basis, shade, grow);
        let regions = (0..count)
            .map(|i| {
                let from = from(i);
                let (mut center, radius) = slice_sphere(&seen.camera, from, splits[i + 1]);
                let mut half = radius + grow;
                let mut floor = center.dot(dir) - radius;
                // Fitted to the seen receivers of the slice where there are any (the
                // sample-distribution idea), else to where the slice holds geometry that
                // shadows can fall on, where that is smaller, its size in steps of 2^(1/8) so
                // that a moving camera rarely changes it.
                let fit = fits[i].or_else(|| {
                    slice_in_bounds(
                        &seen.camera,
                        from,
                        splits[i + 1],
                        bounds,
                        &basis,
                        shade,
                        grow,
                    )
                });
                if let Some((c, h, low)) = fit {
                    floor = floor.max(low);
                    // Not below a hundredth of the slice (one receiver under a sun whose
                    // penumbra reaches nothing would fit a window of no size).
                    let h = h.max(0.01 * radius);
                    let h = 2f32.powf((8.0 * h.max(1e-6).log2()).ceil() / 8.0);
                    if h < half {
                        (center, half) = (c, h);
                    }
                }
                let half_extent = half * (1.0 + MARGIN);
                // The highest caster over the window (a box overlapping it across the light).
                let c = basis.transform_point3(center);
                let top = geometry
                    .casters
                    .iter()
                    .filter(|t| {
                        let v = t.map(|p| basis.transform_point3(p));
                        let (lo, hi) = (v[0].min(v[1]).min(v[2]), v[0].max(v[1]).max(v[2]));
                        lo.x <= c.x + half_extent
                            && hi.x >= c.x - half_extent
                            && lo.y <= c.y + half_extent
                            && hi.y >= c.y - half_extent
                    })
                    .flatten()
                    .map(|p| depth(*p))
                    .fold(f32::NEG_INFINITY, f32::max);
                // Other light directions of the cone reach a little further.
                let top = if top.is_finite() { top + grow } else { floor };
                Region::Cascade {
                    center,
                    half_extent,
                    heights: [floor - grow, top.max(floor)],
                }
            })
            .collect::<Vec<Region>>();
        // Cascades only where they make the near field's texels finer: where one window around
        // every caster and its shadow (what a single view fits) is not at least twice the first
        // cascade's, one view serves better (a small caster near the camera in a deep scene).
        let whole = View::fit_light(
            LightPoint::Direction(dir),
            -dir,
            &Coverage::new(geometry, light),
        );
        if let (
            crate::view::ProjectionKind::Orthographic { half_extent: one },
            Some(Region::Cascade { half_extent, .. }),
        ) = (whole.kind, regions.first())
            && *half_extent > CASCADE_GAIN_MIN.recip() * one
        {
            return Self::single();
        }
        Self {
            regions,
            select: Select::Cascades {
                depth_row: -seen.camera.view.row(2),
                splits,
                direction: dir,
            },
        }
    }

    /// The regions, one per view.
    pub fn regions(&self) -> &[Region] {
        &self.regions
    }

    /// For cube faces, the views whose pyramid around the light's centre, grown by `light`'s
    /// radius (the pyramid of every point of the light, as a face's maps hold the casters
    /// inside it), meets one of `boxes`, in view order; `None` for other views. Conservative:
    /// a box with a corner on the inner side of every grown plane counts.
    pub fn faces_meeting(&self, light: &Light, boxes: &[crate::mesh::Aabb]) -> Option<Vec<usize>> {
        let Select::Cube { center, .. } = self.select else {
            return None;
        };
        let r = crate::coverage::light_radius(light, center);
        Some(
            self.regions
                .iter()
                .enumerate()
                .filter(|(_, region)| {
                    let Region::Face {
                        axis,
                        up,
                        half_angle,
                    } = **region
                    else {
                        return true;
                    };
                    let planes = face_planes(axis, up, half_angle);
                    boxes.iter().filter(|b| !b.is_empty()).any(|b| {
                        planes.iter().all(|n| {
                            let w = center.dot(*n) - r * n.length();
                            b.corners().iter().any(|q| q.dot(*n) >= w)
                        })
                    })
                })
                .map(|(i, _)| i)
                .collect(),
        )
    }

    /// How many views.
    pub fn len(&self) -> usize {
        self.regions.len()
    }

    /// Whether there is no view (never: a plan has at least one).
    pub fn is_empty(&self) -> bool {
        self.regions.is_empty()
    }

    /// Whether this is one view of the whole coverage ([`LightViews::single`]), not cube faces
    /// or cascades (of which there may also be one).
    pub fn is_single(&self) -> bool {
        matches!(self.select, Select::One)
    }

    /// `"single"`, `"cube"` or `"cascades"`, as in reports.
    pub fn kind_name(&self) -> &'static str {
        match self.select {
            Select::One => "single",
            Select::Cube { .. } => "cube",
            Select::Cascades { .. } => "cascades",
        }
    }

    /// Which views of `planned` (planned later for the same light and casters) maps made for
    /// these views at `resolution` must make again, the others serving as they are: none where
    /// the plans are equal; for cascades at the same split depths, those whose window changed
    /// size or moved to other texels (a camera that moved less than a texel moves none) or
    /// whose depth range no longer holds the planned one within a texel. `None` where the
    /// plans differ otherwise (other split depths, other views): every view is made again.
    pub fn moved(&self, planned: &LightViews, resolution: u32) -> Option<Vec<usize>> {
        if self == planned {
            return Some(Vec::new());
        }
        let (
            Select::Cascades { splits, .. },
            Select::Cascades {
                splits: planned_splits,
                ..
            },
        ) = (&self.select, &planned.select)
        else {
            return None;
        };
        if splits != planned_splits || self.regions.len() != planned.regions.len() {
            return None;
        }
        let kept = |a: &Region, b: &Region| match (a, b) {
            (
                Region::Cascade {
                    center: ca,
                    half_extent: ha,
                    heights: da,
                },
                Region::Cascade {
                    center: cb,
                    half_extent: hb,
                    heights: db,
                },
            ) => {
                // A texel of depth to spare: a window's map reaches 1% and more beyond its
                // heights ([`View::fit_light`]).
                let texel = 2.0 * ha / resolution.max(1) as f32;
                ha == hb
                    && self.cascade_texel(*ca, *ha, resolution)
                        == self.cascade_texel(*cb, *hb, resolution)
                    && da[0] <= db[0] + texel
                    && da[1] >= db[1] - texel
            }
            _ => a == b,
        };
        Some(
            (0..self.regions.len())
                .filter(|&i| !kept(&self.regions[i], &planned.regions[i]))
                .collect(),
        )
    }

    /// The views `indices` of these, alone (what a technique generates to make them again).
    pub(crate) fn only(&self, indices: &[usize]) -> LightViews {
        LightViews {
            regions: indices.iter().map(|&i| self.regions[i]).collect(),
            select: self.select.clone(),
        }
    }

    /// The texel of the light-space grid a cascade's window centre snaps to
    /// ([`View::fit_light`]: whole texels of the light's basis, from the world's origin).
    fn cascade_texel(&self, center: Vec3, half_extent: f32, resolution: u32) -> [i64; 2] {
        let Select::Cascades { direction: dir, .. } = self.select else {
            return [0, 0];
        };
        let texel = 2.0 * half_extent / resolution.max(1) as f32;
        let c = crate::view::look_to(Vec3::ZERO, -dir).transform_point3(center);
        [(c.x / texel).round() as i64, (c.y / texel).round() as i64]
    }

    /// How much of view `index`'s visibility a receiver at `p` takes (`view_weight` in WGSL):
    /// 1 in its view, a blend between neighbouring cascades or cube faces, 0 elsewhere.
    pub fn weight(&self, index: usize, p: Vec3) -> f32 {
        self.gpu_select(index as u32).weight(p)
    }

    /// How much of `V` comes from the views at `p` (`views_weight` in WGSL): 1, or less in a
    /// direction of a cube whose face holds no caster (`V` is 1 from that face).
    pub fn total_weight(&self, p: Vec3) -> f32 {
        self.gpu_select(0).total(p)
    }

    /// The shader-side selection for the pass that evaluates view `index`.
    pub fn gpu_select(&self, index: u32) -> ViewSelect {
        let mut s = ViewSelect {
            depth_row: [0.0; 4],
            center: [0.0; 4],
            basis: [[0.0; 4]; 3],
            splits: [0.0; 8],
            face_view: [-1; 8],
            kind: 0,
            index,
            count: self.regions.len() as u32,
            blend: CASCADE_BLEND,
        };
        match &self.select {
            Select::One => {}
            Select::Cube {
                center,
                basis,
                face_view,
            } => {
                s.kind = 1;
                s.blend = FACE_BLEND;
                s.center = center.extend(1.0).to_array();
                s.basis = basis.map(|b| b.extend(0.0).to_array());
                s.face_view[..6].copy_from_slice(face_view);
            }
            Select::Cascades {
                depth_row, splits, ..
            } => {
                s.kind = 2;
                s.depth_row = depth_row.to_array();
                s.splits[..splits.len()].copy_from_slice(splits);
            }
        }
        s
    }

    /// What `light`'s maps over `geometry` would leave out of every view, so that a shadow
    /// would be silently missing: for a local light, the casters of `instances` (each one
    /// object's world-space triangles, those the maps must hold) with a vertex on the light's
    /// emitting side in no view's frustum (the views of one light point hold every direction a
    /// caster lies in); for a distant light's cascades, the receivers of `seen` outside the
    /// window (or the depth range) of a cascade they read that a caster of `instances` can
    /// shadow ([`crate::coverage::can_shadow`]). Empty when every one is held.
    pub fn uncovered(
        &self,
        light: &Light,
        geometry: &SceneGeometry,
        instances: &[Vec<[Vec3; 3]>],
        seen: &[Vec3],
    ) -> Vec<Uncovered> {
        let views: Vec<View> = self
            .regions
            .iter()
            .map(|r| {
                let coverage = Coverage::new(geometry, light)
                    .within(*r, 0)
                    .in_face_of(&[&geometry.casters], light);
                View::for_light_center(light, &coverage)
            })
            .collect();
        let inside = |v: &View, p: Vec3| {
            v.project(p).is_some_and(|(x, y, z)| {
                let e = 1e-4;
                (-e..=1.0 + e).contains(&x)
                    && (-e..=1.0 + e).contains(&y)
                    && z >= v.near * (1.0 - 1e-4) - 1e-6
                    && z <= v.far * (1.0 + 1e-4)
            })
        };
        match light.center() {
            LightPoint::Position(_) => instances
                .iter()
                .enumerate()
                .filter(|(_, tris)| {
                    tris.iter()
                        .flatten()
                        .any(|&p| light.emits_towards(p) && !views.iter().any(|v| inside(v, p)))
                })
                .map(|(i, _)| Uncovered::Caster(i))
                .collect(),
            LightPoint::Direction(_) if matches!(self.select, Select::Cascades { .. }) => {
                let boxes: Vec<crate::mesh::Aabb> = instances
                    .iter()
                    .map(|t| crate::mesh::Aabb::of_triangles(t))
                    .collect();
                seen.iter()
                    .enumerate()
                    .filter(|(_, p)| {
                        (0..self.len())
                            .any(|i| self.weight(i, **p) > 0.0 && !inside(&views[i], **p))
                            && boxes
                                .iter()
                                .any(|b| crate::coverage::can_shadow(light, b, **p, 0.0))
                    })
                    .map(|(k, _)| Uncovered::Receiver(k))
                    .collect()
            }
            // One window fitted around every caster and its penumbra: what it leaves out, no
            // caster shadows.
            LightPoint::Direction(_) => Vec::new(),
        }
    }
}

/// What [`LightViews::uncovered`] found left out.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum Uncovered {
    /// The caster instance of this index lies partly in no view.
    Caster(usize),
    /// The seen receiver of this index lies outside its cascade's window.
    Receiver(usize),
}

impl ViewSelect {
    /// The share of each cube face's axis in `p`'s direction and the view of the face on that
    /// axis's side (-1 where none): axis `a` takes `s_a / sum(s)` with
    /// `s_a = clamp((|c_a| / max|c| - (1 - b)) / b, 0, 1)` (`b` = [`FACE_BLEND`]), `c` the direction
    /// in the cube's basis: 1 inside a face, shared towards a seam, half and half on it.
    fn faces(&self, p: Vec3) -> [(f32, i32); 3] {
        let d = p - Vec4::from(self.center).truncate();
        let c = [0, 1, 2].map(|k| d.dot(Vec4::from(self.basis[k]).truncate()));
        let m = c[0].abs().max(c[1].abs()).max(c[2].abs()).max(1e-30);
        let b = self.blend;
        let s = c.map(|x| ((x.abs() / m - (1.0 - b)) / b).clamp(0.0, 1.0));
        // At the light's centre no direction: no face (V is 1 there).
        let sum = (s[0] + s[1] + s[2]).max(1e-30);
        [0, 1, 2].map(|k| {
            let f = 2 * k + usize::from(c[k] < 0.0);
            (s[k] / sum, self.face_view[f])
        })
    }

    /// Every view's weight at `p`, as (view, weight) pairs (view -1: none; weight 0: none):
    /// up to three cube faces, a cascade and the next one in its blend band, or the one view.
    fn shares(&self, p: Vec3) -> [(i32, f32); 3] {
        match self.kind {
            1 => self.faces(p).map(|(w, v)| (v, w)),
            2 => {
                let z = Vec4::from(self.depth_row).dot(p.extend(1.0));
                let n = self.count as usize;
                let mut i = 0;
                while i + 1 < n && z >= self.splits[i + 1] {
                    i += 1;
                }
                let (mut wi, mut wn) = (1.0, 0.0);
                if i + 1 < n {
                    let band = self.blend * (self.splits[i + 1] - self.splits[i]);
                    let start = self.splits[i + 1] - band;
                    if z > start && band > 0.0 {
                        wn = ((z - start) / band).min(1.0);
                        wi = 1.0 - wn;
                    }
                }
                let next = if i + 1 < n { i as i32 + 1 } else { -1 };
                [(i as i32, wi), (next, wn), (-1, 0.0)]
            }
            _ => [(0, 1.0), (-1, 0.0), (-1, 0.0)],
        }
    }

    /// Weight of view `self.index` at `p` (`view_weight` in WGSL).
    pub fn weight(&self, p: Vec3) -> f32 {
        self.shares(p)
            .iter()
            .filter(|(v, _)| *v == self.index as i32)
            .map(|(_, w)| *w)
            .sum()
    }

    /// The views' total weight at `p` (`views_weight` in WGSL): 0 only in a cube direction
    /// whose face holds no caster.
    pub fn total(&self, p: Vec3) -> f32 {
        self.total_of(&self.shares(p))
    }

    /// The total weight of `shares` ([`ViewSelect::shares`] at a point).
    fn total_of(&self, shares: &[(i32, f32); 3]) -> f32 {
        if self.kind == 1 {
            shares
                .iter()
                .filter(|(v, _)| *v >= 0)
                .map(|(_, w)| *w)
                .sum()
        } else {
            1.0
        }
    }
}

/// The bounding sphere (centre, radius) of the camera frustum's slice between view depths
/// `from` and `to`: its centre on the axis, where the nearest and the farthest corners are
/// equally far (or at the far end).
fn slice_sphere(camera: &View, from: f32, to: f32) -> (Vec3, f32) {
    // The squared half-diagonals of the slice's near and far rectangles.
    let (a2, b2) = match camera.kind {
        crate::view::ProjectionKind::Perspective { fov } => {
            let ty = (0.5 * fov).tan();
            let k2 = ty * ty * (1.0 + camera.aspect * camera.aspect);
            (from * from * k2, to * to * k2)
        }
        crate::view::ProjectionKind::Orthographic { half_extent } => {
            let h2 = half_extent * half_extent * (1.0 + camera.aspect * camera.aspect);
            (h2, h2)
        }
    };
    let z = if to > from {
        ((to * to + b2 - from * from - a2) / (2.0 * (to - from))).clamp(from, to)
    } else {
        to
    };
    let radius = ((z - from).powi(2) + a2).max((to - z).powi(2) + b2).sqrt();
    let inv = camera.view.inverse();
    let center = inv.transform_point3(Vec3::new(0.0, 0.0, -z));
    (center, radius)
}

/// The up vector [`View::fit_light`] gives a view along `axis`.
fn up_for(axis: Vec3) -> Vec3 {
    if axis.normalize().y.abs() > 0.99 {
        Vec3::Z
    } else {
        Vec3::Y
    }
}

/// Where the camera frustum's slice between view depths `from` and `to` meets `bounds`, grown
/// across the light by `grow` (the penumbra's reach), and the rectangle `shade` (light view
/// coordinates) where shadows can fall: the centre (world) and half-side of the square around it
/// in the light's `basis` (world to light view), and the lowest point of the meeting box along
/// the light (its least `z` in the basis, the height along the light); `None` when they do not
/// meet.
#[allow(clippy::too_many_arguments)]
fn slice_in_bounds(
    camera: &View,
    from: f32,
    to: f32,
    bounds: &crate::mesh::Aabb,
    basis: &glam::Mat4,
    shade: (Vec3, Vec3),
    grow: f32,
) -> Option<(Vec3, f32, f32)> {
    let inv = camera.view.inverse();
    let (tx, ty) = match camera.kind {
        crate::view::ProjectionKind::Perspective { fov } => {
            let ty = (0.5 * fov).tan();
            (ty * camera.aspect, ty)
        }
        crate::view::ProjectionKind::Orthographic { .. } => return None,
    };
    let mut slice = crate::mesh::Aabb::EMPTY;
    for z in [from, to] {
        for (sx, sy) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
            slice.grow(inv.transform_point3(Vec3::new(sx * tx * z, sy * ty * z, -z)));
        }
    }
    let lo = slice.min.max(bounds.min);
    let hi = slice.max.min(bounds.max);
    if lo.cmpgt(hi).any() {
        return None;
    }
    let meet = crate::mesh::Aabb { min: lo, max: hi };
    let (mut a, mut b) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
    for c in meet.corners() {
        let v = basis.transform_point3(c);
        a = a.min(v);
        b = b.max(v);
    }
    let g = Vec3::new(grow, grow, 0.0);
    // The basis looks along -direction: a point's height along the light is its view z.
    square_in_shade((a - g, b + g), shade, basis).map(|(center, half)| (center, half, a.z))
}

/// The box `(a, b)` (light view coordinates of `basis`, world to light view) clipped across
/// the light to the rectangle `shade` where shadows can fall: the centre (world) and half-side
/// of the square around it; `None` where they do not meet.
fn square_in_shade(
    (a, b): (Vec3, Vec3),
    shade: (Vec3, Vec3),
    basis: &glam::Mat4,
) -> Option<(Vec3, f32)> {
    let (a, b) = (
        a.max(Vec3::new(shade.0.x, shade.0.y, a.z)),
        b.min(Vec3::new(shade.1.x, shade.1.y, b.z)),
    );
    if a.x > b.x || a.y > b.y {
        return None;
    }
    let center = basis.inverse().transform_point3(0.5 * (a + b));
    Some((center, 0.5 * (b.x - a.x).max(b.y - a.y)))
}

/// For each cascade's depth range along `camera` in `ranges` (the first open towards the
/// camera, the last away from it, as [`LightViews::weight`] reads them; a relative 1e-4 to spare
/// at each split, so that a receiver a split reads on either side counts), the points of
/// `receivers` in it, in the light's `basis` (world to light view, whose `z` is the height along
/// the light): their box grown across the light by `grow` (the penumbra's reach), out to whole
/// steps of a power of two (a sixteenth to an eighth of its half-side, in the light's basis from
/// the world's origin), and clipped to the rectangle `shade` (light view coordinates) where
/// shadows can fall; the centre (world) and half-side of the square around it, and the lowest
/// height of the points, down to a whole step. `None` for a range that holds no point within
/// `shade`. One pass over the receivers.
fn receivers_fit(
    camera: &View,
    ranges: &[(f32, f32)],
    receivers: &[Vec3],
    basis: &glam::Mat4,
    shade: (Vec3, Vec3),
    grow: f32,
) -> Vec<Option<(Vec3, f32, f32)>> {
    let n = ranges.len();
    let mut boxes = vec![(Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)); n];
    for p in receivers {
        let z = camera.linear_depth(*p);
        if !p.is_finite() || z.is_nan() || z <= 0.0 {
            continue;
        }
        let mut v = None;
        for (i, &(from, to)) in ranges.iter().enumerate() {
            let above = i == 0 || z >= from * (1.0 - 1e-4);
            let below = i + 1 == n || z <= to * (1.0 + 1e-4);
            if above && below {
                let v = *v.get_or_insert_with(|| basis.transform_point3(*p));
                let (a, b) = &mut boxes[i];
                (*a, *b) = (a.min(v), b.max(v));
            }
        }
    }
    boxes
        .into_iter()
        .map(|(a, b)| {
            if !(a.x <= b.x && a.y <= b.y) {
                return None;
            }
            // The box, grown by the penumbra's reach, out to whole steps: a receiver at its
            // edge that comes and goes, or a camera that moves a little, seldom moves it.
            let g = Vec3::new(grow, grow, 0.0);
            let (a, b) = (a - g, b + g);
            let half = 0.5 * (b.x - a.x).max(b.y - a.y);
            let step = 2f32.powf(half.max(1e-6).log2().floor() - 3.0);
            let (a, b) = ((a / step).floor() * step, (b / step).ceil() * step);
            square_in_shade((a, b), shade, basis).map(|(center, half)| (center, half, a.z))
        })
        .collect()
}

/// The point of triangle `t` nearest to `p` (Ericson, Real-Time Collision Detection, 5.1.5).
fn closest_on_triangle(p: Vec3, t: &[Vec3; 3]) -> Vec3 {
    let [a, b, c] = *t;
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return a;
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return a + ab * (d1 / (d1 - d3));
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return a + ac * (d2 / (d2 - d6));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    let denom = 1.0 / (va + vb + vc);
    if !denom.is_finite() {
        // A degenerate triangle: its nearest vertex.
        return [a, b, c]
            .into_iter()
            .min_by(|x, y| x.distance(p).total_cmp(&y.distance(p)))
            .unwrap_or(a);
    }
    a + ab * (vb * denom) + ac * (vc * denom)
}

/// A light's maps: one technique's maps per view, with the views that pick one per receiver.
#[derive(Debug)]
pub struct ViewMaps<M> {
    views: LightViews,
    maps: Vec<M>,
}

impl<M> ViewMaps<M> {
    /// The maps of `views`, one per view, in order.
    pub(crate) fn new(views: LightViews, maps: Vec<M>) -> Self {
        debug_assert_eq!(views.len(), maps.len());
        Self { views, maps }
    }

    /// The views.
    pub fn views(&self) -> &LightViews {
        &self.views
    }

    /// The maps of every view, in the views' order.
    pub fn maps(&self) -> &[M] {
        &self.maps
    }

    /// The maps of the first view (the only one where the light has one).
    pub fn first(&self) -> &M {
        &self.maps[0]
    }

    /// The maps, for recycling.
    pub fn into_maps(self) -> Vec<M> {
        self.maps
    }

    /// The views `planned` with the maps of views `indices` replaced by `fresh` (made for
    /// `planned.only(indices)`), in order; the replaced maps are returned for recycling.
    pub(crate) fn splice(
        &mut self,
        planned: &LightViews,
        indices: &[usize],
        fresh: Vec<M>,
    ) -> Vec<M> {
        debug_assert_eq!(indices.len(), fresh.len());
        let old = indices
            .iter()
            .zip(fresh)
            .map(|(&i, m)| std::mem::replace(&mut self.maps[i], m))
            .collect();
        self.views = planned.clone();
        old
    }
}

/// `V` per receiver from per-view evaluations: `eval(i, receivers)` evaluates view `i` over the
/// receivers it holds, and each receiver's `V` is `1 - total + sum(weight_i V_i)` over the views
/// in order ([`LightViews::weight`], [`LightViews::total_weight`]), as the GPU passes add them,
/// clamped to [0, 1] after each: every partial sum lies in [0, 1], but the shares of two or three
/// faces at a seam sum to `total` only within rounding (an umbra read `-1.2e-7`).
pub(crate) fn combine(
    views: &LightViews,
    r: &Receivers,
    mut eval: impl FnMut(usize, Receivers) -> Result<Vec<f32>>,
) -> Result<Vec<f32>> {
    if views.select == Select::One {
        return eval(0, *r);
    }
    // Each receiver's views and weights, once (in parallel), then `1 - total` and the
    // receivers each view holds, in order.
    use rayon::prelude::*;
    let select = views.gpu_select(0);
    let shares: Vec<[(i32, f32); 3]> = r.positions.par_iter().map(|p| select.shares(*p)).collect();
    let mut held: Vec<Vec<(usize, f32)>> = vec![Vec::new(); views.len()];
    let mut out: Vec<f32> = Vec::with_capacity(r.positions.len());
    for (j, shares) in shares.into_iter().enumerate() {
        out.push((1.0 - select.total_of(&shares)).clamp(0.0, 1.0));
        for (v, w) in shares {
            if v >= 0 && w > 0.0 {
                held[v as usize].push((j, w));
            }
        }
    }
    for (i, held) in held.iter().enumerate() {
        if held.is_empty() {
            continue;
        }
        let positions: Vec<Vec3> = held.iter().map(|&(j, _)| r.positions[j]).collect();
        let normals: Vec<Vec3> = held.iter().map(|&(j, _)| r.normals[j]).collect();
        let v = eval(i, Receivers::new(&positions, &normals))?;
        for (&(j, w), v) in held.iter().zip(v) {
            out[j] = (out[j] + w * v).clamp(0.0, 1.0);
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A plate on each side of a point light, so that its plan takes all six cube faces.
    fn boxed_light() -> (Light, LightViews) {
        let light = Light::Point {
            position: Vec3::ZERO,
        };
        let plate = |n: Vec3| -> Vec<[Vec3; 3]> {
            let (u, v) = orthonormal_basis(n);
            let c = 2.0 * n;
            vec![
                [c - u - v, c + u - v, c + u + v],
                [c - u - v, c + u + v, c - u + v],
            ]
        };
        let casters: Vec<[Vec3; 3]> = [Vec3::X, Vec3::NEG_X, Vec3::Y, Vec3::NEG_Y, Vec3::Z]
            .into_iter()
            .chain([Vec3::NEG_Z])
            .flat_map(plate)
            .collect();
        let geometry = SceneGeometry::new(casters, Vec::new());
        let views = LightViews::plan(&light, &geometry, None);
        (light, views)
    }

    /// `V` combined over cube faces stays in [0, 1] where every view reads 1 (lit) or 0 (umbra),
    /// the faces' shares summed in `f32` notwithstanding: receivers near seams and corners, where
    /// two or three faces share a direction.
    #[test]
    fn combined_visibility_stays_in_the_unit_interval_at_seams() {
        let (_, views) = boxed_light();
        assert_eq!(views.len(), 6, "{:?}", views.kind_name());
        let mut positions = Vec::new();
        for i in 0..200 {
            for j in 0..200 {
                let (a, b) = (i as f32 / 199.0, j as f32 / 199.0);
                // Directions near the +x/+y seam and the +x/+y/+z corner.
                positions.push(Vec3::new(1.0, 0.8 + 0.2 * a, 0.8 * b) * 1.7);
                positions.push(Vec3::new(1.0, 0.85 + 0.15 * a, 0.85 + 0.15 * b) * 0.9);
            }
        }
        let normals = vec![Vec3::Y; positions.len()];
        let r = Receivers::new(&positions, &normals);
        for value in [0.0f32, 1.0] {
            let v = combine(&views, &r, |_, sub| Ok(vec![value; sub.positions.len()])).unwrap();
            let out: Vec<f32> = v
                .iter()
                .copied()
                .filter(|x| !(0.0..=1.0).contains(x))
                .collect();
            assert!(
                out.is_empty(),
                "every view reading {value}: {} receivers outside [0, 1], e.g. {:?}",
                out.len(),
                &out[..out.len().min(4)]
            );
        }
    }
}
