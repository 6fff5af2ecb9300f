//! The ray-traced reference against closed forms.
//!
//! Bound: RMS of `(V - V_exact) * 255` at most 1.0 over the penumbra, and every receiver within
//! `4 * standard error + 1/255`. A wrong light parameterisation (a full side taken for a half side,
//! the segment shortened to its half) moves `V` by tens of units on this scale in the penumbra; the
//! tests check that the same bound rejects such a light, so it cannot pass by being loose.

use glam::Vec3;
use soft_shadow_core::Light;
use soft_shadow_reference::ground_truth::{GroundTruthSettings, RayTracer};

fn quad(x0: f32, x1: f32, z0: f32, z1: f32, y: f32) -> Vec<[Vec3; 3]> {
    let p = |x, z| Vec3::new(x, y, z);
    vec![
        [p(x0, z0), p(x1, z0), p(x1, z1)],
        [p(x0, z0), p(x1, z1), p(x0, z1)],
    ]
}

fn overlap(a0: f32, a1: f32, b0: f32, b1: f32) -> f32 {
    (a1.min(b1) - a0.max(b0)).max(0.0)
}

/// Exact visibility of a square light `[-a, a]²` at height `hl` from ground point `p`, with the
/// occluder `[ox0, ox1] x [oz0, oz1]` at height `ho`: the occluder projected from `p` onto the light
/// plane is a rectangle scaled by `hl / ho` about `p`; V = 1 - overlap area / light area.
fn square_exact(p: Vec3, a: f32, hl: f32, occ: [f32; 4], ho: f32) -> f32 {
    let s = hl / ho;
    let px = [p.x + (occ[0] - p.x) * s, p.x + (occ[1] - p.x) * s];
    let pz = [p.z + (occ[2] - p.z) * s, p.z + (occ[3] - p.z) * s];
    1.0 - overlap(px[0], px[1], -a, a) * overlap(pz[0], pz[1], -a, a) / (4.0 * a * a)
}

struct Check {
    rms_255: f64,
    worst_sigma: f64,
}

fn check(tracer: &RayTracer, light: &Light, pts: &[Vec3], exact: &dyn Fn(Vec3) -> f32) -> Check {
    let settings = GroundTruthSettings::default();
    let normals = vec![Vec3::Y; pts.len()];
    let refs = tracer.references(light, pts, &normals, &settings);
    let mut sum = 0.0;
    let mut worst: f64 = 0.0;
    for (p, r) in pts.iter().zip(&refs) {
        let r = r.expect("every receiver faces the light");
        let d = (r.visibility - exact(*p)) as f64;
        sum += (d * 255.0).powi(2);
        worst = worst.max(d.abs() / (4.0 * r.std_error as f64 + 1.0 / 255.0));
    }
    Check {
        rms_255: (sum / pts.len() as f64).sqrt(),
        worst_sigma: worst,
    }
}

#[test]
fn square_occluder_under_square_light_matches_the_box_filter_integral() {
    let (a, hl, ho) = (0.4f32, 2.5f32, 1.0f32);
    let occ = [-0.5f32, 0.5, -0.5, 0.5];
    let mut casters = quad(occ[0], occ[1], occ[2], occ[3], ho);
    casters.extend(quad(-4.0, 4.0, -4.0, 4.0, 0.0));
    let tracer = RayTracer::new(&casters);
    let light = Light::Rect {
        center: Vec3::new(0.0, hl, 0.0),
        u_half: Vec3::X * a,
        v_half: Vec3::Z * a,
    };
    // Receivers across the penumbra (|x| from 0 to 1.3) and along z.
    let pts: Vec<Vec3> = (0..400)
        .map(|i| {
            Vec3::new(
                -1.3 + 2.6 * (i % 40) as f32 / 39.0,
                0.0,
                -1.2 + 2.4 * (i / 40) as f32 / 9.0,
            )
        })
        .collect();
    let exact = |p: Vec3| square_exact(p, a, hl, occ, ho);
    let c = check(&tracer, &light, &pts, &exact);
    assert!(c.rms_255 <= 1.0, "rms {:.3}", c.rms_255);
    assert!(
        c.worst_sigma <= 1.0,
        "worst receiver off by {:.2} of its bound",
        c.worst_sigma
    );
    // The same bound rejects a light whose half-extent was taken for the full side.
    let wrong = Light::Rect {
        center: Vec3::new(0.0, hl, 0.0),
        u_half: Vec3::X * (2.0 * a),
        v_half: Vec3::Z * (2.0 * a),
    };
    let w = check(&tracer, &wrong, &pts, &exact);
    assert!(
        w.rms_255 > 10.0,
        "a wrong parameterisation must fail the bound, rms {:.2}",
        w.rms_255
    );
}

