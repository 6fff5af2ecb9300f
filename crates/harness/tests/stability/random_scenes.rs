//! Random scenes from proptest: up to 12 random triangles over a ground quad, a light of every
//! kind with a random size, at scales 1e-3..1e4; every technique on both backends at a random
//! resolution gives finite `V` in [0, 1] on random receivers (ground and triangle points).

use super::{assert_stable, backends, gpu, techniques};
use glam::Vec3;
use harness::scenes::relight::relight;
use proptest::prelude::*;
use soft_shadow_core::{Aabb, DistantProfile, Light, Receivers, SceneGeometry};

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

/// Ground quad (half side `3 s`, y = 0) plus `tris` (unit-box coordinates scaled by `s`).
fn triangles(tris: &[[Vec3; 3]], s: f32) -> Vec<[Vec3; 3]> {
    let g = 3.0 * s;
    let (a, b, c, d) = (
        Vec3::new(-g, 0.0, -g),
        Vec3::new(g, 0.0, -g),
        Vec3::new(g, 0.0, g),
        Vec3::new(-g, 0.0, g),
    );
    let mut out = vec![[a, c, b], [a, d, c]];
    out.extend(tris.iter().map(|t| t.map(|p| p * s)));
    out
}

/// Receivers: `n` points on the ground (normal +y) and on each triangle with a usable normal.
fn receivers(tris: &[[Vec3; 3]], uv: &[(f32, f32)]) -> (Vec<Vec3>, Vec<Vec3>) {
    let (mut pos, mut nrm) = (Vec::new(), Vec::new());
    for (i, &(u, v)) in uv.iter().enumerate() {
        let t = tris[i % tris.len()];
        let (u, v) = if u + v > 1.0 {
            (1.0 - u, 1.0 - v)
        } else {
            (u, v)
        };
        let n = (t[1] - t[0]).cross(t[2] - t[0]);
        if n.length_squared() <= f32::MIN_POSITIVE || !n.is_finite() {
            continue;
        }
        let n = n.normalize();
        pos.push(t[0] + u * (t[1] - t[0]) + v * (t[2] - t[0]));
        nrm.push(if n.y < 0.0 { -n } else { n });
    }
    (pos, nrm)
}

fn point() -> impl Strategy<Value = Vec3> {
    (-1.0f32..1.0, 0.2f32..1.2, -1.0f32..1.0).prop_map(|(x, y, z)| Vec3::new(x, y, z))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(10))]

    /// Finite `V` in [0, 1] for every technique, any scale, light kind and size.
    #[test]
    fn random_scenes_stay_finite_and_in_range(
        log_scale in -3.0f32..4.0,
        tris in prop::collection::vec([point(), point(), point()], 1..12),
        kind in 0u8..7,
        size in 0.001f32..1.0,
        dir in (-0.7f32..0.7, 0.3f32..1.0, -0.7f32..0.7),
        res in prop::sample::select(vec![16u32, 64, 256]),
        uv in prop::collection::vec((0.0f32..1.0, 0.0f32..1.0), 64..256),
    ) {
        let s = 10f32.powf(log_scale);
        let all = triangles(&tris, s);
        let geometry = SceneGeometry {
            receivers: all.clone(),
            casters: all.clone(),
            bounds: Aabb::of_triangles(&all),
        };
        let (positions, normals) = receivers(&all, &uv);
        let recv = Receivers::new(&positions, &normals);
        let light = light(kind, s, size, Vec3::new(dir.0, dir.1, dir.2).normalize());
        for t in techniques() {
            let l = relight(&light, &geometry.bounds, |k| t.models(k))
                .expect("every technique models rect or linear lights");
            for be in backends() {
                let what = format!(
                    "scale {s:e} {:?} {} {} {res} {}",
                    l.kind(), t.name(), t.variant(), be.name()
                );
                let maps = t
                    .generate(crate::common::context(be, gpu()), &geometry, &l, res)
                    .map_err(|e| TestCaseError::fail(format!("{what}: generate: {e}")))?;
                let v = maps
                    .evaluate(gpu(), &recv)
                    .map_err(|e| TestCaseError::fail(format!("{what}: evaluate: {e}")))?;
                assert_stable(&v, positions.len(), &what);
            }
        }
    }
}
