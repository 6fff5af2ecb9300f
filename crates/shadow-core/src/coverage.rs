//! What a light's maps must cover ("maps cover what casts"): the casters that can
//! shadow a receiver, and the receivers their shadows and penumbrae can reach, never geometry
//! that only receives light where nothing can shadow it.
//!
//! From a light point `q`, a receiver `X` shadowed by caster point `Y` as seen from another light
//! point `q'` lies on `Y + t (Y - q')`, `t >= 0`, no deeper than the scene. Per `q'` these points
//! form the convex hull of the caster box's corners `C` and their extensions `C + t (C - q')` to
//! the scene's deepest depth, so the window of a perspective map from `q` (the range of `x/z`
//! and `y/z`, reached at vertices) only needs those points. For an
//! orthographic map (distant light) the caster box's window grows by the scene's depth below the
//! casters times the tangent of the light's cone. Both are then clipped to the window of the
//! whole scene, and get [`MARGIN`] for filter kernels.

use crate::geometry::SceneGeometry;
use crate::light::{Light, LightPoint};
use crate::mesh::Aabb;
use glam::Vec3;

/// What one view covers, the region a technique fits its maps to.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub enum Region {
    /// Everything the maps cover, in one frustum or window fitted around the casters
    /// ([`crate::View::fit_light`]).
    Whole,
    /// One face of a cube around a local light: a perspective view from each light point along
    /// `axis`, its image's y axis along `up`, with a square window of half-angle `half_angle`
    /// (radians).
    Face {
        /// Unit direction the face looks along.
        axis: Vec3,
        /// Unit direction of the image's y axis, perpendicular to `axis`.
        up: Vec3,
        /// Half-angle of the window, radians (45 degrees and the guard).
        half_angle: f32,
    },
    /// One cascade of a distant light: an orthographic window in the light's basis, centred on
    /// `center` (moved to whole texels of the map), `half_extent` wide, over the heights along
    /// the direction to the light (`direction . p`) from `heights[0]`, the lowest receiver of
    /// its slice, to `heights[1]`, the highest caster over its window: an 8-bit or 16-bit map
    /// spends its steps on what this cascade holds.
    Cascade {
        /// The world point the window is centred on before snapping.
        center: Vec3,
        /// Half the side of the square window, world units.
        half_extent: f32,
        /// Lowest and highest `direction . p` the cascade's depth range must hold.
        heights: [f32; 2],
    },
}

/// Relative margin added to each window, so filter kernels near its edge read empty texels.
pub const MARGIN: f32 = 0.06;

/// The region a light's maps must cover.
#[derive(Clone, Debug, PartialEq)]
pub struct Coverage {
    /// Bounds of the shadow casters (empty when nothing casts); in a cube face's coverage of a
    /// generation ([`crate::Generation::coverage`]), of the parts of them inside the face (and
    /// of the receivers there too, for maps that hold them:
    /// [`crate::Generation::coverage_with_receivers_of`]).
    pub casters: Aabb,
    /// Bounds of all geometry, casters and receivers: caps every window and sets the depth range.
    pub scene: Aabb,
    /// A convex outline of the light whose penumbrae the maps must hold: positions for a local
    /// light (a sphere's bounding-box corners), directions for a distant one.
    pub light: Vec<LightPoint>,
    /// The part of it one view covers ([`crate::views`]): the whole, a cube face or a cascade.
    pub region: Region,
    /// The map side the view's window is snapped to (a cascade's window moves by whole
    /// texels); 0: not snapped.
    pub texels: u32,
}

impl Coverage {
    /// The coverage of `geometry`'s casters for `light`.
    pub fn new(geometry: &SceneGeometry, light: &Light) -> Self {
        let casters = Aabb::of_triangles(&geometry.casters);
        let light_outline = match *light {
            Light::Sphere { center, radius } => Aabb {
                min: center - Vec3::splat(radius),
                max: center + Vec3::splat(radius),
            }
            .corners()
            .into_iter()
            .map(LightPoint::Position)
            .collect(),
            _ => light.outline(casters_or(&casters, &geometry.bounds).center()),
        };
        Self {
            casters,
            scene: geometry.bounds,
            light: light_outline,
            region: Region::Whole,
            texels: 0,
        }
    }

