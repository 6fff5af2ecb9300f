//! Properties of the pieces: shares that sum to 1 (section 3.3), skins only across depth
//! discontinuities (section 3.2), planes free of edges, typed errors on bad input, and the
//! triangle light of section 4.

use soft_shadow_core::CpuContext;
use soft_shadow_core::pool::Pool;
use std::sync::Arc;

/// A pool for one test's maps (nothing kept between calls).
fn pool() -> Arc<Pool> {
    Arc::new(Pool::new(0))
}

use crate::LinearLight;
use crate::samples::{lit_share, neighbours, piece_share};
use crate::skins::{QUAD_TRIANGLES, Unproject, edges, skin_values, skins};
use glam::Vec3;
use proptest::prelude::*;
use soft_shadow_core::{
    Aabb, Light, Map2D, Receivers, SceneGeometry, ShadowError, ShadowTechnique,
};

proptest! {
    #![proptest_config(ProptestConfig::with_cases(500))]

    /// The lit shares of N samples sum to 1, and each sample's share is half the pieces it ends.
    #[test]
    fn lit_shares_sum_to_one(n in 2u32..=64) {
        let total: f32 = (0..n).map(|i| lit_share(i, n)).sum();
        prop_assert!((total - 1.0).abs() <= 1e-5 * n as f32, "{total}");
        for i in 0..n {
            let pieces = neighbours(i, n).count() as f32;
            prop_assert!((lit_share(i, n) - 0.5 * pieces * piece_share(n)).abs() <= 1e-7);
        }
    }

    /// A grid triangle is a skin exactly when its depth range exceeds the threshold, and its
    /// values mark the far vertices 1 and the near ones 0 (at least one of each).
    #[test]
    fn skins_span_discontinuities_only(
        z in prop::array::uniform3(0.1f32..100.0),
        t in 0.001f32..0.5,
    ) {
        let lo = z[0].min(z[1]).min(z[2]);
        let hi = z[0].max(z[1]).max(z[2]);
        match skin_values(z, t) {
            None => prop_assert!(hi - lo <= t * lo),
            Some(v) => {
                prop_assert!(hi - lo > t * lo);
                prop_assert!(v.contains(&0.0) && v.contains(&1.0));
                for k in 0..3 {
                    prop_assert_eq!(v[k] == 1.0, z[k] > 0.5 * (lo + hi));
                }
            }
        }
    }

    /// Any plane seen in perspective has `1/z` affine in the image, so no interior texel is an
    /// edge, however steep the plane.
    #[test]
    fn planes_have_no_edges(a in -0.02f32..0.02, b in -0.02f32..0.02, c in 0.2f32..2.0) {
        let resolution = 32u32;
        let w = |x: f32, y: f32| c + a * x + b * y;
        // In front of the eye everywhere (1/z > 0 over the whole map).
        prop_assume!([0.0, 31.0].iter().all(|&x| [0.0, 31.0].iter().all(|&y| w(x, y) > 0.01)));
        let data: Vec<f32> = (0..resolution * resolution)
            .map(|i| 1.0 / w((i % resolution) as f32, (i / resolution) as f32))
            .collect();
        let e = edges(&pool(), &Map2D::from_vec(resolution, resolution, data).unwrap(), 0.02);
        prop_assert!(!e.data().iter().any(|x| *x));
    }
}

