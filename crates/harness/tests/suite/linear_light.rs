//! linear-light: the linear transition of section 3.1 against its closed form, sums of shares,
//! convergence in N on `linear-bar` and CPU against GPU (hard cases: the stability suite, over every technique).

use super::receivers;
use crate::common::{Failures, gpu_for_test};
use glam::{Vec2, Vec3};
use harness::metrics::rms_255;
use harness::setup::PreparedScene;
use linear_light::LinearLight;
use proptest::prelude::*;
use soft_shadow_core::{
    Aabb, Light, Receivers as Recv, SceneGeometry, ShadowTechnique, TriangleMesh,
};
use soft_shadow_reference::ground_truth::GroundTruthSettings;
use soft_shadow_reference::scenes::catalogue::{SCENE_NAMES, build};
use soft_shadow_reference::scenes::shapes::{horizontal_rect, quad_grid};

fn geometry(meshes: &[TriangleMesh]) -> SceneGeometry {
    let tris: Vec<[Vec3; 3]> = meshes
        .iter()
        .flat_map(|m| m.indices.iter().map(|t| t.map(|i| m.positions[i as usize])))
        .collect();
    SceneGeometry {
        bounds: Aabb::of_triangles(&tris),
        casters: tris.clone(),
        receivers: tris,
    }
}

/// The light `(-h, 2.5, 0)..(h, 2.5, 0)`, an occluder `x in [-1.5, 0]` at height `occ_y` whose
/// edge (along z) crosses the light's direction, a 3 m ground.
fn edge_scene(occ_y: f32, h: f32) -> (SceneGeometry, Light) {
    let g = geometry(&[
        horizontal_rect("ground", Vec2::new(-1.5, 1.5), Vec2::new(-1.5, 1.5), 0.0),
        horizontal_rect(
            "occluder",
            Vec2::new(-1.5, 0.0),
            Vec2::new(-1.5, 1.5),
            occ_y,
        ),
    ]);
    let light = Light::Linear {
        a: Vec3::new(-h, 2.5, 0.0),
        b: Vec3::new(h, 2.5, 0.0),
    };
    (g, light)
}

/// Exact visible fraction of the segment from `p` past the occluder half-plane `x <= 0` at
/// height `occ_y` (z within the occluder): section 3.1's rational function.
fn exact_edge(p: Vec3, occ_y: f32, h: f32) -> f32 {
    if p.y >= occ_y {
        return 1.0;
    }
    let u = (occ_y - p.y) / (2.5 - p.y);
    // The ray to (s, 2.5, 0) crosses the occluder's plane at x = p.x + u (s - p.x) >= 0.
    let s_min = p.x - p.x / u;
    ((h - s_min) / (2.0 * h)).clamp(0.0, 1.0)
}

/// A receiver parallel to the light: `V` is linear across the penumbra (equation 1 with equal
/// slopes) and the technique matches it within 2/255 RMS at 1024, for N = 2, 3, 5.
#[test]
fn linear_light_is_linear_across_a_straight_edge() {
    let (g, light) = edge_scene(1.0, 0.5);
    let positions: Vec<Vec3> = (0..121)
        .flat_map(|i| {
            (0..5).map(move |k| Vec3::new(-0.6 + 0.01 * i as f32, 0.0, -0.4 + 0.2 * k as f32))
        })
        .collect();
    let normals = vec![Vec3::Y; positions.len()];
    let recv = Recv {
        positions: &positions,
        normals: &normals,
    };
    let exact: Vec<f32> = positions.iter().map(|&p| exact_edge(p, 1.0, 0.5)).collect();
    assert!(exact.iter().filter(|v| **v > 0.0 && **v < 1.0).count() > 300);
    for n in [2, 3, 5] {
        let t = LinearLight::new(n);
        let maps = t
            .generate_cpu(crate::common::cpu(), &g, &light, 1024)
            .unwrap();
        let v = t.evaluate_cpu(&maps, &recv).unwrap();
        let rms = rms_255(&v, &exact);
        println!("straight edge, N = {n}, 1024: rms {rms:.3}/255 against the linear closed form");
        assert!(rms < 2.0, "N = {n}: rms {rms:.3}");
    }
}