/// Heidrich et al. 2000, section 3.1, eq. 1: with the occluder edge at the origin of the 2D plane
/// through the light's line, the light `y1 = m x1 + t` and the receiver `y2 = n x2 + s`, the light
/// point just visible from `(x2, y2)` is `x1 = x2 t / (n x2 - m x2 + s)`.
fn eq1_visible_fraction(x2: f32, y2_slope: f32, y2_offset: f32, t: f32, light_x: [f32; 2]) -> f32 {
    let (m, n, s) = (0.0, y2_slope, y2_offset);
    let x1 = x2 * t / (n * x2 - m * x2 + s);
    // The occluder lies at x <= 0: light points with x > x1 are visible.
    ((light_x[1] - x1) / (light_x[1] - light_x[0])).clamp(0.0, 1.0)
}

#[test]
fn straight_edge_under_linear_light_matches_the_rational_function() {
    // Light along x at height 3, from -0.8 to 0.8; occluder half-plane x <= e at height 1.
    let (hl, ho, e, half) = (3.0f32, 1.0f32, 0.2f32, 0.8f32);
    let light = Light::Linear {
        a: Vec3::new(-half, hl, 0.0),
        b: Vec3::new(half, hl, 0.0),
    };
    let occluder = quad(-5.0, e, -5.0, 5.0, ho);
    for (slope, label) in [
        (0.0f32, "parallel receiver: linear"),
        (0.25, "tilted receiver: rational"),
    ] {
        // Receiver plane y = slope * x + y0 (normals ignored by the exact form; use the plane's).
        let y0 = 0.0;
        let mut casters = occluder.clone();
        let r = |x: f32, z: f32| Vec3::new(x, slope * x + y0, z);
        casters.push([r(-4.0, -4.0), r(4.0, -4.0), r(4.0, 4.0)]);
        casters.push([r(-4.0, -4.0), r(4.0, 4.0), r(-4.0, 4.0)]);
        let tracer = RayTracer::new(&casters);
        let pts: Vec<Vec3> = (0..300)
            .map(|i| {
                r(
                    -1.2 + 2.4 * (i % 60) as f32 / 59.0,
                    -1.0 + 2.0 * (i / 60) as f32 / 4.0,
                )
            })
            .collect();
        // In the plane of the light line: coordinates relative to the occluder edge (e, ho).
        let exact = |p: Vec3| {
            eq1_visible_fraction(
                p.x - e,
                slope,
                (slope * e + y0) - ho,
                hl - ho,
                [-half - e, half - e],
            )
        };
        let settings = GroundTruthSettings::default();
        let n = Vec3::new(-slope, 1.0, 0.0).normalize();
        let refs = tracer.references(&light, &pts, &vec![n; pts.len()], &settings);
        let rms = (pts
            .iter()
            .zip(&refs)
            .map(|(p, r)| ((r.unwrap().visibility - exact(*p)) as f64 * 255.0).powi(2))
            .sum::<f64>()
            / pts.len() as f64)
            .sqrt();
        assert!(rms <= 1.0, "{label}: rms {rms:.3}");
        let wrong = Light::Linear {
            a: Vec3::new(-0.5 * half, hl, 0.0),
            b: Vec3::new(0.5 * half, hl, 0.0),
        };
        let wr = tracer.references(&wrong, &pts, &vec![n; pts.len()], &settings);
        let wrms = (pts
            .iter()
            .zip(&wr)
            .map(|(p, r)| ((r.unwrap().visibility - exact(*p)) as f64 * 255.0).powi(2))
            .sum::<f64>()
            / pts.len() as f64)
            .sqrt();
        assert!(
            wrms > 10.0,
            "{label}: a wrong segment must fail the bound, rms {wrms:.2}"
        );
    }
}