/// Edge flags are the definition texel by texel: `|4 w - sum of the 4 neighbours' w| > t w`
/// with `w = 1/z` (0 where empty), a neighbour beyond the border extrapolated as `2 w -
/// w_opposite`; on random maps of 1 to 40 texels a side (rows and columns of one and two
/// texels, where every texel is a border) with empty texels and steps.
#[test]
fn edges_are_the_laplacian_of_inverse_depth() {
    use soft_shadow_core::view::NO_OCCLUDER;
    let mut rng = soft_shadow_core::rng::SplitMix(8);
    let mut flagged = 0;
    for case in 0..400 {
        let (w, h) = (1 + rng.below(40) as usize, 1 + rng.below(40) as usize);
        let data: Vec<f32> = (0..w * h)
            .map(|_| match rng.below(6) {
                0 => NO_OCCLUDER,
                1 => 5.0,
                _ => 3.0 + rng.below(100) as f32 * 1e-3,
            })
            .collect();
        let t = 0.05;
        let inv = |x: usize, y: usize| {
            let z = data[y * w + x];
            if z >= NO_OCCLUDER { 0.0 } else { 1.0 / z }
        };
        let map = Map2D::from_vec(w as u32, h as u32, data.clone()).unwrap();
        let e = edges(&pool(), &map, t);
        for y in 0..h {
            for x in 0..w {
                let c = inv(x, y);
                let sx = if x > 0 && x + 1 < w {
                    inv(x - 1, y) + inv(x + 1, y)
                } else {
                    2.0 * c
                };
                let sy = if y > 0 && y + 1 < h {
                    inv(x, y - 1) + inv(x, y + 1)
                } else {
                    2.0 * c
                };
                let lap = 4.0 * c - sx - sy;
                let expect = c > 0.0 && lap.abs() > t * c;
                assert_eq!(
                    *e.get(x as u32, y as u32),
                    expect,
                    "case {case} {w}x{h} ({x}, {y})"
                );
                flagged += expect as usize;
            }
        }
    }
    assert!(flagged > 1000, "{flagged} edges");
}

/// The skins of a depth map are, in row-major order of their quads, the grid triangles of every
/// quad whose four texels hold a surface and one is an [`edges`] texel, where [`skin_values`]
/// finds a discontinuity, each with its texels unprojected: random maps of 2 to 40 texels a side
/// with empty texels and steps between two depths.
#[test]
fn skins_are_the_discontinuous_triangles_of_edge_quads() {
    use soft_shadow_core::view::{NO_OCCLUDER, View};
    let view = View::fit_light(
        soft_shadow_core::light::LightPoint::Position(Vec3::new(0.0, 4.0, 0.0)),
        Vec3::NEG_Y,
        &soft_shadow_core::Coverage::whole(&Aabb {
            min: Vec3::splat(-1.0),
            max: Vec3::ONE,
        }),
    );
    let mut rng = soft_shadow_core::rng::SplitMix(4);
    let mut next = |n: u64| rng.below(n);
    let mut found = 0;
    for case in 0..300 {
        let resolution = 2 + next(39) as u32;
        let data: Vec<f32> = (0..resolution * resolution)
            .map(|_| match next(8) {
                0 => NO_OCCLUDER,
                1 | 2 => 5.0,
                _ => 3.0 + next(100) as f32 * 1e-4,
            })
            .collect();
        let depth = Map2D::from_vec(resolution, resolution, data).unwrap();
        let t = 0.05;
        let edge = edges(&pool(), &depth, t);
        let un = Unproject::new(&view, resolution);
        let mut expected = Vec::new();
        for y in 0..resolution - 1 {
            for x in 0..resolution - 1 {
                let quad = [(x, y), (x + 1, y), (x, y + 1), (x + 1, y + 1)];
                if quad.iter().any(|&(u, v)| *depth.get(u, v) >= NO_OCCLUDER)
                    || !quad.iter().any(|&(u, v)| *edge.get(u, v))
                {
                    continue;
                }
                for tri in &QUAD_TRIANGLES {
                    let t3 = tri.map(|(dx, dy)| (x + dx, y + dy));
                    let z = t3.map(|(u, v)| *depth.get(u, v));
                    if let Some(values) = skin_values(z, t) {
                        let vertices = [0, 1, 2].map(|k| un.point(t3[k].0, t3[k].1, z[k]));
                        expected.push((vertices, values));
                    }
                }
            }
        }
        let got: Vec<_> = skins(&pool(), &view, &depth, t)
            .iter()
            .map(|s| (s.vertices, s.values))
            .collect();
        assert_eq!(got, expected, "case {case}, {resolution}²");
        found += got.len();
    }
    assert!(found > 1000, "{found} skins");
}

