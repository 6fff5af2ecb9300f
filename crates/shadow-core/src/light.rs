//! The light kinds, their validation and their sampling.
//!
//! Visibility `V` is the fraction of the light's extent a point sees, weighted by the emission
//! profile: length for a segment, area for a rectangle or a disk, the visible disc for a sphere and
//! solid angle for a distant light.

use crate::error::{Result, ShadowError};
use glam::{Vec2, Vec3};

/// Linear limb-darkening coefficient of the built-in sun profile: `I(mu) = 1 - u (1 - mu)`.
///
/// `u = 0.6` is the usual value for the Sun in the visible band (Allen's *Astrophysical Quantities*).
pub const SUN_LIMB_DARKENING_U: f32 = 0.6;

/// Emission profile of a distant light across its disc.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub enum DistantProfile {
    /// Every direction inside the cone emits equally.
    UniformDisk,
    /// The linear limb-darkening law `I(mu) = 1 - u (1 - mu)` with `u` =
    /// [`SUN_LIMB_DARKENING_U`], `mu` the cosine of the angle on the solar sphere.
    LimbDarkenedSun,
}

/// A light source. All positions are in world space, metres.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub enum Light {
    /// A point light (hard shadows).
    Point {
        /// Position.
        position: Vec3,
    },
    /// A segment light from `a` to `b`.
    Linear {
        /// One end.
        a: Vec3,
        /// The other end.
        b: Vec3,
    },
    /// A rectangle `center + s u_half + t v_half`, `s, t in [-1, 1]`, emitting towards `u x v`.
    Rect {
        /// Centre.
        center: Vec3,
        /// Half of one side, as a vector.
        u_half: Vec3,
        /// Half of the other side, as a vector (orthogonal to `u_half`).
        v_half: Vec3,
    },
    /// A disk emitting towards `normal`.
    Disk {
        /// Centre.
        center: Vec3,
        /// Unit emission direction.
        normal: Vec3,
        /// Radius.
        radius: f32,
    },
    /// A triangle `a b c` emitting towards `(b - a) x (c - a)` (counter-clockwise seen from
    /// the lit side): the area light of Heidrich et al., section 4.
    Triangle {
        /// First vertex.
        a: Vec3,
        /// Second vertex.
        b: Vec3,
        /// Third vertex.
        c: Vec3,
    },
    /// A sphere; a receiver sees its silhouette disc.
    Sphere {
        /// Centre.
        center: Vec3,
        /// Radius.
        radius: f32,
    },
    /// A light at infinity seen under a cone.
    Distant {
        /// Unit vector from the scene towards the light's centre.
        direction: Vec3,
        /// Full apparent diameter in radians (the Sun: about 0.0093).
        angular_diameter: f32,
        /// How the disc emits.
        profile: DistantProfile,
    },
}

/// The kind of a [`Light`], without parameters.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
#[non_exhaustive]
pub enum LightKind {
    /// [`Light::Point`].
    Point,
    /// [`Light::Linear`].
    Linear,
    /// [`Light::Rect`].
    Rect,
    /// [`Light::Disk`].
    Disk,
    /// [`Light::Triangle`].
    Triangle,
    /// [`Light::Sphere`].
    Sphere,
    /// [`Light::Distant`].
    Distant,
}

impl LightKind {
    /// Every kind.
    pub const ALL: [LightKind; 7] = [
        LightKind::Point,
        LightKind::Linear,
        LightKind::Rect,
        LightKind::Disk,
        LightKind::Triangle,
        LightKind::Sphere,
        LightKind::Distant,
    ];

    /// Lower-case name used in errors and reports.
    pub fn name(self) -> &'static str {
        match self {
            LightKind::Point => "point",
            LightKind::Linear => "linear",
            LightKind::Rect => "rect",
            LightKind::Disk => "disk",
            LightKind::Triangle => "triangle",
            LightKind::Sphere => "sphere",
            LightKind::Distant => "distant",
        }
    }
}

/// One sample of a light: a position (local lights) or a direction towards the light (distant).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LightPoint {
    /// A point on a local light.
    Position(Vec3),
    /// A unit direction from the scene towards a distant light.
    Direction(Vec3),
}

