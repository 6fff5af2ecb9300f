//! Opening a scene: a catalogue scene by name (one of many lamps among them,
//! [`lamps::LAMP_SCENES`]), a scene file (`.toml`, as the report reads them), or a glTF model
//! (`.glb`, `.gltf`) stood on a ground square.

use crate::renderer::{model_on_ground, moving_light};
use soft_shadow_core::{Aabb, Camera, Light, Result, SceneGeometry, ShadowError};
use soft_shadow_reference::scenes::{SceneSpec, catalogue, lamps, scene_file};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Where a scene comes from.
#[derive(Clone, Debug, PartialEq)]
pub enum SceneSource {
    /// A catalogue scene ([`catalogue::SCENE_NAMES`], [`lamps::LAMP_SCENES`]).
    Catalogue(String),
    /// A scene file or a glTF model.
    File(PathBuf),
}

/// An opened scene: its triangles, camera and light.
#[derive(Clone)]
pub struct LoadedScene {
    /// A name for the panel.
    pub name: String,
    /// Casters and receivers, world space.
    pub geometry: Arc<SceneGeometry>,
    /// The scene's camera.
    pub camera: Camera,
    /// The scene's light (a scene of lamps: its first lamp's).
    pub light: Light,
    /// The name of a scene of lamps ([`lamps::LAMP_SCENES`]), which the frame pipeline shades
    /// ([`crate::lamps::LampsView`]); `None` for a scene of one light.
    pub lamps: Option<String>,
}

fn from_spec(spec: &SceneSpec) -> LoadedScene {
    let triangles = |keep: fn(&soft_shadow_reference::scenes::MeshInstance) -> bool| -> Vec<_> {
        spec.meshes
            .iter()
            .filter(|m| keep(m))
            .flat_map(|m| m.mesh.world_triangles(m.transform).collect::<Vec<_>>())
            .collect()
    };
    let casters = triangles(|m| m.caster);
    let receivers = triangles(|m| m.receiver);
    let mut all = casters.clone();
    all.extend(receivers.iter().copied());
    LoadedScene {
        name: spec.name.clone(),
        geometry: Arc::new(SceneGeometry {
            bounds: Aabb::of_triangles(&all),
            casters,
            receivers,
        }),
        camera: spec.camera,
        light: spec.light,
        lamps: None,
    }
}

/// A scene of lamps: its geometry, camera and first lamp.
fn from_lamps(name: &str) -> Result<LoadedScene> {
    let mut lit = lamps::build(name, 16, 9, crate::lamps::BUDGET_MS)?;
    let g = lit.scene.geometry();
    let mut all = g.casters.clone();
    all.extend(g.receivers.iter().copied());
    Ok(LoadedScene {
        name: name.to_string(),
        geometry: Arc::new(SceneGeometry {
            bounds: Aabb::of_triangles(&all),
            ..g
        }),
        camera: lit.camera,
        light: lit.lights.first().copied().ok_or_else(|| {
            ShadowError::InvalidScene(format!("{name}: a scene of lamps without a lamp"))
        })?,
        lamps: Some(name.to_string()),
    })
}

/// Opens `source`. A name outside the catalogue, a file that cannot be read or parsed, a file
/// of another type, or a scene without casters or receivers is a [`ShadowError`] that names
/// the file and the problem.
pub fn load(source: &SceneSource) -> Result<LoadedScene> {
    let scene = match source {
        SceneSource::Catalogue(name) if lamps::LAMP_SCENES.iter().any(|(n, _)| n == name) => {
            from_lamps(name)?
        }
        SceneSource::Catalogue(name) => from_spec(&catalogue::build(name)?),
        SceneSource::File(path) => load_file(path)?,
    };
    let g = &scene.geometry;
    if g.casters.is_empty() || g.receivers.is_empty() {
        return Err(ShadowError::InvalidScene(format!(
            "{}: {} casters and {} receivers (it needs both)",
            scene.name,
            g.casters.len(),
            g.receivers.len()
        )));
    }
    Ok(scene)
}

fn load_file(path: &Path) -> Result<LoadedScene> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    match ext.as_deref() {
        Some("toml") => Ok(from_spec(&scene_file::load(path)?)),
        Some("glb" | "gltf") => {
            let model = shadow_frame::gltf::import_gltf_file(path)?;
            let (geometry, camera) = model_on_ground(&model);
            Ok(LoadedScene {
                name: path
                    .file_name()
                    .map(|n| n.to_string_lossy().into_owned())
                    .unwrap_or_default(),
                geometry: Arc::new(geometry),
                camera,
                light: moving_light(1, 8),
                lamps: None,
            })
        }
        _ => Err(ShadowError::InvalidScene(format!(
            "{}: not a scene file (.toml) or a glTF model (.glb, .gltf)",
            path.display()
        ))),
    }
}
