//! What the viewer shows, as plain data the window edits and tests check: the orbit camera, the
//! edited light, the techniques chosen and the rules that keep them valid.

use crate::renderer::ViewMode;
use glam::Vec3;
use soft_shadow_core::{
    Camera, DistantProfile, Light, LightKind, LightPoint, Registry, Result, ShadowError,
};

/// A camera orbiting a target: yaw and pitch around it at a distance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OrbitCamera {
    /// The point looked at.
    pub target: Vec3,
    /// Angle around the vertical, radians.
    pub yaw: f32,
    /// Angle above the horizontal, radians, within ±[`OrbitCamera::MAX_PITCH`].
    pub pitch: f32,
    /// Distance from the target.
    pub distance: f32,
    /// Vertical field of view, radians.
    pub fov_y: f32,
}

impl OrbitCamera {
    /// Largest pitch: just short of straight down or up.
    pub const MAX_PITCH: f32 = 1.5;
    /// Nearest and farthest distance, relative to the distance the camera started at.
    pub const ZOOM_RANGE: (f32, f32) = (0.05, 20.0);

    /// The orbit that looks like `camera`.
    pub fn from_camera(camera: &Camera) -> Self {
        let d = camera.eye - camera.target;
        let distance = d.length().max(1e-3);
        Self {
            target: camera.target,
            yaw: d.x.atan2(d.z),
            pitch: (d.y / distance).clamp(-1.0, 1.0).asin(),
            distance,
            fov_y: camera.fov_y,
        }
    }

    /// The camera: near and far planes scaled with the distance.
    pub fn camera(&self) -> Camera {
        let dir = Vec3::new(
            self.pitch.cos() * self.yaw.sin(),
            self.pitch.sin(),
            self.pitch.cos() * self.yaw.cos(),
        );
        Camera {
            eye: self.target + dir * self.distance,
            target: self.target,
            fov_y: self.fov_y,
            near: self.distance * 0.01,
            far: self.distance * 20.0,
        }
    }

    /// Turns by a drag of `dx`, `dy` pixels (0.01 rad per pixel; pitch clamped).
    pub fn orbit(&mut self, dx: f32, dy: f32) {
        self.yaw -= dx * 0.01;
        self.pitch = (self.pitch + dy * 0.01).clamp(-Self::MAX_PITCH, Self::MAX_PITCH);
    }

    /// Moves the target with a drag of `dx`, `dy` pixels in a view `height` pixels high, so
    /// that the point under the cursor follows it.
    pub fn pan(&mut self, dx: f32, dy: f32, height: f32) {
        let cam = self.camera();
        let forward = (cam.target - cam.eye).normalize();
        let right = forward.cross(Vec3::Y).normalize_or(Vec3::X);
        let up = right.cross(forward);
        let per_pixel = 2.0 * self.distance * (self.fov_y * 0.5).tan() / height.max(1.0);
        self.target += (-dx * right + dy * up) * per_pixel;
    }

    /// Walks `forward` and `right` (world units) in the horizontal plane, as a person looking
    /// along the camera's heading does: eye and target move together, the view turns not.
    pub fn walk(&mut self, forward: f32, right: f32) {
        let ahead = Vec3::new(-self.yaw.sin(), 0.0, -self.yaw.cos());
        let side = ahead.cross(Vec3::Y);
        self.target += ahead * forward + side * right;
    }

    /// Zooms by `steps` (positive: nearer), 10% per step, within [`OrbitCamera::ZOOM_RANGE`]
    /// of `home` distance.
    pub fn zoom(&mut self, steps: f32, home: f32) {
        let (lo, hi) = Self::ZOOM_RANGE;
        self.distance = (self.distance * 0.9f32.powf(steps)).clamp(home * lo, home * hi);
    }
}

/// The light as the panel edits it: a kind, where it is, how large, aimed at a target.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightEdit {
    /// Its kind.
    pub kind: LightKind,
    /// Its centre (for a distant light: the direction towards it is `center - target`).
    pub center: Vec3,
    /// The point it faces.
    pub target: Vec3,
    /// Its size: side of a square, diameter of a disk or sphere, length of a segment, side of
    /// a triangle of the same area as that square, and for a distant light the diameter it
    /// would have at this distance.
    pub size: f32,
}

/// Smallest and largest light size relative to the distance to its target.
pub const SIZE_RANGE: (f32, f32) = (0.005, 1.0);

