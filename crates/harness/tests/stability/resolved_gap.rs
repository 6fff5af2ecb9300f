//! Biases cannot push a receiver through a gap the map resolves.
//!
//! A 2 m square occluder hangs over the ground at a height `h` chosen so that its depth gap to the
//! ground along the light, `h / cos(theta)`, is [`GAP_TEXELS`] texels of the hard shadow map
//! beyond the receiver's own depth spread (`DEPTH_SPREAD * tan(theta)` texels), for a small
//! distant light at `theta` from the ground's normal, at every resolution of the hard cases. Bias
//! is capped at one texel beyond that spread (`Bias::MAX_PUSH`), so every technique must see the
//! umbra under the occluder's centre. Before the cap the default terms pushed a receiver by
//! `1/cos + 1 + tan` texels (2 at `theta = 0`, 6.7 at 70 degrees) and every depth-map technique
//! lit the umbra (V = 1) at every resolution. Filters read the receiver's own plane at each
//! tap's texel centre (a signed receiver-plane bias, `ShadowCoord::grad`); the unsigned
//! `tan(theta) * |d|` term they used before pushed a 5x5 PCF kernel through the same gap at
//! 60 degrees.
//!
//! Named exceptions:
//! - penumbra-limit's 16-bit and 8-bit storages ([`QUANTIZED`]): their depth step is coarser
//!   than a 1.5-texel gap (mean V 1.0 at 256-2048).
//! - occlusion-slices at oblique light: its depth resolution is a slice, not a texel. Tilted
//!   60 degrees the occluder spans 1.7 m of depth across the slices, and a receiver within one
//!   slice spacing below a slice fades it out (`Frame::fade`): mean V 0.19-0.47 at 16² and
//!   0.95-1.0 at 256-2048. Straight overhead it passes.

use super::{backends, label, scene_for, techniques};
use glam::{Vec2, Vec3};
use soft_shadow_core::light_space::DEPTH_SPREAD;
use soft_shadow_core::{Camera, Coverage, DistantProfile, Light, SampleView};
use soft_shadow_reference::scenes::shapes::{ground, horizontal_rect};
use soft_shadow_reference::scenes::{MeshInstance, SceneSpec};
use std::sync::Arc;

/// Depth gap beyond the receiver's own spread, in texels of the hard shadow map (the cap is 1).
const GAP_TEXELS: f32 = 1.5;

/// Angles of the light from the ground's normal, degrees.
const ANGLES: [f32; 2] = [0.0, 60.0];

/// Storage variants whose depth step is coarser than the gap at some resolution: the map does
/// not resolve it (penumbra-limit's 16-bit and 8-bit depths).
const QUANTIZED: [&str; 2] = ["-f16", "-rgba8"];

/// Largest mean `V` over the umbra receivers.
const MAX_MEAN_V: f32 = 0.1;

fn scene(theta: f32, h: f32) -> SceneSpec {
    let inst = |mesh, caster| MeshInstance {
        mesh: Arc::new(mesh),
        transform: glam::Mat4::IDENTITY,
        caster,
        receiver: true,
    };
    SceneSpec {
        name: format!("resolved-gap-{}", theta.to_degrees().round()),
        description: "a wide occluder a few texels above the ground".into(),
        hard_case: false,
        meshes: vec![
            inst(ground(8.0, 0.0, 1), false),
            inst(
                horizontal_rect("occluder", Vec2::new(-1.0, 1.0), Vec2::new(-1.0, 1.0), h),
                true,
            ),
        ],
        light: Light::Distant {
            direction: Vec3::new(theta.sin(), theta.cos(), 0.0),
            angular_diameter: 0.5f32.to_radians(),
            profile: DistantProfile::UniformDisk,
        },
        camera: Camera {
            eye: Vec3::new(0.0, 4.0, 3.0),
            target: Vec3::ZERO,
            fov_y: 0.9,
            near: 0.05,
            far: 100.0,
        },
    }
}

/// World size of a texel, at the ground's centre, of the central map of `spec` at `res`.
fn texel(spec: &SceneSpec, res: u32) -> f32 {
    let geometry = spec.to_scene().unwrap().geometry();
    let coverage = Coverage::new(&geometry, &spec.light);
    let m = SampleView::center(&spec.light, &coverage).params(res);
    m.texel_size(m.linear_depth(Vec3::ZERO))
}

#[test]
fn no_bias_pushes_a_receiver_through_a_resolved_gap() {
    let mut failures = Vec::new();
    for t in techniques() {
        if QUANTIZED.iter().any(|q| t.variant().ends_with(q)) {
            continue;
        }
        for deg in ANGLES {
            if deg != 0.0 && t.name() == "occlusion-slices" {
                continue; // Its depth resolution is a slice, not a texel (module docs).
            }
            let theta = deg.to_radians();
            let needed = GAP_TEXELS + 2.0 * DEPTH_SPREAD * theta.tan();
            for res in super::RESOLUTIONS {
                // The occluder's height barely moves the coverage: two rounds settle the texel.
                let mut h = 0.1;
                for _ in 0..2 {
                    h = needed * texel(&scene_for(t.as_ref(), &scene(theta, h)), res) * theta.cos();
                }
                let scene = scene_for(t.as_ref(), &scene(theta, h));
                let geometry = scene.to_scene().unwrap().geometry();
                // Receivers on the ground under the middle of the umbra, which the light throws
                // away from its side (the map sees the occluder foreshortened by cos(theta)).
                let shift = -h * theta.tan();
                let positions: Vec<Vec3> = (0..11 * 11)
                    .map(|i| {
                        let (x, z) = ((i % 11) as f32 - 5.0, (i / 11) as f32 - 5.0);
                        Vec3::new(shift + x * 0.03, 0.0, z * 0.06)
                    })
                    .collect();
                let normals = vec![Vec3::Y; positions.len()];
                let receivers = soft_shadow_core::Receivers::new(&positions, &normals);
                for be in backends() {
                    let what = label(t.as_ref(), &scene.name, res, be);
                    let gpu = super::gpu();
                    let maps = t
                        .generate(
                            crate::common::context(be, gpu),
                            &geometry,
                            &scene.light,
                            res,
                        )
                        .unwrap_or_else(|e| panic!("{what}: generate: {e}"));
                    let v = maps
                        .evaluate(gpu, &receivers)
                        .unwrap_or_else(|e| panic!("{what}: evaluate: {e}"));
                    let mean = v.iter().sum::<f32>() / v.len() as f32;
                    if mean > MAX_MEAN_V {
                        failures.push(format!("{what}: h {h:.5} m, mean V {mean:.2}"));
                    }
                }
            }
        }
    }
    assert!(
        failures.is_empty(),
        "a bias pushed the umbra through a resolved gap:\n{}",
        failures.join("\n")
    );
}