    /// The same coverage restricted to one view's `region`, its window snapped to the texels
    /// of a `texels`-wide map (0: not snapped).
    pub fn within(self, region: Region, texels: u32) -> Self {
        Self {
            region,
            texels,
            ..self
        }
    }

    /// For a cube face's coverage ([`Region::Face`]), `casters` set to the bounds of the parts
    /// of `held` (the triangles the maps hold: the casters, and for maps that hold more, those
    /// too) inside the face's pyramid around `light`'s centre, grown by its radius so that the
    /// face's pyramid from any point of the light holds none beyond them ([`face_casters`]):
    /// the face's depth range then starts just before the nearest of them
    /// ([`crate::View::fit_light`]). Other coverages are returned as they are.
    pub(crate) fn in_face_of(mut self, held: &[&[[Vec3; 3]]], light: &Light) -> Self {
        if let (Region::Face { .. }, LightPoint::Position(c)) = (self.region, light.center()) {
            let r = light_radius(light, c);
            let mut bounds = Aabb::EMPTY;
            for triangles in held {
                let b = face_casters(triangles, &self.region, c, r);
                if !b.is_empty() {
                    bounds.grow(b.min);
                    bounds.grow(b.max);
                }
            }
            self.casters = bounds;
        }
        self
    }

    /// Coverage of a whole box (every point of it may cast, no penumbra beyond it): for maps of
    /// a given region, such as tests of the rasterizer.
    pub fn whole(bounds: &Aabb) -> Self {
        Self {
            casters: *bounds,
            scene: *bounds,
            light: Vec::new(),
            region: Region::Whole,
            texels: 0,
        }
    }

    /// The box the maps are fitted around: the casters' (the scene's when nothing casts).
    pub fn fit_box(&self) -> &Aabb {
        casters_or(&self.casters, &self.scene)
    }

    /// The point a light looks at (for lights without an emission normal, and the receiver
    /// its samples face): the casters' centre, or for a cube face ([`Region::Face`]) a point
    /// along the face's axis from the light.
    pub fn center(&self) -> Vec3 {
        match self.region {
            Region::Face { axis, .. } => {
                let positions: Vec<Vec3> = self
                    .light
                    .iter()
                    .filter_map(|q| match q {
                        LightPoint::Position(p) => Some(*p),
                        LightPoint::Direction(_) => None,
                    })
                    .collect();
                let light = positions.iter().sum::<Vec3>() / positions.len().max(1) as f32;
                light + axis * self.scene.diagonal().max(1e-3)
            }
            _ => self.fit_box().center(),
        }
    }
}

fn casters_or<'a>(casters: &'a Aabb, scene: &'a Aabb) -> &'a Aabb {
    if casters.is_empty() { scene } else { casters }
}

