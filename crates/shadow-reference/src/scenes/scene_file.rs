//! User scenes: a small TOML file naming glTF/GLB meshes with transforms, one light and the camera.
//! Every field, unit and convention: `docs/scene-files.md`.
//!
//! ```toml
//! name = "my-scene"
//! [[mesh]]
//! path = "chair.glb"            # relative to the TOML file
//! translation = [0.0, 0.0, 0.0]
//! rotation_y_deg = 30.0
//! scale = 1.0
//! [[mesh]]
//! ground = 8.0                  # a built-in ground square of this side instead of a file
//!                               # (receiver only unless `caster = true`)
//! [light]
//! kind = "rect"                 # point | linear | rect | triangle | disk | sphere | distant
//! center = [0.0, 3.0, 0.0]
//! u_half = [0.4, 0.0, 0.0]
//! v_half = [0.0, 0.0, 0.4]
//! [camera]
//! eye = [0.0, 4.5, 3.5]
//! target = [0.0, 0.0, 0.0]
//! ```

use super::{MeshInstance, SceneSpec};
use glam::{Mat4, Quat, Vec3};
use serde::Deserialize;
use shadow_frame::gltf::import_gltf_file;
use soft_shadow_core::{Camera, DistantProfile, Light, Result, ShadowError};
use std::path::Path;
use std::sync::Arc;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct FileScene {
    name: Option<String>,
    #[serde(default)]
    mesh: Vec<FileMesh>,
    light: FileLight,
    camera: FileCamera,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct FileMesh {
    path: Option<String>,
    ground: Option<f32>,
    #[serde(default)]
    translation: [f32; 3],
    #[serde(default)]
    rotation_y_deg: f32,
    scale: Option<f32>,
    caster: Option<bool>,
    receiver: Option<bool>,
}

#[derive(Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case", deny_unknown_fields)]
enum FileLight {
    Point {
        position: [f32; 3],
    },
    Linear {
        a: [f32; 3],
        b: [f32; 3],
    },
    Rect {
        center: [f32; 3],
        u_half: [f32; 3],
        v_half: [f32; 3],
    },
    Triangle {
        a: [f32; 3],
        b: [f32; 3],
        c: [f32; 3],
    },
    Disk {
        center: [f32; 3],
        normal: [f32; 3],
        radius: f32,
    },
    Sphere {
        center: [f32; 3],
        radius: f32,
    },
    Distant {
        direction: [f32; 3],
        angular_diameter: f32,
        profile: Option<String>,
    },
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct FileCamera {
    eye: [f32; 3],
    target: [f32; 3],
    fov_y_deg: Option<f32>,
    near: Option<f32>,
    far: Option<f32>,
}

fn bad(path: &Path, reason: impl Into<String>) -> ShadowError {
    ShadowError::InvalidScene(format!("{}: {}", path.display(), reason.into()))
}

/// Reads a user scene file.
pub fn load(path: &Path) -> Result<SceneSpec> {
    let text = std::fs::read_to_string(path).map_err(|source| ShadowError::Io {
        path: path.display().to_string(),
        source,
    })?;
    let file: FileScene = toml::from_str(&text).map_err(|e| bad(path, e.to_string()))?;
    let dir = path.parent().unwrap_or(Path::new("."));
    let mut meshes = Vec::new();
    for m in &file.mesh {
        let mesh = match (&m.path, m.ground) {
            (Some(p), None) => import_gltf_file(&dir.join(p))?,
            (None, Some(size)) if size > 0.0 && size.is_finite() => {
                super::shapes::ground(size, 0.0, 1)
            }
            _ => {
                return Err(bad(
                    path,
                    "each [[mesh]] needs exactly one of `path` or a positive `ground` size",
                ));
            }
        };
        let scale = m.scale.unwrap_or(1.0);
        if !(scale.is_finite() && scale > 0.0) {
            return Err(bad(
                path,
                format!("`scale` must be finite and > 0, got {scale} (0 collapses the mesh)"),
            ));
        }
        let transform = Mat4::from_scale_rotation_translation(
            Vec3::splat(scale),
            Quat::from_rotation_y(m.rotation_y_deg.to_radians()),
            Vec3::from(m.translation),
        );
        meshes.push(MeshInstance {
            mesh: Arc::new(mesh),
            transform,
            // A built-in ground only receives unless the file says otherwise (maps cover what casts).
            caster: m.caster.unwrap_or(m.ground.is_none()),
            receiver: m.receiver.unwrap_or(true),
        });
    }
    let v = Vec3::from;
    let light = match file.light {
        FileLight::Point { position } => Light::Point {
            position: v(position),
        },
        FileLight::Linear { a, b } => Light::Linear { a: v(a), b: v(b) },
        FileLight::Triangle { a, b, c } => Light::Triangle {
            a: v(a),
            b: v(b),
            c: v(c),
        },
        FileLight::Rect {
            center,
            u_half,
            v_half,
        } => Light::Rect {
            center: v(center),
            u_half: v(u_half),
            v_half: v(v_half),
        },
        FileLight::Disk {
            center,
            normal,
            radius,
        } => Light::Disk {
            center: v(center),
            normal: v(normal).normalize_or_zero(),
            radius,
        },
        FileLight::Sphere { center, radius } => Light::Sphere {
            center: v(center),
            radius,
        },
        FileLight::Distant {
            direction,
            angular_diameter,
            profile,
        } => Light::Distant {
            direction: v(direction).normalize_or_zero(),
            angular_diameter,
            profile: match profile.as_deref() {
                None | Some("uniform") => DistantProfile::UniformDisk,
                Some("sun") => DistantProfile::LimbDarkenedSun,
                Some(other) => {
                    return Err(bad(
                        path,
                        format!("unknown distant profile {other:?} (uniform | sun)"),
                    ));
                }
            },
        },
    };
    light.validate()?;
    let c = &file.camera;
    let camera = Camera {
        eye: v(c.eye),
        target: v(c.target),
        fov_y: c.fov_y_deg.unwrap_or(50.0).to_radians(),
        near: c.near.unwrap_or(0.05),
        far: c.far.unwrap_or(100.0),
    };
    if !(camera.near > 0.0 && camera.far > camera.near)
        || (camera.target - camera.eye).length() == 0.0
    {
        return Err(bad(path, "camera needs 0 < near < far and target != eye"));
    }
    let name = file.name.unwrap_or_else(|| {
        path.file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| "user".into())
    });
    Ok(SceneSpec {
        name,
        description: format!("user scene from {}", path.display()),
        hard_case: false,
        meshes,
        light,
        camera,
    })
}