fn occluded_geometry() -> SceneGeometry {
    let quad = |y: f32, h: f32| {
        let p = |x: f32, z: f32| Vec3::new(x, y, z);
        vec![
            [p(-h, -h), p(h, -h), p(h, h)],
            [p(-h, -h), p(h, h), p(-h, h)],
        ]
    };
    let mut casters = quad(0.0, 3.0);
    casters.extend(quad(1.0, 0.5));
    SceneGeometry {
        bounds: Aabb::of_triangles(&casters),
        receivers: casters.clone(),
        casters,
    }
}

/// A triangle light as three linear lights: a point far from the occluder's shadow sees it
/// whole (1), the point under the occluder's centre sees none of it (0).
#[test]
fn triangle_light_is_lit_outside_and_dark_under_the_occluder() {
    let g = occluded_geometry();
    // Counter-clockwise seen from below: it emits downwards.
    let (a, b, c) = (
        Vec3::new(-0.2, 3.0, -0.2),
        Vec3::new(0.25, 3.0, -0.1),
        Vec3::new(0.0, 3.0, 0.2),
    );
    let t = LinearLight::new(3);
    let maps = t
        .generate_cpu(&CpuContext::new(), &g, &Light::Triangle { a, b, c }, 256)
        .unwrap();
    assert_eq!(maps.first().params.len(), 9, "three edges of three samples");
    let positions = [Vec3::new(2.5, 0.0, 2.5), Vec3::new(0.0, 0.0, 0.0)];
    let normals = [Vec3::Y; 2];
    let v = t
        .evaluate_cpu(&maps, &Receivers::new(&positions, &normals))
        .unwrap();
    assert!((v[0] - 1.0).abs() < 1e-5, "lit point {}", v[0]);
    assert_eq!(v[1], 0.0, "umbra point");
    for (what, bad) in [
        ("repeated vertex", (a, a, b)),
        ("collinear", (a, b, 2.0 * b - a)),
    ] {
        let light = Light::Triangle {
            a: bad.0,
            b: bad.1,
            c: bad.2,
        };
        match t.generate_cpu(&CpuContext::new(), &g, &light, 64) {
            Err(ShadowError::InvalidLight(m)) => assert!(m.contains("triangle"), "{what}: {m}"),
            other => panic!("{what}: {:?}", other.map(|_| ())),
        }
    }
}

/// Bad parameters and lights get typed errors that name the problem.
#[test]
fn bad_input_gets_typed_errors() {
    let g = occluded_geometry();
    let seg = Light::Linear {
        a: Vec3::new(-0.5, 3.0, 0.0),
        b: Vec3::new(0.5, 3.0, 0.0),
    };
    for n in [0, 1, 65] {
        match LinearLight::new(n).generate_cpu(&CpuContext::new(), &g, &seg, 64) {
            Err(ShadowError::InvalidParameter(m)) => assert!(m.contains("samples")),
            other => panic!("samples {n}: {:?}", other.map(|_| ())),
        }
    }
    let mut t = LinearLight::new(2);
    t.edge_threshold = 0.0;
    assert!(matches!(
        t.generate_cpu(&CpuContext::new(), &g, &seg, 64),
        Err(ShadowError::InvalidParameter(_))
    ));
    let t = LinearLight::new(2);
    let rect = Light::Rect {
        center: Vec3::Y * 3.0,
        u_half: Vec3::X,
        v_half: Vec3::Z,
    };
    assert!(matches!(
        t.generate_cpu(&CpuContext::new(), &g, &rect, 64),
        Err(ShadowError::UnsupportedLight { .. })
    ));
    assert!(matches!(
        t.generate_cpu(&CpuContext::new(), &g, &seg, 0),
        Err(ShadowError::InvalidResolution { .. })
    ));
    let zero = Light::Linear {
        a: Vec3::Y,
        b: Vec3::Y,
    };
    assert!(matches!(
        t.generate_cpu(&CpuContext::new(), &g, &zero, 64),
        Err(ShadowError::InvalidLight(_))
    ));
}