/// An orthonormal basis `(t, b)` perpendicular to unit `n`.
pub fn orthonormal_basis(n: Vec3) -> (Vec3, Vec3) {
    let helper = if n.x.abs() < 0.9 { Vec3::X } else { Vec3::Y };
    let t = n.cross(helper).normalize();
    (t, n.cross(t))
}

/// Shirley-Chiu concentric map from the unit square to the unit disk (area preserving).
pub fn concentric_disk(u: Vec2) -> Vec2 {
    let a = 2.0 * u - Vec2::ONE;
    if a == Vec2::ZERO {
        return Vec2::ZERO;
    }
    let (r, phi) = if a.x.abs() > a.y.abs() {
        (a.x, std::f32::consts::FRAC_PI_4 * (a.y / a.x))
    } else {
        (
            a.y,
            std::f32::consts::FRAC_PI_2 - std::f32::consts::FRAC_PI_4 * (a.x / a.y),
        )
    };
    Vec2::new(r * phi.cos(), r * phi.sin())
}

/// The silhouette disc of the sphere `(center, radius)` seen from `p`: its centre, its unit
/// normal towards the sphere's centre and its radius; `None` where `p` lies inside the sphere
/// (within 1e-4 of its radius).
fn silhouette(center: Vec3, radius: f32, p: Vec3) -> Option<(Vec3, Vec3, f32)> {
    let to_center = center - p;
    let dist = to_center.length();
    if dist <= radius * 1.0001 {
        return None;
    }
    let w = to_center / dist;
    let disc_center = center - w * (radius * radius / dist);
    let disc_radius = radius * (1.0 - (radius / dist).powi(2)).max(0.0).sqrt();
    Some((disc_center, w, disc_radius))
}

fn check_finite(what: &str, v: Vec3) -> Result<()> {
    if v.is_finite() {
        Ok(())
    } else {
        Err(ShadowError::InvalidLight(format!(
            "{what} is not finite: {v:?}"
        )))
    }
}

fn check_size(what: &str, s: f32) -> Result<()> {
    if s.is_finite() && s > 0.0 {
        Ok(())
    } else {
        Err(ShadowError::InvalidLight(format!(
            "{what} must be positive and finite, got {s}"
        )))
    }
}

impl Light {
    /// The kind of this light.
    pub fn kind(&self) -> LightKind {
        match self {
            Light::Point { .. } => LightKind::Point,
            Light::Linear { .. } => LightKind::Linear,
            Light::Rect { .. } => LightKind::Rect,
            Light::Disk { .. } => LightKind::Disk,
            Light::Triangle { .. } => LightKind::Triangle,
            Light::Sphere { .. } => LightKind::Sphere,
            Light::Distant { .. } => LightKind::Distant,
        }
    }

    /// Checks every parameter: finite, positive sizes, non-degenerate directions.
    pub fn validate(&self) -> Result<()> {
        match *self {
            Light::Point { position } => check_finite("point position", position),
            Light::Linear { a, b } => {
                check_finite("segment end a", a)?;
                check_finite("segment end b", b)?;
                check_size("segment length", (b - a).length())
            }
            Light::Rect {
                center,
                u_half,
                v_half,
            } => {
                check_finite("rect centre", center)?;
                check_finite("rect u_half", u_half)?;
                check_finite("rect v_half", v_half)?;
                check_size("rect |u_half|", u_half.length())?;
                check_size("rect |v_half|", v_half.length())?;
                let cos = u_half.normalize().dot(v_half.normalize()).abs();
                if cos > 1e-3 {
                    return Err(ShadowError::InvalidLight(format!(
                        "rect sides must be orthogonal, cos(angle) = {cos}"
                    )));
                }
                Ok(())
            }
            Light::Disk {
                center,
                normal,
                radius,
            } => {
                check_finite("disk centre", center)?;
                check_finite("disk normal", normal)?;
                check_size("disk normal length", normal.length())?;
                check_size("disk radius", radius)
            }
            Light::Triangle { a, b, c } => {
                check_finite("triangle vertex a", a)?;
                check_finite("triangle vertex b", b)?;
                check_finite("triangle vertex c", c)?;
                let longest = (b - a).length().max((c - b).length()).max((a - c).length());
                check_size("triangle side", longest)?;
                // Twice the area over the longest side squared: the sine of the smallest angle
                // (up to a factor below 2); a sliver has no emitting normal worth the name.
                let flat = (b - a).cross(c - a).length() / (longest * longest);
                if flat.is_nan() || flat <= 1e-4 {
                    return Err(ShadowError::InvalidLight(format!(
                        "triangle vertices are collinear (area / longest side^2 = {flat})"
                    )));
                }
                Ok(())
            }
            Light::Sphere { center, radius } => {
                check_finite("sphere centre", center)?;
                check_size("sphere radius", radius)
            }
            Light::Distant {
                direction,
                angular_diameter,
                ..
            } => {
                check_finite("distant direction", direction)?;
                check_size("distant direction length", direction.length())?;
                check_size("distant angular diameter", angular_diameter)?;
                if angular_diameter >= std::f32::consts::PI {
                    return Err(ShadowError::InvalidLight(format!(
                        "distant angular diameter must be below pi, got {angular_diameter}"
                    )));
                }
                Ok(())
            }
        }
    }

