//! shadow-width against the paper's properties and closed forms (no GPU needed).

use soft_shadow_core::CpuContext;
use soft_shadow_core::pool::Pool;
use std::sync::Arc;

/// A pool for one test's maps (nothing kept between calls).
fn pool() -> Arc<Pool> {
    Arc::new(Pool::new(0))
}

use crate::attenuation::{AttenuationTable, attenuation, linear_falloff};
use crate::width::{cap, edt, jfa, propagate};
use crate::{FalloffKind, Neighbours, ShadowWidth, WidthMethod};
use glam::Vec3;
use proptest::prelude::*;
use soft_shadow_core::{
    Aabb, DistantProfile, Light, Map2D, Receivers, SceneGeometry, ShadowTechnique,
};

fn linear(c_bias: f32) -> FalloffKind {
    FalloffKind::Linear { c_bias }
}

/// Shadow depths and widths from subnormal to huge.
fn magnitude() -> impl Strategy<Value = f32> {
    prop_oneof![
        4 => 1e-3f32..1e3,
        1 => 1e-38f32..1e-30,
        1 => Just(f32::from_bits(1)),
        1 => 1e30f32..f32::MAX,
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    /// Property 1: fully lit where sd = 0 or sw = 0; and always finite, in [0, 1].
    #[test]
    fn lit_where_depth_or_width_is_zero(sd in magnitude(), sw in magnitude(),
                                        c in 0.0f32..100.0, b in 0.0f32..0.5) {
        let f = linear(b);
        prop_assert_eq!(attenuation(0.0, sw, c, &f), 1.0);
        prop_assert_eq!(attenuation(sd, 0.0, c, &f), 1.0);
        let v = attenuation(sd, sw, c, &f);
        prop_assert!(v.is_finite() && (0.0..=1.0).contains(&v), "I({sd}, {sw}) = {v}");
        let t = AttenuationTable::new(&f, 64).attenuation(sd, sw, c);
        prop_assert!(t.is_finite() && (0.0..=1.0).contains(&t), "table I({sd}, {sw}) = {t}");
    }

    /// Property 2: invariant under scaling both arguments (to f32 rounding of sw/sd).
    #[test]
    fn invariant_under_scaling_both(sd in 1e-3f32..1e3, sw in 1e-3f32..1e3, k in 1e-3f32..1e3,
                                    c in 0.01f32..10.0, b in 0.0f32..0.5) {
        let f = linear(b);
        let a = attenuation(sd, sw, c, &f);
        let s = attenuation(sd * k, sw * k, c, &f);
        // |dI/dx| <= 1 and x = c sw / sd changes by at most 4 ulp relative under the scaling.
        let x = c * sw / sd;
        prop_assert!((a - s).abs() <= 4.0 * f32::EPSILON * x.max(1.0), "{a} vs {s}");
    }

    /// Property 3: non-increasing in sw, strictly decreasing while 0 < I < 1; property 5:
    /// non-decreasing in sd (strictly while 0 < I < 1).
    #[test]
    fn monotone_in_width_and_depth(sd in 1e-3f32..1e3, sw in 1e-3f32..1e3, r in 1.001f32..10.0,
                                   c in 0.01f32..10.0, b in 0.0f32..0.5) {
        let f = linear(b);
        let i1 = attenuation(sd, sw, c, &f);
        let i2 = attenuation(sd, sw * r, c, &f);
        prop_assert!(i2 <= i1, "I(sd, sw) = {i1} < I(sd, {r} sw) = {i2}");
        if i2 > 0.0 && i1 < 1.0 {
            prop_assert!(i2 < i1, "not strictly decreasing: {i1} {i2}");
        }
        let i3 = attenuation(sd * r, sw, c, &f);
        prop_assert!(i3 >= i1, "I(sd, sw) = {i1} > I({r} sd, sw) = {i3}");
        if i1 > 0.0 && i3 < 1.0 {
            prop_assert!(i3 > i1, "not strictly increasing in sd: {i1} {i3}");
        }
    }

    /// With c_bias = 0 the paper's property 3 holds as stated: strictly decreasing wherever the
    /// larger width still gives I > 0.
    #[test]
    fn strictly_decreasing_without_bias(sd in 1e-3f32..1e3, sw in 1e-3f32..1e3,
                                        r in 1.001f32..10.0, c in 0.01f32..10.0) {
        let f = linear(0.0);
        let i1 = attenuation(sd, sw, c, &f);
        let i2 = attenuation(sd, sw * r, c, &f);
        if i2 > 0.0 {
            prop_assert!(i2 < i1, "{i1} {i2}");
        }
    }

    /// Property 4, continuity, as the Lipschitz bound of the linear form:
    /// |I(sd, sw + e) - I(sd, sw)| <= c e / sd (plus rounding).
    #[test]
    fn continuous_in_width(sd in 1e-2f32..1e2, sw in 0.0f32..1e2, e in 0.0f32..1e-2,
                           c in 0.01f32..10.0, b in 0.0f32..0.5) {
        let f = linear(b);
        let d = (attenuation(sd, sw + e, c, &f) - attenuation(sd, sw, c, &f)).abs();
        prop_assert!(d <= c * e / sd + 1e-5, "jump {d} for e = {e}");
    }

    /// The lookup table differs from the direct evaluation by at most its interpolation error:
    /// h * max |df/dt| with h = 1/(n-1); for the linear falloff f = 1 + b - t/(1-t),
    /// |df/dt| = 1/(1-t)^2 <= (1+b)^2... up to t = (1+b)/(2+b) where f reaches 0, i.e. (2+b)^2.
    #[test]
    fn table_matches_direct_evaluation(sd in 1e-3f32..1e3, sw in 1e-3f32..1e3,
                                       c in 0.01f32..10.0, b in 0.0f32..0.5) {
        let f = linear(b);
        let n = 256;
        let t = AttenuationTable::new(&f, n);
        let direct = attenuation(sd, sw, c, &f);
        let table = t.attenuation(sd, sw, c);
        let bound = (2.0 + b) * (2.0 + b) / (n - 1) as f32 + 1e-5;
        prop_assert!((direct - table).abs() <= bound, "{direct} vs {table} (bound {bound})");
    }
}

/// A user falloff (the general form) goes through the same special cases.
#[test]
fn custom_falloff_keeps_the_special_cases() {
    let f = FalloffKind::Custom(std::sync::Arc::new(|x: f32| (-x * x).exp()));
    assert_eq!(attenuation(0.0, 1.0, 1.0, &f), 1.0);
    assert_eq!(attenuation(1.0, 0.0, 1.0, &f), 1.0);
    assert!((attenuation(2.0, 1.0, 2.0, &f) - (-1.0f32).exp()).abs() < 1e-6);
    assert_eq!(attenuation(f32::from_bits(1), 1e30, 1.0, &f), 0.0);
    assert_eq!(linear_falloff(0.0, f32::INFINITY), 0.0);
}

fn random_mask(resolution: u32, density: f64, seed: u64) -> Map2D<bool> {
    let mut rng = soft_shadow_core::rng::SplitMix(seed);
    let data = (0..resolution * resolution)
        .map(|_| rng.next_f64() >= density)
        .map(|lit| !lit)
        .collect();
    Map2D::from_vec(resolution, resolution, data).unwrap()
}

fn brute_force(mask: &Map2D<bool>) -> Vec<f32> {
    let resolution = mask.width() as i64;
    let lit: Vec<(i64, i64)> = (0..resolution * resolution)
        .filter(|&i| !mask.data()[i as usize])
        .map(|i| (i % resolution, i / resolution))
        .collect();
    (0..resolution * resolution)
        .map(|i| {
            if !mask.data()[i as usize] {
                return 0.0;
            }
            let (x, y) = (i % resolution, i / resolution);
            lit.iter()
                .map(|&(a, b)| (((a - x).pow(2) + (b - y).pow(2)) as f64).sqrt() as f32)
                .fold(cap(resolution as u32), f32::min)
        })
        .collect()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    /// The exact transform equals brute force on random masks (all-blocked and all-lit
    /// included), and on maps wider than one column strip of the CPU transform (64 columns, the
    /// last strip narrower), mostly blocked so that distances reach across strips.
    #[test]
    fn exact_transform_equals_brute_force(
        (resolution, density) in prop_oneof![
            9 => (1u32..40, 0.0f64..=1.0),
            1 => (65u32..160, 0.9f64..=1.0),
        ],
        seed: u64,
    ) {
        let mask = random_mask(resolution, density, seed);
        let exact = edt::width(&pool(), &mask);
        let brute = brute_force(&mask);
        for (i, (a, b)) in exact.data().iter().zip(&brute).enumerate() {
            prop_assert_eq!(*a, *b, "texel {}", i);
        }
    }
}

/// One propagation pass texel by texel, offset by offset: the paper's loop, which
/// `propagate::pass` must equal bit for bit.
fn pass_per_texel(src: &[f32], resolution: u32, step: u32, n: Neighbours) -> Vec<f32> {
    let r = resolution as i32;
    let offs = propagate::offsets(n, step);
    (0..r * r)
        .map(|i| {
            let (x, y) = (i % r, i / r);
            let mut w = src[i as usize];
            for &(dx, dy, len) in &offs {
                let (qx, qy) = (x + dx, y + dy);
                if qx >= 0 && qy >= 0 && qx < r && qy < r {
                    w = w.min(src[(qy * r + qx) as usize] + len);
                }
            }
            w
        })
        .collect()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(100))]

    /// A propagation pass over whole rows equals the per-texel loop bit for bit, for every
    /// neighbourhood and steps up to beyond the map side.
    #[test]
    fn propagation_pass_equals_the_per_texel_loop(
        resolution in 1u32..40,
        step in 1u32..50,
        values in prop::collection::vec(prop_oneof![Just(0.0f32), Just(propagate::UNREACHED), 0.0f32..100.0], 1600),
    ) {
        let src = &values[..(resolution * resolution) as usize];
        for n in [Neighbours::Three, Neighbours::Four, Neighbours::Six, Neighbours::Eight] {
            let mut dst = vec![0.0; src.len()];
            propagate::pass(src, &mut dst, resolution, step, n);
            let expected = pass_per_texel(src, resolution, step, n);
            prop_assert_eq!(
                dst.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
                expected.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
                "{:?} step {}", n, step
            );
        }
    }
}