/// A tilted receiver: the plane `y = 1.2 (x - 0.1) + 0.2`, which runs under the occluder's edge
/// and crosses the light's line (y = 2.5) at x = 2.02. The linear channel against the rational
/// function of equation 1 is reported (and bounded), and `V` stays finite and in [0, 1] up to the
/// singularity. The plane reaches the light, so the light's views are cube faces; the face
/// below the light images the receiver obliquely, and the channel, linear in that face's image
/// plane, departs from the rational function by 9.97/255 at N = 2 (5.97 in one frustum turned
/// towards the casters, which left the receivers beside the light out of the map).
#[test]
fn linear_light_on_a_tilted_receiver_stays_finite_at_the_light_line() {
    let (_, light) = edge_scene(1.0, 0.5);
    let plane = |x: f32, z: f32| Vec3::new(x, 1.2 * (x - 0.1) + 0.2, z);
    let g = geometry(&[
        quad_grid(
            "tilted",
            plane(-1.0, -1.5),
            Vec3::Z * 3.0,
            plane(2.1, -1.5) - plane(-1.0, -1.5),
            1,
        ),
        horizontal_rect("occluder", Vec2::new(-1.5, 0.0), Vec2::new(-1.5, 1.5), 1.0),
    ]);
    let positions: Vec<Vec3> = (0..=265)
        .flat_map(|i| (0..3).map(move |k| plane(-0.6 + 0.01 * i as f32, -0.3 + 0.3 * k as f32)))
        .collect();
    let normals = vec![Vec3::new(-1.2, 1.0, 0.0).normalize(); positions.len()];
    let recv = Recv {
        positions: &positions,
        normals: &normals,
    };
    let exact: Vec<f32> = positions.iter().map(|&p| exact_edge(p, 1.0, 0.5)).collect();
    assert!(exact.iter().filter(|v| **v > 0.0 && **v < 1.0).count() > 30);
    for n in [2, 3, 5] {
        let t = LinearLight::new(n);
        let maps = t
            .generate_cpu(crate::common::cpu(), &g, &light, 1024)
            .unwrap();
        let v = t.evaluate_cpu(&maps, &recv).unwrap();
        assert!(v.iter().all(|x| x.is_finite() && (0.0..=1.0).contains(x)));
        let rms = rms_255(&v, &exact);
        println!("tilted receiver, N = {n}, 1024: rms {rms:.2}/255 against the rational function");
        assert!(rms < 10.5, "N = {n}: rms {rms:.2}");
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(12))]

    /// Random edge scenes (occluder height, light length) and N: a point whose whole
    /// neighbourhood sees the whole segment sums to 1, a point deep in the umbra to 0.
    #[test]
    fn fully_lit_sums_to_one_and_umbra_to_zero(
        occ_y in 0.5f32..1.8,
        h in 0.1f32..0.8,
        n in prop::sample::select(vec![2u32, 3, 4, 5, 9]),
    ) {
        let (g, light) = edge_scene(occ_y, h);
        let t = LinearLight::new(n);
        let maps = t.generate_cpu(crate::common::cpu(), &g, &light, 256).unwrap();
        let margin = 0.08;
        let candidates: Vec<Vec3> = (0..=60)
            .map(|i| Vec3::new(-1.2 + 0.04 * i as f32, 0.0, 0.1))
            .filter(|p| {
                let v = [-margin, 0.0, margin].map(|d| exact_edge(*p + Vec3::X * d, occ_y, h));
                v.iter().all(|x| *x == 1.0) || v.iter().all(|x| *x == 0.0)
            })
            .collect();
        let normals = vec![Vec3::Y; candidates.len()];
        let v = t
            .evaluate_cpu(&maps, &Recv { positions: &candidates, normals: &normals })
            .unwrap();
        for (p, got) in candidates.iter().zip(&v) {
            let want = exact_edge(*p, occ_y, h);
            prop_assert!((got - want).abs() <= 1e-5, "N = {} at {:?}: {} vs {}", n, p, got, want);
        }
    }
}

