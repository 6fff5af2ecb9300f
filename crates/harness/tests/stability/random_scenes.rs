//! Random scenes from proptest, seeded ([`SEED`]) so that every run draws the same [`CASES`]:
//! up to 12 random triangles over a ground quad, a light of every kind with a random size, at
//! scales 1e-3..1e4, seen by a camera over the ground at a random map side. A fifth of the
//! techniques per scene ([`PICK`]), on both backends, meet the catalogue test's three
//! properties there ([`super::catalogue::check_spec`]): the casters in view covered, `V` finite
//! in [0, 1], and no worse than the hard shadow map against the ray-traced reference, nor than
//! the no-shadow image where the hard map shows a shadow; the techniques that fail the last
//! in some cases ([`KNOWN`]) fail in exactly as many as recorded.

use super::catalogue::{Checks, ShadowRule, check_spec};
use glam::{Mat4, Vec3};
use proptest::prelude::*;
use proptest::strategy::ValueTree;
use proptest::test_runner::{RngSeed, TestRunner};
use soft_shadow_core::{Camera, DistantProfile, Light, TriangleMesh};
use soft_shadow_reference::scenes::{MeshInstance, SceneSpec};
use std::collections::BTreeMap;
use std::sync::Arc;

/// The seed of the cases.
const SEED: u64 = 0x5eed_0f5c_e7e5;
/// How many scenes.
const CASES: u32 = 64;
/// G-buffer side of the receivers.
const SIZE: u32 = 24;
/// A case runs every `PICK`-th technique of the registry (from a random first), so that the
/// cases share the registry: each technique runs on about `CASES / PICK` scenes.
const PICK: usize = 5;

/// A light of kind `kind` (0..7) over a scene of scale `s`; `size` in (0, 1] scales its extent.
fn light(kind: u8, s: f32, size: f32, dir: Vec3) -> Light {
    let c = Vec3::new(0.1 * s, 3.0 * s, -0.2 * s);
    let h = size * 0.5 * s;
    match kind {
        0 => Light::Point { position: c },
        1 => Light::Linear {
            a: c - Vec3::X * h,
            b: c + Vec3::X * h,
        },
        2 => Light::Rect {
            center: c,
            u_half: Vec3::X * h,
            v_half: Vec3::Z * h,
        },
        3 => Light::Disk {
            center: c,
            normal: Vec3::NEG_Y,
            radius: h,
        },
        4 => Light::Sphere {
            center: c,
            radius: h,
        },
        // Counter-clockwise seen from below: it emits downwards.
        5 => Light::Triangle {
            a: c - Vec3::X * h,
            b: c + Vec3::X * h,
            c: c + Vec3::Z * h,
        },
        _ => Light::Distant {
            direction: dir,
            angular_diameter: 0.2 * size,
            profile: DistantProfile::UniformDisk,
        },
    }
}

/// The scene: a ground quad of half side `3 s` at y = 0 (receiving only) and `tris` (unit-box
/// coordinates scaled by `s`) casting and receiving, under `light`, seen from above and in
/// front.
fn scene(tris: &[[Vec3; 3]], s: f32, light: Light) -> SceneSpec {
    let g = 3.0 * s;
    let ground = TriangleMesh::new(
        "ground",
        vec![
            Vec3::new(-g, 0.0, -g),
            Vec3::new(g, 0.0, -g),
            Vec3::new(g, 0.0, g),
            Vec3::new(-g, 0.0, g),
        ],
        vec![[0, 2, 1], [0, 3, 2]],
    )
    .unwrap();
    let positions: Vec<Vec3> = tris.iter().flat_map(|t| t.map(|p| p * s)).collect();
    let indices = (0..tris.len() as u32)
        .map(|i| [3 * i, 3 * i + 1, 3 * i + 2])
        .collect();
    let casters = TriangleMesh::new("triangles", positions, indices).unwrap();
    let inst = |mesh, caster| MeshInstance {
        mesh: Arc::new(mesh),
        transform: Mat4::IDENTITY,
        caster,
        receiver: true,
    };
    SceneSpec {
        name: "random".into(),
        description: "random triangles over a ground quad".into(),
        // Every technique runs: on a light it does not model, under the nearest one it does.
        hard_case: true,
        meshes: vec![inst(ground, false), inst(casters, true)],
        light,
        camera: Camera {
            eye: Vec3::new(0.0, 4.5, 3.5) * s,
            target: Vec3::ZERO,
            fov_y: 50f32.to_radians(),
            near: 0.05 * s,
            far: 100.0 * s,
        },
    }
}

fn point() -> impl Strategy<Value = Vec3> {
    (-1.0f32..1.0, 0.2f32..1.2, -1.0f32..1.0).prop_map(|(x, y, z)| Vec3::new(x, y, z))
}

