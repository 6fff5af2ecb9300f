//! The scene catalogue: built-in, deterministic scenes, plus user scenes from TOML.

pub mod catalogue;
pub mod lamps;
pub mod relight;
pub mod scene_file;
pub mod shapes;

use glam::{Mat4, Vec3};
use shadow_frame::{Scene, Shadows};
use soft_shadow_core::pool::Pool;
use soft_shadow_core::raster::gbuffer;
use soft_shadow_core::{
    Aabb, Camera, Light, LightKind, Result, SceneGeometry, ShadowError, TriangleMesh,
};
use std::sync::Arc;

/// Side of the camera G-buffer whose receivers decide what a scene's light casts onto
/// ([`SceneSpec::casting_bounds`]).
pub const CASTING_VIEW: u32 = 64;

/// One mesh instance of a scene description.
#[derive(Clone, Debug)]
pub struct MeshInstance {
    /// The mesh.
    pub mesh: Arc<TriangleMesh>,
    /// Object to world.
    pub transform: Mat4,
    /// Casts shadows.
    pub caster: bool,
    /// Receives shadows (appears in the G-buffer).
    pub receiver: bool,
}

/// A scene description: what the report renders, built-in or from a user's file.
#[derive(Clone, Debug)]
pub struct SceneSpec {
    /// Name used with `--scenes`.
    pub name: String,
    /// One line saying what the scene tests.
    pub description: String,
    /// Whether it belongs to the stability suite's hard cases.
    pub hard_case: bool,
    /// Meshes.
    pub meshes: Vec<MeshInstance>,
    /// The light.
    pub light: Light,
    /// The camera.
    pub camera: Camera,
}

impl SceneSpec {
    /// Builds the ECS scene (validating meshes and the light).
    pub fn to_scene(&self) -> Result<Scene> {
        let mut scene = Scene::new();
        self.add_meshes(&mut scene)?;
        scene.add_light(self.light)?;
        scene.set_camera(self.camera);
        Ok(scene)
    }

    /// Adds its meshes, casting and receiving as they do here, to `scene` (validating them):
    /// the scene without its light and camera, for lights of your own.
    pub fn add_meshes(&self, scene: &mut Scene) -> Result<()> {
        for m in &self.meshes {
            scene.add_mesh(
                m.mesh.clone(),
                m.transform,
                Shadows {
                    casts: m.caster,
                    receives: m.receiver,
                },
            )?;
        }
        Ok(())
    }

    /// The region its light's maps cover for its camera, which a recast light
    /// ([`SceneSpec::relit`]) faces: the bounds of [`shadow_frame::Scene::casting_onto`] for
    /// the receivers a [`CASTING_VIEW`]² G-buffer of the camera sees (the casters that shadow
    /// what is in view, and the receivers they reach).
    pub fn casting_bounds(&self) -> Result<Aabb> {
        let (_, seen, _) = scene_receivers(self, CASTING_VIEW)?;
        Ok(self.to_scene()?.casting_onto(&self.light, &seen).bounds)
    }

    /// This scene (whose geometry spans `bounds`) under the nearest light `models` accepts
    /// ([`relight::relight`]), named `name@kind`; `None` when the scene's own light is modelled
    /// or no recast one is.
    pub fn relit(&self, bounds: &Aabb, models: impl Fn(LightKind) -> bool) -> Option<SceneSpec> {
        if models(self.light.kind()) {
            return None;
        }
        relight::relight(&self.light, bounds, models).map(|light| SceneSpec {
            name: format!("{}@{}", self.name, light.kind().name()),
            description: format!(
                "{} (relit: the {} light recast as a {} light)",
                self.description,
                self.light.kind().name(),
                light.kind().name()
            ),
            light,
            ..self.clone()
        })
    }
}

/// The receivers of a scene without its reference (cheap): flattened geometry and the positions
/// and normals of the covered pixels of the camera's `size²` CPU G-buffer, row-major, as
/// the harness's `PreparedScene` takes them.
pub fn scene_receivers(
    spec: &SceneSpec,
    size: u32,
) -> Result<(SceneGeometry, Vec<Vec3>, Vec<Vec3>)> {
    let mut scene = spec.to_scene()?;
    let geometry = scene.geometry();
    geometry.validate()?;
    let camera = scene
        .camera()
        .ok_or_else(|| ShadowError::InvalidScene("no camera".into()))?;
    let gb = gbuffer(
        &Arc::new(Pool::new(0)),
        &camera.view(size, size),
        camera.eye,
        size,
        size,
        &geometry.receivers,
    );
    let (positions, normals) = gb
        .data()
        .iter()
        .filter(|t| t.covered && t.normal != Vec3::ZERO)
        .map(|t| (t.position, t.normal))
        .unzip();
    Ok((geometry, positions, normals))
}
