//! The scenes of many lamps that share one frame budget ([`street`]'s night street,
//! [`room`]'s room): the ECS scene, its lamps (each a [`shadow_frame::ShadowConfig::shared`]
//! choice), the camera whose G-buffer gives the frame's receivers, a walk for the camera and
//! one lamp that can swing. [`LAMP_SCENES`] names them for the harness's `frames` and the
//! viewer ([`build`]).

pub(crate) mod names;
pub mod room;
pub mod street;

pub use names::LAMP_SCENES;

use bevy_ecs::change_detection::DetectChangesMut;
use bevy_ecs::entity::Entity;
use glam::Vec3;
use shadow_frame::scene::LightSource;
use shadow_frame::{FrameBudget, FrameReceivers, Scene, ShadowConfig};
use soft_shadow_core::pool::Pool;
use soft_shadow_core::raster::{GBufferTexel, gbuffer};
use soft_shadow_core::{Camera, Light, Map2D, Result, ShadowError};
use std::sync::Arc;

/// Lamps of [`LAMP_SCENES`]' `night-street`.
pub const STREET_LAMPS: usize = 16;

/// The scene of [`LAMP_SCENES`] called `name` ([`street::street`] with [`STREET_LAMPS`] lamps,
/// or [`room::room`]), its receivers from a `width x height` G-buffer, under a frame budget of
/// `budget_ms`. Another name is [`ShadowError::InvalidScene`], naming the ones there are.
pub fn build(name: &str, width: u32, height: u32, budget_ms: f64) -> Result<Lamps> {
    match name {
        "night-street" => street::street(STREET_LAMPS, width, height, budget_ms),
        "room-lamps" => room::room(width, height, budget_ms),
        _ => Err(ShadowError::InvalidScene(format!(
            "{name:?} is not a scene of lamps ({})",
            LAMP_SCENES.map(|(n, _)| n).join(", ")
        ))),
    }
}

/// Sets `scene`'s camera, rasterizes its receivers' `width x height` G-buffer on the CPU and
/// inserts the covered texels as the frame's receivers ([`FrameReceivers`], with the camera's
/// view); returns the G-buffer and the indices of its covered texels.
pub fn look(
    scene: &mut Scene,
    camera: Camera,
    width: u32,
    height: u32,
) -> (Map2D<GBufferTexel>, Vec<usize>) {
    scene.set_camera(camera);
    let geo = scene.geometry();
    let view = camera.view(width, height);
    let pool = Arc::new(Pool::new(0));
    let gb = gbuffer(&pool, &view, camera.eye, width, height, &geo.receivers);
    let pixels: Vec<usize> = (0..gb.data().len())
        .filter(|&i| gb.data()[i].covered)
        .collect();
    scene.world.insert_resource(FrameReceivers {
        positions: pixels.iter().map(|&i| gb.data()[i].position).collect(),
        normals: pixels.iter().map(|&i| gb.data()[i].normal).collect(),
        camera: Some(view),
    });
    (gb, pixels)
}

/// The scene, its lamps and the camera's receivers.
pub struct Lamps {
    /// The ECS scene (frame receivers and the frame budget already inserted).
    pub scene: Scene,
    /// What the scene is, for titles (`"the night street"`, `"the room"`).
    pub title: String,
    /// The lamp entities.
    pub lamps: Vec<Entity>,
    /// The lamps' lights as built (the swinging one moves from its own).
    pub lights: Vec<Light>,
    /// The lamp [`Lamps::swing`] moves.
    pub swinging: usize,
    /// The camera.
    pub camera: Camera,
    /// The unit direction [`Lamps::walk`] moves the camera along.
    walk: Vec3,
    /// The G-buffer's width and height.
    size: (u32, u32),
}

impl Lamps {
    /// `scene` with its `lamps` (entities, and their `lights` as built) under a frame budget of
    /// `budget_ms`, seen by `camera` through a `width x height` G-buffer; the camera walks along
    /// `walk` (normalised; a zero `walk` stands still) and lamp `swinging` swings.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn new(
        mut scene: Scene,
        title: &str,
        lamps: Vec<Entity>,
        lights: Vec<Light>,
        swinging: usize,
        camera: Camera,
        walk: Vec3,
        (width, height): (u32, u32),
        budget_ms: f64,
    ) -> Self {
        scene.world.insert_resource(FrameBudget { ms: budget_ms });
        let mut lit = Self {
            scene,
            title: title.to_string(),
            lamps,
            lights,
            swinging,
            camera,
            walk: walk.normalize_or_zero(),
            size: (width, height),
        };
        lit.look(camera);
        lit
    }

    /// Puts the camera at `camera` and the receivers its `width x height` G-buffer sees in
    /// the frame's receivers ([`look`]).
    pub fn look(&mut self, camera: Camera) {
        self.camera = camera;
        look(&mut self.scene, camera, self.size.0, self.size.1);
    }

    /// The receivers' G-buffer size, width and height.
    pub fn size(&self) -> (u32, u32) {
        self.size
    }

    /// Makes the receivers' G-buffer `width x height` (as the view it stands for is shaped),
    /// the receivers seen again.
    pub fn resize(&mut self, width: u32, height: u32) {
        self.size = (width, height);
        self.look(self.camera);
    }

    /// Walks the camera `metres` along its walk (its G-buffer, and so the frame's receivers,
    /// made again).
    pub fn walk(&mut self, metres: f32) {
        let step = self.walk * metres;
        let c = self.camera;
        self.look(Camera {
            eye: c.eye + step,
            target: c.target + step,
            ..c
        });
    }

    /// Frame `f` of the swinging lamp's swing ([`Lamps::swinging`]): it moves along x on a
    /// 30 cm arc (the other lamps stay), so that lamp alone makes its maps again.
    pub fn swing(&mut self, f: u32) {
        let (Some(&e), Some(&light)) = (
            self.lamps.get(self.swinging),
            self.lights.get(self.swinging),
        ) else {
            return;
        };
        let offset = Vec3::X * 0.3 * (f as f32 * 0.7).sin();
        if let Some(mut l) = self.scene.world.get_mut::<LightSource>(e) {
            l.set_if_neq(LightSource(light.translated(offset)));
        }
    }
}

/// Adds `light` to `scene` as a lamp: a [`ShadowConfig::shared`] choice with influence radius
/// `range` and radiant intensity `intensity`.
pub(crate) fn add_lamp(
    scene: &mut Scene,
    light: Light,
    range: f32,
    intensity: f32,
) -> Result<Entity> {
    let e = scene.add_light(light)?;
    scene.world.entity_mut(e).insert(
        ShadowConfig::shared()
            .with_range(range)
            .with_intensity(intensity),
    );
    Ok(e)
}