/// On `linear-bar` at 512, more samples never make the error worse: RMS of `V * 255` against the
/// Monte Carlo reference for N = 2, 3, 5, 9 is non-increasing (within the reference's own
/// standard error).
#[test]
fn more_samples_do_not_increase_the_error_on_linear_bar() {
    let spec = build("linear-bar").unwrap();
    let prep = PreparedScene::new(spec, 96, GroundTruthSettings::default()).unwrap();
    let reference = prep.reference_v();
    let noise = prep.std_error_255();
    let mut last = f64::INFINITY;
    for n in [2, 3, 5, 9] {
        let t = LinearLight::new(n);
        let maps = t
            .generate_cpu(crate::common::cpu(), &prep.geometry, &prep.spec.light, 512)
            .unwrap();
        let v = t.evaluate_cpu(&maps, &prep.receivers()).unwrap();
        let rms = rms_255(&v, &reference);
        println!("linear-bar N = {n} at 512: rms {rms:.3}/255 (reference noise {noise:.2})");
        assert!(rms <= last + noise, "N = {n}: {rms:.3} after {last:.3}");
        last = rms;
    }
}

/// The scene's light as linear-light models it: segments and triangles as they are, a rect's u
/// axis, a disk's or sphere's diameter, a short segment through a point light; distant lights
/// (and kinds added later) are skipped.
fn as_segment(light: &Light) -> Option<Light> {
    let seg = |c: Vec3, half: Vec3| Light::Linear {
        a: c - half,
        b: c + half,
    };
    match *light {
        Light::Linear { .. } | Light::Triangle { .. } => Some(*light),
        Light::Rect { center, u_half, .. } => Some(seg(center, u_half)),
        Light::Disk {
            center,
            normal,
            radius,
        } => Some(seg(
            center,
            soft_shadow_core::light::orthonormal_basis(normal).0 * radius,
        )),
        Light::Sphere { center, radius } => Some(seg(center, Vec3::X * radius)),
        Light::Point { position } => Some(seg(position, Vec3::X * 1e-4)),
        _ => None,
    }
}

/// Every catalogue scene with a local light, lit by a segment (its own, or the light's axis):
/// `V` agrees between CPU and GPU ([`crate::common::Agreement`]) for N = 2, 3, 5 at
/// [`super::AGREEMENT_RESOLUTIONS`], and where the GPU rasterizes as the CPU does, the
/// visibility channels equal up to rasterization (mean absolute difference below 0.01).
#[test]
#[cfg_attr(
    no_gpu_adapter,
    ignore = "needs a GPU adapter: no Vulkan driver found (apt-get install mesa-vulkan-drivers)"
)]
fn linear_light_agrees_between_cpu_and_gpu_on_every_scene() {
    let Some(ctx) = gpu_for_test("linear_light_agrees_between_cpu_and_gpu_on_every_scene") else {
        return;
    };
    let mut failures = Failures::default();
    // The maps are held to the CPU's where the GPU rasterizes as it does; `V` everywhere.
    let same_raster = crate::common::rasterizes_as_the_cpu(&ctx);
    for name in SCENE_NAMES {
        let spec = build(name).unwrap();
        let Some(light) = as_segment(&spec.light) else {
            continue;
        };
        let r = receivers(&spec, 96);
        let recv = Recv {
            positions: &r.positions,
            normals: &r.normals,
        };
        for t in LinearLight::standard_set() {
            for res in super::AGREEMENT_RESOLUTIONS {
                let cm = t
                    .generate_cpu(crate::common::cpu(), &r.geometry, &light, res)
                    .unwrap();
                let gm = t.generate_gpu(&ctx, &r.geometry, &light, res).unwrap();
                let gc = gm.first().read_channels(&ctx).unwrap();
                let diff: f64 = cm
                    .first()
                    .channels()
                    .iter()
                    .zip(&gc)
                    .flat_map(|(a, b)| a.data().iter().zip(b.data()))
                    .map(|(a, b)| (a - b).abs() as f64)
                    .sum::<f64>()
                    / (t.samples * res * res) as f64;
                println!("{name} {} {res}: channels differ by {diff:.4}", t.label());
                failures.check(!same_raster || diff < 0.01, || {
                    format!("{name} {} {res}: channels differ by {diff:.4}", t.label())
                });
                let cv = t.evaluate_cpu(&cm, &recv).unwrap();
                let gv = t.evaluate_gpu(&ctx, &gm, &recv).unwrap();
                failures.agree(&format!("{name} {} {res}", t.label()), &cv, &gv);
            }
        }
    }
    failures.assert_none();
}