    /// The centre of the light: a position, or the direction towards a distant light.
    pub fn center(&self) -> LightPoint {
        match *self {
            Light::Point { position } => LightPoint::Position(position),
            Light::Linear { a, b } => LightPoint::Position((a + b) * 0.5),
            Light::Triangle { a, b, c } => LightPoint::Position((a + b + c) / 3.0),
            Light::Rect { center, .. }
            | Light::Disk { center, .. }
            | Light::Sphere { center, .. } => LightPoint::Position(center),
            Light::Distant { direction, .. } => LightPoint::Direction(direction.normalize()),
        }
    }

    /// The light's size as one number, for filters that need one (PCSS):
    /// the diameter of the disk of equal area (rect, triangle), the length (segment), the diameter
    /// (disk, sphere),
    /// `2 tan(angular_diameter / 2)` for a distant light (a width per unit distance), 0 for a point.
    pub fn size(&self) -> f32 {
        match *self {
            Light::Point { .. } => 0.0,
            Light::Linear { a, b } => (b - a).length(),
            Light::Rect { u_half, v_half, .. } => {
                let area = 4.0 * u_half.length() * v_half.length();
                2.0 * (area / std::f32::consts::PI).sqrt()
            }
            Light::Triangle { a, b, c } => {
                let area = 0.5 * (b - a).cross(c - a).length();
                2.0 * (area / std::f32::consts::PI).sqrt()
            }
            Light::Disk { radius, .. } | Light::Sphere { radius, .. } => 2.0 * radius,
            Light::Distant {
                angular_diameter, ..
            } => 2.0 * (0.5 * angular_diameter).tan(),
        }
    }

    /// The direction a shadow-map frustum for this light looks along, given the scene's centre:
    /// the emission normal for rect, disk and triangle lights, the reverse light direction for distant lights,
    /// and from the light's centre to the scene otherwise.
    pub fn axis(&self, scene_center: Vec3) -> Vec3 {
        let towards_scene = |p: Vec3| {
            let d = scene_center - p;
            if d.length_squared() > 0.0 {
                d.normalize()
            } else {
                Vec3::NEG_Y
            }
        };
        match (self.front(), self.center()) {
            (Some((_, normal)), _) => normal.normalize(),
            (None, LightPoint::Direction(d)) => -d,
            (None, LightPoint::Position(p)) => towards_scene(p),
        }
    }

    /// The same light moved by `offset` (a distant light has no position and is returned as is).
    pub fn translated(&self, offset: Vec3) -> Light {
        let mut l = *self;
        match &mut l {
            Light::Point { position: p }
            | Light::Rect { center: p, .. }
            | Light::Disk { center: p, .. }
            | Light::Sphere { center: p, .. } => *p += offset,
            Light::Linear { a, b } => {
                *a += offset;
                *b += offset;
            }
            Light::Triangle { a, b, c } => {
                *a += offset;
                *b += offset;
                *c += offset;
            }
            Light::Distant { .. } => {}
        }
        l
    }