/// `(technique, cases, why)`: the techniques that fail the catalogue's accuracy property on
/// some of the [`CASES`] random scenes, in how many of the cases they ran in (exactly: the
/// cases are seeded, and fewer fails too, so the count follows every fix), and why, measured.
/// Any other technique failing anywhere, or any scene failing to prepare or to be covered,
/// fails the test. Random triangles at random scales are harder than the catalogue: in most
/// of the 64 cases some technique fails. On 576 receivers one receiver wrong by a whole light is
/// 10.6/255 of `V` rms, so a case often turns on a few receivers where triangles cut through
/// each other (case 1, the sun at 64²: the hard map reads one receiver there lit where the
/// reference is umbra, 16-sample accumulation three, image error 17.05 against 10.92).
const KNOWN: &[(&str, u32, &str)] = &[
    (
        "occlusion-slices",
        26,
        "of 64 cases: 13 under a segment recast as a rect 100 times longer than wide, whose \
         square slice maps have texels 100 times longer along the light than across, so the \
         triangles fall between texel centres (one such case: no shadow at 64² and 256², the \
         shadow at 1024²); 8 under the sun; 5 under disk, sphere and point lights; worst \
         52/255 above the hard map",
    ),
    (
        "penumbra-limit",
        19,
        "of 64 cases: 8 under the 100:1 rect a segment is recast as; 11 others, 7 of them at 16² \
         (texels wider than the triangles' edges, ribbons of two texels and more overlap into \
         false umbra); worst 12.5/255 of V above the hard map (22 cases before outer ribbons \
         kept off a caster on their edge's lit plane)",
    ),
    (
        "pcf",
        5,
        "of 14 cases: the fixed 5x5 kernel, 3 at 16² (5/16 of the map) and 2 at 64²; worst \
         12.3/255 above the hard map",
    ),
    (
        "shadow-width",
        3,
        "of 64 cases, all under the 100:1 rect a segment is recast as; within 1.9/255 of the \
         hard map",
    ),
    (
        "linear-light",
        4,
        "of 37 cases: 3 under the sun recast as a segment (worst 14/255 above the hard map), \
         1 under a point light at 64² (n5, 0.6/255 above it)",
    ),
    (
        "accumulation",
        1,
        "of 23 cases (both sample patterns): the grid's 16 samples under the sun at 64², \
         6.1/255 above the hard map",
    ),
];

/// Every case's scene and map side, from [`SEED`].
fn cases() -> impl Strategy<Value = (SceneSpec, u32, usize)> {
    (
        -3.0f32..4.0,
        prop::collection::vec([point(), point(), point()], 1..12),
        0u8..7,
        0.001f32..1.0,
        (-0.7f32..0.7, 0.3f32..1.0, -0.7f32..0.7),
        prop::sample::select(vec![16u32, 64, 256]),
        0usize..PICK,
    )
        .prop_map(|(log_scale, tris, kind, size, dir, res, first)| {
            let s = 10f32.powf(log_scale);
            let light = light(kind, s, size, Vec3::new(dir.0, dir.1, dir.2).normalize());
            (scene(&tris, s, light), res, first)
        })
}

/// The catalogue's properties for the techniques of each case, any scale, light kind and size:
/// nothing fails but [`KNOWN`]'s techniques, in exactly as many cases as it records.
#[test]
fn random_scenes_pass_the_catalogue_properties() {
    let config = ProptestConfig {
        cases: CASES,
        rng_seed: RngSeed::Fixed(SEED),
        failure_persistence: None,
        ..ProptestConfig::default()
    };
    let mut runner = TestRunner::new(config);
    let mut unknown = Vec::new();
    let mut failing: BTreeMap<&str, Vec<String>> = BTreeMap::new();
    let mut ran: BTreeMap<&str, u32> = BTreeMap::new();
    let all = super::techniques();
    for case in 0..CASES {
        let (spec, res, first) = cases().new_tree(&mut runner).unwrap().current();
        let pick = |i: usize| i % PICK == first;
        let outcome = check_spec(
            &spec,
            &Checks {
                size: SIZE,
                resolutions: &[res],
                shadows: ShadowRule::WhereTheHardMapDoes,
                pick: &pick,
            },
        );
        let what = format!(
            "case {case}: scale {:e}, {:?} light, {res}²",
            spec.camera.eye.y / 4.5,
            spec.light
        );
        let mut names: Vec<&str> = all
            .iter()
            .enumerate()
            .filter(|(i, _)| pick(*i))
            .map(|(_, t)| t.name())
            .collect();
        names.dedup();
        for n in &names {
            *ran.entry(n).or_default() += 1;
        }
        unknown.extend(outcome.scene.iter().map(|f| format!("{what}: {f}")));
        let mut in_case: BTreeMap<&str, Vec<String>> = BTreeMap::new();
        for (t, f) in &outcome.configurations {
            in_case.entry(t).or_default().push(f.clone());
        }
        for (t, fs) in in_case {
            let line = format!("{what}:\n  {}", fs.join("\n  "));
            if KNOWN.iter().any(|k| k.0 == t) {
                failing.entry(t).or_default().push(line);
            } else {
                unknown.push(line);
            }
        }
    }
    for (t, cases, _) in KNOWN {
        let got = failing.get(t).map_or(0, |f| f.len() as u32);
        let of = ran.get(t).copied().unwrap_or(0);
        println!("{t}: fails in {got} of the {of} cases it ran in (recorded {cases})");
        if got != *cases {
            unknown.push(format!(
                "{t} fails in {got} of its {of} cases, recorded {cases}:\n{}",
                failing.get(t).map_or(String::new(), |f| f.join("\n"))
            ));
        }
    }
    assert!(unknown.is_empty(), "{}", unknown.join("\n"));
}