/// A receiver never shadows itself: an unoccluded plane lit from any side above it reads V = 1.
#[test]
fn receivers_do_not_shadow_themselves() {
    let casters = quad(-50.0, 50.0, -50.0, 50.0, 0.0);
    let tracer = RayTracer::new(&casters);
    let light = Light::Distant {
        direction: Vec3::new(1.0, 0.05, 0.0).normalize(),
        angular_diameter: 0.02,
        profile: soft_shadow_core::DistantProfile::UniformDisk,
    };
    let pts: Vec<Vec3> = (0..200)
        .map(|i| Vec3::new(-40.0 + 0.4 * i as f32, 0.0, 7.0 - 0.07 * i as f32))
        .collect();
    let refs = tracer.references(
        &light,
        &pts,
        &vec![Vec3::Y; pts.len()],
        &GroundTruthSettings::default(),
    );
    assert!(
        refs.iter().all(|r| r.map(|r| r.visibility) == Some(1.0)),
        "{:?}",
        refs.iter().find(|r| r.map(|r| r.visibility) != Some(1.0))
    );
}

/// Visibility v2: light below a receiver's tangent plane, or behind a one-sided light, is the
/// lighting's business. A receiver facing away from every light point is unlit (`None`); one that
/// sees part of the light above its horizon, with nothing in the way, has `V = 1` exactly; and a
/// rect light 2 m under the ground leaves the ground unlit.
#[test]
fn the_horizon_and_the_back_of_a_light_are_not_shadow() {
    let tracer = RayTracer::new(&quad(-0.1, 0.1, -0.1, 0.1, 10.0));
    let settings = GroundTruthSettings::default();
    let sphere = Light::Sphere {
        center: Vec3::new(0.0, 1.0, 0.0),
        radius: 0.5,
    };
    let p = Vec3::new(2.0, 1.0, 0.0);
    // Normal facing the sphere: lit; tilted so that half the sphere is below the horizon: still
    // V = 1 (nothing occludes); facing away: unlit.
    for (n, expected) in [
        (Vec3::NEG_X, Some(1.0)),
        (Vec3::Y, Some(1.0)),
        (Vec3::X, None),
    ] {
        let r = tracer.reference(&sphere, p, n, &settings, 7);
        assert_eq!(r.map(|r| r.visibility), expected, "normal {n}");
    }
    let under = Light::Rect {
        center: Vec3::new(0.0, -2.0, 0.0),
        u_half: Vec3::X * 0.4,
        v_half: Vec3::Z * 0.4,
    };
    // The rect emits towards u x v = -Y: the ground above it is behind it.
    assert_eq!(
        tracer.reference(&under, Vec3::ZERO, Vec3::Y, &settings, 1),
        None
    );
}

