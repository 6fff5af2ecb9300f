//! Views: the camera and the light-space frusta that shadow maps are rendered from.
//!
//! Both use a reversed-Z projection (NDC depth 1 at the near plane, 0 at the far plane) so that an
//! `f32` depth keeps its relative precision over depth ranges such as 1e-3..1e4.

use crate::coverage::{Coverage, MARGIN, Region};
use crate::light::{Light, LightPoint};
use crate::mesh::Aabb;
use glam::{Mat4, Vec3, Vec4};

/// Sentinel stored in a linear depth map where no surface was rasterized.
pub const NO_OCCLUDER: f32 = f32::MAX;

/// Kind of projection of a [`View`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ProjectionKind {
    /// Perspective with the full vertical and horizontal field of view `fov` (radians, square).
    Perspective {
        /// Full field of view.
        fov: f32,
    },
    /// Orthographic with the square half-extent `half_extent` (world units).
    Orthographic {
        /// Half of the side of the square window.
        half_extent: f32,
    },
}

/// A view (world to view to reversed-Z clip space) with its depth range.
///
/// View space is right-handed and looks along -Z; *linear depth* is the distance along the view axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct View {
    /// World to view space.
    pub view: Mat4,
    /// The projection.
    pub kind: ProjectionKind,
    /// Near plane distance (> 0 for perspective).
    pub near: f32,
    /// Far plane distance.
    pub far: f32,
    /// Aspect ratio width / height (1 for light views).
    pub aspect: f32,
}

pub(crate) fn look_to(eye: Vec3, axis: Vec3) -> Mat4 {
    let up = if axis.y.abs() > 0.99 {
        Vec3::Z
    } else {
        Vec3::Y
    };
    look_to_up(eye, axis.normalize(), up)
}

/// World to view for an eye at `eye` looking along unit `dir`, with `up` (not parallel to `dir`)
/// giving the image's y axis: view x is `dir x up` normalised, view y is `x x dir`.
pub fn look_to_up(eye: Vec3, dir: Vec3, up: Vec3) -> Mat4 {
    let s = dir.cross(up).normalize();
    let u = s.cross(dir);
    Mat4::from_cols(
        Vec4::new(s.x, u.x, -dir.x, 0.0),
        Vec4::new(s.y, u.y, -dir.y, 0.0),
        Vec4::new(s.z, u.z, -dir.z, 0.0),
        Vec4::new(-s.dot(eye), -u.dot(eye), dir.dot(eye), 1.0),
    )
}

impl View {
    /// A perspective view from `eye` along unit `axis`.
    pub fn perspective(eye: Vec3, axis: Vec3, fov: f32, aspect: f32, near: f32, far: f32) -> Self {
        Self {
            view: look_to(eye, axis),
            kind: ProjectionKind::Perspective { fov },
            near,
            far,
            aspect,
        }
    }

    /// The reversed-Z projection matrix (view to clip).
    pub fn projection(&self) -> Mat4 {
        let (n, f) = (self.near, self.far);
        match self.kind {
            ProjectionKind::Perspective { fov } => {
                let sy = 1.0 / (0.5 * fov).tan();
                let sx = sy / self.aspect;
                // z_ndc = n (f - z) / (z (f - n)) with z = -z_view: 1 at near, 0 at far.
                let a = -n / (f - n);
                let b = n * f / (f - n);
                Mat4::from_cols(
                    Vec4::new(sx, 0.0, 0.0, 0.0),
                    Vec4::new(0.0, sy, 0.0, 0.0),
                    Vec4::new(0.0, 0.0, -a, -1.0),
                    Vec4::new(0.0, 0.0, b, 0.0),
                )
            }
            ProjectionKind::Orthographic { half_extent } => {
                let s = 1.0 / half_extent;
                // z_ndc = (f - z) / (f - n) with z = -z_view.
                Mat4::from_cols(
                    Vec4::new(s / self.aspect, 0.0, 0.0, 0.0),
                    Vec4::new(0.0, s, 0.0, 0.0),
                    Vec4::new(0.0, 0.0, 1.0 / (f - n), 0.0),
                    Vec4::new(0.0, 0.0, f / (f - n), 1.0),
                )
            }
        }
    }