    /// The emitting plane of a one-sided light, as a point on it and its front normal (not
    /// normalised): `u x v` for a rect, `normal` for a disk, `(b - a) x (c - a)` for a
    /// triangle; `None` for the kinds that emit all around.
    pub fn front(&self) -> Option<(Vec3, Vec3)> {
        match *self {
            Light::Rect {
                center,
                u_half,
                v_half,
            } => Some((center, u_half.cross(v_half))),
            Light::Disk { center, normal, .. } => Some((center, normal)),
            Light::Triangle { a, b, c } => Some((a, (b - a).cross(c - a))),
            _ => None,
        }
    }

    /// Whether the light emits towards `p` at all: a one-sided light ([`Light::front`]) only
    /// towards its front; every other kind all around.
    pub fn emits_towards(&self, p: Vec3) -> bool {
        self.front().is_none_or(|(q, n)| (p - q).dot(n) > 0.0)
    }

    /// Whether the light point `q` *reaches* the receiver `p` with normal `n` (the library's
    /// visibility definition): `q` lies strictly above `p`'s tangent plane (`n . (q - p) > 0`, or
    /// `n . d > 0` for a direction) and `p` is on the light's emitting side. Points that do not
    /// reach are the unshadowed lighting term's business (horizon clipping), not the shadow's.
    pub fn reaches(&self, q: LightPoint, p: Vec3, n: Vec3) -> bool {
        self.emits_towards(p)
            && match q {
                LightPoint::Position(x) => n.dot(x - p) > 0.0,
                LightPoint::Direction(d) => n.dot(d) > 0.0,
            }
    }

    /// Whether any point of the light reaches `p` with normal `n` ([`Light::reaches`]); a
    /// receiver with none is *unlit*: it has no `V` and takes no part in any error.
    pub fn reaches_any(&self, p: Vec3, n: Vec3) -> bool {
        if !self.emits_towards(p) {
            return false;
        }
        // Largest height above the tangent plane over a disc of centre `c`, unit axis `w`, radius `r`.
        let disc = |c: Vec3, w: Vec3, r: f32| {
            n.dot(c - p) + r * (n.length_squared() - n.dot(w).powi(2)).max(0.0).sqrt()
        };
        match *self {
            Light::Point { position } => n.dot(position - p) > 0.0,
            Light::Linear { a, b } => n.dot(a - p).max(n.dot(b - p)) > 0.0,
            Light::Triangle { a, b, c } => n.dot(a - p).max(n.dot(b - p)).max(n.dot(c - p)) > 0.0,
            Light::Rect {
                center,
                u_half,
                v_half,
            } => {
                let h = n.dot(center - p);
                h + n.dot(u_half).abs() + n.dot(v_half).abs() > 0.0
            }
            Light::Disk {
                center,
                normal,
                radius,
            } => disc(center, normal.normalize(), radius) > 0.0,
            Light::Sphere { center, radius } => match silhouette(center, radius, p) {
                Some((disc_center, w, disc_radius)) => disc(disc_center, w, disc_radius) > 0.0,
                None => n.dot(center - p) > 0.0,
            },
            Light::Distant {
                direction,
                angular_diameter,
                ..
            } => {
                let a = direction.normalize();
                let half = 0.5 * angular_diameter;
                disc(p + a * half.cos(), a, half.sin()) > 0.0
            }
        }
    }

    /// A convex outline that contains every point of the light seen from `p`: the light's own
    /// vertices (point, segment, rect, triangle), a regular octagon circumscribing the disk or the sphere's
    /// silhouette disc, or for a distant light the octagon of directions circumscribing its cone.
    /// Used to prove a receiver fully lit: if nothing crosses the hull of `p` and the outline,
    /// nothing blocks any light point.
    pub fn outline(&self, p: Vec3) -> Vec<LightPoint> {
        let octagon = |c: Vec3, w: Vec3, r: f32| -> Vec<Vec3> {
            let (t, b) = orthonormal_basis(w);
            let rr = r / (std::f32::consts::PI / 8.0).cos();
            (0..8)
                .map(|i| {
                    let phi = std::f32::consts::TAU * i as f32 / 8.0;
                    c + (t * phi.cos() + b * phi.sin()) * rr
                })
                .collect()
        };
        let pos = |v: Vec<Vec3>| v.into_iter().map(LightPoint::Position).collect();
        match *self {
            Light::Point { position } => vec![LightPoint::Position(position)],
            Light::Linear { a, b } => pos(vec![a, b]),
            Light::Triangle { a, b, c } => pos(vec![a, b, c]),
            Light::Rect {
                center,
                u_half,
                v_half,
            } => pos(vec![
                center - u_half - v_half,
                center + u_half - v_half,
                center + u_half + v_half,
                center - u_half + v_half,
            ]),
            Light::Disk {
                center,
                normal,
                radius,
            } => pos(octagon(center, normal.normalize(), radius)),
            Light::Sphere { center, radius } => match silhouette(center, radius, p) {
                Some((disc_center, w, disc_radius)) => pos(octagon(disc_center, w, disc_radius)),
                None => vec![LightPoint::Position(center)],
            },
            Light::Distant {
                direction,
                angular_diameter,
                ..
            } => {
                let a = direction.normalize();
                let tan = (0.5 * angular_diameter).tan();
                octagon(a, a, tan)
                    .into_iter()
                    .map(|d| LightPoint::Direction(d.normalize()))
                    .collect()
            }
        }
    }

