//! The animated demo scene of the frame pipeline, shared by `examples/animated.rs`, the
//! `frame_caching` bench and tests: five lights of different kinds (rect, segment, disk, sphere,
//! and a point that takes the hard-shadow path), a static torus and a box that orbits between the
//! lights for the first half of the frames, then rests.

use bevy_ecs::change_detection::DetectChangesMut;
use bevy_ecs::entity::Entity;
use glam::{Mat4, Vec3};
use shadow_frame::scene::Transform;
use shadow_frame::{FramePipeline, ShadowConfig};
use shadow_frame::{Scene, Shadows};
use soft_shadow_core::raster::GBufferTexel;
use soft_shadow_core::{Camera, DynTechnique, Light, Map2D, Result};
use soft_shadow_reference::scenes::shapes::{cuboid, ground, torus};
use std::sync::Arc;

pub use soft_shadow_reference::scenes::lamps::look;

/// A frame pipeline with every technique of `soft_shadow_techniques::registry()` registered.
pub fn pipeline() -> FramePipeline {
    FramePipeline::new().with_registry(&soft_shadow_techniques::registry())
}

/// The scene, its light entities, the moving caster and the camera G-buffer its receivers come
/// from.
pub struct AnimatedScene {
    /// The ECS scene (frame receivers already inserted).
    pub scene: Scene,
    /// The light entities, in the order above.
    pub lights: Vec<Entity>,
    /// The orbiting box.
    pub mover: Entity,
    /// The camera G-buffer (`size²`).
    pub gbuffer: Map2D<GBufferTexel>,
    /// G-buffer indices of the frame receivers.
    pub pixels: Vec<usize>,
}

impl AnimatedScene {
    /// Builds the scene with `size²` camera receivers and maps of `resolution`.
    pub fn new(size: u32, resolution: u32) -> Result<Self> {
        let mut scene = Scene::new();
        scene.add_mesh(
            Arc::new(ground(14.0, 0.0, 1)),
            Mat4::IDENTITY,
            Shadows::CAST_AND_RECEIVE,
        )?;
        scene.add_mesh(
            Arc::new(torus(Vec3::new(-3.0, 0.9, -3.0), 0.6, 0.2, 32, 12)),
            Mat4::IDENTITY,
            Shadows::CAST_AND_RECEIVE,
        )?;
        let mover = scene.add_mesh(
            Arc::new(cuboid("mover", Vec3::ZERO, Vec3::splat(0.35))),
            Mat4::IDENTITY,
            Shadows::CAST_AND_RECEIVE,
        )?;
        let lights = [
            (
                Light::Rect {
                    center: Vec3::new(-3.0, 3.0, -3.0),
                    u_half: Vec3::X * 0.4,
                    v_half: Vec3::Z * 0.4,
                },
                Arc::new(occlusion_slices::OcclusionSlices::new(
                    8,
                    occlusion_slices::Prefilter::Sat,
                )) as Arc<dyn DynTechnique>,
            ),
            (
                Light::Linear {
                    a: Vec3::new(2.4, 3.0, -3.0),
                    b: Vec3::new(3.6, 3.0, -3.0),
                },
                Arc::new(linear_light::LinearLight::new(3)),
            ),
            (
                Light::Disk {
                    center: Vec3::new(3.0, 3.0, 3.0),
                    normal: Vec3::NEG_Y,
                    radius: 0.4,
                },
                Arc::new(penumbra_limit::PenumbraLimit::new(
                    penumbra_limit::Generator::Silhouette,
                )),
            ),
            (
                Light::Sphere {
                    center: Vec3::new(-3.0, 3.0, 3.0),
                    radius: 0.3,
                },
                Arc::new(shadow_width::ShadowWidth::standard_set().remove(0)),
            ),
            (
                Light::Point {
                    position: Vec3::new(0.0, 3.5, 0.0),
                },
                Arc::new(shadow_maps::ShadowMapBaseline::new(
                    shadow_maps::Filter::Hard,
                )),
            ),
        ];
        let mut ids = Vec::new();
        for (light, t) in lights {
            let e = scene.add_light(light)?;
            scene
                .world
                .entity_mut(e)
                .insert(ShadowConfig::explicit(t, resolution).with_range(4.5));
            ids.push(e);
        }
        let camera = Camera {
            eye: Vec3::new(0.0, 12.0, 7.0),
            target: Vec3::ZERO,
            fov_y: 55f32.to_radians(),
            near: 0.1,
            far: 50.0,
        };
        let (gb, pixels) = look(&mut scene, camera, size, size);
        Ok(Self {
            scene,
            lights: ids,
            mover,
            gbuffer: gb,
            pixels,
        })
    }

    /// Places the box for frame `f` of `frames`: it orbits the centre for the first half, then
    /// rests. An unchanged transform is not written (`set_if_neq`), so it is not a change.
    pub fn step(&mut self, f: u32, frames: u32) {
        let t = (f.min(frames / 2) as f32) * 0.25;
        let at = Vec3::new(3.0 * t.cos(), 0.9, 3.0 * t.sin());
        if let Some(mut tr) = self.scene.world.get_mut::<Transform>(self.mover) {
            tr.set_if_neq(Transform(Mat4::from_translation(at)));
        }
    }
}