/// Whether something inside the box `caster` can shadow a receiver point within `radius` of `p`
/// from some point of `light`: whether the cone from `p` around the light (a local light's
/// bounding sphere, a distant light's cone of directions), widened by `radius`, meets the box
/// beyond `p`. Conservative: `true` whenever the box might block a light point; `false` proves
/// that nothing in it does, such as for a convex caster's own faces turned to the light.
///
/// Along the cone's axis `p + s a`, `dist(p + s a, caster) - w(s)` (with `w` the cone's radius,
/// linear in `s`) is convex in `s`; the box meets the cone where it is at most 0. It is
/// minimised over `s` from a thousandth of the box's diagonal (so a receiver on the box's surface
/// does not count the box as shadowing it where the light leaves that surface) to the light, or
/// past the box.
pub fn can_shadow(light: &Light, caster: &Aabb, p: Vec3, radius: f32) -> bool {
    if caster.is_empty() {
        return false;
    }
    // The octagons of `Light::outline` circumscribe a circle of radius r with r / cos(pi / 8).
    let circumscribed = 1.0 / (std::f32::consts::PI / 8.0).cos();
    let far = (caster.center() - p).length() + caster.diagonal() + radius;
    // The cone's axis, its length, and its radius `w0 + w1 s` at `s` along it: for a distant
    // light the receiver's ball swept along the cone of directions; for a local one the convex
    // hull of the receiver's ball and the light's bounding ball (radii interpolated along the
    // axis, over the cosine of the hull's half-angle).
    let (axis, end, w0, w1) = match light.center() {
        LightPoint::Direction(d) => {
            let half = match *light {
                Light::Distant {
                    angular_diameter, ..
                } => (0.5 * angular_diameter).tan() * circumscribed,
                _ => 0.0,
            };
            (d, far, radius, half)
        }
        LightPoint::Position(c) => {
            let v = c - p;
            let l = v.length();
            let rho = light_radius(light, c);
            if l.is_nan() || l <= rho + radius {
                // The receiver's ball reaches the light's.
                return true;
            }
            let cos = (1.0 - ((rho - radius) / l).powi(2)).sqrt();
            (v / l, l.min(far), radius / cos, (rho - radius) / (l * cos))
        }
    };
    let f = |s: f32| box_distance(caster, p + axis * s) - (w0 + w1 * s);
    let (mut a, mut b) = (1e-3 * caster.diagonal(), end);
    if a.is_nan() || b.is_nan() || a >= b {
        // The light lies closer than the search starts: one test at the light.
        return f(b.max(0.0)) <= 0.0;
    }
    if f(a) <= 0.0 || f(b) <= 0.0 {
        return true;
    }
    // Golden-section search of the convex `f`.
    let g = 0.5 * (5f32.sqrt() - 1.0);
    let (mut x1, mut x2) = (b - g * (b - a), a + g * (b - a));
    let (mut f1, mut f2) = (f(x1), f(x2));
    for _ in 0..48 {
        if f1 <= 0.0 || f2 <= 0.0 {
            return true;
        }
        if f1 < f2 {
            b = x2;
            (x2, f2) = (x1, f1);
            x1 = b - g * (b - a);
            f1 = f(x1);
        } else {
            a = x1;
            (x1, f1) = (x2, f2);
            x2 = a + g * (b - a);
            f2 = f(x2);
        }
    }
    f1 <= 0.0 || f2 <= 0.0
}

/// The radius of a sphere around `c` (a local light's centre) holding every point of `light`.
pub fn light_radius(light: &Light, c: Vec3) -> f32 {
    match *light {
        Light::Sphere { radius, .. } => radius,
        _ => light
            .outline(c)
            .iter()
            .filter_map(|q| match q {
                LightPoint::Position(q) => Some((*q - c).length()),
                LightPoint::Direction(_) => None,
            })
            .fold(0.0, f32::max),
    }
}

/// Distance from `p` to the box `b` (0 inside).
fn box_distance(b: &Aabb, p: Vec3) -> f32 {
    (b.min - p).max(p - b.max).max(Vec3::ZERO).length()
}

/// The indices of the casters of `instances` (each one object's world-space triangles) that
/// [`can_shadow`] one of the receiver points `seen`, in order: those [`casting_onto`] keeps.
pub fn casting_instances(light: &Light, instances: &[Vec<[Vec3; 3]>], seen: &[Vec3]) -> Vec<usize> {
    instances
        .iter()
        .enumerate()
        .filter(|(_, tris)| {
            let b = Aabb::of_triangles(tris);
            seen.iter().any(|&p| can_shadow(light, &b, p, 0.0))
        })
        .map(|(i, _)| i)
        .collect()
}

