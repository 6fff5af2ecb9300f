//! A street at night for the frame pipeline's shared budget: lamps of five kinds on posts along
//! both sides of a street, a parked car and a bench under each, every lamp a
//! [`ShadowConfig::shared`] choice with its own brightness, and a camera at eye height looking
//! down the street (from 8 lamps on, some stand behind it and light nothing it sees). One lamp
//! can swing.

use bevy_ecs::change_detection::DetectChangesMut;
use bevy_ecs::entity::Entity;
use glam::{Mat4, Vec3};
use shadow_frame::scene::LightSource;
use shadow_frame::{FrameBudget, Scene, ShadowConfig, Shadows};
use soft_shadow_core::{Camera, Light, LightPoint, Result};
use soft_shadow_reference::scenes::shapes::{cuboid, ground};
use std::sync::Arc;

/// Metres between neighbouring lamps on one side of the street.
pub const SPACING: f32 = 9.0;

/// A lamp's influence radius, metres.
pub const RANGE: f32 = 9.0;

/// The street, its lamps and the camera's receivers.
pub struct NightStreet {
    /// The ECS scene (frame receivers and the frame budget already inserted).
    pub scene: Scene,
    /// The lamp entities, in the order they stand (alternating sides, down the street).
    pub lamps: Vec<Entity>,
    /// The lamps' lights as built (the swinging one moves from its own).
    pub lights: Vec<Light>,
    /// The lamp [`NightStreet::swing`] moves: the first one ahead of the camera.
    pub swinging: usize,
    /// The camera.
    pub camera: Camera,
    /// The G-buffer's width and height.
    size: (u32, u32),
}

/// Lamp `i`'s light, its head at `at`: a sphere, a disk, a rect, a segment or a triangle, by
/// `i` modulo 5, the one-sided ones facing down.
fn lamp(i: usize, at: Vec3) -> Light {
    match i % 5 {
        0 => Light::Sphere {
            center: at,
            radius: 0.15,
        },
        1 => Light::Disk {
            center: at,
            normal: Vec3::NEG_Y,
            radius: 0.2,
        },
        2 => Light::Rect {
            center: at,
            u_half: Vec3::Z * 0.1,
            v_half: Vec3::X * 0.3,
        },
        3 => Light::Linear {
            a: at - Vec3::X * 0.4,
            b: at + Vec3::X * 0.4,
        },
        _ => Light::Triangle {
            a: at + Vec3::new(-0.25, 0.0, -0.2),
            b: at + Vec3::new(0.25, 0.0, -0.2),
            c: at + Vec3::new(0.0, 0.0, 0.25),
        },
    }
}

impl NightStreet {
    /// `lamps` lamps (alternating sides, [`SPACING`] apart on each), receivers from a
    /// `width x height` G-buffer of a camera 1.7 m high looking down the street, and a frame
    /// budget of `budget_ms`.
    pub fn new(lamps: usize, width: u32, height: u32, budget_ms: f64) -> Result<Self> {
        let mut scene = Scene::new();
        let length = SPACING * (lamps.div_ceil(2) as f32 + 1.0);
        // The first lamps stand ahead of the camera (at x = -2); from 8 lamps on, an eighth of
        // the pairs stand behind it.
        let first = -4.0 - SPACING * (lamps / 8) as f32;
        scene.add_mesh(
            Arc::new(ground((length - first).max(20.0) * 2.0, 0.0, 1)),
            Mat4::IDENTITY,
            Shadows::CAST_AND_RECEIVE,
        )?;
        let post = Arc::new(cuboid("post", Vec3::ZERO, Vec3::new(0.06, 1.6, 0.06)));
        let car = Arc::new(cuboid("car", Vec3::ZERO, Vec3::new(2.0, 0.7, 0.9)));
        let bench = Arc::new(cuboid("bench", Vec3::ZERO, Vec3::new(0.8, 0.25, 0.3)));
        let mut ids = Vec::new();
        let mut lights = Vec::new();
        for i in 0..lamps {
            let side = if i % 2 == 0 { 1.0 } else { -1.0 };
            let x = first + SPACING * (i / 2) as f32 + (i % 2) as f32 * 0.5 * SPACING;
            let at = |dx: f32, y: f32, z: f32| Mat4::from_translation(Vec3::new(x + dx, y, z));
            scene.add_mesh(
                post.clone(),
                at(0.0, 1.6, side * 5.0),
                Shadows::CAST_AND_RECEIVE,
            )?;
            scene.add_mesh(
                car.clone(),
                at(2.5, 0.7, side * 3.2),
                Shadows::CAST_AND_RECEIVE,
            )?;
            scene.add_mesh(
                bench.clone(),
                at(-2.0, 0.25, side * 5.6),
                Shadows::CAST_AND_RECEIVE,
            )?;
            let light = lamp(i, Vec3::new(x, 3.6, side * 4.4));
            let e = scene.add_light(light)?;
            // Brightness varies from lamp to lamp, as a street's old and new lamps do.
            let intensity = [1.0, 0.4, 2.0, 0.7][i % 4];
            scene.world.entity_mut(e).insert(
                ShadowConfig::shared()
                    .with_range(RANGE)
                    .with_intensity(intensity),
            );
            ids.push(e);
            lights.push(light);
        }
        let eye = Vec3::new(-2.0, 1.7, 0.5);
        let swinging = lights
            .iter()
            .position(|l: &Light| matches!(l.center(), LightPoint::Position(p) if p.x > eye.x))
            .unwrap_or(0);
        let camera = Camera {
            eye,
            target: Vec3::new(30.0, 0.0, 0.0),
            fov_y: 60f32.to_radians(),
            near: 0.1,
            far: 120.0,
        };
        scene.world.insert_resource(FrameBudget { ms: budget_ms });
        let mut street = Self {
            scene,
            lamps: ids,
            lights,
            swinging,
            camera,
            size: (width, height),
        };
        street.look(camera);
        Ok(street)
    }

    /// Puts the camera at `camera` and the receivers it sees in the frame's receivers.
    fn look(&mut self, camera: Camera) {
        self.camera = camera;
        crate::animated::look(&mut self.scene, camera, self.size.0, self.size.1);
    }

    /// Walks the camera `metres` down the street (its G-buffer, and so the frame's receivers,
    /// made again).
    pub fn walk(&mut self, metres: f32) {
        let step = Vec3::X * metres;
        let c = self.camera;
        self.look(Camera {
            eye: c.eye + step,
            target: c.target + step,
            ..c
        });
    }

    /// Frame `f` of the swinging lamp's swing ([`NightStreet::swinging`]): it moves along the
    /// street on a 30 cm arc (the other lamps stay), so that lamp alone makes its maps again.
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