/// A receiver that only a sliver of a disk light reaches (the rest lies below its horizon):
/// every stated error is one a `V` in [0, 1] allows (at most 0.5), and it still bounds the
/// error. Unoccluded, `V` is 1; with everything at `x < 0` occluded, 1/2 by symmetry.
#[test]
fn a_sliver_of_light_above_the_horizon_gets_an_honest_error() {
    let wall = vec![
        [
            Vec3::new(-5.0, -1.0, 1.0),
            Vec3::new(0.0, -1.0, 1.0),
            Vec3::new(0.0, 1.0, 1.0),
        ],
        [
            Vec3::new(-5.0, -1.0, 1.0),
            Vec3::new(0.0, 1.0, 1.0),
            Vec3::new(-5.0, 1.0, 1.0),
        ],
    ];
    let far_away = quad(50.0, 51.0, 50.0, 51.0, 50.0);
    let settings = GroundTruthSettings::default();
    let mut seen = 0;
    for (casters, exact) in [(far_away, 1.0f32), (wall, 0.5)] {
        let tracer = RayTracer::new(&casters);
        for k in 0..16 {
            // Sliver heights from 1e-4 to 1e-2 of the light's radius 0.5.
            let h = 1e-4 * 100f32.powf(k as f32 / 15.0);
            let light = Light::Disk {
                center: Vec3::new(0.0, h - 0.5, 2.0),
                normal: Vec3::NEG_Z,
                radius: 0.5,
            };
            let Some(r) = tracer.reference(&light, Vec3::ZERO, Vec3::Y, &settings, k) else {
                continue;
            };
            seen += 1;
            assert!(
                r.std_error <= 0.5,
                "sliver {h:e}: stated error {} is more than a V in [0, 1] allows",
                r.std_error
            );
            assert!(
                (r.visibility - exact).abs() <= 4.0 * r.std_error + 1.0 / 255.0,
                "sliver {h:e}: V {} against {exact}, stated error {}",
                r.visibility,
                r.std_error
            );
        }
    }
    assert!(seen >= 20, "only {seen} slivers were sampled");
}

/// A sample of `scene`'s receivers (a 32² G-buffer), the reference at the default settings and
/// an independent recomputation: other seeds, 16 replicates of 48² strata (36,864 rays per
/// receiver, 9x the reference) and no proof of lit receivers.
fn recompute(scene: &str) -> Vec<(f32, f32, f32, f32)> {
    use soft_shadow_reference::scenes::catalogue::build;
    let spec = build(scene).unwrap();
    let (geometry, positions, normals) =
        soft_shadow_reference::scenes::scene_receivers(&spec, 32).unwrap();
    let tracer = RayTracer::new(&geometry.casters);
    let settings = GroundTruthSettings::default();
    let hi = GroundTruthSettings {
        strata_side: 48,
        replicates: 16,
        ..settings
    };
    let refs = tracer.references(&spec.light, &positions, &normals, &settings);
    refs.iter()
        .enumerate()
        .filter_map(|(i, r)| {
            let r = (*r)?;
            let h = tracer
                .estimate_unproven(
                    &spec.light,
                    positions[i],
                    normals[i],
                    &hi,
                    1_000_003 + i as u64,
                )
                .expect("the same receiver is lit");
            Some((r.visibility, r.std_error, h.visibility, h.std_error))
        })
        .collect()
}

/// The stated error is the true worst error: on scenes with wires, thin sheets and thousands of
/// small quads (features a sparse pilot misses), every receiver's reference lies within 4.5 of
/// its stated errors (plus the recomputation's own, and 0.25/255) of a 9x larger independent
/// estimate: over about 2000 receivers, 4 standard errors were exceeded once (by 2%) on `foliage`.
/// The landed pilot settled such receivers with error 0 and was up to 11.7/255 off.
#[test]
fn the_stated_reference_error_bounds_an_independent_recomputation() {
    for scene in ["thin", "foliage"] {
        let rows = recompute(scene);
        let mut worst: f64 = 0.0;
        let mut max_stated: f64 = 0.0;
        for &(v, se, h, hse) in &rows {
            let d = (v - h).abs() as f64;
            let bound = 4.5 * (se as f64 + hse as f64) + 0.25 / 255.0;
            worst = worst.max(d / bound);
            max_stated = max_stated.max(se as f64);
        }
        assert!(
            worst <= 1.0,
            "{scene}: a receiver is off by {worst:.2} of its bound (max stated {:.2}/255)",
            max_stated * 255.0
        );
        assert!(rows.len() > 500, "{scene}: {} receivers", rows.len());
    }
}