impl LightEdit {
    /// The edit that gives `light` (its kind, centre and size), aimed at `target`.
    pub fn from_light(light: &Light, target: Vec3) -> Self {
        let (center, size) = match *light {
            Light::Point { position } => (position, 0.2),
            Light::Linear { a, b } => ((a + b) * 0.5, (b - a).length()),
            Light::Rect {
                center,
                u_half,
                v_half,
            } => (center, 2.0 * (u_half.length() * v_half.length()).sqrt()),
            Light::Disk { center, radius, .. } | Light::Sphere { center, radius } => {
                (center, 2.0 * radius)
            }
            Light::Triangle { a, b, c } => (
                (a + b + c) / 3.0,
                (0.5 * (b - a).cross(c - a).length()).sqrt(),
            ),
            Light::Distant {
                direction,
                angular_diameter,
                ..
            } => {
                let d = 4.0;
                (
                    target + direction.normalize() * d,
                    2.0 * d * (angular_diameter * 0.5).tan(),
                )
            }
            // A kind added later: its centre and size.
            other => match other.center() {
                LightPoint::Position(p) => (p, other.size()),
                LightPoint::Direction(d) => (target + d * 4.0, 4.0 * other.size()),
            },
        };
        Self {
            kind: light.kind(),
            center,
            target,
            size,
        }
    }

    /// Distance from the light to its target.
    pub fn distance(&self) -> f32 {
        (self.center - self.target).length()
    }

    /// Moves the light along the line to its target to `distance` (at least 0.05).
    pub fn set_distance(&mut self, distance: f32) {
        let d = (self.center - self.target).normalize_or(Vec3::Y);
        self.center = self.target + d * distance.max(0.05);
    }

    /// Moves the light by `dx`, `dz` in the horizontal plane.
    pub fn drag(&mut self, dx: f32, dz: f32) {
        self.center += Vec3::new(dx, 0.0, dz);
    }

    /// The light: oriented to face its target, a size within [`SIZE_RANGE`] of its distance
    /// (an invalid one is the light's own error).
    pub fn light(&self) -> Result<Light> {
        let to_target = self.target - self.center;
        let distance = to_target.length();
        if distance.is_nan() || distance <= 1e-4 || !self.center.is_finite() {
            return Err(ShadowError::InvalidLight(format!(
                "the light's centre {} is on its target",
                self.center
            )));
        }
        let size = self
            .size
            .clamp(SIZE_RANGE.0 * distance, SIZE_RANGE.1 * distance);
        let n = to_target / distance;
        // Sides of a rectangle or triangle facing the target, aligned with the world where
        // they can be.
        let u = n.cross(Vec3::Z).normalize_or(n.any_orthonormal_vector());
        let v = u.cross(n);
        let c = self.center;
        let light = match self.kind {
            LightKind::Point => Light::Point { position: c },
            LightKind::Linear => Light::Linear {
                a: c - u * size * 0.5,
                b: c + u * size * 0.5,
            },
            LightKind::Rect => Light::Rect {
                center: c,
                u_half: u * size * 0.5,
                v_half: -v * size * 0.5,
            },
            LightKind::Disk => Light::Disk {
                center: c,
                normal: n,
                radius: size * 0.5,
            },
            LightKind::Triangle => {
                // Equilateral, of the area of a square of side `size`.
                let side = size * (4.0 / 3f32.sqrt()).sqrt();
                let (x, y) = (u * side, v * side * 3f32.sqrt() / 2.0);
                Light::Triangle {
                    a: c - 0.5 * x - y / 3.0,
                    b: c - 0.5 * x - y / 3.0 + x,
                    c: c + 2.0 * y / 3.0,
                }
            }
            LightKind::Sphere => Light::Sphere {
                center: c,
                radius: size * 0.5,
            },
            LightKind::Distant => Light::Distant {
                direction: -n,
                angular_diameter: 2.0 * (0.5 * size / distance).atan(),
                profile: DistantProfile::UniformDisk,
            },
            other => {
                return Err(ShadowError::InvalidLight(format!(
                    "the viewer cannot place a {} light",
                    other.name()
                )));
            }
        };
        let light = fix_winding(light, n);
        light.validate()?;
        Ok(light)
    }

    /// The light after `seconds` of the animation: its centre turned around the vertical
    /// through the target at [`ANIMATION_RAD_PER_S`].
    pub fn animated(&self, seconds: f32) -> Self {
        let d = self.center - self.target;
        let a = seconds * ANIMATION_RAD_PER_S;
        let (s, c) = a.sin_cos();
        Self {
            center: self.target + Vec3::new(c * d.x + s * d.z, d.y, -s * d.x + c * d.z),
            ..*self
        }
    }
}

/// Angular speed of the light animation.
pub const ANIMATION_RAD_PER_S: f32 = 0.6;

