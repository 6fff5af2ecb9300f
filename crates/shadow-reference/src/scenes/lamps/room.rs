//! A room lit by three lamps for the frame pipeline's shared budget: `room-lamp`'s closed 6 m
//! room and furniture (a cabinet, a shelf, a desk, a crate, a teapot and Suzanne), lit by its
//! sphere lamp at table height, a rect panel under the ceiling and a small disk lamp over the
//! desk, every lamp a [`shadow_frame::ShadowConfig::shared`] choice with its own brightness,
//! and a camera in a corner of the room walking towards its middle, as [`Lamps`]. The table
//! lamp can swing.

use super::{Lamps, add_lamp};
use crate::scenes::catalogue;
use glam::Vec3;
use soft_shadow_core::{Light, Result};

/// A lamp's influence radius, metres: the whole room.
pub const RANGE: f32 = 9.0;

/// The room with its three lamps, receivers from a `width x height` G-buffer of
/// `room-lamp-corner`'s camera, and a frame budget of `budget_ms`.
pub fn room(width: u32, height: u32, budget_ms: f64) -> Result<Lamps> {
    let spec = catalogue::build("room-lamp-corner")?;
    let mut scene = shadow_frame::Scene::new();
    spec.add_meshes(&mut scene)?;
    let lamps = [
        // The table lamp, `room-lamp`'s own.
        (spec.light, 1.0),
        // A panel under the ceiling, facing down.
        (
            Light::Rect {
                center: Vec3::new(0.2, 2.9, -0.4),
                u_half: Vec3::X * 0.3,
                v_half: Vec3::Z * 0.3,
            },
            3.0,
        ),
        // A reading lamp over the desk, facing down.
        (
            Light::Disk {
                center: Vec3::new(-1.3, 1.7, 0.2),
                normal: Vec3::NEG_Y,
                radius: 0.08,
            },
            0.3,
        ),
    ];
    let (mut ids, mut lights) = (Vec::new(), Vec::new());
    for (light, intensity) in lamps {
        ids.push(add_lamp(&mut scene, light, RANGE, intensity)?);
        lights.push(light);
    }
    let camera = spec.camera;
    let walk = (camera.target - camera.eye) * Vec3::new(1.0, 0.0, 1.0);
    Ok(Lamps::new(
        scene,
        "the room",
        ids,
        lights,
        0,
        camera,
        walk,
        (width, height),
        budget_ms,
    ))
}