/// The reference does not depend on the shadow-ray offset beyond its stated error: on `torus`
/// (a curved receiver lit to its terminator) and `contact`, 0.5x and 2x the default offset move
/// no receiver by more than 4 of the two stated errors (plus 0.25/255), and leave the same
/// receivers unlit.
#[test]
fn the_reference_does_not_depend_on_the_ray_offset() {
    use soft_shadow_reference::scenes::catalogue::build;
    for scene in ["torus", "contact"] {
        let spec = build(scene).unwrap();
        let (geometry, positions, normals) =
            soft_shadow_reference::scenes::scene_receivers(&spec, 40).unwrap();
        let tracer = RayTracer::new(&geometry.casters);
        let base = GroundTruthSettings::default();
        let at = |k: f32| {
            tracer.references(
                &spec.light,
                &positions,
                &normals,
                &GroundTruthSettings {
                    ray_offset: base.ray_offset * k,
                    ..base
                },
            )
        };
        let one = at(1.0);
        for k in [0.5, 2.0] {
            let other = at(k);
            for (i, (a, b)) in one.iter().zip(&other).enumerate() {
                match (a, b) {
                    (None, None) => {}
                    (Some(a), Some(b)) => {
                        let d = (a.visibility - b.visibility).abs();
                        let bound = 4.0 * (a.std_error + b.std_error) + 0.25 / 255.0;
                        assert!(
                            d <= bound,
                            "{scene} x{k} receiver {i}: {} vs {} (bound {bound})",
                            a.visibility,
                            b.visibility
                        );
                    }
                    _ => panic!("{scene} x{k} receiver {i}: lit in one, unlit in the other"),
                }
            }
        }
    }
}

/// Traced together ([`soft_shadow_reference::ground_truth::packet::OriginRays`]: one receiver's candidate
/// casters, binned by direction), every shadow ray gets the answer the BVH gives ray by ray
/// ([`RayTracer::sees_with`]): on every catalogue scene with an extended light, 256 light points
/// for each receiver of a 24² G-buffer that is not proven lit, over 100,000 rays blocked and as
/// many seen. Binning a triangle that reaches behind the origin by its projection, one cell
/// short, by nothing when only the origin is above its plane, or by nothing when it reaches
/// behind the origin, fails this.
#[test]
fn rays_traced_together_get_the_bvh_answer() {
    use soft_shadow_reference::scenes::catalogue::{SCENE_NAMES, build};
    let offset = GroundTruthSettings::default().ray_offset;
    let mut total = [0usize; 2];
    for scene in SCENE_NAMES {
        let spec = build(scene).unwrap();
        let light = spec.light;
        if light.sample_dimension() == 0 {
            continue;
        }
        let (geometry, positions, normals) =
            soft_shadow_reference::scenes::scene_receivers(&spec, 24).unwrap();
        let tracer = RayTracer::new(&geometry.casters);
        let mut seen = [0usize; 2];
        for (i, (&p, &n)) in positions.iter().zip(&normals).enumerate() {
            if !light.reaches_any(p, n) || tracer.proven_lit(&light, p, n, offset) {
                continue;
            }
            let rays = tracer
                .origin_rays(&light, p, n, offset)
                .expect("catalogue lights bound their rays");
            for k in 0..256u32 {
                let u = glam::Vec2::new(
                    ((k % 16) as f32 + 0.5 + 0.4 * ((i * 7 + k as usize) % 5) as f32 / 5.0) / 16.0,
                    ((k / 16) as f32 + 0.5) / 16.0,
                );
                let q = light.sample(u, p).0;
                let want = tracer.sees_with(p, n, q, offset);
                assert_eq!(rays.sees(q), want, "{scene}: receiver {i}, sample {k}");
                seen[want as usize] += 1;
            }
        }
        assert!(seen[0] + seen[1] > 0, "{scene}: no ray traced");
        total[0] += seen[0];
        total[1] += seen[1];
    }
    assert!(total[0] > 100_000 && total[1] > 100_000, "{total:?}");
}