    /// World to clip.
    pub fn view_projection(&self) -> Mat4 {
        self.projection() * self.view
    }

    /// Converts a reversed-Z NDC depth to linear depth; `<= 0` (the cleared value) gives [`NO_OCCLUDER`].
    pub fn linear_depth_from_ndc(&self, z_ndc: f32) -> f32 {
        if z_ndc <= 0.0 {
            return NO_OCCLUDER;
        }
        let (n, f) = (self.near, self.far);
        match self.kind {
            ProjectionKind::Perspective { .. } => n * f / (z_ndc * (f - n) + n),
            ProjectionKind::Orthographic { .. } => f - z_ndc * (f - n),
        }
    }

    /// Linear depth of a world point (distance along the view axis).
    pub fn linear_depth(&self, p: Vec3) -> f32 {
        -self.view.transform_point3(p).z
    }

    /// Map coordinates of a world point: `(u, v)` in `[0, 1]²` (v down) and its linear depth,
    /// or `None` when it lies behind a perspective eye.
    pub fn project(&self, p: Vec3) -> Option<(f32, f32, f32)> {
        let clip = self.view_projection() * p.extend(1.0);
        if clip.w <= 0.0 {
            return None;
        }
        let ndc = clip.truncate() / clip.w;
        Some((ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5, self.linear_depth(p)))
    }

    /// World size of one texel of a `resolution`-wide map at linear depth `z`:
    /// `a * z + b` with `(a, b)` from [`View::texel_scale`].
    pub fn texel_world_size(&self, resolution: u32, z: f32) -> f32 {
        let (a, b) = self.texel_scale(resolution);
        a * z + b
    }

    /// `(a, b)` with texel world size `a * z + b`: `(2 tan(fov/2) / resolution, 0)` for perspective,
    /// `(0, 2 half_extent / resolution)` for orthographic views.
    pub fn texel_scale(&self, resolution: u32) -> (f32, f32) {
        let r = resolution.max(1) as f32;
        match self.kind {
            ProjectionKind::Perspective { fov } => (2.0 * (0.5 * fov).tan() / r, 0.0),
            ProjectionKind::Orthographic { half_extent } => (0.0, 2.0 * half_extent / r),
        }
    }