    /// Dimension of the light's sample domain: 0 (point), 1 (segment) or 2.
    pub fn sample_dimension(&self) -> u32 {
        match self {
            Light::Point { .. } => 0,
            Light::Linear { .. } => 1,
            _ => 2,
        }
    }

    /// Maps `u` in the unit square to a point of the light seen from `receiver`, with its weight
    /// under the emission profile. Uniform in the measure of the visibility definition, so
    /// an average of `weight * visible` over stratified `u` divided by the average weight is `V`.
    ///
    /// For a sphere the sample lies on the silhouette disc seen from `receiver`; a receiver inside
    /// the sphere gets its centre. For a segment only `u.x` is used.
    pub fn sample(&self, u: Vec2, receiver: Vec3) -> (LightPoint, f32) {
        match *self {
            Light::Point { position } => (LightPoint::Position(position), 1.0),
            Light::Linear { a, b } => (LightPoint::Position(a + (b - a) * u.x), 1.0),
            Light::Triangle { a, b, c } => {
                // Uniform in area: the square folded onto the triangle by `sqrt` (Shirley).
                let r = u.x.sqrt();
                (
                    LightPoint::Position(a * (1.0 - r) + b * (r * (1.0 - u.y)) + c * (r * u.y)),
                    1.0,
                )
            }
            Light::Rect {
                center,
                u_half,
                v_half,
            } => {
                let s = 2.0 * u - Vec2::ONE;
                (
                    LightPoint::Position(center + s.x * u_half + s.y * v_half),
                    1.0,
                )
            }
            Light::Disk {
                center,
                normal,
                radius,
            } => {
                let (t, b) = orthonormal_basis(normal.normalize());
                let d = concentric_disk(u) * radius;
                (LightPoint::Position(center + d.x * t + d.y * b), 1.0)
            }
            Light::Sphere { center, radius } => {
                let Some((disc_center, w, disc_radius)) = silhouette(center, radius, receiver)
                else {
                    return (LightPoint::Position(center), 1.0);
                };
                let (t, b) = orthonormal_basis(w);
                let d = concentric_disk(u) * disc_radius;
                (LightPoint::Position(disc_center + d.x * t + d.y * b), 1.0)
            }
            Light::Distant {
                direction,
                angular_diameter,
                profile,
            } => {
                let axis = direction.normalize();
                let half = 0.5 * angular_diameter;
                // Uniform in solid angle: cos(theta) uniform in [cos(half), 1], written in
                // `1 - cos` (`2 sin^2(half / 2)`) so that f32 keeps small cones exact (from
                // `cos` directly, a 0.06 degree cone sampled 6% outside itself).
                let one_minus = u.x * 2.0 * (0.5 * half).sin().powi(2);
                let cos_theta = 1.0 - one_minus;
                let sin_theta = (one_minus * (2.0 - one_minus)).max(0.0).sqrt();
                let phi = std::f32::consts::TAU * u.y;
                let (t, b) = orthonormal_basis(axis);
                let dir =
                    (axis * cos_theta + (t * phi.cos() + b * phi.sin()) * sin_theta).normalize();
                let weight = match profile {
                    DistantProfile::UniformDisk => 1.0,
                    DistantProfile::LimbDarkenedSun => {
                        let r = (sin_theta / half.sin()).min(1.0);
                        let mu = (1.0 - r * r).max(0.0).sqrt();
                        1.0 - SUN_LIMB_DARKENING_U * (1.0 - mu)
                    }
                };
                (LightPoint::Direction(dir), weight)
            }
        }
    }