/// The geometry a light's maps need to shadow what a camera sees, the receiver points `seen`:
/// of the casters `instances` (each one object's world-space triangles), those that
/// [`can_shadow`] one of the points; the receiving triangles `receivers`; and bounds over the
/// casters kept and the receiving triangles they can shadow (every receiving triangle when no
/// caster is kept). A caster that shadows nothing in view takes no part in the maps, nor does a
/// receiver no caster can reach. Each instance is tested against the points until one can be
/// shadowed, so an instance left out costs a test per point: meant once per view, not per
/// frame of thousands of instances.
pub fn casting_onto(
    light: &Light,
    instances: &[Vec<[Vec3; 3]>],
    receivers: Vec<[Vec3; 3]>,
    seen: &[Vec3],
) -> SceneGeometry {
    let mut casters = Vec::new();
    let mut boxes = Vec::new();
    for i in casting_instances(light, instances, seen) {
        let tris = &instances[i];
        casters.extend_from_slice(tris);
        boxes.push(Aabb::of_triangles(tris));
    }
    let mut bounds = Aabb::of_triangles(&casters);
    for t in &receivers {
        let centre = (t[0] + t[1] + t[2]) / 3.0;
        let radius = t.iter().map(|v| v.distance(centre)).fold(0.0, f32::max);
        if boxes.is_empty() || boxes.iter().any(|b| can_shadow(light, b, centre, radius)) {
            t.iter().for_each(|&v| bounds.grow(v));
        }
    }
    SceneGeometry {
        casters,
        receivers,
        bounds,
    }
}

/// The inward normals of a cube face's pyramid (apex at the light, looking along `axis` with
/// its image's y axis along `up`, a square window of half-angle `half_angle`): its four side
/// planes, then the plane through the apex. A point `q` lies inside where `(q - apex) . n >= 0`
/// for every `n`.
pub(crate) fn face_planes(axis: Vec3, up: Vec3, half_angle: f32) -> [Vec3; 5] {
    let tan_half = half_angle.tan();
    let right = axis.cross(up);
    [
        axis * tan_half + right,
        axis * tan_half - right,
        axis * tan_half + up,
        axis * tan_half - up,
        axis,
    ]
}

/// The bounds of the parts of `casters` (the triangles a face's maps hold) inside the pyramid
/// of cube face `region` around `apex`, grown by `radius` (each plane moved out by it): the
/// pyramid of every light point within `radius` of `apex` lies inside, so a face's map from
/// any of them holds none of them outside these bounds. Each triangle is clipped to the grown
/// pyramid (Sutherland-Hodgman); empty where none reaches it, and for another region.
pub(crate) fn face_casters(
    casters: &[[Vec3; 3]],
    region: &Region,
    apex: Vec3,
    radius: f32,
) -> Aabb {
    let Region::Face {
        axis,
        up,
        half_angle,
    } = *region
    else {
        return Aabb::EMPTY;
    };
    // Each plane as `q . n >= w`: inside the grown pyramid.
    let planes = face_planes(axis, up, half_angle).map(|n| (n, apex.dot(n) - radius * n.length()));
    let mut bounds = Aabb::EMPTY;
    let (mut poly, mut next) = (Vec::with_capacity(9), Vec::with_capacity(9));
    for t in casters {
        // Signed distances (scaled) of the three vertices to each plane.
        let sides = planes.map(|(n, w)| t.map(|q| q.dot(n) - w));
        if sides.iter().any(|s| s.iter().all(|&d| d < 0.0)) {
            continue;
        }
        if sides.iter().all(|s| s.iter().all(|&d| d >= 0.0)) {
            t.iter().for_each(|&q| bounds.grow(q));
            continue;
        }
        poly.clear();
        poly.extend_from_slice(t);
        for &(n, w) in &planes {
            next.clear();
            for (i, &a) in poly.iter().enumerate() {
                let b = poly[(i + 1) % poly.len()];
                let (sa, sb) = (a.dot(n) - w, b.dot(n) - w);
                if sa >= 0.0 {
                    next.push(a);
                }
                if (sa >= 0.0) != (sb >= 0.0) {
                    next.push(a + (b - a) * (sa / (sa - sb)));
                }
            }
            std::mem::swap(&mut poly, &mut next);
            if poly.is_empty() {
                break;
            }
        }
        poly.iter().for_each(|&q| bounds.grow(q));
    }
    bounds
}
