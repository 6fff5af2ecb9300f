//! A street at night for the frame pipeline's shared budget: lamps of five kinds on posts along
//! both sides of a street, a parked car and a bench under each, every lamp a
//! [`shadow_frame::ShadowConfig::shared`] choice with its own brightness, and a camera at eye
//! height looking down the street (from 8 lamps on, some stand behind it and light nothing it
//! sees), as [`Lamps`]. One lamp can swing.

use super::{Lamps, add_lamp};
use crate::scenes::shapes::{cuboid, ground};
use glam::{Mat4, Vec3};
use shadow_frame::{Scene, Shadows};
use soft_shadow_core::{Camera, Light, LightPoint, Result};
use std::sync::Arc;

/// Metres between neighbouring lamps on one side of the street.
pub const SPACING: f32 = 9.0;

/// A lamp's influence radius, metres.
pub const RANGE: f32 = 9.0;

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
            u_half: Vec3::X * 0.3,
            v_half: Vec3::Z * 0.1,
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

/// The street with `lamps` lamps (alternating sides, [`SPACING`] apart on each), receivers
/// from a `width x height` G-buffer of a camera 1.7 m high looking down the street (it walks
/// down the street), and a frame budget of `budget_ms`; the first lamp ahead of the camera
/// swings.
pub fn street(lamps: usize, width: u32, height: u32, budget_ms: f64) -> Result<Lamps> {
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
        // Brightness varies from lamp to lamp, as a street's old and new lamps do.
        let intensity = [1.0, 0.4, 2.0, 0.7][i % 4];
        ids.push(add_lamp(&mut scene, light, RANGE, intensity)?);
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
    Ok(Lamps::new(
        scene,
        "the night street",
        ids,
        lights,
        swinging,
        camera,
        Vec3::X,
        (width, height),
        budget_ms,
    ))
}