    /// [`sample`](Self::sample) for a sample that stands for many receivers at once (one map of
    /// a set that accumulates point lights, [`crate::light_space::sample_views`]), placed for
    /// the receivers around `toward`, with a third coordinate `s` in `[0, 1)`.
    ///
    /// Every light but a sphere gives [`sample`](Self::sample)'s point and ignores `s`. A sphere
    /// shows each receiver its whole silhouette disc, facing that receiver, so points on the
    /// disc facing `toward` show a receiver seen at an angle from it that disc foreshortened by
    /// the angle's cosine: a penumbra too sharp across it (a room lamp's, 35 degrees and more
    /// off a cube face's axis, read +14.3/255 too sharp with 16 samples, +3.1 near the axis; in
    /// the ball +3.5 and +3.5). Here a sphere's sample lies inside the ball instead: the disc
    /// point `d = concentric_disk(u)` (within the unit disc) lifted along the axis to `toward`
    /// by `sqrt(1 - |d|²) sin(pi (s - 1/2))`, all times the radius, about the centre. Over
    /// uniform `u` and `s` that is the ball with density proportional to `1 / sqrt(1 - r²)`,
    /// whose projection along any direction is the uniform disc (its chord integral, an Abel
    /// transform, is constant), so a receiver's rays through the samples cross its own
    /// silhouette disc uniformly: exactly from afar, and from a distance `D` within about
    /// `3 (R / D)²` (a perspective view weighs the rim a little less). `s = 1/2` keeps the point
    /// on the centre's plane. A receiver inside the sphere gets the centre.
    pub fn map_sample(&self, u: Vec2, s: f32, toward: Vec3) -> (LightPoint, f32) {
        match *self {
            Light::Sphere { center, radius } => {
                let Some((_, w, _)) = silhouette(center, radius, toward) else {
                    return (LightPoint::Position(center), 1.0);
                };
                let (t, b) = orthonormal_basis(w);
                let d = concentric_disk(u);
                let lift = (1.0 - d.length_squared()).max(0.0).sqrt()
                    * (std::f32::consts::PI * (s - 0.5)).sin();
                (
                    LightPoint::Position(center + radius * (d.x * t + d.y * b - lift * w)),
                    1.0,
                )
            }
            _ => self.sample(u, toward),
        }
    }

    /// `n` deterministic, stratified samples of the light seen from `receiver` (the centres of a
    /// grid's cells for 2D lights, evenly spaced for a segment), for techniques that accumulate point lights.
    pub fn stratified_samples(&self, n: u32, receiver: Vec3) -> Vec<(LightPoint, f32)> {
        let (cells, _) = self.stratified_grid(n);
        cells
            .into_iter()
            .map(|u| self.sample(u, receiver))
            .collect()
    }

    /// The cells of [`stratified_samples`](Self::stratified_samples)' grid: their centres in
    /// the unit square of [`sample`](Self::sample) (in the samples' order) and the size every
    /// cell has there (zero for a point, `(1/n, 0)` for a segment).
    pub fn stratified_grid(&self, n: u32) -> (Vec<Vec2>, Vec2) {
        let n = n.max(1);
        match self.sample_dimension() {
            0 => (vec![Vec2::ZERO], Vec2::ZERO),
            1 => (
                (0..n)
                    .map(|i| Vec2::new((i as f32 + 0.5) / n as f32, 0.5))
                    .collect(),
                Vec2::new(1.0 / n as f32, 0.0),
            ),
            _ => {
                let cols = (n as f32).sqrt().ceil() as u32;
                let rows = n.div_ceil(cols);
                let cells = (0..n)
                    .map(|i| {
                        let (c, r) = (i % cols, i / cols);
                        Vec2::new(
                            (c as f32 + 0.5) / cols as f32,
                            (r as f32 + 0.5) / rows as f32,
                        )
                    })
                    .collect();
                (cells, Vec2::new(1.0 / cols as f32, 1.0 / rows as f32))
            }
        }
    }
}