/// The propagated width map of `mask` by its passes run texel by texel ([`pass_per_texel`]),
/// capped, as bits.
fn width_per_texel(mask: &Map2D<bool>, n: Neighbours) -> Vec<u32> {
    let resolution = mask.width();
    let mut w: Vec<f32> = mask
        .data()
        .iter()
        .map(|&b| if b { propagate::UNREACHED } else { 0.0 })
        .collect();
    for step in propagate::steps(resolution) {
        w = pass_per_texel(&w, resolution, step, n);
    }
    bits(&w.iter().map(|v| v.min(cap(resolution))).collect::<Vec<_>>())
}

fn bits(v: &[f32]) -> Vec<u32> {
    v.iter().map(|v| v.to_bits()).collect()
}

/// A propagated width map does not depend on what its pooled buffers held: after a map blocked
/// everywhere (whose buffers go back to the pool full of non-zero widths), a disc blocked in an
/// unblocked map (chunks of 0 around it, which the passes skip) equals its passes run texel by
/// texel.
#[test]
fn propagation_ignores_what_its_pooled_buffers_held() {
    let resolution = 320;
    for n in [Neighbours::Four, Neighbours::Eight] {
        drop(propagate::width(
            &pool(),
            &Map2D::new(resolution, resolution, true),
            n,
        ));
        let disc: Vec<bool> = (0..resolution * resolution)
            .map(|i| {
                let (x, y) = (
                    (i % resolution) as f32 - 150.0,
                    (i / resolution) as f32 - 170.0,
                );
                x * x + y * y < 60.0 * 60.0
            })
            .collect();
        let mask = Map2D::from_vec(resolution, resolution, disc).unwrap();
        let got = propagate::width(&pool(), &mask, n);
        assert!(bits(got.data()) == width_per_texel(&mask, n), "{n:?}");
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(40))]

    /// The propagated width map equals its passes run texel by texel bit for bit: the chunks a
    /// pass leaves alone (0 in its source, and 0s already in its destination from two passes
    /// before) are the ones the per-texel loop leaves at 0. Sides up to 150 have rows of three
    /// chunks, the last one partial.
    #[test]
    fn propagated_width_equals_its_passes_per_texel(
        resolution in 1u32..150,
        density in 0.0f64..=1.0,
        seed: u64,
    ) {
        let mask = random_mask(resolution, density, seed);
        for n in [Neighbours::Three, Neighbours::Four, Neighbours::Six, Neighbours::Eight] {
            let got = propagate::width(&pool(), &mask, n);
            prop_assert_eq!(bits(got.data()), width_per_texel(&mask, n), "{:?}", n);
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    /// Propagation and jump flooding never under-estimate (each value is the length of a path to
    /// an unblocked texel), and are exact on unblocked texels.
    #[test]
    fn approximations_never_underestimate(resolution in 1u32..40, density in 0.0f64..=1.0, seed: u64) {
        let mask = random_mask(resolution, density, seed);
        let exact = edt::width(&pool(), &mask);
        for w in [
            propagate::width(&pool(), &mask, Neighbours::Three),
            propagate::width(&pool(), &mask, Neighbours::Four),
            propagate::width(&pool(), &mask, Neighbours::Six),
            propagate::width(&pool(), &mask, Neighbours::Eight),
            jfa::width(&pool(), &mask),
        ] {
            for ((a, e), m) in w.data().iter().zip(exact.data()).zip(mask.data()) {
                prop_assert!(*a >= *e - 1e-4, "{a} < exact {e}");
                if !*m {
                    prop_assert_eq!(*a, 0.0);
                }
            }
        }
    }
}

/// The approximations' error against the exact transform on blob-shaped masks (discs and
/// rectangles, like shadow footprints) at 256²: printed, and bounded by what each method can
/// reach.
#[test]
fn approximation_error_is_bounded_and_reported() {
    let resolution = 256u32;
    let mut data = vec![false; (resolution * resolution) as usize];
    for y in 0..resolution {
        for x in 0..resolution {
            let (fx, fy) = (x as f32 + 0.5, y as f32 + 0.5);
            let disc = (fx - 90.0).powi(2) + (fy - 100.0).powi(2) < 60.0f32.powi(2);
            let rect = (150.0..240.0).contains(&fx) && (40.0..200.0).contains(&fy);
            let tilted = ((fx - fy) * 0.7).abs() < 12.0 && fy > 180.0;
            data[(y * resolution + x) as usize] = disc || rect || tilted;
        }
    }
    let mask = Map2D::from_vec(resolution, resolution, data).unwrap();
    let exact = edt::width(&pool(), &mask);
    let report = |name: &str, w: &Map2D<f32>| {
        let (mut max_abs, mut max_rel, mut sum, mut n) = (0.0f32, 0.0f32, 0.0f64, 0usize);
        for ((a, e), m) in w.data().iter().zip(exact.data()).zip(mask.data()) {
            if *m {
                max_abs = max_abs.max(a - e);
                max_rel = max_rel.max((a - e) / e);
                sum += (a - e) as f64;
                n += 1;
            }
        }
        let mean = sum / n as f64;
        eprintln!(
            "{name}: mean error {mean:.3} texels, max {max_abs:.2} texels, max relative {max_rel:.3}"
        );
        (mean, max_rel)
    };
    let (m3, r3) = report(
        "propagate-3",
        &propagate::width(&pool(), &mask, Neighbours::Three),
    );
    let (m4, r4) = report(
        "propagate-4",
        &propagate::width(&pool(), &mask, Neighbours::Four),
    );
    let (m6, r6) = report(
        "propagate-6",
        &propagate::width(&pool(), &mask, Neighbours::Six),
    );
    let (m8, r8) = report(
        "propagate-8",
        &propagate::width(&pool(), &mask, Neighbours::Eight),
    );
    let (mj, rj) = report("jfa", &jfa::width(&pool(), &mask));
    // The doubling scheme moves at most once per power of two, in one direction per pass, so some
    // offsets cannot be reached directly and the path found can exceed even the city-block
    // distance (measured on this mask: 4 neighbours up to 2.24x the exact distance, 8 neighbours
    // 1.38x; the paper's hardware directions, 3 up to 5.84x and 6 up to 3.24x, mean errors 4.30
    // and 0.77 texels). These are regression bounds on that measurement: a change that makes
    // the propagation worse fails here.
    assert!(
        r3 <= 5.0 && m3 < 4.5,
        "propagate-3 relative {r3}, mean {m3}"
    );
    assert!(
        r6 <= 2.4 && m6 < 0.85,
        "propagate-6 relative {r6}, mean {m6}"
    );
    assert!(
        r4 <= 1.3 && m4 < 1.5,
        "propagate-4 relative {r4}, mean {m4}"
    );
    assert!(
        r8 <= 0.4 && m8 < 0.5,
        "propagate-8 relative {r8}, mean {m8}"
    );
    assert!(
        m8 < m6 && m6 < m4 && m4 < m3,
        "more neighbours should do better on average: 3 {m3}, 4 {m4}, 6 {m6}, 8 {m8}"
    );
    assert!(rj < 0.05 && mj < 0.01, "jfa relative {rj}, mean {mj}");
}

fn quad(c: Vec3, half: f32) -> [[Vec3; 3]; 2] {
    let p = |x: f32, z: f32| c + Vec3::new(x * half, 0.0, z * half);
    [
        [p(-1.0, -1.0), p(-1.0, 1.0), p(1.0, 1.0)],
        [p(-1.0, -1.0), p(1.0, 1.0), p(1.0, -1.0)],
    ]
}

fn geometry(h: f32) -> SceneGeometry {
    let ground = quad(Vec3::ZERO, 2.0);
    let blocker = quad(Vec3::new(-1.0, h, 0.0), 1.0);
    // The ground only receives (maps cover what casts).
    let casters: Vec<[Vec3; 3]> = blocker.to_vec();
    let everything: Vec<[Vec3; 3]> = ground.iter().chain(&blocker).copied().collect();
    SceneGeometry {
        bounds: Aabb::of_triangles(&everything),
        receivers: ground.to_vec(),
        casters,
    }
}

/// Units of `sw` and the physical softness, against the closed form of the paper's `I` for a
/// straight edge: a blocker covering `x < 0` at height `h` over the ground. Inside the shadow at
/// distance `x` from the edge, `sd = h` and the width is `x` (world units, distant light) or
/// `x / z_r` (an angle, light overhead), so `I = 1 - 2x/(hL)` for a distant light of size
/// `L = 2 tan(θ/2)` and `I = 1 - 2 z_b x / (L h)` for a local light, each times the fit factor
/// (2.5 for round lights). Bound: one texel of width.
#[test]
fn width_units_follow_the_closed_form() {
    let h = 1.0;
    let g = geometry(h);
    let resolution = 512;
    let lights = [
        Light::Distant {
            direction: Vec3::Y,
            angular_diameter: 2.0 * 0.25f32.atan(),
            profile: DistantProfile::UniformDisk,
        },
        Light::Disk {
            center: Vec3::new(0.0, 6.0, 0.0),
            normal: Vec3::NEG_Y,
            radius: 0.25,
        },
    ];
    for light in lights {
        let t = ShadowWidth::new(WidthMethod::Exact);
        let maps = t
            .generate_cpu(&CpuContext::new(), &g, &light, resolution)
            .unwrap();
        let xs: Vec<f32> = (1..40).map(|i| -0.005 * i as f32).collect();
        let positions: Vec<Vec3> = xs.iter().map(|&x| Vec3::new(x, 0.0, 0.1)).collect();
        let normals = vec![Vec3::Y; positions.len()];
        let v = t
            .evaluate_cpu(&maps, &Receivers::new(&positions, &normals))
            .unwrap();
        let l = light.size() / crate::params::fit_factor(light.kind());
        let (slope, texel) = match light {
            Light::Distant { .. } => (2.0 / (h * l), maps.first().params.texel_b),
            _ => {
                let z_b = 6.0 - h;
                (2.0 * z_b / (l * h), maps.first().params.texel_a * 6.0)
            }
        };
        for (x, v) in xs.iter().zip(&v) {
            let expected = (1.0 - slope * x.abs()).clamp(0.0, 1.0);
            let bound = slope * texel * 1.0 + 1e-3;
            assert!(
                (v - expected).abs() <= bound,
                "{:?} x = {x}: V = {v}, closed form {expected} (bound {bound})",
                light.kind()
            );
        }
    }
}

/// Bad parameters and inputs get typed errors naming the problem, never a panic.
#[test]
fn bad_input_gets_typed_errors() {
    use crate::Softness;
    use soft_shadow_core::ShadowError;
    let g = geometry(1.0);
    let light = Light::Point {
        position: Vec3::new(0.0, 5.0, 0.0),
    };
    let mut t = ShadowWidth::new(WidthMethod::JumpFlood);
    t.softness = Softness::Constant(f32::NAN);
    assert!(matches!(
        t.generate_cpu(&CpuContext::new(), &g, &light, 64),
        Err(ShadowError::InvalidParameter(m)) if m.contains("c_scale")
    ));
    let mut t = ShadowWidth::new(WidthMethod::Exact);
    t.falloff = FalloffKind::Linear { c_bias: -0.1 };
    assert!(matches!(
        t.generate_cpu(&CpuContext::new(), &g, &light, 64),
        Err(ShadowError::InvalidParameter(m)) if m.contains("c_bias")
    ));
    let mut t = ShadowWidth::new(WidthMethod::Exact);
    t.table = Some(1);
    assert!(matches!(
        t.generate_cpu(&CpuContext::new(), &g, &light, 64),
        Err(ShadowError::InvalidParameter(m)) if m.contains("table")
    ));
    let t = ShadowWidth::new(WidthMethod::Exact);
    assert!(matches!(
        t.generate_cpu(&CpuContext::new(), &g, &light, 0),
        Err(ShadowError::InvalidResolution { requested: 0, .. })
    ));
    let bad = Light::Disk {
        center: Vec3::Y,
        normal: Vec3::NEG_Y,
        radius: -1.0,
    };
    assert!(matches!(
        t.generate_cpu(&CpuContext::new(), &g, &bad, 64),
        Err(ShadowError::InvalidLight(_))
    ));
    let maps = t.generate_cpu(&CpuContext::new(), &g, &light, 64).unwrap();
    let p = [Vec3::ZERO, Vec3::ONE];
    let n = [Vec3::Y];
    assert!(matches!(
        t.evaluate_cpu(&maps, &Receivers::new(&p, &n)),
        Err(ShadowError::InvalidReceivers(_))
    ));
}