/// A triangle emitting towards `n` (its winding flipped where it emitted away).
fn fix_winding(light: Light, n: Vec3) -> Light {
    match light {
        Light::Triangle { a, b, c } if (b - a).cross(c - a).dot(n) < 0.0 => {
            Light::Triangle { a, b: c, c: b }
        }
        Light::Rect {
            center,
            u_half,
            v_half,
        } if u_half.cross(v_half).dot(n) < 0.0 => Light::Rect {
            center,
            u_half,
            v_half: -v_half,
        },
        other => other,
    }
}

/// One technique as chosen in the panel: which one, which variant, at which map side.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Choice {
    /// Technique name.
    pub technique: &'static str,
    /// Variant label.
    pub variant: String,
    /// Map side.
    pub resolution: u32,
}

impl Choice {
    /// `name`'s default variant at `resolution`.
    pub fn new(registry: &Registry, name: &str, resolution: u32) -> Result<Self> {
        let e = registry.family(name)?;
        Ok(Self {
            technique: e.name(),
            variant: e.default_variant().variant(),
            resolution,
        })
    }
}

/// Everything the viewer shows.
#[derive(Clone, Debug, PartialEq)]
pub struct ViewState {
    /// The camera.
    pub camera: OrbitCamera,
    /// The camera's distance when the scene opened (zoom is relative to it).
    pub home_distance: f32,
    /// The light as edited (the animation turns it).
    pub light: LightEdit,
    /// The scene's own light, shown as given until the light is edited or animated.
    pub scene_light: Option<Light>,
    /// The technique shown.
    pub shadow: Choice,
    /// A second technique, right of the split.
    pub compare: Option<Choice>,
    /// Where the split is, as a fraction of the view's width.
    pub split: f32,
    /// What the pixels show.
    pub mode: ViewMode,
    /// Whether the light turns around the scene.
    pub animate: bool,
    /// Seconds the animation has run.
    pub time: f32,
}

impl ViewState {
    /// The state for a scene seen by `camera` under `light`, showing `shadow`.
    pub fn new(camera: &Camera, light: &Light, shadow: Choice) -> Self {
        let orbit = OrbitCamera::from_camera(camera);
        Self {
            home_distance: orbit.distance,
            camera: orbit,
            light: LightEdit::from_light(light, camera.target),
            scene_light: Some(*light),
            shadow,
            compare: None,
            split: 0.5,
            mode: ViewMode::Shaded,
            animate: false,
            time: 0.0,
        }
    }

    /// The light of this frame: the scene's own until edited, else the edit (the animation
    /// applied).
    pub fn frame_light(&self) -> Result<Light> {
        match (self.animate, self.scene_light) {
            (true, _) => self.light.animated(self.time).light(),
            (false, Some(light)) => Ok(light),
            (false, None) => self.light.light(),
        }
    }

    /// Changes the light's kind. A chosen technique that does not model it is replaced by the
    /// first that does, and each replacement is said in the returned lines.
    pub fn set_light_kind(&mut self, kind: LightKind, registry: &Registry) -> Vec<String> {
        if kind != self.light.kind {
            self.light.kind = kind;
            self.scene_light = None;
        }
        let mut said = Vec::new();
        let fallback = registry
            .families()
            .iter()
            .find(|e| e.availability(kind).is_ok())
            .map(|e| e.name());
        for choice in std::iter::once(&mut self.shadow).chain(self.compare.as_mut()) {
            let Ok(e) = registry.family(choice.technique) else {
                continue;
            };
            if let (Err(why), Some(to)) = (e.availability(kind), fallback) {
                said.push(format!("{why}: showing {to} instead"));
                if let Ok(c) = Choice::new(registry, to, choice.resolution) {
                    *choice = c;
                }
            }
        }
        said
    }

    /// Sets the technique shown (`second`: the compared one) to `name`'s default variant,
    /// keeping the map side; a technique that does not model the light is refused with why.
    pub fn choose(
        &mut self,
        second: bool,
        name: &str,
        registry: &Registry,
    ) -> std::result::Result<(), String> {
        let e = registry.family(name).map_err(|e| e.to_string())?;
        e.availability(self.light.kind)?;
        let slot = if second {
            self.compare.get_or_insert_with(|| self.shadow.clone())
        } else {
            &mut self.shadow
        };
        *slot = Choice {
            technique: e.name(),
            variant: e.default_variant().variant(),
            resolution: slot.resolution,
        };
        Ok(())
    }

    /// The split column in a view `width` pixels wide (none without a compared technique).
    pub fn split_column(&self, width: u32) -> Option<u32> {
        self.compare
            .as_ref()
            .map(|_| ((self.split.clamp(0.0, 1.0) * width as f32).round() as u32).min(width))
    }
}
