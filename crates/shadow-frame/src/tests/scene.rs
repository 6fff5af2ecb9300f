//! The ECS scene flattens into plain geometry: transforms applied, caster/receiver flags kept.

use crate::{Scene, Shadows};
use glam::{Mat4, Vec3};
use soft_shadow_core::{Camera, Light, TriangleMesh};
use std::sync::Arc;

fn unit_triangle() -> Arc<TriangleMesh> {
    Arc::new(TriangleMesh::new("tri", vec![Vec3::ZERO, Vec3::X, Vec3::Z], vec![[0, 1, 2]]).unwrap())
}

#[test]
fn geometry_applies_transforms_and_flags() {
    let mut scene = Scene::new();
    let tri = unit_triangle();
    scene
        .add_mesh(
            tri.clone(),
            Mat4::from_translation(Vec3::Y * 2.0),
            Shadows::CAST_ONLY,
        )
        .unwrap();
    scene
        .add_mesh(
            tri.clone(),
            Mat4::from_scale(Vec3::splat(3.0)),
            Shadows::RECEIVE_ONLY,
        )
        .unwrap();
    scene
        .add_mesh(tri, Mat4::IDENTITY, Shadows::CAST_AND_RECEIVE)
        .unwrap();
    let g = scene.geometry();
    assert_eq!(g.casters.len(), 2);
    assert_eq!(g.receivers.len(), 2);
    assert_eq!(
        g.casters[0],
        [
            Vec3::Y * 2.0,
            Vec3::new(1.0, 2.0, 0.0),
            Vec3::new(0.0, 2.0, 1.0)
        ]
    );
    assert_eq!(g.receivers[0][1], Vec3::new(3.0, 0.0, 0.0));
    assert_eq!(g.bounds.min, Vec3::ZERO);
    assert_eq!(g.bounds.max, Vec3::new(3.0, 2.0, 3.0));
}

#[test]
fn lights_and_camera_round_trip() {
    let mut scene = Scene::new();
    let a = Light::Point { position: Vec3::Y };
    let b = Light::Sphere {
        center: Vec3::Y * 3.0,
        radius: 0.5,
    };
    scene.add_light(a).unwrap();
    scene.add_light(b).unwrap();
    assert_eq!(scene.lights(), vec![a, b]);
    assert!(scene.camera().is_none());
    let cam = Camera {
        eye: Vec3::ONE,
        target: Vec3::ZERO,
        fov_y: 1.0,
        near: 0.1,
        far: 10.0,
    };
    scene.set_camera(cam);
    let cam2 = Camera {
        eye: Vec3::splat(2.0),
        ..cam
    };
    scene.set_camera(cam2);
    assert_eq!(
        scene.camera(),
        Some(cam2),
        "set_camera replaces the previous camera"
    );
    assert!(
        Scene::new().geometry().validate().is_err(),
        "an empty scene is a typed error"
    );
}