    /// A light-space view from one light sample that covers `coverage` (the casters and the
    /// receivers their penumbrae reach; see [`crate::coverage`]) within its region
    /// ([`crate::views::Region`]), looking along `axis`.
    ///
    /// Perspective from a position: for the whole coverage, a square window around `axis`
    /// fitted to the casters and their penumbrae, clamped to 2 x 80 degrees
    /// ([`crate::views::LightViews::plan`] gives a light whose casters need more than 2 x 75
    /// degrees cube faces instead); for a cube face, the face's axis and window. The depth range
    /// spans the whole scene; a cube face's starts just before the nearest caster it holds
    /// (`coverage.casters`, as [`crate::Generation::coverage`] narrows it; with the receivers
    /// for maps that hold them). Orthographic for a direction: the window is centred on what it
    /// covers (a cascade: its own window, centred on whole texels), the depth range starts just
    /// before the nearest caster (1% of the range before it) and ends beyond the scene's
    /// deepest point.
    pub fn fit_light(sample: LightPoint, axis: Vec3, coverage: &Coverage) -> View {
        let axis = axis.normalize();
        let bounds = &coverage.scene;
        let diag = bounds.diagonal().max(1e-6);
        match sample {
            LightPoint::Position(eye) => {
                // A cube face has its own axis and window; otherwise the window is fitted.
                let (view, half) = match coverage.region {
                    Region::Face {
                        axis,
                        up,
                        half_angle,
                    } => (look_to_up(eye, axis, up), half_angle),
                    _ => {
                        let view = look_to(eye, axis);
                        let tan_max = perspective_tan(&view, eye, coverage);
                        let half =
                            tan_max.atan().clamp(1f32.to_radians(), 80f32.to_radians()) * 1.02;
                        (view, half)
                    }
                };
                let depth = |c: Vec3| -view.transform_point3(c).z;
                let zmax = bounds
                    .corners()
                    .map(depth)
                    .into_iter()
                    .fold(0.0f32, f32::max);
                // A cube face starts before the nearest caster it holds (`Coverage::casters`,
                // narrowed to the face by `Generation::coverage`; with the receivers where the
                // maps hold them too), as a distant light's window does: an 8-bit or 16-bit
                // map spends its steps on what casts, and nothing nearer can shadow a
                // receiver in the face.
                let near_box = match coverage.region {
                    Region::Face { .. } if !coverage.casters.is_empty() => &coverage.casters,
                    _ => bounds,
                };
                let zmin = near_box
                    .corners()
                    .map(depth)
                    .into_iter()
                    .fold(f32::INFINITY, f32::min);
                let far = (zmax * 1.01).max(1e-3 * diag);
                // The box's nearest point is at depth max(zmin, 0): when a corner lies behind the
                // eye's plane, geometry can come arbitrarily close, so the near plane goes down to
                // 1e-5 of the far plane (reversed-Z float keeps the precision).
                let near = if zmin > 0.0 { zmin * 0.95 } else { 0.0 };
                let near = near.max(far * 1e-5);
                View {
                    view,
                    kind: ProjectionKind::Perspective { fov: 2.0 * half },
                    near,
                    far,
                    aspect: 1.0,
                }
            }
            LightPoint::Direction(dir) => {
                let dir = dir.normalize();
                // The eye sits outside the bounds, towards the light.
                let radius = 0.5 * diag;
                let eye = bounds.center() + dir * (radius * 1.1 + 1e-3);
                let view = look_to(eye, -dir);
                let range = |b: &Aabb| {
                    let (mut lo, mut hi) =
                        (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
                    for c in b.corners() {
                        let v = view.transform_point3(c);
                        let v = Vec3::new(v.x, v.y, -v.z);
                        lo = lo.min(v);
                        hi = hi.max(v);
                    }
                    (lo, hi)
                };
                let (all_lo, all_hi) = range(bounds);
                let (cast_lo, cast_hi) = range(coverage.fit_box());
                // Penumbra spread per unit of depth: the widest outline direction's tangent.
                let spread = coverage
                    .light
                    .iter()
                    .filter_map(|q| match q {
                        LightPoint::Direction(d) => {
                            let v = view.transform_vector3(-d.normalize());
                            (-v.z > 1e-3).then(|| v.x.abs().max(v.y.abs()) / -v.z)
                        }
                        LightPoint::Position(_) => None,
                    })
                    .fold(0.0f32, f32::max);
                let grow = (all_hi.z - cast_lo.z).max(0.0) * spread;
                let lo = (cast_lo - Vec3::splat(grow)).max(all_lo);
                let hi = (cast_hi + Vec3::splat(grow)).min(all_hi);
                let (mid_x, mid_y, half_extent) = match coverage.region {
                    Region::Cascade {
                        center,
                        half_extent,
                        ..
                    } => {
                        // The cascade's own window, its centre on whole texels of the light's
                        // basis (absolute coordinates, so the grid does not move with the scene).
                        let c = view.transform_point3(center);
                        let texel = if coverage.texels > 0 {
                            2.0 * half_extent / coverage.texels as f32
                        } else {
                            0.0
                        };
                        let snap = |rel: f32, origin: f32| {
                            if texel > 0.0 {
                                ((rel + origin) / texel).round() * texel - origin
                            } else {
                                rel
                            }
                        };
                        // The eye's own coordinates in the basis: the grid's origin is the world's.
                        let basis = look_to(Vec3::ZERO, -dir);
                        let o = basis.transform_point3(eye);
                        (snap(c.x, o.x), snap(c.y, o.y), half_extent)
                    }
                    _ => {
                        let mid = 0.5 * (lo + hi);
                        let half = 0.5 * (hi.x - lo.x).max(hi.y - lo.y).max(0.0);
                        (mid.x, mid.y, half * (1.0 + MARGIN) * 1.01 + 1e-6 * diag)
                    }
                };
                // Centre the window: move the eye across the view.
                let inv = view.inverse();
                let eye = eye
                    + inv.transform_vector3(Vec3::X) * mid_x
                    + inv.transform_vector3(Vec3::Y) * mid_y;
                let view = look_to(eye, -dir);
                let clip = (0.05 * radius).max(1e-6);
                // The depth range starts just before the nearest caster: nothing in front of it
                // casts, and an 8-bit or 16-bit map spends its steps on what does. A cascade
                // holds its own heights (its lowest receiver, its highest caster).
                let (cast_near, deepest) = match coverage.region {
                    Region::Cascade { heights, .. } => {
                        let eye_h = eye.dot(dir);
                        (
                            (eye_h - heights[1]).max(cast_lo.z),
                            (eye_h - heights[0]).min(all_hi.z),
                        )
                    }
                    _ => (cast_lo.z, all_hi.z),
                };
                let far = deepest * 1.01 + clip;
                let near = (cast_near - 0.01 * (far - cast_near)).max(clip);
                View {
                    view,
                    kind: ProjectionKind::Orthographic { half_extent },
                    near,
                    far,
                    aspect: 1.0,
                }
            }
        }
    }

    /// The tangent of the half-angle of the square window a perspective view from `eye` along
    /// `axis` needs to hold `coverage`'s casters and their penumbrae (with the filters'
    /// margin), before [`View::fit_light`] clamps it to 80 degrees; infinite when a caster
    /// lies beside or behind the eye.
    pub(crate) fn window_tan(eye: Vec3, axis: Vec3, coverage: &Coverage) -> f32 {
        perspective_tan(&look_to(eye, axis.normalize()), eye, coverage)
    }

    /// The light view of `light`'s centre sample, covering `coverage`.
    pub fn for_light_center(light: &Light, coverage: &Coverage) -> View {
        View::fit_light(light.center(), light.axis(coverage.center()), coverage)
    }
}

/// The tangent of [`View::window_tan`] for a perspective `view` from `eye`: the casters' corners,
/// and where their penumbra reaches at the scene's deepest depth, from each corner away from
/// each light point (a direction that never gets deeper bounds the window by its own tangent),
/// capped by the whole scene's window.
fn perspective_tan(view: &Mat4, eye: Vec3, coverage: &Coverage) -> f32 {
    let bounds = &coverage.scene;
    let fit = coverage.fit_box();
    let diag = bounds.diagonal().max(1e-6);
    // Widest tangent over directions, infinite when one is not in front.
    let tan_of = |d: Vec3| {
        let v = view.transform_vector3(d);
        let z = -v.z;
        if z > 1e-6 * d.length().max(1e-30) {
            v.x.abs().max(v.y.abs()) / z
        } else {
            f32::INFINITY
        }
    };
    let mut zmax = 0.0f32;
    let mut tan_all: f32 = 0.0;
    for c in bounds.corners() {
        let z = -view.transform_point3(c).z;
        zmax = zmax.max(z);
        tan_all = tan_all.max(if z > 1e-6 * diag {
            tan_of(c - eye)
        } else {
            f32::INFINITY
        });
    }
    let mut tan_cast: f32 = 0.0;
    for c in fit.corners() {
        tan_cast = tan_cast.max(tan_of(c - eye));
        let zc = -view.transform_point3(c).z;
        for q in &coverage.light {
            if let LightPoint::Position(q) = q {
                let d = c - *q;
                let dz = -view.transform_vector3(d).z;
                tan_cast = tan_cast.max(if dz > 1e-6 * d.length() {
                    tan_of(c + d * ((zmax - zc).max(0.0) / dz) - eye)
                } else {
                    tan_of(d)
                });
            }
        }
    }
    tan_all.min(tan_cast) * (1.0 + MARGIN)
}

/// A perspective camera for the G-buffer.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// Eye position.
    pub eye: Vec3,
    /// Point looked at.
    pub target: Vec3,
    /// Vertical field of view in radians.
    pub fov_y: f32,
    /// Near plane.
    pub near: f32,
    /// Far plane.
    pub far: f32,
}

impl Camera {
    /// The camera's view for a `width` x `height` image.
    pub fn view(&self, width: u32, height: u32) -> View {
        let axis = (self.target - self.eye).normalize();
        View::perspective(
            self.eye,
            axis,
            self.fov_y,
            width as f32 / height.max(1) as f32,
            self.near,
            self.far,
        )
    }
}