/// A receiver-only plate 0.3 m under a segment lamp, over a box that casts, in a room whose
/// walls and ceiling cast (so the lamp's views are cube faces): nothing casts between the plate
/// and the lamp, so `V = 1` on it, CPU and GPU. The face below starts just before the nearest
/// surface its grid maps hold, the plate (`Generation::coverage_with_receivers_of`): from the
/// nearest caster alone (the box's top), the plate fell in front of the near plane, out of the
/// grid maps, and read the skins of the box's edges behind it.
#[test]
fn a_receiver_before_every_caster_of_a_cube_face_reads_lit() {
    use soft_shadow_core::DynTechnique;
    use soft_shadow_reference::scenes::shapes::cuboid;
    let tris = |m: TriangleMesh| m.world_triangles(glam::Mat4::IDENTITY).collect::<Vec<_>>();
    let room = tris(cuboid(
        "room",
        Vec3::new(0.0, 1.5, 0.0),
        Vec3::new(3.0, 1.5, 3.0),
    ));
    let mut casters = room.clone();
    casters.extend(tris(cuboid(
        "box",
        Vec3::new(0.0, 0.2, 0.0),
        Vec3::splat(0.25),
    )));
    let plate = tris(cuboid(
        "plate",
        Vec3::new(0.0, 0.69, 0.0),
        Vec3::new(0.4, 0.01, 0.4),
    ));
    let mut receivers = room;
    receivers.extend(plate.iter().copied());
    let geometry = SceneGeometry::new(casters, receivers);
    let light = Light::Linear {
        a: Vec3::new(-0.2, 1.0, 0.0),
        b: Vec3::new(0.2, 1.0, 0.0),
    };
    assert_eq!(
        soft_shadow_core::LightViews::plan(&light, &geometry, None).kind_name(),
        "cube"
    );
    // The plate's top, 0.3 m under the lamp.
    let positions: Vec<Vec3> = (0..15 * 15)
        .map(|i| {
            Vec3::new(
                -0.35 + 0.05 * (i % 15) as f32,
                0.7,
                -0.35 + 0.05 * (i / 15) as f32,
            )
        })
        .collect();
    let normals = vec![Vec3::Y; positions.len()];
    let recv = Recv::new(&positions, &normals);
    let gpu = gpu_for_test("a_receiver_before_every_caster_of_a_cube_face_reads_lit");
    let backends = crate::common::backends(gpu.as_ref());
    for be in backends {
        let ctx = crate::common::context(be, gpu.as_ref());
        for t in LinearLight::standard_set() {
            let maps = t.generate(ctx, &geometry, &light, 128).unwrap();
            let v = maps.evaluate(gpu.as_ref(), &recv).unwrap();
            let worst = v.iter().copied().fold(1.0f32, f32::min);
            assert!(
                worst >= 1.0 - 1.0 / 255.0,
                "{} {be:?}: the plate reads V = {worst} under the lamp",
                t.label()
            );
        }
    }
}
