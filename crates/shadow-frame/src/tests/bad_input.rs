//! Bad input gets a typed error naming the problem; nothing panics.

use crate::gltf::{glb, import_gltf_slice};
use crate::{Scene, Shadows};
use glam::{Mat4, Vec3};
use soft_shadow_core::{Light, ShadowError, TriangleMesh};
use std::sync::Arc;

const BUNNY: &[u8] = include_bytes!("../../../../assets/stanford-bunny.glb");

fn triangle_glb(mode: u32, index: u16) -> Vec<u8> {
    let mut bin = Vec::new();
    for v in [[0f32, 0., 0.], [1., 0., 0.], [0., 1., 0.]] {
        for c in v {
            bin.extend_from_slice(&c.to_le_bytes());
        }
    }
    for i in [0u16, 1, index] {
        bin.extend_from_slice(&i.to_le_bytes());
    }
    let json = format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],"nodes":[{{"mesh":0,"translation":[0,2,0]}}],
        "meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}},"indices":1,"mode":{mode}}}]}}],
        "buffers":[{{"byteLength":42}}],
        "bufferViews":[{{"buffer":0,"byteOffset":0,"byteLength":36}},{{"buffer":0,"byteOffset":36,"byteLength":6}}],
        "accessors":[{{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}},
                     {{"bufferView":1,"componentType":5123,"count":3,"type":"SCALAR"}}]}}"#
    );
    glb(&json, &bin)
}

fn gltf_reason(r: soft_shadow_core::Result<TriangleMesh>) -> String {
    match r {
        Err(ShadowError::Gltf { reason, .. }) => reason,
        other => panic!("expected a glTF error, got {other:?}"),
    }
}

#[test]
fn valid_glb_imports_with_node_transform() {
    let m = import_gltf_slice(&triangle_glb(4, 2), "tri.glb", None).expect("valid file");
    assert_eq!(m.indices, vec![[0, 1, 2]]);
    assert_eq!(
        m.positions[2],
        Vec3::new(0.0, 3.0, 0.0),
        "node translation applied"
    );
}

#[test]
fn strips_and_fans_become_triangles() {
    // Mode 5 = TRIANGLE_STRIP, 6 = TRIANGLE_FAN: three indices make one triangle either way.
    for mode in [5, 6] {
        let m = import_gltf_slice(&triangle_glb(mode, 2), "strip.glb", None).expect("valid file");
        assert_eq!(m.indices.len(), 1, "mode {mode}");
    }
}

#[test]
fn the_bunny_has_69451_triangles() {
    let m = import_gltf_slice(BUNNY, "bunny", None).expect("bunny imports");
    assert_eq!(m.indices.len(), 69_451);
}

#[test]
fn malformed_gltf_is_a_typed_error() {
    assert!(!gltf_reason(import_gltf_slice(b"not a gltf at all", "junk", None)).is_empty());
    assert!(
        !gltf_reason(import_gltf_slice(
            &BUNNY[..BUNNY.len() / 2],
            "half-bunny",
            None
        ))
        .is_empty()
    );
    let r = gltf_reason(import_gltf_slice(
        &triangle_glb(4, 7),
        "bad-index.glb",
        None,
    ));
    assert!(r.contains("index 7 out of range"), "{r}");
    let r = gltf_reason(import_gltf_slice(&triangle_glb(0, 2), "points.glb", None));
    assert!(r.contains("only triangles cast shadows"), "{r}");
}

/// A text file named `.glb` is "not a glTF/GLB file", not a JSON parser's complaint.
#[test]
fn a_text_file_is_not_a_gltf_file() {
    for bytes in [&b"hello, this is text"[..], b"", b"\x00\x01binary"] {
        match crate::gltf::import_gltf_slice(bytes, "notes.glb", None) {
            Err(ShadowError::Gltf { reason, .. }) => {
                assert!(reason.contains("not a glTF/GLB file"), "{reason}")
            }
            other => panic!("{:?}", other.map(|m| m.name)),
        }
    }
}

#[test]
fn nan_vertex_is_a_typed_error() {
    let r = TriangleMesh::new(
        "nan",
        vec![Vec3::ZERO, Vec3::X, Vec3::new(f32::NAN, 0.0, 0.0)],
        vec![[0, 1, 2]],
    );
    assert!(
        matches!(r, Err(ShadowError::InvalidMesh { ref reason, .. }) if reason.contains("vertex 2")),
        "{r:?}"
    );
    let bad = Arc::new(TriangleMesh {
        name: "nan".into(),
        positions: vec![Vec3::NAN; 3],
        indices: vec![[0, 1, 2]],
    });
    assert!(matches!(
        Scene::new().add_mesh(bad, Mat4::IDENTITY, Shadows::CAST_AND_RECEIVE),
        Err(ShadowError::InvalidMesh { .. })
    ));
}

#[test]
fn zero_or_negative_light_size_is_a_typed_error() {
    let bad = [
        Light::Rect {
            center: Vec3::Y,
            u_half: Vec3::ZERO,
            v_half: Vec3::Z,
        },
        Light::Disk {
            center: Vec3::Y,
            normal: Vec3::NEG_Y,
            radius: 0.0,
        },
        Light::Sphere {
            center: Vec3::Y,
            radius: -1.0,
        },
        Light::Linear {
            a: Vec3::Y,
            b: Vec3::Y,
        },
        Light::Distant {
            direction: Vec3::Y,
            angular_diameter: 0.0,
            profile: soft_shadow_core::DistantProfile::UniformDisk,
        },
        Light::Point {
            position: Vec3::NAN,
        },
        Light::Triangle {
            a: Vec3::Y,
            b: Vec3::Y,
            c: Vec3::Y,
        },
        Light::Triangle {
            a: Vec3::Y,
            b: Vec3::new(1.0, 1.0, 0.0),
            c: Vec3::new(2.0, 1.0, 1e-6),
        },
        Light::Triangle {
            a: Vec3::Y,
            b: Vec3::X,
            c: Vec3::INFINITY,
        },
    ];
    for l in bad {
        assert!(
            matches!(l.validate(), Err(ShadowError::InvalidLight(_))),
            "{l:?}"
        );
        assert!(Scene::new().add_light(l).is_err());
    }
}
